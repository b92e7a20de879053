// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "morph/MorphMesh.h"
#include "morph/WeightOptimizer.h"
#include "morph/Weights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

using namespace morphnode;

namespace
{
TargetDistances Metrics(std::vector<double> distNorm, std::vector<double> maxDisplacement)
{
  TargetDistances d;
  d.DistMorph = distNorm;
  d.DistNorm = std::move(distNorm);
  d.MaxDisplacement = std::move(maxDisplacement);
  return d;
}

WeightOptimizer Make(OptimizerSettings s, const TargetDistances& d)
{
  WeightOptimizer o;
  o.SetSettings(s);
  o.SetTargetDistances(d);
  return o;
}

void ExpectWeights(const std::vector<double>& got, const std::vector<double>& expected)
{
  ASSERT_EQ(got.size(), expected.size());
  for (size_t i = 0; i < got.size(); ++i)
  {
    EXPECT_NEAR(got[i], expected[i], 1e-12) << "weight " << i;
  }
}

double Sum(const std::vector<double>& w)
{
  return std::accumulate(w.begin(), w.end(), 0.0);
}

const TargetDistances Flat = Metrics({ 0, 1, 0.5, 0.8 }, { 0, 1, 2, 4 });
} // namespace

TEST(WeightOptimizer, OffLeavesWeightsAlone)
{
  auto o = Make({}, Flat);
  ExpectWeights(o.Optimize({ 0.5, 0.3, 0.15, 0.05 }), { 0.5, 0.3, 0.15, 0.05 });
  EXPECT_EQ(o.GetLastErrorBound(), 0.0);
}

TEST(WeightOptimizer, FixedThresholdToMaximum)
{
  OptimizerSettings s;
  s.Threshold = 0.1;
  s.Strategy = Redistribution::Maximum;
  auto o = Make(s, Flat);
  // 0.05 < 0.1 is pruned and goes to the largest weight, the neutral's 0.5.
  ExpectWeights(o.Optimize({ 0.5, 0.3, 0.15, 0.05 }), { 0.55, 0.3, 0.15, 0.0 });
  // The largest can be a target: 0.05 + 0.08 go to target 1.
  ExpectWeights(o.Optimize({ 0.27, 0.6, 0.08, 0.05 }), { 0.27, 0.73, 0.0, 0.0 });
}

TEST(WeightOptimizer, FixedThresholdToRemaining)
{
  OptimizerSettings s;
  s.Threshold = 0.1;
  s.Strategy = Redistribution::Remaining;
  auto o = Make(s, Flat);
  // 0.05 spread over 0.5, 0.3, 0.15 in proportion: each scaled by 1 / 0.95.
  ExpectWeights(o.Optimize({ 0.5, 0.3, 0.15, 0.05 }), { 0.5 / 0.95, 0.3 / 0.95, 0.15 / 0.95, 0.0 });
  // Error bound: |0.3/0.95 - 0.3| * 1 + |0.15/0.95 - 0.15| * 2 + 0.05 * 4.
  EXPECT_NEAR(o.GetLastErrorBound(), 0.3 * 0.05 / 0.95 + 0.15 * 0.05 / 0.95 * 2 + 0.2, 1e-12);
}

TEST(WeightOptimizer, NeutralRedistributionHasNoGeometricCostBeyondThePrunedTargets)
{
  OptimizerSettings s;
  s.Threshold = 0.1;
  s.Strategy = Redistribution::Neutral;
  auto o = Make(s, Flat);
  ExpectWeights(o.Optimize({ 0.5, 0.3, 0.15, 0.05 }), { 0.55, 0.3, 0.15, 0.0 });
  EXPECT_NEAR(o.GetLastErrorBound(), 0.05 * 4, 1e-12);
}

TEST(WeightOptimizer, AdjustedThresholdKeepsTargetsThatMoveMuch)
{
  OptimizerSettings s;
  s.Threshold = 0.4;
  s.Strategy = Redistribution::Remaining;
  s.AdjustThreshold = true;
  auto o = Make(s, Flat);
  // th_adj: neutral 0.4, target1 0.4*(1-1)=0, target2 0.4*0.5=0.2, target3 0.4*0.2=0.08.
  // 0.15 < 0.2 and 0.05 < 0.08 are pruned; 0.2 goes to 0.5 and 0.3 (scale 1.25).
  ExpectWeights(o.Optimize({ 0.5, 0.3, 0.15, 0.05 }), { 0.625, 0.375, 0.0, 0.0 });

  s.AdjustThreshold = false;
  auto fixed = Make(s, Flat);
  // Without adjustment 0.3 < 0.4 is pruned too: all goes to the neutral.
  ExpectWeights(fixed.Optimize({ 0.5, 0.3, 0.15, 0.05 }), { 1.0, 0.0, 0.0, 0.0 });
}

