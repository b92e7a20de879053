// SPDX-License-Identifier: BSD-3-Clause
#include "capture/LiveLinkCsv.h"

#include "base/Error.h"
#include "base/Text.h"
#include "behavior/Frames.h"
#include "capture/ArkitNames.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <istream>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

namespace morphnode
{
namespace
{
constexpr double SecondsPerDay = 86400.0;

std::string Place(size_t line, size_t column, const std::string& name)
{
  std::ostringstream out;
  out << "Live Link CSV line " << line << ", column " << column;
  if (!name.empty())
  {
    out << " (" << text::Quote(name) << ")";
  }
  return out.str() + ": ";
}

std::vector<std::string> SplitCells(const std::string& line)
{
  std::vector<std::string> cells;
  size_t start = 0;
  while (true)
  {
    const size_t comma = line.find(',', start);
    cells.push_back(
      line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos)
    {
      return cells;
    }
    start = comma + 1;
  }
}

bool ReadLine(std::istream& in, std::string& line)
{
  if (!std::getline(in, line))
  {
    return false;
  }
  if (!line.empty() && line.back() == '\r')
  {
    line.pop_back();
  }
  return true;
}

void CheckRate(int rate)
{
  if (rate < 1 || rate > 1000)
  {
    throw InputError("Live Link CSV: the timecode rate must be a whole number of frames per "
                     "second in [1, 1000], not " +
      std::to_string(rate));
  }
}

void CheckPoseUnit(double degreesPerUnit)
{
  if (!(degreesPerUnit > 0.0) || !std::isfinite(degreesPerUnit))
  {
    throw InputError("Live Link CSV: degrees per angle unit must be > 0 and finite");
  }
}

/// A non-negative decimal integer of 1..maxDigits digits.
bool ParseField(std::string_view s, size_t maxDigits, long& value)
{
  if (s.empty() || s.size() > maxDigits)
  {
    return false;
  }
  for (char c : s)
  {
    if (c < '0' || c > '9')
    {
      return false;
    }
  }
  return text::ParseNumber(s, value);
}

std::string FixedNumber(double value)
{
  char buffer[400]; // 309 digits before the point at most, 10 after
  const auto result =
    std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, 10);
  std::string s(buffer, result.ptr);
  if (s == "-0.0000000000")
  {
    s = "0.0000000000";
  }
  return s;
}
} // namespace

int LiveLinkCapture::FindChannel(const std::string& name) const
{
  const auto it = std::find(this->Channels.begin(), this->Channels.end(), name);
  return it == this->Channels.end() ? -1 : static_cast<int>(it - this->Channels.begin());
}

double LiveLinkCapture::Sample(double time, size_t channel) const
{
  const size_t rows = this->Times.size();
  if (rows == 0 || channel >= this->Channels.size())
  {
    return 0.0;
  }
  if (!(time > this->Times.front()))
  {
    return this->GetValue(0, channel);
  }
  if (time >= this->Times.back())
  {
    return this->GetValue(rows - 1, channel);
  }
  // The first row after `time`; time lies in [Times[r - 1], Times[r]).
  const size_t r = static_cast<size_t>(
    std::upper_bound(this->Times.begin(), this->Times.end(), time) - this->Times.begin());
  const double t0 = this->Times[r - 1];
  const double t1 = this->Times[r];
  const double a = (time - t0) / (t1 - t0);
  return (1.0 - a) * this->GetValue(r - 1, channel) + a * this->GetValue(r, channel);
}

std::vector<double> LiveLinkCapture::Sample(double time) const
{
  std::vector<double> values(this->Channels.size());
  for (size_t c = 0; c < values.size(); ++c)
  {
    values[c] = this->Sample(time, c);
  }
  return values;
}

