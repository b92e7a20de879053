// SPDX-License-Identifier: BSD-3-Clause
// Timings from other tools: Praat TextGrids (MFA), speech-mark JSON lines (Polly), phone
// alphabets, and the one loader behind the behaviour control, scripts and the apps.
#include "MorphNodeTestErrors.h"
#include "base/Error.h"
#include "speech/PhoneSets.h"
#include "speech/Sampa.h"
#include "speech/ServiceTimings.h"
#include "speech/SpeechMarks.h"
#include "speech/SpeechSynthesizer.h"
#include "speech/TextGrid.h"
#include "speech/TimingFiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>

using namespace morphnode;

using morphnode_test::ErrorOf;

namespace
{
// What the Montreal Forced Aligner writes (english_us_arpa): long text format.
const char* LongGrid = R"(File type = "ooTextFile"
Object class = "TextGrid"

xmin = 0 
xmax = 1.2 
tiers? <exists> 
size = 2 
item []: 
    item [1]:
        class = "IntervalTier" 
        name = "words" 
        xmin = 0 
        xmax = 1.2 
        intervals: size = 2 
        intervals [1]:
            xmin = 0 
            xmax = 0.1 
            text = "" 
        intervals [2]:
            xmin = 0.1 
            xmax = 1.0 
            text = "bee moo" 
    item [2]:
        class = "IntervalTier" 
        name = "phones" 
        xmin = 0 
        xmax = 1.2 
        intervals: size = 5 
        intervals [1]:
            xmin = 0 
            xmax = 0.1 
            text = "sil" 
        intervals [2]:
            xmin = 0.1 
            xmax = 0.3 
            text = "B" 
        intervals [3]:
            xmin = 0.3 
            xmax = 0.5 
            text = "IY1" 
        intervals [4]:
            xmin = 0.5 
            xmax = 0.7 
            text = "M" 
        intervals [5]:
            xmin = 0.7 
            xmax = 1.0 
            text = "UW1" 
)";

// The same phone tier in Praat's short text format, with IPA labels and a point tier.
const char* ShortGrid = R"(File type = "ooTextFile"
Object class = "TextGrid"

0
1.2
<exists>
2
"TextTier"
"accents"
0
1.2
1
0.4
"H*"
"IntervalTier"
"phones"
0
1.2
4
0.1
0.3
"b"
0.3
0.5
"iː"
0.5
0.7
"m"
0.7
1.0
"uː"
)";

std::vector<std::string> Names(const std::vector<TimedPhoneme>& phonemes)
{
  std::vector<std::string> names;
  for (const auto& p : phonemes)
  {
    names.push_back(p.Sampa);
  }
  return names;
}

std::string Utf16(const std::string& ascii, bool littleEndian)
{
  std::string out = littleEndian ? std::string("\xFF\xFE", 2) : std::string("\xFE\xFF", 2);
  for (char c : ascii)
  {
    out += littleEndian ? std::string{ c, '\0' } : std::string{ '\0', c };
  }
  return out;
}

const std::vector<std::string> BeeMoo = { "_", "b", "i:", "m", "u:", "_" };
} // namespace

TEST(TextGrid, LongFormatPhoneTierInArpabet)
{
  const TextGrid grid = ParseTextGrid(LongGrid);
  ASSERT_EQ(grid.Tiers.size(), 2u);
  EXPECT_EQ(grid.Tiers[0].Name, "words");
  EXPECT_EQ(grid.Tiers[1].Items[2].Text, "IY1");
  const auto phonemes = TextGridPhonemes(grid);
  EXPECT_EQ(Names(phonemes), BeeMoo);
  EXPECT_DOUBLE_EQ(phonemes[1].Start, 0.1);
  EXPECT_DOUBLE_EQ(phonemes[1].Duration, 0.2);
  EXPECT_DOUBLE_EQ(phonemes.back().Start, 1.0); // the gap to the grid's end is a pause
  EXPECT_NEAR(phonemes.back().Duration, 0.2, 1e-12);
}

