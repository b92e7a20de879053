// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "rig/Rig.h"
#include "rig/RigOptimizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
const char* const SmallRig = R"({
  "name": "Small",
  "description": "two targets, three shapes",
  "targets": ["jawOpen", "mouthFunnel", "eyeBlink_L"],
  "shapes": {
    "A": {"jawOpen": 0.6, "mouthFunnel": 0.1},
    "O": {"jawOpen": 0.5, "mouthFunnel": 0.8},
    "Blink": {"eyeBlink_L": 1.0},
    "Ah": "A"
  },
  "sets": {"vowels": ["A", "O"]},
  "notes": {"A": "open"}
})";

const std::vector<std::string> FaceTargets = { "eyeBlink_L", "mouthFunnel", "jawOpen",
  "cheekPuff_L" };

// Expects an InputError whose message contains every given fragment.
template <typename F>
void ExpectInputError(F&& f, const std::vector<std::string>& fragments)
{
  try
  {
    f();
    FAIL() << "no InputError thrown";
  }
  catch (const InputError& e)
  {
    const std::string message = e.what();
    for (const auto& fragment : fragments)
    {
      EXPECT_NE(message.find(fragment), std::string::npos)
        << "'" << fragment << "' missing in: " << message;
    }
  }
}
} // namespace

TEST(Rig, LoadsNamesShapesSetsAndAliasesInFileOrder)
{
  const Rig rig = Rig::LoadString(SmallRig);
  EXPECT_EQ(rig.GetName(), "Small");
  EXPECT_EQ(rig.GetDescription(), "two targets, three shapes");
  EXPECT_EQ(rig.GetShapeNames(), (std::vector<std::string>{ "A", "O", "Blink", "Ah" }));
  EXPECT_EQ(rig.GetDeclaredTargets().size(), 3u);
  ASSERT_EQ(rig.GetShapeTerms(0).size(), 2u);
  EXPECT_EQ(rig.GetShapeTerms(0)[0].Target, "jawOpen");
  EXPECT_DOUBLE_EQ(rig.GetShapeTerms(0)[0].Coefficient, 0.6);
  EXPECT_EQ(rig.FindShape("Blink"), 2);
  EXPECT_EQ(rig.FindShape("nope"), -1);
  EXPECT_EQ(rig.GetAliasOf(3), "A");
  EXPECT_EQ(rig.GetAliasOf(0), "");
  EXPECT_EQ(rig.GetShapeTerms(3).size(), 2u);
  EXPECT_EQ(rig.GetSet("vowels"), (std::vector<std::string>{ "A", "O" }));
  EXPECT_EQ(rig.GetSetNames(), (std::vector<std::string>{ "vowels" }));
  EXPECT_THROW(rig.GetSet("consonants"), InputError);
}

TEST(Rig, ExpandIsTheSparseProductClampedToZeroOne)
{
  Rig rig = Rig::LoadString(SmallRig);
  rig.Bind(FaceTargets);
  ASSERT_TRUE(rig.IsBound());
  ASSERT_EQ(rig.GetNumberOfBoundTargets(), 4u);
  // Face order: eyeBlink_L, mouthFunnel, jawOpen, cheekPuff_L.
  std::vector<double> out(4, -7.0);
  const double shapes[4] = { 0.5, 0.25, 0.0, 0.0 };
  rig.Expand(shapes, out.data());
  EXPECT_DOUBLE_EQ(out[0], 0.0);
  EXPECT_DOUBLE_EQ(out[1], 0.5 * 0.1 + 0.25 * 0.8);
  EXPECT_DOUBLE_EQ(out[2], 0.5 * 0.6 + 0.25 * 0.5);
  EXPECT_DOUBLE_EQ(out[3], 0.0);

  // A + O at full weight would open the jaw 1.1: clamped to the sculpted maximum.
  const auto both = rig.Expand(std::map<std::string, double>{ { "A", 1.0 }, { "O", 1.0 } });
  EXPECT_DOUBLE_EQ(both[2], 1.0);
  EXPECT_DOUBLE_EQ(both[1], 0.9);
  // Negative semantic weights cannot drive a target below 0.
  const auto negative = rig.Expand(std::vector<double>{ -1.0, 0.0, 0.0, 0.0 });
  EXPECT_DOUBLE_EQ(negative[2], 0.0);
  // An alias expands like its original.
  EXPECT_EQ(rig.Expand(std::map<std::string, double>{ { "Ah", 0.3 } }),
    rig.Expand(std::map<std::string, double>{ { "A", 0.3 } }));
}

