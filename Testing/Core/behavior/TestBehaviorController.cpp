// SPDX-License-Identifier: BSD-3-Clause
// Commands on the blackboard: gestures, moods, looks, speech, and the blending rules.
#include "BehaviorTestUtilities.h"

#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "behavior/Random.h"
#include "behavior/Timeline.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace morphnode;
using behaviortest::MakeUtterance;
using behaviortest::QuietParameters;

namespace
{
double At(const BehaviorController& b, double t, const char* channel)
{
  std::vector<double> w;
  b.Sample(t, w);
  const int c = b.FindChannel(channel);
  EXPECT_GE(c, 0) << channel;
  return c < 0 ? 0.0 : w[c];
}

BehaviorController Base(uint64_t seed = 5)
{
  BehaviorController b;
  b.SetSeed(seed);
  b.SetDuration(10.0);
  b.SetFrameRate(100.0);
  return b;
}
} // namespace

TEST(BehaviorController, ChannelsAreFixedAndNamed)
{
  BehaviorController b = Base();
  b.Prepare();
  const std::vector<std::string> expected = { "EyesClosed", "BrowsUp", "BrowsFright", "BrowsAngry",
    "MouthSmile", "MouthSad", "LookUp", "LookDown", "LookLeft", "LookRight", "HeadYaw", "HeadPitch",
    "HeadRoll", "EyeYaw", "EyePitch" };
  EXPECT_EQ(b.GetChannelNames(), expected);
  EXPECT_EQ(BehaviorChannel::Names(), expected);
  b.Speak(MakeUtterance(), 1.0);
  b.Prepare();
  ASSERT_EQ(b.GetNumberOfChannels(), expected.size() + 4);
  EXPECT_EQ(b.GetChannelNames()[15], "sil");
  EXPECT_EQ(b.GetChannelNames()[17], "aa");
  // Sample() and GenerateTrack() agree.
  const WeightTrack track = b.GenerateTrack();
  std::vector<double> w;
  for (size_t f : { 0u, 137u, 555u })
  {
    b.Sample(track.GetTime(f), w);
    for (size_t c = 0; c < w.size(); ++c)
    {
      EXPECT_EQ(w[c], track.GetValue(f, c));
    }
  }
}

TEST(BehaviorController, SampleNeedsPrepareAfterEveryChange)
{
  BehaviorController b = Base();
  double out[64];
  EXPECT_THROW(b.Sample(0.0, out), InputError);
  b.Prepare();
  EXPECT_NO_THROW(b.Sample(0.0, out));
  b.Gesture("smile", 1.0);
  EXPECT_THROW(b.Sample(0.0, out), InputError);
}

TEST(BehaviorController, GesturesShowAtTheirTimesOnlyOnTheirChannels)
{
  struct Case
  {
    const char* Gesture;
    const char* Channel;
    double MinimumChange; // at the middle of the gesture
  };
  const Case cases[] = { { "smile", "MouthSmile", 0.7 }, { "sad", "MouthSad", 0.7 },
    { "raise_brows", "BrowsUp", 0.7 }, { "frown", "BrowsAngry", 0.7 },
    { "fright", "BrowsFright", 0.7 }, { "close_eyes", "EyesClosed", 0.5 },
    { "nod", "HeadPitch", 5.0 }, { "shake", "HeadYaw", 5.0 }, { "tilt", "HeadRoll", 5.0 } };
  for (const Case& k : cases)
  {
    BehaviorController plain = Base(), with = Base();
    with.Gesture(k.Gesture, 3.0, 2.0, 0.8);
    plain.Prepare();
    with.Prepare();
    const int c = with.FindChannel(k.Channel);
    double inside = 0.0;
    std::vector<double> a, b;
    for (double t = 0.0; t <= 10.0; t += 0.01)
    {
      plain.Sample(t, a);
      with.Sample(t, b);
      const double change = std::abs(b[c] - a[c]);
      // (A close-eyes also drops idle blinks that would overlap its start.)
      if (t < 3.0 - BlinkLength(with.GetParameters()) || t > 5.0)
      {
        ASSERT_LT(change, 1e-9) << k.Gesture << " at " << t;
      }
      else
      {
        inside = std::max(inside, change);
      }
      // Other semantic channels are untouched (except the eyes compensating head gestures).
      for (int o = BehaviorChannel::EyesClosed; o <= BehaviorChannel::MouthSad; ++o)
      {
        if (o != c)
        {
          ASSERT_NEAR(a[o], b[o], 1e-9) << k.Gesture << " moved channel " << o;
        }
      }
    }
    EXPECT_GT(inside, k.MinimumChange) << k.Gesture;
    const auto& g = with.GetGestures().back();
    EXPECT_DOUBLE_EQ(g.Sync.Start, 3.0);
    EXPECT_DOUBLE_EQ(g.Sync.End, 5.0);
    EXPECT_LE(g.Sync.Ready, g.Sync.Stroke);
    EXPECT_LE(g.Sync.Stroke, g.Sync.Relax);
  }
}

