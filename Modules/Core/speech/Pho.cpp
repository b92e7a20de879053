// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Pho.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

namespace morphnode
{
using namespace text;

namespace
{
// Longer phonemes are certainly garbage; the limit also keeps the running start finite.
constexpr double MaximumDurationMs = 3.6e6;

[[noreturn]] void Fail(size_t line, const std::string& what)
{
  throw InputError("pho line " + std::to_string(line) + ": " + what);
}

/// `;; T=1.2`: applies T (time ratio) and F (frequency ratio); ignores other commands.
void ParseCommand(std::string_view body, size_t line, double& timeRatio, double& frequencyRatio)
{
  std::string compact;
  for (char c : body)
  {
    if (c != ' ' && c != '\t')
    {
      compact += c;
    }
  }
  const size_t eq = compact.find('=');
  if (eq == std::string::npos)
  {
    return; // a remark, not a setting
  }
  const std::string key = compact.substr(0, eq);
  if (key != "T" && key != "F")
  {
    return;
  }
  double value = 0.0;
  if (!ParseNumber(std::string_view(compact).substr(eq + 1), value) || !(value > 0.0) ||
    value > 1000.0)
  {
    Fail(
      line, "command " + key + " needs a ratio in (0, 1000], got " + Quote(compact.substr(eq + 1)));
  }
  (key == "T" ? timeRatio : frequencyRatio) = value;
}
} // namespace

std::vector<TimedPhoneme> ReadPho(std::istream& in)
{
  std::vector<TimedPhoneme> phonemes;
  double timeRatio = 1.0, frequencyRatio = 1.0;
  double start = 0.0;
  std::string text;
  size_t lineNumber = 0;
  while (std::getline(in, text))
  {
    ++lineNumber;
    std::string_view line = Trim(text);
    if (line.empty())
    {
      continue;
    }
    if (line.substr(0, 2) == ";;")
    {
      ParseCommand(line.substr(2), lineNumber, timeRatio, frequencyRatio);
      continue;
    }
    line = line.substr(0, line.find(';')); // a comment may also end a phoneme line
    const auto tokens = SplitWhitespace(line);
    if (tokens.empty() || tokens[0][0] == '#')
    {
      continue; // comment or flush
    }
    if (tokens.size() < 2)
    {
      Fail(lineNumber, "phoneme " + Quote(tokens[0]) + " has no duration");
    }
    double durationMs = 0.0;
    if (!ParseNumber(tokens[1], durationMs) || durationMs < 0.0)
    {
      Fail(lineNumber, "duration " + Quote(tokens[1]) + " is not a number of milliseconds >= 0");
    }
    durationMs *= timeRatio;
    if (durationMs > MaximumDurationMs)
    {
      Fail(lineNumber, "duration " + Quote(tokens[1]) + " ms is longer than an hour");
    }
    if ((tokens.size() - 2) % 2 != 0)
    {
      Fail(lineNumber, "pitch targets come in pairs 'position% pitch', found an odd count");
    }
    TimedPhoneme p;
    p.Sampa = std::string(tokens[0]);
    p.Start = start;
    p.Duration = durationMs / 1000.0;
    for (size_t i = 2; i + 1 < tokens.size(); i += 2)
    {
      double position = 0.0, pitch = 0.0;
      std::string_view positionToken = tokens[i];
      if (!positionToken.empty() && positionToken.back() == '%')
      {
        positionToken.remove_suffix(1);
      }
      if (!ParseNumber(positionToken, position) || position < 0.0 || position > 100.0)
      {
        Fail(lineNumber, "pitch position " + Quote(tokens[i]) + " is not a percentage 0..100");
      }
      if (!ParseNumber(tokens[i + 1], pitch) || !(pitch > 0.0) || pitch > 1e5)
      {
        Fail(lineNumber, "pitch " + Quote(tokens[i + 1]) + " is not a frequency in Hz > 0");
      }
      p.Pitch.emplace_back(position / 100.0, pitch * frequencyRatio);
    }
    start += p.Duration;
    phonemes.push_back(std::move(p));
  }
  return phonemes;
}

std::vector<TimedPhoneme> ParsePho(const std::string& text)
{
  std::istringstream in(text);
  return ReadPho(in);
}

std::vector<TimedPhoneme> ReadPhoFile(const std::string& path)
{
  // Kind and size checked before reading (base/File.h: a directory or a FIFO is an error
  // naming it, not a library's "basic_filebuf::underflow").
  std::istringstream in(text::ReadFile(path, "pho file"));
  try
  {
    return ReadPho(in);
  }
  catch (const InputError& e)
  {
    throw InputError(path + ": " + e.what());
  }
}

namespace
{
// Gaps below this (seconds) are rounding, not pauses.
constexpr double GapTolerance = 5e-7;

void CheckWritable(const TimedPhoneme& p, size_t index)
{
  const std::string where = "pho phoneme " + std::to_string(index) + " ";
  if (p.Sampa.empty() || p.Sampa[0] == ';' || p.Sampa[0] == '#' ||
    p.Sampa.find_first_of(" \t\r\n;") != std::string::npos)
  {
    throw InputError(where + Quote(p.Sampa) +
      ": a name must be non-empty, without blanks or ';' and not start with '#'");
  }
  if (!std::isfinite(p.Start) || !std::isfinite(p.Duration) || p.Start < 0.0 || p.Duration < 0.0)
  {
    throw InputError(where + Quote(p.Sampa) + ": start and duration must be finite and >= 0");
  }
  for (const auto& [position, pitch] : p.Pitch)
  {
    if (!(position >= 0.0 && position <= 1.0) || !(pitch > 0.0) || !std::isfinite(pitch))
    {
      throw InputError(
        where + Quote(p.Sampa) + ": pitch targets need a position in [0, 1] and a pitch > 0");
    }
  }
}
} // namespace

void WritePho(std::ostream& out, const std::vector<TimedPhoneme>& phonemes)
{
  double end = 0.0;
  for (size_t i = 0; i < phonemes.size(); ++i)
  {
    const TimedPhoneme& p = phonemes[i];
    CheckWritable(p, i);
    if (p.Start - end > GapTolerance)
    {
      out << "_ " << FormatNumber((p.Start - end) * 1000.0) << '\n';
    }
    out << p.Sampa << ' ' << FormatNumber(p.Duration * 1000.0);
    for (const auto& [position, pitch] : p.Pitch)
    {
      out << ' ' << FormatNumber(position * 100.0) << ' ' << FormatNumber(pitch);
    }
    out << '\n';
    end = std::max(end, p.Start) + p.Duration;
  }
}

void WritePhoFile(const std::string& path, const std::vector<TimedPhoneme>& phonemes)
{
  std::ofstream out(path);
  if (!out)
  {
    throw InputError("cannot write pho file '" + path + "'");
  }
  WritePho(out, phonemes);
  if (!out)
  {
    throw InputError("error while writing pho file '" + path + "'");
  }
}
} // namespace morphnode
