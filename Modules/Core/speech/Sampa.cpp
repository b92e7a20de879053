// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Sampa.h"

#include "base/Text.h"
#include "speech/Articulation.h"
#include "speech/PhoneSets.h"

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
    "tS", "dZ", "f", "v", "s", "z", "S", "Z", "C", "j", "x", "h", "m", "n", "N", "l", "R", "r", "I",
    "E", "a", "O", "U", "Y", "9", "i:", "e:", "E:", "a:", "o:", "u:", "y:", "2:", "aI", "aU", "OY",
    "@", "6", "_" };
  return inventory;
}

const std::set<std::string>& EnglishInventory()
{
  static const std::set<std::string> inventory = { "p", "b", "t", "d", "k", "g", "?", "tS", "dZ",
    "f", "v", "T", "D", "s", "z", "S", "Z", "h", "m", "n", "N", "r", "l", "5", "w", "j", "I", "e",
    "{", "Q", "V", "U", "@", "i:", "eI", "aI", "OI", "u:", "@U", "aU", "I@", "e@", "U@",
    "A:", "O:", "3:", "_" };
  return inventory;
}

const std::set<std::string>& Vowels()
{
  static const std::set<std::string> vowels = { "I", "E", "a", "O", "U", "Y", "9",
    "i:", "e:", "E:", "a:", "o:", "u:", "y:", "2:", "aI", "aU", "OY", "@", "6", "e", "{", "Q", "V",
    "eI", "OI", "@U", "I@", "e@", "U@", "A:", "O:", "3:" };
  return vowels;
}

// eSpeak NG mnemonics that differ from SAMPA (checked against eSpeak NG 1.51 output).
const std::unordered_map<std::string, std::string>& GermanTable()
{
  static const std::unordered_map<std::string, std::string> table = { { "3", "6" }, { "r", "R" },
    { "A:", "a:" }, { "A", "a" }, { "OI", "OY" }, { "y", "Y" }, { "W", "9" }, { "Y:", "2:" },
    { "pF", "pf" }, { "i", "i:" }, { "e", "e:" }, { "o", "o:" }, { "u", "u:" }, { "eI", "e:" },
    { "UR", "U" } };
  return table;
}

const std::unordered_map<std::string, std::string>& EnglishTable()
{
  static const std::unordered_map<std::string, std::string> table = { { "oU", "@U" }, { "a", "{" },
    { "0", "Q" }, { "E", "e" }, { "O", "O:" }, { "@L", "5" }, { "3", "@" }, { "a#", "@" },
    { "i", "i:" }, { "A@", "A:" }, { "aa", "A:" }, { "A", "A:" }, { "i@", "I@" }, { "i@3", "I@" },
    { "IR", "I@" }, { "O@", "O:" }, { "o@", "O:" }, { "aI@", "aI" }, { "aU@", "aU" },
    { "x", "k" } };
  return table;
}

bool IsVariantMark(char c)
{
  return c == '#' || c == '/' || c == '-' || c == ';' || c == '~' ||
    std::isdigit(static_cast<unsigned char>(c));
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
  if (std::all_of(espeakName.begin(), espeakName.end(), IsVariantMark))
  {
    return ""; // a mark eSpeak reports on its own (the ';' of "i;" before a vowel): no sound
  }
  std::string stripped = espeakName;
  while (stripped.size() > 1 && IsVariantMark(stripped.back()))
  {
    stripped.pop_back();
  }
  found = Lookup(stripped, language);
  if (!found.empty())
  {
    return found;
  }
  // Phonemes of eSpeak's shared base tables that the language's SAMPA table lacks (its
  // phoneme inventory inherits them: c, B, n^, ...): their X-SAMPA, which the viseme tables
  // place by articulation. A name even that does not describe stays, to be warned about.
  const std::string xsampa = EspeakMnemonicToXSampa(espeakName, language);
  const std::vector<std::string> segments = SplitPhone(xsampa);
  if (!IsPausePhoneme(xsampa) && !segments.empty() && DescribePhone(segments[0]).IsKnown())
  {
    return xsampa;
  }
  return espeakName;
}

