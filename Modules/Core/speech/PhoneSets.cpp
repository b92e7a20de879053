// SPDX-License-Identifier: BSD-3-Clause
#include "speech/PhoneSets.h"

#include "base/Error.h"
#include "base/Text.h"
#include "speech/Sampa.h"
#include "speech/Utf8.h"

#include <cctype>
#include <unordered_map>

namespace morphnode
{
namespace
{
const std::unordered_map<std::string, std::string>& ArpabetTable()
{
  static const std::unordered_map<std::string, std::string> table = { { "AA", "A:" }, { "AE", "{" },
    { "AH", "V" }, { "AO", "O:" }, { "AW", "aU" }, { "AX", "@" }, { "AXR", "@" }, { "AY", "aI" },
    { "EH", "e" }, { "ER", "3:" }, { "EY", "eI" }, { "IH", "I" }, { "IX", "I" }, { "IY", "i:" },
    { "OW", "@U" }, { "OY", "OI" }, { "UH", "U" }, { "UW", "u:" }, { "UX", "u:" }, { "B", "b" },
    { "CH", "tS" }, { "D", "d" }, { "DH", "D" }, { "DX", "d" }, { "EL", "5" }, { "EM", "m" },
    { "EN", "n" }, { "F", "f" }, { "G", "g" }, { "HH", "h" }, { "H", "h" }, { "JH", "dZ" },
    { "K", "k" }, { "L", "l" }, { "M", "m" }, { "N", "n" }, { "NG", "N" }, { "NX", "n" },
    { "P", "p" }, { "Q", "?" }, { "R", "r" }, { "S", "s" }, { "SH", "S" }, { "T", "t" },
    { "TH", "T" }, { "V", "v" }, { "W", "w" }, { "WH", "w" }, { "Y", "j" }, { "Z", "z" },
    { "ZH", "Z" } };
  return table;
}

/// IPA code point -> X-SAMPA. Modifiers that change no viseme map to "".
const std::unordered_map<char32_t, std::string>& IpaTable()
{
  static const std::unordered_map<char32_t, std::string> table = { // vowels
    { U'i', "i" }, { U'y', "y" }, { U'ɨ', "1" }, { U'ʉ', "}" }, { U'ɯ', "M" }, { U'u', "u" },
    { U'ɪ', "I" }, { U'ʏ', "Y" }, { U'ʊ', "U" }, { U'e', "e" }, { U'ø', "2" }, { U'ɘ', "@\\" },
    { U'ɵ', "8" }, { U'ɤ', "7" }, { U'o', "o" }, { U'ə', "@" }, { U'ɛ', "E" }, { U'œ', "9" },
    { U'ɜ', "3" }, { U'ɞ', "3\\" }, { U'ʌ', "V" }, { U'ɔ', "O" }, { U'æ', "{" }, { U'ɐ', "6" },
    { U'a', "a" }, { U'ɶ', "&" }, { U'ɑ', "A" }, { U'ɒ', "Q" }, { U'ɚ', "@`" }, { U'ɝ', "3`" },
    // consonants
    { U'p', "p" }, { U'b', "b" }, { U't', "t" }, { U'd', "d" }, { U'ʈ', "t`" }, { U'ɖ', "d`" },
    { U'c', "c" }, { U'ɟ', "J\\" }, { U'k', "k" }, { U'g', "g" }, { U'ɡ', "g" }, { U'q', "q" },
    { U'ɢ', "G\\" }, { U'ʔ', "?" }, { U'm', "m" }, { U'ɱ', "F" }, { U'n', "n" }, { U'ɳ', "n`" },
    { U'ɲ', "J" }, { U'ŋ', "N" }, { U'ɴ', "N\\" }, { U'ʙ', "B\\" }, { U'r', "r" }, { U'ʀ', "R\\" },
    { U'ɾ', "4" }, { U'ɽ', "r`" }, { U'ɸ', "p\\" }, { U'β', "B" }, { U'f', "f" }, { U'v', "v" },
    { U'θ', "T" }, { U'ð', "D" }, { U's', "s" }, { U'z', "z" }, { U'ʃ', "S" }, { U'ʒ', "Z" },
    { U'ʂ', "s`" }, { U'ʐ', "z`" }, { U'ç', "C" }, { U'ʝ', "j\\" }, { U'x', "x" }, { U'ɣ', "G" },
    { U'χ', "X" }, { U'ʁ', "R" }, { U'ħ', "X\\" }, { U'ʕ', "?\\" }, { U'h', "h" }, { U'ɦ', "h\\" },
    { U'ɬ', "K" }, { U'ɮ', "K\\" }, { U'ʋ', "v\\" }, { U'ɹ', "r\\" }, { U'ɻ', "r\\`" },
    { U'j', "j" }, { U'ɰ', "M\\" }, { U'l', "l" }, { U'ɭ', "l`" }, { U'ʎ', "L" }, { U'ʟ', "L\\" },
    { U'ɫ', "5" }, { U'w', "w" }, { U'ʍ', "W" }, { U'ɥ', "H" }, { U'ɕ', "s\\" }, { U'ʑ', "z\\" },
    { U'ɧ', "x\\" }, { U'ʦ', "ts" }, { U'ʧ', "tS" }, { U'ʤ', "dZ" },
    // length and modifiers
    { U'ː', ":" }, { U'ˑ', "" }, { U'ʰ', "" }, { U'ʲ', "" }, { U'ʷ', "" }, { U'ˠ', "" },
    { U'ˤ', "" }, { U'ˈ', "" }, { U'ˌ', "" }, { U'.', "" }, { 0x0329, "" } /* syllabic */,
    { 0x032F, "" } /* non-syllabic */, { 0x0361, "" } /* tie above */, { 0x035C, "" },
    { 0x032A, "" } /* dental */, { 0x0303, "~" } /* nasal */, { 0x0325, "" }, { 0x031A, "" },
    { 0x0306, "" }, { 0x0308, "" }, { 0x031E, "" }, { 0x031D, "" }, { 0x0320, "" }, { 0x031F, "" }
  };
  return table;
}

/// X-SAMPA -> the SAMPA of the language's tables.
std::string ToLanguageSampa(const std::string& xsampa, const std::string& language)
{
  static const std::unordered_map<std::string, std::string> english = { { "r\\", "r" },
    { "r\\`", "r" }, { "4", "d" }, { "@`", "@" }, { "3`", "3:" }, { "3`:", "3:" }, { "oU", "@U" },
    { "@U", "@U" }, { "eI", "eI" }, { "A", "A:" }, { "A:", "A:" }, { "i", "i:" }, { "u", "u:" },
    { "O", "O:" }, { "3", "3:" }, { "E", "e" }, { "a", "{" }, { "aI", "aI" }, { "aU", "aU" },
    { "OI", "OI" }, { "5", "l" }, { "e", "e" }, { "o", "@U" }, { "Q", "Q" }, { "i:", "i:" },
    { "u:", "u:" }, { "O:", "O:" }, { "}:", "u:" }, { "}", "u:" }, { "6", "@" }, { "I@", "I@" },
    { "e@", "e@" }, { "U@", "U@" }, { "E@", "e@" }, { "@:", "3:" } };
  static const std::unordered_map<std::string, std::string> german = { { "R\\", "R" },
    { "r\\", "R" }, { "r", "R" }, { "X", "x" }, { "a", "a" }, { "i", "i:" }, { "e", "e:" },
    { "o", "o:" }, { "u", "u:" }, { "y", "y:" }, { "2", "2:" }, { "ae", "aI" }, { "ao", "aU" },
    { "OY", "OY" }, { "Oy", "OY" }, { "E", "E" }, { "5", "l" }, { "g", "g" } };
  const auto& table = language == "de" ? german : english;
  const auto it = table.find(xsampa);
  return it == table.end() ? xsampa : it->second;
}

bool IsArpabetShape(const std::string& label)
{
  if (label.empty() || label.size() > 4)
  {
    return false;
  }
  size_t letters = 0;
  while (letters < label.size() && std::isupper(static_cast<unsigned char>(label[letters])))
  {
    ++letters;
  }
  if (letters == 0)
  {
    return false;
  }
  if (letters < label.size())
  {
    return letters + 1 == label.size() && label[letters] >= '0' && label[letters] <= '2';
  }
  return true;
}
} // namespace

const char* PhoneAlphabetName(PhoneAlphabet alphabet)
{
  switch (alphabet)
  {
    case PhoneAlphabet::Sampa:
      return "sampa";
    case PhoneAlphabet::Arpabet:
      return "arpabet";
    case PhoneAlphabet::Ipa:
      return "ipa";
    case PhoneAlphabet::Auto:
      break;
  }
  return "auto";
}

PhoneAlphabet ParsePhoneAlphabet(const std::string& name)
{
  const std::string n = text::ToLower(name);
  for (PhoneAlphabet a :
    { PhoneAlphabet::Auto, PhoneAlphabet::Sampa, PhoneAlphabet::Arpabet, PhoneAlphabet::Ipa })
  {
    if (n == PhoneAlphabetName(a))
    {
      return a;
    }
  }
  throw InputError("unknown phone alphabet " + text::Quote(name) + " (auto, sampa, arpabet, ipa)");
}

bool IsSilenceLabel(const std::string& label)
{
  const std::string l = text::ToLower(text::Trim(label));
  return l.empty() || l == "sil" || l == "sp" || l == "spn" || l == "<eps>" || l == "<sil>" ||
    l == "#" || l == "<s>" || l == "</s>" || l == "+nsn+" || l == "+spn+" || l == "<p:>" ||
    l == "<unk>" || IsPausePhoneme(l);
}

std::string ArpabetToSampa(const std::string& label)
{
  if (IsSilenceLabel(label))
  {
    return "_";
  }
  std::string base = label;
  char stress = 0;
  if (!base.empty() && base.back() >= '0' && base.back() <= '2')
  {
    stress = base.back();
    base.pop_back();
  }
  base = text::ToLower(base);
  for (char& c : base)
  {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  // Unstressed AH and ER are schwas.
  if (stress == '0' && base == "AH")
  {
    return "@";
  }
  if (stress == '0' && base == "ER")
  {
    return "@";
  }
  const auto it = ArpabetTable().find(base);
  return it == ArpabetTable().end() ? label : it->second;
}

std::string IpaToSampa(const std::string& label, const std::string& language)
{
  if (IsSilenceLabel(label))
  {
    return "_";
  }
  std::string xsampa;
  for (char32_t cp : DecodeUtf8(std::string(text::Trim(label))))
  {
    const auto it = IpaTable().find(cp);
    if (it != IpaTable().end())
    {
      xsampa += it->second;
    }
    else
    {
      xsampa += EncodeUtf8(cp);
    }
  }
  // Affricates written with a tie are plain pairs now ("t͡ʃ" -> "tS"). German and English
  // get their SAMPA spellings; other languages keep X-SAMPA (the viseme tables find them
  // by articulation).
  if (xsampa.empty())
  {
    return "_";
  }
  if (!HasSampaTables(language) && language != "en" && language != "de")
  {
    return xsampa;
  }
  return ToLanguageSampa(xsampa, SpeechLanguageOf(language));
}

PhoneAlphabet GuessPhoneAlphabet(const std::vector<std::string>& labels)
{
  bool allArpabet = true, arpabetEvidence = false;
  for (const std::string& label : labels)
  {
    for (char c : label)
    {
      if (static_cast<unsigned char>(c) >= 0x80)
      {
        return PhoneAlphabet::Ipa;
      }
    }
    if (IsSilenceLabel(label))
    {
      continue;
    }
    if (!IsArpabetShape(label))
    {
      allArpabet = false;
      continue;
    }
    const bool digit = std::isdigit(static_cast<unsigned char>(label.back())) != 0;
    std::string base = digit ? label.substr(0, label.size() - 1) : label;
    if (ArpabetTable().count(base) == 0)
    {
      allArpabet = false;
    }
    else if (digit || base.size() >= 2)
    {
      arpabetEvidence = true;
    }
  }
  return allArpabet && arpabetEvidence ? PhoneAlphabet::Arpabet : PhoneAlphabet::Sampa;
}

std::string PhoneLabelToSampa(
  const std::string& label, PhoneAlphabet alphabet, const std::string& language)
{
  switch (alphabet)
  {
    case PhoneAlphabet::Arpabet:
      return ArpabetToSampa(label);
    case PhoneAlphabet::Ipa:
      return IpaToSampa(label, language);
    case PhoneAlphabet::Sampa:
    case PhoneAlphabet::Auto:
      break;
  }
  return IsSilenceLabel(label) ? std::string("_") : std::string(text::Trim(label));
}
} // namespace morphnode
