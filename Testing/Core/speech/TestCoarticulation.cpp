// SPDX-License-Identifier: BSD-3-Clause
#include "MorphNodeTestSkips.h"
#include "base/Error.h"
#include "speech/Coarticulation.h"
#include "speech/Sampa.h"
#include "speech/Speech.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace morphnode;

namespace
{
/// Phonemes back to back from (name, milliseconds) pairs.
std::vector<TimedPhoneme> Sequence(const std::vector<std::pair<std::string, double>>& items)
{
  std::vector<TimedPhoneme> phonemes;
  double start = 0.0;
  for (const auto& [name, ms] : items)
  {
    phonemes.push_back({ name, start, ms / 1000.0, {} });
    start += ms / 1000.0;
  }
  return phonemes;
}

double End(const std::vector<TimedPhoneme>& phonemes)
{
  return phonemes.back().Start + phonemes.back().Duration;
}

/// The largest value of a channel over the frames within one frame of `time`.
double PeakNear(const WeightTrack& track, int channel, double time)
{
  const double frame = time * track.GetFrameRate();
  double best = 0.0;
  for (long f = std::lround(std::floor(frame)) - 1; f <= std::lround(std::ceil(frame)) + 1; ++f)
  {
    if (f >= 0 && f < static_cast<long>(track.GetNumberOfFrames()))
    {
      best = std::max(best, track.GetValue(static_cast<size_t>(f), static_cast<size_t>(channel)));
    }
  }
  return best;
}

int ArgMax(const WeightTrack& track, size_t frame)
{
  const double* v = track.GetFrame(frame);
  return static_cast<int>(std::max_element(v, v + track.GetNumberOfChannels()) - v);
}
} // namespace

TEST(Coarticulation, ChannelsAreConvexWeights)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, "de");
  const auto phonemes = Sequence({ { "_", 100 }, { "m", 80 }, { "a:", 200 }, { "p", 60 },
    { "a:", 200 }, { "b", 40 }, { "U", 150 }, { "_", 100 } });
  const WeightTrack track = CoarticulatePhonemes(phonemes, map, End(phonemes), {});
  EXPECT_EQ(track.GetChannels(), map.GetVisemes());
  EXPECT_EQ(
    track.GetNumberOfFrames(), static_cast<size_t>(std::ceil(End(phonemes) * 60.0 - 1e-9)) + 1);
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    double sum = 0.0;
    for (size_t c = 0; c < track.GetNumberOfChannels(); ++c)
    {
      EXPECT_GE(track.GetValue(f, c), 0.0);
      EXPECT_LE(track.GetValue(f, c), 1.0 + 1e-12);
      sum += track.GetValue(f, c);
    }
    EXPECT_NEAR(sum, 1.0, 1e-9) << f;
  }
  // The face rests at both ends.
  EXPECT_GT(track.GetValue(0, map.GetSilenceIndex()), 0.5);
  EXPECT_GT(track.GetValue(track.GetNumberOfFrames() - 1, map.GetSilenceIndex()), 0.5);
}

TEST(Coarticulation, BilabialsCloseFullyAndOpenVowelsOpen)
{
  CoarticulationOptions options;
  options.Lead = 0.0;
  for (VisemeSet set : { VisemeSet::Oculus15, VisemeSet::German16, VisemeSet::Paper6 })
  {
    const VisemeMap map = VisemeMap::Builtin(set, "de");
    // A very short b between dominant rounded vowels must still close completely.
    const auto phonemes = Sequence({ { "_", 100 }, { "m", 80 }, { "a:", 200 }, { "p", 60 },
      { "a:", 200 }, { "b", 12 }, { "u:", 150 }, { "m", 30 }, { "a", 90 }, { "_", 100 } });
    for (double rate : { 24.0, 30.0, 60.0, 100.0 })
    {
      options.FrameRate = rate;
      const WeightTrack track = CoarticulatePhonemes(phonemes, map, End(phonemes), options);
      for (const auto& p : phonemes)
      {
        const int channel = map.MapPhoneme(p.Sampa);
        const double centre = p.Start + 0.5 * p.Duration;
        if (map.IsClosurePhoneme(p.Sampa))
        {
          EXPECT_GE(PeakNear(track, channel, centre), 0.999)
            << VisemeSetName(set) << " " << rate << " fps, " << p.Sampa << " at " << centre;
        }
        if (p.Sampa == "a:")
        {
          EXPECT_GE(track.Sample(centre, static_cast<size_t>(channel)), 0.75)
            << VisemeSetName(set) << " " << rate;
        }
      }
    }
  }
}