WeightTrack LiveLinkCapture::ToTrack(double frameRate) const
{
  WeightTrack track(this->Channels, frameRate);
  if (this->Times.empty())
  {
    return track;
  }
  const size_t frames = NumberOfFrames(this->GetDuration(), frameRate);
  for (size_t f = 0; f < frames; ++f)
  {
    track.AppendFrame(this->Sample(FrameTime(f, frameRate)));
  }
  return track;
}

double ParseLiveLinkTimecode(const std::string& timecode, int rate)
{
  CheckRate(rate);
  const std::string_view tc = text::Trim(timecode);
  auto bad = [&](const std::string& why)
  { return InputError("timecode " + text::Quote(tc) + " " + why); };
  // HH:MM:SS:FF[.fff]; ';' before FF marks drop-frame timecode in SMPTE notation, read the
  // same way (the rate is a whole number here).
  std::string_view fields[4];
  size_t start = 0;
  for (int i = 0; i < 3; ++i)
  {
    const size_t sep = tc.find_first_of(i == 2 ? ":;" : ":", start);
    if (sep == std::string_view::npos)
    {
      throw bad("is not HH:MM:SS:FF(.fff)");
    }
    fields[i] = tc.substr(start, sep - start);
    start = sep + 1;
  }
  fields[3] = tc.substr(start);
  std::string_view sub;
  const size_t dot = fields[3].find('.');
  if (dot != std::string_view::npos)
  {
    sub = fields[3].substr(dot + 1);
    fields[3] = fields[3].substr(0, dot);
    if (sub.empty() || sub.size() > 9 ||
      sub.find_first_not_of("0123456789") != std::string_view::npos)
    {
      throw bad("has a sub-frame part that is not 1 to 9 digits");
    }
  }
  long h = 0, m = 0, s = 0, f = 0;
  if (!ParseField(fields[0], 2, h) || !ParseField(fields[1], 2, m) ||
    !ParseField(fields[2], 2, s) || !ParseField(fields[3], 4, f))
  {
    throw bad("is not HH:MM:SS:FF(.fff)");
  }
  if (h >= 24 || m >= 60 || s >= 60)
  {
    throw bad("is not a time of day");
  }
  if (f >= rate)
  {
    throw bad("has frame " + std::to_string(f) + ", not below the rate of " + std::to_string(rate) +
      " frames per second");
  }
  double fraction = 0.0;
  if (!sub.empty())
  {
    long digits = 0;
    text::ParseNumber(sub, digits);
    fraction = static_cast<double>(digits) / std::pow(10.0, static_cast<double>(sub.size()));
  }
  return static_cast<double>(h * 3600 + m * 60 + s) + (static_cast<double>(f) + fraction) / rate;
}

std::string FormatLiveLinkTimecode(double seconds, int rate)
{
  CheckRate(rate);
  if (!std::isfinite(seconds))
  {
    throw InputError("Live Link CSV: a time that is not finite has no timecode");
  }
  seconds = std::fmod(seconds, SecondsPerDay);
  if (seconds < 0.0)
  {
    seconds += SecondsPerDay;
  }
  // Thousandths of a frame, counted as integers so that carries are exact.
  const long long perDay = static_cast<long long>(SecondsPerDay) * rate * 1000;
  long long units = std::llround(seconds * rate * 1000.0) % perDay;
  const long long sub = units % 1000;
  units /= 1000;
  const long long frame = units % rate;
  units /= rate;
  const long long s = units % 60, m = units / 60 % 60, h = units / 3600;
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%02lld:%02lld:%02lld:%02lld.%03lld", h, m, s, frame, sub);
  return buffer;
}