namespace
{
/// eSpeak's events with each name converted by `convert`; language switches ("(en)") and
/// empty pauses dropped, adjacent pauses merged. A name `convert` returns empty joins the
/// previous phoneme (a modifier eSpeak reported on its own, such as a palatalization mark).
template <typename Convert>
std::vector<TimedPhoneme> NormalizeEvents(
  const std::vector<TimedPhoneme>& events, Convert&& convert)
{
  std::vector<TimedPhoneme> result;
  result.reserve(events.size());
  for (const TimedPhoneme& e : events)
  {
    if (e.Sampa.size() > 1 && e.Sampa.front() == '(' && e.Sampa.back() == ')')
    {
      // A language switch such as "(en)", not a sound: the previous phoneme lasts on.
      if (!result.empty())
      {
        result.back().Duration =
          std::max(result.back().Duration, e.Start + e.Duration - result.back().Start);
      }
      continue;
    }
    TimedPhoneme p = e;
    p.Sampa = convert(e.Sampa);
    if (p.Sampa.empty())
    {
      if (!result.empty())
      {
        result.back().Duration =
          std::max(result.back().Duration, e.Start + e.Duration - result.back().Start);
      }
      continue;
    }
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
} // namespace

std::vector<std::string> EspeakLanguageSwitches(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& voice)
{
  const std::string own = text::ToLower(voice.substr(0, voice.find('+')));
  std::vector<std::string> switches;
  for (const TimedPhoneme& e : espeakPhonemes)
  {
    if (e.Sampa.size() < 3 || e.Sampa.front() != '(' || e.Sampa.back() != ')')
    {
      continue;
    }
    const std::string language = text::ToLower(e.Sampa.substr(1, e.Sampa.size() - 2));
    const bool same =
      own == language || own.rfind(language + "-", 0) == 0 || language.rfind(own + "-", 0) == 0;
    if (!same && std::find(switches.begin(), switches.end(), language) == switches.end())
    {
      switches.push_back(language);
    }
  }
  return switches;
}

std::vector<TimedPhoneme> NormalizeEspeakPhonemes(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& language)
{
  return NormalizeEvents(espeakPhonemes,
    [&language](const std::string& name) { return NormalizeEspeakPhoneme(name, language); });
}

std::string EspeakMnemonicToXSampa(const std::string& name, const std::string& voice)
{
  if (name == "_!")
  {
    return "?";
  }
  if (name.empty() || IsPausePhoneme(name))
  {
    return "_";
  }
  // eSpeak's mnemonics follow Kirshenbaum's ASCII IPA; its suffixes: digits, '#', '-', '/'
  // mark variants, ';' palatalization, '[' dental, '^' palatal (n^ l^), '.' retroflex.
  std::string m;
  for (size_t i = 0; i < name.size(); ++i)
  {
    const char c = name[i];
    // eSpeak's variant and syllable marks; a palatalization mark inside (tS;h) too.
    if (c != '-' && c != '!' && c != '/' && c != '<' && c != '>' &&
      !(c == ';' && i + 1 < name.size()))
    {
      m += c;
    }
  }
  while (m.size() > 1 &&
    (std::isdigit(static_cast<unsigned char>(m.back())) || m.back() == '#' || m.back() == '+' ||
      m.back() == '_'))
  {
    m.pop_back(); // variant marks (O+ in Vietnamese, n_ in Russian, d_ ...)
  }
  if (m.size() == 2 && m[0] == 'h' &&
    std::string("ptkbdgszmnlrwjSZ").find(m[1]) != std::string::npos)
  {
    m.erase(0, 1); // a voiceless or pre-aspirated consonant written with h first (Burmese hs, ht)
  }
  if (m.size() >= 3 && m.back() == 'h' && m[m.size() - 2] == '.' && (m[0] == 't' || m[0] == 'd'))
  {
    m.pop_back(); // an aspirated retroflex affricate (Mandarin ts.h)
  }
  if (m.size() == 2 && m.back() == 'H' && std::string("ptkcqbdg").find(m[0]) != std::string::npos)
  {
    m.pop_back(); // breathy-voiced or aspirated stop written with H (Hindi, Arabic dH, gH)
  }
  if (m.size() > 1 && m[0] == '?' &&
    std::string("aeiouyAEIOUY@&0369V{").find(m[1]) != std::string::npos)
  {
    m.erase(0, 1); // a vowel with a glottal onset (Danish stød)
  }
  if (m.size() == 2 && m[0] == m[1] && std::isalpha(static_cast<unsigned char>(m[0])))
  {
    m.pop_back(); // a long (geminate) consonant
  }
  const bool affricate = m.size() == 3 && (m[0] == 't' || m[0] == 'd') &&
    std::string("sSzZ").find(m[1]) != std::string::npos;
  if (m.size() >= 2 && m.back() == 'h' &&
    (affricate || std::string("ptkcqbdg").find(m[m.size() - 2]) != std::string::npos))
  {
    m.pop_back(); // aspiration written as h (ph, tSh, kh)
  }
  if (m.size() >= 2 && m.back() == 'R' &&
    std::string("aeiouyAEIOUY@&0369V{:").find(m[m.size() - 2]) != std::string::npos)
  {
    m.back() = '6'; // a vocalized r after a vowel (Luxembourgish eR)
  }
  static const std::unordered_map<std::string, std::string> whole = { { "S;", "s\\" },
    { "Z;", "z\\" }, { "tS;", "ts\\" }, { "dZ;", "dz\\" }, { "ts;", "ts\\" }, { "dz;", "dz\\" },
    { "n^", "J" }, { "l^", "L" }, { "**", "4" }, { "*", "4" }, { "a#", "6" }, { "TS", "ts" },
    { "@r", "@`" }, { "tz", "ts" }, { "sx", "x\\" }, { "ng", "N" },
    // Lateral affricate (Icelandic, Greenlandic tl), trilled r, Vietnamese tr, palatal k.
    { "tl", "t" }, { "rR", "r" }, { "cr", "c" }, { "ky", "c" },
    // Cantonese and Mandarin finals of a vowel and a velar nasal: the mouth shows the vowel.
    { "ang", "a" }, { "aang", "a:" }, { "eng", "E" }, { "ing", "i" }, { "ong", "U" },
    { "ung", "U" }, { "oeng", "9" } };
  if (const auto it = whole.find(m); it != whole.end())
  {
    return it->second;
  }
  // Where eSpeak's own IPA output (espeakINITIALIZE_PHONEME_IPA, eSpeak NG 1.51) reads a
  // mnemonic otherwise than Kirshenbaum: "y" is the unrounded ɨ in these languages.
  const std::string language = text::ToLower(voice.substr(0, voice.find_first_of("+-")));
  if ((m == "y" || m == "y:") &&
    (language == "am" || language == "ml" || language == "pl" ||
      (language == "pt" && text::ToLower(voice).rfind("pt-br", 0) != 0)))
  {
    return "1" + m.substr(1);
  }
  std::string out;
  for (size_t i = 0; i < m.size(); ++i)
  {
    const char c = m[i];
    const char next = i + 1 < m.size() ? m[i + 1] : '\0';
    if (next == '.' && std::string("tdnszlr").find(c) != std::string::npos)
    {
      out += c;
      out += '`'; // retroflex
      ++i;
      continue;
    }
    switch (c)
    {
      case '&':
        out += "{";
        break;
      case '0':
        out += "Q";
        break;
      case 'Q':
        out += "G";
        break;
      case 'G':
        out += "G\\";
        break;
      case 'L':
        out += "5";
        break;
      case 'M':
        out += "F";
        break;
      case 'W':
        out += "9";
        break;
      case 'R':
        out += "r";
        break; // eSpeak's R is mostly a trill (rr), its IPA says r
      case 'Y':
        out += "2";
        break;
      case 'H':
        out += "X\\";
        break;
      case 'P':
        out += "p\\";
        break;
      case 'J':
        out += "J\\";
        break;
      case '*':
        out += "4";
        break;
      case ';':
      case '[':
      case '^':
      case '.':
      case '#':
      case '\'':
      case ',':
        break;
      default:
        out += c;
        break;
    }
  }
  // Only marks left (a lone length or nasal mark): nothing of its own.
  const bool hasLetter = std::any_of(out.begin(), out.end(),
    [](char c)
    {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '@' || c == '{' || c == '?' ||
        c == '&';
    });
  return hasLetter ? out : std::string("_");
}

bool HasSampaTables(const std::string& voice)
{
  const std::string prefix = text::ToLower(voice.substr(0, 2));
  return (prefix == "de" || prefix == "en") &&
    (voice.size() == 2 || voice[2] == '-' || voice[2] == '+' || voice[2] == '_');
}

std::string NormalizeIpaPhoneme(const std::string& ipaName, const std::string& voice)
{
  // eSpeak marks variants with ASCII after the IPA ("ə-"); stress marks carry no shape.
  std::string name = ipaName;
  while (!name.empty() &&
    (name.back() == '-' || name.back() == '#' || name.back() == '/' ||
      std::isdigit(static_cast<unsigned char>(name.back()))))
  {
    name.pop_back();
  }
  if (ipaName.empty() || IsPausePhoneme(ipaName))
  {
    return "_";
  }
  const std::string sampa = IpaToSampa(name, voice);
  // Nothing left (a lone modifier such as ʲ or ː): it belongs to the previous phoneme.
  return sampa == "_" ? std::string() : sampa;
}

std::vector<TimedPhoneme> NormalizeVoicePhonemes(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& voice)
{
  if (HasSampaTables(voice))
  {
    return NormalizeEspeakPhonemes(espeakPhonemes, SpeechLanguageOf(voice));
  }
  return NormalizeEvents(espeakPhonemes,
    [&voice](const std::string& name)
    {
      const std::string x = EspeakMnemonicToXSampa(name, voice);
      return x == "_" && !name.empty() && !IsPausePhoneme(name) ? std::string() : x;
    });
}

std::vector<TimedPhoneme> NormalizeIpaPhonemes(
  const std::vector<TimedPhoneme>& ipaPhonemes, const std::string& voice)
{
  return NormalizeEvents(
    ipaPhonemes, [&voice](const std::string& name) { return NormalizeIpaPhoneme(name, voice); });
}
} // namespace morphnode
