// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Rhubarb.h"

#include "base/Error.h"
#include "base/LibraryMessage.h"
#include "base/Text.h"

#include <expat.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <istream>
#include <iterator>
#include <limits>
#include <memory>
#include <ostream>
#include <sstream>

namespace morphnode
{
using namespace text;

namespace
{
// Times closer than this (seconds) are the same instant.
constexpr double TimeTolerance = 1e-9;

void CheckCues(const std::vector<MouthCue>& cues)
{
  double previousStart = 0.0;
  for (size_t i = 0; i < cues.size(); ++i)
  {
    const MouthCue& c = cues[i];
    const std::string where = "mouth cue " + std::to_string(i) + ": ";
    if (!IsRhubarbShape(c.Shape))
    {
      throw InputError(where + "shape " + Quote(std::string(1, c.Shape)) + " is not A-H or X");
    }
    if (!std::isfinite(c.Start) || !std::isfinite(c.End) || c.Start < 0.0 || c.End < c.Start)
    {
      throw InputError(where + "needs finite times with 0 <= start <= end");
    }
    if (c.Start < previousStart)
    {
      throw InputError(where + "starts before the cue before it");
    }
    previousStart = c.Start;
  }
}
} // namespace

bool IsRhubarbShape(char shape)
{
  return (shape >= 'A' && shape <= 'H') || shape == 'X';
}

std::vector<MouthCue> ReadRhubarbTsv(std::istream& in, double endTime)
{
  std::vector<MouthCue> cues;
  std::string text;
  size_t lineNumber = 0;
  auto fail = [&](const std::string& what)
  { throw InputError("rhubarb tsv line " + std::to_string(lineNumber) + ": " + what); };
  while (std::getline(in, text))
  {
    ++lineNumber;
    const std::string_view line = Trim(text);
    if (line.empty())
    {
      continue;
    }
    const auto tokens = SplitWhitespace(line);
    if (tokens.size() != 2)
    {
      fail("expected 'start<TAB>shape', got " + Quote(line));
    }
    MouthCue cue;
    if (!ParseNumber(tokens[0], cue.Start) || cue.Start < 0.0)
    {
      fail("start " + Quote(tokens[0]) + " is not a time in seconds >= 0");
    }
    if (tokens[1].size() != 1 || !IsRhubarbShape(tokens[1][0]))
    {
      fail("shape " + Quote(tokens[1]) + " is not one of A-H or X");
    }
    cue.Shape = tokens[1][0];
    if (!cues.empty() && cue.Start < cues.back().Start)
    {
      fail("start " + Quote(tokens[0]) + " is before the previous cue's start");
    }
    if (!cues.empty())
    {
      cues.back().End = cue.Start;
    }
    cue.End = cue.Start;
    cues.push_back(cue);
  }
  if (!cues.empty() && std::isfinite(endTime) && endTime >= cues.back().Start)
  {
    cues.back().End = endTime;
  }
  return cues;
}

std::vector<MouthCue> ParseRhubarb(const std::string& text)
{
  std::istringstream in(text);
  const std::string_view content = Trim(text);
  if (!content.empty() && content.front() == '<')
  {
    return ReadRhubarbXml(in);
  }
  return !content.empty() && content.front() == '{' ? ReadRhubarbJson(in) : ReadRhubarbTsv(in);
}

std::vector<MouthCue> ReadRhubarbFile(const std::string& path)
{
  const std::string text = text::ReadFile(path, "rhubarb file");
  try
  {
    return ParseRhubarb(text);
  }
  catch (const InputError& e)
  {
    throw InputError(path + ": " + e.what());
  }
}

void WriteRhubarbTsv(std::ostream& out, const std::vector<MouthCue>& cues)
{
  CheckCues(cues);
  for (size_t i = 0; i < cues.size(); ++i)
  {
    if (i > 0 && cues[i].Start > cues[i - 1].End + TimeTolerance)
    {
      out << FormatNumber(cues[i - 1].End) << "\tX\n"; // a gap is rest
    }
    out << FormatNumber(cues[i].Start) << '\t' << cues[i].Shape << '\n';
  }
  if (!cues.empty() && cues.back().Shape != 'X' &&
    cues.back().End > cues.back().Start + TimeTolerance)
  {
    out << FormatNumber(cues.back().End) << "\tX\n";
  }
}

std::vector<MouthCue> ReadRhubarbJson(std::istream& in)
{
  using nlohmann::json;
  json root;
  try
  {
    root = json::parse(in);
  }
  catch (const json::exception& e)
  {
    throw InputError(
      std::string("rhubarb json: not valid JSON (") + text::LibraryMessage(e.what()) + ")");
  }
  if (!root.is_object())
  {
    throw InputError("rhubarb json: the top level must be an object");
  }
  const auto list = root.find("mouthCues");
  if (list == root.end() || !list->is_array())
  {
    throw InputError("rhubarb json: 'mouthCues' must be an array");
  }
  std::vector<MouthCue> cues;
  for (size_t i = 0; i < list->size(); ++i)
  {
    const json& item = (*list)[i];
    const std::string where = "rhubarb json: mouth cue " + std::to_string(i) + ": ";
    if (!item.is_object())
    {
      throw InputError(where + "must be an object");
    }
    auto number = [&](const char* key)
    {
      const auto it = item.find(key);
      if (it == item.end() || !it->is_number() || !std::isfinite(it->get<double>()) ||
        it->get<double>() < 0.0)
      {
        throw InputError(where + "'" + key + "' must be a time in seconds >= 0");
      }
      return it->get<double>();
    };
    MouthCue cue;
    cue.Start = number("start");
    cue.End = number("end");
    const auto value = item.find("value");
    if (value == item.end() || !value->is_string() ||
      value->get_ref<const std::string&>().size() != 1 ||
      !IsRhubarbShape(value->get_ref<const std::string&>()[0]))
    {
      throw InputError(where + "'value' must be one of A-H or X");
    }
    cue.Shape = value->get_ref<const std::string&>()[0];
    if (cue.End < cue.Start)
    {
      throw InputError(where + "ends before it starts");
    }
    if (!cues.empty() && cue.Start < cues.back().Start)
    {
      throw InputError(where + "starts before the cue before it");
    }
    cues.push_back(cue);
  }
  return cues;
}

namespace
{
/// What the expat callbacks collect: the cues and the first fault.
struct XmlCues
{
  XML_Parser Parser = nullptr;
  std::vector<MouthCue> Cues;
  std::string Error;
  bool InCue = false;
  int Depth = 0;
  std::string Text;
  MouthCue Cue;