TEST(BehaviorController, GestureIntensityScalesAndEnvelopeIsSmooth)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.Gesture("smile", 2.0, 2.0, 0.5);
  b.Prepare();
  EXPECT_NEAR(At(b, 3.0, "MouthSmile"), 0.5, 1e-9);
  double previous = 0.0;
  for (double t = 1.9; t < 4.2; t += 0.01)
  {
    const double v = At(b, t, "MouthSmile");
    EXPECT_LT(std::abs(v - previous), 0.05) << t;
    previous = v;
  }
}

TEST(BehaviorController, UnknownNamesAreErrorsNamingThem)
{
  BehaviorController b;
  try
  {
    b.Gesture("wink", 0.0);
    FAIL();
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("wink"), std::string::npos);
  }
  try
  {
    b.SetMood("bored", 0.5);
    FAIL();
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("bored"), std::string::npos);
  }
  EXPECT_THROW(b.Gesture("smile", 0.0, 1.0, 1.5), InputError);
  EXPECT_THROW(b.Gesture("smile", -1.0), InputError);
  EXPECT_THROW(b.SetMood("happy", std::nan("")), InputError);
  EXPECT_THROW(b.LookAt(0.0, 120.0, 0.0), InputError);
  EXPECT_THROW(b.SetFrameRate(0.0), InputError);
  EXPECT_NO_THROW(b.Gesture("Raise-Brows", 0.0)); // spelling variants are one name
}

TEST(BehaviorController, MoodsShowAndFadeWithoutJumps)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.SetMood("happy", 0.8, 2.0);
  b.SetMood("sad", 1.0, 5.0, 1.0);
  b.SetMood("neutral", 0.0, 8.0);
  const WeightTrack track = b.GenerateTrack();
  const int smile = track.FindChannel("MouthSmile"), sad = track.FindChannel("MouthSad");
  EXPECT_EQ(track.Sample(1.9, smile), 0.0);
  EXPECT_NEAR(track.Sample(4.0, smile), 0.8 * 0.7, 1e-9);
  EXPECT_NEAR(track.Sample(7.0, sad), 0.7, 1e-9);
  EXPECT_NEAR(track.Sample(7.0, smile), 0.0, 1e-9);
  EXPECT_NEAR(track.Sample(9.5, sad), 0.0, 1e-9);
  EXPECT_LT(track.Sample(7.0, track.FindChannel("HeadPitch")), -3.0); // sad head hangs
  // Fades: at 100 fps no channel jumps more than 0.02 between frames.
  for (size_t f = 1; f < track.GetNumberOfFrames(); ++f)
  {
    for (int c : { smile, sad, track.FindChannel("BrowsFright") })
    {
      ASSERT_LT(std::abs(track.GetValue(f, c) - track.GetValue(f - 1, c)), 0.02) << "frame " << f;
    }
  }
}

TEST(BehaviorController, InterruptedMoodFadeDoesNotJump)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.SetMood("happy", 1.0, 1.0, 2.0);
  b.SetMood("neutral", 0.0, 2.0, 2.0); // halfway through the first fade
  const WeightTrack track = b.GenerateTrack();
  const int smile = track.FindChannel("MouthSmile");
  for (size_t f = 1; f < track.GetNumberOfFrames(); ++f)
  {
    ASSERT_LT(std::abs(track.GetValue(f, smile) - track.GetValue(f - 1, smile)), 0.01);
  }
  EXPECT_NEAR(track.Sample(2.0, smile), 0.35, 1e-9); // smoothstep(0.5) x 0.7
}

TEST(BehaviorController, ExplicitGestureOverridesMoodOnItsChannel)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.SetMood("angry", 1.0, 0.0, 0.5);
  b.Gesture("raise_brows", 3.0, 2.0, 0.6);
  b.Prepare();
  EXPECT_NEAR(At(b, 2.0, "BrowsAngry"), 0.8, 1e-9);
  EXPECT_NEAR(At(b, 4.0, "BrowsAngry"), 0.0, 1e-9);
  EXPECT_NEAR(At(b, 4.0, "BrowsUp"), 0.6, 1e-9);
  EXPECT_NEAR(At(b, 6.0, "BrowsAngry"), 0.8, 1e-9);
  EXPECT_GE(At(b, 4.0, "EyesClosed"), 0.1 - 1e-9); // the lids keep the mood
}