LiveLinkCapture ReadLiveLinkCsv(std::istream& in, const LiveLinkOptions& options)
{
  CheckRate(options.TimecodeRate);
  CheckPoseUnit(options.PoseDegreesPerUnit);
  std::string line;
  if (!ReadLine(in, line))
  {
    throw InputError("Live Link CSV: empty input, no header");
  }
  if (line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
  {
    line.erase(0, 3); // a UTF-8 byte order mark
  }
  const std::vector<std::string> header = SplitCells(line);
  if (text::ToLower(text::Trim(header[0])) != "timecode")
  {
    throw InputError(
      Place(1, 1, header[0]) + "the header must start with 'Timecode' (a Live Link Face CSV)");
  }
  // What each column holds.
  enum Kind
  {
    TimecodeColumn,
    CountColumn,
    ShapeColumn,
    PoseColumn,
    UnknownColumn
  };
  struct Column
  {
    Kind What = UnknownColumn;
    int Index = -1; // shape index or pose index
  };
  LiveLinkCapture capture;
  capture.TimecodeRate = options.TimecodeRate;
  std::vector<Column> columns(header.size());
  std::set<std::string> seen;
  std::vector<int> shapeColumn(ArkitShapeCount, -1);
  std::vector<int> poseColumn(LiveLinkPoseNames().size(), -1);
  columns[0].What = TimecodeColumn;
  for (size_t c = 1; c < header.size(); ++c)
  {
    const std::string name(text::Trim(header[c]));
    if (name.empty())
    {
      throw InputError(Place(1, c + 1, "") + "a column without a name");
    }
    if (std::any_of(name.begin(), name.end(),
          [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f; }))
    {
      throw InputError(Place(1, c + 1, name) + "a column name with a control character");
    }
    if (!seen.insert(text::ToLower(name)).second)
    {
      throw InputError(Place(1, c + 1, name) + "the column appears twice");
    }
    if (text::ToLower(name) == "blendshapecount")
    {
      columns[c].What = CountColumn;
      continue;
    }
    const int shape = FindArkitShape(name);
    if (shape >= 0)
    {
      if (shapeColumn[static_cast<size_t>(shape)] >= 0)
      {
        throw InputError(Place(1, c + 1, name) + "a second column for ARKit shape '" +
          ArkitShapeNames()[static_cast<size_t>(shape)] + "'");
      }
      shapeColumn[static_cast<size_t>(shape)] = static_cast<int>(c);
      columns[c] = { ShapeColumn, shape };
      continue;
    }
    const auto& poses = LiveLinkPoseNames();
    const auto pose = std::find_if(poses.begin(), poses.end(),
      [&](const std::string& p) { return text::ToLower(p) == text::ToLower(name); });
    if (pose != poses.end())
    {
      const int p = static_cast<int>(pose - poses.begin());
      poseColumn[static_cast<size_t>(p)] = static_cast<int>(c);
      columns[c] = { PoseColumn, p };
      continue;
    }
    capture.UnknownColumns.push_back(name);
  }
  // Output channels: shapes in file order, then the poses in the app's order, then the gaze.
  std::vector<int> channelOfColumn(header.size(), -1);
  for (size_t c = 0; c < header.size(); ++c)
  {
    if (columns[c].What == ShapeColumn)
    {
      channelOfColumn[c] = static_cast<int>(capture.Channels.size());
      capture.Channels.push_back(ArkitShapeNames()[static_cast<size_t>(columns[c].Index)]);
    }
  }
  for (size_t p = 0; p < poseColumn.size(); ++p)
  {
    if (poseColumn[p] >= 0)
    {
      channelOfColumn[static_cast<size_t>(poseColumn[p])] =
        static_cast<int>(capture.Channels.size());
      capture.Channels.push_back(LiveLinkPoseNames()[p]);
    }
  }
  // LeftEyeYaw, LeftEyePitch, RightEyeYaw, RightEyePitch: pose indices 3, 4, 6, 7.
  const bool gaze =
    poseColumn[3] >= 0 && poseColumn[4] >= 0 && poseColumn[6] >= 0 && poseColumn[7] >= 0;
  if (gaze)
  {
    capture.Channels.push_back("EyeYaw");
    capture.Channels.push_back("EyePitch");
  }
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    if (shapeColumn[s] < 0)
    {
      capture.MissingShapes.push_back(ArkitShapeNames()[s]);
    }
  }

  const size_t numChannels = capture.Channels.size();
  std::vector<double> row(numChannels);
  double previous = 0.0;
  double dayOffset = 0.0;
  size_t lineNumber = 1;
  while (ReadLine(in, line))
  {
    ++lineNumber;
    if (text::Trim(line).empty())
    {
      continue;
    }
    const std::vector<std::string> cells = SplitCells(line);
    if (cells.size() < header.size())
    {
      throw InputError(Place(lineNumber, cells.size() + 1, header[cells.size()]) +
        "missing: the row has " + std::to_string(cells.size()) + " cells, the header " +
        std::to_string(header.size()));
    }
    if (cells.size() > header.size())
    {
      throw InputError(Place(lineNumber, header.size() + 1, "") + "the row has " +
        std::to_string(cells.size()) + " cells, the header only " + std::to_string(header.size()));
    }
    double time = 0.0;
    try
    {
      time = ParseLiveLinkTimecode(cells[0], options.TimecodeRate);
    }
    catch (const InputError& e)
    {
      throw InputError(Place(lineNumber, 1, header[0]) + e.what());
    }
    for (size_t c = 1; c < cells.size(); ++c)
    {
      double v = 0.0;
      if (!text::ParseNumber(text::Trim(cells[c]), v))
      {
        throw InputError(
          Place(lineNumber, c + 1, header[c]) + text::Quote(cells[c]) + " is not a finite number");
      }
      if (columns[c].What == PoseColumn)
      {
        v *= options.PoseDegreesPerUnit;
        if (!std::isfinite(v))
        {
          throw InputError(
            Place(lineNumber, c + 1, header[c]) + text::Quote(cells[c]) + " is no angle");
        }
      }
      if (channelOfColumn[c] >= 0)
      {
        row[static_cast<size_t>(channelOfColumn[c])] = v;
      }
    }
    if (gaze)
    {
      auto value = [&](size_t pose)
      { return row[static_cast<size_t>(channelOfColumn[static_cast<size_t>(poseColumn[pose])])]; };
      row[numChannels - 2] = 0.5 * value(3) + 0.5 * value(6);
      row[numChannels - 1] = 0.5 * value(4) + 0.5 * value(7);
    }
    if (capture.Times.empty())
    {
      capture.StartTimecode = time;
    }
    else
    {
      // A take that runs past midnight: the time of day starts again from 0.
      if (time + dayOffset < previous && previous - (time + dayOffset) > SecondsPerDay / 2)
      {
        dayOffset += SecondsPerDay;
      }
      if (!(time + dayOffset > previous))
      {
        throw InputError(Place(lineNumber, 1, header[0]) + text::Quote(cells[0]) +
          " is not later than the row before it");
      }
    }
    previous = time + dayOffset;
    capture.Times.push_back(previous - capture.StartTimecode);
    capture.Values.insert(capture.Values.end(), row.begin(), row.end());
  }
  if (capture.Times.empty())
  {
    throw InputError("Live Link CSV: a header and no rows");
  }
  return capture;
}

