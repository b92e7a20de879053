// SPDX-License-Identifier: BSD-3-Clause
// The endless, streaming behaviour (LiveBehavior): blinks past any horizon, no period,
// commands merged without touching what lies outside their span, bounded memory, mood
// effects beyond the smile, the override rules, chunked speech.
#include "BehaviorTestUtilities.h"

#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "behavior/LiveBehavior.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

using namespace morphnode;
using C = BehaviorChannel;

namespace
{
const std::vector<std::string> Visemes = { "sil", "PP", "aa", "E", "ou" };

/// Blink starts seen in the output: EyesClosed rising through 0.6.
std::vector<double> BlinksInOutput(LiveBehavior& live, double from, double to, double fps = 60.0)
{
  std::vector<double> w(live.GetNumberOfChannels());
  std::vector<double> starts;
  bool closed = false;
  for (double t = from; t < to; t += 1.0 / fps)
  {
    live.Sample(t, w.data());
    const bool now = w[C::EyesClosed] > 0.6;
    if (now && !closed)
    {
      starts.push_back(t);
    }
    closed = now;
  }
  return starts;
}

/// Normalized autocorrelation of a 0/1 train (mean removed) at lag k.
double Autocorrelation(const std::vector<double>& x, size_t k)
{
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
  double num = 0.0, den = 0.0;
  for (size_t i = 0; i < x.size(); ++i)
  {
    den += (x[i] - mean) * (x[i] - mean);
    if (i + k < x.size())
    {
      num += (x[i] - mean) * (x[i + k] - mean);
    }
  }
  return den > 0.0 ? num / den : 0.0;
}

/// The largest autocorrelation of a blink train (0.1 s bins) over lags of 1 s .. 5 min.
double MaxBlinkAutocorrelation(const std::vector<double>& starts, double duration)
{
  std::vector<double> train(static_cast<size_t>(duration * 10.0) + 1, 0.0);
  for (double s : starts)
  {
    train[static_cast<size_t>(s * 10.0)] = 1.0;
  }
  double best = 0.0;
  for (size_t k = 10; k <= 3000; ++k)
  {
    best = std::max(best, Autocorrelation(train, k));
  }
  return best;
}

std::vector<double> CollectBlinkStarts(LiveBehavior& live, double duration, double fps)
{
  std::vector<double> w(live.GetNumberOfChannels()), starts;
  double previous = 0.0;
  for (double t = 0.0; t < duration; t += 1.0 / fps)
  {
    live.Sample(t, w.data());
    for (double s : live.GetBlinkStarts(previous, t))
    {
      starts.push_back(s);
    }
    previous = t;
  }
  return starts;
}

/// An utterance with an "ou" held fully open over [0.2, 0.8] s and "aa" after it.
Utterance RoundedUtterance()
{
  Utterance u;
  u.Visemes = WeightTrack({ "sil", "ou", "aa" }, 100.0);
  for (int f = 0; f <= 150; ++f)
  {
    const double t = f / 100.0;
    const double ou = t >= 0.2 && t <= 0.8 ? 1.0 : 0.0;
    const double aa = t >= 0.9 && t <= 1.4 ? 1.0 : 0.0;
    u.Visemes.AppendFrame(std::vector<double>{ 1.0 - ou - aa, ou, aa });
  }
  u.Duration = 1.5;
  return u;
}
} // namespace

TEST(LiveBehavior, ChannelsAreFixedAtConstruction)
{
  LiveBehavior live(Visemes);
  ASSERT_EQ(live.GetNumberOfChannels(), C::NumberOfBaseChannels + Visemes.size());
  EXPECT_EQ(live.GetChannelNames()[C::NumberOfBaseChannels + 2], "aa");
  EXPECT_THROW(LiveBehavior({ "aa", "aa" }), InputError);
  EXPECT_THROW(LiveBehavior({ "HeadYaw" }), InputError);
  BehaviorParameters bad;
  bad.BlinkRateRest = 0.0;
  EXPECT_THROW(LiveBehavior(Visemes, bad), InputError);
  // An utterance with a viseme the avatar does not have.
  Utterance u = behaviortest::MakeUtterance(0.5);
  LiveBehavior few({ "sil", "aa" });
  EXPECT_THROW(few.Speak(u, 0.0), InputError);
}