TEST(WeightOptimizer, NeverPrunesTheLargestWeight)
{
  OptimizerSettings s;
  s.Threshold = 0.5;
  auto o = Make(s, Metrics({ 0, 0.1, 0.1, 0.1, 0.1 }, { 0, 1, 1, 1, 1 }));
  const auto e = o.Optimize({ 0.1, 0.3, 0.2, 0.2, 0.2 });
  ExpectWeights(e, { 0.0, 1.0, 0.0, 0.0, 0.0 });
}

TEST(WeightOptimizer, HysteresisStopsFlicker)
{
  OptimizerSettings s;
  s.Threshold = 0.1;
  s.Strategy = Redistribution::Maximum;
  auto plain = Make(s, Flat);
  s.Hysteresis = 0.5;
  auto sticky = Make(s, Flat);
  for (auto* o : { &plain, &sticky })
  {
    EXPECT_GT(o->Optimize({ 0.58, 0.3, 0.0, 0.12 })[3], 0.0);
  }
  // 0.07 is below 0.1 but above 0.1 * (1 - 0.5): only the sticky one keeps it.
  EXPECT_EQ(plain.Optimize({ 0.63, 0.3, 0.0, 0.07 })[3], 0.0);
  EXPECT_NEAR(sticky.Optimize({ 0.63, 0.3, 0.0, 0.07 })[3], 0.07, 1e-12);
  // Once off, the target needs the full threshold again.
  EXPECT_EQ(sticky.Optimize({ 0.66, 0.3, 0.0, 0.04 })[3], 0.0);
  EXPECT_EQ(sticky.Optimize({ 0.63, 0.3, 0.0, 0.07 })[3], 0.0);
}

// Hysteresis lowers the *adjusted* threshold th_fix * (1 - dist_norm_i) by (1 - h), not th_fix.
TEST(WeightOptimizer, HysteresisLowersTheAdjustedThreshold)
{
  OptimizerSettings s;
  s.Threshold = 0.2;
  s.AdjustThreshold = true;
  s.Strategy = Redistribution::Neutral;
  s.Hysteresis = 0.5;
  auto o = Make(s, Flat); // target 2: dist_norm 0.5, th_adj 0.1, sticky 0.05
  EXPECT_NEAR(o.Optimize({ 0.6, 0.28, 0.12, 0.0 })[2], 0.12, 1e-12);
  // 0.08 < 0.1 but >= 0.05: kept (with hysteresis on th_fix, 0.1, it would go).
  EXPECT_NEAR(o.Optimize({ 0.64, 0.28, 0.08, 0.0 })[2], 0.08, 1e-12);
  EXPECT_EQ(o.Optimize({ 0.68, 0.28, 0.04, 0.0 })[2], 0.0);
  // Forgetting the history asks for the full threshold again.
  EXPECT_NEAR(o.Optimize({ 0.6, 0.28, 0.12, 0.0 })[2], 0.12, 1e-12);
  o.ResetHistory();
  EXPECT_EQ(o.Optimize({ 0.64, 0.28, 0.08, 0.0 })[2], 0.0);
}