TEST(Coarticulation, NextVisemeIsAnticipated)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, "de");
  const auto phonemes = Sequence({ { "_", 100 }, { "a:", 200 }, { "u:", 200 }, { "_", 100 } });
  const size_t ou = static_cast<size_t>(map.FindViseme("ou"));
  CoarticulationOptions options;
  options.Lead = 0.0;
  options.FrameRate = 100.0;
  const WeightTrack track = CoarticulatePhonemes(phonemes, map, End(phonemes), options);
  const double boundary = 0.3;
  // Rounding starts well before the u: and already dominates at its start.
  EXPECT_GT(track.Sample(boundary - 0.05, ou), 0.2);
  EXPECT_GT(track.Sample(boundary, ou), 0.55);
  // Symmetric decay (no anticipation) rounds later.
  options.ThetaBefore = options.ThetaAfter;
  const WeightTrack symmetric = CoarticulatePhonemes(phonemes, map, End(phonemes), options);
  EXPECT_LT(symmetric.Sample(boundary, ou), track.Sample(boundary, ou) - 0.1);
}

TEST(Coarticulation, LeadShiftsTheTrackEarlier)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::German16, "de");
  const auto phonemes =
    Sequence({ { "_", 300 }, { "m", 80 }, { "a:", 200 }, { "l", 60 }, { "a", 200 }, { "_", 300 } });
  CoarticulationOptions options;
  options.FrameRate = 100.0;
  options.Lead = 0.0;
  const WeightTrack base = CoarticulatePhonemes(phonemes, map, End(phonemes), options);
  options.Lead = 0.1;
  const WeightTrack led = CoarticulatePhonemes(phonemes, map, End(phonemes), options);
  ASSERT_EQ(base.GetNumberOfFrames(), led.GetNumberOfFrames());
  const size_t shift = 10; // 0.1 s at 100 fps
  for (size_t f = 0; f + shift < base.GetNumberOfFrames(); ++f)
  {
    for (size_t c = 0; c < base.GetNumberOfChannels(); ++c)
    {
      ASSERT_NEAR(led.GetValue(f, c), base.GetValue(f + shift, c), 1e-9) << f << " " << c;
    }
  }
  // The M closure shows 0.1 s earlier.
  const size_t m = static_cast<size_t>(map.FindViseme("M"));
  EXPECT_GE(led.Sample(0.34 - 0.1, m), 0.999);
  EXPECT_LT(led.Sample(0.34, m), 0.5);
}

TEST(Coarticulation, BadOptionsAndSegmentsAreInputErrors)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, "en");
  const auto phonemes = Sequence({ { "a:", 100 } });
  CoarticulationOptions options;
  options.FrameRate = 0.0;
  EXPECT_THROW(CoarticulatePhonemes(phonemes, map, 0.1, options), InputError);
  options = {};
  options.ThetaBefore = -1.0;
  EXPECT_THROW(CoarticulatePhonemes(phonemes, map, 0.1, options), InputError);
  EXPECT_THROW(CoarticulatePhonemes(phonemes, map, std::nan(""), {}), InputError);
  EXPECT_THROW(CoarticulatePhonemes(phonemes, map, 1e9, {}), InputError);
  EXPECT_THROW(Coarticulate({ VisemeSegment{ 99, 0.0, 0.1, false } }, map, 0.1, {}), InputError);
  EXPECT_THROW(Coarticulate({ VisemeSegment{ 1, 0.0, -0.1, false } }, map, 0.1, {}), InputError);
  // Nothing to say: one resting frame.
  const WeightTrack empty = Coarticulate({}, map, 0.0, {});
  ASSERT_EQ(empty.GetNumberOfFrames(), 1u);
  EXPECT_DOUBLE_EQ(empty.GetValue(0, static_cast<size_t>(map.GetSilenceIndex())), 1.0);
}

/// Synthesized German and English: closures, open vowels and timing against eSpeak's events.
class SpokenTrack : public ::testing::TestWithParam<std::pair<const char*, const char*>>
{
};

