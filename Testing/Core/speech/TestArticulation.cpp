// SPDX-License-Identifier: BSD-3-Clause
// Visemes for every language: phones described by articulation (X-SAMPA), eSpeak mnemonics
// of languages without SAMPA tables, the nearest table phoneme, diphthongs as sequences,
// every eSpeak NG voice without an unmapped phoneme, and lips that round, close and bite in
// ten languages.
#include "base/Error.h"
#include "speech/Articulation.h"
#include "speech/Sampa.h"
#include "speech/Speech.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

using namespace morphnode;

namespace
{
double MaxWeight(const WeightTrack& track, const std::string& channel)
{
  const int c = track.FindChannel(channel);
  double m = 0.0;
  for (size_t f = 0; c >= 0 && f < track.GetNumberOfFrames(); ++f)
  {
    m = std::max(m, track.GetFrame(f)[c]);
  }
  return m;
}
} // namespace

TEST(Articulation, DescribesVowelsAndConsonants)
{
  const Articulation u = DescribePhone("u:");
  EXPECT_EQ(u.Type, Articulation::Kind::Vowel);
  EXPECT_TRUE(u.Rounded);
  EXPECT_EQ(u.Height, 0.0);
  EXPECT_TRUE(DescribePhone("y").Rounded);
  EXPECT_FALSE(DescribePhone("i").Rounded);
  EXPECT_TRUE(DescribePhone("O~").Nasalized);
  EXPECT_TRUE(DescribePhone("p_h").ClosesLips());
  EXPECT_TRUE(DescribePhone("m").ClosesLips());
  EXPECT_FALSE(DescribePhone("f").ClosesLips());
  EXPECT_EQ(DescribePhone("f").Place, ArticulationPlace::Labiodental);
  EXPECT_EQ(DescribePhone("tS").Manner, ArticulationManner::Affricate);
  EXPECT_EQ(DescribePhone("t`").Place, ArticulationPlace::Retroflex);
  EXPECT_EQ(DescribePhone("_").Type, Articulation::Kind::Pause);
  EXPECT_FALSE(DescribePhone("Xq").IsKnown());
  EXPECT_EQ(SplitPhone("aI"), (std::vector<std::string>{ "a", "I" }));
  EXPECT_EQ(SplitPhone("aU@"), (std::vector<std::string>{ "a", "U", "@" }));
  EXPECT_EQ(SplitPhone("pf"), (std::vector<std::string>{ "p", "f" }));
  EXPECT_EQ(SplitPhone("ja"), (std::vector<std::string>{ "j", "a" }));
  EXPECT_EQ(SplitPhone("tS"), (std::vector<std::string>{ "tS" }));
  EXPECT_TRUE(SplitPhone("Xq").empty()); // two consonants are no phone
  EXPECT_TRUE(SplitPhone("zz9").empty());
}

TEST(Articulation, EspeakMnemonicsOfOtherLanguages)
{
  EXPECT_EQ(EspeakMnemonicToXSampa("W"), "9");   // œ
  EXPECT_EQ(EspeakMnemonicToXSampa("Y:"), "2:"); // ø:
  EXPECT_EQ(EspeakMnemonicToXSampa("n^"), "J");
  EXPECT_EQ(EspeakMnemonicToXSampa("t."), "t`");
  EXPECT_EQ(EspeakMnemonicToXSampa("S;"), "s\\");
  EXPECT_EQ(EspeakMnemonicToXSampa("tS;h"), "tS");
  EXPECT_EQ(EspeakMnemonicToXSampa("u-:"), "u:");
  EXPECT_EQ(EspeakMnemonicToXSampa("?E"), "E");
  EXPECT_EQ(EspeakMnemonicToXSampa("_:"), "_");
  EXPECT_EQ(EspeakMnemonicToXSampa(":"), "_"); // a lone mark joins the previous phoneme
  EXPECT_EQ(EspeakMnemonicToXSampa("y", "fr"), "y");
  EXPECT_EQ(EspeakMnemonicToXSampa("y", "pl"), "1"); // Polish y is unrounded
  EXPECT_TRUE(HasSampaTables("en-us"));
  EXPECT_TRUE(HasSampaTables("de+f2"));
  EXPECT_FALSE(HasSampaTables("fr"));
  EXPECT_FALSE(HasSampaTables("eu")); // Basque, not English
}