// What the core does with a budget: hysteresis acts in the threshold step only, and it
// remembers what was *shown*. A target the budget pruned in the last frame was not shown,
// so it needs the full threshold again (it does not get a lowered one and win the budget).
// (The budget's and the error bound's own hysteresis: TestOptimizerHysteresis.cpp.)
TEST(WeightOptimizer, HysteresisRemembersWhatTheBudgetLeft)
{
  OptimizerSettings s;
  s.Threshold = 0.1;
  s.Hysteresis = 0.5;
  s.MaxActiveTargets = 1;
  s.Strategy = Redistribution::Neutral;
  auto o = Make(s, Flat);
  // Both pass the threshold; contributions 0.6 * 1 > 0.12 * 4: the budget keeps target 1.
  ExpectWeights(o.Optimize({ 0.28, 0.6, 0.0, 0.12 }), { 0.4, 0.6, 0.0, 0.0 });
  // Target 3 (0.07) is below 0.1; were it remembered as active (0.05) it would win the
  // budget (0.28 > 0.2).
  ExpectWeights(o.Optimize({ 0.73, 0.2, 0.0, 0.07 }), { 0.8, 0.2, 0.0, 0.0 });
  // A target the budget kept stays sticky within the threshold step.
  ExpectWeights(o.Optimize({ 0.75, 0.07, 0.0, 0.18 }), { 0.82, 0.0, 0.0, 0.18 });
  ExpectWeights(o.Optimize({ 0.94, 0.0, 0.0, 0.06 }), { 0.94, 0.0, 0.0, 0.06 });
}

TEST(WeightOptimizer, BudgetKeepsLargestGeometricContribution)
{
  OptimizerSettings s;
  s.MaxActiveTargets = 1;
  s.Strategy = Redistribution::Remaining;
  auto o = Make(s, Flat);
  // Equal raw weights; contributions 0.3*1, 0.3*2, 0.3*4: target 3 stays.
  // Pruned 0.6 goes to 0.1 and 0.3 (scale 2.5).
  ExpectWeights(o.Optimize({ 0.1, 0.3, 0.3, 0.3 }), { 0.25, 0.0, 0.0, 0.75 });
  EXPECT_EQ(CountActiveTargets(o.Optimize({ 0.1, 0.3, 0.3, 0.3 })), 1);
}

TEST(WeightOptimizer, ErrorBoundAlonePrunesCheapestFirst)
{
  OptimizerSettings s;
  s.MaxVertexError = 0.5;
  s.Strategy = Redistribution::Neutral;
  auto o = Make(s, Flat);
  // Costs 0.3*1, 0.2*2, 0.1*4: only target 1 fits in 0.5.
  ExpectWeights(o.Optimize({ 0.4, 0.3, 0.2, 0.1 }), { 0.7, 0.0, 0.2, 0.1 });
  EXPECT_NEAR(o.GetLastErrorBound(), 0.3, 1e-12);
}

TEST(WeightOptimizer, ErrorBoundRestrainsThreshold)
{
  OptimizerSettings s;
  s.Threshold = 0.35;
  s.Strategy = Redistribution::Neutral;
  s.MaxVertexError = 0.5;
  auto o = Make(s, Flat);
  // The threshold alone would prune 1, 2 and 3 (bound 1.1); the bound restores the most
  // expensive (3: 0.4, then 2: 0.4) until 0.3 <= 0.5.
  ExpectWeights(o.Optimize({ 0.4, 0.3, 0.2, 0.1 }), { 0.7, 0.0, 0.2, 0.1 });
}

TEST(WeightOptimizer, RejectsBadSettingsAndSizes)
{
  WeightOptimizer o;
  OptimizerSettings s;
  s.Threshold = -0.1;
  EXPECT_THROW(o.SetSettings(s), InputError);
  s = {};
  s.Hysteresis = 1.0;
  EXPECT_THROW(o.SetSettings(s), InputError);
  s = {};
  s.Threshold = 0.2;
  o.SetSettings(s);
  o.SetTargetDistances(Flat);
  EXPECT_THROW(o.Optimize({ 0.5, 0.5 }), InputError);
}

