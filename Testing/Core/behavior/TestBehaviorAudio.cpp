// SPDX-License-Identifier: BSD-3-Clause
// The behaviour's sound (behavior/BehaviorAudio.h): utterances mixed at their start times on
// the track's time axis, summed and clipped, resampled to one rate, written as WAV.
#include "BehaviorTestUtilities.h"

#include "audio/AudioFile.h"
#include "base/Error.h"
#include "behavior/BehaviorAudio.h"
#include "behavior/BehaviorController.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
const std::string OutputDir = MORPHNODE_TEST_OUTPUT_DIR;

/// An utterance with `count` samples of `value` at `rate` (and the test visemes).
Utterance Sound(size_t count, int16_t value, int rate = 22050)
{
  Utterance u = behaviortest::MakeUtterance(0.1);
  u.Audio.assign(count, value);
  u.SampleRate = rate;
  u.Duration = static_cast<double>(count) / rate;
  return u;
}

std::vector<int16_t> Int16(const AudioBuffer& audio)
{
  return ToInt16Mono(audio);
}
} // namespace

TEST(BehaviorAudio, UtterancesAtTheirStartsSummedAndClipped)
{
  BehaviorController b;
  b.SetDuration(1.0);
  b.Speak(Sound(2205, 1000), 0.1);   // samples [2205, 4410)
  b.Speak(Sound(2205, -300), 0.15);  // samples [3307.5 -> 3308, 5513): overlaps the first
  b.Speak(Sound(100, 30000), 0.5);   // [11025, 11125)
  b.Speak(Sound(50, 10000), 0.5045); // [11124.225 -> 11124, 11174): 30000 + 10000 clips
  b.Speak(Sound(10, -30000), 0.6);
  b.Speak(Sound(10, -30000), 0.6); // -60000 clips to -32768
  b.Prepare();
  const AudioBuffer mix = MixBehaviorAudio(b);
  EXPECT_EQ(mix.SampleRate, 22050);
  EXPECT_EQ(mix.Channels, 1);
  ASSERT_EQ(mix.Samples.size(), 22050u) << "as long as the track (1 s)";
  const std::vector<int16_t> s = Int16(mix);
  EXPECT_EQ(s[0], 0);
  EXPECT_EQ(s[2204], 0);
  EXPECT_EQ(s[2205], 1000);
  EXPECT_EQ(s[3307], 1000);
  EXPECT_EQ(s[3308], 700);
  EXPECT_EQ(s[4409], 700);
  EXPECT_EQ(s[4410], -300);
  EXPECT_EQ(s[5512], -300);
  EXPECT_EQ(s[5513], 0);
  EXPECT_EQ(s[11025], 30000);
  EXPECT_EQ(s[11123], 30000);
  EXPECT_EQ(s[11124], 32767);
  EXPECT_EQ(s[11125], 10000);
  EXPECT_EQ(s[11173], 10000);
  EXPECT_EQ(s[11174], 0);
  EXPECT_EQ(s[13230], -32768);
  EXPECT_EQ(s[13239], -32768);
  EXPECT_EQ(s[13240], 0);
  // The mix itself keeps the sums (the clipping happens when converting to 16 bits).
  EXPECT_NEAR(mix.Samples[11124] * 32768.0, 40000.0, 1e-3);
}

TEST(BehaviorAudio, LongerThanTheTrackWhenTheSoundIsAndSilentWithoutSound)
{
  BehaviorController b;
  b.SetDuration(1.0);
  b.Prepare();
  AudioBuffer mix = MixBehaviorAudio(b);
  EXPECT_EQ(mix.SampleRate, DefaultMixSampleRate);
  ASSERT_EQ(mix.Samples.size(), 22050u);
  for (float v : mix.Samples)
  {
    ASSERT_EQ(v, 0.0f);
  }
  // An utterance without audio (e.g. from a .pho file) adds nothing.
  b.Speak(behaviortest::MakeUtterance(0.5), 0.2);
  b.Prepare();
  EXPECT_EQ(MixBehaviorAudio(b).Samples.size(), 22050u);

  // Sound past the end of the track lengthens the mix.
  b.Speak(Sound(22050, 5), 0.5);
  b.Prepare();
  EXPECT_GE(b.GetEffectiveDuration(), 1.0);
  mix = MixBehaviorAudio(b);
  const double end = std::max(b.GetEffectiveDuration(), 1.5);
  EXPECT_EQ(mix.Samples.size(), static_cast<size_t>(std::ceil(end * 22050 - 1e-9)));
  EXPECT_EQ(Int16(mix)[static_cast<size_t>(1.5 * 22050) - 1], 5);

  // Not prepared, or a bad minimum: InputError.
  b.Gesture("nod", 1.0);
  EXPECT_THROW(MixBehaviorAudio(b), InputError);
  EXPECT_THROW(MixUtteranceAudio({}, -1.0), InputError);
  EXPECT_THROW(MixUtteranceAudio({}, std::nan("")), InputError);
  EXPECT_THROW(MixUtteranceAudio({}, 1e9), InputError); // more than a WAV file holds
  EXPECT_EQ(MixUtteranceAudio({}, 0.0).Samples.size(), 0u);
}

TEST(BehaviorAudio, AnUtteranceAtAnotherRateIsResampledToTheHighest)
{
  BehaviorController b;
  b.SetDuration(1.0);
  b.Speak(Sound(11025, 8000, 11025), 0.0); // 1 s at 11025 Hz
  b.Speak(Sound(4410, 100, 44100), 0.5);   // 0.1 s at 44100 Hz: the mix's rate
  b.Prepare();
  const AudioBuffer mix = MixBehaviorAudio(b);
  EXPECT_EQ(mix.SampleRate, 44100);
  ASSERT_EQ(mix.Samples.size(), 44100u);
  const std::vector<int16_t> s = Int16(mix);
  // The constant 11025 Hz signal stays constant after resampling (away from its edges).
  for (size_t i : { 1000u, 10000u, 20000u, 30000u, 40000u })
  {
    const int expected = 8000 + (i >= 22050 && i < 22050 + 4410 ? 100 : 0);
    EXPECT_NEAR(s[i], expected, 40) << "sample " << i;
  }
}

TEST(BehaviorAudio, WritesAWavFileOnTheTrackTimeAxis)
{
  BehaviorController b;
  b.SetDuration(0.5);
  b.Speak(Sound(441, 1234), 0.25);
  b.Prepare();
  const std::string path = OutputDir + "/TestBehaviorAudio.wav";
  WriteBehaviorAudio(path, b);
  const AudioBuffer back = ReadAudioFile(path);
  EXPECT_EQ(back.SampleRate, 22050);
  EXPECT_EQ(back.Channels, 1);
  const std::vector<int16_t> s = ToInt16Mono(back);
  ASSERT_EQ(s.size(), 11025u);
  EXPECT_EQ(s[5512], 0);
  EXPECT_EQ(s[5513], 1234); // round(0.25 * 22050) = 5513 (5512.5 rounds up)
  EXPECT_EQ(s[5953], 1234);
  EXPECT_EQ(s[5954], 0);
  EXPECT_THROW(WriteBehaviorAudio("/nonexistent/folder/x.wav", b), InputError);
}
