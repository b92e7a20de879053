// SPDX-License-Identifier: BSD-3-Clause
// The glTF animation sampler (gltf/GltfAnimation.h) against the glTF 2.0 specification's
// definitions (Appendix C): STEP, LINEAR (slerp for rotations), CUBICSPLINE (Hermite with
// tangents scaled by the key interval, checked through its derivatives at the keys), holding
// the first/last value outside the keys, default weights, weights by target name over the
// parts of a head, and bad animations named by their JSON pointer.

#include "gltf/GltfAnimation.h"

#include "GltfAnimatedTestFiles.h"
#include "base/Error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace
{
using morphnode::GltfAnimationPlayer;
using morphnode::GltfScene;
using morphnode::InputError;
using namespace gltftest;

GltfScene Load(const std::string& bytes)
{
  return morphnode::LoadGltfSceneFromMemory(
    bytes.data(), bytes.size(), std::string(), {}, "head.glb");
}

GltfScene Head()
{
  return Load(AnimatedHead().Glb());
}

/// Linear interpolation of the face's weights by hand.
std::vector<double> FaceLinear(double t)
{
  const auto& times = AnimatedTimes();
  const auto& w = AnimatedFaceWeights();
  size_t k = 0;
  while (k + 2 < times.size() && t >= times[k + 1])
  {
    ++k;
  }
  const double u = std::min(1.0, std::max(0.0, (t - times[k]) / (times[k + 1] - times[k])));
  std::vector<double> out(3);
  for (size_t i = 0; i < 3; ++i)
  {
    out[i] = (1 - u) * w[3 * k + i] + u * w[3 * (k + 1) + i];
  }
  return out;
}

double AngleAboutY(const std::array<double, 4>& q)
{
  EXPECT_NEAR(q[0], 0, 1e-12);
  EXPECT_NEAR(q[2], 0, 1e-12);
  return 2 * std::atan2(q[1], q[3]) * 180.0 / 3.14159265358979323846;
}

std::string ErrorOf(const std::string& bytes)
{
  try
  {
    const GltfScene scene = Load(bytes);
    for (size_t a = 0; a < scene.Animations.size(); ++a)
    {
      GltfAnimationPlayer(scene, static_cast<int>(a), "head.glb").Sample(0.7);
    }
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "no error";
}

template <typename T>
void Poke(Builder& b, int view, size_t byte, T value)
{
  const size_t offset =
    b.Doc["bufferViews"][static_cast<size_t>(view)]["byteOffset"].get<size_t>() + byte;
  std::memcpy(b.Bin.data() + offset, &value, sizeof(T));
}

int ViewOf(const Builder& b, int accessor)
{
  return b.Doc["accessors"][static_cast<size_t>(accessor)]["bufferView"].get<int>();
}
} // namespace

TEST(GltfAnimation, NamesRangeAndKeys)
{
  const GltfScene scene = Head();
  ASSERT_EQ(scene.Animations.size(), 4u);
  EXPECT_EQ(morphnode::FindGltfAnimation(scene, "Cubic"), 2);
  EXPECT_EQ(morphnode::FindGltfAnimation(scene, "Nope"), -1);
  const GltfAnimationPlayer player(scene, 3);
  EXPECT_EQ(player.GetName(), "Pose");
  EXPECT_DOUBLE_EQ(player.GetStartTime(), 0.0);
  EXPECT_DOUBLE_EQ(player.GetEndTime(), 2.0);
  EXPECT_EQ(player.GetKeyTimes(), (std::vector<double>{ 0, 0.5, 1.25, 2 }));
  EXPECT_EQ(player.GetAnimatedNodes(), (std::vector<int>{ 0, 2 }));
  EXPECT_THROW(GltfAnimationPlayer(scene, 4), InputError);
  EXPECT_THROW(GltfAnimationPlayer(scene, -1), InputError);
}

TEST(GltfAnimation, LinearWeightsAndHolding)
{
  const GltfScene scene = Head();
  const GltfAnimationPlayer player(scene, 0);
  for (double t : { -1.0, 0.0, 0.1, 0.25, 0.5, 0.9, 1.25, 1.7, 2.0, 5.0 })
  {
    const auto sample = player.Sample(t);
    const std::vector<double> expected = FaceLinear(t);
    ASSERT_EQ(sample.Nodes[0].Weights.size(), 3u);
    for (size_t i = 0; i < 3; ++i)
    {
      EXPECT_NEAR(sample.Nodes[0].Weights[i], expected[i], 1e-7) << "t " << t << " target " << i;
    }
    EXPECT_TRUE(sample.Nodes[0].WeightsAnimated);
    EXPECT_NEAR(sample.Nodes[1].Weights[0], expected[0], 1e-7);
    EXPECT_TRUE(sample.Nodes[2].Weights.empty());
    // Not animated: the rest pose.
    EXPECT_FALSE(sample.Nodes[0].RotationAnimated);
    EXPECT_DOUBLE_EQ(sample.Nodes[0].World[13], 1.0);
  }
}

TEST(GltfAnimation, StepHoldsTheKeyBefore)
{
  const GltfScene scene = Head();
  const GltfAnimationPlayer player(scene, 1);
  const auto& w = AnimatedFaceWeights();
  const std::vector<std::pair<double, size_t>> cases{ { -0.5, 0 }, { 0, 0 }, { 0.49, 0 },
    { 0.5, 1 }, { 1.0, 1 }, { 1.25, 2 }, { 1.99, 2 }, { 2.0, 3 }, { 9.0, 3 } };
  for (const auto& [t, key] : cases)
  {
    const auto sample = player.Sample(t);
    for (size_t i = 0; i < 3; ++i)
    {
      EXPECT_FLOAT_EQ(static_cast<float>(sample.Nodes[0].Weights[i]), w[3 * key + i]) << "t " << t;
    }
  }
}

TEST(GltfAnimation, CubicSplineIsTheSpecsHermite)
{
  const GltfScene scene = Head();
  const GltfAnimationPlayer player(scene, 2);
  const auto& times = AnimatedTimes();
  const auto& w = AnimatedFaceWeights();
  const std::vector<float> cubic = AnimatedFaceCubic();
  auto in = [&](size_t k, size_t i) { return double(cubic[9 * k + i]); };
  auto out = [&](size_t k, size_t i) { return double(cubic[9 * k + 6 + i]); };
  // The values at the keys (not the tangents), and held outside.
  for (size_t k = 0; k < times.size(); ++k)
  {
    const auto sample = player.Sample(times[k]);
    for (size_t i = 0; i < 3; ++i)
    {
      EXPECT_NEAR(sample.Nodes[0].Weights[i], w[3 * k + i], 1e-7);
    }
  }
  EXPECT_NEAR(player.Sample(-3).Nodes[0].Weights[0], w[0], 1e-12);
  EXPECT_NEAR(player.Sample(7).Nodes[0].Weights[1], w[10], 1e-12);
  // Slopes: leaving key k at the out-tangent b_k, arriving at key k+1 at the in-tangent
  // a_k+1 (per second: the tangents are scaled by the key interval).
  const double h = 1e-4;
  for (size_t k = 0; k + 1 < times.size(); ++k)
  {
    const auto right = player.Sample(times[k] + h).Nodes[0].Weights;
    const auto left = player.Sample(times[k + 1] - h).Nodes[0].Weights;
    for (size_t i = 0; i < 3; ++i)
    {
      EXPECT_NEAR((right[i] - w[3 * k + i]) / h, out(k, i), 2e-3) << "key " << k << " target " << i;
      EXPECT_NEAR((w[3 * (k + 1) + i] - left[i]) / h, in(k + 1, i), 2e-3)
        << "key " << k + 1 << " target " << i;
    }
  }
  // One point inside, by the formula: t = 0.8 in [0.5, 1.25], u = 0.4, td = 0.75.
  const double u = 0.4, td = 0.75;
  const double h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u,
               h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  const auto mid = player.Sample(0.8).Nodes[0].Weights;
  for (size_t i = 0; i < 3; ++i)
  {
    const double expected =
      h00 * w[3 + i] + h10 * td * out(1, i) + h01 * w[6 + i] + h11 * td * in(2, i);
    EXPECT_NEAR(mid[i], expected, 1e-7);
  }
}

TEST(GltfAnimation, RotationsSlerpAndNodesCompose)
{
  const GltfScene scene = Head();
  const GltfAnimationPlayer player(scene, 3);
  // 0 -> 40 degrees over [0, 0.5]: slerp turns at constant speed (nlerp would give 9.7 at u 1/4).
  EXPECT_NEAR(AngleAboutY(player.Sample(0.125).Nodes[0].Rotation), 10.0, 1e-5);
  // 40 -> -30 over [0.5, 1.25]: u = 0.2 gives 26 degrees.
  EXPECT_NEAR(AngleAboutY(player.Sample(0.65).Nodes[0].Rotation), 26.0, 1e-5);
  EXPECT_NEAR(AngleAboutY(player.Sample(5).Nodes[0].Rotation), 10.0, 1e-5);
  // The eye turns by STEP: 25 degrees about x from 0.5 to 2.
  const auto s = player.Sample(0.7);
  EXPECT_NEAR(
    2 * std::atan2(s.Nodes[2].Rotation[0], s.Nodes[2].Rotation[3]) * 180 / 3.14159265358979323846,
    25.0, 1e-4);
  EXPECT_TRUE(s.Nodes[2].RotationAnimated);
  // Translation, linear: 0.7 is u = 4/15 of (0.1, 1.2, 0) -> (-0.2, 0.9, 0.1).
  const double u = 0.2 / 0.75;
  EXPECT_NEAR(s.Nodes[0].Translation[0], 0.1 + u * -0.3, 1e-7);
  EXPECT_NEAR(s.Nodes[0].Translation[1], 1.2 + u * -0.3, 1e-7);
  EXPECT_NEAR(s.Nodes[0].Translation[2], u * 0.1, 1e-7);
  // World = parent's world * local: the eye's origin is the head's T R S applied to its
  // translation.
  const auto& head = s.Nodes[0];
  const morphnode::GltfMatrix expectedHead =
    morphnode::GltfComposeTrs(head.Translation, head.Rotation, head.Scale);
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_NEAR(head.World[static_cast<size_t>(i)], expectedHead[static_cast<size_t>(i)], 1e-12);
  }
  const morphnode::GltfMatrix eye = morphnode::GltfMultiply(expectedHead, s.Nodes[2].Local);
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_NEAR(s.Nodes[2].World[static_cast<size_t>(i)], eye[static_cast<size_t>(i)], 1e-12);
  }
  // Weights stay at the defaults (node 0's mesh weights 0.1 0 0) when not animated.
  EXPECT_EQ(s.Nodes[0].Weights, (std::vector<double>{ 0.1, 0, 0 }));
  EXPECT_FALSE(s.Nodes[0].WeightsAnimated);
}