// Every method keeps the Java3D sum-to-1 rule, and the bound holds on real vertices, for
// absolute weights and for relative (glTF, ARKit) weights summing above 1, whose neutral
// weight is negative. No kept weight changes sign or moves by more than the pruned mass.
TEST(WeightOptimizer, SumToOneAndBoundHoldOnRandomWeights)
{
  const size_t numPoints = 200, numTargets = 12;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MorphMesh model(numPoints);
  model.SetTargetNames(DefaultTargetNames(numTargets));
  auto& p = model.AddAttribute<double>("Points", AttributeRole::Position, 3);
  std::vector<double> neutral(numPoints * 3);
  for (auto& v : neutral)
  {
    v = u(rng);
  }
  p.SetNeutral(neutral.data());
  for (size_t i = 1; i < numTargets; ++i)
  {
    std::vector<double> t(neutral);
    for (size_t k = 0; k < t.size(); ++k)
    {
      if ((k / 3 + i) % 3 == 0)
      {
        t[k] += 0.3 * static_cast<double>(i) * u(rng);
      }
    }
    p.AddAbsoluteTarget(t.data(), 0.3);
  }
  const TargetDistances d = model.ComputeDistances();

  std::vector<OptimizerSettings> methods;
  for (Redistribution r :
    { Redistribution::Maximum, Redistribution::Remaining, Redistribution::Neutral })
  {
    for (double th : { 0.1, 0.3, 0.5 })
    {
      OptimizerSettings s;
      s.Threshold = th;
      s.Strategy = r;
      methods.push_back(s);
      s.AdjustThreshold = true;
      methods.push_back(s);
    }
    OptimizerSettings bound;
    bound.Strategy = r;
    bound.MaxVertexError = 0.2;
    methods.push_back(bound);
    OptimizerSettings budget;
    budget.Strategy = r;
    budget.MaxActiveTargets = 3;
    budget.Hysteresis = 0.3;
    budget.Threshold = 0.05;
    methods.push_back(budget);
  }
  std::exponential_distribution<double> e(1.0);
  std::uniform_real_distribution<double> relativeWeight(0.0, 0.45);
  std::vector<double> ref(numPoints * 3), opt(numPoints * 3);
  int negativeNeutralFrames = 0;
  for (bool relative : { false, true })
  {
    for (const auto& s : methods)
    {
      auto o = Make(s, d);
      for (int frame = 0; frame < 200; ++frame)
      {
        std::vector<double> w(numTargets);
        if (relative)
        {
          // Relative weights in [0, 0.45] on ~70 % of the targets (sum ~1.7), neutral 1 - sum.
          double sum = 0.0;
          for (size_t i = 1; i < numTargets; ++i)
          {
            w[i] = u(rng) > -0.4 ? relativeWeight(rng) : 0.0;
            sum += w[i];
          }
          w[0] = 1.0 - sum;
          negativeNeutralFrames += w[0] < 0.0 ? 1 : 0;
        }
        else
        {
          for (auto& v : w)
          {
            v = e(rng) * (u(rng) > 0.3 ? 1.0 : 0.0);
          }
          w[0] += 0.01;
          const double total = Sum(w);
          for (auto& v : w)
          {
            v /= total;
          }
        }
        const auto eff = o.Optimize(w);
        ASSERT_NEAR(Sum(eff), 1.0, 1e-12);
        double prunedMass = 0.0;
        for (size_t i = 0; i < w.size(); ++i)
        {
          prunedMass += eff[i] == 0.0 ? std::abs(w[i]) : 0.0;
        }
        for (size_t i = 0; i < w.size(); ++i)
        {
          if (i > 0) // targets keep their sign; the neutral may receive weight and change it
          {
            ASSERT_GE(eff[i], 0.0) << "target " << i;
          }
          if (eff[i] != 0.0)
          {
            ASSERT_LE(std::abs(eff[i] - w[i]), prunedMass + 1e-12)
              << "weight " << i << " (" << w[i] << " -> " << eff[i] << ") moved by more than "
              << "the pruned mass, " << (relative ? "relative" : "absolute") << " weights, "
              << RedistributionName(s.Strategy) << " threshold " << s.Threshold;
          }
        }
        p.Blend(w.data(), w.size(), ref.data(), 0, numPoints);
        p.Blend(eff.data(), eff.size(), opt.data(), 0, numPoints);
        double worst = 0.0;
        for (size_t q = 0; q < numPoints; ++q)
        {
          worst = std::max(worst,
            std::hypot(ref[3 * q] - opt[3 * q], ref[3 * q + 1] - opt[3 * q + 1],
              ref[3 * q + 2] - opt[3 * q + 2]));
        }
        ASSERT_LE(worst, o.GetLastErrorBound() + 1e-9);
        if (s.MaxVertexError > 0.0)
        {
          ASSERT_LE(o.GetLastErrorBound(), s.MaxVertexError + 1e-12);
        }
        if (s.MaxActiveTargets > 0)
        {
          ASSERT_LE(CountActiveTargets(eff), s.MaxActiveTargets);
        }
      }
    }
  }
  // Most relative frames really have a negative neutral weight.
  EXPECT_GT(negativeNeutralFrames, static_cast<int>(methods.size()) * 200 * 3 / 4);
}