TEST(LiveBehavior, BlinksPastAnyHorizon)
{
  LiveBehavior live(Visemes, BehaviorParameters(), 11);
  std::vector<double> w(live.GetNumberOfChannels());
  // Jump ahead (the time only has to be non-decreasing): blinks after 10 and 30 minutes.
  for (double at : { 600.0, 1800.0, 36000.0 })
  {
    const auto blinks = BlinksInOutput(live, at, at + 60.0);
    EXPECT_GE(blinks.size(), 8u) << "blinks per minute after " << at << " s";
    EXPECT_LE(blinks.size(), 30u) << "blinks per minute after " << at << " s";
  }
  // Saccades too.
  size_t saccades = 0;
  for (double t = 36060.0; t < 36120.0; t += 0.5)
  {
    live.Sample(t, w.data());
    saccades += live.GetSaccades(t - 0.5, t).size();
  }
  EXPECT_GT(saccades, 20u);
}

TEST(LiveBehavior, NoPeriodInTheBlinkTrain)
{
  LiveBehavior live(Visemes, BehaviorParameters(), 5);
  const double duration = 1800.0;
  const auto starts = CollectBlinkStarts(live, duration, 30.0);
  ASSERT_GT(starts.size(), 300u);
  const double free = MaxBlinkAutocorrelation(starts, duration);
  EXPECT_LT(free, 0.12) << "a peak in the autocorrelation: the blinks repeat";

  // Negative control: the same blinks of the first 20 s looped (what a periodic schedule
  // does) give a clear peak at the period.
  std::vector<double> looped;
  for (double s : starts)
  {
    if (s < 20.0)
    {
      for (double k = 0.0; s + k < duration; k += 20.0)
      {
        looped.push_back(s + k);
      }
    }
  }
  EXPECT_GT(MaxBlinkAutocorrelation(looped, duration), 0.8);

  // The intervals are not correlated with their successors either.
  std::vector<double> intervals;
  for (size_t i = 1; i < starts.size(); ++i)
  {
    intervals.push_back(starts[i] - starts[i - 1]);
  }
  for (size_t k = 1; k < 20; ++k)
  {
    EXPECT_LT(std::abs(Autocorrelation(intervals, k)), 0.2) << "lag " << k;
  }
}

TEST(LiveBehavior, SameSeedWithoutCommandsIsTheFiniteController)
{
  // One set of idle generators and the gestures' data: the live behaviour and the finite
  // controller agree (close_eyes differs on purpose: the live one also blocks the gaze
  // shapes, VRM's overrideLookAt).
  BehaviorController controller;
  controller.SetSeed(3);
  controller.SetDuration(60.0);
  controller.Gesture("nod", 10.0, 0.8, 0.7);
  controller.Gesture("smile", 20.0, 1.5, 0.6);
  controller.Gesture("frown", 30.0, 2.0, 1.0);
  controller.Gesture("tilt", 40.0, 1.5, 1.0);
  controller.Prepare();
  LiveBehavior live({}, BehaviorParameters(), 3);
  std::vector<double> a(controller.GetNumberOfChannels()), b(live.GetNumberOfChannels());
  ASSERT_EQ(a.size(), b.size());
  bool nod = false, smile = false, close = false, tilt = false;
  for (int f = 0; f < 60 * 30; ++f)
  {
    const double t = f / 30.0;
    if (t >= 10.0 && !nod)
    {
      live.Gesture("nod", 10.0, 0.7, 0.8), nod = true;
    }
    if (t >= 20.0 && !smile)
    {
      live.Gesture("smile", 20.0, 0.6, 1.5), smile = true;
    }
    if (t >= 30.0 && !close)
    {
      live.Gesture("frown", 30.0, 1.0, 2.0), close = true;
    }
    if (t >= 40.0 && !tilt)
    {
      live.Gesture("tilt", 40.0, 1.0, 1.5), tilt = true;
    }
    controller.Sample(t, a.data());
    live.Sample(t, b.data());
    for (size_t c = 0; c < a.size(); ++c)
    {
      ASSERT_NEAR(a[c], b[c], 1e-12) << C::Name(static_cast<int>(c)) << " at " << t;
    }
  }
}

