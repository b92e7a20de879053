// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "morph/Distances.h"
#include "morph/MorphAttribute.h"
#include "morph/MorphMesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace morphnode;

namespace
{
// A reference blend, written as plainly as possible: sum_i w_i * G_i over absolute shapes.
std::vector<double> NaiveAbsoluteBlend(
  const std::vector<std::vector<double>>& shapes, const std::vector<double>& w)
{
  std::vector<double> out(shapes[0].size(), 0.0);
  for (size_t i = 0; i < shapes.size(); ++i)
  {
    for (size_t k = 0; k < out.size(); ++k)
    {
      out[k] += w[i] * shapes[i][k];
    }
  }
  return out;
}
} // namespace

class MorphAttributeStorage : public ::testing::TestWithParam<double>
{
};

TEST_P(MorphAttributeStorage, BlendEqualsNaiveJava3DBlend)
{
  const double sparseCoverage = GetParam();
  const size_t numPoints = 257;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::vector<double>> shapes(5, std::vector<double>(numPoints * 3));
  for (auto& v : shapes[0])
  {
    v = u(rng);
  }
  for (size_t i = 1; i < shapes.size(); ++i)
  {
    shapes[i] = shapes[0];
    // Each target moves a different fraction of the points.
    for (size_t p = 0; p < numPoints; ++p)
    {
      if ((p * i) % 7 < i)
      {
        for (int c = 0; c < 3; ++c)
        {
          shapes[i][p * 3 + c] += u(rng);
        }
      }
    }
  }
  MorphAttribute<double> attribute("Points", AttributeRole::Position, 3, numPoints);
  attribute.SetNeutral(shapes[0].data());
  for (size_t i = 1; i < shapes.size(); ++i)
  {
    attribute.AddAbsoluteTarget(shapes[i].data(), sparseCoverage);
  }
  const std::vector<double> w = { 0.1, 0.2, 0.0, 0.3, 0.4 };
  std::vector<double> out(numPoints * 3, -99.0);
  // Two ranges, as a parallel caller would split them.
  attribute.Blend(w.data(), w.size(), out.data(), 0, 100);
  attribute.Blend(w.data(), w.size(), out.data(), 100, numPoints);
  const auto expected = NaiveAbsoluteBlend(shapes, w);
  for (size_t k = 0; k < out.size(); ++k)
  {
    ASSERT_NEAR(out[k], expected[k], 1e-12) << "value " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(DenseAndSparse, MorphAttributeStorage, ::testing::Values(0.0, 0.5, 1.0));

TEST(MorphAttribute, ChoosesSparseStoragePerTargetByCoverage)
{
  const size_t numPoints = 100;
  std::vector<float> neutral(numPoints * 3, 0.0f);
  std::vector<float> few(neutral), many(neutral);
  few[3 * 10] = 1.0f;
  for (size_t p = 0; p < 80; ++p)
  {
    many[3 * p + 1] = 2.0f;
  }
  MorphAttribute<float> a("Points", AttributeRole::Position, 3, numPoints);
  a.SetNeutral(neutral.data());
  a.AddAbsoluteTarget(few.data(), 0.3);
  a.AddAbsoluteTarget(many.data(), 0.3);
  EXPECT_TRUE(a.GetTarget(1).IsSparse());
  EXPECT_EQ(a.GetTarget(1).GetNumberOfMovedPoints(), 1u);
  EXPECT_FALSE(a.GetTarget(2).IsSparse());
  EXPECT_EQ(a.GetTarget(2).GetNumberOfMovedPoints(), 80u);
  EXPECT_DOUBLE_EQ(a.GetTarget(2).GetMaxNorm(), 2.0);
  EXPECT_DOUBLE_EQ(a.GetTarget(2).GetSumNorm(), 160.0);
}

TEST(MorphAttribute, ResultDoesNotDependOnStorage)
{
  // The same targets stored densely, sparsely, and mixed (as two pieces of one mesh may
  // store them) blend to the same bits: every point gets its targets in target order.
  const size_t numPoints = 3000;
  const size_t numTargets = 11;
  std::mt19937 random(42);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::vector<float> neutral(numPoints * 3);
  for (float& v : neutral)
  {
    v = value(random);
  }
  std::vector<std::vector<float>> deltas(numTargets, std::vector<float>(numPoints * 3, 0.0f));
  for (size_t t = 0; t < numTargets; ++t)
  {
    for (size_t p = 0; p < numPoints; ++p)
    {
      if ((p * 7 + t * 13) % 5 < 2) // 40 % of the points move
      {
        for (size_t c = 0; c < 3; ++c)
        {
          deltas[t][3 * p + c] = 0.1f * value(random);
        }
      }
    }
  }
  std::vector<double> weights(numTargets + 1);
  for (double& w : weights)
  {
    w = 0.05 + 0.9 * (value(random) + 1.0f) / 2.0f;
  }
  auto blend = [&](auto coverageOf)
  {
    MorphAttribute<float> a("Points", AttributeRole::Position, 3, numPoints);
    a.SetNeutral(neutral.data());
    for (size_t t = 0; t < numTargets; ++t)
    {
      a.AddRelativeTarget(deltas[t].data(), coverageOf(t));
    }
    std::vector<float> out(numPoints * 3);
    a.Blend(weights.data(), weights.size(), out.data(), 0, numPoints);
    return out;
  };
  const auto dense = blend([](size_t) { return 0.0; });
  const auto sparse = blend([](size_t) { return 1.0; });
  const auto mixed = blend([](size_t t) { return t % 3 == 1 ? 1.0 : 0.0; });
  EXPECT_EQ(dense, sparse);
  EXPECT_EQ(dense, mixed);
}

// Sparse targets keep long runs of consecutive moved points as spans and the rest as single
// points. Runs of 1 to 40 points (both kinds), blended over point ranges that cut through
// them at odd places, give the same bits as dense storage blended in one range.
TEST(MorphAttribute, SparseSpansBlendLikeDenseOverAnyRanges)
{
  const size_t numPoints = 2000;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::uniform_int_distribution<size_t> runLength(1, 40), gapLength(1, 25);
  std::vector<float> neutral(numPoints * 3), deltas(numPoints * 3, 0.0f);
  for (float& v : neutral)
  {
    v = value(random);
  }
  size_t spans = 0, singles = 0;
  for (size_t p = gapLength(random); p < numPoints; p += gapLength(random))
  {
    const size_t begin = p, end = std::min(numPoints, p + runLength(random));
    for (; p < end; ++p)
    {
      for (size_t c = 0; c < 3; ++c)
      {
        deltas[3 * p + c] = 0.1f * value(random) + 0.2f; // never exactly zero
      }
    }
    const bool span = end - begin >= TargetDeltas<float>::MinSpanPoints;
    spans += span ? 1 : 0;
    singles += span ? 0 : end - begin;
  }
  const auto build = [&](double coverage)
  {
    MorphAttribute<float> a("Points", AttributeRole::Position, 3, numPoints);
    a.SetNeutral(neutral.data());
    a.AddRelativeTarget(deltas.data(), coverage);
    return a;
  };
  const MorphAttribute<float> sparse = build(1.0), dense = build(0.0);
  ASSERT_TRUE(sparse.GetTarget(1).IsSparse());
  EXPECT_GT(spans, 10u);
  EXPECT_GT(singles, 10u);
  EXPECT_EQ(sparse.GetTarget(1).GetNumberOfSpans(), spans);
  EXPECT_EQ(sparse.GetTarget(1).GetNumberOfSinglePoints(), singles);
  EXPECT_EQ(
    dense.GetTarget(1).GetNumberOfSpans() + dense.GetTarget(1).GetNumberOfSinglePoints(), 0u);

  const double w[2] = { 0.3, 0.7 };
  std::vector<float> expected(numPoints * 3), pieces(numPoints * 3);
  dense.Blend(w, 2, expected.data(), 0, numPoints);
  std::uniform_int_distribution<size_t> step(1, 97);
  for (size_t begin = 0, end = 0; begin < numPoints; begin = end)
  {
    end = std::min(numPoints, begin + step(random));
    sparse.Blend(w, 2, pieces.data(), begin, end);
  }
  EXPECT_EQ(pieces, expected);

  std::vector<float> roundTrip(numPoints * 3);
  sparse.GetTarget(1).ToDense(roundTrip.data());
  EXPECT_EQ(roundTrip, deltas);
}

TEST(MorphAttribute, RenormalizesNormals)
{
  const float up[3] = { 0.f, 0.f, 1.f };
  const float side[3] = { 1.f, 0.f, 0.f };
  MorphAttribute<float> n("Normals", AttributeRole::Normal, 3, 1);
  n.SetNeutral(up);
  n.AddAbsoluteTarget(side, 0.0);
  const double w[2] = { 0.5, 0.5 };
  float out[3];
  n.Blend(w, 2, out, 0, 1);
  EXPECT_NEAR(out[0], std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(out[2], std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(std::hypot(out[0], out[1], out[2]), 1.0, 1e-6);
}

// The vectorized renormalization must round exactly as the scalar rule it replaced: length
// in double, its inverse rounded to float, one multiply per component; a zero-length normal
// (opposite shapes cancelling) stays zero instead of turning into NaN. 1001 points, so the
// vector loop's tail runs too.
TEST(MorphAttribute, RenormalizedNormalsMatchTheScalarRuleBitForBit)
{
  const size_t numPoints = 1001;
  std::vector<float> neutral(numPoints * 3), target(numPoints * 3);
  for (size_t p = 0; p < numPoints; ++p)
  {
    const double a = 0.37 * static_cast<double>(p);
    neutral[3 * p] = static_cast<float>(std::cos(a));
    neutral[3 * p + 1] = static_cast<float>(std::sin(a));
    neutral[3 * p + 2] = 0.25f;
    const bool cancels = p % 97 == 0; // target = -neutral: 0.5 n + 0.5 t = 0
    for (int c = 0; c < 3; ++c)
    {
      target[3 * p + c] = cancels ? -neutral[3 * p + c] : static_cast<float>(std::cos(a * (c + 2)));
    }
  }
  MorphAttribute<float> normals("Normals", AttributeRole::Normal, 3, numPoints);
  normals.SetNeutral(neutral.data());
  normals.AddAbsoluteTarget(target.data(), 0.0);
  const double w[2] = { 0.5, 0.5 };
  std::vector<float> out(numPoints * 3);
  normals.Blend(w, 2, out.data(), 0, numPoints);

  for (size_t p = 0; p < numPoints; ++p)
  {
    float v[3];
    double sum = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      v[c] = neutral[3 * p + c];
      v[c] += 0.5f * (target[3 * p + c] - neutral[3 * p + c]);
      sum += static_cast<double>(v[c]) * static_cast<double>(v[c]);
    }
    const double len = std::sqrt(sum);
    for (int c = 0; c < 3; ++c)
    {
      const float expected = len > 0.0 ? v[c] * static_cast<float>(1.0 / len) : v[c];
      ASSERT_EQ(out[3 * p + c], expected) << "point " << p << " component " << c;
    }
    if (p % 97 == 0)
    {
      EXPECT_EQ(std::hypot(out[3 * p], out[3 * p + 1], out[3 * p + 2]), 0.0) << "point " << p;
    }
  }
}

// The same for normals stored as double: every clone of the kernel (AVX-512, AVX2, baseline)
// rounds as the scalar rule, none fuses the squares into an FMA.
TEST(MorphAttribute, RenormalizedDoubleNormalsMatchTheScalarRuleBitForBit)
{
  const size_t numPoints = 1001;
  std::vector<double> neutral(numPoints * 3), target(numPoints * 3);
  for (size_t p = 0; p < numPoints; ++p)
  {
    const double a = 0.37 * static_cast<double>(p);
    for (int c = 0; c < 3; ++c)
    {
      neutral[3 * p + c] = std::cos(a * (c + 1)) / 3.0;
      target[3 * p + c] = std::sin(a * (c + 3)) / 7.0;
    }
  }
  MorphAttribute<double> normals("Normals", AttributeRole::Normal, 3, numPoints);
  normals.SetNeutral(neutral.data());
  normals.AddAbsoluteTarget(target.data(), 0.0);
  const double w[2] = { 0.3, 0.7 };
  std::vector<double> out(numPoints * 3);
  normals.Blend(w, 2, out.data(), 0, numPoints);
  for (size_t p = 0; p < numPoints; ++p)
  {
    volatile double v[3]; // volatile: no FMA in the reference either
    volatile double sum = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      v[c] = neutral[3 * p + c];
      const volatile double delta = target[3 * p + c] - neutral[3 * p + c];
      const volatile double scaled = 0.7 * delta;
      v[c] = v[c] + scaled;
      const volatile double square = v[c] * v[c];
      sum = sum + square;
    }
    const double len = std::sqrt(sum);
    for (int c = 0; c < 3; ++c)
    {
      const double expected = len > 0.0 ? v[c] * (1.0 / len) : v[c];
      ASSERT_EQ(out[3 * p + c], expected) << "point " << p << " component " << c;
    }
  }
}

TEST(MorphAttribute, ClampsColors)
{
  const double black[3] = { 0, 0, 0 };
  const double white[3] = { 255, 255, 255 };
  MorphAttribute<double> c("Colors", AttributeRole::Color, 3, 1);
  c.SetClampRange(0, 255);
  c.SetNeutral(black);
  c.AddAbsoluteTarget(white, 0.0);
  const double w[2] = { -0.5, 1.5 }; // relative-mode overshoot
  double out[3];
  c.Blend(w, 2, out, 0, 1);
  EXPECT_EQ(out[0], 255.0);
}

TEST(MorphAttribute, ZeroWeightTargetsAreNotRead)
{
  const double neutral[3] = { 1, 2, 3 };
  const double target[3] = { 4, 5, 6 };
  MorphAttribute<double> a("Points", AttributeRole::Position, 3, 1);
  a.SetNeutral(neutral);
  a.AddAbsoluteTarget(target, 0.0);
  // A NaN weight would poison the result if the zero-weight path read the target.
  const double w[2] = { 1.0, 0.0 };
  double out[3];
  a.Blend(w, 2, out, 0, 1);
  EXPECT_EQ(out[0], 1.0);
}

TEST(MorphAttribute, RejectsNonFiniteTargets)
{
  const double neutral[3] = { 0, 0, 0 };
  const double bad[3] = { 0, std::nan(""), 0 };
  MorphAttribute<double> a("Points", AttributeRole::Position, 3, 1);
  a.SetNeutral(neutral);
  EXPECT_THROW(a.AddAbsoluteTarget(bad, 0.0), InputError);
}

TEST(Distances, NormalizedDistancesAndAnimatedRegion)
{
  // Three points; target 1 moves point 0 by 1; target 2 moves points 1 and 2 by 2.
  const double neutral[9] = { 0, 0, 0, 1, 0, 0, 2, 0, 0 };
  double t1[9], t2[9];
  std::copy(neutral, neutral + 9, t1);
  std::copy(neutral, neutral + 9, t2);
  t1[1] += 1.0;
  t2[5] += 2.0;
  t2[8] -= 2.0;
  MorphMesh model(3);
  model.SetTargetNames({ "Neutral", "a", "b" });
  auto& p = model.AddAttribute<double>("Points", AttributeRole::Position, 3);
  p.SetNeutral(neutral);
  p.AddAbsoluteTarget(t1, 0.5);
  p.AddAbsoluteTarget(t2, 0.5);
  const TargetDistances d = model.ComputeDistances();
  EXPECT_DOUBLE_EQ(d.DistMorph[1], 1.0);
  EXPECT_DOUBLE_EQ(d.DistMorph[2], 4.0);
  EXPECT_DOUBLE_EQ(d.DistNorm[0], 0.0);
  EXPECT_DOUBLE_EQ(d.DistNorm[1], 0.25);
  EXPECT_DOUBLE_EQ(d.DistNorm[2], 1.0);
  EXPECT_DOUBLE_EQ(d.MaxDisplacement[2], 2.0);
  EXPECT_EQ(model.ComputeAnimatedRegion(), (std::vector<double>{ 1.0, 2.0, 2.0 }));
  EXPECT_EQ(model.ComputePointDistances(1), (std::vector<double>{ 1.0, 0.0, 0.0 }));
}

TEST(MorphMesh, ValidateCatchesMissingTargets)
{
  MorphMesh model(1);
  model.SetTargetNames({ "Neutral", "a" });
  const double v[3] = { 0, 0, 0 };
  model.AddAttribute<double>("Points", AttributeRole::Position, 3).SetNeutral(v);
  EXPECT_THROW(model.Validate(), InputError);
}
