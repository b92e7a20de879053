// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Timeline.h
/// @brief Precomputed time structures that make sampling at any t cheap and allocation-free:
/// an index of the intervals alive at t, and piecewise smoothstep fades between states.

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace morphnode
{
/// Which of a set of intervals [begin, end] contain t, in O(1 + number found): the time
/// axis is cut into buckets, each listing the intervals overlapping it. Intervals longer
/// than many buckets are kept apart in a short list that every query scans, so that a few
/// long intervals cannot blow the index up.
class IntervalIndex
{
public:
  /// Intervals with end < begin or non-finite ends are never found.
  void Build(const std::vector<std::pair<double, double>>& intervals);
  /// Calls f(i) for every interval i that may contain t (a superset of those that do).
  template <typename F>
  void ForEachCandidate(double t, F&& f) const
  {
    for (uint32_t i : this->Long)
    {
      f(i);
    }
    if (this->Offsets.size() < 2 || !(t >= this->Origin))
    {
      return;
    }
    const double b = (t - this->Origin) * this->InverseWidth;
    if (!(b < static_cast<double>(this->Offsets.size() - 1)))
    {
      return;
    }
    const size_t bucket = static_cast<size_t>(b);
    for (uint32_t k = this->Offsets[bucket]; k < this->Offsets[bucket + 1]; ++k)
    {
      f(this->Items[k]);
    }
  }

private:
  double Origin = 0.0;
  double InverseWidth = 1.0;
  std::vector<uint32_t> Offsets; // bucket b lists Items[Offsets[b] .. Offsets[b + 1])
  std::vector<uint32_t> Items;
  std::vector<uint32_t> Long;
};

/// A state of N values that changes by smoothstep fades: each key fades from whatever the
/// state is at its time to its target, so an interrupted fade never jumps.
template <int N>
class FadeTrack
{
public:
  using State = std::array<double, N>;

  explicit FadeTrack(const State& initial = State{})
    : Initial(initial)
  {
  }
  /// Keys may come in any order; among keys at the same time the one added last wins.
  void Add(double time, double fade, const State& target)
  {
    this->Keys.push_back({ time, fade, target, target, this->NextOrder++ });
  }
  void Clear() { this->Keys.clear(); }
  /// Sorts the keys and computes where each fade starts from. Call after the last Add().
  void Finalize()
  {
    std::sort(this->Keys.begin(), this->Keys.end(),
      [](const Key& a, const Key& b)
      { return a.Time < b.Time || (a.Time == b.Time && a.Order < b.Order); });
    for (size_t i = 0; i < this->Keys.size(); ++i)
    {
      this->Keys[i].From =
        i == 0 ? this->Initial : this->Blend(this->Keys[i - 1], this->Keys[i].Time);
    }
  }
  size_t GetNumberOfKeys() const { return this->Keys.size(); }

  // ---- streaming use (LiveBehavior): keys added in time order, the past forgotten ----
  /// Removes the keys at or after `time` (a new command replaces what was planned from
  /// then on, e.g. the return of a timed look). Call Finalize() before evaluating.
  void DropFrom(double time)
  {
    this->Keys.erase(std::remove_if(this->Keys.begin(), this->Keys.end(),
                       [time](const Key& k) { return k.Time >= time; }),
      this->Keys.end());
  }
  /// Forgets the keys that no longer matter at `t` or later: everything before the last
  /// key at or before t; that key too once its fade is over (it becomes the initial
  /// state). Evaluate(t') for t' >= t is unchanged. Needs a finalized track.
  void ForgetBefore(double t)
  {
    auto it = std::upper_bound(
      this->Keys.begin(), this->Keys.end(), t, [](double v, const Key& k) { return v < k.Time; });
    if (it == this->Keys.begin())
    {
      return;
    }
    --it; // the last key at or before t
    if (!(it->Fade > 0.0) || t >= it->Time + it->Fade)
    {
      this->Initial = it->To;
      this->Keys.erase(this->Keys.begin(), it + 1);
    }
    else
    {
      this->Initial = it->From;
      this->Keys.erase(this->Keys.begin(), it);
    }
  }

  void Evaluate(double t, double* out) const
  {
    auto it = std::upper_bound(
      this->Keys.begin(), this->Keys.end(), t, [](double v, const Key& k) { return v < k.Time; });
    const State s = it == this->Keys.begin() ? this->Initial : this->Blend(*(it - 1), t);
    std::copy(s.begin(), s.end(), out);
  }

private:
  struct Key
  {
    double Time;
    double Fade;
    State From;
    State To;
    size_t Order;
  };
  static State Blend(const Key& k, double t)
  {
    if (!(k.Fade > 0.0) || t >= k.Time + k.Fade)
    {
      return k.To;
    }
    double x = (t - k.Time) / k.Fade;
    x = x < 0.0 ? 0.0 : x;
    const double a = x * x * (3.0 - 2.0 * x);
    State s;
    for (int i = 0; i < N; ++i)
    {
      s[i] = k.From[i] + a * (k.To[i] - k.From[i]);
    }
    return s;
  }

  State Initial;
  std::vector<Key> Keys;
  size_t NextOrder = 0;
};
} // namespace morphnode
