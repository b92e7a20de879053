// SPDX-License-Identifier: BSD-3-Clause
#include "morph/Weights.h"

#include "base/Error.h"

#include <cmath>
#include <sstream>

namespace morphnode
{
const char* WeightModeName(WeightMode mode)
{
  switch (mode)
  {
    case WeightMode::Strict:
      return "Strict";
    case WeightMode::Normalize:
      return "Normalize";
    case WeightMode::Relative:
      return "Relative";
  }
  return "Unknown";
}

std::vector<double> ResolveWeights(WeightMode mode, const std::vector<double>& requested)
{
  std::vector<double> absolute;
  ResolveWeights(mode, requested.data(), requested.size(), absolute);
  return absolute;
}

void ResolveWeights(
  WeightMode mode, const double* requested, size_t count, std::vector<double>& absolute)
{
  if (count == 0)
  {
    throw InputError("no weights: the morph node needs at least the neutral target");
  }
  double sum = 0.0;
  for (size_t i = 0; i < count; ++i)
  {
    const double w = requested[i];
    if (!std::isfinite(w))
    {
      std::ostringstream msg;
      msg << "weight " << i << " is " << w << "; weights must be finite numbers";
      throw InputError(msg.str());
    }
    // Java3D's Morph checks only the sum, so Strict accepts negative weights (a negative
    // neutral is common when expression weights sum above 1); Normalize cannot divide them.
    if (w < 0.0 && mode == WeightMode::Normalize)
    {
      std::ostringstream msg;
      msg << "weight " << i << " is negative (" << w
          << "); Normalize mode needs weights >= 0 (Strict and Relative accept negative ones)";
      throw InputError(msg.str());
    }
    sum += w;
  }

  absolute.assign(requested, requested + count);
  switch (mode)
  {
    case WeightMode::Strict:
      if (std::abs(sum - 1.0) > StrictTolerance)
      {
        std::ostringstream msg;
        msg << "Strict weight mode: the weights sum to " << sum << ", not 1 (tolerance "
            << StrictTolerance << ", as in Java3D's Morph node)";
        throw InputError(msg.str());
      }
      break;
    case WeightMode::Normalize:
      if (!(sum > 0.0))
      {
        throw InputError("Normalize weight mode: the weights sum to 0; nothing to normalize");
      }
      for (double& w : absolute)
      {
        w /= sum;
      }
      break;
    case WeightMode::Relative:
    {
      double others = 0.0;
      for (size_t i = 1; i < count; ++i)
      {
        others += requested[i];
      }
      absolute[0] = 1.0 - others;
      break;
    }
  }
}

int CountActiveTargets(const std::vector<double>& absolute)
{
  int count = 0;
  for (size_t i = 1; i < absolute.size(); ++i)
  {
    count += absolute[i] != 0.0 ? 1 : 0;
  }
  return count;
}
} // namespace morphnode
