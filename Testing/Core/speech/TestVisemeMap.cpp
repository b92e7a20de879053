// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "speech/Coarticulation.h"
#include "speech/Sampa.h"
#include "speech/VisemeMap.h"

#include <gtest/gtest.h>

#include <fstream>

using namespace morphnode;

namespace
{
const VisemeSet AllSets[] = { VisemeSet::Oculus15, VisemeSet::German16, VisemeSet::Paper6 };

std::string DataFile(VisemeSet set, const std::string& language)
{
  return std::string(MORPHNODE_SOURCE_DIR) + "/Modules/Core/speech/data/visemes_" +
    VisemeSetName(set) + "_" + language + ".json";
}
} // namespace

TEST(VisemeMap, BuiltinTablesHaveTheDocumentedVisemes)
{
  const std::vector<std::string> oculus = { "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn",
    "RR", "aa", "E", "ih", "oh", "ou" };
  const std::vector<std::string> german = { "sil", "P", "M", "F", "S", "Z", "T", "L", "R", "K", "A",
    "O", "U", "E", "Y", "Q" };
  const std::vector<std::string> paper = { "sil", "A", "E", "O", "S", "F", "L" };
  for (const char* language : { "de", "en" })
  {
    EXPECT_EQ(VisemeMap::Builtin(VisemeSet::Oculus15, language).GetVisemes(), oculus);
    EXPECT_EQ(VisemeMap::Builtin(VisemeSet::German16, language).GetVisemes(), german);
    EXPECT_EQ(VisemeMap::Builtin(VisemeSet::Paper6, language).GetVisemes(), paper);
  }
}

TEST(VisemeMap, German16GroupsAfterAschenbernerAndWeiss)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::German16, "de");
  const std::vector<std::pair<std::string, std::string>> groups = { { "P", "p b" }, { "M", "m" },
    { "F", "f v pf" }, { "S", "s z ts" }, { "Z", "S Z tS dZ" }, { "T", "t d n" }, { "L", "l" },
    { "R", "R r" }, { "K", "k g N x C j h ?" }, { "A", "a a: aI aU" }, { "O", "o: O OY" },
    { "U", "u: U" }, { "E", "i: I e: E: E" }, { "Y", "y: Y 2: 9" }, { "Q", "@ 6" },
    { "sil", "_" } };
  for (const auto& [viseme, phonemes] : groups)
  {
    std::istringstream list(phonemes);
    std::string p;
    while (list >> p)
    {
      EXPECT_EQ(map.MapPhonemeName(p), viseme) << p;
    }
  }
}

TEST(VisemeMap, EveryPhonemeOfTheLanguageIsMappedWithoutWarning)
{
  const std::vector<std::string> german = { "p", "b", "t", "d", "k", "g", "?", "pf", "ts", "tS",
    "dZ", "f", "v", "s", "z", "S", "Z", "C", "j", "x", "h", "m", "n", "N", "l", "R", "I", "E", "a",
    "O", "U", "Y", "9", "i:", "e:", "E:", "a:", "o:", "u:", "y:", "2:", "aI", "aU", "OY", "@",
    "6" };
  const std::vector<std::string> english = { "p", "b", "t", "d", "k", "g", "tS", "dZ", "f", "v",
    "T", "D", "s", "z", "S", "Z", "h", "m", "n", "N", "r", "l", "w", "j", "I", "e", "{", "Q", "V",
    "U", "@", "i:", "eI", "aI", "OI", "u:", "@U", "aU", "I@", "e@", "U@", "A:", "O:", "3:", "5" };
  for (VisemeSet set : AllSets)
  {
    for (const auto& [language, inventory] :
      { std::make_pair("de", german), std::make_pair("en", english) })
    {
      const VisemeMap map = VisemeMap::Builtin(set, language);
      std::vector<std::string> warnings;
      for (const auto& p : inventory)
      {
        EXPECT_TRUE(IsSampaPhoneme(p, language)) << p;
        map.MapPhoneme(p, CollectWarnings(warnings));
      }
      EXPECT_TRUE(warnings.empty())
        << VisemeSetName(set) << "/" << language << ": " << warnings.front();
      EXPECT_EQ(map.GetLanguage(), language);
      for (const char* bilabial : { "p", "b", "m" })
      {
        EXPECT_TRUE(map.IsClosurePhoneme(bilabial));
      }
      EXPECT_FALSE(map.IsClosurePhoneme("f"));
    }
  }
}

