// SPDX-License-Identifier: BSD-3-Clause
#include "capture/ArkitNames.h"

#include "base/Error.h"
#include "base/Text.h"

#include <nlohmann/json.hpp>

#include <map>
#include <sstream>
#include <stdexcept>

namespace morphnode
{
namespace
{
struct ShapeRow
{
  const char* Apple;
  const char* IctLeft;  // the ICT-FaceKit name (or its _L half)
  const char* IctRight; // the _R half of a split shape, else nullptr
};

// THE table: Apple's name and ICT-FaceKit's in Live Link Face's column order. Live Link
// Face's names are Apple's with a capital first letter.
constexpr ShapeRow Shapes[ArkitShapeCount] = {
  { "eyeBlinkLeft", "eyeBlink_L", nullptr },
  { "eyeLookDownLeft", "eyeLookDown_L", nullptr },
  { "eyeLookInLeft", "eyeLookIn_L", nullptr },
  { "eyeLookOutLeft", "eyeLookOut_L", nullptr },
  { "eyeLookUpLeft", "eyeLookUp_L", nullptr },
  { "eyeSquintLeft", "eyeSquint_L", nullptr },
  { "eyeWideLeft", "eyeWide_L", nullptr },
  { "eyeBlinkRight", "eyeBlink_R", nullptr },
  { "eyeLookDownRight", "eyeLookDown_R", nullptr },
  { "eyeLookInRight", "eyeLookIn_R", nullptr },
  { "eyeLookOutRight", "eyeLookOut_R", nullptr },
  { "eyeLookUpRight", "eyeLookUp_R", nullptr },
  { "eyeSquintRight", "eyeSquint_R", nullptr },
  { "eyeWideRight", "eyeWide_R", nullptr },
  { "jawForward", "jawForward", nullptr },
  { "jawRight", "jawRight", nullptr },
  { "jawLeft", "jawLeft", nullptr },
  { "jawOpen", "jawOpen", nullptr },
  { "mouthClose", "mouthClose", nullptr },
  { "mouthFunnel", "mouthFunnel", nullptr },
  { "mouthPucker", "mouthPucker", nullptr },
  { "mouthRight", "mouthRight", nullptr },
  { "mouthLeft", "mouthLeft", nullptr },
  { "mouthSmileLeft", "mouthSmile_L", nullptr },
  { "mouthSmileRight", "mouthSmile_R", nullptr },
  { "mouthFrownLeft", "mouthFrown_L", nullptr },
  { "mouthFrownRight", "mouthFrown_R", nullptr },
  { "mouthDimpleLeft", "mouthDimple_L", nullptr },
  { "mouthDimpleRight", "mouthDimple_R", nullptr },
  { "mouthStretchLeft", "mouthStretch_L", nullptr },
  { "mouthStretchRight", "mouthStretch_R", nullptr },
  { "mouthRollLower", "mouthRollLower", nullptr },
  { "mouthRollUpper", "mouthRollUpper", nullptr },
  { "mouthShrugLower", "mouthShrugLower", nullptr },
  { "mouthShrugUpper", "mouthShrugUpper", nullptr },
  { "mouthPressLeft", "mouthPress_L", nullptr },
  { "mouthPressRight", "mouthPress_R", nullptr },
  { "mouthLowerDownLeft", "mouthLowerDown_L", nullptr },
  { "mouthLowerDownRight", "mouthLowerDown_R", nullptr },
  { "mouthUpperUpLeft", "mouthUpperUp_L", nullptr },
  { "mouthUpperUpRight", "mouthUpperUp_R", nullptr },
  { "browDownLeft", "browDown_L", nullptr },
  { "browDownRight", "browDown_R", nullptr },
  { "browInnerUp", "browInnerUp_L", "browInnerUp_R" },
  { "browOuterUpLeft", "browOuterUp_L", nullptr },
  { "browOuterUpRight", "browOuterUp_R", nullptr },
  { "cheekPuff", "cheekPuff_L", "cheekPuff_R" },
  { "cheekSquintLeft", "cheekSquint_L", nullptr },
  { "cheekSquintRight", "cheekSquint_R", nullptr },
  { "noseSneerLeft", "noseSneer_L", nullptr },
  { "noseSneerRight", "noseSneer_R", nullptr },
  { "tongueOut", "tongueOut", nullptr },
};

const std::map<std::string, int>& Lookup()
{
  static const std::map<std::string, int> lookup = []
  {
    std::map<std::string, int> m;
    for (size_t s = 0; s < ArkitShapeCount; ++s)
    {
      const int index = static_cast<int>(s);
      m[text::ToLower(Shapes[s].Apple)] = index; // also Live Link's PascalCase
      m[text::ToLower(Shapes[s].IctLeft)] = index;
      if (Shapes[s].IctRight)
      {
        m[text::ToLower(Shapes[s].IctRight)] = index;
      }
    }
    return m;
  }();
  return lookup;
}

void Append(std::ostringstream& out, const std::vector<std::string>& names)
{
  for (size_t i = 0; i < names.size(); ++i)
  {
    out << (i ? ", " : " ") << names[i];
  }
}
} // namespace

const std::vector<std::string>& ArkitShapeNames()
{
  static const std::vector<std::string> names = []
  {
    std::vector<std::string> v;
    for (const auto& row : Shapes)
    {
      v.emplace_back(row.Apple);
    }
    return v;
  }();
  return names;
}

std::string ArkitLiveLinkName(size_t shape)
{
  std::string name = ArkitShapeNames().at(shape);
  name[0] = static_cast<char>(name[0] - 'a' + 'A');
  return name;
}

const std::vector<std::string>& ArkitIctNames(size_t shape)
{
  static const std::vector<std::vector<std::string>> names = []
  {
    std::vector<std::vector<std::string>> v;
    for (const auto& row : Shapes)
    {
      v.push_back(row.IctRight ? std::vector<std::string>{ row.IctLeft, row.IctRight }
                               : std::vector<std::string>{ row.IctLeft });
    }
    return v;
  }();
  return names.at(shape);
}

int FindArkitShape(std::string_view name)
{
  const auto& lookup = Lookup();
  const auto it = lookup.find(text::ToLower(name));
  return it == lookup.end() ? -1 : it->second;
}

const std::vector<std::string>& LiveLinkPoseNames()
{
  static const std::vector<std::string> names = { "HeadYaw", "HeadPitch", "HeadRoll", "LeftEyeYaw",
    "LeftEyePitch", "LeftEyeRoll", "RightEyeYaw", "RightEyePitch", "RightEyeRoll" };
  return names;
}

std::string ArkitFaceMapping::Report() const
{
  size_t driving = 0;
  size_t driven = 0;
  for (const auto& targets : this->Targets)
  {
    driving += targets.empty() ? 0 : 1;
    driven += targets.size();
  }
  std::ostringstream out;
  out << driving << " of " << ArkitShapeCount << " ARKit shapes drive " << driven << " of "
      << driven + this->UnmappedTargets.size() << " face targets";
  if (!this->UnmappedShapes.empty())
  {
    out << "; no target for:";
    Append(out, this->UnmappedShapes);
  }
  if (!this->UnmappedTargets.empty())
  {
    out << "; no ARKit shape for:";
    Append(out, this->UnmappedTargets);
  }
  return out.str();
}

ArkitFaceMapping MapArkitShapes(const std::vector<std::string>& faceTargets)
{
  ArkitFaceMapping mapping;
  mapping.Targets.resize(ArkitShapeCount);
  for (size_t t = 0; t < faceTargets.size(); ++t)
  {
    const int shape = FindArkitShape(faceTargets[t]);
    if (shape < 0)
    {
      mapping.UnmappedTargets.push_back(faceTargets[t]);
    }
    else
    {
      mapping.Targets[static_cast<size_t>(shape)].push_back(t);
    }
  }
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    if (mapping.Targets[s].empty())
    {
      mapping.UnmappedShapes.push_back(ArkitShapeNames()[s]);
    }
  }
  return mapping;
}

Rig MakeArkitRig(const std::vector<std::string>& faceTargets, ArkitFaceMapping* mappingOut)
{
  ArkitFaceMapping mapping = MapArkitShapes(faceTargets);
  nlohmann::ordered_json doc;
  doc["name"] = "ARKit capture";
  doc["description"] = "The 52 ARKit blendshapes onto this face's targets of the same name "
                       "(capture/ArkitNames.h): " +
    mapping.Report();
  doc["targets"] = faceTargets;
  nlohmann::ordered_json shapes = nlohmann::ordered_json::object();
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    nlohmann::ordered_json terms = nlohmann::ordered_json::object();
    for (size_t t : mapping.Targets[s])
    {
      terms[faceTargets[t]] = 1.0;
    }
    shapes[ArkitShapeNames()[s]] = terms;
  }
  doc["shapes"] = shapes;
  Rig rig = Rig::LoadString(doc.dump(), "ARKit capture rig");
  rig.Bind(faceTargets);
  if (mappingOut)
  {
    *mappingOut = std::move(mapping);
  }
  return rig;
}
} // namespace morphnode
