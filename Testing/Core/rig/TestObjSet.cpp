// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "rig/ObjSet.h"
#include "rig/Rig.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace morphnode;

namespace
{
/// Dense position deltas of target `target` (neutral = 0) of an OBJ set.
std::vector<float> Deltas(const MorphMesh& set, int target)
{
  std::vector<float> deltas(3 * set.GetNumberOfPoints());
  std::get<MorphAttribute<float>>(set.GetAttribute(0))
    .GetTarget(static_cast<size_t>(target))
    .ToDense(deltas.data());
  return deltas;
}

ObjMesh Parse(const std::string& text, const std::string& name = "test.obj")
{
  std::istringstream in(text);
  return ParseObj(in, name);
}

void ExpectParseError(const std::string& text, const std::string& fragment)
{
  try
  {
    Parse(text, "bad.obj");
    FAIL() << "no InputError for:\n" << text;
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// A scratch directory of its own per test, removed at the end.
class ScratchDir
{
public:
  explicit ScratchDir(const std::string& name)
    : Path(std::filesystem::temp_directory_path() / ("morphnode_objset_" + name))
  {
    std::filesystem::remove_all(this->Path);
    std::filesystem::create_directories(this->Path);
  }
  ~ScratchDir() { std::filesystem::remove_all(this->Path); }
  std::string Write(const std::string& file, const std::string& text) const
  {
    const auto p = this->Path / file;
    std::ofstream(p) << text;
    return p.string();
  }
  std::string Str() const { return this->Path.string(); }

private:
  std::filesystem::path Path;
};

const char* const Square = "# a unit square\n"
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                           "f 1 2 3 4\n";
} // namespace

TEST(ObjParse, AllCornerFormsAndFanTriangulation)
{
  const ObjMesh mesh = Parse("o face  # object name\n"
                             "v 0 0 0\nv 1 0 0\r\nv 1 1 0 1.0\nv 0 1 0 0.5 0.5 0.5\nv 0.5 2 +0\n"
                             "vt 0 0\nvt 1 0\nvt 1 1 0\n"
                             "vn 0 0 1\n"
                             "s off\nusemtl skin\n"
                             "f 1 2 3\n"
                             "f 1/1 3/3 4/2\n"
                             "f 1//1 2//1 3//1\n"
                             "f -5/1/1 -4/2/1 -3/3/1 -2/1/1 -1/2/1\n");
  EXPECT_EQ(mesh.GetNumberOfPoints(), 5u);
  EXPECT_FLOAT_EQ(mesh.Positions[13], 2.0f);
  EXPECT_EQ(mesh.TexCoords.size(), 6u);
  EXPECT_EQ(mesh.Normals.size(), 3u);
  EXPECT_EQ(mesh.NumberOfPolygons, 4u);
  // 1 + 1 + 1 + 3 (pentagon fanned) triangles.
  ASSERT_EQ(mesh.GetNumberOfTriangles(), 6u);
  EXPECT_EQ(mesh.CornerTexCoords[0], -1);
  EXPECT_EQ(mesh.CornerNormals[0], -1);
  EXPECT_EQ(mesh.CornerTexCoords[4], 2);
  EXPECT_EQ(mesh.CornerNormals[6], 0);
  EXPECT_EQ(mesh.CornerTexCoords[6], -1);
  // Pentagon fan from its first corner: (0,1,2) (0,2,3) (0,3,4).
  const std::vector<uint32_t> fan(mesh.Triangles.begin() + 9, mesh.Triangles.end());
  EXPECT_EQ(fan, (std::vector<uint32_t>{ 0, 1, 2, 0, 2, 3, 0, 3, 4 }));
}

TEST(ObjParse, MalformedLinesNameTheFileAndLine)
{
  ExpectParseError("v 0 0 0\nv 1 0\n", "bad.obj:2:");
  ExpectParseError("v 0 0 0\nv 1 x 0\n", "bad number 'x'");
  ExpectParseError("v 0 0 0\nv 1 0 0\nf 1 2\n", "bad.obj:3: 'f' needs at least 3");
  ExpectParseError(
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "bad.obj:4: vertex index 4 is out of range");
  ExpectParseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "vertex index 0");
  ExpectParseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "texture coordinate index 1");
  ExpectParseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2// 3//\n", "not one of v, v/vt");
  ExpectParseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n", "bad texture coordinate index 'a'");
  ExpectParseError("vn 0 0\n", "'vn' needs 3");
  ExpectParseError("# only a comment\n", "no vertices");
  EXPECT_THROW(ReadObj("/nonexistent/face.obj"), InputError);
}

