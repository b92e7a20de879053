// SPDX-License-Identifier: BSD-3-Clause
// The core morph node: weight mode, optimizer settings and presets, effective weights,
// error bound, active count and the blend of a point range.
#include "base/Error.h"
#include "morph/MorphNode.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>

using namespace morphnode;

namespace
{
constexpr size_t NumPoints = 97;
constexpr size_t NumTargets = 5; // neutral + 4

/// Absolute shapes (neutral first) of positions, normals (float) and a 2-component double
/// attribute; target k moves only some points, so sparse and dense storage both occur.
struct Shapes
{
  std::vector<std::vector<float>> Positions, Normals;
  std::vector<std::vector<double>> Extra;
};

Shapes MakeShapes()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  Shapes s;
  for (size_t t = 0; t < NumTargets; ++t)
  {
    std::vector<float> p(3 * NumPoints), n(3 * NumPoints);
    std::vector<double> e(2 * NumPoints);
    for (size_t i = 0; i < NumPoints; ++i)
    {
      // Target t moves every (t+1)-th point; the neutral is random.
      const bool moves = t > 0 && i % (t + 1) == 0;
      for (int c = 0; c < 3; ++c)
      {
        p[3 * i + c] = t == 0 ? u(rng) : s.Positions[0][3 * i + c] + (moves ? 0.1f * u(rng) : 0.f);
        n[3 * i + c] = t == 0 ? u(rng) : s.Normals[0][3 * i + c] + (moves ? 0.3f * u(rng) : 0.f);
      }
      for (int c = 0; c < 2; ++c)
      {
        e[2 * i + c] = t == 0 ? u(rng) : s.Extra[0][2 * i + c] + (moves ? u(rng) : 0.0);
      }
    }
    s.Positions.push_back(p);
    s.Normals.push_back(n);
    s.Extra.push_back(e);
  }
  return s;
}

std::shared_ptr<const MorphMesh> MakeMesh(const Shapes& s, double sparseCoverage = 0.3)
{
  auto mesh = std::make_shared<MorphMesh>(NumPoints);
  mesh->SetTargetNames(DefaultTargetNames(NumTargets));
  // Each attribute filled before the next is added (adding may move the earlier ones).
  auto fill = [&](auto& attribute, const auto& shapes)
  {
    attribute.SetNeutral(shapes[0].data());
    for (size_t t = 1; t < NumTargets; ++t)
    {
      attribute.AddAbsoluteTarget(shapes[t].data(), sparseCoverage);
    }
  };
  fill(mesh->AddAttribute<float>("Points", AttributeRole::Position, 3), s.Positions);
  fill(mesh->AddAttribute<float>("Normals", AttributeRole::Normal, 3), s.Normals);
  fill(mesh->AddAttribute<double>("Extra", AttributeRole::Generic, 2), s.Extra);
  return mesh;
}

/// Java3D's blend in double: sum_t w_t G_t over absolute shapes.
template <typename T>
std::vector<double> Naive(const std::vector<std::vector<T>>& shapes, const std::vector<double>& w)
{
  std::vector<double> out(shapes[0].size(), 0.0);
  for (size_t t = 0; t < shapes.size(); ++t)
  {
    for (size_t i = 0; i < out.size(); ++i)
    {
      out[i] += w[t] * static_cast<double>(shapes[t][i]);
    }
  }
  return out;
}

struct Buffers
{
  std::vector<float> Points = std::vector<float>(3 * NumPoints, -7.f);
  std::vector<float> Normals = std::vector<float>(3 * NumPoints, -7.f);
  std::vector<double> Extra = std::vector<double>(2 * NumPoints, -7.0);
  std::vector<AttributeOutput> Outputs() { return { Points.data(), Normals.data(), Extra.data() }; }
};
} // namespace