TEST(LiveBehavior, MergingLeavesEverythingOutsideTheSpanUnchanged)
{
  // Blinking much faster while speaking, so that a rate change leaking out of the speech's
  // span shows.
  BehaviorParameters fast;
  fast.BlinkRateSpeaking = 80.0;
  LiveBehavior plain(Visemes, fast, 9);
  LiveBehavior merged(Visemes, fast, 9);
  const double fps = 50.0;
  std::vector<double> a(plain.GetNumberOfChannels()), b(merged.GetNumberOfChannels());
  std::vector<LiveBehavior::Timing> spans;
  bool differs = false;
  for (int f = 0; f < 60 * 50; ++f)
  {
    const double t = f / fps;
    if (f == 20 * 50)
    {
      // Merged while running: a gesture, speech, a look, a blink.
      // (Long speech: the faster blinking it brings must stay inside its span.)
      spans.push_back(merged.Gesture("nod", t + 0.5, 1.0));
      spans.push_back(merged.Speak(behaviortest::MakeUtterance(8.0), t + 1.0));
      spans.push_back(merged.LookAt(20.0, 5.0, t + 11.0, 1.0));
      spans.push_back(merged.Gesture("blink", t + 15.0));
      spans.push_back(merged.Gesture("close_eyes", t + 19.0, 0.8, 2.0));
    }
    plain.Sample(t, a.data());
    merged.Sample(t, b.data());
    bool inside = false;
    for (const auto& s : spans)
    {
      inside = inside || (t >= s.Start && t <= s.End);
    }
    if (inside)
    {
      differs = differs || a != b;
      continue;
    }
    for (size_t c = 0; c < a.size(); ++c)
    {
      ASSERT_EQ(a[c], b[c]) << plain.GetChannelNames()[c] << " at " << t << " s";
    }
  }
  EXPECT_TRUE(differs) << "the merged commands did nothing";
  // A mood's span is open-ended: nothing before it changes.
  LiveBehavior calm(Visemes, BehaviorParameters(), 9), sad(Visemes, BehaviorParameters(), 9);
  for (int f = 0; f < 30 * 50; ++f)
  {
    const double t = f / fps;
    if (f == 10 * 50)
    {
      sad.SetMood("sad", 1.0, t);
    }
    calm.Sample(t, a.data());
    sad.Sample(t, b.data());
    if (t < 10.0)
    {
      ASSERT_EQ(a, b) << "at " << t;
    }
  }
  EXPECT_NE(a, b);
}

TEST(LiveBehavior, PastIsNeverChanged)
{
  LiveBehavior live(Visemes);
  std::vector<double> w(live.GetNumberOfChannels());
  live.Sample(5.0, w.data());
  // A command in the past takes effect now.
  const auto timing = live.Gesture("nod", 2.0);
  EXPECT_DOUBLE_EQ(timing.Start, 5.0);
  EXPECT_THROW(live.Sample(4.0, w.data()), InputError);
  EXPECT_THROW(live.Sample(std::nan(""), w.data()), InputError);
  EXPECT_THROW(live.Gesture("spin", 6.0), InputError);
  EXPECT_THROW(live.SetMood("bored", 1.0, 6.0), InputError);
  EXPECT_THROW(live.Gesture("nod", 6.0, 2.0), InputError);
  EXPECT_THROW(live.Say("hello", 6.0), InputError); // no synthesizer
}