TEST(GltfAnimation, SlerpTakesTheShorterArc)
{
  morphnode::GltfAnimationSampler sampler;
  sampler.Times = { 0, 1 };
  // 170 degrees about z, then the same orientation as -q (190 degrees written the long way).
  const double a = 170.0 * 3.14159265358979323846 / 360.0,
               b = 190.0 * 3.14159265358979323846 / 360.0;
  sampler.Values = { 0, 0, static_cast<float>(std::sin(a)), static_cast<float>(std::cos(a)), 0, 0,
    static_cast<float>(std::sin(b)), static_cast<float>(std::cos(b)) };
  double q[4];
  morphnode::SampleGltfSampler(sampler, 4, true, 0.5, q);
  // Half way from 170 to 190 degrees is 180, not 0 (which the long way round would give).
  EXPECT_NEAR(std::abs(q[2]), 1.0, 1e-6);
  EXPECT_NEAR(q[3], 0.0, 1e-6);
  sampler.Values.resize(7);
  EXPECT_THROW(morphnode::SampleGltfSampler(sampler, 4, true, 0.5, q), InputError);
}

TEST(GltfAnimation, DuplicateKeyTimesJump)
{
  morphnode::GltfAnimationSampler sampler;
  sampler.Times = { 0, 1, 1, 2 };
  sampler.Values = { 0, 1, 5, 6 };
  double v = 0;
  morphnode::SampleGltfSampler(sampler, 1, false, 0.5, &v);
  EXPECT_DOUBLE_EQ(v, 0.5);
  morphnode::SampleGltfSampler(sampler, 1, false, 1.0, &v);
  EXPECT_DOUBLE_EQ(v, 5.0);
  morphnode::SampleGltfSampler(sampler, 1, false, 1.5, &v);
  EXPECT_DOUBLE_EQ(v, 5.5);
}

