// SPDX-License-Identifier: BSD-3-Clause
#include "morph/WeightOptimizer.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace morphnode
{
const char* RedistributionName(Redistribution strategy)
{
  switch (strategy)
  {
    case Redistribution::Maximum:
      return "Maximum";
    case Redistribution::Remaining:
      return "Remaining";
    case Redistribution::Neutral:
      return "Neutral";
  }
  return "Unknown";
}

void WeightOptimizer::SetSettings(const OptimizerSettings& s)
{
  auto check = [](double v, const char* what)
  {
    if (!std::isfinite(v) || v < 0.0)
    {
      std::ostringstream msg;
      msg << what << " must be a finite number >= 0, got " << v;
      throw InputError(msg.str());
    }
  };
  check(s.Threshold, "threshold");
  check(s.MaxVertexError, "maximum vertex error");
  check(s.Hysteresis, "hysteresis");
  if (s.Hysteresis >= 1.0)
  {
    throw InputError("hysteresis must be below 1");
  }
  if (s.MaxActiveTargets < 0)
  {
    throw InputError("the maximum number of active targets must be >= 0");
  }
  this->Settings = s;
}

void WeightOptimizer::SetTargetDistances(const TargetDistances& distances)
{
  this->Distances = distances;
  this->WasActive.clear();
}

std::vector<double> WeightOptimizer::Redistribute(
  const std::vector<double>& w, const std::vector<bool>& keep, Redistribution strategy)
{
  std::vector<double> e(w.size(), 0.0);
  double pruned = 0.0;
  for (size_t i = 0; i < w.size(); ++i)
  {
    if (keep[i])
    {
      e[i] = w[i];
    }
    else
    {
      pruned += w[i];
    }
  }
  if (pruned == 0.0 || e.empty())
  {
    return e;
  }
  switch (strategy)
  {
    case Redistribution::Maximum:
    {
      size_t k = 0;
      for (size_t i = 1; i < e.size(); ++i)
      {
        if (keep[i] && (!keep[k] || e[i] > e[k]))
        {
          k = i;
        }
      }
      e[k] += pruned;
      break;
    }
    case Redistribution::Remaining:
    {
      // In proportion to the size |w_j| of each remaining weight. For non-negative weights
      // (the paper's, Java3D's) this is the paper's scaling by 1 + m / S. Scaling by the
      // *signed* sum S instead explodes as S -> 0: relative (glTF, ARKit) weights often sum
      // to more than 1, the neutral's absolute weight is then negative, and S = 1 - m can
      // be ~0 or negative (kept targets scaled by 100x, or flipped). With |w_j| each weight
      // moves by at most m |w_j| / sum |w|.
      double remaining = 0.0;
      for (size_t i = 0; i < e.size(); ++i)
      {
        remaining += std::abs(e[i]);
      }
      if (remaining > 0.0)
      {
        const double share = pruned / remaining;
        for (double& v : e)
        {
          v += share * std::abs(v);
        }
      }
      else
      {
        e[0] += pruned;
      }
      break;
    }
    case Redistribution::Neutral:
      e[0] += pruned;
      break;
  }
  return e;
}

double WeightOptimizer::ErrorBound(const std::vector<double>& original,
  const std::vector<double>& effective, const std::vector<double>& maxDisplacement)
{
  double b = 0.0;
  for (size_t i = 1; i < original.size() && i < maxDisplacement.size(); ++i)
  {
    b += std::abs(effective[i] - original[i]) * maxDisplacement[i];
  }
  return b;
}

double WeightOptimizer::Bound(const std::vector<double>& w, const std::vector<bool>& keep) const
{
  return ErrorBound(
    w, Redistribute(w, keep, this->Settings.Strategy), this->Distances.MaxDisplacement);
}

std::vector<double> WeightOptimizer::Optimize(const std::vector<double>& w)
{
  const size_t n = w.size();
  const OptimizerSettings& s = this->Settings;
  this->LastErrorBound = 0.0;
  if (!s.IsActive())
  {
    return w;
  }
  if (this->Distances.MaxDisplacement.size() != n)
  {
    std::ostringstream msg;
    msg << "the optimizer got " << n << " weights for " << this->Distances.MaxDisplacement.size()
        << " targets";
    throw InputError(msg.str());
  }
  if (this->WasActive.size() != n)
  {
    this->WasActive.assign(n, false);
  }
  const std::vector<double>& reach = this->Distances.MaxDisplacement;
  auto contribution = [&](size_t i) { return std::abs(w[i]) * reach[i]; };
  // Hysteresis: a target shown in the previous frame (an incumbent) keeps its place unless
  // a criterion beats it by the margin h. Threshold: pruned below th_i (1 - h). Budget:
  // ranked by c_i / (1 - h). Bound: pruned only while B <= eps (1 - h).
  const double stay = 1.0 - s.Hysteresis;
  auto incumbent = [&](size_t i) { return s.Hysteresis > 0.0 && this->WasActive[i]; };
  auto stickyContribution = [&](size_t i)
  { return incumbent(i) ? contribution(i) / stay : contribution(i); };

  std::vector<bool> keep(n);
  for (size_t i = 0; i < n; ++i)
  {
    keep[i] = w[i] != 0.0;
  }
  // Handing weight to the neutral must leave it a target that can receive it.
  const bool neutralPrunable = s.Strategy != Redistribution::Neutral;

  // 1. Threshold.
  if (s.Threshold > 0.0)
  {
    size_t largest = 0;
    for (size_t i = 1; i < n; ++i)
    {
      if (std::abs(w[i]) > std::abs(w[largest]))
      {
        largest = i;
      }
    }
    for (size_t i = 0; i < n; ++i)
    {
      if (!keep[i] || i == largest || (i == 0 && !neutralPrunable))
      {
        continue;
      }
      double th = s.Threshold;
      if (s.AdjustThreshold)
      {
        th *= 1.0 - this->Distances.DistNorm[i];
      }
      if (this->WasActive[i])
      {
        th *= 1.0 - s.Hysteresis;
      }
      if (std::abs(w[i]) < th)
      {
        keep[i] = false;
      }
    }
  }

  // 2. Budget: keep the k largest geometric contributions. With hysteresis a target shown
  // in the previous frame competes with c_i / (1 - h): an outsider takes its place only
  // when c_out * (1 - h) > c_in, the threshold step's margin with the rival's contribution
  // as the threshold.
  if (s.MaxActiveTargets > 0)
  {
    std::vector<size_t> active;
    for (size_t i = 1; i < n; ++i)
    {
      if (keep[i])
      {
        active.push_back(i);
      }
    }
    if (active.size() > static_cast<size_t>(s.MaxActiveTargets))
    {
      std::stable_sort(active.begin(), active.end(),
        [&](size_t a, size_t b) { return stickyContribution(a) > stickyContribution(b); });
      for (size_t k = static_cast<size_t>(s.MaxActiveTargets); k < active.size(); ++k)
      {
        keep[active[k]] = false;
      }
    }
  }

  // 3. Error bound.
  if (s.MaxVertexError > 0.0)
  {
    if (s.Threshold == 0.0 && s.MaxActiveTargets == 0)
    {
      // Prune greedily, cheapest first, as long as the bound holds.
      std::vector<size_t> candidates;
      for (size_t i = 1; i < n; ++i)
      {
        if (keep[i])
        {
          candidates.push_back(i);
        }
      }
      // With hysteresis an incumbent is tried later (ranked by c_i / (1 - h)) and pruned
      // only while the bound stays within eps (1 - h); a target pruned in the previous
      // frame stays pruned as long as B <= eps.
      std::stable_sort(candidates.begin(), candidates.end(),
        [&](size_t a, size_t b) { return stickyContribution(a) < stickyContribution(b); });
      for (size_t i : candidates)
      {
        keep[i] = false;
        const double limit = incumbent(i) ? s.MaxVertexError * stay : s.MaxVertexError;
        if (this->Bound(w, keep) > limit)
        {
          keep[i] = true;
        }
      }
    }
    else
    {
      // Restore the most expensive pruned targets until the bound holds. The neutral is a
      // candidate too (last: it moves nothing itself): the threshold may have pruned it, and
      // with Remaining or Maximum its weight then lands on the targets. Restoring every
      // target but not the neutral could leave B > eps; with everything restored B = 0.
      std::vector<size_t> pruned;
      for (size_t i = 0; i < n; ++i)
      {
        if (!keep[i] && w[i] != 0.0)
        {
          pruned.push_back(i);
        }
      }
      std::stable_sort(pruned.begin(), pruned.end(),
        [&](size_t a, size_t b) { return stickyContribution(a) > stickyContribution(b); });
      for (size_t k = 0; k < pruned.size() && this->Bound(w, keep) > s.MaxVertexError; ++k)
      {
        keep[pruned[k]] = true;
      }
      // Hysteresis: a target shown in the previous frame that the threshold or the budget
      // pruned again is pruned only while the bound stays within eps (1 - h); restore such
      // incumbents (most expensive first) while B > eps (1 - h). A target pruned in the
      // previous frame is restored only when B > eps (above). Like the restore above, this
      // band wins over the budget.
      if (s.Hysteresis > 0.0)
      {
        for (size_t k = 0; k < pruned.size() && this->Bound(w, keep) > s.MaxVertexError * stay; ++k)
        {
          if (this->WasActive[pruned[k]])
          {
            keep[pruned[k]] = true;
          }
        }
      }
    }
  }

  std::vector<double> e = Redistribute(w, keep, s.Strategy);
  this->LastErrorBound = ErrorBound(w, e, reach);
  for (size_t i = 0; i < n; ++i)
  {
    this->WasActive[i] = e[i] != 0.0;
  }
  return e;
}
} // namespace morphnode
