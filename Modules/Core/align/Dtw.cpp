// SPDX-License-Identifier: BSD-3-Clause
#include "align/Dtw.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace morphnode
{
namespace
{
constexpr float Infinity = std::numeric_limits<float>::infinity();

enum Step : uint8_t
{
  Diagonal,
  RightThenUp, // (i-1, j-2) -> (i, j-1) -> (i, j)
  UpThenRight, // (i-2, j-1) -> (i-1, j) -> (i, j)
  HoldA,       // (i, j-1) -> (i, j): row i of A held
  HoldB,       // (i-1, j) -> (i, j): row j of B held
  Start
};

struct Window
{
  std::vector<size_t> Lo, Hi; // per row of A: columns [Lo, Hi)
};

float Distance(const FeatureMatrix& a, size_t i, const FeatureMatrix& b, size_t j)
{
  const float* x = a.Row(i);
  const float* y = b.Row(j);
  float sum = 0.0f;
  for (int k = 0; k < a.Dimension; ++k)
  {
    const float d = x[k] - y[k];
    sum += d * d;
  }
  return std::sqrt(sum);
}

/// DTW inside a window. Returns the path (empty when the end is unreachable).
std::vector<std::pair<size_t, size_t>> Solve(const FeatureMatrix& a, const FeatureMatrix& b,
  const std::vector<bool>& silentA, const std::vector<bool>& silentB, const Window& w,
  const DtwOptions& options, size_t& cells, double& meanDistance)
{
  const size_t n = a.Rows, m = b.Rows;
  std::vector<std::vector<float>> cost(n), local(n);
  std::vector<std::vector<uint8_t>> step(n);
  const float penalty = static_cast<float>(options.SilencePenalty);
  auto at = [&](const std::vector<std::vector<float>>& table, size_t i, size_t j) -> float
  { return (j >= w.Lo[i] && j < w.Hi[i]) ? table[i][j - w.Lo[i]] : Infinity; };
  for (size_t i = 0; i < n; ++i)
  {
    const size_t lo = w.Lo[i], hi = w.Hi[i];
    cost[i].assign(hi - lo, Infinity);
    local[i].resize(hi - lo);
    step[i].assign(hi - lo, Start);
    cells += hi - lo;
    for (size_t j = lo; j < hi; ++j)
    {
      local[i][j - lo] = Distance(a, i, b, j);
    }
    for (size_t j = lo; j < hi; ++j)
    {
      const float d = local[i][j - lo];
      float best = Infinity;
      uint8_t how = Start;
      if (i == 0 && j == 0)
      {
        best = d;
      }
      if (i > 0 && j > 0)
      {
        const float c = at(cost, i - 1, j - 1) + 2.0f * d;
        if (c < best)
        {
          best = c;
          how = Diagonal;
        }
      }
      if (options.SlopeConstraint)
      {
        if (i > 0 && j > 1)
        {
          const float c = at(cost, i - 1, j - 2) + 2.0f * at(local, i, j - 1) + d;
          if (c < best)
          {
            best = c;
            how = RightThenUp;
          }
        }
        if (i > 1 && j > 0)
        {
          const float c = at(cost, i - 2, j - 1) + 2.0f * at(local, i - 1, j) + d;
          if (c < best)
          {
            best = c;
            how = UpThenRight;
          }
        }
      }
      const bool holdA = !options.SlopeConstraint || (silentB.empty() ? false : silentB[j]);
      const bool holdB = !options.SlopeConstraint || (silentA.empty() ? false : silentA[i]);
      if (j > 0 && holdA)
      {
        const float c = at(cost, i, j - 1) + d + penalty * d;
        if (c < best)
        {
          best = c;
          how = HoldA;
        }
      }
      if (i > 0 && holdB)
      {
        const float c = at(cost, i - 1, j) + d + penalty * d;
        if (c < best)
        {
          best = c;
          how = HoldB;
        }
      }
      cost[i][j - lo] = best;
      step[i][j - lo] = how;
    }
    if (options.Progress && (i % 256 == 0) && !options.Progress(static_cast<double>(i) / n))
    {
      throw InputError("alignment cancelled");
    }
  }
  std::vector<std::pair<size_t, size_t>> path;
  if (!(at(cost, n - 1, m - 1) < Infinity))
  {
    return path;
  }
  size_t i = n - 1, j = m - 1;
  double sum = 0.0;
  for (;;)
  {
    path.emplace_back(i, j);
    sum += at(local, i, j);
    const uint8_t how = step[i][j - w.Lo[i]];
    if (how == Start)
    {
      break;
    }
    switch (how)
    {
      case Diagonal:
        --i;
        --j;
        break;
      case RightThenUp:
        path.emplace_back(i, j - 1);
        sum += at(local, i, j - 1);
        --i;
        j -= 2;
        break;
      case UpThenRight:
        path.emplace_back(i - 1, j);
        sum += at(local, i - 1, j);
        i -= 2;
        --j;
        break;
      case HoldA:
        --j;
        break;
      case HoldB:
        --i;
        break;
      default:
        break;
    }
  }
  std::reverse(path.begin(), path.end());
  meanDistance = sum / static_cast<double>(path.size());
  return path;
}

FeatureMatrix Halve(const FeatureMatrix& x)
{
  FeatureMatrix h;
  h.Dimension = x.Dimension;
  h.Rows = (x.Rows + 1) / 2;
  h.Values.assign(h.Rows * static_cast<size_t>(x.Dimension), 0.0f);
  for (size_t i = 0; i < h.Rows; ++i)
  {
    const size_t r0 = 2 * i, r1 = std::min(2 * i + 1, x.Rows - 1);
    for (int k = 0; k < x.Dimension; ++k)
    {
      h.Values[i * static_cast<size_t>(x.Dimension) + static_cast<size_t>(k)] =
        0.5f * (x.Row(r0)[k] + x.Row(r1)[k]);
    }
  }
  return h;
}

std::vector<bool> HalveFlags(const std::vector<bool>& flags)
{
  std::vector<bool> h((flags.size() + 1) / 2);
  for (size_t i = 0; i < h.size(); ++i)
  {
    h[i] = flags[2 * i] && flags[std::min(2 * i + 1, flags.size() - 1)];
  }
  return h;
}

Window FullWindow(size_t n, size_t m)
{
  Window w;
  w.Lo.assign(n, 0);
  w.Hi.assign(n, m);
  return w;
}

/// The window of radius r around a coarse path projected to the fine resolution.
Window Project(const std::vector<std::pair<size_t, size_t>>& coarse, size_t n, size_t m, size_t r)
{
  std::vector<size_t> lo(n, m), hi(n, 0);
  for (const auto& [ci, cj] : coarse)
  {
    for (size_t i = 2 * ci; i <= 2 * ci + 1 && i < n; ++i)
    {
      lo[i] = std::min(lo[i], 2 * cj);
      hi[i] = std::max(hi[i], std::min(m, 2 * cj + 2));
    }
  }
  for (size_t i = 0; i < n; ++i)
  {
    if (lo[i] > hi[i]) // not covered (cannot happen with a connected path): take the neighbour
    {
      lo[i] = i > 0 ? lo[i - 1] : 0;
      hi[i] = i > 0 ? hi[i - 1] : 1;
    }
  }
  Window w;
  w.Lo.resize(n);
  w.Hi.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    const size_t from = i >= r ? i - r : 0, to = std::min(n - 1, i + r);
    size_t l = m, h = 0;
    for (size_t k = from; k <= to; ++k)
    {
      l = std::min(l, lo[k]);
      h = std::max(h, hi[k]);
    }
    w.Lo[i] = l >= r ? l - r : 0;
    w.Hi[i] = std::min(m, h + r);
  }
  w.Lo[0] = 0;
  w.Hi[n - 1] = m;
  return w;
}

std::vector<std::pair<size_t, size_t>> SolveMultiscale(const FeatureMatrix& a,
  const FeatureMatrix& b, const std::vector<bool>& silentA, const std::vector<bool>& silentB,
  const DtwOptions& options, size_t& cells, double& meanDistance, int depth)
{
  const size_t n = a.Rows, m = b.Rows;
  if (n * m <= options.MaximumCells || n < 8 || m < 8 || depth > 20)
  {
    return Solve(a, b, silentA, silentB, FullWindow(n, m), options, cells, meanDistance);
  }
  DtwOptions coarseOptions = options;
  coarseOptions.Progress = nullptr;
  double ignored = 0.0;
  const auto coarse =
    SolveMultiscale(Halve(a), Halve(b), silentA.empty() ? silentA : HalveFlags(silentA),
      silentB.empty() ? silentB : HalveFlags(silentB), coarseOptions, cells, ignored, depth + 1);
  if (coarse.empty())
  {
    return coarse;
  }
  return Solve(a, b, silentA, silentB,
    Project(coarse, n, m, static_cast<size_t>(std::max(1, options.Radius))), options, cells,
    meanDistance);
}
} // namespace

