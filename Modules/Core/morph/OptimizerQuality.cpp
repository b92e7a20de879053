// SPDX-License-Identifier: BSD-3-Clause
#include "morph/OptimizerQuality.h"

#include "base/Error.h"
#include "morph/Weights.h"

#include <chrono>
#include <cmath>
#include <sstream>

namespace morphnode
{
std::vector<FrameQuality> MeasureOptimizerQuality(const MorphAttribute<float>& positions,
  const TargetDistances& distances, const WeightTrack& track, const OptimizerMethod& method)
{
  if (track.GetNumberOfChannels() != positions.GetNumberOfTargets())
  {
    std::ostringstream msg;
    msg << "the weight track has " << track.GetNumberOfChannels() << " channels for "
        << positions.GetNumberOfTargets() << " targets";
    throw InputError(msg.str());
  }
  WeightOptimizer optimizer;
  optimizer.SetSettings(method.Settings);
  optimizer.SetTargetDistances(distances);
  const size_t n = positions.GetNumberOfPoints();
  std::vector<float> reference(n * 3), optimized(n * 3);
  std::vector<FrameQuality> frames;
  frames.reserve(track.GetNumberOfFrames());
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    const double* row = track.GetFrame(f);
    const std::vector<double> w(row, row + track.GetNumberOfChannels());
    FrameQuality q;
    q.Weights = optimizer.Optimize(w);
    q.ErrorBound = optimizer.GetLastErrorBound();
    q.ActiveTargets = CountActiveTargets(q.Weights);
    positions.Blend(w.data(), w.size(), reference.data(), 0, n);
    const auto t0 = std::chrono::steady_clock::now();
    positions.Blend(q.Weights.data(), q.Weights.size(), optimized.data(), 0, n);
    q.MorphSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double sum2 = 0.0;
    for (size_t p = 0; p < n; ++p)
    {
      const double dx = reference[3 * p] - optimized[3 * p];
      const double dy = reference[3 * p + 1] - optimized[3 * p + 1];
      const double dz = reference[3 * p + 2] - optimized[3 * p + 2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      sum2 += d2;
      q.MaxError = std::max(q.MaxError, std::sqrt(d2));
    }
    q.RmsError = n ? std::sqrt(sum2 / static_cast<double>(n)) : 0.0;
    frames.push_back(std::move(q));
  }
  return frames;
}

WeightTrack ToAbsoluteWeights(
  const WeightTrack& relative, const std::vector<std::string>& targetNames)
{
  std::vector<int> source(targetNames.size(), -1);
  for (size_t c = 0; c < relative.GetNumberOfChannels(); ++c)
  {
    const std::string& name = relative.GetChannels()[c];
    bool found = false;
    for (size_t t = 1; t < targetNames.size(); ++t)
    {
      if (targetNames[t] == name)
      {
        source[t] = static_cast<int>(c);
        found = true;
      }
    }
    if (!found)
    {
      throw InputError("weight track channel '" + name + "' names no target of the face");
    }
  }
  WeightTrack absolute(targetNames, relative.GetFrameRate());
  std::vector<double> row(targetNames.size());
  for (size_t f = 0; f < relative.GetNumberOfFrames(); ++f)
  {
    double others = 0.0;
    for (size_t t = 1; t < targetNames.size(); ++t)
    {
      row[t] = source[t] < 0 ? 0.0 : relative.GetValue(f, static_cast<size_t>(source[t]));
      others += row[t];
    }
    row[0] = 1.0 - others;
    absolute.AppendFrame(row);
  }
  return absolute;
}
} // namespace morphnode