TEST(GltfAnimation, WeightsByTargetNameOverTheHead)
{
  const GltfScene scene = Head();
  const auto rest = morphnode::GltfWeightsByTargetName(scene, morphnode::GltfRestPose(scene));
  EXPECT_EQ(rest.Names, (std::vector<std::string>{ "jawOpen", "smile", "eyeBlinkLeft" }));
  EXPECT_EQ(rest.Values, (std::vector<double>{ 0.1, 0, 0 }));
  // The teeth's default jawOpen is 0 while the face's is 0.1: reported.
  EXPECT_EQ(rest.Disagreements, (std::vector<std::string>{ "jawOpen" }));

  const GltfAnimationPlayer player(scene, 0);
  const auto named = morphnode::GltfWeightsByTargetName(scene, player.Sample(0.9));
  const std::vector<double> expected = FaceLinear(0.9);
  ASSERT_EQ(named.Values.size(), 3u);
  for (size_t i = 0; i < 3; ++i)
  {
    EXPECT_NEAR(named.Values[i], expected[i], 1e-7);
  }
  EXPECT_TRUE(named.Disagreements.empty()); // the teeth follow the face's jawOpen
}

TEST(GltfAnimation, BadAnimationsNameTheirPlace)
{
  // Key times going back.
  {
    Builder b = AnimatedHead();
    const int times = b.Doc["animations"][0]["samplers"][0]["input"].get<int>();
    Poke<float>(b, ViewOf(b, times), 8, 0.25f);
    EXPECT_NE(
      ErrorOf(b.Glb()).find(
        "key time 2 (0.25 s, input of /animations/0/samplers/0) is earlier than the key before it"),
      std::string::npos)
      << ErrorOf(b.Glb());
  }
  // NaN in the key times and in the weights.
  {
    Builder b = AnimatedHead();
    const int times = b.Doc["animations"][0]["samplers"][0]["input"].get<int>();
    Poke<float>(b, ViewOf(b, times), 4, std::nanf(""));
    const std::string e = ErrorOf(b.Glb());
    EXPECT_NE(e.find("/accessors/" + std::to_string(times)), std::string::npos) << e;
    EXPECT_NE(e.find("NaN"), std::string::npos) << e;
  }
  {
    Builder b = AnimatedHead();
    const int output = b.Doc["animations"][2]["samplers"][0]["output"].get<int>();
    Poke<float>(b, ViewOf(b, output), 12, std::nanf(""));
    const std::string e = ErrorOf(b.Glb());
    EXPECT_NE(e.find("/accessors/" + std::to_string(output)), std::string::npos) << e;
    EXPECT_NE(e.find("NaN"), std::string::npos) << e;
  }
  // CUBICSPLINE weights without their tangents (output count of LINEAR).
  {
    Builder b = AnimatedHead();
    json doc = b.Finished();
    doc["animations"][2]["samplers"][0]["output"] = doc["animations"][0]["samplers"][0]["output"];
    const std::string e = ErrorOf(Builder::MakeGlb(doc.dump(), b.PaddedBin()));
    EXPECT_NE(e.find("/animations/2/samplers/0/output: 12 output elements, but 4 keys of weights "
                     "(3 morph targets) "
                     "with CUBICSPLINE tangents need 36"),
      std::string::npos)
      << e;
  }
  // Weights for the wrong number of targets (the teeth's sampler on the face).
  {
    Builder b = AnimatedHead();
    json doc = b.Finished();
    doc["animations"][0]["channels"][0]["sampler"] = 1;
    const std::string e = ErrorOf(Builder::MakeGlb(doc.dump(), b.PaddedBin()));
    EXPECT_NE(e.find("/animations/0/samplers/1/output: 4 output elements, but 4 keys of weights (3 "
                     "morph targets) need 12"),
      std::string::npos)
      << e;
  }
  // A channel to a node that does not exist.
  {
    Builder b = AnimatedHead();
    json doc = b.Finished();
    doc["animations"][3]["channels"][3]["target"]["node"] = 7;
    const std::string e = ErrorOf(Builder::MakeGlb(doc.dump(), b.PaddedBin()));
    EXPECT_NE(e.find("/animations/3/channels/3/target/node: there is no node 7"), std::string::npos)
      << e;
  }
  // The TRS of a node given by a matrix (glTF forbids animating it): found by the player.
  {
    Builder b = AnimatedHead();
    json doc = b.Finished();
    doc["nodes"][2].erase("translation");
    doc["nodes"][2]["matrix"] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.3, 0.2, 0.1, 1 };
    const std::string e = ErrorOf(Builder::MakeGlb(doc.dump(), b.PaddedBin()));
    EXPECT_NE(e.find("head.glb: /animations/3/channels/3/target/node: node 2 gives a matrix"),
      std::string::npos)
      << e;
  }
}
