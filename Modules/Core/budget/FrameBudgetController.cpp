// SPDX-License-Identifier: BSD-3-Clause
#include "budget/FrameBudgetController.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace morphnode
{
CostModel CostModel::Fit(const std::vector<double>& x, const std::vector<double>& y)
{
  if (x.size() != y.size() || x.size() < 2)
  {
    throw InputError("CostModel::Fit needs at least two (target points, seconds) samples of "
                     "matching sizes, got " +
      std::to_string(x.size()) + " and " + std::to_string(y.size()) + ".");
  }
  const double n = static_cast<double>(x.size());
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (size_t i = 0; i < x.size(); ++i)
  {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  CostModel m;
  const double det = n * sxx - sx * sx;
  if (det > 0.0)
  {
    m.PerTargetPoint = std::max(0.0, (n * sxy - sx * sy) / det);
    m.Fixed = std::max(0.0, (sy - m.PerTargetPoint * sx) / n);
  }
  else
  {
    m.Fixed = std::max(0.0, sy / n); // all samples at one x: no slope to fit
  }
  return m;
}

namespace
{
double Median(std::vector<double>& v)
{
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0)
  {
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  }
  return m;
}
} // namespace

CostModel CostModel::FitMedian(
  const std::vector<double>& x, const std::vector<double>& y, double flatSlope)
{
  if (x.size() != y.size() || x.empty())
  {
    throw InputError("CostModel::FitMedian needs at least one (target points, seconds) "
                     "sample and sizes that match, got " +
      std::to_string(x.size()) + " and " + std::to_string(y.size()) + ".");
  }
  // Pairs closer than a tenth of the largest point count give no slope: over a small
  // difference, one slow frame makes an enormous one.
  double largest = 0.0;
  for (double v : x)
  {
    largest = std::max(largest, std::abs(v));
  }
  std::vector<double> slopes;
  for (size_t i = 0; i < x.size(); ++i)
  {
    for (size_t j = i + 1; j < x.size(); ++j)
    {
      if (std::abs(x[j] - x[i]) > 0.1 * largest)
      {
        slopes.push_back((y[j] - y[i]) / (x[j] - x[i]));
      }
    }
  }
  CostModel m;
  m.PerTargetPoint = std::max(0.0, slopes.empty() ? flatSlope : Median(slopes));
  std::vector<double> fixed(x.size());
  for (size_t i = 0; i < x.size(); ++i)
  {
    fixed[i] = y[i] - m.PerTargetPoint * x[i];
  }
  m.Fixed = std::max(0.0, Median(fixed));
  return m;
}

double DeviceFrameBudget(DeviceClass device)
{
  switch (device)
  {
    case DeviceClass::Desktop:
      return 0.002;
    case DeviceClass::Laptop:
      return 0.001;
    case DeviceClass::Mobile:
      return 0.0004;
    case DeviceClass::Embedded:
      return 0.00015;
  }
  return 0.001;
}

const char* DeviceClassName(DeviceClass device)
{
  switch (device)
  {
    case DeviceClass::Desktop:
      return "desktop";
    case DeviceClass::Laptop:
      return "laptop";
    case DeviceClass::Mobile:
      return "mobile";
    case DeviceClass::Embedded:
      return "embedded";
  }
  return "unknown";
}

std::vector<double> MovedPointsPerTarget(const std::vector<std::vector<float>>& positionDeltas)
{
  std::vector<double> moved(positionDeltas.size() + 1, 0.0);
  for (size_t k = 0; k < positionDeltas.size(); ++k)
  {
    const auto& d = positionDeltas[k];
    size_t count = 0;
    for (size_t p = 0; p + 2 < d.size(); p += 3)
    {
      count += (d[p] != 0.0f || d[p + 1] != 0.0f || d[p + 2] != 0.0f) ? 1 : 0;
    }
    moved[k + 1] = static_cast<double>(count);
  }
  return moved;
}

void FrameBudgetController::SetSettings(const ControllerSettings& s)
{
  if (!std::isfinite(s.FrameBudget) || s.FrameBudget <= 0.0)
  {
    throw InputError("FrameBudgetController: the frame budget must be a positive number of "
                     "seconds, got " +
      std::to_string(s.FrameBudget) + ".");
  }
  if (s.Thresholds.empty())
  {
    throw InputError("FrameBudgetController: no candidate thresholds.");
  }
  for (double t : s.Thresholds)
  {
    if (!std::isfinite(t) || t < 0.0 || t > 1.0)
    {
      throw InputError(
        "FrameBudgetController: thresholds must lie in [0, 1], got " + std::to_string(t) + ".");
    }
  }
  if (!(s.LevelHysteresis >= 0.0 && s.LevelHysteresis < 1.0) ||
    !(s.ThresholdHysteresis >= 0.0 && s.ThresholdHysteresis < 1.0) ||
    !(s.OptimizerHysteresis >= 0.0 && s.OptimizerHysteresis < 1.0))
  {
    throw InputError("FrameBudgetController: hysteresis must lie in [0, 1).");
  }
  if (s.MinFramesPerLevel < 0 || s.GeomorphFrames < 0 || s.MeasurementWindow < 0 ||
    s.MaxGeomorphFrames < 0 || !std::isfinite(s.MaxGeomorphPixels) || s.MaxGeomorphPixels < 0.0)
  {
    throw InputError("FrameBudgetController: frame counts must be >= 0.");
  }
  if (!(s.MeasuredQuantile >= 0.5 && s.MeasuredQuantile < 1.0))
  {
    throw InputError("FrameBudgetController: the measured quantile must lie in [0.5, 1).");
  }
  if (s.MaxActiveTargets < 0 || !std::isfinite(s.MaxVertexError) || s.MaxVertexError < 0.0)
  {
    throw InputError("FrameBudgetController: the optimizer's budget and error bound must be >= 0.");
  }
  if (!std::isfinite(s.PixelBound) || s.PixelBound < 0.0 || !std::isfinite(s.TargetPixelBound) ||
    s.TargetPixelBound < 0.0 || s.FinestLevel < 0)
  {
    throw InputError("FrameBudgetController: the pixel bounds and the finest level must be >= 0.");
  }
  this->Settings = s;
  this->OptimizerBound = s.MaxVertexError;
  // Rebuild the optimizers for the new thresholds.
  std::vector<LevelOfDetail> levels;
  levels.swap(this->Levels);
  this->Optimizers.clear();
  this->Models.clear();
  this->Margins.clear();
  this->Chosen.clear();
  this->Evaluated.clear();
  this->Samples.clear();
  for (const auto& level : levels)
  {
    this->AddLevel(level);
  }
}

void FrameBudgetController::AddLevel(const LevelOfDetail& level)
{
  if (!this->Levels.empty())
  {
    const auto& first = this->Levels.front();
    if (level.MovedPoints.size() != first.MovedPoints.size())
    {
      throw InputError("FrameBudgetController: level '" + level.Name + "' has " +
        std::to_string(level.MovedPoints.size()) + " targets, the first level " +
        std::to_string(first.MovedPoints.size()) + ".");
    }
    if (level.NumberOfPoints >= this->Levels.back().NumberOfPoints)
    {
      throw InputError("FrameBudgetController: level '" + level.Name +
        "' is not coarser than the previous one; add levels finest first.");
    }
  }
  if (level.Distances.MaxDisplacement.size() != level.MovedPoints.size())
  {
    throw InputError("FrameBudgetController: level '" + level.Name + "' has distances for " +
      std::to_string(level.Distances.MaxDisplacement.size()) + " targets and moved points for " +
      std::to_string(level.MovedPoints.size()) + ".");
  }
  std::vector<WeightOptimizer> optimizers(this->Settings.Thresholds.size());
  for (size_t t = 0; t < optimizers.size(); ++t)
  {
    OptimizerSettings os;
    os.Threshold = this->Settings.Thresholds[t];
    os.Strategy = this->Settings.Strategy;
    os.AdjustThreshold = this->Settings.AdjustThreshold;
    os.Hysteresis = this->Settings.OptimizerHysteresis;
    os.MaxActiveTargets = this->Settings.MaxActiveTargets;
    os.MaxVertexError = this->OptimizerBound;
    optimizers[t].SetSettings(os);
    optimizers[t].SetTargetDistances(level.Distances);
  }
  this->Levels.push_back(level);
  this->Optimizers.push_back(std::move(optimizers));
  this->Models.push_back(level.Cost);
  this->Margins.push_back(0.0);
  this->Chosen.push_back(-1);
  this->Evaluated.push_back(false);
  this->Samples.emplace_back();
  this->LastLevel = -1;
  this->Reset(0);
}

void FrameBudgetController::Reset(int level)
{
  // Never finer than the finest level allowed (a device profile's largest level).
  this->Current = std::clamp(std::max(level, this->Settings.FinestLevel), 0,
    std::max(0, static_cast<int>(this->Levels.size()) - 1));
  this->Streak = 0;
  this->StreakDirection = 0;
  this->MorphFrom = -1;
  this->MorphProgress = 0.0;
  this->Switches = 0;
  std::fill(this->Chosen.begin(), this->Chosen.end(), -1);
  std::fill(this->Evaluated.begin(), this->Evaluated.end(), false);
  for (auto& perLevel : this->Optimizers)
  {
    for (auto& o : perLevel)
    {
      o.ResetHistory();
    }
  }
}

FrameBudgetController::Candidate FrameBudgetController::Evaluate(
  size_t level, const std::vector<double>& weights, double budget)
{
  const LevelOfDetail& lod = this->Levels[level];
  std::vector<Candidate> all(this->Settings.Thresholds.size());
  int best = -1, cheapest = -1;
  for (size_t t = 0; t < this->Settings.Thresholds.size(); ++t)
  {
    Candidate& c = all[t];
    c.Threshold = this->Settings.Thresholds[t];
    c.Weights = this->Optimizers[level][t].Optimize(weights);
    double targetPoints = 0.0;
    for (size_t i = 1; i < c.Weights.size(); ++i)
    {
      if (c.Weights[i] != 0.0)
      {
        ++c.Active;
        targetPoints += lod.MovedPoints[i];
      }
    }
    c.TargetPoints = targetPoints;
    c.Seconds = this->Models[level].Predict(targetPoints) + this->Margins[level];
    c.Error = lod.GeometricError +
      WeightOptimizer::ErrorBound(weights, c.Weights, lod.Distances.MaxDisplacement);
    const int ti = static_cast<int>(t);
    if (c.Seconds <= budget && (best < 0 || c.Error < all[static_cast<size_t>(best)].Error))
    {
      best = ti;
    }
    // The cheapest; of equal predictions (a flat cost model) the fewest moved points.
    const Candidate* k = cheapest < 0 ? nullptr : &all[static_cast<size_t>(cheapest)];
    if (!k || c.Seconds < k->Seconds ||
      (c.Seconds == k->Seconds && c.TargetPoints < k->TargetPoints))
    {
      cheapest = ti;
    }
  }
  int chosen = best >= 0 ? best : cheapest;
  // The previous frame's threshold stays while it fits, unless a better one fits with a
  // margin: in (1 - ThresholdHysteresis) of the budget, or at no more cost than it (as the
  // level's rule for a finer level). When nothing fits, it stays while it is as cheap as
  // the cheapest.
  const int previous = this->Chosen[level];
  if (previous >= 0 && previous != chosen)
  {
    const Candidate& p = all[static_cast<size_t>(previous)];
    const Candidate& c = all[static_cast<size_t>(chosen)];
    const bool keep = best >= 0 ? p.Seconds <= budget &&
        !(c.Seconds <= (1.0 - this->Settings.ThresholdHysteresis) * budget ||
          c.Seconds <= p.Seconds)
                                : p.Seconds <= c.Seconds && p.TargetPoints <= c.TargetPoints;
    chosen = keep ? previous : chosen;
  }
  this->Chosen[level] = chosen;
  return all[static_cast<size_t>(chosen)];
}

ControllerDecision FrameBudgetController::Update(const std::vector<double>& weights)
{
  return this->Update(weights, 0.0);
}

void FrameBudgetController::SetOptimizerBound(double bound)
{
  if (bound == this->OptimizerBound)
  {
    return;
  }
  this->OptimizerBound = bound;
  for (auto& perLevel : this->Optimizers)
  {
    for (auto& o : perLevel)
    {
      OptimizerSettings os = o.GetSettings();
      os.MaxVertexError = bound;
      o.SetSettings(os); // keeps the hysteresis history
    }
  }
}

double ScreenPixelsPerUnit(double viewportHeight, double fovYDegrees, double distance)
{
  if (!std::isfinite(viewportHeight) || viewportHeight <= 0.0 || !std::isfinite(distance) ||
    distance <= 0.0 || !std::isfinite(fovYDegrees) || fovYDegrees <= 0.0 || fovYDegrees >= 180.0)
  {
    throw InputError("ScreenPixelsPerUnit: the viewport height and distance must be positive "
                     "and the field of view in (0, 180) degrees.");
  }
  const double halfAngle = 0.5 * fovYDegrees * 3.14159265358979323846 / 180.0;
  return viewportHeight / (2.0 * distance * std::tan(halfAngle));
}

ControllerDecision FrameBudgetController::Update(
  const std::vector<double>& weights, double pixelsPerUnit)
{
  if (!std::isfinite(pixelsPerUnit))
  {
    throw InputError("FrameBudgetController: pixels per unit must be finite.");
  }
  if (this->Levels.empty())
  {
    throw InputError("FrameBudgetController: no levels of detail.");
  }
  if (weights.size() != this->Levels.front().MovedPoints.size())
  {
    throw InputError("FrameBudgetController: got " + std::to_string(weights.size()) +
      " weights for " + std::to_string(this->Levels.front().MovedPoints.size()) + " targets.");
  }
  const double budget = this->Settings.FrameBudget;
  const int last = static_cast<int>(this->Levels.size()) - 1;
  const bool onScreen = pixelsPerUnit > 0.0;
  // Target level of detail: the error the screen cannot see bounds the optimizer.
  double bound = this->Settings.MaxVertexError;
  double targetBound = 0.0;
  if (onScreen && this->Settings.TargetPixelBound > 0.0)
  {
    targetBound = this->Settings.TargetPixelBound / pixelsPerUnit;
    bound = bound > 0.0 ? std::min(bound, targetBound) : targetBound;
  }
  this->SetOptimizerBound(bound);
  const int finest = std::clamp(this->Settings.FinestLevel, 0, last);
  // The level the screen asks for: the coarsest whose error projects within the pixel
  // bound, a coarser one than the current within (1 - LevelHysteresis) of it.
  int screenLevel = -1;
  if (onScreen && this->Settings.PixelBound > 0.0)
  {
    screenLevel = finest;
    for (int l = last; l > finest; --l)
    {
      const double px = this->Levels[l].GeometricError * pixelsPerUnit;
      const double allowed = this->Settings.PixelBound *
        (l > this->Current ? 1.0 - this->Settings.LevelHysteresis : 1.0);
      if (px <= allowed)
      {
        screenLevel = l;
        break;
      }
    }
  }
  else if (finest > 0)
  {
    screenLevel = -2; // no screen, but a finest level: only the floor applies
  }
  // The decisions below look at the current level and its two neighbours only, so only
  // they are evaluated (each level's optimizers at every threshold: the controller's own
  // cost). A level entering this window starts without history (no incumbents, no chosen
  // threshold), as after Reset.
  std::vector<Candidate> candidates(this->Levels.size());
  const int lo = std::max(0, this->Current - 1), hi = std::min(last, this->Current + 1);
  for (int l = 0; l <= last; ++l)
  {
    const bool inWindow = l >= lo && l <= hi;
    if (inWindow && !this->Evaluated[static_cast<size_t>(l)])
    {
      for (auto& o : this->Optimizers[static_cast<size_t>(l)])
      {
        o.ResetHistory();
      }
      this->Chosen[static_cast<size_t>(l)] = -1;
    }
    this->Evaluated[static_cast<size_t>(l)] = inWindow;
    if (inWindow)
    {
      candidates[static_cast<size_t>(l)] = this->Evaluate(static_cast<size_t>(l), weights, budget);
    }
  }

  // Start a transition when none is running.
  if (this->MorphFrom < 0)
  {
    const Candidate& here = candidates[this->Current];
    const double keep = 1.0 - this->Settings.LevelHysteresis;
    // Where would we rather be? Coarser: at once when the budget is broken at every
    // threshold, else when the coarser level is clearly better (less error within budget).
    // Finer: when it fits with a margin and is clearly better.
    int direction = 0;
    bool forced = false;
    if ((here.Seconds > budget || this->Current < finest) && this->Current < last)
    {
      direction = +1;
      forced = true;
    }
    else if (screenLevel >= 0)
    {
      // On screen: towards the screen's level; finer only while it fits the budget with
      // the margin (the budget breaks the tie as below).
      if (screenLevel > this->Current)
      {
        direction = +1;
      }
      else if (screenLevel < this->Current &&
        candidates[this->Current - 1].Seconds <= keep * budget)
      {
        direction = -1;
      }
    }
    else if (this->Current < last && candidates[this->Current + 1].Seconds <= budget &&
      candidates[this->Current + 1].Error < keep * here.Error)
    {
      direction = +1;
    }
    else if (this->Current > finest && candidates[this->Current - 1].Seconds <= keep * budget &&
      candidates[this->Current - 1].Error < keep * here.Error)
    {
      direction = -1;
    }
    this->Streak = (direction != 0 && direction == this->StreakDirection) ? this->Streak + 1 : 1;
    this->StreakDirection = direction;
    if (direction != 0 && (forced || this->Streak >= this->Settings.MinFramesPerLevel))
    {
      this->Streak = 0;
      this->StreakDirection = 0;
      if (this->Settings.GeomorphFrames == 0)
      {
        this->Current += direction;
        ++this->Switches;
      }
      else if (direction > 0)
      {
        this->MorphFrom = this->Current; // coarsen: the fine level slides onto the coarse one
        this->MorphProgress = 0.0;
      }
      else
      {
        // refine: take the fine topology at once, shaped like the coarse level, and slide
        // out of it
        this->MorphFrom = this->Current;
        this->MorphProgress = 0.0;
        --this->Current;
        ++this->Switches;
      }
    }
  }

  ControllerDecision d;
  int shown = this->Current;
  if (this->MorphFrom >= 0)
  {
    // Both directions display the finer level (Current) while it slides.
    const bool coarsening = this->MorphFrom == this->Current;
    const int fine = this->Current;
    shown = fine;
    double delta = 1.0 / static_cast<double>(this->Settings.GeomorphFrames);
    const auto& reach = this->Levels[fine].GeomorphReach;
    if (onScreen && this->Settings.MaxGeomorphPixels > 0.0 && reach.size() == weights.size())
    {
      // The largest jump of a point over the whole transition, in pixels, under this
      // frame's weights: slide slower where it is large.
      double jump = reach[0];
      for (size_t k = 1; k < reach.size(); ++k)
      {
        jump += std::abs(weights[k]) * reach[k];
      }
      jump *= pixelsPerUnit;
      if (jump * delta > this->Settings.MaxGeomorphPixels)
      {
        delta = std::max(this->Settings.MaxGeomorphPixels / jump,
          1.0 /
            static_cast<double>(
              std::max(this->Settings.MaxGeomorphFrames, this->Settings.GeomorphFrames)));
      }
    }
    // Snap a progress within rounding of the end onto it.
    this->MorphProgress =
      this->MorphProgress + delta >= 1.0 - 1e-9 ? 1.0 : this->MorphProgress + delta;
    const double step = this->MorphProgress;
    d.MorphTowards = fine + 1;
    d.Alpha = coarsening ? step : 1.0 - step;
    if (this->MorphProgress >= 1.0)
    {
      if (coarsening)
      {
        ++this->Current;
        ++this->Switches;
      }
      this->MorphFrom = -1;
      if (d.Alpha >= 1.0)
      {
        // The last frame of a coarsening shows the coarse shape: show it as the coarse level.
        shown = this->Current;
        d.MorphTowards = -1;
        d.Alpha = 0.0;
      }
    }
  }
  const Candidate& c = candidates[shown];
  d.Level = shown;
  d.Threshold = c.Threshold;
  d.Weights = c.Weights;
  d.ActiveTargets = c.Active;
  d.TargetPoints = c.TargetPoints;
  d.PredictedSeconds = c.Seconds;
  d.PredictedError = c.Error;
  if (d.MorphTowards >= 0)
  {
    const double coarseError = this->Levels[d.MorphTowards].GeometricError;
    d.PredictedError += d.Alpha * std::max(0.0, coarseError - this->Levels[shown].GeometricError);
  }
  d.WithinBudget = d.PredictedSeconds <= budget;
  d.ScreenLevel = screenLevel >= 0 ? screenLevel : -1;
  d.TargetErrorBound = targetBound;
  if (onScreen)
  {
    double geometric = this->Levels[shown].GeometricError;
    if (d.MorphTowards >= 0)
    {
      geometric += d.Alpha * std::max(0.0, this->Levels[d.MorphTowards].GeometricError - geometric);
    }
    d.LevelPixelError = geometric * pixelsPerUnit;
  }
  this->LastLevel = shown;
  this->LastTargetPoints = c.TargetPoints;
  return d;
}

void FrameBudgetController::ReportMeasuredSeconds(double seconds)
{
  this->ReportMeasuredSeconds(seconds, this->LastTargetPoints);
}

void FrameBudgetController::ReportMeasuredSeconds(double seconds, double targetPoints)
{
  if (!std::isfinite(targetPoints) || targetPoints < 0.0)
  {
    throw InputError("FrameBudgetController: a measured frame must move a finite, "
                     "non-negative number of target points, got " +
      std::to_string(targetPoints) + ".");
  }
  if (!std::isfinite(seconds) || seconds < 0.0)
  {
    throw InputError("FrameBudgetController: a measured frame must take a finite, non-negative "
                     "number of seconds, got " +
      std::to_string(seconds) + ".");
  }
  if (this->LastLevel < 0)
  {
    throw InputError("FrameBudgetController: a measurement without a decided frame (call "
                     "Update first).");
  }
  const size_t window = static_cast<size_t>(this->Settings.MeasurementWindow);
  if (window == 0)
  {
    return;
  }
  const size_t level = static_cast<size_t>(this->LastLevel);
  auto& samples = this->Samples[level];
  if (samples.size() >= window)
  {
    samples.erase(
      samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(samples.size() - window + 1));
  }
  samples.emplace_back(targetPoints, seconds);
  // Frames far slower than the model expects (preempted, a page fault) are left out of the
  // fit while they are a minority; when most are, the machine has slowed down: all count.
  const CostModel& current = this->Models[level];
  auto slow = [&](const std::pair<double, double>& m)
  { return m.second > 3.0 * (current.Predict(m.first) + this->Margins[level]); };
  const size_t slowFrames =
    static_cast<size_t>(std::count_if(samples.begin(), samples.end(), slow));
  const bool dropSlow = 3 * slowFrames < samples.size();
  std::vector<double> x, y;
  for (const auto& m : samples)
  {
    if (!dropSlow || !slow(m))
    {
      x.push_back(m.first);
      y.push_back(m.second);
    }
  }
  const CostModel model = CostModel::FitMedian(x, y, current.PerTargetPoint);
  this->Models[level] = model;
  std::vector<double> residuals(x.size());
  for (size_t i = 0; i < x.size(); ++i)
  {
    residuals[i] = y[i] - model.Predict(x[i]);
  }
  const size_t q = static_cast<size_t>(
    this->Settings.MeasuredQuantile * static_cast<double>(residuals.size() - 1));
  std::nth_element(
    residuals.begin(), residuals.begin() + static_cast<std::ptrdiff_t>(q), residuals.end());
  this->Margins[level] = std::max(0.0, residuals[q]);
}
} // namespace morphnode