TEST(LiveBehavior, MemoryStaysBounded)
{
  LiveBehavior live(Visemes, BehaviorParameters(), 4);
  std::vector<double> w(live.GetNumberOfChannels());
  size_t firstMax = 0, laterMax = 0;
  const double fps = 10.0;
  for (int f = 0; f < 4 * 3600 * 10; ++f)
  {
    const double t = f / fps;
    // Commands keep coming, as from a dialog system.
    if (f % 50 == 0)
    {
      live.Gesture(f % 100 == 0 ? "nod" : "smile", t, 0.8);
    }
    if (f % 70 == 0)
    {
      live.LookAt(10.0, 0.0, t, 1.0);
    }
    if (f % 300 == 0)
    {
      live.Speak(behaviortest::MakeUtterance(2.0), t);
    }
    if (f % 600 == 0)
    {
      live.SetMood(f % 1200 == 0 ? "happy" : "sad", 0.7, t);
    }
    live.Sample(t, w.data());
    live.TakeAudio();
    const size_t held = live.GetNumberOfHeldEvents();
    (t < 600.0 ? firstMax : laterMax) = std::max(t < 600.0 ? firstMax : laterMax, held);
  }
  EXPECT_LT(laterMax, 80u);
  EXPECT_LE(laterMax, firstMax + 10) << "held events grow with the run";
}

TEST(LiveBehavior, MoodChangesBlinksGazeAndHead)
{
  struct Figures
  {
    double BlinksPerMinute, MeanSaccade, LookDown, HeadYawSd;
  };
  auto run = [](const char* mood)
  {
    LiveBehavior live(Visemes, BehaviorParameters(), 21);
    live.SetMood(mood, 1.0, 0.0);
    const double duration = 900.0;
    std::vector<double> w(live.GetNumberOfChannels());
    double lookDown = 0.0, yaw = 0.0, yaw2 = 0.0, n = 0.0, amplitude = 0.0, saccades = 0.0;
    size_t blinks = 0;
    double previous = 0.0;
    for (double t = 0.0; t < duration; t += 0.05)
    {
      live.Sample(t, w.data());
      blinks += live.GetBlinkStarts(previous, t).size();
      for (const auto& s : live.GetSaccades(previous, t))
      {
        amplitude += s.Amplitude, saccades += 1.0;
      }
      previous = t;
      if (t > 5.0)
      {
        lookDown += w[C::LookDown], yaw += w[C::HeadYaw], yaw2 += w[C::HeadYaw] * w[C::HeadYaw];
        n += 1.0;
      }
    }
    return Figures{ blinks / (duration / 60.0), amplitude / saccades, lookDown / n,
      std::sqrt(yaw2 / n - (yaw / n) * (yaw / n)) };
  };
  const Figures neutral = run("neutral"), sad = run("sad"), afraid = run("afraid"),
                angry = run("angry");
  EXPECT_GT(afraid.BlinksPerMinute, 1.3 * neutral.BlinksPerMinute);
  EXPECT_LT(angry.BlinksPerMinute, 0.9 * neutral.BlinksPerMinute);
  EXPECT_LT(sad.MeanSaccade, 0.85 * neutral.MeanSaccade);
  EXPECT_GT(afraid.MeanSaccade, neutral.MeanSaccade);
  EXPECT_GT(sad.LookDown, neutral.LookDown + 0.08) << "a sad gaze rests lower";
  EXPECT_LT(sad.HeadYawSd, 0.75 * neutral.HeadYawSd);
  EXPECT_GT(afraid.HeadYawSd, 1.15 * neutral.HeadYawSd);
}

TEST(LiveBehavior, SpeakingBlinksFaster)
{
  LiveBehavior quiet(Visemes, BehaviorParameters(), 2), talking(Visemes, BehaviorParameters(), 2);
  std::vector<double> w(quiet.GetNumberOfChannels());
  size_t q = 0, s = 0;
  double previous = 0.0;
  for (double t = 0.0; t < 1200.0; t += 0.05)
  {
    if (!talking.IsSpeaking(t))
    {
      talking.Speak(behaviortest::MakeUtterance(5.0), t);
    }
    quiet.Sample(t, w.data());
    talking.Sample(t, w.data());
    q += quiet.GetBlinkStarts(previous, t).size();
    s += talking.GetBlinkStarts(previous, t).size();
    previous = t;
  }
  const double expected =
    BehaviorParameters().BlinkRateSpeaking / BehaviorParameters().BlinkRateRest;
  EXPECT_NEAR(static_cast<double>(s) / static_cast<double>(q), expected, 0.25 * expected);
}

