// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file WeightTrack.h
/// @brief Named channels (target or semantic-shape weights, head pose, ...) sampled at a
/// fixed frame rate: what the behaviour control produces and the morph node consumes.

#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
class WeightTrack
{
public:
  WeightTrack() = default;
  /// Throws InputError for a frame rate <= 0 or duplicate channel names.
  WeightTrack(std::vector<std::string> channels, double frameRate);

  size_t GetNumberOfChannels() const { return this->Channels.size(); }
  size_t GetNumberOfFrames() const
  {
    return this->Channels.empty() ? 0 : this->Values.size() / this->Channels.size();
  }
  double GetFrameRate() const { return this->FrameRate; }
  double GetTime(size_t frame) const { return static_cast<double>(frame) / this->FrameRate; }
  const std::vector<std::string>& GetChannels() const { return this->Channels; }
  /// -1 when absent.
  int FindChannel(const std::string& name) const;

  /// Appends one frame (GetNumberOfChannels() values).
  void AppendFrame(const double* values);
  void AppendFrame(const std::vector<double>& values);
  const double* GetFrame(size_t frame) const
  {
    return this->Values.data() + frame * this->Channels.size();
  }
  double GetValue(size_t frame, size_t channel) const
  {
    return this->Values[frame * this->Channels.size() + channel];
  }
  /// Linear interpolation between frames, clamped to the track.
  double Sample(double time, size_t channel) const;

  /// CSV: header `time,<channel>,...`, one row per frame.
  void WriteCsv(std::ostream& out) const;
  /// Reads what WriteCsv writes; the frame rate comes from the time column.
  /// Throws InputError naming the line of any malformed row.
  static WeightTrack ReadCsv(std::istream& in);

private:
  std::vector<std::string> Channels;
  double FrameRate = 30.0;
  std::vector<double> Values; // frame-major
};
} // namespace morphnode
