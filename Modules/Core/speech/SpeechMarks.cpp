// SPDX-License-Identifier: BSD-3-Clause
#include "speech/SpeechMarks.h"

#include "base/Error.h"
#include "base/Text.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <istream>
#include <sstream>
#include <unordered_map>

namespace morphnode
{
std::string PollyVisemeToSampa(const std::string& viseme)
{
  // Amazon Polly's viseme tables (docs: "Phoneme and Viseme Tables for Supported
  // Languages"): p = p b m, t = t d n, S = S Z tS dZ, T = T D, f = f v, k = k g N h,
  // i = i I j, r = r\, s = s z, u = u U w, @ = @ V, a = A aI aU, e = e eI, E = E {,
  // o = o @U, O = O OI, sil = silence; l = l (English); and the visemes other languages
  // add, each named by X-SAMPA for its phones: B = B (Spanish, Catalan: the bilabial
  // fricative of "bebe"), J = j\ L (Spanish: the palatals of "sayo", "llave"), which the
  // viseme tables place by articulation.
  static const std::unordered_map<std::string, std::string> table = { { "p", "p" }, { "t", "t" },
    { "S", "S" }, { "T", "T" }, { "f", "f" }, { "k", "k" }, { "i", "i:" }, { "r", "r" },
    { "s", "s" }, { "u", "u:" }, { "@", "@" }, { "a", "A:" }, { "e", "e" }, { "E", "{" },
    { "o", "@U" }, { "O", "O:" }, { "sil", "_" }, { "l", "l" }, { "B", "B" }, { "J", "j\\" } };
  const auto it = table.find(viseme);
  return it == table.end() ? std::string() : it->second;
}

SpeechMarks ReadSpeechMarks(std::istream& in, const SpeechMarkOptions& options)
{
  if (!(options.LastDuration >= 0.0) || !std::isfinite(options.LastDuration))
  {
    throw InputError("speech marks: the last duration must be finite and >= 0");
  }
  struct Event
  {
    double Time;
    std::string Sampa;
    std::string Label; // phoneme events: the raw label until the alphabet is known
    bool IsPhoneme;
  };
  std::vector<Event> events;
  SpeechMarks marks;
  double lastTime = 0.0;
  std::string line;
  size_t lineNumber = 0;
  while (std::getline(in, line))
  {
    ++lineNumber;
    const std::string_view trimmed = text::Trim(line);
    if (trimmed.empty())
    {
      continue;
    }
    const std::string where = "speech marks line " + std::to_string(lineNumber) + ": ";
    nlohmann::json j = nlohmann::json::parse(trimmed.begin(), trimmed.end(), nullptr, false);
    if (j.is_discarded() || !j.is_object())
    {
      throw InputError(where + "not a JSON object");
    }
    const auto time = j.find("time");
    if (time == j.end() || !time->is_number() || !std::isfinite(time->get<double>()) ||
      time->get<double>() < 0)
    {
      throw InputError(where + "needs \"time\" in milliseconds, >= 0");
    }
    const double t = time->get<double>() / 1000.0;
    if (t < lastTime)
    {
      throw InputError(where + "time " + text::FormatNumber(t * 1000.0) +
        " ms is earlier than the previous event's (" + text::FormatNumber(lastTime * 1000.0) +
        " ms): times out of order");
    }
    lastTime = t;
    const auto type = j.find("type");
    const auto value = j.find("value");
    if (type == j.end() || !type->is_string())
    {
      throw InputError(where + "needs a \"type\" (word, viseme, phoneme, sentence, ssml)");
    }
    const std::string kind = type->get<std::string>();
    const std::string v =
      (value != j.end() && value->is_string()) ? value->get<std::string>() : std::string();
    if (kind == "viseme")
    {
      const std::string sampa = PollyVisemeToSampa(v);
      if (sampa.empty())
      {
        throw InputError(where + "unknown viseme " + text::Quote(v) +
          " (Polly's are p t S T f k i r s u @ a e E o O l B J sil)");
      }
      events.push_back({ t, sampa, v, false });
    }
    else if (kind == "phoneme")
    {
      if (v.empty())
      {
        throw InputError(where + "a phoneme event needs a \"value\"");
      }
      events.push_back({ t, std::string(), v, true });
    }
    else if (kind == "word")
    {
      marks.Words.push_back({ t, v });
    }
    // sentence, ssml and unknown types carry nothing for the face
  }
  if (events.empty())
  {
    throw InputError("speech marks: no viseme or phoneme events (ask the service for "
                     "viseme speech marks, e.g. Polly's SpeechMarkTypes=[\"viseme\",\"word\"])");
  }
  std::vector<std::string> labels;
  for (const Event& e : events)
  {
    if (e.IsPhoneme)
    {
      labels.push_back(e.Label);
    }
  }
  const PhoneAlphabet alphabet =
    options.Alphabet == PhoneAlphabet::Auto ? GuessPhoneAlphabet(labels) : options.Alphabet;
  for (size_t i = 0; i < events.size(); ++i)
  {
    const Event& e = events[i];
    TimedPhoneme p;
    p.Sampa = e.IsPhoneme ? PhoneLabelToSampa(e.Label, alphabet, options.Language) : e.Sampa;
    p.Start = e.Time;
    p.Duration =
      (i + 1 < events.size() ? events[i + 1].Time : e.Time + options.LastDuration) - e.Time;
    if (p.Duration <= 0.0)
    {
      continue; // two events at the same time: the later one wins
    }
    if (p.Sampa == "_" && !marks.Phonemes.empty() && marks.Phonemes.back().Sampa == "_")
    {
      marks.Phonemes.back().Duration += p.Duration;
      continue;
    }
    marks.Phonemes.push_back(std::move(p));
  }
  if (!marks.Phonemes.empty() && marks.Phonemes.front().Start > 0.0)
  {
    TimedPhoneme pause;
    pause.Sampa = "_";
    pause.Duration = marks.Phonemes.front().Start;
    if (marks.Phonemes.front().Sampa == "_")
    {
      marks.Phonemes.front().Duration += pause.Duration;
      marks.Phonemes.front().Start = 0.0;
    }
    else
    {
      marks.Phonemes.insert(marks.Phonemes.begin(), pause);
    }
  }
  marks.Duration =
    marks.Phonemes.empty() ? 0.0 : marks.Phonemes.back().Start + marks.Phonemes.back().Duration;
  return marks;
}

SpeechMarks ParseSpeechMarks(const std::string& text, const SpeechMarkOptions& options)
{
  std::istringstream in(text);
  return ReadSpeechMarks(in, options);
}

SpeechMarks ReadSpeechMarksFile(const std::string& path, const SpeechMarkOptions& options)
{
  const std::string bytes = text::ReadFile(path, "speech marks file");
  try
  {
    return ParseSpeechMarks(bytes, options);
  }
  catch (const InputError& e)
  {
    throw InputError("'" + path + "': " + e.what());
  }
}
} // namespace morphnode