TEST(BehaviorController, BlinksNeverReopenClosedEyes)
{
  for (uint64_t seed = 1; seed <= 10; ++seed)
  {
    BehaviorController b = Base(seed);
    b.SetFrameRate(1000.0);
    b.Gesture("close_eyes", 2.0, 5.0, 1.0);
    b.Gesture("blink", 4.0); // an explicit blink inside merges
    Utterance u = MakeUtterance(3.0);
    u.Cues.push_back({ NonverbalCue::Kind::Blink, 1.0, 0.1, 1.0 }); // at 4.0
    b.Speak(u, 3.0);
    const WeightTrack track = b.GenerateTrack();
    const int lid = track.FindChannel("EyesClosed");
    const SyncPoints s = b.GetGestures().front().Sync;
    for (size_t f = 1; f < track.GetNumberOfFrames(); ++f)
    {
      const double t = track.GetTime(f);
      const double v = track.GetValue(f, lid), previous = track.GetValue(f - 1, lid);
      if (t >= s.Ready && t <= s.Relax)
      {
        ASSERT_NEAR(v, 1.0, 1e-12) << "seed " << seed << " t " << t;
      }
      if (t > s.Start && t < s.Ready)
      {
        ASSERT_GE(v, previous - 1e-12) << "closing, seed " << seed << " t " << t;
      }
      if (t > s.Relax && t <= s.End)
      {
        ASSERT_LE(v, previous + 1e-12) << "opening, seed " << seed << " t " << t;
      }
    }
    // Only the explicit blink remains in the closed span.
    int inside = 0;
    for (const BlinkEvent& e : b.GetIdleSchedule().Blinks)
    {
      inside += e.Start + BlinkLength(b.GetParameters()) > s.Start && e.Start < s.End;
    }
    EXPECT_EQ(inside, 1) << "seed " << seed;
  }
}

TEST(BehaviorController, UtteranceVisemesOnTheMouthChannelsAtTheirTimes)
{
  BehaviorController b = Base();
  b.Speak(MakeUtterance(1.0), 2.0);
  b.Prepare();
  EXPECT_EQ(At(b, 1.99, "aa"), 0.0);
  EXPECT_NEAR(At(b, 2.4, "aa"), 1.0, 1e-9);
  EXPECT_NEAR(At(b, 2.75, "PP"), 1.0, 1e-9);
  EXPECT_NEAR(At(b, 2.75, "aa"), 0.0, 1e-9);
  EXPECT_NEAR(At(b, 2.05, "sil"), 1.0, 1e-9);
  EXPECT_EQ(At(b, 3.01, "sil"), 0.0); // after the utterance nothing speaks
  // Interpolated between viseme frames.
  EXPECT_NEAR(At(b, 2.165, "aa"), 0.3, 1e-9);
  // Queued after the previous one.
  b.Speak(MakeUtterance(1.0));
  b.Prepare();
  EXPECT_DOUBLE_EQ(b.GetUtterances().back().Start, 3.0);
  EXPECT_NEAR(At(b, 3.4, "aa"), 1.0, 1e-9);
}

TEST(BehaviorController, SmileGivesWayToAnOpenVowel)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.SetMood("happy", 1.0, 0.0, 0.5);
  b.Speak(MakeUtterance(1.0), 2.0);
  b.Prepare();
  const double before = At(b, 1.5, "MouthSmile");
  const double during = At(b, 2.4, "MouthSmile"); // "aa" fully open
  EXPECT_NEAR(before, 0.7, 1e-9);
  EXPECT_NEAR(during, 0.7 * (1.0 - 0.7), 1e-9);
  EXPECT_NEAR(At(b, 2.05, "MouthSmile"), 0.7, 1e-9); // silence does not damp
  EXPECT_NEAR(At(b, 3.5, "MouthSmile"), 0.7, 1e-9);
}

TEST(BehaviorController, SpeechCuesDriveBrowsLidsAndHead)
{
  BehaviorController plain = Base(), with = Base();
  plain.SetParameters(QuietParameters());
  with.SetParameters(QuietParameters());
  Utterance u = MakeUtterance(3.0);
  u.Cues.push_back({ NonverbalCue::Kind::BrowRaise, 0.5, 0.4, 1.0 });
  u.Cues.push_back({ NonverbalCue::Kind::Nod, 1.5, 0.5, 1.0 });
  u.Cues.push_back({ NonverbalCue::Kind::Blink, 2.5, 0.1, 1.0 });
  with.Speak(u, 1.0);
  Utterance silent = MakeUtterance(3.0); // same speech, no cues: same blink rate
  plain.Speak(silent, 1.0);
  plain.Prepare();
  with.Prepare();
  EXPECT_GT(At(with, 1.7, "BrowsUp"), At(plain, 1.7, "BrowsUp") + 0.5);
  EXPECT_LT(At(with, 2.75, "HeadPitch"), At(plain, 2.75, "HeadPitch") - 4.0);
  EXPECT_GT(At(with, 3.5 + 0.11, "EyesClosed"), 0.95);
}

