// SPDX-License-Identifier: BSD-3-Clause
#include "gaze/EyeRig.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace
{
bool Finite3(const std::array<double, 3>& v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

/// Throws unless forward and up are finite, non-zero and not parallel.
void CheckDirections(
  const std::array<double, 3>& forward, const std::array<double, 3>& up, const std::string& what)
{
  if (!Finite3(forward) || !Finite3(up))
  {
    throw InputError(what + ": the forward and up directions must be finite");
  }
  const double f =
    std::sqrt(forward[0] * forward[0] + forward[1] * forward[1] + forward[2] * forward[2]);
  const double u = std::sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
  if (!(f > 1e-12) || !(u > 1e-12))
  {
    throw InputError(what + ": the forward and up directions must not be zero");
  }
  const double cx = forward[1] * up[2] - forward[2] * up[1];
  const double cy = forward[2] * up[0] - forward[0] * up[2];
  const double cz = forward[0] * up[1] - forward[1] * up[0];
  if (std::sqrt(cx * cx + cy * cy + cz * cz) < 1e-6 * f * u)
  {
    throw InputError(what + ": the forward and up directions must not be parallel");
  }
}

/// The node part of a part name: "EyeLeft" of "EyeLeft/M_Iris".
std::string NodePrefix(const std::string& partName)
{
  const size_t slash = partName.find('/');
  return slash == std::string::npos ? partName : partName.substr(0, slash);
}

bool IsSeparator(char c)
{
  return c == '_' || c == '.' || c == '-' || c == ' ' || c == ':' || c == '|';
}
} // namespace

void EyeLimits::Validate(const std::string& what) const
{
  for (const double v : { this->MaxYaw, this->MaxUp, this->MaxDown })
  {
    if (!std::isfinite(v) || v <= 0.0 || v > 90.0)
    {
      throw InputError(what + ": every limit (yaw, up, down) must be in (0, 90] degrees, got " +
        text::FormatNumber(v));
    }
  }
}

GazeAngles EyeLimits::Clamp(const GazeAngles& a) const
{
  if (!std::isfinite(a.Yaw) || !std::isfinite(a.Pitch))
  {
    throw InputError("gaze angles must be finite");
  }
  return { std::clamp(a.Yaw, -this->MaxYaw, this->MaxYaw),
    std::clamp(a.Pitch, -this->MaxDown, this->MaxUp) };
}

const char* EyeSideName(EyeSide side)
{
  switch (side)
  {
    case EyeSide::Left:
      return "left";
    case EyeSide::Right:
      return "right";
    default:
      return "unknown";
  }
}

void EyeRig::AddEye(const EyeSpec& eye)
{
  if (eye.Name.empty())
  {
    throw InputError("an eye of the rig has no name (a node or part name)");
  }
  for (const EyeSpec& other : this->Eyes)
  {
    if (other.Name == eye.Name)
    {
      throw InputError("the eye " + text::Quote(eye.Name) + " is named twice");
    }
  }
  CheckDirections(eye.Forward, eye.Up, "eye " + text::Quote(eye.Name));
  this->Eyes.push_back(eye);
}

void EyeRig::SetDefaultDirections(
  const std::array<double, 3>& forward, const std::array<double, 3>& up)
{
  CheckDirections(forward, up, "the eyes' default directions");
  this->DefaultForward = forward;
  this->DefaultUp = up;
}

void EyeRig::SetLimits(const EyeLimits& limits)
{
  limits.Validate();
  this->Limits = limits;
}

bool EyeRig::FindEye(const std::string& nodeName, const std::string& partName, EyeSpec& eye) const
{
  if (!this->Eyes.empty())
  {
    const std::string prefix = NodePrefix(partName);
    for (const EyeSpec& named : this->Eyes)
    {
      if ((!nodeName.empty() && named.Name == nodeName) ||
        (!partName.empty() && (named.Name == partName || named.Name == prefix)))
      {
        eye = named;
        return true;
      }
    }
    return false;
  }
  const std::string node = nodeName.empty() ? NodePrefix(partName) : nodeName;
  if (!MatchesDefaultConvention(node))
  {
    return false;
  }
  eye = EyeSpec();
  eye.Side = SideFromName(node);
  eye.Forward = this->DefaultForward;
  eye.Up = this->DefaultUp;
  return true;
}

bool EyeRig::MatchesDefaultConvention(const std::string& nodeName)
{
  const std::string lower = text::ToLower(nodeName);
  if (lower.find("eye") == std::string::npos)
  {
    return false;
  }
  static const char* const neighbours[] = { "lash", "brow", "lid", "socket", "lacrimal", "tear",
    "blend", "occlusion", "shadow", "bag", "liner", "highlight", "wet" };
  for (const char* word : neighbours)
  {
    if (lower.find(word) != std::string::npos)
    {
      return false;
    }
  }
  return true;
}

EyeSide EyeRig::SideFromName(const std::string& name)
{
  const std::string lower = text::ToLower(name);
  const bool left = lower.find("left") != std::string::npos;
  const bool right = lower.find("right") != std::string::npos;
  if (left != right)
  {
    return left ? EyeSide::Left : EyeSide::Right;
  }
  if (left || lower.size() < 2)
  {
    return EyeSide::Unknown; // both words, or too short to tell
  }
  // An L/R token at either end: eye_L, eye.R, L_eye, or glued to "eye": lEye, EyeL.
  const size_t n = lower.size();
  auto sideOf = [](char c)
  { return c == 'l' ? EyeSide::Left : (c == 'r' ? EyeSide::Right : EyeSide::Unknown); };
  EyeSide end = EyeSide::Unknown;
  if (IsSeparator(lower[n - 2]) || (n >= 4 && lower.compare(n - 4, 3, "eye") == 0))
  {
    end = sideOf(lower[n - 1]);
  }
  EyeSide start = EyeSide::Unknown;
  if (IsSeparator(lower[1]) || lower.compare(1, 3, "eye") == 0)
  {
    start = sideOf(lower[0]);
  }
  if (end != EyeSide::Unknown && start != EyeSide::Unknown && end != start)
  {
    return EyeSide::Unknown;
  }
  return end != EyeSide::Unknown ? end : start;
}

EyeRig MakeEyeRig(const std::vector<std::string>& names, const std::array<double, 3>& forward,
  const std::array<double, 3>& up, const EyeLimits& limits)
{
  EyeRig rig;
  rig.SetDefaultDirections(forward, up);
  rig.SetLimits(limits);
  for (const std::string& name : names)
  {
    EyeSpec eye;
    eye.Name = name;
    eye.Side = EyeRig::SideFromName(name);
    eye.Forward = forward;
    eye.Up = up;
    rig.AddEye(eye);
  }
  return rig;
}
} // namespace morphnode
