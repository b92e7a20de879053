// SPDX-License-Identifier: BSD-3-Clause
#include "track/WeightTrack.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>
#include <istream>
#include <ostream>
#include <set>
#include <sstream>

namespace morphnode
{
WeightTrack::WeightTrack(std::vector<std::string> channels, double frameRate)
  : Channels(std::move(channels))
  , FrameRate(frameRate)
{
  if (!(frameRate > 0.0) || !std::isfinite(frameRate))
  {
    throw InputError("a weight track needs a frame rate > 0");
  }
  std::set<std::string> seen;
  for (const auto& c : this->Channels)
  {
    if (!seen.insert(c).second)
    {
      throw InputError("weight track channel '" + c + "' appears twice");
    }
  }
}

int WeightTrack::FindChannel(const std::string& name) const
{
  auto it = std::find(this->Channels.begin(), this->Channels.end(), name);
  return it == this->Channels.end() ? -1 : static_cast<int>(it - this->Channels.begin());
}

void WeightTrack::AppendFrame(const double* values)
{
  this->Values.insert(this->Values.end(), values, values + this->Channels.size());
}

void WeightTrack::AppendFrame(const std::vector<double>& values)
{
  if (values.size() != this->Channels.size())
  {
    std::ostringstream msg;
    msg << "a frame of " << values.size() << " values for " << this->Channels.size() << " channels";
    throw InputError(msg.str());
  }
  this->AppendFrame(values.data());
}

double WeightTrack::Sample(double time, size_t channel) const
{
  const size_t frames = this->GetNumberOfFrames();
  if (frames == 0)
  {
    return 0.0;
  }
  const double f = std::clamp(time * this->FrameRate, 0.0, static_cast<double>(frames - 1));
  const size_t f0 = static_cast<size_t>(std::floor(f));
  const size_t f1 = std::min(f0 + 1, frames - 1);
  const double a = f - static_cast<double>(f0);
  return (1.0 - a) * this->GetValue(f0, channel) + a * this->GetValue(f1, channel);
}

void WeightTrack::WriteCsv(std::ostream& out) const
{
  out << "time";
  for (const auto& c : this->Channels)
  {
    out << "," << c;
  }
  out << "\n";
  const auto precision = out.precision(9);
  for (size_t f = 0; f < this->GetNumberOfFrames(); ++f)
  {
    out << this->GetTime(f);
    for (size_t c = 0; c < this->Channels.size(); ++c)
    {
      out << "," << this->GetValue(f, c);
    }
    out << "\n";
  }
  out.precision(precision);
}

WeightTrack WeightTrack::ReadCsv(std::istream& in)
{
  auto split = [](const std::string& line)
  {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ','))
    {
      cells.push_back(cell);
    }
    if (!line.empty() && line.back() == ',')
    {
      cells.emplace_back();
    }
    return cells;
  };
  std::string line;
  if (!std::getline(in, line))
  {
    throw InputError("weight track CSV: empty input");
  }
  if (!line.empty() && line.back() == '\r')
  {
    line.pop_back();
  }
  std::vector<std::string> header = split(line);
  if (header.size() < 2 || header[0] != "time")
  {
    throw InputError("weight track CSV line 1: expected a header 'time,<channel>,...'");
  }
  std::vector<std::string> channels(header.begin() + 1, header.end());
  for (const std::string& channel : channels)
  {
    // A control character (a second '\r' before the line end, say) would not survive
    // WriteCsv -> ReadCsv: "a\r" reads back as "a".
    if (std::any_of(channel.begin(), channel.end(),
          [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    {
      throw InputError("weight track CSV line 1: a channel name contains a control character");
    }
  }
  std::vector<double> times;
  std::vector<double> values;
  size_t lineNumber = 1;
  while (std::getline(in, line))
  {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r')
    {
      line.pop_back();
    }
    if (line.empty())
    {
      continue;
    }
    const std::vector<std::string> cells = split(line);
    if (cells.size() != header.size())
    {
      std::ostringstream msg;
      msg << "weight track CSV line " << lineNumber << ": " << cells.size() << " cells, expected "
          << header.size();
      throw InputError(msg.str());
    }
    for (size_t i = 0; i < cells.size(); ++i)
    {
      // from_chars, not a stream: a locale with a decimal comma must not misread "0.5".
      double v = 0.0;
      if (!text::ParseNumber(text::Trim(cells[i]), v))
      {
        std::ostringstream msg;
        msg << "weight track CSV line " << lineNumber << ": '" << cells[i] << "' in column '"
            << header[i] << "' is not a finite number";
        throw InputError(msg.str());
      }
      (i == 0 ? times : values).push_back(v);
    }
  }
  double rate = 30.0;
  if (times.size() >= 2)
  {
    const double dt = (times.back() - times.front()) / static_cast<double>(times.size() - 1);
    if (!(dt > 0.0))
    {
      throw InputError("weight track CSV: times must increase");
    }
    rate = 1.0 / dt;
  }
  WeightTrack track(std::move(channels), rate);
  track.Values = std::move(values);
  return track;
}
} // namespace morphnode
