// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: the frame-budget controller over a chain of reduced levels.
#include "ReductionStudy.h"

#include "morph/Distances.h"
#include "morph/OptimizerQuality.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <numeric>
#include <random>

namespace reductionstudy
{
namespace
{
struct Level
{
  ReductionMesh Mesh;
  std::vector<uint32_t> ToFull;          // level point -> full point
  std::vector<uint32_t> ToPrevious;      // level point -> previous level's point
  std::vector<uint32_t> Representatives; // previous level point -> this level's point
  std::unique_ptr<morphnode::MorphAttribute<float>> Attribute;
  Correspondence Corr;
  double Error = 0.0;
};

/// Median time of blending `weights` on one level.
double TimeBlend(const morphnode::MorphAttribute<float>& attr, const std::vector<double>& weights,
  std::vector<float>& out, int repeats)
{
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    attr.Blend(weights.data(), weights.size(), out.data(), 0, attr.GetNumberOfPoints());
    times.push_back(Seconds(std::chrono::steady_clock::now() - t0));
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  return times[times.size() / 2];
}

/// The chain of levels: the full face, then each budget (largest first) reduced from the
/// previous level.
std::vector<Level> BuildLevels(
  const ReductionMesh& full, const std::vector<double>& sorted, double weight)
{
  std::vector<Level> levels(1);
  levels[0].Mesh = full;
  levels[0].ToFull.resize(full.GetNumberOfPoints());
  std::iota(levels[0].ToFull.begin(), levels[0].ToFull.end(), 0u);
  for (double b : sorted)
  {
    const Level& prev = levels.back();
    morphnode::ReductionSettings s;
    s.TargetTriangles = static_cast<size_t>(std::round(b * full.GetNumberOfTriangles()));
    s.AnimationWeight = weight;
    auto r = morphnode::ReduceAnimationAware(ToMorphMesh(prev.Mesh), s);
    Level next;
    next.Mesh = FromMorphMesh(r.Mesh);
    next.ToPrevious = r.OriginalPointIds;
    next.Representatives = r.Representatives;
    for (uint32_t id : r.OriginalPointIds)
    {
      next.ToFull.push_back(prev.ToFull[id]);
    }
    levels.push_back(std::move(next));
  }
  return levels;
}

/// A level's attribute, correspondence, cost model (timed on random active sets, written to
/// `cal`) and error over the track, as the controller's LevelOfDetail.
morphnode::LevelOfDetail PrepareLevel(std::vector<Level>& levels, size_t l,
  const std::vector<double>& sorted, const ReductionMesh& full, const morphnode::WeightTrack& track,
  size_t stride, std::mt19937& rng, std::ostream& cal)
{
  Level& level = levels[l];
  const size_t np = level.Mesh.GetNumberOfPoints();
  level.Attribute = std::make_unique<morphnode::MorphAttribute<float>>(
    "positions", morphnode::AttributeRole::Position, 3, np);
  level.Attribute->SetNeutral(level.Mesh.Positions.data());
  for (const auto& d : level.Mesh.PositionDeltas)
  {
    level.Attribute->AddRelativeTarget(d.data(), 0.3);
  }
  level.Corr = Correspond(full, level.Mesh);
  morphnode::LevelOfDetail lod;
  lod.Name = l == 0 ? "full" : std::to_string(int(std::round(100.0 * sorted[l - 1]))) + " %";
  lod.NumberOfPoints = np;
  lod.MovedPoints = morphnode::MovedPointsPerTarget(level.Mesh.PositionDeltas);
  lod.Distances = morphnode::ComputeTargetDistances(*level.Attribute);
  // Calibrate: time random active sets of several sizes.
  std::vector<double> xs, ys;
  std::vector<float> out(3 * np);
  const size_t nt = level.Mesh.GetNumberOfTargets();
  for (size_t active :
    { size_t(0), size_t(1), size_t(2), size_t(4), size_t(8), size_t(16), size_t(32), nt })
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
        w[order[i]] = 0.5 / double(std::max<size_t>(active, 1));
        x += lod.MovedPoints[order[i]];
      }
      w[0] = 1.0 - std::accumulate(w.begin() + 1, w.end(), 0.0);
      const double t = TimeBlend(*level.Attribute, w, out, 41);
      xs.push_back(x);
      ys.push_back(t);
      cal << l << "," << active << "," << x << "," << t << "\n";
    }
  }
  lod.Cost = morphnode::CostModel::Fit(xs, ys);
  // The level's own error: RMS correspondence error over the track (unoptimized weights).
  if (l > 0)
  {
    double sum = 0.0;
    size_t n = 0;
    std::vector<float> a, b;
    for (size_t f = 0; f < track.GetNumberOfFrames(); f += stride)
    {
      Animate(full, track.GetFrame(f), a);
      Animate(level.Mesh, track.GetFrame(f), b);
      const double rms = CorrespondenceRms(level.Corr, b, a);
      sum += rms * rms;
      ++n;
    }
    level.Error = std::sqrt(sum / n);
  }
  lod.GeometricError = level.Error;
  if (l + 1 < levels.size())
  {
    // This level's point -> the next level's point it collapses into, in this level's ids.
    const Level& next = levels[l + 1];
    for (uint32_t rep : next.Representatives)
    {
      lod.RepresentativeInThisLevel.push_back(next.ToPrevious[rep]);
    }
    lod.CoarserToThis = next.ToPrevious;
  }
  std::cerr << "level " << lod.Name << ": " << np << " points, cost " << Us(lod.Cost.Fixed)
            << " us + " << lod.Cost.PerTargetPoint * 1e9 << " ns per target point, error "
            << Mm(level.Error) << " mm\n";
  return lod;
}

