// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file CaptureMapping.h
/// @brief A capture's channels as a face's: the ARKit shapes of a take (Live Link Face)
/// through MakeArkitRig onto the face's own targets, then the take's head and eye angles;
/// without face targets, the take's own channels by Apple's names. What a player of a
/// capture samples (vtkLiveLinkFaceReader converts its rows to tables).

#include "capture/LiveLinkCsv.h"
#include "rig/Rig.h"

#include <string>
#include <vector>

namespace morphnode
{
class CaptureFaceMapping
{
public:
  /// `capture` must outlive the mapping. `faceTargets`: the face's relative targets (no
  /// neutral), empty for none. Throws InputError when the targets make no rig (duplicate
  /// names, ...).
  CaptureFaceMapping(const LiveLinkCapture& capture, const std::vector<std::string>& faceTargets);

  /// The output channels: the face's targets then the angles, or the take's channels.
  const std::vector<std::string>& GetChannels() const { return this->Channels; }
  /// The take's columns that are no ARKit shape or angle, then (with a face) the shapes the
  /// take has that drive no target of the face.
  const std::vector<std::string>& GetUnmapped() const { return this->Unmapped; }
  /// One line for users: the mapping's report, and the names that map to nothing.
  const std::string& GetReport() const { return this->Report; }

  /// The channels at `time` (seconds from the first row; GetChannels().size() values).
  void Sample(double time, double* row) const;

private:
  const LiveLinkCapture* Capture;
  bool Mapped = false;
  Rig ArkitRig;
  std::vector<std::string> Channels;
  std::vector<std::string> Unmapped;
  std::string Report;
  /// Per output channel from the rig's bound targets on: the capture channel it copies.
  std::vector<int> Source;
  /// Per ARKit shape: its capture channel, -1 when the take lacks it.
  std::vector<int> ShapeChannel;
  mutable std::vector<double> Shapes;
};
} // namespace morphnode