TEST(TextGrid, ShortFormatWithIpaAndAPointTier)
{
  const TextGrid grid = ParseTextGrid(ShortGrid);
  ASSERT_EQ(grid.Tiers.size(), 2u);
  EXPECT_FALSE(grid.Tiers[0].IsInterval);
  EXPECT_EQ(grid.Tiers[0].Items[0].Text, "H*");
  EXPECT_EQ(Names(TextGridPhonemes(grid)), BeeMoo); // leading gap from 0 becomes `_`
}

TEST(TextGrid, Utf16BothByteOrders)
{
  for (bool le : { true, false })
  {
    const TextGrid grid = ParseTextGrid(Utf16(LongGrid, le));
    EXPECT_EQ(Names(TextGridPhonemes(grid)), BeeMoo) << (le ? "LE" : "BE");
  }
  // Non-ASCII in UTF-16: "ʃ" (U+0283) survives as UTF-8.
  std::string grid =
    Utf16(std::string(ShortGrid).replace(std::string(ShortGrid).find("\"b\""), 3, "\"#\""), true);
  const size_t hash = grid.find(std::string("#\0", 2));
  ASSERT_NE(hash, std::string::npos);
  grid[hash] = '\x83';
  grid[hash + 1] = '\x02';
  EXPECT_EQ(TextGridPhonemes(ParseTextGrid(grid))[1].Sampa, "S");
}

TEST(TextGrid, NamedTierAndAlphabetOptions)
{
  TextGridPhoneOptions options;
  options.TierName = "WORDS";
  options.Alphabet = PhoneAlphabet::Sampa;
  const auto words = TextGridPhonemes(ParseTextGrid(LongGrid), options);
  EXPECT_EQ(words[1].Sampa, "bee moo");
}

TEST(TextGrid, BadFilesAreClearErrors)
{
  // No phone tier: the message names the tiers there are.
  std::string noPhones = LongGrid;
  noPhones.replace(noPhones.find("\"phones\""), 8, "\"tones\"");
  const std::string e1 = ErrorOf([&] { TextGridPhonemes(ParseTextGrid(noPhones)); });
  EXPECT_NE(e1.find("no phone tier"), std::string::npos) << e1;
  EXPECT_NE(e1.find("'tones'"), std::string::npos) << e1;
  // Intervals out of order.
  std::string disorder = ShortGrid;
  disorder.replace(disorder.find("0.5\n0.7\n\"m\""), 11, "0.2\n0.7\n\"m\"");
  const std::string e2 = ErrorOf([&] { ParseTextGrid(disorder); });
  EXPECT_NE(e2.find("out of order"), std::string::npos) << e2;
  // An interval that ends before it starts, a time outside the grid.
  std::string backwards = ShortGrid;
  backwards.replace(backwards.find("0.7\n1.0\n"), 8, "0.7\n0.6\n");
  EXPECT_NE(ErrorOf([&] { ParseTextGrid(backwards); }).find("before it starts"), std::string::npos);
  std::string outside = ShortGrid;
  outside.replace(outside.find("0.7\n1.0\n"), 8, "0.7\n9.0\n");
  EXPECT_NE(ErrorOf([&] { ParseTextGrid(outside); }).find("outside the grid"), std::string::npos);
  // Truncated, binary, other classes, lying counts.
  const std::string whole = LongGrid;
  EXPECT_NE(ErrorOf([&] { ParseTextGrid(whole.substr(0, whole.size() / 2)); }).find("ends before"),
    std::string::npos);
  EXPECT_NE(
    ErrorOf([&] { ParseTextGrid("ooBinaryFile\x08TextGrid"); }).find("binary"), std::string::npos);
  EXPECT_THROW(ParseTextGrid("File type = \"ooTextFile\"\nObject class = \"Sound\"\n"), InputError);
  EXPECT_THROW(ParseTextGrid(""), InputError);
  std::string lying = ShortGrid;
  lying.replace(lying.find("\"phones\"\n0\n1.2\n4\n"), 17, "\"phones\"\n0\n1.2\n4000000000\n");
  EXPECT_THROW(ParseTextGrid(lying), InputError);
  // Only silence in the phone tier.
  const char* silent =
    "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n0\n1\n<exists>\n1\n"
    "\"IntervalTier\"\n\"phones\"\n0\n1\n1\n0\n1\n\"sil\"\n";
  EXPECT_NE(ErrorOf([&] { TextGridPhonemes(ParseTextGrid(silent)); }).find("holds no phones"),
    std::string::npos);
}

