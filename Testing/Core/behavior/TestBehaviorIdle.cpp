// SPDX-License-Identifier: BSD-3-Clause
// Idle behaviour: reproducibility, blink statistics, lid curve, saccade law, head motion.
#include "BehaviorTestUtilities.h"

#include "behavior/BehaviorController.h"
#include "behavior/IdleSchedule.h"
#include "behavior/Random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace morphnode;
using behaviortest::MakeUtterance;

namespace
{
WeightTrack Scene(uint64_t seed)
{
  BehaviorController b;
  b.SetSeed(seed);
  b.SetDuration(30.0);
  b.SetMood("happy", 0.5, 1.0);
  b.Gesture("nod", 4.0, 0.8, 0.7);
  b.LookAt(15.0, -5.0, 6.0, 2.0);
  b.Speak(MakeUtterance(2.0), 10.0);
  return b.GenerateTrack();
}

/// Blinks seen in the lid channel: upward crossings of 0.5.
int CountBlinks(const WeightTrack& track)
{
  const int lid = track.FindChannel("EyesClosed");
  int count = 0;
  for (size_t f = 1; f < track.GetNumberOfFrames(); ++f)
  {
    count += track.GetValue(f - 1, lid) < 0.5 && track.GetValue(f, lid) >= 0.5;
  }
  return count;
}

/// Kolmogorov-Smirnov statistic of the log inter-blink intervals against the normal law
/// N(mu, sigma) that log-normal intervals with the given mean and shape must follow.
double LogIntervalKolmogorovSmirnov(
  const std::vector<BlinkEvent>& blinks, double meanInterval, double sigma)
{
  std::vector<double> x;
  for (size_t i = 1; i < blinks.size(); ++i)
  {
    x.push_back(std::log(blinks[i].Start - blinks[i - 1].Start));
  }
  std::sort(x.begin(), x.end());
  const double mu = std::log(meanInterval) - 0.5 * sigma * sigma;
  const double n = static_cast<double>(x.size());
  double d = 0.0;
  for (size_t i = 0; i < x.size(); ++i)
  {
    const double cdf = 0.5 * std::erfc(-(x[i] - mu) / (sigma * std::sqrt(2.0)));
    d = std::max({ d, std::abs(cdf - i / n), std::abs((i + 1) / n - cdf) });
  }
  return d;
}
} // namespace

TEST(BehaviorIdle, SameSeedGivesAnIdenticalTrack)
{
  const WeightTrack a = Scene(42), b = Scene(42);
  ASSERT_EQ(a.GetChannels(), b.GetChannels());
  ASSERT_EQ(a.GetNumberOfFrames(), b.GetNumberOfFrames());
  for (size_t f = 0; f < a.GetNumberOfFrames(); ++f)
  {
    for (size_t c = 0; c < a.GetNumberOfChannels(); ++c)
    {
      ASSERT_EQ(a.GetValue(f, c), b.GetValue(f, c)) << "frame " << f << " channel " << c;
    }
  }
}

TEST(BehaviorIdle, AnotherSeedGivesAnotherTrack)
{
  const WeightTrack a = Scene(42), b = Scene(43);
  ASSERT_EQ(a.GetNumberOfFrames(), b.GetNumberOfFrames());
  // The idle channels differ; the commanded ones (the visemes) do not.
  for (const char* name : { "EyesClosed", "HeadYaw", "EyeYaw", "EyePitch" })
  {
    const int c = a.FindChannel(name);
    double difference = 0.0;
    for (size_t f = 0; f < a.GetNumberOfFrames(); ++f)
    {
      difference += std::abs(a.GetValue(f, c) - b.GetValue(f, c));
    }
    EXPECT_GT(difference, 1.0) << name;
  }
  const int aa = a.FindChannel("aa");
  for (size_t f = 0; f < a.GetNumberOfFrames(); ++f)
  {
    ASSERT_EQ(a.GetValue(f, aa), b.GetValue(f, aa));
  }
}

TEST(BehaviorIdle, BlinkRateAtRestOverTenMinutes)
{
  for (uint64_t seed : { 1u, 2u, 3u })
  {
    BehaviorController b;
    b.SetSeed(seed);
    b.SetDuration(600.0);
    b.SetFrameRate(60.0);
    const WeightTrack track = b.GenerateTrack();
    const double perMinute = CountBlinks(track) / 10.0;
    EXPECT_GE(perMinute, 14.0) << "seed " << seed; // published ~17/min at rest
    EXPECT_LE(perMinute, 20.0) << "seed " << seed;
    EXPECT_EQ(CountBlinks(track), static_cast<int>(b.GetIdleSchedule().Blinks.size()));
  }
}