TEST(MorphNode, EffectiveWeightsFollowTheWeightMode)
{
  MorphNode node(MakeMesh(MakeShapes()));
  EXPECT_EQ(node.GetNumberOfTargets(), NumTargets);
  EXPECT_EQ(node.GetWeightMode(), WeightMode::Normalize);
  const auto& w = node.SetWeights({ 2.0, 1.0, 0.0, 1.0, 0.0 });
  ASSERT_EQ(w.size(), NumTargets);
  EXPECT_DOUBLE_EQ(w[0], 0.5);
  EXPECT_DOUBLE_EQ(w[1], 0.25);
  EXPECT_DOUBLE_EQ(w[3], 0.25);
  EXPECT_EQ(node.GetActiveTargetCount(), 2);
  EXPECT_EQ(node.GetErrorBound(), 0.0);

  node.SetWeightMode(WeightMode::Relative);
  node.SetWeights({ 9.0, 0.5, 0.75, 0.0, 0.0 });
  EXPECT_DOUBLE_EQ(node.GetEffectiveWeights()[0], 1.0 - 1.25);
  EXPECT_EQ(node.GetActiveTargetCount(), 2);
}

// Java3D's Morph accepts any weights summing to 1 within 1e-4, a negative neutral included.
TEST(MorphNode, StrictModeAcceptsNegativeWeightsSummingToOne)
{
  MorphNode node(MakeMesh(MakeShapes()));
  node.SetWeightMode(WeightMode::Strict);
  const std::vector<double> java3d{ 1.3, -0.1, -0.2, 0.0, 0.0 };
  EXPECT_EQ(node.SetWeights(java3d), java3d);
  const std::vector<double> negativeNeutral{ -0.25, 0.5, 0.75, 0.0, 0.0 };
  EXPECT_EQ(node.SetWeights(negativeNeutral), negativeNeutral);
  EXPECT_THROW(node.SetWeights({ 1.3, -0.1, -0.1998, 0.0, 0.0 }), InputError);
  EXPECT_FALSE(node.HasEffectiveWeights());
}

TEST(MorphNode, OptimizerMatchesTheWeightOptimizer)
{
  auto mesh = MakeMesh(MakeShapes());
  MorphNode node(mesh);
  OptimizerSettings s;
  s.Threshold = 0.15;
  s.Strategy = Redistribution::Maximum;
  node.SetOptimizerSettings(s);
  WeightOptimizer reference;
  reference.SetSettings(s);
  reference.SetTargetDistances(mesh->ComputeDistances());
  const std::vector<double> w{ 0.4, 0.3, 0.1, 0.12, 0.08 };
  node.SetWeightMode(WeightMode::Strict); // the weights as given, as the optimizer gets them
  EXPECT_EQ(node.SetWeights(w), reference.Optimize(w));
  EXPECT_EQ(node.GetErrorBound(), reference.GetLastErrorBound());
  EXPECT_GT(node.GetErrorBound(), 0.0);
  EXPECT_EQ(node.GetActiveTargetCount(), 1);
  EXPECT_EQ(node.GetTargetDistances().DistNorm, mesh->ComputeDistances().DistNorm);
}

TEST(MorphNode, PresetsSetTheMethodAndKeepBudgetAndHysteresis)
{
  MorphNode node(MakeMesh(MakeShapes()));
  OptimizerSettings s;
  s.MaxActiveTargets = 3;
  s.Hysteresis = 0.25;
  node.SetOptimizerSettings(s);
  for (int p = 0; p < NumberOfOptimizerPresets; ++p)
  {
    const auto preset = static_cast<OptimizerPreset>(p);
    node.SetOptimizerPreset(preset, 0.2, 0.01);
    OptimizerSettings expected = MakeOptimizerSettings(preset, 0.2, 0.01);
    const OptimizerSettings& got = node.GetOptimizerSettings();
    EXPECT_EQ(got.Threshold, expected.Threshold) << OptimizerPresetName(preset);
    EXPECT_EQ(got.Strategy, expected.Strategy) << OptimizerPresetName(preset);
    EXPECT_EQ(got.AdjustThreshold, expected.AdjustThreshold) << OptimizerPresetName(preset);
    EXPECT_EQ(got.MaxVertexError, expected.MaxVertexError) << OptimizerPresetName(preset);
    EXPECT_EQ(got.MaxActiveTargets, 3) << OptimizerPresetName(preset);
    EXPECT_EQ(got.Hysteresis, 0.25) << OptimizerPresetName(preset);
  }
  // The adjusted preset is the paper's th_adj: a target moving more keeps a lower threshold.
  node.SetOptimizerPreset(OptimizerPreset::Adjusted, 0.2, 0.0);
  EXPECT_TRUE(node.GetOptimizerSettings().AdjustThreshold);
  EXPECT_EQ(node.GetOptimizerSettings().Strategy, Redistribution::Remaining);
  // Invalid settings are refused and the previous ones kept.
  EXPECT_THROW(node.SetOptimizerPreset(OptimizerPreset::FixedMaximum, -1.0, 0.0), InputError);
  EXPECT_TRUE(node.GetOptimizerSettings().AdjustThreshold);
}