DtwResult AlignFeatures(const FeatureMatrix& a, const FeatureMatrix& b,
  const std::vector<bool>& silentA, const std::vector<bool>& silentB, const DtwOptions& options)
{
  if (a.Rows == 0 || b.Rows == 0)
  {
    throw InputError("DTW: both sequences need at least one frame");
  }
  if (a.Dimension != b.Dimension || a.Dimension <= 0 ||
    a.Values.size() != a.Rows * static_cast<size_t>(a.Dimension) ||
    b.Values.size() != b.Rows * static_cast<size_t>(b.Dimension))
  {
    throw InputError("DTW: the sequences need the same feature dimension and whole rows");
  }
  if ((!silentA.empty() && silentA.size() != a.Rows) ||
    (!silentB.empty() && silentB.size() != b.Rows))
  {
    throw InputError("DTW: one silence flag per row (or none)");
  }
  DtwResult result;
  result.Path =
    SolveMultiscale(a, b, silentA, silentB, options, result.CellsEvaluated, result.MeanDistance, 0);
  if (result.Path.empty())
  {
    throw InputError("DTW: no path within the slope constraint (the sequences differ in length "
                     "by more than 2:1 outside silence)");
  }
  if (options.Progress)
  {
    options.Progress(1.0);
  }
  return result;
}
} // namespace morphnode