TEST(LiveBehavior, ClosedEyesBlockBlinks)
{
  // Half-closed eyes held for a minute: a blink would close them fully.
  auto maxLid = [](const BehaviorLibrary& library)
  {
    LiveBehavior live(Visemes, BehaviorParameters(), 8, library);
    std::vector<double> w(live.GetNumberOfChannels());
    live.Gesture("close_eyes", 1.0, 0.5, 61.0);
    double lid = 0.0;
    for (double t = 0.0; t < 60.0; t += 0.01)
    {
      live.Sample(t, w.data());
      if (t > 2.0)
      {
        lid = std::max(lid, w[C::EyesClosed]);
      }
    }
    return lid;
  };
  EXPECT_NEAR(maxLid(BehaviorLibrary::Default()), 0.5, 1e-9);
  // Negative control: the same gesture without the override lets blinks through.
  const BehaviorLibrary noOverride = BehaviorLibrary::FromJson(
    R"({"gestures": {"close_eyes": {"duration": 2, "shapes": {"EyesClosed": 1}}}})", "test",
    &BehaviorLibrary::Default());
  EXPECT_GT(maxLid(noOverride), 0.9);
}

TEST(LiveBehavior, SpeechLimitsTheMoodsMouth)
{
  LiveBehavior live({ "sil", "ou", "aa" }, behaviortest::QuietParameters(), 1);
  std::vector<double> w(live.GetNumberOfChannels());
  live.SetMood("happy", 1.0, 0.0);
  live.Sample(3.0, w.data());
  const double smile = w[C::MouthSmile];
  EXPECT_GT(smile, 0.6);
  live.Speak(RoundedUtterance(), 3.0);
  live.Sample(4.1, w.data()); // "aa" fully open
  EXPECT_NEAR(w[C::NumberOfBaseChannels + 2], 1.0, 1e-9);
  EXPECT_LT(w[C::MouthSmile], 0.5 * smile) << "the smile fights the open vowel";
}

TEST(LiveBehavior, AStrongExpressionLimitsClashingMouthShapes)
{
  auto mouth = [](double intensity)
  {
    LiveBehavior live({ "sil", "ou", "aa" }, behaviortest::QuietParameters(), 1);
    std::vector<double> w(live.GetNumberOfChannels());
    live.Gesture("smile", 0.0, intensity, 5.0);
    live.Speak(RoundedUtterance(), 1.0);
    live.Sample(1.5, w.data()); // "ou" fully rounded in the speech
    const double ou = w[C::NumberOfBaseChannels + 1];
    live.Sample(2.1, w.data()); // "aa"
    return std::make_pair(ou, w[C::NumberOfBaseChannels + 2]);
  };
  const auto none = mouth(0.0), light = mouth(0.3), strong = mouth(1.0);
  EXPECT_NEAR(none.first, 1.0, 1e-9);
  EXPECT_NEAR(light.first, 0.7, 1e-9);
  EXPECT_NEAR(strong.first, 0.0, 1e-9) << "a full smile and rounded lips fight";
  // Shapes that do not clash are left alone.
  EXPECT_NEAR(strong.second, 1.0, 1e-9);
}