TEST(MorphNode, ErrorBoundHoldsOnTheBlend)
{
  const Shapes shapes = MakeShapes();
  MorphNode node(MakeMesh(shapes));
  const std::vector<double> w{ 0.35, 0.3, 0.05, 0.2, 0.1 };
  node.SetWeightMode(WeightMode::Strict);
  node.SetWeights(w);
  Buffers exact;
  node.Blend(exact.Outputs(), 0, NumPoints);
  EXPECT_EQ(node.GetActiveTargetCount(), 4);

  node.SetOptimizerPreset(OptimizerPreset::FixedRemaining, 0.15, 0.0);
  node.SetWeights(w);
  Buffers pruned;
  node.Blend(pruned.Outputs(), 0, NumPoints);
  EXPECT_EQ(node.GetActiveTargetCount(), 2);
  const double bound = node.GetErrorBound();
  ASSERT_GT(bound, 0.0);
  double worst = 0.0;
  for (size_t i = 0; i < NumPoints; ++i)
  {
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      const double d = pruned.Points[3 * i + c] - exact.Points[3 * i + c];
      d2 += d * d;
    }
    worst = std::max(worst, std::sqrt(d2));
  }
  EXPECT_LE(worst, bound + 1e-6);
  EXPECT_GT(worst, 0.0);

  // Error-bounded: no vertex farther than eps.
  node.SetOptimizerPreset(OptimizerPreset::ErrorBounded, 0.0, 0.02);
  node.SetWeights(w);
  EXPECT_LE(node.GetErrorBound(), 0.02);
}

TEST(MorphNode, BlendOfARangeMatchesANaiveReference)
{
  const Shapes shapes = MakeShapes();
  for (double coverage : { 0.0, 1.0, 0.3 }) // dense, sparse, mixed storage
  {
    MorphNode node(MakeMesh(shapes, coverage));
    node.SetWeightMode(WeightMode::Strict);
    const std::vector<double> w{ -0.2, 0.7, 0.0, 0.25, 0.25 }; // negative neutral
    node.SetWeights(w);
    Buffers b;
    const size_t begin = 13, end = 71;
    node.Blend(b.Outputs(), begin, end);
    const std::vector<double> points = Naive(shapes.Positions, w);
    const std::vector<double> normals = Naive(shapes.Normals, w);
    const std::vector<double> extra = Naive(shapes.Extra, w);
    for (size_t i = 0; i < NumPoints; ++i)
    {
      const bool inside = i >= begin && i < end;
      const double len = std::sqrt(normals[3 * i] * normals[3 * i] +
        normals[3 * i + 1] * normals[3 * i + 1] + normals[3 * i + 2] * normals[3 * i + 2]);
      for (int c = 0; c < 3; ++c)
      {
        if (!inside)
        {
          EXPECT_EQ(b.Points[3 * i + c], -7.f) << "point " << i << " outside the range was written";
          EXPECT_EQ(b.Normals[3 * i + c], -7.f)
            << "normal " << i << " outside the range was written";
          continue;
        }
        EXPECT_NEAR(b.Points[3 * i + c], points[3 * i + c], 1e-5)
          << "point " << i << " coverage " << coverage;
        EXPECT_NEAR(b.Normals[3 * i + c], normals[3 * i + c] / len, 1e-5) << "normal " << i;
      }
      for (int c = 0; c < 2; ++c)
      {
        if (inside)
        {
          EXPECT_NEAR(b.Extra[2 * i + c], extra[2 * i + c], 1e-12) << "extra " << i;
        }
        else
        {
          EXPECT_EQ(b.Extra[2 * i + c], -7.0);
        }
      }
    }
  }
}

