// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/IdleSchedule.h"

#include "base/Error.h"
#include "behavior/Random.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace morphnode
{
namespace
{
constexpr double TwoPi = 6.283185307179586;

// Random streams of one seed: one per behaviour, so they never disturb each other.
enum Stream : uint64_t
{
  BlinkStream = 1,
  SaccadeStream = 2,
  SmileStream = 3,
  HeadStream = 4
};

std::vector<std::pair<double, double>> MergeIntervals(std::vector<std::pair<double, double>> in)
{
  in.erase(std::remove_if(in.begin(), in.end(),
             [](const std::pair<double, double>& i) { return !(i.second > i.first); }),
    in.end());
  std::sort(in.begin(), in.end());
  std::vector<std::pair<double, double>> out;
  for (const auto& i : in)
  {
    if (!out.empty() && i.first <= out.back().second)
    {
      out.back().second = std::max(out.back().second, i.second);
    }
    else
    {
      out.push_back(i);
    }
  }
  return out;
}

/// Advances real time t by `clock` seconds of the rest-rate blink clock, which runs
/// `factor` times faster inside the speaking intervals. `k` is the first interval that
/// ends after t (kept between calls since t only grows).
double AdvanceBlinkClock(double t, double clock, double factor,
  const std::vector<std::pair<double, double>>& speaking, size_t& k)
{
  const double inf = std::numeric_limits<double>::infinity();
  while (clock > 0.0)
  {
    while (k < speaking.size() && speaking[k].second <= t)
    {
      ++k;
    }
    if (k < speaking.size() && t >= speaking[k].first)
    {
      const double capacity = (speaking[k].second - t) * factor;
      if (clock <= capacity)
      {
        return t + clock / factor;
      }
      clock -= capacity;
      t = speaking[k].second;
    }
    else
    {
      const double next = k < speaking.size() ? speaking[k].first : inf;
      if (clock <= next - t)
      {
        return t + clock;
      }
      clock -= next - t;
      t = next;
    }
  }
  return t;
}
} // namespace

void HeadMicroMotion::Evaluate(double t, double* yawPitchRoll) const
{
  for (int axis = 0; axis < 3; ++axis)
  {
    double v = 0.0;
    for (int i = axis * 3; i < axis * 3 + 3; ++i)
    {
      v += this->Amplitude[i] * std::sin(this->Frequency[i] * t + this->Phase[i]);
    }
    yawPitchRoll[axis] = v;
  }
}

double SaccadeAmplitudeLaw(double p)
{
  return -6.9 * std::log(p / 15.7);
}

double SaccadeDuration(const BehaviorParameters& parameters, double amplitude)
{
  return parameters.SaccadeBase + parameters.SaccadePerDegree * amplitude;
}

double BlinkLength(const BehaviorParameters& p)
{
  return p.BlinkCloseTime + p.BlinkClosedTime + p.BlinkOpenTime;
}

double BlinkLidCurve(const BehaviorParameters& p, double t)
{
  if (!(t > 0.0))
  {
    return 0.0;
  }
  if (t < p.BlinkCloseTime)
  {
    return Smoothstep(t / p.BlinkCloseTime);
  }
  t -= p.BlinkCloseTime;
  if (t <= p.BlinkClosedTime)
  {
    return 1.0;
  }
  t -= p.BlinkClosedTime;
  if (t >= p.BlinkOpenTime)
  {
    return 0.0;
  }
  // Ease-out: the lid leaves fast and creeps the last part, as measured lids do.
  const double u = 1.0 - t / p.BlinkOpenTime;
  return u * u;
}

BlinkTrain::BlinkTrain(const BehaviorParameters& p, uint64_t seed,
  const std::vector<std::pair<double, double>>& speaking)
  : Parameters(p)
  , Random(seed, BlinkStream)
  , Speaking(MergeIntervals(speaking))
{
  if (!(p.BlinkRateRest > 0.0) || !(p.BlinkRateSpeaking > 0.0))
  {
    throw InputError("blink rates must be > 0");
  }
  // A random phase for the first blink: no blink pile-up at t = 0 for every seed.
  this->Time = AdvanceBlinkClock(0.0, this->Random.Uniform() * (60.0 / p.BlinkRateRest),
    p.BlinkRateSpeaking / p.BlinkRateRest, this->Speaking, this->Interval);
}

BlinkEvent BlinkTrain::Next()
{
  const BehaviorParameters& p = this->Parameters;
  const BlinkEvent blink{ this->Time, this->Random.Uniform(0.9, 1.0) };
  const double clock = this->Random.LogNormalWithMean(60.0 / p.BlinkRateRest, p.BlinkIntervalSigma);
  const double minInterval = std::max(p.BlinkMinInterval, BlinkLength(p));
  this->Time = std::max(AdvanceBlinkClock(this->Time, clock, p.BlinkRateSpeaking / p.BlinkRateRest,
                          this->Speaking, this->Interval),
    this->Time + minInterval);
  return blink;
}

SaccadeTrain::SaccadeTrain(const BehaviorParameters& p, uint64_t seed)
  : Random(seed, SaccadeStream)
{
  if (!(p.FixationMean > 0.0))
  {
    throw InputError("the fixation mean must be > 0");
  }
  this->Time = this->Random.Uniform() * p.FixationMean;
}

SaccadeEvent SaccadeTrain::Next(const BehaviorParameters& p)
{
  BehaviorRandom& rng = this->Random;
  const double range = p.SaccadeRange;
  const double yaw = this->Yaw, pitch = this->Pitch;
  const double amplitude =
    std::min(SaccadeAmplitudeLaw(15.0 * rng.UniformOpen()), p.SaccadeMaxAmplitude);
  const double angle = rng.Uniform() * TwoPi;
  double dy = std::cos(angle), dp = std::sin(angle);
  auto outside = [&](double y, double q) { return std::hypot(y, q / 0.6) > range; };
  if (outside(yaw + amplitude * dy, pitch + amplitude * dp))
  {
    dy = -dy, dp = -dp; // the other way is usually back toward the target
  }
  double toYaw = yaw + amplitude * dy, toPitch = pitch + amplitude * dp;
  const double r = std::hypot(toYaw, toPitch / 0.6);
  if (r > range)
  {
    toYaw *= range / r;
    toPitch *= range / r;
  }
  SaccadeEvent e;
  e.Start = this->Time;
  e.Amplitude = std::hypot(toYaw - yaw, toPitch - pitch);
  e.Duration = SaccadeDuration(p, e.Amplitude);
  e.FromYaw = yaw, e.FromPitch = pitch, e.ToYaw = toYaw, e.ToPitch = toPitch;
  this->Yaw = toYaw, this->Pitch = toPitch;
  this->Time +=
    e.Duration + std::max(p.FixationMin, rng.LogNormalWithMean(p.FixationMean, p.FixationSigma));
  return e;
}

SmileTrain::SmileTrain(const BehaviorParameters& p, uint64_t seed)
  : Parameters(p)
  , Random(seed, SmileStream)
{
  this->Time = p.IdleSmileInterval > 0.0 && p.IdleSmileIntensity > 0.0
    ? this->Random.Exponential(p.IdleSmileInterval)
    : std::numeric_limits<double>::infinity();
}

IdleSmileEvent SmileTrain::Next()
{
  const BehaviorParameters& p = this->Parameters;
  IdleSmileEvent e;
  e.Start = this->Time;
  e.Duration = this->Random.Uniform(1.5, 3.5);
  e.Intensity = p.IdleSmileIntensity * this->Random.Uniform(0.6, 1.0);
  this->Time += e.Duration + this->Random.Exponential(p.IdleSmileInterval);
  return e;
}

HeadMicroMotion MakeHeadMicroMotion(const BehaviorParameters& p, uint64_t seed)
{
  // Slow, middle and fast components per axis.
  HeadMicroMotion head;
  BehaviorRandom rng(seed, HeadStream);
  const double axisAmplitude[3] = { p.HeadYawAmplitude, p.HeadPitchAmplitude, p.HeadRollAmplitude };
  const double share[3] = { 0.55, 0.3, 0.15 };
  const double lowHz[3] = { 0.06, 0.15, 0.35 }, highHz[3] = { 0.12, 0.30, 0.60 };
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int c = 0; c < 3; ++c)
    {
      const int i = axis * 3 + c;
      head.Amplitude[i] = axisAmplitude[axis] * share[c];
      head.Frequency[i] = TwoPi * rng.Uniform(lowHz[c], highHz[c]);
      head.Phase[i] = TwoPi * rng.Uniform();
    }
  }
  return head;
}