TEST(LiveBehavior, SplitSpeechChunks)
{
  const std::string text =
    "Hello there, my dear friend, how wonderful that you could come today to see us all. "
    "The weather is fine! Shall we walk?\nYes; let us go, 3.5 km.";
  const auto chunks = SplitSpeechChunks(text, 40, 60);
  ASSERT_GE(chunks.size(), 5u);
  EXPECT_LE(chunks[0].size(), 40u);
  std::string joined, words;
  for (const auto& c : chunks)
  {
    EXPECT_FALSE(c.empty());
    EXPECT_LE(c.size(), 60u);
    joined += (joined.empty() ? "" : " ") + c;
  }
  auto squash = [](const std::string& s)
  {
    std::string out;
    for (char c : s)
    {
      out += std::isspace(static_cast<unsigned char>(c)) ? ' ' : c;
    }
    return out;
  };
  EXPECT_EQ(squash(joined), squash(text));
  EXPECT_EQ(chunks[0], "Hello there, my dear friend,");
  EXPECT_NE(std::find(chunks.begin(), chunks.end(), "let us go, 3.5 km."), chunks.end());
  EXPECT_TRUE(SplitSpeechChunks("   ").empty());
}

TEST(LiveBehavior, LongTextStartsAfterOneChunk)
{
  LiveBehavior live(Visemes, BehaviorParameters(), 1);
  std::vector<std::string> synthesized;
  live.SetSynthesizer(
    [&](const std::string& text)
    {
      synthesized.push_back(text);
      Utterance u = behaviortest::MakeUtterance(0.05 * static_cast<double>(text.size()));
      u.Audio.assign(100, 1);
      return u;
    });
  const std::string text = "One sentence here. Another sentence follows it. A third one comes. "
                           "And a fourth. Then the last one of all.";
  const auto timing = live.Say(text, 1.0);
  EXPECT_EQ(synthesized.size(), 1u) << "only the first chunk is synthesized at once";
  EXPECT_FALSE(timing.Final);
  EXPECT_DOUBLE_EQ(timing.Start, 1.0);
  auto audio = live.TakeAudio();
  ASSERT_EQ(audio.size(), 1u);
  EXPECT_DOUBLE_EQ(audio[0].Start, 1.0);
  std::vector<double> w(live.GetNumberOfChannels());
  double mouth = 0.0, lastSpeech = 0.0;
  for (double t = 1.0; t < 20.0; t += 0.02)
  {
    live.Sample(t, w.data());
    for (auto& a : live.TakeAudio())
    {
      audio.push_back(std::move(a));
    }
    mouth = std::max(mouth, w[C::NumberOfBaseChannels + 2]);
    if (w[C::NumberOfBaseChannels + 2] > 0.5)
    {
      lastSpeech = t;
    }
  }
  EXPECT_EQ(synthesized.size(), 5u);
  ASSERT_EQ(audio.size(), 5u);
  // The chunks follow each other without gaps.
  for (size_t i = 1; i < audio.size(); ++i)
  {
    EXPECT_NEAR(audio[i].Start - audio[i - 1].Start,
      0.05 * static_cast<double>(synthesized[i - 1].size()), 1e-9);
  }
  EXPECT_GT(lastSpeech, audio.back().Start);
  EXPECT_FALSE(live.IsSpeaking(20.0));
}

TEST(LiveBehavior, StopSpeakingEndsTheMouthAndDropsTheQueue)
{
  LiveBehavior live(Visemes, behaviortest::QuietParameters(), 1);
  int calls = 0;
  live.SetSynthesizer(
    [&](const std::string&)
    {
      ++calls;
      return behaviortest::MakeUtterance(1.0);
    });
  live.Say("First part. Second part. Third part.", 0.0);
  std::vector<double> w(live.GetNumberOfChannels());
  live.Sample(0.4, w.data());
  EXPECT_GT(w[C::NumberOfBaseChannels + 2], 0.9);
  const int before = calls;
  live.StopSpeaking(0.45);
  live.Sample(0.45 + LiveBehavior::StopFade + 0.01, w.data());
  for (size_t c = C::NumberOfBaseChannels; c < w.size(); ++c)
  {
    EXPECT_EQ(w[c], 0.0) << live.GetChannelNames()[c];
  }
  for (double t = 0.6; t < 6.0; t += 0.05)
  {
    live.Sample(t, w.data());
    EXPECT_EQ(w[C::NumberOfBaseChannels + 2], 0.0);
  }
  EXPECT_EQ(calls, before) << "nothing synthesized after the stop";
  EXPECT_FALSE(live.IsSpeaking(6.0));
}

