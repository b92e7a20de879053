// SPDX-License-Identifier: BSD-3-Clause
#include "skin/AvatarBones.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gaze/EyeRotation.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace morphnode
{
bool NamesJawOpenTarget(const std::vector<std::string>& targetNames)
{
  return std::any_of(targetNames.begin(), targetNames.end(),
    [](const std::string& name)
    {
      std::string n = text::ToLower(name);
      n.erase(std::remove(n.begin(), n.end(), '_'), n.end());
      return n == "jawopen";
    });
}

std::string CanonicalBoneName(const std::string& name)
{
  std::string lower = text::ToLower(name);
  static const char* const prefixes[] = { "mixamorig:", "mixamorig_", "mixamorig", "cc_base_",
    "j_bip_c_", "j_bip_", "j_adj_", "bip01 ", "bip01_", "def-", "org-", "armature|", "armature_" };
  for (bool again = true; again;)
  {
    again = false;
    for (const char* p : prefixes)
    {
      const std::string prefix(p);
      if (lower.compare(0, prefix.size(), prefix) == 0)
      {
        lower.erase(0, prefix.size());
        again = true;
      }
    }
  }
  std::string out;
  for (char c : lower)
  {
    if (std::isalnum(static_cast<unsigned char>(c)))
    {
      out += c;
    }
  }
  return out;
}

std::string AvatarBoneRoles::Describe(const Skeleton& skeleton) const
{
  std::string out;
  auto add = [&](const char* role, int joint)
  {
    if (!out.empty())
    {
      out += ", ";
    }
    out += std::string(role) + " " +
      (joint >= 0 ? text::Quote(skeleton.GetJoint(static_cast<size_t>(joint)).Name)
                  : std::string("none"));
  };
  add("head", this->Head);
  add("neck", this->Neck);
  add("left eye", this->LeftEye);
  add("right eye", this->RightEye);
  add("jaw", this->Jaw);
  add("left arm", this->LeftUpperArm);
  add("right arm", this->RightUpperArm);
  for (auto [role, joint] : { std::pair<const char*, int>{ "left upper lid", this->LeftUpperLid },
         { "right upper lid", this->RightUpperLid }, { "left lower lid", this->LeftLowerLid },
         { "right lower lid", this->RightLowerLid } })
  {
    if (joint >= 0)
    {
      add(role, joint);
    }
  }
  return out;
}

std::vector<size_t> PointsUnderJoint(
  const Skeleton& skeleton, const SkinJoints& joints, const SkinInfluences& influences, int joint)
{
  std::vector<size_t> points;
  const size_t per = influences.PerPoint;
  for (size_t i = 0; joint >= 0 && i < influences.GetNumberOfPoints(); ++i)
  {
    size_t best = 0;
    for (size_t k = 1; k < per; ++k)
    {
      best = influences.Weights[i * per + k] > influences.Weights[i * per + best] ? k : best;
    }
    if (skeleton.IsAncestor(joint, joints.Joints[influences.Joints[i * per + best]]))
    {
      points.push_back(i);
    }
  }
  return points;
}

AvatarBoneRoles FindAvatarBones(const Skeleton& skeleton)
{
  AvatarBoneRoles roles;
  const size_t n = skeleton.GetNumberOfJoints();
  auto find = [&](std::initializer_list<const char*> names)
  {
    for (const char* want : names)
    {
      for (size_t j = 0; j < n; ++j)
      {
        if (CanonicalBoneName(skeleton.GetJoint(j).Name) == want)
        {
          return static_cast<int>(j);
        }
      }
    }
    return -1;
  };
  roles.Head = find({ "head" });
  roles.Neck = find({ "neck", "necktwist01", "neck1", "neck01" });
  roles.Jaw = find({ "jaw", "jawroot", "lowerjaw", "jawbone" });
  roles.LeftUpperArm =
    find({ "leftarm", "leftupperarm", "lupperarm", "upperarml", "luparm", "larm" });
  roles.LeftForeArm = find({ "leftforearm", "leftlowerarm", "lforearm", "forearml", "llowerarm" });
  roles.RightUpperArm =
    find({ "rightarm", "rightupperarm", "rupperarm", "upperarmr", "ruparm", "rarm" });
  roles.RightForeArm =
    find({ "rightforearm", "rightlowerarm", "rforearm", "forearmr", "rlowerarm" });
  for (size_t j = 0; j < n; ++j)
  {
    const std::string& name = skeleton.GetJoint(j).Name;
    // An eye bone lies below the head (when there is one) and is called an eye by the
    // gaze concept's convention (not a lid, lash, brow, ... bone); its end bones are not.
    const std::string canonical = CanonicalBoneName(name);
    if (!EyeRig::MatchesDefaultConvention(name) || canonical.find("end") != std::string::npos ||
      canonical.find("target") != std::string::npos ||
      (roles.Head >= 0 && !skeleton.IsAncestor(roles.Head, static_cast<int>(j))))
    {
      continue;
    }
    EyeSide side = EyeRig::SideFromName(name);
    if (side == EyeSide::Unknown && canonical.size() > 1 &&
      canonical.find("eye") != std::string::npos)
    {
      // CC_Base_L_Eye, Bip01 LEye: a side letter the prefixes hid from SideFromName.
      side = canonical[0] == 'l' ? EyeSide::Left
        : canonical[0] == 'r'    ? EyeSide::Right
                                 : EyeSide::Unknown;
    }
    if (side == EyeSide::Left && roles.LeftEye < 0)
    {
      roles.LeftEye = static_cast<int>(j);
    }
    else if (side == EyeSide::Right && roles.RightEye < 0)
    {
      roles.RightEye = static_cast<int>(j);
    }
  }
  // Eyelid bones: "lid" in the name with upper/lower and a side, below the head.
  for (size_t j = 0; j < n; ++j)
  {
    const std::string& name = skeleton.GetJoint(j).Name;
    const std::string canonical = CanonicalBoneName(name);
    if (canonical.find("lid") == std::string::npos || canonical.find("end") != std::string::npos ||
      (roles.Head >= 0 && !skeleton.IsAncestor(roles.Head, static_cast<int>(j))))
    {
      continue;
    }
    const bool upper =
      canonical.find("upper") != std::string::npos || canonical.find("top") != std::string::npos;
    const bool lower =
      canonical.find("lower") != std::string::npos || canonical.find("bottom") != std::string::npos;
    EyeSide side = EyeRig::SideFromName(name);
    if (side == EyeSide::Unknown && !canonical.empty())
    {
      side = canonical[0] == 'l' ? EyeSide::Left
        : canonical[0] == 'r'    ? EyeSide::Right
                                 : EyeSide::Unknown;
    }
    int* role = side == EyeSide::Left ? (upper      ? &roles.LeftUpperLid
                                            : lower ? &roles.LeftLowerLid
                                                    : nullptr)
      : side == EyeSide::Right        ? (upper      ? &roles.RightUpperLid
                                            : lower ? &roles.RightLowerLid
                                                    : nullptr)
                                      : nullptr;
    if (role && *role < 0)
    {
      *role = static_cast<int>(j);
    }
  }
  return roles;
}

glm::dquat HeadRotation(double yaw, double pitch, double roll)
{
  const double d = glm::pi<double>() / 180.0;
  return glm::angleAxis(yaw * d, glm::dvec3(0, 1, 0)) *
    glm::angleAxis(-pitch * d, glm::dvec3(1, 0, 0)) *
    glm::angleAxis(-roll * d, glm::dvec3(0, 0, 1));
}

AvatarBoneRoles FindAvatarBones(
  const Skeleton& skeleton, const std::map<std::string, std::string>& humanoid)
{
  AvatarBoneRoles roles = FindAvatarBones(skeleton);
  for (auto [bone, role] :
    { std::pair<const char*, int*>{ "head", &roles.Head }, { "neck", &roles.Neck },
      { "leftEye", &roles.LeftEye }, { "rightEye", &roles.RightEye }, { "jaw", &roles.Jaw },
      { "leftUpperArm", &roles.LeftUpperArm }, { "leftLowerArm", &roles.LeftForeArm },
      { "rightUpperArm", &roles.RightUpperArm }, { "rightLowerArm", &roles.RightForeArm } })
  {
    const auto it = humanoid.find(bone);
    const int joint = it == humanoid.end() ? -1 : skeleton.FindJoint(it->second);
    if (joint >= 0)
    {
      *role = joint;
    }
  }
  return roles;
}

namespace
{
/// One eye's angles through VRM's range maps: yaw inner or outer by the eye's side and the
/// direction (the left eye, at +X, looks outward at positive yaw), pitch down or up.
GazeAngles MapEyeAngles(const GazeAngles& in, EyeSide side, const EyeRangeMaps& m)
{
  auto map = [](double v, double max, double scale)
  { return !(max > 0.0) ? 0.0 : (v < 0 ? -1.0 : 1.0) * std::min(std::abs(v), max) / max * scale; };
  const bool outward = side == EyeSide::Left ? in.Yaw > 0.0
    : side == EyeSide::Right                 ? in.Yaw < 0.0
                                             : true;
  GazeAngles out;
  out.Yaw = outward ? map(in.Yaw, m.OuterMax, m.OuterScale) : map(in.Yaw, m.InnerMax, m.InnerScale);
  out.Pitch =
    in.Pitch > 0.0 ? map(in.Pitch, m.UpMax, m.UpScale) : map(in.Pitch, m.DownMax, m.DownScale);
  return out;
}
} // namespace

void PoseAvatarBones(SkeletonPose& pose, const AvatarBoneRoles& roles, const AvatarBonePose& a)
{
  for (double v : { a.HeadYaw, a.HeadPitch, a.HeadRoll, a.EyeYaw, a.EyePitch, a.Vergence,
         a.NeckShare, a.JawOpen, a.MaxJawAngle, a.LidFollow })
  {
    if (!std::isfinite(v))
    {
      throw InputError("avatar bones: the head, gaze and jaw angles must be finite");
    }
  }
  if (a.NeckShare < 0.0 || a.NeckShare > 1.0)
  {
    throw InputError("avatar bones: the neck's share of the head turn must lie in [0, 1]");
  }
  const glm::dquat frame = glm::quat_cast(a.FaceFrame);
  auto inWorld = [&](const glm::dquat& q) { return frame * q * glm::inverse(frame); };
  const glm::dquat head = HeadRotation(a.HeadYaw, a.HeadPitch, a.HeadRoll);
  const bool headTurns = a.HeadYaw != 0.0 || a.HeadPitch != 0.0 || a.HeadRoll != 0.0;
  const glm::dquat identity(1.0, 0.0, 0.0, 0.0);
  double neckShare =
    roles.Neck >= 0 && roles.Head >= 0 ? a.NeckShare : (roles.Neck >= 0 ? 1.0 : 0.0);
  if (roles.Neck >= 0 && neckShare > 0.0 && headTurns)
  {
    pose.TurnJoint(roles.Neck, inWorld(glm::slerp(identity, head, neckShare)));
  }
  if (roles.Head >= 0 && neckShare < 1.0 && headTurns)
  {
    pose.TurnJoint(roles.Head, inWorld(glm::slerp(identity, head, 1.0 - neckShare)));
  }
  if (a.RelaxArms)
  {
    for (const auto& [upper, fore] : { std::pair<int, int>{ roles.LeftUpperArm, roles.LeftForeArm },
           std::pair<int, int>{ roles.RightUpperArm, roles.RightForeArm } })
    {
      if (upper < 0 || fore < 0)
      {
        continue;
      }
      const auto world = pose.World();
      const glm::dvec3 from = glm::dvec3(world[static_cast<size_t>(fore)][3]) -
        glm::dvec3(world[static_cast<size_t>(upper)][3]);
      const glm::dvec3 down = -a.FaceFrame[1];
      const glm::dvec3 side = from - glm::dot(from, down) * down; // out to the side (and forward)
      if (glm::length(from) <= 0.0 || glm::length(side) <= 1e-9 * glm::length(from))
      {
        continue; // already straight down
      }
      const double angle = a.ArmAngle * glm::pi<double>() / 180.0;
      const glm::dvec3 to = std::cos(angle) * down + std::sin(angle) * glm::normalize(side);
      const glm::dvec3 f = glm::normalize(from);
      const glm::dvec3 axis = glm::cross(f, to);
      if (glm::length(axis) > 1e-12)
      {
        pose.TurnJoint(upper,
          glm::angleAxis(std::acos(glm::clamp(glm::dot(f, to), -1.0, 1.0)), glm::normalize(axis)));
      }
    }
  }
  // The eyes turn in the face's frame as the head has turned it.
  const glm::dquat turnedFrame = (roles.Head >= 0 || roles.Neck >= 0) ? head : identity;
  for (const auto& [joint, side] : { std::pair<int, EyeSide>{ roles.LeftEye, EyeSide::Left },
         std::pair<int, EyeSide>{ roles.RightEye, EyeSide::Right } })
  {
    if (joint < 0)
    {
      continue;
    }
    EyeLimits open;
    open.MaxYaw = open.MaxUp = open.MaxDown = 90.0;
    const GazeAngles angles = a.RangeMaps.Enabled
      ? MapEyeAngles(
          EyeAngles(GazeAngles{ a.EyeYaw, a.EyePitch }, a.Vergence, side, open), side, a.RangeMaps)
      : EyeAngles(GazeAngles{ a.EyeYaw, a.EyePitch }, a.Vergence, side, a.Limits);
    if (angles.Yaw == 0.0 && angles.Pitch == 0.0)
    {
      continue;
    }
    const glm::dquat gaze = HeadRotation(angles.Yaw, angles.Pitch, 0.0);
    pose.TurnJoint(joint, inWorld(turnedFrame * gaze * glm::inverse(turnedFrame)));
    // The lids of this eye follow its pitch.
    const int upper = side == EyeSide::Left ? roles.LeftUpperLid : roles.RightUpperLid;
    const int lower = side == EyeSide::Left ? roles.LeftLowerLid : roles.RightLowerLid;
    for (auto [lid, share] :
      { std::pair<int, double>{ upper, a.LidFollow }, { lower, 0.5 * a.LidFollow } })
    {
      // (a lid below the eye joint already turns with it)
      if (lid >= 0 && share != 0.0 && angles.Pitch != 0.0 &&
        !pose.GetSkeleton().IsAncestor(joint, lid))
      {
        const glm::dquat follow = HeadRotation(0.0, share * angles.Pitch, 0.0);
        pose.TurnJoint(lid, inWorld(turnedFrame * follow * glm::inverse(turnedFrame)));
      }
    }
  }
  // The jaw: chin down (negative pitch) about its pivot, in the turned face.
  const double jaw = std::clamp(a.JawOpen, 0.0, 1.0) * a.MaxJawAngle;
  if (roles.Jaw >= 0 && jaw != 0.0)
  {
    const glm::dquat open = HeadRotation(0.0, -jaw, 0.0);
    pose.TurnJoint(roles.Jaw, inWorld(turnedFrame * open * glm::inverse(turnedFrame)));
  }
}
bool TurnedByEyeJoints(const SkinInfluences& influences, const std::vector<int>& skinJoints,
  const Skeleton& skeleton, const AvatarBoneRoles& roles)
{
  const size_t n = influences.GetNumberOfPoints();
  if (n == 0 || !roles.HasEyes())
  {
    return false;
  }
  const size_t per = influences.PerPoint;
  for (size_t i = 0; i < n; ++i)
  {
    size_t best = 0;
    for (size_t k = 1; k < per; ++k)
    {
      best = influences.Weights[i * per + k] > influences.Weights[i * per + best] ? k : best;
    }
    const size_t local = influences.Joints[i * per + best];
    if (local >= skinJoints.size())
    {
      return false;
    }
    const int joint = skinJoints[local];
    if (!(roles.LeftEye >= 0 && skeleton.IsAncestor(roles.LeftEye, joint)) &&
      !(roles.RightEye >= 0 && skeleton.IsAncestor(roles.RightEye, joint)))
    {
      return false;
    }
  }
  return true;
}
} // namespace morphnode
