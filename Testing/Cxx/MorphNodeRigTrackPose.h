// SPDX-License-Identifier: BSD-3-Clause
// Poses a face from a track of rig shapes (e.g. a viseme track): the lip-sync tests on the
// ICT face (TestLipSyncOnFace, TestLipSyncLanguages) share it.
#ifndef MorphNodeRigTrackPose_h
#define MorphNodeRigTrackPose_h

#include "vtkMorphNodeFilter.h"

#include "rig/Rig.h"
#include "track/WeightTrack.h"

#include "vtkPointSet.h"

#include <algorithm>
#include <string>
#include <vector>

namespace morphnode_test
{
/// Each channel of `track` names a shape of `rig` (bound to the face's targets 1..n, the
/// neutral being target 0); At(t) sums the channels into shape weights, expands them through
/// the rig into target weights, sets them on `morph` (relative weights) and returns its
/// output at t.
class RigTrackPose
{
public:
  RigTrackPose(
    const morphnode::Rig& rig, const morphnode::WeightTrack& track, vtkMorphNodeFilter* morph)
    : Rig(rig)
    , Track(track)
    , Morph(morph)
    , ShapeWeights(rig.GetNumberOfShapes())
    , TargetWeights(rig.GetNumberOfBoundTargets())
  {
    for (const auto& channel : track.GetChannels())
    {
      this->ShapeOfChannel.push_back(rig.FindShape(channel));
      if (this->ShapeOfChannel.back() < 0 && this->Missing.empty())
      {
        this->Missing = channel;
      }
    }
    morph->SetWeightModeToRelative();
  }

  /// The first channel the rig has no shape for; empty when every channel maps.
  const std::string& GetMissingShape() const { return this->Missing; }

  vtkPointSet* At(double t)
  {
    std::fill(this->ShapeWeights.begin(), this->ShapeWeights.end(), 0.0);
    for (size_t c = 0; c < this->Track.GetNumberOfChannels(); ++c)
    {
      if (this->ShapeOfChannel[c] >= 0)
      {
        this->ShapeWeights[static_cast<size_t>(this->ShapeOfChannel[c])] +=
          this->Track.Sample(t, c);
      }
    }
    this->Rig.Expand(this->ShapeWeights.data(), this->TargetWeights.data());
    for (size_t k = 0; k < this->TargetWeights.size(); ++k)
    {
      this->Morph->SetWeight(static_cast<int>(k + 1), this->TargetWeights[k]);
    }
    this->Morph->Update();
    return vtkPointSet::SafeDownCast(this->Morph->GetOutput());
  }

private:
  const morphnode::Rig& Rig;
  const morphnode::WeightTrack& Track;
  vtkMorphNodeFilter* Morph;
  std::vector<int> ShapeOfChannel;
  std::vector<double> ShapeWeights, TargetWeights;
  std::string Missing;
};
} // namespace morphnode_test

#endif