TEST(LiveBehavior, EachTextKeepsItsSynthesizer)
{
  LiveBehavior live(Visemes, BehaviorParameters(), 1);
  std::string calls;
  auto voice = [&](char name)
  {
    return [&calls, name](const std::string& text)
    {
      calls += name;
      return behaviortest::MakeUtterance(0.02 * static_cast<double>(text.size()));
    };
  };
  live.SetSynthesizer(voice('d'));
  live.Say("First sentence one. First sentence two.", 0.0);       // d now, d later
  live.Say("Second text one. Second text two.", 0.0, voice('x')); // queued: x, x
  live.Say("Third.", 0.0);                                        // queued: d
  EXPECT_EQ(calls, "d");
  std::vector<double> w(live.GetNumberOfChannels());
  for (double t = 0.0; t < 10.0; t += 0.05)
  {
    live.Sample(t, w.data());
  }
  EXPECT_EQ(calls, "ddxxd");
  EXPECT_THROW(live.Say("No voice.", 10.0, LiveBehavior::Synthesizer()), InputError);
  EXPECT_TRUE(live.TakeErrors().empty());
}

TEST(LiveBehavior, SpeechTimingOutlivesTheSpeechBriefly)
{
  LiveBehavior live(Visemes, BehaviorParameters(), 1);
  live.SetSynthesizer([](const std::string&) { return behaviortest::MakeUtterance(1.0); });
  const auto said = live.Say("One. Two.", 0.0);
  EXPECT_FALSE(said.Final);
  std::vector<double> w(live.GetNumberOfChannels());
  for (double t = 0.0; t <= 2.5; t += 0.1)
  {
    live.Sample(t, w.data());
  }
  const auto done = live.GetSpeechTiming(said.Id);
  EXPECT_EQ(done.Id, said.Id);
  EXPECT_TRUE(done.Final);
  EXPECT_DOUBLE_EQ(done.Start, 0.0);
  EXPECT_DOUBLE_EQ(done.End, 2.0);
  live.Sample(2.0 + LiveBehavior::ForgetAfter + 0.5, w.data());
  EXPECT_EQ(live.GetSpeechTiming(said.Id).Id, 0u);
}

// Issue 29: a gesture of 1e-320 s passed every check and made the head pose NaN. Durations
// below MinBehaviorDuration are refused (one command costs one command), and a gesture at
// the floor, sampled exactly at its start, keeps every channel finite.
TEST(LiveBehavior, TinyDurationsAreRefusedAndTheFloorStaysFinite)
{
  LiveBehavior live(Visemes);
  std::vector<double> w;
  live.Sample(0.0, w);
  for (const char* g : { "nod", "shake", "tilt", "smile" })
  {
    EXPECT_THROW(live.Gesture(g, 1.0, 1.0, 1e-320), InputError) << g;
    EXPECT_THROW(live.Gesture(g, 1.0, 1.0, 1e-20), InputError) << g;
  }
  EXPECT_THROW(live.LookAt(10.0, 5.0, 1.0, 1e-300), InputError);
  double start = 1.0;
  for (const char* g : { "nod", "shake" })
  {
    start += 1.0; // each at its own, later start
    live.Gesture(g, start, 1.0, MinBehaviorDuration);
    for (double t = start; t < start + 2.0 * MinBehaviorDuration; t += MinBehaviorDuration / 8.0)
    {
      live.Sample(t, w);
      for (size_t c = 0; c < w.size(); ++c)
      {
        EXPECT_TRUE(std::isfinite(w[c])) << g << " " << live.GetChannelNames()[c] << " at " << t;
      }
    }
  }
  EXPECT_EQ(live.GetNumberOfNonFiniteValues(), 0u);
}
