// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Sampa.h"

#include "base/Text.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <unordered_map>

namespace morphnode
{
namespace
{
const std::set<std::string>& GermanInventory()
{
  static const std::set<std::string> inventory = { "p", "b", "t", "d", "k", "g", "?", "pf", "ts",
    "tS", "dZ", "f", "v", "s", "z", "S", "Z", "C", "j", "x", "h", "m", "n", "N", "l", "R", "r",
    "I", "E", "a", "O", "U", "Y", "9", "i:", "e:", "E:", "a:", "o:", "u:", "y:", "2:", "aI", "aU",
    "OY", "@", "6", "_" };
  return inventory;
}

const std::set<std::string>& EnglishInventory()
{
  static const std::set<std::string> inventory = { "p", "b", "t", "d", "k", "g", "?", "tS", "dZ",
    "f", "v", "T", "D", "s", "z", "S", "Z", "h", "m", "n", "N", "r", "l", "5", "w", "j", "I", "e",
    "{", "Q", "V", "U", "@", "i:", "eI", "aI", "OI", "u:", "@U", "aU", "I@", "e@", "U@", "A:",
    "O:", "3:", "_" };
  return inventory;
}

const std::set<std::string>& Vowels()
{
  static const std::set<std::string> vowels = { "I", "E", "a", "O", "U", "Y", "9", "i:", "e:",
    "E:", "a:", "o:", "u:", "y:", "2:", "aI", "aU", "OY", "@", "6", "e", "{", "Q", "V", "eI",
    "OI", "@U", "I@", "e@", "U@", "A:", "O:", "3:" };
  return vowels;
}

// eSpeak NG mnemonics that differ from SAMPA (checked against eSpeak NG 1.51 output).
const std::unordered_map<std::string, std::string>& GermanTable()
{
  static const std::unordered_map<std::string, std::string> table = { { "3", "6" },
    { "r", "R" }, { "A:", "a:" }, { "A", "a" }, { "OI", "OY" }, { "y", "Y" }, { "W", "9" },
    { "Y:", "2:" }, { "pF", "pf" }, { "i", "i:" }, { "e", "e:" }, { "o", "o:" }, { "u", "u:" }, { "eI", "e:" }, { "UR", "U" } };
  return table;
}

const std::unordered_map<std::string, std::string>& EnglishTable()
{
  static const std::unordered_map<std::string, std::string> table = { { "oU", "@U" },
    { "a", "{" }, { "0", "Q" }, { "E", "e" }, { "O", "O:" }, { "@L", "5" }, { "3", "@" },
    { "a#", "@" }, { "i", "i:" }, { "A@", "A:" }, { "aa", "A:" }, { "A", "A:" }, { "i@", "I@" },
    { "i@3", "I@" }, { "IR", "I@" }, { "O@", "O:" }, { "o@", "O:" }, { "aI@", "aI" },
    { "aU@", "aU" }, { "x", "k" } };
  return table;
}

bool IsVariantMark(char c)
{
  return c == '#' || c == '/' || c == '-' || c == ';' || c == '~' || std::isdigit(static_cast<unsigned char>(c));
}

/// Table then inventory; empty when neither knows the name.
std::string Lookup(const std::string& name, const std::string& language)
{
  const bool german = language == "de";
  const auto& table = german ? GermanTable() : EnglishTable();
  auto it = table.find(name);
  if (it != table.end())
  {
    return it->second;
  }
  return IsSampaPhoneme(name, language) ? name : std::string();
}
} // namespace

std::string SpeechLanguageOf(const std::string& voice)
{
  const std::string prefix = text::ToLower(voice.substr(0, 2));
  return prefix == "de" ? "de" : "en";
}

bool IsPausePhoneme(const std::string& sampa)
{
  return !sampa.empty() && sampa[0] == '_';
}

bool IsSampaPhoneme(const std::string& sampa, const std::string& language)
{
  if (IsPausePhoneme(sampa))
  {
    return true;
  }
  const auto& inventory = language == "de" ? GermanInventory() : EnglishInventory();
  return inventory.count(sampa) > 0;
}

bool IsSampaVowel(const std::string& sampa)
{
  return Vowels().count(sampa) > 0;
}

std::string NormalizeEspeakPhoneme(const std::string& espeakName, const std::string& language)
{
  if (espeakName == "_!")
  {
    return "?"; // eSpeak's German glottal stop is spelled like a pause
  }
  if (IsPausePhoneme(espeakName))
  {
    return "_";
  }
  std::string found = Lookup(espeakName, language);
  if (!found.empty())
  {
    return found;
  }
  std::string stripped = espeakName;
  while (stripped.size() > 1 && IsVariantMark(stripped.back()))
  {
    stripped.pop_back();
  }
  found = Lookup(stripped, language);
  return found.empty() ? espeakName : found;
}

std::vector<TimedPhoneme> NormalizeEspeakPhonemes(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& language)
{
  std::vector<TimedPhoneme> result;
  result.reserve(espeakPhonemes.size());
  for (const TimedPhoneme& e : espeakPhonemes)
  {
    if (e.Sampa.size() > 1 && e.Sampa.front() == '(' && e.Sampa.back() == ')')
    {
      // A language switch such as "(en)", not a sound: the previous phoneme lasts on.
      if (!result.empty())
      {
        result.back().Duration = std::max(result.back().Duration, e.Start + e.Duration - result.back().Start);
      }
      continue;
    }
    TimedPhoneme p = e;
    p.Sampa = NormalizeEspeakPhoneme(e.Sampa, language);
    const bool pause = IsPausePhoneme(p.Sampa);
    if (pause && p.Duration <= 0.0)
    {
      continue;
    }
    if (pause && !result.empty() && IsPausePhoneme(result.back().Sampa))
    {
      TimedPhoneme& previous = result.back();
      previous.Duration = std::max(previous.Duration, p.Start + p.Duration - previous.Start);
      continue;
    }
    result.push_back(std::move(p));
  }
  return result;
}
} // namespace morphnode