TEST(SpeechMarks, PollyVisemesAndWords)
{
  const SpeechMarks marks = ParseSpeechMarks(
    "{\"time\":0,\"type\":\"sentence\",\"start\":0,\"end\":7,\"value\":\"Bee moo\"}\n"
    "{\"time\":50,\"type\":\"word\",\"start\":0,\"end\":3,\"value\":\"Bee\"}\n"
    "{\"time\":50,\"type\":\"viseme\",\"value\":\"p\"}\n"
    "{\"time\":150,\"type\":\"viseme\",\"value\":\"i\"}\n"
    "{\"time\":350,\"type\":\"word\",\"start\":4,\"end\":7,\"value\":\"moo\"}\n"
    "{\"time\":350,\"type\":\"viseme\",\"value\":\"p\"}\n"
    "{\"time\":450,\"type\":\"viseme\",\"value\":\"u\"}\n"
    "{\"time\":700,\"type\":\"viseme\",\"value\":\"sil\"}\n");
  EXPECT_EQ(Names(marks.Phonemes), (std::vector<std::string>{ "_", "p", "i:", "p", "u:", "_" }));
  EXPECT_DOUBLE_EQ(marks.Phonemes[1].Start, 0.05);
  EXPECT_DOUBLE_EQ(marks.Phonemes[2].Duration, 0.2);
  ASSERT_EQ(marks.Words.size(), 2u);
  EXPECT_EQ(marks.Words[1].Text, "moo");
  EXPECT_DOUBLE_EQ(marks.Words[1].Start, 0.35);
  EXPECT_NEAR(marks.Duration, 0.85, 1e-12);
}

TEST(SpeechMarks, PhonemeEventsInArpabetOrIpa)
{
  const SpeechMarks arpa =
    ParseSpeechMarks("{\"time\":0,\"type\":\"phoneme\",\"value\":\"M\"}\n{\"time\":100,\"type\":"
                     "\"phoneme\",\"value\":\"UW1\"}\n");
  EXPECT_EQ(Names(arpa.Phonemes), (std::vector<std::string>{ "m", "u:" }));
  SpeechMarkOptions german;
  german.Language = "de";
  const SpeechMarks ipa = ParseSpeechMarks("{\"time\":0,\"type\":\"phoneme\",\"value\":\"ʁ\"}\n{"
                                           "\"time\":100,\"type\":\"phoneme\",\"value\":\"yː\"}\n",
    german);
  EXPECT_EQ(Names(ipa.Phonemes), (std::vector<std::string>{ "R", "y:" }));
}

TEST(SpeechMarks, BadInputIsAClearError)
{
  EXPECT_NE(ErrorOf(
              []
              {
                ParseSpeechMarks("{\"time\":100,\"type\":\"viseme\",\"value\":\"p\"}\n{\"time\":50,"
                                 "\"type\":\"viseme\",\"value\":\"t\"}\n");
              })
              .find("out of order"),
    std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSpeechMarks("{\"time\":0,\"type\":\"viseme\",\"value\":\"Q\"}\n"); })
              .find("unknown viseme"),
    std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSpeechMarks("{\"time\":0,\"type\":\"word\",\"value\":\"hi\"}\n"); })
              .find("no viseme or phoneme"),
    std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSpeechMarks("[1,2]\n"); }).find("line 1"), std::string::npos);
  EXPECT_THROW(ParseSpeechMarks("{\"time\":-5,\"type\":\"viseme\",\"value\":\"p\"}\n"), InputError);
  EXPECT_THROW(ParseSpeechMarks("{\"type\":\"viseme\",\"value\":\"p\"}\n"), InputError);
  EXPECT_THROW(ParseSpeechMarks(""), InputError);
}