IdleSchedule IdleSchedule::Generate(const BehaviorParameters& p, uint64_t seed, double horizon,
  const std::vector<std::pair<double, double>>& speaking)
{
  if (!(horizon >= 0.0) || !std::isfinite(horizon))
  {
    throw InputError("the idle behaviour needs a finite duration >= 0");
  }
  if (!(p.BlinkRateRest > 0.0) || !(p.BlinkRateSpeaking > 0.0) || !(p.FixationMean > 0.0))
  {
    throw InputError("blink rates and the fixation mean must be > 0");
  }
  IdleSchedule s;
  BlinkTrain blinks(p, seed, speaking);
  while (blinks.Peek() <= horizon)
  {
    s.Blinks.push_back(blinks.Next());
  }
  SaccadeTrain saccades(p, seed);
  while (saccades.Peek() <= horizon)
  {
    s.Saccades.push_back(saccades.Next(p));
  }
  SmileTrain smiles(p, seed);
  while (smiles.Peek() <= horizon)
  {
    s.Smiles.push_back(smiles.Next());
  }
  s.Head = MakeHeadMicroMotion(p, seed);
  return s;
}

void IdleSchedule::GazeOffset(double t, double& yaw, double& pitch) const
{
  auto it = std::upper_bound(this->Saccades.begin(), this->Saccades.end(), t,
    [](double v, const SaccadeEvent& e) { return v < e.Start; });
  if (it == this->Saccades.begin())
  {
    yaw = pitch = 0.0;
    return;
  }
  const SaccadeEvent& e = *(it - 1);
  const double a = e.Duration > 0.0 ? Smoothstep((t - e.Start) / e.Duration) : 1.0;
  yaw = e.FromYaw + a * (e.ToYaw - e.FromYaw);
  pitch = e.FromPitch + a * (e.ToPitch - e.FromPitch);
}
} // namespace morphnode