/// The absolute weights of the (relative) track, neutral first.
morphnode::WeightTrack AbsoluteWeights(const Face& face, const morphnode::WeightTrack& track)
{
  morphnode::WeightTrack relativeNamed(
    std::vector<std::string>(face.Names.begin() + 1, face.Names.end()), track.GetFrameRate());
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    relativeNamed.AppendFrame(track.GetFrame(f));
  }
  return morphnode::ToAbsoluteWeights(relativeNamed, face.Names);
}

/// The controller at one frame budget over the track: a row of `md`, rows of `ctl`.
void RunBudget(const std::string& label, double budget, const std::vector<Level>& levels,
  const std::vector<morphnode::LevelOfDetail>& lods, const ReductionMesh& full,
  const morphnode::WeightTrack& track, const morphnode::WeightTrack& absolute, std::ostream& ctl,
  std::ostream& md)
{
  morphnode::FrameBudgetController controller;
  morphnode::ControllerSettings cs;
  cs.FrameBudget = budget;
  controller.SetSettings(cs);
  for (const auto& lod : lods)
  {
    controller.AddLevel(lod);
  }
  std::vector<size_t> perLevel(lods.size(), 0);
  std::vector<double> times;
  double thresholdSum = 0, activeSum = 0, predictedSum = 0, measuredSum = 0, measuredMax = 0;
  size_t over = 0;
  std::vector<float> shown, morphed, truth;
  for (size_t f = 0; f < absolute.GetNumberOfFrames(); ++f)
  {
    std::vector<double> w(
      absolute.GetFrame(f), absolute.GetFrame(f) + absolute.GetNumberOfChannels());
    const morphnode::ControllerDecision d = controller.Update(w);
    const Level& level = levels[d.Level];
    shown.resize(3 * level.Mesh.GetNumberOfPoints());
    const auto t0 = std::chrono::steady_clock::now();
    level.Attribute->Blend(
      d.Weights.data(), d.Weights.size(), shown.data(), 0, level.Mesh.GetNumberOfPoints());
    if (d.MorphTowards >= 0)
    {
      morphed.resize(shown.size());
      morphnode::Geomorph(shown.data(), level.Mesh.GetNumberOfPoints(),
        lods[d.Level].RepresentativeInThisLevel, d.Alpha, morphed.data());
      shown.swap(morphed);
    }
    const double t = Seconds(std::chrono::steady_clock::now() - t0);
    times.push_back(t);
    over += t > budget ? 1 : 0;
    Animate(full, track.GetFrame(f), truth);
    const double err = CorrespondenceRms(level.Corr, shown, truth);
    ++perLevel[d.Level];
    thresholdSum += d.Threshold;
    activeSum += d.ActiveTargets;
    predictedSum += d.PredictedError;
    measuredSum += err;
    measuredMax = std::max(measuredMax, err);
    ctl << std::quoted(label) << "," << f << "," << d.Level << "," << d.MorphTowards << ","
        << d.Alpha << "," << d.Threshold << "," << d.ActiveTargets << "," << Us(d.PredictedSeconds)
        << "," << Us(t) << "," << Mm(d.PredictedError, 5) << "," << Mm(err, 5) << "\n";
  }
  const double n = static_cast<double>(absolute.GetNumberOfFrames());
  std::vector<double> sortedTimes = times;
  std::sort(sortedTimes.begin(), sortedTimes.end());
  std::ostringstream levelsText;
  for (size_t l = 0; l < perLevel.size(); ++l)
  {
    levelsText << (l ? " / " : "") << perLevel[l];
  }
  md << "| " << label << " | " << Us(budget) << " | " << levelsText.str() << " | "
     << controller.GetNumberOfSwitches() << " | " << std::setprecision(3) << thresholdSum / n
     << " | " << std::setprecision(3) << activeSum / n << " | "
     << Us(std::accumulate(times.begin(), times.end(), 0.0) / n) << " / "
     << Us(sortedTimes[sortedTimes.size() * 95 / 100]) << " | " << over << " of " << times.size()
     << " | " << Mm(predictedSum / n) << " | " << Mm(measuredSum / n) << " / " << Mm(measuredMax)
     << " |\n";
  std::cerr << "controller " << label << ": levels " << levelsText.str() << ", switches "
            << controller.GetNumberOfSwitches() << ", over budget " << over << "\n";
}
} // namespace

