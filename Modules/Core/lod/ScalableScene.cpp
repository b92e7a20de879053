// SPDX-License-Identifier: BSD-3-Clause
#include "lod/ScalableScene.h"

#include "base/Error.h"
#include "morph/MorphScene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
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
    throw InputError("ScalableScene: every part's ladder needs a float Position attribute.");
  }
  return *positions;
}
} // namespace

void ScalableScene::Layout(Ladders parts)
{
  if (parts.empty())
  {
    throw InputError("ScalableScene: no parts.");
  }
  this->TargetNames.clear();
  this->TargetMaps.clear();
  this->Unmapped.clear();
  this->Positions.clear();
  this->Levels = 0;
  // The scene's targets are the parts' matched by name, as the morph node's scene matches
  // them (CombineTargetDistances: order of first appearance, a name twice in a part refused).
  std::vector<NamedTargetDistances> named;
  for (size_t p = 0; p < parts.size(); ++p)
  {
    if (!parts[p] || parts[p]->Levels.empty())
    {
      throw InputError("ScalableScene: part " + std::to_string(p) + " has no ladder.");
    }
    const MorphLadder& ladder = *parts[p];
    FloatPositions(ladder);
    this->Levels = std::max(this->Levels, ladder.Levels.size());
    NamedTargetDistances part;
    part.Names = ladder.Mesh.GetTargetNames();
    part.DistMorph.assign(part.Names.size(), 0.0);
    part.MaxDisplacement.assign(part.Names.size(), 0.0);
    named.push_back(std::move(part));
    this->Positions.emplace_back(3 * ladder.Mesh.GetNumberOfPoints(), 0.0f);
  }
  this->TargetNames = CombineTargetDistances(named).Names;
  for (const NamedTargetDistances& part : named)
  {
    std::vector<size_t> map(part.Names.size(), 0);
    std::vector<char> has(this->TargetNames.size(), 0);
    for (size_t k = 1; k < part.Names.size(); ++k)
    {
      map[k] = static_cast<size_t>(
        std::find(this->TargetNames.begin(), this->TargetNames.end(), part.Names[k]) -
        this->TargetNames.begin());
      has[map[k]] = 1;
    }
    // The scene targets a part lacks: their weight goes to its neutral.
    std::vector<size_t> lacks;
    for (size_t t = 1; t < has.size(); ++t)
    {
      if (!has[t])
      {
        lacks.push_back(t);
      }
    }
    this->TargetMaps.push_back(std::move(map));
    this->Unmapped.push_back(std::move(lacks));
  }
  this->Parts = std::move(parts);
}

void ScalableScene::SetParts(Ladders parts, const std::vector<CostModel>& costs)
{
  ScalableScene next;
  next.Layout(std::move(parts));
  if (costs.size() != next.Levels)
  {
    throw InputError("ScalableScene: " + std::to_string(costs.size()) + " cost models for " +
      std::to_string(next.Levels) + " levels.");
  }
  this->Parts = std::move(next.Parts);
  this->Levels = next.Levels;
  this->TargetNames = std::move(next.TargetNames);
  this->TargetMaps = std::move(next.TargetMaps);
  this->Unmapped = std::move(next.Unmapped);
  this->Positions = std::move(next.Positions);
  this->Costs = costs;
  this->Frame = SceneFrame();
  this->PartWeights.assign(this->Parts.size(), {});
  this->Shown.assign(this->Parts.size(), ShownState());
  this->Rebuild();
}

void ScalableScene::SetSettings(const ControllerSettings& settings)
{
  FrameBudgetController check;
  check.SetSettings(settings);
  this->Settings = settings;
  this->Rebuild();
}

void ScalableScene::SetProfile(const DeviceProfile& profile)
{
  ControllerSettings s = this->Settings;
  ApplyDeviceProfile(profile, s);
  this->SetSettings(s);
}

int ScalableScene::GetPartLevel(size_t part, int level) const
{
  const int coarsest = static_cast<int>(this->Parts.at(part)->Levels.size()) - 1;
  return std::clamp(level, 0, coarsest);
}