TEST(Articulation, TablesFindTheNearestPhoneme)
{
  const VisemeMap oculus = VisemeMap::Builtin(VisemeSet::Oculus15, "fr");
  EXPECT_EQ(oculus.GetVoice(), "fr");
  std::vector<std::string> warnings;
  const WarningHandler warn = CollectWarnings(warnings);
  EXPECT_EQ(oculus.MapPhonemeName("u", warn), "ou"); // French ou
  EXPECT_EQ(oculus.MapPhonemeName("y", warn), "ou"); // French u: rounded
  EXPECT_EQ(oculus.MapPhonemeName("o~", warn), oculus.MapPhonemeName("o", warn));
  EXPECT_EQ(oculus.MapPhonemeName("i", warn), "ih");
  EXPECT_EQ(oculus.MapPhonemeName("a", warn), "aa");
  EXPECT_EQ(oculus.MapPhonemeName("B", warn), "PP"); // Spanish β: lips
  EXPECT_EQ(oculus.MapPhonemeName("p_h", warn), "PP");
  EXPECT_TRUE(oculus.IsClosurePhoneme("p_h"));
  EXPECT_FALSE(oculus.IsClosurePhoneme("B"));
  EXPECT_EQ(oculus.MapPhonemeName("v\\", warn), "FF"); // ʋ
  EXPECT_EQ(oculus.MapPhonemeName("x", warn), "kk");
  EXPECT_EQ(oculus.MapPhonemeName("s`", warn), "CH");
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const VisemeMap german = VisemeMap::Builtin(VisemeSet::German16, "fr");
  EXPECT_EQ(german.MapPhonemeName("y", warn), "Y");
  EXPECT_EQ(german.MapPhonemeName("u", warn), "U");
  // A table's own entries win: the German table's R stays what it says.
  const VisemeMap de = VisemeMap::Builtin(VisemeSet::German16, "de");
  EXPECT_EQ(de.MapPhoneme("R"), de.GetPhonemeTable().at("R"));
  // Diphthongs are sequences: English aI opens, then closes to ih.
  const VisemeMap en = VisemeMap::Builtin(VisemeSet::Oculus15, "en");
  const auto parts = en.MapPhonemeParts("aI");
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(en.GetVisemes()[parts[0].Viseme], "aa");
  EXPECT_EQ(en.GetVisemes()[parts[1].Viseme], "ih");
  EXPECT_DOUBLE_EQ(parts[0].Fraction + parts[1].Fraction, 1.0);
  const auto pf = VisemeMap::Builtin(VisemeSet::Oculus15, "de").MapPhonemeParts("pf");
  ASSERT_EQ(pf.size(), 2u);
  EXPECT_TRUE(pf[0].Closure);
  EXPECT_EQ(en.GetVisemes()[pf[1].Viseme], "FF");
  // Unknown stays a warning naming the phoneme and the voice.
  warnings.clear();
  EXPECT_EQ(oculus.MapPhonemeName("Xq", warn), oculus.GetFallback());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'Xq'"), std::string::npos);
  EXPECT_NE(warnings[0].find("voice fr"), std::string::npos) << warnings[0];
}