TEST(MorphNode, RangesComposeToTheWholeBitForBit)
{
  MorphNode node(MakeMesh(MakeShapes()));
  node.SetWeights({ 0.2, 0.3, 0.1, 0.25, 0.15 });
  Buffers whole, pieces;
  node.Blend(whole.Outputs(), 0, NumPoints);
  node.Blend(pieces.Outputs(), 0, 40);
  node.BlendAttribute<float>(0, pieces.Points.data(), 40, 1000); // end clamped
  node.BlendAttribute<float>(1, pieces.Normals.data(), 40, NumPoints);
  node.BlendAttribute<double>(2, pieces.Extra.data(), 40, NumPoints);
  EXPECT_EQ(whole.Points, pieces.Points);
  EXPECT_EQ(whole.Normals, pieces.Normals);
  EXPECT_EQ(whole.Extra, pieces.Extra);
}

TEST(MorphNode, BadInputIsAnInputError)
{
  MorphNode empty;
  EXPECT_EQ(empty.GetNumberOfTargets(), 0u);
  EXPECT_THROW(empty.SetWeights({ 1.0 }), InputError);

  MorphNode node(MakeMesh(MakeShapes()));
  Buffers b;
  EXPECT_THROW(node.Blend(b.Outputs(), 0, NumPoints), InputError); // no weights yet
  EXPECT_THROW(node.SetWeights({ 1.0, 0.0 }), InputError);         // count
  const double nan = std::numeric_limits<double>::quiet_NaN();
  node.SetWeights({ 1.0, 0.0, 0.0, 0.0, 0.0 });
  EXPECT_TRUE(node.HasEffectiveWeights());
  EXPECT_THROW(node.SetWeights({ 1.0, nan, 0.0, 0.0, 0.0 }), InputError);
  EXPECT_FALSE(node.HasEffectiveWeights()); // an error clears the last result
  EXPECT_EQ(node.GetActiveTargetCount(), 0);
  EXPECT_THROW(node.Blend(b.Outputs(), 0, NumPoints), InputError);

  node.SetWeights({ 1.0, 0.0, 0.0, 0.0, 0.0 });
  std::vector<double> wrongType(3 * NumPoints);
  EXPECT_THROW(
    node.Blend({ wrongType.data(), b.Normals.data(), b.Extra.data() }, 0, NumPoints), InputError);
  EXPECT_THROW(node.Blend({ b.Points.data(), b.Normals.data() }, 0, NumPoints), InputError);
  EXPECT_THROW(
    node.Blend({ static_cast<float*>(nullptr), b.Normals.data(), b.Extra.data() }, 0, NumPoints),
    InputError);
  EXPECT_THROW(node.BlendAttribute<double>(0, wrongType.data(), 0, NumPoints), InputError);
  EXPECT_THROW(node.BlendAttribute<float>(3, b.Points.data(), 0, NumPoints), InputError);

  // A mesh that fails validation is refused.
  auto broken = std::make_shared<MorphMesh>(NumPoints);
  broken->SetTargetNames(DefaultTargetNames(3));
  broken->AddAttribute<float>("Points", AttributeRole::Position, 3); // no targets added
  EXPECT_THROW(node.SetMesh(broken), InputError);
}

TEST(MorphNode, NewMeshClearsResultAndHistory)
{
  const Shapes shapes = MakeShapes();
  MorphNode node(MakeMesh(shapes));
  OptimizerSettings s;
  s.Threshold = 0.2;
  s.Hysteresis = 0.5;
  node.SetOptimizerSettings(s);
  // Target 1 active at 0.3, then at 0.15: below the threshold, but kept by hysteresis
  // (0.15 >= 0.2 * (1 - 0.5)).
  node.SetWeights({ 0.7, 0.3, 0.0, 0.0, 0.0 });
  EXPECT_EQ(node.SetWeights({ 0.85, 0.15, 0.0, 0.0, 0.0 })[1], 0.15);
  node.ResetHistory();
  EXPECT_EQ(node.SetWeights({ 0.85, 0.15, 0.0, 0.0, 0.0 })[1], 0.0);

  node.SetWeights({ 0.7, 0.3, 0.0, 0.0, 0.0 });
  node.SetMesh(MakeMesh(shapes));
  EXPECT_FALSE(node.HasEffectiveWeights());
  EXPECT_EQ(node.SetWeights({ 0.85, 0.15, 0.0, 0.0, 0.0 })[1], 0.0);
  node.SetMesh(nullptr);
  EXPECT_EQ(node.GetMesh(), nullptr);
  EXPECT_THROW(node.SetWeights({ 1.0 }), InputError);
}
