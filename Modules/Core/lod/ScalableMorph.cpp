// SPDX-License-Identifier: BSD-3-Clause
#include "lod/ScalableMorph.h"

#include "base/Error.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>
#include <string>
#include <variant>

namespace morphnode
{
namespace
{
const MorphAttribute<float>& FloatPositions(const MorphLadder& ladder)
{
  const int index = ladder.Mesh.GetPositionAttribute();
  const auto* positions = index < 0
    ? nullptr
    : std::get_if<MorphAttribute<float>>(&ladder.Mesh.GetAttribute(static_cast<size_t>(index)));
  if (!positions)
  {
    throw InputError("ScalableMorph: the ladder needs a float Position attribute.");
  }
  return *positions;
}
} // namespace

void ScalableMorph::SetLadder(std::shared_ptr<const MorphLadder> ladder, const std::vector<CostModel>& costs)
{
  if (!ladder || ladder->Levels.empty())
  {
    throw InputError("ScalableMorph: no ladder.");
  }
  if (costs.size() != ladder->Levels.size())
  {
    throw InputError("ScalableMorph: " + std::to_string(costs.size()) + " cost models for " +
      std::to_string(ladder->Levels.size()) + " levels.");
  }
  FloatPositions(*ladder);
  this->Ladder = std::move(ladder);
  this->Costs = costs;
  this->Positions.assign(3 * this->Ladder->Mesh.GetNumberOfPoints(), 0.0f);
  this->Rebuild();
}

void ScalableMorph::SetSettings(const ControllerSettings& settings)
{
  FrameBudgetController check;
  check.SetSettings(settings);
  this->Settings = settings;
  this->Rebuild();
}

void ScalableMorph::SetProfile(const DeviceProfile& profile)
{
  ControllerSettings s = this->Settings;
  ApplyDeviceProfile(profile, s);
  this->SetSettings(s);
}

void ScalableMorph::Rebuild()
{
  this->Controller = FrameBudgetController();
  this->Controller.SetSettings(this->Settings);
  if (!this->Ladder)
  {
    return;
  }
  for (size_t l = 0; l < this->Ladder->Levels.size(); ++l)
  {
    this->Controller.AddLevel(ToLevelOfDetail(*this->Ladder, l, this->Costs[l]));
  }
}

const std::vector<uint32_t>& ScalableMorph::GetTriangles() const
{
  if (!this->Ladder)
  {
    throw InputError("ScalableMorph: no ladder.");
  }
  return this->Ladder->Levels.at(static_cast<size_t>(this->Frame.Decision.Level)).Triangles;
}

const ScalableFrame& ScalableMorph::Update(const std::vector<double>& weights, double pixelsPerUnit)
{
  if (!this->Ladder)
  {
    throw InputError("ScalableMorph: no ladder.");
  }
  ScalableFrame& f = this->Frame;
  f.Decision = this->Controller.Update(weights, pixelsPerUnit);
  const size_t level = static_cast<size_t>(f.Decision.Level);
  f.NumberOfPoints = this->Ladder->Levels[level].NumberOfPoints;
  const auto t0 = std::chrono::steady_clock::now();
  FloatPositions(*this->Ladder).Blend(
    f.Decision.Weights.data(), f.Decision.Weights.size(), this->Positions.data(), 0, f.NumberOfPoints);
  if (f.Decision.MorphTowards >= 0)
  {
    GeomorphLadder(*this->Ladder, level, f.Decision.Alpha, this->Positions.data());
  }
  f.BlendSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  this->Controller.ReportMeasuredSeconds(f.BlendSeconds);
  return f;
}

std::vector<CostModel> ScalableMorph::Calibrate(const MorphLadder& ladder, unsigned seed)
{
  const MorphAttribute<float>& positions = FloatPositions(ladder);
  std::mt19937 rng(seed);
  std::vector<float> out(3 * ladder.Mesh.GetNumberOfPoints());
  const size_t nt = ladder.Mesh.GetNumberOfTargets() - 1;
  std::vector<CostModel> costs;
  for (const auto& level : ladder.Levels)
  {
    std::vector<double> xs, ys;
    for (size_t active : { size_t(0), size_t(1), size_t(4), size_t(16), nt })
    {
      for (int trial = 0; trial < 3; ++trial)
      {
        std::vector<size_t> order(nt);
        std::iota(order.begin(), order.end(), size_t(1));
        std::shuffle(order.begin(), order.end(), rng);
        std::vector<double> w(nt + 1, 0.0);
        double x = 0.0;
        for (size_t i = 0; i < std::min(active, nt); ++i)
        {
          w[order[i]] = 0.5 / static_cast<double>(std::max<size_t>(active, 1));
          x += level.MovedPoints[order[i]];
        }
        w[0] = 1.0 - std::accumulate(w.begin() + 1, w.end(), 0.0);
        // The fastest of a few runs: the cost without other threads' noise.
        double best = 1e9;
        for (int run = 0; run < 5; ++run)
        {
          const auto t0 = std::chrono::steady_clock::now();
          positions.Blend(w.data(), w.size(), out.data(), 0, level.NumberOfPoints);
          best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        xs.push_back(x);
        ys.push_back(best);
      }
    }
    costs.push_back(CostModel::Fit(xs, ys));
  }
  return costs;
}
} // namespace morphnode
