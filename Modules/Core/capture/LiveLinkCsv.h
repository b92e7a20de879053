// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file LiveLinkCsv.h
/// @brief Live Link Face CSV (the take files of Epic's iPhone app) in and out: ARKit
/// blendshape weights with head and eye angles per row, timed by SMPTE-style timecodes
/// (format, sources and conventions in docs/capture.md).
///
/// The file: a header `Timecode,BlendShapeCount,EyeBlinkLeft,...,TongueOut,HeadYaw,
/// HeadPitch,HeadRoll,LeftEyeYaw,LeftEyePitch,LeftEyeRoll,RightEyeYaw,RightEyePitch,
/// RightEyeRoll`, then one row per captured frame, `HH:MM:SS:FF.fff,61,<61 numbers>`:
/// FF counts frames at the timecode rate (60 in the app's takes), `.fff` is the fraction of
/// a frame. Weights are in [0, 1]; the angles in the file's unit (radians by default).

#include "track/WeightTrack.h"

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
/// A capture as read: rows at their own times (a capture may drop or repeat frames, so the
/// rows need not be evenly spaced), channels named the MorphNode way.
struct LiveLinkCapture
{
  /// Row times in seconds from the first row (0), strictly increasing.
  std::vector<double> Times;
  /// The first row's timecode as seconds since midnight; Write starts from it again.
  double StartTimecode = 0.0;
  /// The rate FF counts at.
  int TimecodeRate = 60;
  /// ARKit shapes by Apple's name (`eyeBlinkLeft`) in the file's column order, then the
  /// pose channels in degrees: HeadYaw, HeadPitch, HeadRoll, LeftEyeYaw, LeftEyePitch,
  /// LeftEyeRoll, RightEyeYaw, RightEyePitch, RightEyeRoll as far as the file has them, and
  /// EyeYaw, EyePitch (the mean of both eyes: the behaviour's gaze channels) when it has both
  /// eyes' yaw and pitch.
  std::vector<std::string> Channels;
  /// Row-major, Times.size() x Channels.size().
  std::vector<double> Values;
  /// Header names that are no ARKit shape and no pose column: read past, reported.
  std::vector<std::string> UnknownColumns;
  /// ARKit shapes the file has no column for (weigh 0).
  std::vector<std::string> MissingShapes;

  size_t GetNumberOfRows() const { return this->Times.size(); }
  /// -1 when absent.
  int FindChannel(const std::string& name) const;
  double GetValue(size_t row, size_t channel) const
  {
    return this->Values[row * this->Channels.size() + channel];
  }
  /// Linear interpolation between rows at `time` seconds, clamped to the capture.
  double Sample(double time, size_t channel) const;
  /// Every channel at `time` (Channels.size() values).
  std::vector<double> Sample(double time) const;
  /// Seconds from the first to the last row.
  double GetDuration() const { return this->Times.empty() ? 0.0 : this->Times.back(); }
  /// Sampled at i / frameRate, i = 0 .. floor(duration * frameRate) (behavior/Frames.h).
  WeightTrack ToTrack(double frameRate) const;
};

struct LiveLinkOptions
{
  /// The rate FF counts at: a whole number of frames per second in [1, 1000]; 60 in the
  /// app's takes.
  int TimecodeRate = 60;
  /// Degrees per unit of the file's angles: 180 / pi (radians, the default) or e.g. 90 for
  /// angles normalised to [-1, 1] = [-90, 90] degrees.
  double PoseDegreesPerUnit = 57.29577951308232;
  /// CaptureFromTrack only: the timecode of time 0, seconds since midnight, in [0, 86400).
  double StartTimecode = 0.0;
};

/// Reads a Live Link Face CSV. Throws InputError naming the line and column at fault: no or
/// a bad header (no `Timecode` first, a duplicate or empty name), a row with too few or too
/// many cells, a cell that is not a finite number, a malformed timecode or one with FF not
/// below the rate, times that do not increase (a take running past midnight is fine), no
/// rows at all. Nothing is returned unless the whole file reads.
LiveLinkCapture ReadLiveLinkCsv(std::istream& in, const LiveLinkOptions& options = {});
/// The same from a file (InputError when it cannot be opened).
LiveLinkCapture ReadLiveLinkCsvFile(const std::string& path, const LiveLinkOptions& options = {});

/// Parses one timecode `HH:MM:SS:FF` with an optional sub-frame fraction `.fff` (';' is
/// accepted before FF too) into seconds since midnight. Throws InputError (without a
/// place: the caller adds it).
double ParseLiveLinkTimecode(const std::string& timecode, int rate);
/// Formats seconds since midnight (wrapped into a day) as `HH:MM:SS:FF.fff`, the
/// sub-frame fraction rounded to thousandths of a frame.
std::string FormatLiveLinkTimecode(double seconds, int rate);

/// Writes a capture as Live Link Face CSV: the full header (52 shapes, 9 angles, in the app's
/// order), one row per capture row, shapes and angles it lacks written as 0, angles converted
/// from degrees. The capture's own StartTimecode and TimecodeRate are used.
void WriteLiveLinkCsv(
  std::ostream& out, const LiveLinkCapture& capture, const LiveLinkOptions& options = {});

/// A capture from a weight track (e.g. the behaviour's output expanded through a rig onto
/// an ARKit-named face): channels spelled as any ARKit name (`eyeBlinkLeft`,
/// `EyeBlinkLeft`, `eyeBlink_L`; the two halves of a split shape are averaged) become the
/// shapes; HeadYaw, HeadPitch, HeadRoll, LeftEyeYaw, ..., RightEyeRoll, and EyeYaw / EyePitch
/// (for both eyes where the per-eye channels are absent) are the angles in degrees.
/// `unmapped` (optional) receives the channels that are neither. Times are the track's
/// frames; StartTimecode and TimecodeRate come from `options`.
LiveLinkCapture CaptureFromTrack(const WeightTrack& track, const LiveLinkOptions& options = {},
  std::vector<std::string>* unmapped = nullptr);
} // namespace morphnode
