// SPDX-License-Identifier: BSD-3-Clause
#include "MorphNodeTestSkips.h"
#include "speech/Nonverbal.h"
#include "speech/Speech.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace morphnode;

namespace
{
using Kind = NonverbalCue::Kind;

/// (name, ms, pitch Hz or 0) back to back.
std::vector<TimedPhoneme> Sequence(
  const std::vector<std::tuple<std::string, double, double>>& items)
{
  std::vector<TimedPhoneme> phonemes;
  double start = 0.0;
  for (const auto& [name, ms, pitch] : items)
  {
    TimedPhoneme p{ name, start, ms / 1000.0, {} };
    if (pitch > 0.0)
    {
      p.Pitch = { { 0.5, pitch } };
    }
    phonemes.push_back(p);
    start += ms / 1000.0;
  }
  return phonemes;
}

std::vector<NonverbalCue> OfKind(const std::vector<NonverbalCue>& cues, Kind kind)
{
  std::vector<NonverbalCue> out;
  std::copy_if(cues.begin(), cues.end(), std::back_inserter(out),
    [&](const NonverbalCue& c) { return c.Type == kind; });
  return out;
}
} // namespace

TEST(Nonverbal, PitchAccentRaisesTheBrows)
{
  // "a statement": flat 100 Hz with one accented vowel at 150 Hz, falling at the end.
  const auto phonemes = Sequence(
    { { "_", 100, 0 }, { "d", 50, 0 }, { "a:", 150, 100 }, { "s", 80, 0 }, { "i:", 120, 150 },
      { "t", 60, 0 }, { "a", 150, 98 }, { "n", 80, 95 }, { "@", 120, 90 }, { "_", 100, 0 } });
  const auto cues = DeriveNonverbalCues(phonemes);
  const auto brows = OfKind(cues, Kind::BrowRaise);
  ASSERT_EQ(brows.size(), 1u);
  EXPECT_NEAR(brows[0].Start, phonemes[4].Start - NonverbalOptions().BrowLead, 1e-12);
  EXPECT_GT(brows[0].Intensity, 0.5);
  EXPECT_LE(brows[0].Intensity, 1.0);
  // A statement ends with a nod on its last spoken phoneme.
  const auto nods = OfKind(cues, Kind::Nod);
  ASSERT_EQ(nods.size(), 1u);
  EXPECT_NEAR(nods[0].Start, phonemes[8].Start, 1e-12);
  // No inner pause: no blink, no relax.
  EXPECT_TRUE(OfKind(cues, Kind::Blink).empty());
  EXPECT_TRUE(OfKind(cues, Kind::Relax).empty());
  // Without the accent there is no brow raise.
  auto flat = phonemes;
  flat[4].Pitch = { { 0.5, 101.0 } };
  EXPECT_TRUE(OfKind(DeriveNonverbalCues(flat), Kind::BrowRaise).empty());
}

TEST(Nonverbal, PausesRelaxAndInviteBlinksSentencesNod)
{
  const auto phonemes = Sequence(
    { { "_", 50, 0 }, { "j", 60, 100 }, { "a:", 150, 100 }, { "_", 350, 0 }, { "n", 60, 100 },
      { "aI", 150, 100 }, { "_", 100, 0 }, { "g", 50, 0 }, { "u:", 150, 95 }, { "_", 50, 0 } });
  const auto cues = DeriveNonverbalCues(phonemes);
  const auto relax = OfKind(cues, Kind::Relax);
  ASSERT_EQ(relax.size(), 1u); // the 100 ms pause is too short
  EXPECT_NEAR(relax[0].Start, phonemes[3].Start, 1e-12);
  EXPECT_NEAR(relax[0].Duration, 0.35, 1e-12);
  const auto blinks = OfKind(cues, Kind::Blink);
  ASSERT_EQ(blinks.size(), 1u);
  EXPECT_NEAR(blinks[0].Start, phonemes[3].Start, 1e-12);
  const auto nods = OfKind(cues, Kind::Nod);
  ASSERT_EQ(nods.size(), 2u); // after the long pause and at the end
  EXPECT_NEAR(nods[0].Start, phonemes[2].Start, 1e-12);
  EXPECT_NEAR(nods[1].Start, phonemes[8].Start, 1e-12);
  EXPECT_TRUE(std::is_sorted(cues.begin(), cues.end(),
    [](const NonverbalCue& a, const NonverbalCue& b) { return a.Start < b.Start; }));
}

TEST(Nonverbal, QuestionGetsBrowsNotANod)
{
  const auto phonemes = Sequence({ { "_", 50, 0 }, { "j", 60, 100 }, { "a:", 150, 100 },
    { "n", 60, 100 }, { "aI", 150, 100 }, { "g", 50, 0 }, { "u:", 150, 125 }, { "_", 50, 0 } });
  const auto cues = DeriveNonverbalCues(phonemes);
  EXPECT_TRUE(OfKind(cues, Kind::Nod).empty());
  EXPECT_FALSE(OfKind(cues, Kind::BrowRaise).empty());
}

TEST(Nonverbal, WithoutPitchOnlyPausesAndEndsCount)
{
  const auto phonemes = Sequence({ { "a:", 150, 0 }, { "_", 300, 0 }, { "o:", 150, 0 } });
  const auto cues = DeriveNonverbalCues(phonemes);
  EXPECT_TRUE(OfKind(cues, Kind::BrowRaise).empty());
  EXPECT_EQ(OfKind(cues, Kind::Nod).size(), 2u);
  EXPECT_EQ(OfKind(cues, Kind::Blink).size(), 1u);
  EXPECT_TRUE(DeriveNonverbalCues({}).empty());
  EXPECT_TRUE(DeriveNonverbalCues(Sequence({ { "_", 500, 0 } })).empty());
}

TEST(Nonverbal, SynthesizedSpeechGetsCues)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  SpeechOptions options;
  options.Voice = "en";
  const Utterance u =
    SpeakText("This is really important. Please listen to me carefully.", options);
  ASSERT_FALSE(u.Cues.empty());
  for (const auto& c : u.Cues)
  {
    EXPECT_GE(c.Start, 0.0);
    EXPECT_LE(c.Start, u.Duration);
    EXPECT_GE(c.Intensity, 0.0);
    EXPECT_LE(c.Intensity, 1.0);
  }
  EXPECT_EQ(OfKind(u.Cues, Kind::Nod).size(), 2u);       // two statements
  EXPECT_EQ(OfKind(u.Cues, Kind::Blink).size(), 1u);     // the sentence pause
  EXPECT_GE(OfKind(u.Cues, Kind::BrowRaise).size(), 1u); // eSpeak accents stressed syllables
}