TEST(BehaviorController, LookAtMovesTheEyesFirstThenTheHead)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.LookAt(20.0, -10.0, 1.0, 2.0);
  b.Prepare();
  EXPECT_GT(At(b, 1.12, "EyeYaw"), 15.0); // eyes jump at saccade speed
  EXPECT_LT(At(b, 1.12, "HeadYaw"), 3.0);
  EXPECT_NEAR(At(b, 2.5, "HeadYaw"), 8.0, 1e-9); // head takes its 40 % share
  EXPECT_NEAR(At(b, 2.5, "EyeYaw"), 12.0, 1e-9); // eyes the rest
  EXPECT_NEAR(At(b, 2.5, "LookLeft"), 12.0 / 30.0, 1e-9);
  EXPECT_EQ(At(b, 2.5, "LookRight"), 0.0);
  EXPECT_NEAR(At(b, 2.5, "LookDown"), 6.0 / 25.0, 1e-9);
  EXPECT_NEAR(At(b, 4.0, "HeadYaw"), 0.0, 1e-9); // and back
  EXPECT_NEAR(At(b, 4.0, "EyeYaw"), 0.0, 1e-9);
}

TEST(BehaviorController, SayCallsTheSynthesizer)
{
  BehaviorController b = Base();
  EXPECT_THROW(b.Say("Hello"), InputError);
  std::string heard;
  b.SetSynthesizer(
    [&](const std::string& text)
    {
      heard = text;
      return MakeUtterance(1.5);
    });
  b.Say("Hello world", 0.5);
  b.Say("Again");
  EXPECT_EQ(heard, "Again");
  ASSERT_EQ(b.GetUtterances().size(), 2u);
  EXPECT_DOUBLE_EQ(b.GetUtterances()[1].Start, 2.0);
  b.Prepare();
  EXPECT_NEAR(At(b, 0.9, "aa"), 1.0, 1e-9);
}

TEST(BehaviorController, VisemeChannelMayNotShadowABehaviourChannel)
{
  Utterance u;
  u.Visemes = WeightTrack({ "sil", "EyesClosed" }, 100.0);
  u.Visemes.AppendFrame(std::vector<double>{ 1.0, 0.0 });
  BehaviorController b;
  EXPECT_THROW(b.Speak(u, 0.0), InputError);
}

TEST(BehaviorController, SampleRejectsANonFiniteTime)
{
  BehaviorController b = Base();
  b.Prepare();
  double out[64];
  EXPECT_THROW(b.Sample(std::nan(""), out), InputError);
  EXPECT_NO_THROW(b.Sample(1e6, out)); // beyond the schedule: valid, just calm
}

TEST(BehaviorTimeline, IntervalIndexFindsEveryContainingInterval)
{
  BehaviorRandom rng(3);
  std::vector<std::pair<double, double>> spans;
  for (int i = 0; i < 500; ++i)
  {
    const double start = rng.Uniform(0.0, 300.0);
    const double length = i % 50 == 0 ? rng.Uniform(50.0, 200.0) : rng.Uniform(0.0, 3.0);
    spans.emplace_back(start, start + length);
  }
  spans.emplace_back(5.0, 4.0); // reversed: never found
  IntervalIndex index;
  index.Build(spans);
  for (int k = 0; k < 5000; ++k)
  {
    const double t = rng.Uniform(-10.0, 510.0);
    std::vector<char> found(spans.size(), 0);
    index.ForEachCandidate(t, [&](uint32_t i) { found[i] = 1; });
    for (size_t i = 0; i < spans.size(); ++i)
    {
      if (t >= spans[i].first && t <= spans[i].second)
      {
        ASSERT_TRUE(found[i]) << "interval " << i << " at " << t;
      }
    }
    ASSERT_FALSE(found.back());
  }
}