LiveLinkCapture ReadLiveLinkCsvFile(const std::string& path, const LiveLinkOptions& options)
{
  std::istringstream in(text::ReadFile(path, "Live Link CSV"));
  try
  {
    return ReadLiveLinkCsv(in, options);
  }
  catch (const InputError& e)
  {
    throw InputError(path + ": " + e.what());
  }
}

void WriteLiveLinkCsv(
  std::ostream& out, const LiveLinkCapture& capture, const LiveLinkOptions& options)
{
  CheckRate(capture.TimecodeRate);
  CheckPoseUnit(options.PoseDegreesPerUnit);
  const auto& poses = LiveLinkPoseNames();
  std::vector<int> shapeChannel(ArkitShapeCount, -1);
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    shapeChannel[s] = capture.FindChannel(ArkitShapeNames()[s]);
  }
  std::vector<int> poseChannel(poses.size(), -1);
  for (size_t p = 0; p < poses.size(); ++p)
  {
    poseChannel[p] = capture.FindChannel(poses[p]);
  }
  // Eyes without per-eye channels turn together by the gaze channels.
  const int eyeYaw = capture.FindChannel("EyeYaw");
  const int eyePitch = capture.FindChannel("EyePitch");
  for (size_t p : { size_t(3), size_t(6) })
  {
    poseChannel[p] = poseChannel[p] >= 0 ? poseChannel[p] : eyeYaw;
  }
  for (size_t p : { size_t(4), size_t(7) })
  {
    poseChannel[p] = poseChannel[p] >= 0 ? poseChannel[p] : eyePitch;
  }
  out << "Timecode,BlendShapeCount";
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    out << "," << ArkitLiveLinkName(s);
  }
  for (const auto& p : poses)
  {
    out << "," << p;
  }
  out << "\n";
  const size_t count = ArkitShapeCount + poses.size();
  for (size_t r = 0; r < capture.GetNumberOfRows(); ++r)
  {
    out << FormatLiveLinkTimecode(capture.StartTimecode + capture.Times[r], capture.TimecodeRate)
        << "," << count;
    for (size_t s = 0; s < ArkitShapeCount; ++s)
    {
      out << ","
          << FixedNumber(shapeChannel[s] >= 0
                 ? capture.GetValue(r, static_cast<size_t>(shapeChannel[s]))
                 : 0.0);
    }
    for (size_t p = 0; p < poses.size(); ++p)
    {
      const double degrees =
        poseChannel[p] >= 0 ? capture.GetValue(r, static_cast<size_t>(poseChannel[p])) : 0.0;
      out << "," << FixedNumber(degrees / options.PoseDegreesPerUnit);
    }
    out << "\n";
  }
}