TEST(ObjSet, ShapesAreNamedByStemAndMustMatchTheNeutral)
{
  ScratchDir dir("small");
  const std::string neutral = dir.Write("neutral.obj", Square);
  const std::string up =
    dir.Write("liftUp.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0.5\nf 1 2 3 4\n");
  const MorphMesh model = ReadObjSet(neutral, { up });
  EXPECT_EQ(model.GetTargetNames(), (std::vector<std::string>{ "Neutral", "liftUp" }));
  EXPECT_EQ(model.FindTarget("liftUp"), 1);
  EXPECT_EQ(model.FindTarget("x"), -1);
  EXPECT_EQ(Deltas(model, 1), (std::vector<float>{ 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0, 0, 0.5f }));
  ASSERT_EQ(model.GetNumberOfAttributes(), 1u);
  EXPECT_EQ(model.GetPositionAttribute(), 0);
  EXPECT_EQ(std::get<MorphAttribute<float>>(model.GetAttribute(0)).GetNeutral(),
    ReadObj(neutral).Positions);
  // the neutral's square, fan-triangulated
  EXPECT_EQ(model.GetTriangles(), (std::vector<uint32_t>{ 0, 1, 2, 0, 2, 3 }));
  EXPECT_NO_THROW(model.Validate());
  EXPECT_NEAR(model.ComputeDistances().DistMorph[1], 1.0, 1e-6);

  const std::string bad = dir.Write("short.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  try
  {
    ReadObjSet(neutral, { up, bad });
    FAIL() << "no InputError";
  }
  catch (const InputError& e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("short.obj"), std::string::npos) << message;
    EXPECT_NE(message.find("3 vertices"), std::string::npos) << message;
  }
  // Directory form: every other *.obj is a shape, in name order.
  dir.Write("another.obj", Square);
  std::filesystem::remove(bad);
  const MorphMesh fromDir = ReadObjSetDirectory(dir.Str(), "neutral.obj");
  EXPECT_EQ(fromDir.GetTargetNames(), (std::vector<std::string>{ "Neutral", "another", "liftUp" }));
  EXPECT_THROW(ReadObjSetDirectory(dir.Str(), "missing.obj"), InputError);
}

TEST(ObjSet, IctFaceKitOriginals)
{
  const std::string dir = std::string(MORPHNODE_FACEKIT_DIR) + "/obj";
  if (!std::filesystem::exists(dir + "/generic_neutral_mesh.obj"))
  {
    GTEST_SKIP() << "ICT-FaceKit OBJ folder not found at " << dir;
  }
  const ObjMesh neutral = ReadObj(dir + "/generic_neutral_mesh.obj");
  EXPECT_EQ(neutral.NumberOfPolygons, 26384u);
  EXPECT_EQ(neutral.TexCoords.size(), 2u * 28911u);
  const MorphMesh model = ReadObjSetDirectory(dir, "generic_neutral_mesh.obj");
  EXPECT_EQ(model.GetNumberOfPoints(), 26719u);
  // 25,836 quads and 548 triangles.
  EXPECT_EQ(model.GetNumberOfTriangles(), 2u * 25836u + 548u);
  EXPECT_EQ(model.GetTargetNames(),
    (std::vector<std::string>{
      "Neutral", "browInnerUp_L", "eyeBlink_L", "jawOpen", "mouthFunnel", "mouthSmile_L" }));

  const TargetDistances distances = model.ComputeDistances();
  // Every shape moves the face; jawOpen moves the most of these five (it drags the chin).
  const size_t jaw = static_cast<size_t>(model.FindTarget("jawOpen"));
  for (size_t t = 1; t < model.GetNumberOfTargets(); ++t)
  {
    EXPECT_GT(distances.DistMorph[t], 0.0) << model.GetTargetNames()[t];
    EXPECT_LE(distances.DistMorph[t], distances.DistMorph[jaw]) << model.GetTargetNames()[t];
  }
  // eyeBlink_L moves the left lid: a small fraction of the vertices by more than 0.1 mm
  // (the scan's shapes carry sub-micrometre noise everywhere else).
  const auto blink = Deltas(model, model.FindTarget("eyeBlink_L"));
  size_t movedBlink = 0;
  for (size_t p = 0; p < model.GetNumberOfPoints(); ++p)
  {
    movedBlink += std::hypot(blink[3 * p], blink[3 * p + 1], blink[3 * p + 2]) > 0.01 ? 1 : 0;
  }
  EXPECT_GT(movedBlink, 100u);
  EXPECT_LT(movedBlink, model.GetNumberOfPoints() / 5);

  // A rig baked on the real face: O = 0.35 jawOpen + 0.6 mouthFunnel, vertex by vertex.
  Rig rig =
    Rig::LoadString(R"({"name": "t", "shapes": {"O": {"jawOpen": 0.35, "mouthFunnel": 0.6}}})");
  const MorphMesh baked = rig.BakeModel(model);
  ASSERT_EQ(baked.GetTargetNames(), (std::vector<std::string>{ "Neutral", "O" }));
  EXPECT_EQ(baked.GetTriangles(), model.GetTriangles());
  const std::vector<float> o = Deltas(baked, 1);
  const auto jawDeltas = Deltas(model, model.FindTarget("jawOpen"));
  const auto funnelDeltas = Deltas(model, model.FindTarget("mouthFunnel"));
  double maxError = 0.0;
  for (size_t v = 0; v < o.size(); ++v)
  {
    maxError = std::max(maxError, std::abs(o[v] - (0.35 * jawDeltas[v] + 0.6 * funnelDeltas[v])));
  }
  EXPECT_LT(maxError, 1e-4); // centimetres
}

TEST(ObjSet, FileNamesInErrors)
{
  ScratchDir dir("errors");
  const std::string broken = dir.Write("broken.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n");
  try
  {
    ReadObj(broken);
    FAIL() << "no InputError";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find(broken + ":4:"), std::string::npos) << e.what();
  }
}