TEST_P(SpokenTrack, FollowsEspeakPhonemeEvents)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  const auto [voice, text] = GetParam();
  for (VisemeSet set : { VisemeSet::Oculus15, VisemeSet::German16 })
  {
    SpeechOptions options;
    options.Voice = voice;
    options.Visemes = set;
    options.Coarticulation.FrameRate = 60.0;
    std::vector<std::string> warnings;
    options.Warn = CollectWarnings(warnings);
    // One synthesis, kept raw: eSpeak's timing varies by a few samples from call to call.
    SpeechSynthesizer synthesizer(voice);
    const SynthesisResult raw = synthesizer.Synthesize(text);
    const VisemeMap map = SelectVisemeMap(options);
    const Utterance u = BuildUtterance(raw.Phonemes, raw.Audio, raw.SampleRate, map, options);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    ASSERT_FALSE(u.Audio.empty());
    EXPECT_NEAR(u.Duration, double(u.Audio.size()) / u.SampleRate, 1e-9);
    const WeightTrack& track = u.Visemes;
    const double lead = options.Coarticulation.Lead;
    const double frame = 1.0 / track.GetFrameRate();

    // eSpeak's own events (in SAMPA) on the utterance's time axis: the utterance is delayed
    // when the mouth must lead the first sound by more than the silence before it.
    const auto spoken = [](const TimedPhoneme& p) { return !IsPausePhoneme(p.Sampa); };
    const auto firstRaw = std::find_if(raw.Phonemes.begin(), raw.Phonemes.end(), spoken);
    const auto firstUtterance = std::find_if(u.Phonemes.begin(), u.Phonemes.end(), spoken);
    ASSERT_NEAR(firstRaw->Start, raw.EspeakPhonemes.front().Start, 1e-12);
    const double delay = firstUtterance->Start - firstRaw->Start;
    EXPECT_GE(delay, 0.0);
    EXPECT_LE(delay, lead + 1e-3);
    EXPECT_EQ(
      u.Audio.size(), raw.Audio.size() + static_cast<size_t>(std::lround(delay * u.SampleRate)));

    // What the track shows in turn: each phoneme, a diphthong as its vowels' visemes, each
    // over its part of the phoneme's time (VisemeMap::MapPhonemeParts).
    struct Unit
    {
      std::string Sampa;
      double Start, Duration;
      int Viseme;
      bool Closure;
    };
    std::vector<Unit> units;
    for (const TimedPhoneme& p : raw.Phonemes)
    {
      double at = p.Start;
      for (const VisemePart& part : map.MapPhonemeParts(p.Sampa))
      {
        units.push_back({ p.Sampa, at, p.Duration * part.Fraction, part.Viseme, part.Closure });
        at += p.Duration * part.Fraction;
      }
    }
    int closures = 0, openVowels = 0, checked = 0;
    for (size_t i = 0; i < units.size(); ++i)
    {
      const Unit& p = units[i];
      if (IsPausePhoneme(p.Sampa))
      {
        continue;
      }
      const int channel = p.Viseme;
      // Where this phoneme shows in the track: its audio time, minus the lead.
      const double start = p.Start + delay - lead, end = start + p.Duration;
      const double centre = 0.5 * (start + end);
      if (p.Closure)
      {
        EXPECT_GE(PeakNear(track, channel, centre), 0.999)
          << VisemeSetName(set) << " " << p.Sampa << " at " << p.Start;
        ++closures;
      }
      const std::string& viseme = map.GetVisemes()[static_cast<size_t>(channel)];
      if ((viseme == "aa" || viseme == "A") && p.Duration >= 0.06)
      {
        EXPECT_GE(track.Sample(centre, static_cast<size_t>(channel)), 0.6)
          << VisemeSetName(set) << " " << p.Sampa << " at " << p.Start;
        ++openVowels;
      }
      // Timing: a viseme that no other phoneme near it shares peaks within the phoneme's
      // span, give or take one frame.
      bool distinct = i > 0 && i + 1 < units.size();
      for (size_t j = 0; j < units.size() && distinct; ++j)
      {
        const Unit& q = units[j];
        const bool near =
          q.Start < p.Start + p.Duration + 4 * frame && q.Start + q.Duration > p.Start - 4 * frame;
        distinct = j == i || !near || q.Viseme != channel;
      }
      if (distinct && p.Duration >= 2 * frame)
      {
        size_t bestFrame = 0;
        double best = -1.0;
        for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
        {
          const double t = track.GetTime(f);
          if (t >= start - 3 * frame && t <= end + 3 * frame &&
            track.GetValue(f, size_t(channel)) > best)
          {
            best = track.GetValue(f, size_t(channel));
            bestFrame = f;
          }
        }
        EXPECT_GE(track.GetTime(bestFrame), start - frame - 1e-9)
          << VisemeSetName(set) << " " << p.Sampa << " at " << p.Start;
        EXPECT_LE(track.GetTime(bestFrame), end + frame + 1e-9)
          << VisemeSetName(set) << " " << p.Sampa << " at " << p.Start;
        if (p.Duration >= 3 * frame)
        {
          EXPECT_EQ(ArgMax(track, size_t(std::lround(centre / frame))), channel)
            << VisemeSetName(set) << " " << p.Sampa << " at " << p.Start;
        }
        ++checked;
      }
    }
    EXPECT_GE(closures, 3);
    EXPECT_GE(openVowels, 2);
    EXPECT_GE(checked, 8);
  }
}

INSTANTIATE_TEST_SUITE_P(Speech, SpokenTrack,
  ::testing::Values(std::make_pair("de", "Papa bringt meine Bälle mit. Am Abend malt Mama Tannen."),
    std::make_pair("en", "Bob meets Pam at the market, maybe by bus. Father was calm.")),
  [](const ::testing::TestParamInfo<std::pair<const char*, const char*>>& info)
  {
    return std::string(info.param.first); // the voice: stable test names for ctest
  });