LiveLinkCapture CaptureFromTrack(
  const WeightTrack& track, const LiveLinkOptions& options, std::vector<std::string>* unmapped)
{
  CheckRate(options.TimecodeRate);
  if (!(options.StartTimecode >= 0.0 && options.StartTimecode < SecondsPerDay))
  {
    throw InputError("Live Link CSV: the start timecode must be in [0, 86400) seconds");
  }
  LiveLinkCapture capture;
  capture.TimecodeRate = options.TimecodeRate;
  capture.StartTimecode = options.StartTimecode;
  // Per output channel, the track channels averaged into it.
  std::vector<std::vector<size_t>> sources;
  std::map<int, size_t> channelOfShape;
  std::vector<size_t> poseOf;
  const auto& poses = LiveLinkPoseNames();
  std::vector<std::string> left;
  for (size_t c = 0; c < track.GetNumberOfChannels(); ++c)
  {
    const std::string& name = track.GetChannels()[c];
    const int shape = FindArkitShape(name);
    if (shape >= 0)
    {
      auto it = channelOfShape.find(shape);
      if (it == channelOfShape.end())
      {
        it = channelOfShape.emplace(shape, capture.Channels.size()).first;
        capture.Channels.push_back(ArkitShapeNames()[static_cast<size_t>(shape)]);
        sources.emplace_back();
      }
      sources[it->second].push_back(c);
      continue;
    }
    if (std::find(poses.begin(), poses.end(), name) != poses.end() || name == "EyeYaw" ||
      name == "EyePitch")
    {
      capture.Channels.push_back(name);
      sources.push_back({ c });
      continue;
    }
    left.push_back(name);
  }
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    if (!channelOfShape.count(static_cast<int>(s)))
    {
      capture.MissingShapes.push_back(ArkitShapeNames()[s]);
    }
  }
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    capture.Times.push_back(track.GetTime(f));
    for (const auto& from : sources)
    {
      double sum = 0.0;
      for (size_t c : from)
      {
        sum += track.GetValue(f, c);
      }
      capture.Values.push_back(sum / static_cast<double>(from.size()));
    }
  }
  if (unmapped)
  {
    *unmapped = std::move(left);
  }
  return capture;
}
} // namespace morphnode