TEST(Rig, ExpandShapeFramesAddsAShapesColumnsPerFrameAndNamesABadValue)
{
  Rig rig = Rig::LoadString(SmallRig);
  rig.Bind(FaceTargets);
  // Two columns drive A (they add up), one drives O; three frames.
  const std::vector<ShapeWeightColumn> columns = { { 0, "A", { 0.1, 0.2, 0.0 } },
    { 0, "Ah", { 0.1, 0.0, 0.0 } }, { 1, "O", { 0.0, 0.5, 1.0 } } };
  const auto frames = ExpandShapeFrames(rig, columns, 3, nullptr);
  ASSERT_EQ(frames.size(), 4u);
  for (size_t f = 0; f < 3; ++f)
  {
    const std::vector<double> shapes = { columns[0].Values[f] + columns[1].Values[f],
      columns[2].Values[f], 0.0, 0.0 };
    const std::vector<double> expected = rig.Expand(shapes);
    for (size_t t = 0; t < 4; ++t)
    {
      ASSERT_EQ(frames[t].size(), 3u);
      EXPECT_DOUBLE_EQ(frames[t][f], expected[t]) << "target " << t << ", frame " << f;
    }
  }
  EXPECT_DOUBLE_EQ(frames[2][0], 0.2 * 0.6); // jawOpen of A at 0.1 + 0.1
  ExpectInputError(
    [&] {
      ExpandShapeFrames(rig, { { 1, "O", { 0.0, std::nan("") } } }, 2, nullptr);
    },
    { "row 1", "'O'", "not finite" });
  ExpectInputError(
    [&] {
      ExpandShapeFrames(rig, { { 1, "O", { 0.0 } } }, 2, nullptr);
    },
    { "'O'", "1 values for 2 frames" });
}

TEST(Rig, ExpandRejectsBadCalls)
{
  Rig rig = Rig::LoadString(SmallRig);
  ExpectInputError([&] { rig.Expand(std::vector<double>(4, 0.0)); }, { "Bind" });
  rig.Bind(FaceTargets);
  ExpectInputError(
    [&] { rig.Expand(std::vector<double>(3, 0.0)); }, { "3 shape weights", "4 shapes" });
  ExpectInputError([&] { rig.Expand(std::map<std::string, double>{ { "U", 1.0 } }); }, { "'U'" });
  ExpectInputError(
    [&] {
      rig.Expand(std::vector<double>{ 0.0, std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0 });
    },
    { "'O'", "not finite" });
}

TEST(Rig, ValidateNamesTheShapeAndTheMissingTarget)
{
  Rig rig = Rig::LoadString(SmallRig);
  EXPECT_NO_THROW(rig.Validate(FaceTargets));
  ExpectInputError(
    [&] {
      rig.Validate({ "jawOpen", "mouthFunnel" });
    },
    { "'Blink'", "'eyeBlink_L'" });
  ExpectInputError(
    [&] { rig.Bind(std::vector<std::string>{ "jawOpen" }); }, { "'A'", "'mouthFunnel'" });
  EXPECT_FALSE(rig.IsBound());
}

TEST(Rig, LoadErrorsNameTheFieldAtFault)
{
  ExpectInputError([] { Rig::LoadString("{", "bad.json"); }, { "bad.json", "not valid JSON" });
  ExpectInputError([] { Rig::LoadString("[]"); }, { "top level" });
  ExpectInputError([] { Rig::LoadString(R"({"shapes": {}})"); }, { "'name'" });
  ExpectInputError([] { Rig::LoadString(R"({"name": "x"})"); }, { "'shapes'" });
  ExpectInputError([] { Rig::LoadString(R"({"name": "x", "shapes": {}, "shape": {}})"); },
    { "unknown field 'shape'" });
  ExpectInputError(
    [] { Rig::LoadString(R"({"name": "x", "shapes": {"A": 3}})"); }, { "shape 'A'" });
  ExpectInputError([] { Rig::LoadString(R"({"name": "x", "shapes": {"A": {"jawOpen": "0.5"}}})"); },
    { "shape 'A'", "target 'jawOpen'", "number" });
  ExpectInputError(
    [] {
      Rig::LoadString(R"({"name": "x", "targets": ["jawOpen"], "shapes": {"A": {"jawOpn": 0.5}}})");
    },
    { "shape 'A'", "'jawOpn'", "'targets'" });
  ExpectInputError([] { Rig::LoadString(R"({"name": "x", "targets": ["a", "a"], "shapes": {}})"); },
    { "'a'", "twice" });
  ExpectInputError(
    [] { Rig::LoadString(R"({"name": "x", "shapes": {"E": {}, "E": {}}})"); }, { "'E'", "twice" });
  ExpectInputError(
    [] { Rig::LoadString(R"({"name": "x", "shapes": {"FF": "F"}})"); }, { "'FF'", "alias", "'F'" });
  ExpectInputError([]
    { Rig::LoadString(R"({"name": "x", "shapes": {"F": {}, "FF": "F", "V": "FF"}})"); },
    { "'V'", "itself an alias" });
  ExpectInputError([]
    { Rig::LoadString(R"({"name": "x", "shapes": {"A": {}}, "sets": {"v": ["A", "O"]}})"); },
    { "set 'v'", "'O'" });
  ExpectInputError([]
    { Rig::LoadString(R"({"name": "x", "shapes": {"A": {}}, "notes": {"B": "?"}})"); },
    { "'B'" });
  ExpectInputError([] { Rig::LoadFile("/nonexistent/rig.json"); }, { "/nonexistent/rig.json" });
}