TEST(PhoneSets, ArpabetIpaAndTheGuess)
{
  EXPECT_EQ(ArpabetToSampa("AH0"), "@");
  EXPECT_EQ(ArpabetToSampa("AH1"), "V");
  EXPECT_EQ(ArpabetToSampa("OW2"), "@U");
  EXPECT_EQ(ArpabetToSampa("TH"), "T");
  EXPECT_EQ(ArpabetToSampa("sil"), "_");
  EXPECT_EQ(IpaToSampa("t͡ʃ", "en"), "tS");
  EXPECT_EQ(IpaToSampa("ɹ", "en"), "r");
  EXPECT_EQ(IpaToSampa("oʊ", "en"), "@U");
  EXPECT_EQ(IpaToSampa("pʰ", "en"), "p");
  EXPECT_EQ(IpaToSampa("ʁ", "de"), "R");
  EXPECT_EQ(IpaToSampa("øː", "de"), "2:");
  EXPECT_EQ(GuessPhoneAlphabet({ "sil", "HH", "AH0", "L", "OW1" }), PhoneAlphabet::Arpabet);
  EXPECT_EQ(GuessPhoneAlphabet({ "h", "@", "l", "@U" }), PhoneAlphabet::Sampa);
  EXPECT_EQ(GuessPhoneAlphabet({ "h", "ə", "l" }), PhoneAlphabet::Ipa);
  EXPECT_EQ(ParsePhoneAlphabet("ARPAbet"), PhoneAlphabet::Arpabet);
  EXPECT_THROW(ParsePhoneAlphabet("klingon"), InputError);
}

TEST(TimingFiles, EveryFormatThroughOneLoader)
{
  const std::string dir = MORPHNODE_TEST_OUTPUT_DIR;
  const auto write = [&](const std::string& name, const std::string& content)
  {
    std::ofstream(dir + "/" + name, std::ios::binary) << content;
    return dir + "/" + name;
  };
  const std::string grid = write("timing.TextGrid", LongGrid);
  const std::string marks = write("timing.marks",
    "{\"time\":100,\"type\":\"viseme\",\"value\":\"p\"}\n{\"time\":300,\"type\":\"viseme\","
    "\"value\":\"u\"}\n");
  const std::string pho = write("timing.pho", "_ 100\nb 200\ni: 200\nm 200\nu: 300\n_ 200\n");
  const std::string tsv = write("timing.tsv", "0.00\tX\n0.10\tA\n0.30\tF\n0.60\tX\n");
  const std::string json = write("timing.json",
    "{\"metadata\":{\"soundFile\":\"\",\"duration\":0.6},\"mouthCues\":[{\"start\":0.0,\"end\":0.1,"
    "\"value\":\"X\"},{\"start\":0.1,\"end\":0.6,\"value\":\"A\"}]}");
  // Content sniffing when the extension does not tell.
  const std::string gridTxt = write("timing_grid.txt", LongGrid);
  EXPECT_EQ(GuessTimingFormat(gridTxt, LongGrid), TimingFormat::TextGrid);
  EXPECT_EQ(GuessTimingFormat("x.json", "{\"time\":1,\"type\":\"viseme\",\"value\":\"p\"}"),
    TimingFormat::SpeechMarks);

  SpeechOptions speech;
  for (const std::string& path : { grid, marks, pho, tsv, json, gridTxt })
  {
    const Utterance u = LoadTimingFile(path, speech);
    EXPECT_GT(u.Duration, 0.4) << path;
    EXPECT_GT(u.Visemes.GetNumberOfFrames(), 10u) << path;
    // The bilabial closure reaches full weight somewhere in every file.
    const int pp = u.Visemes.FindChannel("PP");
    ASSERT_GE(pp, 0);
    double maxPP = 0.0;
    for (size_t f = 0; f < u.Visemes.GetNumberOfFrames(); ++f)
    {
      maxPP = std::max(maxPP, u.Visemes.GetFrame(f)[pp]);
    }
    EXPECT_GT(maxPP, 0.99) << path;
  }
  EXPECT_EQ(Names(LoadTimedPhonemes(grid, "en")), BeeMoo);
  EXPECT_THROW(LoadTimedPhonemes(tsv, "en"), InputError);
  EXPECT_THROW(LoadTimingFile(dir + "/no-such.TextGrid", speech), InputError);
  const std::string unknown = write("timing.xyz", "hello\n");
  EXPECT_NE(
    ErrorOf([&] { LoadTimingFile(unknown, speech); }).find("cannot tell"), std::string::npos);
  EXPECT_EQ(ParseTimingFormat("TextGrid"), TimingFormat::TextGrid);
}