LevelOfDetail ScalableScene::GetSceneLevel(size_t l, const CostModel& cost) const
{
  if (l >= this->Levels)
  {
    throw InputError(
      "ScalableScene: level " + std::to_string(l) + " of " + std::to_string(this->Levels) + ".");
  }
  const size_t nt = this->TargetNames.size();
  LevelOfDetail lod;
  lod.Name = l == 0 ? "full" : "level " + std::to_string(l);
  lod.MovedPoints.assign(nt, 0.0);
  const bool coarser = l + 1 < this->Levels;
  if (coarser)
  {
    lod.GeomorphReach.assign(nt, 0.0);
  }
  std::vector<NamedTargetDistances> named;
  for (size_t p = 0; p < this->Parts.size(); ++p)
  {
    const MorphLadder& ladder = *this->Parts[p];
    const size_t pl = static_cast<size_t>(this->GetPartLevel(p, static_cast<int>(l)));
    const LadderLevel& level = ladder.Levels[pl];
    const std::vector<size_t>& map = this->TargetMaps[p];
    lod.NumberOfPoints += level.NumberOfPoints;
    // The part whose error is largest sets the level.
    lod.GeometricError = std::max(lod.GeometricError, level.Error99);
    named.push_back(
      { ladder.Mesh.GetTargetNames(), level.Distances.DistMorph, level.Distances.MaxDisplacement });
    for (size_t k = 1; k < map.size(); ++k)
    {
      lod.MovedPoints[map[k]] += level.MovedPoints.at(k);
    }
    // Only a part that has a coarser level of its own slides during the scene's geomorph.
    if (coarser && pl == l && !level.GeomorphReach.empty())
    {
      lod.GeomorphReach[0] = std::max(lod.GeomorphReach[0], level.GeomorphReach[0]);
      for (size_t k = 1; k < map.size(); ++k)
      {
        lod.GeomorphReach[map[k]] = std::max(lod.GeomorphReach[map[k]], level.GeomorphReach.at(k));
      }
    }
  }
  // Distances summed and the largest displacement the largest over the parts, as the morph
  // node's scene decides for its whole model.
  lod.Distances = MakeTargetDistances(CombineTargetDistances(named));
  lod.Cost = cost;
  return lod;
}

void ScalableScene::Rebuild()
{
  this->Controller = FrameBudgetController();
  this->Controller.SetSettings(this->Settings);
  for (size_t l = 0; l < this->Levels && !this->Parts.empty(); ++l)
  {
    this->Controller.AddLevel(this->GetSceneLevel(l, this->Costs[l]));
  }
}

const std::vector<uint32_t>& ScalableScene::GetTriangles(size_t part) const
{
  const MorphLadder& ladder = *this->Parts.at(part);
  return ladder.Levels.at(static_cast<size_t>(this->GetPartLevel(part, this->Frame.Decision.Level)))
    .Triangles;
}

void ScalableScene::Blend(const std::vector<double>& w, int level, int morphTowards, double alpha)
{
  this->PartWeights.resize(this->Parts.size());
  this->Shown.resize(this->Parts.size());
  this->Frame.PartLevels.resize(this->Parts.size());
  this->Frame.PartPoints.resize(this->Parts.size());
  this->Frame.NumberOfPoints = 0;
  for (size_t p = 0; p < this->Parts.size(); ++p)
  {
    const MorphLadder& ladder = *this->Parts[p];
    const int pl = this->GetPartLevel(p, level);
    const size_t n = ladder.Levels[static_cast<size_t>(pl)].NumberOfPoints;
    const std::vector<size_t>& map = this->TargetMaps[p];
    std::vector<double>& pw = this->Scratch;
    pw.resize(map.size());
    pw[0] = w[0];
    for (size_t s : this->Unmapped[p])
    {
      pw[0] += w[s];
    }
    for (size_t k = 1; k < map.size(); ++k)
    {
      pw[k] = w[map[k]];
    }
    const bool morphs =
      morphTowards >= 0 && pl == level && static_cast<size_t>(pl) + 1 < ladder.Levels.size();
    // A part shown as in the last frame (its level, its weights, no geomorph then or now,
    // e.g. an eye no active target moves) keeps its positions: nothing to blend.
    ShownState& shown = this->Shown[p];
    const bool same = this->SkipUnchanged && shown.Valid && shown.Level == pl && !shown.Morphed &&
      !morphs && this->PartWeights[p] == pw;
    this->PartWeights[p].swap(pw);
    if (!same)
    {
      FloatPositions(ladder).Blend(
        this->PartWeights[p].data(), this->PartWeights[p].size(), this->Positions[p].data(), 0, n);
      if (morphs)
      {
        GeomorphLadder(ladder, static_cast<size_t>(pl), alpha, this->Positions[p].data());
      }
    }
    shown = { true, pl, morphs, !same };
    this->Frame.PartLevels[p] = pl;
    this->Frame.PartPoints[p] = n;
    this->Frame.NumberOfPoints += n;
  }
}