TEST(VisemeMap, UnknownPhonemeWarnsByNameAndUsesTheFallback)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, "en");
  std::vector<std::string> warnings;
  EXPECT_EQ(map.MapPhonemeName("Xq", CollectWarnings(warnings)), "E");
  EXPECT_EQ(map.GetFallback(), "E");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'Xq'"), std::string::npos) << warnings[0];
  // Without a handler it is silent, never a crash; pauses are never unknown.
  EXPECT_EQ(map.MapPhonemeName("Xq"), "E");
  EXPECT_EQ(map.MapPhonemeName("_:", CollectWarnings(warnings)), "sil");
  EXPECT_EQ(warnings.size(), 1u);
  // Through the segment mapping: one warning per unknown name, however often it occurs.
  warnings.clear();
  const auto segments = PhonemesToVisemeSegments({ { "Xq", 0.0, 0.1, {} }, { "a:", 0.1, 0.1, {} },
                                                   { "Xq", 0.2, 0.1, {} }, { "Yq", 0.3, 0.1, {} } },
    VisemeMap::Builtin(VisemeSet::German16, "de"), CollectWarnings(warnings));
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("'Xq'"), std::string::npos);
  EXPECT_NE(warnings[1].find("'Yq'"), std::string::npos);
  EXPECT_EQ(segments[0].Viseme, VisemeMap::Builtin(VisemeSet::German16, "de").FindViseme("Q"));
}

TEST(VisemeMap, DataFilesAreTheBuiltinTables)
{
  for (VisemeSet set : AllSets)
  {
    for (const char* language : { "de", "en" })
    {
      const VisemeMap file = VisemeMap::Load(DataFile(set, language));
      const VisemeMap builtin = VisemeMap::Builtin(set, language);
      EXPECT_EQ(file.GetVisemes(), builtin.GetVisemes());
      EXPECT_EQ(file.GetPhonemeTable(), builtin.GetPhonemeTable());
      EXPECT_EQ(file.GetSetName(), VisemeSetName(set));
      for (size_t v = 0; v < file.GetVisemes().size(); ++v)
      {
        EXPECT_EQ(file.GetRhubarbShape(int(v)), builtin.GetRhubarbShape(int(v)));
        EXPECT_DOUBLE_EQ(file.GetDominance(int(v)), builtin.GetDominance(int(v)));
      }
    }
  }
}

TEST(VisemeMap, OverrideFileAndMalformedTables)
{
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/speech_custom_visemes.json";
  {
    std::ofstream out(path);
    out << R"({"set": "mine", "visemes": ["rest", "open", "closed"], "silence": "rest",
      "fallback": "open", "phonemes": {"a:": "open", "m": "closed"}, "dominance": {"closed": 2}})";
  }
  const VisemeMap map = VisemeMap::Load(path);
  EXPECT_EQ(map.GetSetName(), "mine");
  EXPECT_EQ(map.MapPhonemeName("m"), "closed");
  EXPECT_EQ(map.MapPhonemeName("_"), "rest");
  EXPECT_EQ(map.MapPhonemeName("o:"), "open");
  EXPECT_DOUBLE_EQ(map.GetDominance(2), 2.0);
  EXPECT_TRUE(map.IsClosurePhoneme("m")); // default closure phonemes

  const char* bad[] = {
    "not json",
    "[]",
    R"({"visemes": [], "silence": "a", "fallback": "a", "phonemes": {}})",
    R"({"visemes": ["a", "a"], "silence": "a", "fallback": "a", "phonemes": {}})",
    R"({"visemes": ["a"], "silence": "b", "fallback": "a", "phonemes": {}})",
    R"({"visemes": ["a"], "silence": "a", "fallback": "a", "phonemes": {"p": "zz"}})",
    R"({"visemes": ["a"], "silence": "a", "fallback": "a", "phonemes": {"p": 3}})",
    R"({"visemes": ["a"], "silence": "a", "fallback": "a", "phonemes": {}, "dominance": {"a": -1}})",
    R"({"visemes": ["a"], "silence": "a", "fallback": "a", "phonemes": {}, "rhubarb": {"toShape": {"a": "Q"}, "fromShape": {}}})",
    R"({"visemes": ["a", "b"], "silence": "a", "fallback": "a", "phonemes": {}, "rhubarb": {"toShape": {"a": "X"}, "fromShape": {}}})",
  };
  for (const char* text : bad)
  {
    EXPECT_THROW(VisemeMap::FromJson(text, "test table"), InputError) << text;
  }
  EXPECT_THROW(VisemeMap::Load("/nonexistent.json"), InputError);
  EXPECT_THROW(ParseVisemeSet("mpeg4"), InputError);
  EXPECT_EQ(ParseVisemeSet("German16"), VisemeSet::German16);
}
