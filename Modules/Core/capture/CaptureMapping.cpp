// SPDX-License-Identifier: BSD-3-Clause
#include "capture/CaptureMapping.h"

#include "capture/ArkitNames.h"

namespace morphnode
{
CaptureFaceMapping::CaptureFaceMapping(
  const LiveLinkCapture& capture, const std::vector<std::string>& faceTargets)
  : Capture(&capture)
  , Mapped(!faceTargets.empty())
  , ShapeChannel(ArkitShapeCount, -1)
  , Shapes(ArkitShapeCount, 0.0)
{
  this->Unmapped = capture.UnknownColumns;
  if (this->Mapped)
  {
    ArkitFaceMapping mapping;
    this->ArkitRig = MakeArkitRig(faceTargets, &mapping);
    this->Channels = faceTargets;
    this->Source.assign(faceTargets.size(), -1);
    for (size_t c = 0; c < capture.Channels.size(); ++c)
    {
      const int s = FindArkitShape(capture.Channels[c]);
      if (s >= 0)
      {
        this->ShapeChannel[static_cast<size_t>(s)] = static_cast<int>(c);
        if (mapping.Targets[static_cast<size_t>(s)].empty())
        {
          this->Unmapped.push_back(capture.Channels[c]);
        }
      }
    }
    this->Report = mapping.Report();
  }
  else
  {
    this->Report = "no face: the " +
      std::to_string(ArkitShapeCount - capture.MissingShapes.size()) +
      " ARKit shapes of the take by Apple's names";
  }
  // The angles (every channel without a face) are copied.
  for (size_t c = 0; c < capture.Channels.size(); ++c)
  {
    if (!this->Mapped || FindArkitShape(capture.Channels[c]) < 0)
    {
      this->Channels.push_back(capture.Channels[c]);
      this->Source.push_back(static_cast<int>(c));
    }
  }
  if (!this->Unmapped.empty())
  {
    this->Report += "; names that map to nothing:";
    for (const auto& name : this->Unmapped)
    {
      this->Report += " " + name;
    }
  }
}

void CaptureFaceMapping::Sample(double time, double* row) const
{
  size_t first = 0;
  if (this->Mapped)
  {
    for (size_t s = 0; s < this->Shapes.size(); ++s)
    {
      const int c = this->ShapeChannel[s];
      this->Shapes[s] = c >= 0 ? this->Capture->Sample(time, static_cast<size_t>(c)) : 0.0;
    }
    this->ArkitRig.Expand(this->Shapes.data(), row);
    first = this->ArkitRig.GetNumberOfBoundTargets();
  }
  for (size_t c = first; c < this->Channels.size(); ++c)
  {
    row[c] = this->Capture->Sample(time, static_cast<size_t>(this->Source[c]));
  }
}
} // namespace morphnode
