// SPDX-License-Identifier: BSD-3-Clause
#include "morph/Distances.h"

#include <algorithm>

namespace morphnode
{
void NormalizeDistances(TargetDistances& d)
{
  const size_t n = d.DistMorph.size();
  d.DistNorm.assign(n, 0.0);
  double largest = 0.0;
  for (size_t i = 1; i < n; ++i)
  {
    largest = std::max(largest, d.DistMorph[i]);
  }
  if (largest > 0.0)
  {
    for (size_t i = 1; i < n; ++i)
    {
      d.DistNorm[i] = d.DistMorph[i] / largest;
    }
  }
}

template <typename T>
TargetDistances ComputeTargetDistances(const MorphAttribute<T>& positions)
{
  const size_t n = positions.GetNumberOfTargets();
  TargetDistances d;
  d.DistMorph.assign(n, 0.0);
  d.MaxDisplacement.assign(n, 0.0);
  for (size_t i = 1; i < n; ++i)
  {
    d.DistMorph[i] = positions.GetTarget(i).GetSumNorm();
    d.MaxDisplacement[i] = positions.GetTarget(i).GetMaxNorm();
  }
  NormalizeDistances(d);
  return d;
}

template <typename T>
std::vector<double> ComputePointDistances(const MorphAttribute<T>& positions, size_t target)
{
  std::vector<double> perPoint;
  positions.GetTarget(target).PointNorms(perPoint);
  return perPoint;
}

template <typename T>
std::vector<double> ComputeAnimatedRegion(const MorphAttribute<T>& positions)
{
  std::vector<double> region(positions.GetNumberOfPoints(), 0.0);
  std::vector<double> perPoint;
  for (size_t i = 1; i < positions.GetNumberOfTargets(); ++i)
  {
    positions.GetTarget(i).PointNorms(perPoint);
    for (size_t p = 0; p < region.size(); ++p)
    {
      region[p] = std::max(region[p], perPoint[p]);
    }
  }
  return region;
}

template TargetDistances ComputeTargetDistances(const MorphAttribute<float>&);
template TargetDistances ComputeTargetDistances(const MorphAttribute<double>&);
template std::vector<double> ComputePointDistances(const MorphAttribute<float>&, size_t);
template std::vector<double> ComputePointDistances(const MorphAttribute<double>&, size_t);
template std::vector<double> ComputeAnimatedRegion(const MorphAttribute<float>&);
template std::vector<double> ComputeAnimatedRegion(const MorphAttribute<double>&);
} // namespace morphnode