// The intervals' shape, not only their spread: at rest, log intervals must follow
// N(log(mean) - sigma^2 / 2, sigma). Uniform or exponential intervals of the same mean
// (which a coefficient-of-variation check lets through) give D > 0.15 here.
TEST(BehaviorIdle, BlinkIntervalsAreLogNormal)
{
  for (uint64_t seed : { 1u, 2u, 3u })
  {
    BehaviorController b;
    b.SetSeed(seed);
    b.SetDuration(3600.0); // an hour at rest: ~1000 intervals
    b.Prepare();
    const BehaviorParameters& p = b.GetParameters();
    const auto& blinks = b.GetIdleSchedule().Blinks;
    ASSERT_GT(blinks.size(), 800u) << "seed " << seed;
    const double d =
      LogIntervalKolmogorovSmirnov(blinks, 60.0 / p.BlinkRateRest, p.BlinkIntervalSigma);
    // KS critical value at alpha = 0.001: 1.95 / sqrt(n).
    EXPECT_LT(d, 1.95 / std::sqrt(static_cast<double>(blinks.size() - 1)))
      << "seed " << seed << ": log blink intervals are not N(mu, " << p.BlinkIntervalSigma << ")";
  }
}

TEST(BehaviorIdle, BlinkRateWhileSpeakingOverTenMinutes)
{
  for (uint64_t seed : { 1u, 2u, 3u })
  {
    BehaviorController b;
    b.SetSeed(seed);
    b.SetDuration(600.0);
    b.SetFrameRate(60.0);
    Utterance talk = MakeUtterance(1.0);
    talk.Duration = 600.0; // ten minutes of conversation
    b.Speak(talk, 0.0);
    const WeightTrack track = b.GenerateTrack();
    const double perMinute = CountBlinks(track) / 10.0;
    EXPECT_GE(perMinute, 22.0) << "seed " << seed; // published ~26/min in conversation
    EXPECT_LE(perMinute, 30.0) << "seed " << seed;
  }
}

TEST(BehaviorIdle, BlinkRateFollowsSpeechWithinOneTrack)
{
  BehaviorController b;
  b.SetSeed(9);
  b.SetDuration(1200.0);
  Utterance talk = MakeUtterance(1.0);
  talk.Duration = 600.0;
  b.Speak(talk, 600.0); // rest for 10 minutes, then speak for 10
  b.Prepare();
  int rest = 0, speaking = 0;
  for (const BlinkEvent& e : b.GetIdleSchedule().Blinks)
  {
    (e.Start < 600.0 ? rest : speaking)++;
  }
  EXPECT_GT(speaking, rest * 1.25);
}

TEST(BehaviorIdle, LidClosesFasterThanItOpens)
{
  BehaviorController b;
  b.SetSeed(5);
  b.SetDuration(20.0);
  b.SetFrameRate(1000.0);
  const WeightTrack track = b.GenerateTrack();
  const int lid = track.FindChannel("EyesClosed");
  const auto& blinks = b.GetIdleSchedule().Blinks;
  ASSERT_GE(blinks.size(), 2u);
  for (const BlinkEvent& blink : blinks)
  {
    const size_t start = static_cast<size_t>(std::ceil(blink.Start * 1000.0));
    if (start + 400 >= track.GetNumberOfFrames())
    {
      continue;
    }
    size_t peak = start, rise = 0, fall = 0;
    for (size_t f = start; f < start + 400; ++f)
    {
      peak = track.GetValue(f, lid) > track.GetValue(peak, lid) ? f : peak;
    }
    EXPECT_GT(track.GetValue(peak, lid), 0.85);
    for (size_t f = start; f <= peak && track.GetValue(f, lid) < 0.9 * track.GetValue(peak, lid);
         ++f)
    {
      ++rise;
    }
    for (size_t f = peak; f < start + 400 && track.GetValue(f, lid) > 0.05; ++f)
    {
      ++fall;
    }
    EXPECT_LT(rise, 110u); // closing ~100 ms
    EXPECT_GT(fall, rise); // opening slower
    EXPECT_LT(fall + rise, 400u);
  }
}

TEST(BehaviorIdle, BlinkCurveShape)
{
  const BehaviorParameters p;
  EXPECT_EQ(BlinkLidCurve(p, -0.01), 0.0);
  EXPECT_NEAR(BlinkLidCurve(p, p.BlinkCloseTime), 1.0, 1e-12);
  EXPECT_EQ(BlinkLidCurve(p, BlinkLength(p)), 0.0);
  // Opening: monotone down.
  double previous = 1.0;
  for (double t = p.BlinkCloseTime + p.BlinkClosedTime; t < BlinkLength(p); t += 0.005)
  {
    const double v = BlinkLidCurve(p, t);
    EXPECT_LE(v, previous + 1e-12);
    previous = v;
  }
}

