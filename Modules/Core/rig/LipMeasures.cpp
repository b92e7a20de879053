// SPDX-License-Identifier: BSD-3-Clause
#include "rig/LipMeasures.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace morphnode
{
bool FindLipPair(const std::vector<float>& points, const std::vector<double>& opening,
  double midline, double touch, LipPair& pair)
{
  const size_t n = points.size() / 3;
  if (n == 0 || opening.size() != points.size())
  {
    return false;
  }
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (size_t p = 0; p < n; ++p)
  {
    lo = std::min(lo, static_cast<double>(points[3 * p]));
    hi = std::max(hi, static_cast<double>(points[3 * p]));
  }
  const double centre = 0.5 * (lo + hi);
  std::vector<size_t> mid;
  for (size_t p = 0; p < n; ++p)
  {
    if (std::abs(points[3 * p] - centre) <= midline)
    {
      mid.push_back(p);
    }
  }
  bool found = false;
  for (size_t u : mid)
  {
    for (size_t l : mid)
    {
      const double dx = points[3 * u] - points[3 * l];
      const double dy = points[3 * u + 1] - points[3 * l + 1];
      const double dz = points[3 * u + 2] - points[3 * l + 2];
      if (u == l || dy < 0.0 || std::abs(dx) > midline ||
        std::sqrt(dx * dx + dy * dy + dz * dz) > touch)
      {
        continue;
      }
      const double grows = opening[3 * u + 1] - opening[3 * l + 1];
      if (grows > pair.Opening || !found)
      {
        pair.Upper = u;
        pair.Lower = l;
        pair.RestGap = dy;
        pair.Opening = grows;
        found = true;
      }
    }
  }
  return found && pair.Opening > 0.0;
}

bool FindMouthCorners(const std::vector<float>& points, const std::vector<double>& spread,
  std::array<size_t, 2>& corners)
{
  const size_t n = points.size() / 3;
  double best[2] = { 0.0, 0.0 };
  for (size_t p = 0; p < n && spread.size() == points.size(); ++p)
  {
    const double dx = spread[3 * p];
    const int side = points[3 * p] >= 0.0 ? 0 : 1;
    const double outward = side == 0 ? dx : -dx;
    if (outward > best[side])
    {
      best[side] = outward;
      corners[static_cast<size_t>(side)] = p;
    }
  }
  return best[0] > 0.0 && best[1] > 0.0;
}

std::array<double, 3> BlendPoint(const std::vector<float>& points,
  const std::vector<const float*>& deltas, const double* weights, size_t p)
{
  std::array<double, 3> v{ { points[3 * p], points[3 * p + 1], points[3 * p + 2] } };
  for (size_t t = 0; t < deltas.size(); ++t)
  {
    if (deltas[t] && weights[t] != 0.0)
    {
      for (int c = 0; c < 3; ++c)
      {
        v[static_cast<size_t>(c)] += weights[t] * deltas[t][3 * p + static_cast<size_t>(c)];
      }
    }
  }
  return v;
}
} // namespace morphnode