  void Fail(const std::string& what)
  {
    if (this->Error.empty())
    {
      this->Error =
        "rhubarb xml line " + std::to_string(XML_GetCurrentLineNumber(this->Parser)) + ": " + what;
      XML_StopParser(this->Parser, XML_FALSE);
    }
  }
};

void XMLCALL XmlStart(void* data, const XML_Char* name, const XML_Char** attributes)
{
  auto* x = static_cast<XmlCues*>(data);
  if (++x->Depth > 64)
  {
    x->Fail("nested too deeply");
    return;
  }
  if (x->InCue)
  {
    x->Fail("a mouthCue holds only its shape");
    return;
  }
  if (std::string(name) != "mouthCue")
  {
    return;
  }
  x->InCue = true;
  x->Text.clear();
  bool haveStart = false, haveEnd = false;
  for (size_t i = 0; attributes[i] && attributes[i + 1]; i += 2)
  {
    const std::string key = attributes[i];
    double value = 0.0;
    if (key != "start" && key != "end")
    {
      continue;
    }
    if (!text::ParseNumber(attributes[i + 1], value) || !std::isfinite(value) || value < 0.0)
    {
      x->Fail("mouthCue '" + key + "' must be a time in seconds >= 0");
      return;
    }
    (key == "start" ? x->Cue.Start : x->Cue.End) = value;
    (key == "start" ? haveStart : haveEnd) = true;
  }
  if (!haveStart || !haveEnd)
  {
    x->Fail("a mouthCue needs 'start' and 'end'");
  }
}

void XMLCALL XmlEnd(void* data, const XML_Char* name)
{
  auto* x = static_cast<XmlCues*>(data);
  --x->Depth;
  if (!x->InCue || std::string(name) != "mouthCue")
  {
    return;
  }
  x->InCue = false;
  const std::string shape(text::Trim(x->Text));
  if (shape.size() != 1 || !IsRhubarbShape(shape[0]))
  {
    x->Fail("a mouthCue's shape must be one of A-H or X");
    return;
  }
  x->Cue.Shape = shape[0];
  if (x->Cue.End < x->Cue.Start)
  {
    x->Fail("a mouthCue ends before it starts");
    return;
  }
  if (!x->Cues.empty() && x->Cue.Start < x->Cues.back().Start)
  {
    x->Fail("a mouthCue starts before the cue before it");
    return;
  }
  x->Cues.push_back(x->Cue);
}

void XMLCALL XmlText(void* data, const XML_Char* s, int length)
{
  auto* x = static_cast<XmlCues*>(data);
  if (x->InCue && x->Text.size() < 64)
  {
    x->Text.append(s, static_cast<size_t>(std::min(length, 64)));
  }
}
} // namespace

std::vector<MouthCue> ReadRhubarbXml(std::istream& in)
{
  // expat >= 2.4 (Debian 12: 2.5) limits entity amplification ("billion laughs") itself.
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  XmlCues x;
  std::unique_ptr<XML_ParserStruct, decltype(&XML_ParserFree)> parser(
    XML_ParserCreate("UTF-8"), &XML_ParserFree);
  if (!parser)
  {
    throw InputError("rhubarb xml: cannot create the XML parser");
  }
  x.Parser = parser.get();
  XML_SetUserData(parser.get(), &x);
  XML_SetElementHandler(parser.get(), XmlStart, XmlEnd);
  XML_SetCharacterDataHandler(parser.get(), XmlText);
  if (bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
  {
    throw InputError("rhubarb xml: the file is too large");
  }
  const XML_Status status =
    XML_Parse(parser.get(), bytes.data(), static_cast<int>(bytes.size()), XML_TRUE);
  if (!x.Error.empty())
  {
    throw InputError(x.Error);
  }
  if (status != XML_STATUS_OK)
  {
    throw InputError("rhubarb xml line " + std::to_string(XML_GetCurrentLineNumber(parser.get())) +
      ": not valid XML (" + XML_ErrorString(XML_GetErrorCode(parser.get())) + ")");
  }
  return x.Cues;
}

void WriteRhubarbJson(std::ostream& out, const std::vector<MouthCue>& cues,
  const std::string& soundFile, double duration)
{
  CheckCues(cues);
  using nlohmann::ordered_json;
  ordered_json root;
  root["metadata"]["soundFile"] = soundFile;
  root["metadata"]["duration"] =
    duration >= 0.0 ? duration : (cues.empty() ? 0.0 : cues.back().End);
  root["mouthCues"] = ordered_json::array();
  for (const MouthCue& c : cues)
  {
    root["mouthCues"].push_back(
      { { "start", c.Start }, { "end", c.End }, { "value", std::string(1, c.Shape) } });
  }
  out << root.dump(2) << '\n';
}

std::vector<MouthCue> VisemeTrackToMouthCues(
  const WeightTrack& visemes, const VisemeMap& map, double minimumDuration)
{
  // Channel -> shape through the table; channels the table does not know are ignored.
  std::vector<char> shapeOf(visemes.GetNumberOfChannels(), '\0');
  bool any = false;
  for (size_t c = 0; c < shapeOf.size(); ++c)
  {
    const int v = map.FindViseme(visemes.GetChannels()[c]);
    if (v >= 0)
    {
      shapeOf[c] = map.GetRhubarbShape(v);
      if (!shapeOf[c])
      {
        throw InputError("viseme table " + map.GetSetName() + " has no Rhubarb shapes");
      }
      any = true;
    }
  }
  const size_t frames = visemes.GetNumberOfFrames();
  if (!any || frames == 0)
  {
    if (frames > 0)
    {
      throw InputError("no channel of the track is a viseme of table " + map.GetSetName());
    }
    return {};
  }
  const double rate = visemes.GetFrameRate();
  const double end = visemes.GetTime(frames - 1);
  std::vector<MouthCue> cues;
  for (size_t f = 0; f < frames; ++f)
  {
    size_t best = shapeOf.size();
    for (size_t c = 0; c < shapeOf.size(); ++c)
    {
      if (shapeOf[c] &&
        (best == shapeOf.size() || visemes.GetValue(f, c) > visemes.GetValue(f, best)))
      {
        best = c;
      }
    }
    // Frame f stands for the time from half a frame before it to half a frame after.
    const double from = std::max(0.0, (static_cast<double>(f) - 0.5) / rate);
    const double to = std::min(end, (static_cast<double>(f) + 0.5) / rate);
    if (!cues.empty() && cues.back().Shape == shapeOf[best])
    {
      cues.back().End = to;
    }
    else
    {
      cues.push_back({ from, to, shapeOf[best] });
    }
  }
  if (minimumDuration > 0.0 && cues.size() > 1)
  {
    std::vector<MouthCue> kept;
    for (size_t i = 0; i < cues.size(); ++i)
    {
      MouthCue c = cues[i];
      const bool tooShort = c.End - c.Start < minimumDuration && c.Shape != 'A';
      if (tooShort && !kept.empty())
      {
        kept.back().End = c.End;
      }
      else if (tooShort && i + 1 < cues.size())
      {
        cues[i + 1].Start = c.Start;
      }
      else if (!kept.empty() && kept.back().Shape == c.Shape)
      {
        kept.back().End = c.End;
      }
      else
      {
        kept.push_back(c);
      }
    }
    cues = std::move(kept);
  }
  return cues;
}

std::vector<VisemeSegment> MouthCuesToVisemeSegments(
  const std::vector<MouthCue>& cues, const VisemeMap& map)
{
  CheckCues(cues);
  std::vector<VisemeSegment> segments;
  segments.reserve(cues.size());
  for (const MouthCue& c : cues)
  {
    VisemeSegment s;
    s.Viseme = map.GetVisemeOfShape(c.Shape);
    if (s.Viseme < 0)
    {
      throw InputError("viseme table " + map.GetSetName() + " has no viseme for Rhubarb shape '" +
        std::string(1, c.Shape) + "'");
    }
    s.Start = c.Start;
    s.Duration = c.End - c.Start;
    s.Closure = c.Shape == 'A';
    segments.push_back(s);
  }
  return segments;
}
} // namespace morphnode
