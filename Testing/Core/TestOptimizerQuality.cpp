// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "morph/MorphMesh.h"
#include "morph/OptimizerPresets.h"
#include "morph/OptimizerQuality.h"

#include <gtest/gtest.h>

#include <random>

using namespace morphnode;

namespace
{
MorphAttribute<float> RandomFace(size_t numPoints, size_t numTargets, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  MorphAttribute<float> a("Points", AttributeRole::Position, 3, numPoints);
  std::vector<float> neutral(numPoints * 3);
  for (auto& v : neutral)
  {
    v = u(rng);
  }
  a.SetNeutral(neutral.data());
  for (size_t t = 1; t < numTargets; ++t)
  {
    std::vector<float> d(numPoints * 3, 0.f);
    for (size_t k = 0; k < d.size(); k += t)
    {
      d[k] = 0.2f * static_cast<float>(t) * u(rng);
    }
    a.AddRelativeTarget(d.data(), 0.3);
  }
  return a;
}
} // namespace

TEST(OptimizerQuality, MeasuresErrorAgainstTheUnoptimizedBlend)
{
  const auto face = RandomFace(500, 6, 11);
  const TargetDistances d = ComputeTargetDistances(face);
  WeightTrack relative({ "target0", "target1", "target2", "target3", "target4" }, 30.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 0.3);
  for (int f = 0; f < 50; ++f)
  {
    relative.AppendFrame({ u(rng), u(rng), 0.0, u(rng), u(rng) * 0.2 });
  }
  const WeightTrack absolute = ToAbsoluteWeights(relative, DefaultTargetNames(6));
  ASSERT_EQ(absolute.GetNumberOfChannels(), 6u);
  // Every optimizer method (morph/OptimizerPresets.h) and a budget.
  std::vector<OptimizerMethod> methods;
  for (int p = 0; p < NumberOfOptimizerPresets; ++p)
  {
    const auto preset = static_cast<OptimizerPreset>(p);
    methods.push_back({ OptimizerPresetName(preset), MakeOptimizerSettings(preset, 0.3, 0.05) });
  }
  OptimizerSettings budget;
  budget.MaxActiveTargets = 2;
  budget.Strategy = Redistribution::Neutral;
  methods.push_back({ "budget 2", budget });
  for (const auto& method : methods)
  {
    const auto frames = MeasureOptimizerQuality(face, d, absolute, method);
    ASSERT_EQ(frames.size(), 50u);
    double total = 0.0;
    for (const auto& q : frames)
    {
      EXPECT_LE(q.MaxError, q.ErrorBound + 1e-6) << method.Name;
      EXPECT_LE(q.RmsError, q.MaxError + 1e-12) << method.Name;
      total += q.MaxError;
    }
    if (method.Name == "none")
    {
      EXPECT_EQ(total, 0.0);
    }
    else
    {
      EXPECT_GT(total, 0.0) << method.Name << " pruned nothing on any frame";
    }
    if (method.Settings.MaxVertexError > 0)
    {
      for (const auto& q : frames)
      {
        EXPECT_LE(q.MaxError, method.Settings.MaxVertexError + 1e-6);
      }
    }
  }
}

TEST(OptimizerQuality, AbsoluteWeightsFromRelativeOnes)
{
  WeightTrack relative({ "b", "a" }, 10.0);
  relative.AppendFrame({ 0.25, 0.5 });
  const WeightTrack absolute = ToAbsoluteWeights(relative, { "Neutral", "a", "b", "c" });
  EXPECT_DOUBLE_EQ(absolute.GetValue(0, 0), 0.25);
  EXPECT_DOUBLE_EQ(absolute.GetValue(0, 1), 0.5);
  EXPECT_DOUBLE_EQ(absolute.GetValue(0, 2), 0.25);
  EXPECT_DOUBLE_EQ(absolute.GetValue(0, 3), 0.0);
  WeightTrack unknown({ "z" }, 10.0);
  unknown.AppendFrame({ 0.1 });
  EXPECT_THROW(ToAbsoluteWeights(unknown, { "Neutral", "a" }), InputError);
}

TEST(WeightTrack, CsvRoundTripAndErrorsWithLineNumbers)
{
  WeightTrack track({ "A", "B" }, 25.0);
  track.AppendFrame({ 0.1, 0.2 });
  track.AppendFrame({ 0.3, 0.4 });
  std::stringstream csv;
  track.WriteCsv(csv);
  const WeightTrack back = WeightTrack::ReadCsv(csv);
  EXPECT_EQ(back.GetChannels(), track.GetChannels());
  EXPECT_NEAR(back.GetFrameRate(), 25.0, 1e-9);
  EXPECT_DOUBLE_EQ(back.GetValue(1, 1), 0.4);
  EXPECT_NEAR(back.Sample(0.02, 0), 0.2, 1e-9);

  std::stringstream bad("time,A\n0,0.5\n0.04,x\n");
  try
  {
    WeightTrack::ReadCsv(bad);
    FAIL() << "no error";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::stringstream ragged("time,A,B\n0,0.5\n");
  EXPECT_THROW(WeightTrack::ReadCsv(ragged), InputError);
  EXPECT_THROW(WeightTrack({ "A", "A" }, 30.0), InputError);
}