// Polly's viseme tables of other languages: Spanish "bebé", "sayo", "llave" bring B and J,
// English "l" its own viseme. They read, and the Spanish mouth follows them: B near closed
// lips (a bilabial), J not.
TEST(SpeechMarks, PollyVisemesOfEveryLanguage)
{
  SpeechMarkOptions spanish;
  spanish.Language = "es";
  const SpeechMarks marks =
    ParseSpeechMarks("{\"time\":0,\"type\":\"word\",\"start\":0,\"end\":4,\"value\":\"bebé\"}\n"
                     "{\"time\":0,\"type\":\"viseme\",\"value\":\"p\"}\n"
                     "{\"time\":80,\"type\":\"viseme\",\"value\":\"e\"}\n"
                     "{\"time\":180,\"type\":\"viseme\",\"value\":\"B\"}\n"
                     "{\"time\":300,\"type\":\"viseme\",\"value\":\"e\"}\n"
                     "{\"time\":420,\"type\":\"viseme\",\"value\":\"J\"}\n"
                     "{\"time\":540,\"type\":\"viseme\",\"value\":\"a\"}\n"
                     "{\"time\":700,\"type\":\"viseme\",\"value\":\"sil\"}\n",
      spanish);
  EXPECT_EQ(
    Names(marks.Phonemes), (std::vector<std::string>{ "p", "e", "B", "e", "j\\", "A:", "_" }));
  SpeechOptions speech;
  speech.Voice = "es";
  std::vector<std::string> warnings;
  speech.Warn = [&](const std::string& w) { warnings.push_back(w); };
  const Utterance u = UtteranceFromPhonemes(marks.Phonemes, speech);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const VisemeMap map = SelectVisemeMap(speech);
  EXPECT_EQ(map.MapPhonemeName("B"), "PP");
  EXPECT_NE(map.MapPhonemeName("j\\"), "PP");
  EXPECT_EQ(PollyVisemeToSampa("l"), "l");
  EXPECT_EQ(PollyVisemeToSampa("Q"), ""); // still no Polly viseme
}

// Azure's VisemeReceived events (AudioOffset in 100-ns ticks, VisemeId 0..21) as a program
// collects them: "Bob met Pam" closes at its bilabials.
TEST(ServiceTimings, AzureVisemeIds)
{
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/azure_visemes.json";
  std::ofstream(path)
    << R"([{"AudioOffset": 500000, "VisemeId": 0}, {"AudioOffset": 1000000, "VisemeId": 21},
    {"AudioOffset": 1800000, "VisemeId": 3}, {"AudioOffset": 2600000, "VisemeId": 21},
    {"AudioOffset": 3400000, "VisemeId": 0}])";
  const auto phonemes = LoadTimedPhonemes(path, "en");
  EXPECT_EQ(Names(phonemes), (std::vector<std::string>{ "_", "_", "p", "O:", "p", "_" }));
  EXPECT_DOUBLE_EQ(phonemes[2].Start, 0.1);
  EXPECT_NEAR(phonemes[2].Duration, 0.08, 1e-12);
  const Utterance u = LoadTimingFile(path);
  const int pp = u.Visemes.FindChannel("PP");
  ASSERT_GE(pp, 0);
  EXPECT_GT(u.Visemes.Sample(0.14 - 0.05, static_cast<size_t>(pp)), 0.9);
  // An object with "visemes", offsets in milliseconds, lower-case keys.
  EXPECT_EQ(
    Names(ParseAzureVisemes(
      R"({"visemes": [{"offsetMs": 0, "visemeId": 21}, {"offsetMs": 80, "visemeId": 6}]})")),
    (std::vector<std::string>{ "p", "i:" }));
  EXPECT_NE(ErrorOf([] { ParseAzureVisemes(R"([{"AudioOffset": 0, "VisemeId": 22}])"); })
              .find("not in 0..21"),
    std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseAzureVisemes(R"([{"AudioOffset": 0}])"); }).find("VisemeId"),
    std::string::npos);
  EXPECT_NE(ErrorOf(
              [] {
                ParseAzureVisemes(
                  R"([{"AudioOffset": 9, "VisemeId": 1}, {"AudioOffset": 1, "VisemeId": 1}])");
              })
              .find("event 1: starts before"),
    std::string::npos);
  EXPECT_NE(
    ErrorOf([] { ParseAzureVisemes(R"([{"AudioOffset": -1, "VisemeId": 1}])"); }).find(">= 0"),
    std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseAzureVisemes("[]"); }).find("no events"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseAzureVisemes("{"); }).find("not valid JSON"), std::string::npos);
}