void RunController(
  const Options& o, const Face& face, const morphnode::WeightTrack& track, std::ostream& md)
{
  const ReductionMesh& full = face.Mesh;
  std::vector<double> sorted = o.Budgets;
  std::sort(sorted.rbegin(), sorted.rend());
  std::vector<Level> levels = BuildLevels(full, sorted, o.Weight);
  std::vector<morphnode::LevelOfDetail> lods;
  std::mt19937 rng(3);
  std::ofstream cal(o.OutDir + "/controller_calibration.csv");
  cal << "level,active_targets,target_points,seconds\n";
  for (size_t l = 0; l < levels.size(); ++l)
  {
    lods.push_back(PrepareLevel(levels, l, sorted, full, track, o.Stride, rng, cal));
  }

  const morphnode::WeightTrack absolute = AbsoluteWeights(face, track);
  // Budgets relative to the full face's predicted cost on this track: its 95th percentile.
  std::vector<double> fullCosts;
  for (size_t f = 0; f < absolute.GetNumberOfFrames(); ++f)
  {
    double x = 0.0;
    for (size_t i = 1; i < absolute.GetNumberOfChannels(); ++i)
    {
      x += absolute.GetValue(f, i) != 0.0 ? lods[0].MovedPoints[i] : 0.0;
    }
    fullCosts.push_back(lods[0].Cost.Predict(x));
  }
  std::sort(fullCosts.begin(), fullCosts.end());
  const double p95 = fullCosts[fullCosts.size() * 95 / 100];
  const std::vector<std::pair<std::string, double>> frameBudgets = {
    { "generous (100 % of full p95)", p95 }, { "medium (45 %)", 0.45 * p95 },
    { "tight (18 %)", 0.18 * p95 }
  };

  std::ofstream ctl(o.OutDir + "/controller.csv");
  ctl << "budget,frame,level,morph_towards,alpha,threshold,active,predicted_us,measured_us,"
         "predicted_error_mm,"
         "measured_error_mm\n";
  md << "\n## Frame-budget controller\n\nLevels (chained reductions, each from the previous "
        "one):\n\n"
     << "| level | points | cost model a | b (ns per target point) | level error (correspondence "
        "RMS, mm) |\n"
     << "|---|---|---|---|---|\n";
  for (const auto& lod : lods)
  {
    md << "| " << lod.Name << " | " << lod.NumberOfPoints << " | " << Us(lod.Cost.Fixed) << " us | "
       << std::setprecision(3) << lod.Cost.PerTargetPoint * 1e9 << " | " << Mm(lod.GeometricError)
       << " |\n";
  }
  md << "\nFull face, 95th percentile of the predicted per-frame cost on the track: " << Us(p95)
     << " us.\n\n";
  md << "| budget | us | frames per level (full/...) | switches | mean threshold | mean active "
        "targets "
        "| measured time mean / p95 (us) | frames over budget (measured) | predicted error mean "
        "(mm) "
        "| measured error mean / max (mm) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [label, budget] : frameBudgets)
  {
    RunBudget(label, budget, levels, lods, full, track, absolute, ctl, md);
  }
}
} // namespace reductionstudy