TEST(BehaviorTimeline, FadeTrackFadesFromWhereItIs)
{
  FadeTrack<1> track({ 0.0 });
  track.Add(2.0, 1.0, { 0.0 }); // added first, same time as the next: loses
  track.Add(0.0, 2.0, { 1.0 });
  track.Add(2.0, 1.0, { -1.0 });
  track.Finalize();
  double v = 0.0;
  track.Evaluate(-1.0, &v);
  EXPECT_EQ(v, 0.0);
  track.Evaluate(1.0, &v);
  EXPECT_DOUBLE_EQ(v, 0.5);
  track.Evaluate(2.0, &v);
  EXPECT_DOUBLE_EQ(v, 1.0); // the interrupting fade starts where the first one is
  track.Evaluate(2.5, &v);
  EXPECT_DOUBLE_EQ(v, 0.0);
  track.Evaluate(9.0, &v);
  EXPECT_DOUBLE_EQ(v, -1.0);
}

TEST(BehaviorController, MoodsModulateIdleSmiles)
{
  auto peakSmile = [](const char* mood, double intensity)
  {
    BehaviorController b;
    b.SetSeed(4);
    b.SetDuration(300.0);
    b.SetFrameRate(10.0);
    b.SetMood(mood, intensity, 0.0, 0.0);
    const WeightTrack track = b.GenerateTrack();
    const int smile = track.FindChannel("MouthSmile");
    const double moodSmile = std::string(mood) == "happy" ? 0.7 * intensity : 0.0;
    double peak = 0.0;
    for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
    {
      peak = std::max(peak, track.GetValue(f, smile) - moodSmile); // the idle part
    }
    return peak;
  };
  const double neutral = peakSmile("neutral", 0.0);
  EXPECT_GT(neutral, 0.15);
  EXPECT_NEAR(peakSmile("sad", 1.0), 0.0, 1e-12);            // a sad face does not smile idly
  EXPECT_NEAR(peakSmile("happy", 0.2), 1.2 * neutral, 1e-9); // a happy one smiles broader
}

TEST(BehaviorController, RelaxCueSoftensTheBrows)
{
  BehaviorController b = Base();
  b.SetParameters(QuietParameters());
  b.SetMood("surprised", 1.0, 0.0, 0.0);
  Utterance u = MakeUtterance(3.0);
  u.Cues.push_back({ NonverbalCue::Kind::Relax, 1.0, 1.0, 1.0 });
  b.Speak(u, 1.0);
  b.Prepare();
  EXPECT_NEAR(At(b, 1.5, "BrowsUp"), 0.9, 1e-9);
  EXPECT_NEAR(At(b, 2.5, "BrowsUp"), 0.45, 1e-9); // halved in the pause
  EXPECT_NEAR(At(b, 3.5, "BrowsUp"), 0.9, 1e-9);
}

TEST(BehaviorParameters, EveryFigureByName)
{
  const auto& names = BehaviorParameterNames();
  ASSERT_EQ(names.size(), sizeof(BehaviorParameters) / sizeof(double));
  EXPECT_EQ(names.front(), "BlinkRateRest");
  EXPECT_EQ(names.back(), "SpeechExpressionDamping");
  BehaviorParameters p;
  EXPECT_EQ(GetBehaviorParameter(p, "BlinkRateRest"), 17.0);
  EXPECT_EQ(GetBehaviorParameter(p, "blink_rate_speaking"), 26.0); // matched like gestures
  EXPECT_EQ(GetBehaviorParameter(p, "HeadShareOfGaze"), 0.4);
  // Each name reaches its own field: set them all to distinct values and read them back.
  for (size_t i = 0; i < names.size(); ++i)
  {
    SetBehaviorParameter(p, names[i], 1000.0 + static_cast<double>(i));
  }
  for (size_t i = 0; i < names.size(); ++i)
  {
    EXPECT_EQ(GetBehaviorParameter(p, names[i]), 1000.0 + static_cast<double>(i)) << names[i];
  }
  EXPECT_EQ(p.BlinkRateRest, 1000.0);
  EXPECT_EQ(p.SpeechExpressionDamping, 1000.0 + static_cast<double>(names.size() - 1));
  try
  {
    GetBehaviorParameter(p, "BlinkSpeed");
    FAIL() << "an unknown parameter was found";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("'BlinkSpeed'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SetBehaviorParameter(p, "", 1.0), InputError);

  // The controller checks the values (the faster blinking shows in the track).
  BehaviorController b;
  BehaviorParameters fast = b.GetParameters();
  SetBehaviorParameter(fast, "BlinkRateRest", 60.0);
  b.SetParameters(fast);
  EXPECT_EQ(b.GetParameters().BlinkRateRest, 60.0);
  SetBehaviorParameter(fast, "BlinkRateRest", -1.0);
  EXPECT_THROW(b.SetParameters(fast), InputError);
  EXPECT_EQ(b.GetParameters().BlinkRateRest, 60.0);
}