TEST(BehaviorIdle, SaccadesFollowLeeEtAl)
{
  EXPECT_NEAR(SaccadeAmplitudeLaw(15.0), -6.9 * std::log(15.0 / 15.7), 1e-12);
  EXPECT_NEAR(SaccadeAmplitudeLaw(15.7), 0.0, 1e-12);
  BehaviorParameters p;
  p.SaccadeRange = 90.0; // let every drawn amplitude through
  const IdleSchedule s = IdleSchedule::Generate(p, 11, 600.0, {});
  ASSERT_GT(s.Saccades.size(), 200u);
  double meanAmplitude = 0.0;
  for (size_t i = 0; i < s.Saccades.size(); ++i)
  {
    const SaccadeEvent& e = s.Saccades[i];
    EXPECT_NEAR(e.Duration, 0.025 + 0.0024 * e.Amplitude, 1e-12);
    EXPECT_LE(e.Amplitude, 15.0 + 1e-9);
    EXPECT_GE(e.Amplitude, -6.9 * std::log(15.0 / 15.7) - 1e-9);
    if (i > 0)
    {
      const SaccadeEvent& prev = s.Saccades[i - 1];
      EXPECT_GE(e.Start - (prev.Start + prev.Duration), p.FixationMin - 1e-9);
      EXPECT_DOUBLE_EQ(e.FromYaw, prev.ToYaw);
    }
    meanAmplitude += e.Amplitude / s.Saccades.size();
  }
  // E[min(-6.9 ln(P/15.7), 15)] for P ~ U(0, 15): 6.9 (1 + ln(15.7/15)) minus the capped
  // tail P(A > 15) x 6.9 = 0.119 x 6.9, about 6.4 degrees.
  EXPECT_NEAR(meanAmplitude, 6.4, 0.5);
}

TEST(BehaviorIdle, IdleGazeStaysNearTheTarget)
{
  BehaviorController b;
  b.SetSeed(3);
  b.SetDuration(120.0);
  const WeightTrack track = b.GenerateTrack();
  const int yaw = track.FindChannel("EyeYaw"), pitch = track.FindChannel("EyePitch");
  double moved = 0.0;
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    // Saccade range 10 deg plus the head micro-motion the eyes compensate.
    EXPECT_LE(std::abs(track.GetValue(f, yaw)), 10.0 + 2.0 + 1e-9);
    EXPECT_LE(std::abs(track.GetValue(f, pitch)), 6.0 + 1.5 + 1e-9);
    moved = std::max(moved, std::abs(track.GetValue(f, yaw)));
  }
  EXPECT_GT(moved, 3.0);
}

TEST(BehaviorIdle, HeadMicroMotionIsSmallSmoothAndAlive)
{
  BehaviorController b;
  b.SetSeed(8);
  b.SetDuration(120.0);
  b.SetFrameRate(60.0);
  const WeightTrack track = b.GenerateTrack();
  for (const char* name : { "HeadYaw", "HeadPitch", "HeadRoll" })
  {
    const int c = track.FindChannel(name);
    double lo = 1e9, hi = -1e9, jump = 0.0;
    for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
    {
      lo = std::min(lo, track.GetValue(f, c));
      hi = std::max(hi, track.GetValue(f, c));
      if (f > 0)
      {
        jump = std::max(jump, std::abs(track.GetValue(f, c) - track.GetValue(f - 1, c)));
      }
    }
    EXPECT_LE(std::max(-lo, hi), 2.0 + 1e-9) << name; // a few degrees at most
    EXPECT_GT(hi - lo, 0.5) << name;                  // but moving
    EXPECT_LT(jump, 0.1) << name;                     // degrees per frame: smooth
  }
}

TEST(BehaviorIdle, OccasionalSmiles)
{
  BehaviorController b;
  b.SetSeed(4);
  b.SetDuration(600.0);
  b.SetFrameRate(10.0);
  const WeightTrack track = b.GenerateTrack();
  const int smile = track.FindChannel("MouthSmile");
  double peak = 0.0, mean = 0.0;
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    peak = std::max(peak, track.GetValue(f, smile));
    mean += track.GetValue(f, smile) / track.GetNumberOfFrames();
  }
  EXPECT_GE(b.GetIdleSchedule().Smiles.size(), 10u);
  EXPECT_GT(peak, 0.15);
  EXPECT_LT(mean, 0.1); // occasional, not a grin
}

TEST(BehaviorIdle, RandomIsReproducibleAndStreamsDiffer)
{
  BehaviorRandom a(7, 1), b(7, 1), c(7, 2);
  bool differs = false;
  for (int i = 0; i < 100; ++i)
  {
    const uint64_t x = a.Next();
    EXPECT_EQ(x, b.Next());
    differs = differs || x != c.Next();
  }
  EXPECT_TRUE(differs);
  BehaviorRandom r(1);
  double mean = 0.0;
  for (int i = 0; i < 20000; ++i)
  {
    mean += r.LogNormalWithMean(3.0, 0.5) / 20000.0;
  }
  EXPECT_NEAR(mean, 3.0, 0.06);
}
