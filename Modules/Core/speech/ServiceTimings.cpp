// SPDX-License-Identifier: BSD-3-Clause
#include "speech/ServiceTimings.h"

#include "base/Error.h"
#include "base/Text.h"
#include "speech/Sampa.h"
#include "speech/SpeechSynthesizer.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

namespace morphnode
{
namespace
{
using nlohmann::json;

json ParseJson(const std::string& text, const char* what)
{
  try
  {
    return json::parse(text);
  }
  catch (const json::exception& e)
  {
    throw InputError(std::string(what) + ": not valid JSON (" + e.what() + ")");
  }
}

/// A member by either spelling (AudioOffset / audioOffset), nullptr when absent.
const json* Member(const json& object, const char* name)
{
  auto it = object.find(name);
  if (it != object.end())
  {
    return &*it;
  }
  std::string lower = name;
  lower[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(lower[0])));
  it = object.find(lower);
  return it != object.end() ? &*it : nullptr;
}

double Seconds(const json& value, double scale, const std::string& where)
{
  if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0)
  {
    throw InputError(where + "a time must be a number >= 0");
  }
  return value.get<double>() * scale;
}
} // namespace

std::string AzureVisemeToSampa(int visemeId)
{
  static const char* const table[22] = { "_", "{", "A:", "O:", "e", "3:", "i:", "u:", "@U", "aU",
    "OI", "aI", "h", "r", "l", "s", "S", "T", "f", "t", "k", "p" };
  return visemeId >= 0 && visemeId < 22 ? table[visemeId] : std::string();
}

std::vector<TimedPhoneme> ParseAzureVisemes(const std::string& text, double lastDuration)
{
  const json root = ParseJson(text, "azure visemes");
  const json* list = &root;
  if (root.is_object())
  {
    list = Member(root, "Visemes");
  }
  if (!list || !list->is_array())
  {
    throw InputError("azure visemes: expected an array of {\"AudioOffset\", \"VisemeId\"} "
                     "(or an object with \"visemes\")");
  }
  std::vector<TimedPhoneme> phonemes;
  for (size_t i = 0; i < list->size(); ++i)
  {
    const json& event = (*list)[i];
    const std::string where = "azure visemes: event " + std::to_string(i) + ": ";
    if (!event.is_object())
    {
      throw InputError(where + "must be an object");
    }
    const json* id = Member(event, "VisemeId");
    if (!id || !id->is_number_integer())
    {
      throw InputError(where + "needs an integer \"VisemeId\" (0..21)");
    }
    const std::string sampa = AzureVisemeToSampa(id->get<int>());
    if (sampa.empty())
    {
      throw InputError(
        where + "viseme ID " + std::to_string(id->get<long long>()) + " is not in 0..21");
    }
    double start = 0.0;
    if (const json* ticks = Member(event, "AudioOffset"))
    {
      start = Seconds(*ticks, 1e-7, where); // 100-nanosecond ticks
    }
    else if (const json* ms = Member(event, "OffsetMs"))
    {
      start = Seconds(*ms, 1e-3, where);
    }
    else
    {
      throw InputError(where + "needs \"AudioOffset\" (100-ns ticks) or \"offsetMs\"");
    }
    if (!phonemes.empty() && start < phonemes.back().Start)
    {
      throw InputError(where + "starts before the event before it");
    }
    if (!phonemes.empty())
    {
      phonemes.back().Duration = start - phonemes.back().Start;
    }
    phonemes.push_back({ sampa, start, lastDuration, {} });
  }
  if (phonemes.empty())
  {
    throw InputError("azure visemes: no events");
  }
  if (phonemes.front().Start > 0.0)
  {
    phonemes.insert(phonemes.begin(), { "_", 0.0, phonemes.front().Start, {} });
  }
  return phonemes;
}

std::vector<AlignedWord> ParseCharacterAlignment(const std::string& text)
{
  const json root = ParseJson(text, "character alignment");
  if (!root.is_object())
  {
    throw InputError("character alignment: expected an object");
  }
  const json* alignment = &root;
  for (const char* key : { "alignment", "normalized_alignment" })
  {
    const auto it = root.find(key);
    if (!root.contains("characters") && it != root.end() && it->is_object())
    {
      alignment = &*it;
      break;
    }
  }
  auto array = [&](const char* key) -> const json&
  {
    const auto it = alignment->find(key);
    if (it == alignment->end() || !it->is_array())
    {
      throw InputError(std::string("character alignment: \"") + key + "\" must be an array");
    }
    return *it;
  };
  const json& characters = array("characters");
  const json& starts = array("character_start_times_seconds");
  const json& ends = array("character_end_times_seconds");
  if (starts.size() != characters.size() || ends.size() != characters.size())
  {
    throw InputError("character alignment: " + std::to_string(characters.size()) + " characters, " +
      std::to_string(starts.size()) + " start and " + std::to_string(ends.size()) + " end times");
  }
  std::vector<AlignedWord> words;
  bool inWord = false;
  double previous = 0.0;
  for (size_t i = 0; i < characters.size(); ++i)
  {
    const std::string where = "character alignment: character " + std::to_string(i) + ": ";
    if (!characters[i].is_string())
    {
      throw InputError(where + "must be a string");
    }
    const std::string& c = characters[i].get_ref<const std::string&>();
    const double start = Seconds(starts[i], 1.0, where);
    const double end = Seconds(ends[i], 1.0, where);
    if (end < start || start < previous - 1e-9)
    {
      throw InputError(where + "times must not decrease");
    }
    previous = start;
    const bool space = c.empty() ||
      std::all_of(c.begin(), c.end(),
        [](char ch) { return std::isspace(static_cast<unsigned char>(ch)) != 0; });
    if (space)
    {
      inWord = false;
      continue;
    }
    if (!inWord)
    {
      words.push_back({ "", start, end });
      inWord = true;
    }
    words.back().Text += c;
    words.back().End = std::max(words.back().End, end);
  }
  if (words.empty())
  {
    throw InputError("character alignment: no words");
  }
  return words;
}

std::vector<TimedPhoneme> PhonemesOfAlignedWords(
  const std::vector<AlignedWord>& words, const std::string& voice)
{
  if (!SpeechSynthesizer::IsAvailable())
  {
    throw InputError("character alignments are read by eSpeak NG, which this build lacks");
  }
  const SpeechSynthesizer synthesizer(voice);
  std::vector<TimedPhoneme> phonemes;
  double at = 0.0;
  for (const AlignedWord& word : words)
  {
    if (word.Start > at + 1e-6)
    {
      phonemes.push_back({ "_", at, word.Start - at, {} });
    }
    std::vector<TimedPhoneme> own;
    double total = 0.0;
    for (const TimedPhoneme& p : synthesizer.Synthesize(word.Text).Phonemes)
    {
      if (!IsPausePhoneme(p.Sampa))
      {
        own.push_back(p);
        total += p.Duration;
      }
    }
    const double span = std::max(0.0, word.End - word.Start);
    double t = word.Start;
    for (const TimedPhoneme& p : own)
    {
      const double d =
        total > 0.0 ? span * p.Duration / total : span / static_cast<double>(own.size());
      phonemes.push_back({ p.Sampa, t, d, {} });
      t += d;
    }
    at = std::max(at, word.End);
  }
  return phonemes;
}
} // namespace morphnode
