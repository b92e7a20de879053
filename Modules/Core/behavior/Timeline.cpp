// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/Timeline.h"

#include <cmath>

namespace morphnode
{
void IntervalIndex::Build(const std::vector<std::pair<double, double>>& intervals)
{
  this->Offsets.clear();
  this->Items.clear();
  this->Long.clear();
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const auto& i : intervals)
  {
    if (std::isfinite(i.first) && std::isfinite(i.second) && i.second >= i.first)
    {
      lo = std::min(lo, i.first);
      hi = std::max(hi, i.second);
    }
  }
  if (!(hi >= lo))
  {
    return;
  }
  // Half-second buckets: idle events are seconds apart, so a bucket holds one or two.
  constexpr double MaxBuckets = 1 << 20;
  constexpr double LongBuckets = 64; // an interval over more buckets goes to the long list
  const double width = std::max(0.5, (hi - lo) / MaxBuckets);
  const size_t buckets = static_cast<size_t>((hi - lo) / width) + 1;
  this->Origin = lo;
  this->InverseWidth = 1.0 / width;
  std::vector<uint32_t> counts(buckets + 1, 0);
  auto range = [&](const std::pair<double, double>& i)
  {
    const size_t b0 = static_cast<size_t>((i.first - lo) * this->InverseWidth);
    const size_t b1 =
      std::min(buckets - 1, static_cast<size_t>((i.second - lo) * this->InverseWidth));
    return std::make_pair(b0, b1);
  };
  auto valid = [](const std::pair<double, double>& i)
  { return std::isfinite(i.first) && std::isfinite(i.second) && i.second >= i.first; };
  for (uint32_t n = 0; n < intervals.size(); ++n)
  {
    if (!valid(intervals[n]))
    {
      continue;
    }
    const auto r = range(intervals[n]);
    if (static_cast<double>(r.second - r.first) > LongBuckets)
    {
      this->Long.push_back(n);
      continue;
    }
    for (size_t b = r.first; b <= r.second; ++b)
    {
      ++counts[b + 1];
    }
  }
  for (size_t b = 0; b < buckets; ++b)
  {
    counts[b + 1] += counts[b];
  }
  this->Offsets = counts;
  this->Items.resize(counts[buckets]);
  for (uint32_t n = 0; n < intervals.size(); ++n)
  {
    if (!valid(intervals[n]))
    {
      continue;
    }
    const auto r = range(intervals[n]);
    if (static_cast<double>(r.second - r.first) > LongBuckets)
    {
      continue;
    }
    for (size_t b = r.first; b <= r.second; ++b)
    {
      this->Items[counts[b]++] = n;
    }
  }
}
} // namespace morphnode
