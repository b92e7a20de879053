// SPDX-License-Identifier: BSD-3-Clause
#include "speech/TimingFiles.h"

#include "base/Error.h"
#include "base/Text.h"
#include "speech/Pho.h"
#include "speech/Sampa.h"
#include "speech/ServiceTimings.h"
#include "speech/SpeechMarks.h"
#include "speech/TextGrid.h"

#include <sstream>

namespace morphnode
{
namespace
{
std::string LanguageOf(const SpeechOptions& speech)
{
  return speech.Language.empty() ? speech.Voice : speech.Language;
}

std::vector<TimedPhoneme> PhonemesFrom(TimingFormat format, const std::string& bytes,
  const std::string& language, const TimingFileOptions& options)
{
  switch (format)
  {
    case TimingFormat::Pho:
      return ParsePho(bytes);
    case TimingFormat::TextGrid:
    {
      TextGridPhoneOptions o;
      o.TierName = options.TierName;
      o.Alphabet = options.Alphabet;
      o.Language = language;
      return TextGridPhonemes(ParseTextGrid(bytes), o);
    }
    case TimingFormat::AzureVisemes:
      return ParseAzureVisemes(bytes);
    case TimingFormat::CharacterAlignment:
      return PhonemesOfAlignedWords(ParseCharacterAlignment(bytes), language);
    case TimingFormat::SpeechMarks:
    {
      SpeechMarkOptions o;
      o.Alphabet = options.Alphabet;
      o.Language = language;
      return ParseSpeechMarks(bytes, o).Phonemes;
    }
    default:
      break;
  }
  throw InputError("a Rhubarb file holds mouth shapes, not phonemes");
}
} // namespace

bool IsRhubarbFormat(TimingFormat format)
{
  return format == TimingFormat::RhubarbTsv || format == TimingFormat::RhubarbJson ||
    format == TimingFormat::RhubarbXml;
}

const char* TimingFormatName(TimingFormat format)
{
  switch (format)
  {
    case TimingFormat::Pho:
      return "pho";
    case TimingFormat::RhubarbTsv:
      return "rhubarb-tsv";
    case TimingFormat::RhubarbJson:
      return "rhubarb-json";
    case TimingFormat::RhubarbXml:
      return "rhubarb-xml";
    case TimingFormat::TextGrid:
      return "textgrid";
    case TimingFormat::SpeechMarks:
      return "speech-marks";
    case TimingFormat::AzureVisemes:
      return "azure-visemes";
    case TimingFormat::CharacterAlignment:
      return "character-alignment";
    case TimingFormat::Auto:
      break;
  }
  return "auto";
}

TimingFormat ParseTimingFormat(const std::string& name)
{
  const std::string n = text::ToLower(name);
  for (TimingFormat f : { TimingFormat::Auto, TimingFormat::Pho, TimingFormat::RhubarbTsv,
         TimingFormat::RhubarbJson, TimingFormat::RhubarbXml, TimingFormat::TextGrid,
         TimingFormat::SpeechMarks, TimingFormat::AzureVisemes, TimingFormat::CharacterAlignment })
  {
    if (n == TimingFormatName(f))
    {
      return f;
    }
  }
  throw InputError("unknown timing format " + text::Quote(name) +
    " (auto, pho, rhubarb-tsv, rhubarb-json, rhubarb-xml, textgrid, speech-marks, azure-visemes, "
    "character-alignment)");
}

TimingFormat GuessTimingFormat(const std::string& path, const std::string& bytes)
{
  if (text::HasExtension(path, ".pho"))
  {
    return TimingFormat::Pho;
  }
  if (text::HasExtension(path, ".textgrid"))
  {
    return TimingFormat::TextGrid;
  }
  if (text::HasExtension(path, ".marks") || text::HasExtension(path, ".jsonl"))
  {
    return TimingFormat::SpeechMarks;
  }
  if (text::HasExtension(path, ".tsv"))
  {
    return TimingFormat::RhubarbTsv;
  }
  // By content: a TextGrid (possibly UTF-16) names its class near the top; Rhubarb JSON is
  // one object with mouthCues; speech marks are objects with "time" and "type", one a line.
  const std::string head = bytes.substr(0, 512);
  std::string ascii; // UTF-16 text with its zero bytes removed, for the sniffing only
  for (char c : head)
  {
    if (c != '\0')
    {
      ascii += c;
    }
  }
  if (ascii.find("ooTextFile") != std::string::npos ||
    ascii.find("ooBinaryFile") != std::string::npos)
  {
    return TimingFormat::TextGrid;
  }
  if (bytes.find("\"mouthCues\"") != std::string::npos)
  {
    return TimingFormat::RhubarbJson;
  }
  if (ascii.find("isemeId\"") != std::string::npos)
  {
    return TimingFormat::AzureVisemes;
  }
  if (bytes.find("\"character_start_times_seconds\"") != std::string::npos)
  {
    return TimingFormat::CharacterAlignment;
  }
  if (ascii.find("<rhubarbResult") != std::string::npos || text::HasExtension(path, ".xml"))
  {
    return TimingFormat::RhubarbXml;
  }
  if (ascii.find("\"time\"") != std::string::npos && ascii.find("\"type\"") != std::string::npos)
  {
    return TimingFormat::SpeechMarks;
  }
  if (text::HasExtension(path, ".json"))
  {
    return TimingFormat::RhubarbJson;
  }
  const std::string firstLine = head.substr(0, head.find('\n'));
  const std::string_view first = text::Trim(firstLine);
  const auto tokens = text::SplitWhitespace(first);
  double number = 0.0;
  if (tokens.size() == 2 && text::ParseNumber(tokens[0], number) && tokens[1].size() == 1)
  {
    return TimingFormat::RhubarbTsv;
  }
  if (!tokens.empty() && tokens.size() >= 2 && text::ParseNumber(tokens[1], number))
  {
    return TimingFormat::Pho;
  }
  throw InputError("'" + path +
    "': cannot tell the timing format (use the extension .pho, "
    ".tsv, .json, .xml, .TextGrid or .marks, or name the format: --timings-format, "
    "'timings_format' in a dialog command)");
}

std::vector<TimedPhoneme> LoadTimedPhonemesData(const std::string& bytes, const std::string& path,
  const std::string& language, const TimingFileOptions& options)
{
  try
  {
    const TimingFormat format =
      options.Format == TimingFormat::Auto ? GuessTimingFormat(path, bytes) : options.Format;
    return PhonemesFrom(format, bytes, language, options);
  }
  catch (const InputError& e)
  {
    const std::string what = e.what();
    throw InputError(what.rfind("'" + path + "'", 0) == 0 ? what : "'" + path + "': " + what);
  }
}

std::vector<TimedPhoneme> LoadTimedPhonemes(
  const std::string& path, const std::string& language, const TimingFileOptions& options)
{
  return LoadTimedPhonemesData(text::ReadFile(path, "timing file"), path, language, options);
}

Utterance LoadTimingData(const std::string& bytes, const std::string& path,
  const SpeechOptions& speech, const TimingFileOptions& options)
{
  try
  {
    const TimingFormat format =
      options.Format == TimingFormat::Auto ? GuessTimingFormat(path, bytes) : options.Format;
    if (IsRhubarbFormat(format))
    {
      std::istringstream in(bytes);
      const std::vector<MouthCue> cues = format == TimingFormat::RhubarbTsv ? ReadRhubarbTsv(in)
        : format == TimingFormat::RhubarbJson                               ? ReadRhubarbJson(in)
                                                                            : ReadRhubarbXml(in);
      return UtteranceFromMouthCues(cues, speech);
    }
    return UtteranceFromPhonemes(PhonemesFrom(format, bytes, LanguageOf(speech), options), speech);
  }
  catch (const InputError& e)
  {
    const std::string what = e.what();
    throw InputError(what.rfind("'" + path + "'", 0) == 0 ? what : "'" + path + "': " + what);
  }
}

Utterance LoadTimingFile(
  const std::string& path, const SpeechOptions& speech, const TimingFileOptions& options)
{
  return LoadTimingData(text::ReadFile(path, "timing file"), path, speech, options);
}
} // namespace morphnode