TEST(Rig, BakeCombinesTargetDeltasLinearly)
{
  Rig rig = Rig::LoadString(SmallRig);
  rig.Bind(FaceTargets);
  // Two points, 6 values per target.
  const std::vector<float> blink = { 0, 1, 0, 0, 0, 0 };
  const std::vector<float> funnel = { 0, 0, 1, 0, 0, 2 };
  const std::vector<float> jaw = { 0, -1, 0, 0, -2, 0 };
  const std::vector<float> puff = { 5, 5, 5, 5, 5, 5 };
  const auto baked = rig.Bake<float>({ blink.data(), funnel.data(), jaw.data(), puff.data() }, 6);
  ASSERT_EQ(baked.size(), 4u);
  const std::vector<float> expectedA = { 0, -0.6f, 0.1f, 0, -1.2f, 0.2f };
  for (size_t v = 0; v < 6; ++v)
  {
    EXPECT_FLOAT_EQ(baked[0][v], expectedA[v]);
    EXPECT_FLOAT_EQ(baked[3][v], expectedA[v]); // alias
    EXPECT_FLOAT_EQ(baked[2][v], blink[v]);
  }
  EXPECT_THROW(rig.Bake<float>({ blink.data() }, 6), InputError);
  ExpectInputError(
    [&] {
      rig.Bake<float>({ blink.data(), funnel.data(), nullptr, puff.data() }, 6);
    },
    { "'A'", "'jawOpen'" });
}

TEST(Rig, BakeModelGivesTheSameGeometryAsExpandWithinZeroOne)
{
  // A 3-point face with 4 relative targets.
  MorphMesh face(3);
  face.SetTargetNames({ "Neutral", "eyeBlink_L", "mouthFunnel", "jawOpen", "cheekPuff_L" });
  auto& positions = face.AddAttribute<float>("Position", AttributeRole::Position, 3);
  const std::vector<float> neutral = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
  positions.SetNeutral(neutral.data());
  for (int t = 0; t < 4; ++t)
  {
    std::vector<float> deltas(9);
    for (size_t v = 0; v < 9; ++v)
    {
      deltas[v] = static_cast<float>((t + 1) * 0.01 * (static_cast<double>(v % 4) - 1.5));
    }
    positions.AddRelativeTarget(deltas.data(), 0.0);
  }
  Rig rig = Rig::LoadString(SmallRig);
  const MorphMesh baked = rig.BakeModel(face, { "O", "A" });
  EXPECT_EQ(baked.GetTargetNames(), (std::vector<std::string>{ "Neutral", "O", "A" }));
  ASSERT_EQ(baked.GetNumberOfAttributes(), 1u);
  const auto& bakedPositions = std::get<MorphAttribute<float>>(baked.GetAttribute(0));

  // Blend the baked model at O = 0.4, A = 0.3 and the face at the expanded weights.
  const std::vector<double> semantic = { 0.3, 0.4, 0.0, 0.0 };
  const std::vector<double> targets = rig.Expand(semantic);
  std::vector<double> faceWeights{ 1.0 };
  faceWeights.insert(faceWeights.end(), targets.begin(), targets.end());
  const std::vector<double> bakedWeights = { 1.0, 0.4, 0.3 };
  std::vector<float> viaFace(9), viaBaked(9);
  positions.Blend(faceWeights.data(), faceWeights.size(), viaFace.data(), 0, 3);
  bakedPositions.Blend(bakedWeights.data(), bakedWeights.size(), viaBaked.data(), 0, 3);
  for (size_t v = 0; v < 9; ++v)
  {
    EXPECT_NEAR(viaFace[v], viaBaked[v], 1e-6);
  }
  ExpectInputError([&] { rig.BakeModel(face, { "X" }); }, { "'X'" });
}
