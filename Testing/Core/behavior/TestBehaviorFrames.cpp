// SPDX-License-Identifier: BSD-3-Clause
// The frames of a behaviour track (behavior/Frames.h): the one formula, the controller's
// SampleTrack() on exactly those frames, and its limits.
#include "BehaviorTestUtilities.h"

#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "behavior/Frames.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace morphnode;

TEST(BehaviorFrames, FromZeroToTheLastFrameAtOrBeforeTheEnd)
{
  EXPECT_EQ(NumberOfFrames(5.0, 30.0), 151u); // 0, 1/30, ..., 5
  EXPECT_EQ(NumberOfFrames(4.0, 25.0), 101u);
  EXPECT_EQ(NumberOfFrames(0.0, 30.0), 1u);        // t = 0 alone
  EXPECT_EQ(NumberOfFrames(1.0 / 60.0, 30.0), 1u); // the end falls between frames 0 and 1
  EXPECT_EQ(NumberOfFrames(1.05, 10.0), 11u);      // the last frame (1.0) before the end
  // 0.29 * 100 = 28.999999999999996 in doubles: still 30 frames, the last at 0.29 s.
  ASSERT_LT(0.29 * 100.0, 29.0);
  EXPECT_EQ(NumberOfFrames(0.29, 100.0), 30u);
  // 24 h at 1000 fps is the largest a controller allows; counting them is no problem.
  EXPECT_EQ(NumberOfFrames(86400.0, 1000.0), 86400001u);

  EXPECT_EQ(FrameTime(0, 30.0), 0.0);
  EXPECT_EQ(FrameTime(30, 30.0), 1.0);
  EXPECT_EQ(FrameTime(7, 25.0), 7.0 / 25.0);
  const std::vector<double> times = FrameTimes(2.0, 4.0);
  EXPECT_EQ(times, (std::vector<double>{ 0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0 }));
}

TEST(BehaviorFrames, BadRatesAndDurationsAreInputErrors)
{
  for (double fps : { 0.0, -30.0, std::nan(""), HUGE_VAL })
  {
    EXPECT_THROW(NumberOfFrames(1.0, fps), InputError) << fps;
  }
  for (double duration : { -1.0, std::nan(""), HUGE_VAL })
  {
    EXPECT_THROW(NumberOfFrames(duration, 30.0), InputError) << duration;
  }
  EXPECT_THROW(NumberOfFrames(1e300, 1000.0), InputError); // no overflow into size_t
  EXPECT_THROW(FrameTimes(86400.0, 1000.0), InputError);   // more than MaxTrackValues
}

TEST(BehaviorFrames, SampleTrackSamplesTheControllerAtItsFrames)
{
  BehaviorController b;
  b.SetSeed(4);
  b.SetFrameRate(24.0);
  b.Speak(behaviortest::MakeUtterance(1.0), 0.5);
  b.Gesture("nod", 1.0, 0.8, 0.7);
  b.SetMood("happy", 0.5, 0.2);
  EXPECT_THROW(b.SampleTrack(), InputError) << "sampled before Prepare()";
  b.Prepare();
  EXPECT_DOUBLE_EQ(b.GetEffectiveDuration(), 5.0);
  ASSERT_EQ(b.GetNumberOfFrames(), 121u);
  EXPECT_EQ(b.GetFrameTime(0), 0.0);
  EXPECT_EQ(b.GetFrameTime(12), 0.5);

  const WeightTrack track = b.SampleTrack();
  ASSERT_EQ(track.GetNumberOfFrames(), b.GetNumberOfFrames());
  EXPECT_EQ(track.GetChannels(), b.GetChannelNames());
  EXPECT_EQ(track.GetFrameRate(), 24.0);
  std::vector<double> row;
  double mouth = 0.0;
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    EXPECT_EQ(track.GetTime(f), b.GetFrameTime(f));
    b.Sample(b.GetFrameTime(f), row);
    for (size_t c = 0; c < row.size(); ++c)
    {
      ASSERT_EQ(track.GetValue(f, c), row[c]) << "frame " << f << ", " << b.GetChannelNames()[c];
    }
    mouth = std::max(mouth, track.GetValue(f, static_cast<size_t>(b.FindChannel("aa"))));
  }
  EXPECT_GT(mouth, 0.9) << "the utterance is in the track";

  // GenerateTrack() prepares after a change and gives the same as SampleTrack().
  b.SetDuration(2.0);
  EXPECT_THROW(b.SampleTrack(), InputError);
  const WeightTrack generated = b.GenerateTrack();
  ASSERT_EQ(generated.GetNumberOfFrames(), 49u);
  const WeightTrack sampled = b.SampleTrack();
  for (size_t f = 0; f < generated.GetNumberOfFrames(); ++f)
  {
    for (size_t c = 0; c < generated.GetNumberOfChannels(); ++c)
    {
      ASSERT_EQ(generated.GetValue(f, c), sampled.GetValue(f, c));
    }
  }
}

TEST(BehaviorFrames, ATrackTooLargeForMemoryIsAnInputErrorNotAnAllocation)
{
  BehaviorController b;
  b.SetFrameRate(1000.0);
  b.SetDuration(86400.0); // 86.4 million frames x 15 channels
  b.Prepare();
  EXPECT_EQ(b.GetNumberOfFrames(), 86400001u);
  try
  {
    b.SampleTrack();
    FAIL() << "a track of 1.3 billion values was sampled";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("one time at a time"), std::string::npos) << e.what();
  }
  // Sampling single times still works.
  std::vector<double> row;
  b.Sample(43200.5, row);
  EXPECT_EQ(row.size(), b.GetNumberOfChannels());
}