// ElevenLabs-style character alignments ("with timestamps"): words from characters, read
// by eSpeak NG into the words' times: the bilabials of "Bob met Pam" close at their words.
TEST(ServiceTimings, CharacterAlignments)
{
  const std::string text = "Bob met Pam";
  std::string characters, starts, ends;
  for (size_t i = 0; i < text.size(); ++i)
  {
    characters += std::string(i ? ", " : "") + "\"" + text[i] + "\"";
    starts += std::string(i ? ", " : "") + std::to_string(0.2 + 0.08 * static_cast<double>(i));
    ends += std::string(i ? ", " : "") + std::to_string(0.28 + 0.08 * static_cast<double>(i));
  }
  const std::string json = R"({"audio_base64": "", "alignment": {"characters": [)" + characters +
    R"(], "character_start_times_seconds": [)" + starts + R"(], "character_end_times_seconds": [)" +
    ends + "]}}";
  const auto words = ParseCharacterAlignment(json);
  ASSERT_EQ(words.size(), 3u);
  EXPECT_EQ(words[2].Text, "Pam");
  EXPECT_NEAR(words[2].Start, 0.2 + 0.08 * 8, 1e-9);
  EXPECT_NEAR(words[2].End, 0.28 + 0.08 * 10, 1e-9);
  EXPECT_NE(
    ErrorOf(
      []
      {
        ParseCharacterAlignment(
          R"({"characters": ["a"], "character_start_times_seconds": [], "character_end_times_seconds": [1]})");
      })
      .find("1 characters, 0 start"),
    std::string::npos);
  EXPECT_NE(
    ErrorOf(
      []
      {
        ParseCharacterAlignment(
          R"({"characters": ["a", "b"], "character_start_times_seconds": [1, 0.5], "character_end_times_seconds": [1, 1]})");
      })
      .find("must not decrease"),
    std::string::npos);
  EXPECT_NE(
    ErrorOf(
      []
      {
        ParseCharacterAlignment(
          R"({"characters": [" "], "character_start_times_seconds": [0], "character_end_times_seconds": [1]})");
      })
      .find("no words"),
    std::string::npos);
  if (!SpeechSynthesizer::IsAvailable())
  {
    GTEST_SKIP() << "built without eSpeak NG: words are read by eSpeak NG";
  }
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/alignment.json";
  std::ofstream(path) << json;
  const auto phonemes = LoadTimedPhonemes(path, "en");
  ASSERT_GE(phonemes.size(), 8u);
  EXPECT_EQ(phonemes.front().Sampa, "_");
  // Each word's first phoneme starts with the word; b and p are there.
  for (const auto& w : words)
  {
    const auto at = std::find_if(phonemes.begin(), phonemes.end(),
      [&](const TimedPhoneme& p)
      { return std::abs(p.Start - w.Start) < 1e-9 && !IsPausePhoneme(p.Sampa); });
    EXPECT_NE(at, phonemes.end()) << w.Text;
  }
  EXPECT_EQ(
    std::count_if(phonemes.begin(), phonemes.end(),
      [](const TimedPhoneme& p) { return p.Sampa == "b" || p.Sampa == "p" || p.Sampa == "m"; }),
    5); // b b m p m
  EXPECT_NEAR(phonemes.back().Start + phonemes.back().Duration, words.back().End, 1e-9);
}