TEST(Articulation, EveryEspeakVoiceSpeaksWithoutAnUnmappedPhoneme)
{
  if (!SpeechSynthesizer::IsAvailable())
  {
    GTEST_SKIP() << "built without eSpeak NG";
  }
  const std::vector<std::string> voices = SpeechSynthesizer::ListVoices();
  ASSERT_GE(voices.size(), 100u); // espeak-ng --voices lists 131 in eSpeak NG 1.51
  std::map<std::string, std::vector<std::string>> unmapped;
  for (const std::string& voice : voices)
  {
    SpeechOptions options;
    options.Voice = voice;
    std::vector<std::string> warnings;
    options.Warn = CollectWarnings(warnings);
    SpeechSynthesizer synthesizer(voice);
    synthesizer.SetEstimatePitch(false);
    // Numbers are spoken in each language's own words, whatever its script.
    const SynthesisResult r =
      synthesizer.Synthesize("1 2 3 4 5 6 7 8 9 10 11 12 20 100. Hello, good morning!");
    EXPECT_GT(r.Phonemes.size(), 10u) << voice;
    const VisemeMap map = SelectVisemeMap(options);
    for (const TimedPhoneme& p : r.Phonemes)
    {
      map.MapPhonemeParts(p.Sampa, options.Warn);
    }
    if (!warnings.empty())
    {
      unmapped[voice] = warnings;
    }
  }
  for (const auto& [voice, warnings] : unmapped)
  {
    ADD_FAILURE() << voice << ": " << warnings.front();
  }
}

/// Sentences with a rounded vowel, a bilabial and a labiodental each.
class LipsInLanguage : public ::testing::TestWithParam<std::pair<const char*, const char*>>
{
};

TEST_P(LipsInLanguage, RoundCloseAndBite)
{
  if (!SpeechSynthesizer::IsAvailable())
  {
    GTEST_SKIP() << "built without eSpeak NG";
  }
  const auto [voice, text] = GetParam();
  SpeechOptions options;
  options.Voice = voice;
  std::vector<std::string> warnings;
  options.Warn = CollectWarnings(warnings);
  const Utterance u = SpeakText(text, options);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  // Bilabials close the lips fully, labiodentals bite, rounded vowels round.
  EXPECT_GE(MaxWeight(u.Visemes, "PP"), 0.999) << voice;
  EXPECT_GE(MaxWeight(u.Visemes, "FF"), 0.5) << voice;
  EXPECT_GE(std::max(MaxWeight(u.Visemes, "ou"), MaxWeight(u.Visemes, "oh")), 0.5) << voice;
  // And unrounded front vowels do not: the phonemes themselves.
  const VisemeMap map = SelectVisemeMap(options);
  bool rounded = false, spread = false;
  for (const TimedPhoneme& p : u.Phonemes)
  {
    const std::vector<std::string> parts = SplitPhone(p.Sampa);
    if (parts.size() != 1)
    {
      continue;
    }
    const Articulation a = DescribePhone(parts[0]);
    if (a.Type != Articulation::Kind::Vowel)
    {
      continue;
    }
    const std::string& viseme = map.MapPhonemeName(p.Sampa);
    if (a.Rounded)
    {
      rounded = true;
      EXPECT_TRUE(viseme == "ou" || viseme == "oh") << voice << " " << p.Sampa << " -> " << viseme;
    }
    else if (a.Backness < 0.3)
    {
      spread = true;
      EXPECT_TRUE(viseme != "ou" && viseme != "oh") << voice << " " << p.Sampa << " -> " << viseme;
    }
  }
  EXPECT_TRUE(rounded) << voice;
  EXPECT_TRUE(spread) << voice;
}

INSTANTIATE_TEST_SUITE_P(Languages, LipsInLanguage,
  ::testing::Values(std::make_pair("fr", "Vous avez bu du beau vin, mon ami."),
    std::make_pair("es", "Un buen vino fuerte para Pablo y su amigo."),
    std::make_pair("it", "Il lupo buono beve vino fuori con Paolo."),
    std::make_pair("pt", "O bom vinho fica para o povo da vila."),
    std::make_pair("nl", "De boer fietst voor de molen met zijn vriend."),
    std::make_pair("pl", "Mój brat pije wodę w fabryce i mówi dużo."),
    std::make_pair("sv", "Fem bullar och ost på bordet i kväll."),
    std::make_pair("fi", "Vuori on pieni ja puu on vanha, sanoi isä."),
    std::make_pair("tr", "Bu ufak köpek vapurda oturuyor, bence iyi."),
    std::make_pair("cs", "Pes bude vařit polévku pro mého bratra.")),
  [](const auto& info) { return std::string(info.param.first); });