const SceneFrame& ScalableScene::Update(const std::vector<double>& weights, double pixelsPerUnit)
{
  if (this->Parts.empty())
  {
    throw InputError("ScalableScene: no parts.");
  }
  SceneFrame& f = this->Frame;
  f.Decision = this->Controller.Update(weights, pixelsPerUnit);
  const auto t0 = std::chrono::steady_clock::now();
  this->Blend(f.Decision.Weights, f.Decision.Level, f.Decision.MorphTowards, f.Decision.Alpha);
  f.BlendSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  this->Controller.ReportMeasuredSeconds(f.BlendSeconds);
  return f;
}

template <typename T>
void ScalableScene::BlendAttribute(size_t part, size_t attribute, T* out) const
{
  if (part >= this->Parts.size() || this->PartWeights.at(part).empty())
  {
    throw InputError(
      "ScalableScene: no frame of part " + std::to_string(part) + " to blend an attribute of.");
  }
  const MorphLadder& ladder = *this->Parts[part];
  if (attribute >= ladder.Mesh.GetNumberOfAttributes())
  {
    throw InputError("ScalableScene: part " + std::to_string(part) + " has no attribute " +
      std::to_string(attribute) + ".");
  }
  const auto* values = std::get_if<MorphAttribute<T>>(&ladder.Mesh.GetAttribute(attribute));
  if (!values)
  {
    throw InputError("ScalableScene: attribute " + std::to_string(attribute) + " of part " +
      std::to_string(part) + " is not of the type asked for.");
  }
  const std::vector<double>& w = this->PartWeights[part];
  const int pl = this->Frame.PartLevels.at(part);
  const size_t n = this->Frame.PartPoints.at(part);
  values->Blend(w.data(), w.size(), out, 0, n);
  const ControllerDecision& d = this->Frame.Decision;
  if (d.MorphTowards >= 0 && pl == d.Level && static_cast<size_t>(pl) + 1 < ladder.Levels.size())
  {
    const int nc = values->GetNumberOfComponents();
    GeomorphLadder(ladder, static_cast<size_t>(pl), d.Alpha, out, nc);
    if (values->GetRole() == AttributeRole::Normal)
    {
      // The slid points only: the others were renormalized by the blend.
      for (size_t p = ladder.Levels[static_cast<size_t>(pl) + 1].NumberOfPoints; p < n; ++p)
      {
        double norm = 0.0;
        for (int c = 0; c < nc; ++c)
        {
          norm += double(out[nc * p + c]) * double(out[nc * p + c]);
        }
        norm = std::sqrt(norm);
        for (int c = 0; c < nc && norm > 0.0; ++c)
        {
          out[nc * p + c] = static_cast<T>(out[nc * p + c] / norm);
        }
      }
    }
  }
}

template void ScalableScene::BlendAttribute(size_t, size_t, float*) const;
template void ScalableScene::BlendAttribute(size_t, size_t, double*) const;

std::vector<CostModel> ScalableScene::Calibrate(const Ladders& parts, unsigned seed)
{
  ScalableScene scene;
  scene.Layout(parts);
  scene.SkipUnchanged = false; // every run of a blend timed
  std::mt19937 rng(seed);
  const size_t nt = scene.TargetNames.size() - 1;
  std::vector<CostModel> costs;
  for (size_t l = 0; l < scene.Levels; ++l)
  {
    const LevelOfDetail level = scene.GetSceneLevel(l, CostModel());
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
          scene.Blend(w, static_cast<int>(l), -1, 0.0);
          best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
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
