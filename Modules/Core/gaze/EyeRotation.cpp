// SPDX-License-Identifier: BSD-3-Clause
#include "gaze/EyeRotation.h"

#include "base/Error.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace morphnode
{
namespace
{
constexpr double DegreesToRadians = 3.14159265358979323846 / 180.0;

bool Finite(const double* v, size_t n)
{
  for (size_t i = 0; i < n; ++i)
  {
    if (!std::isfinite(v[i]))
    {
      return false;
    }
  }
  return true;
}

glm::dvec3 Vec(const std::array<double, 3>& v)
{
  return { v[0], v[1], v[2] };
}

/// An orthonormal frame from two directions: columns left = up x forward, up (made
/// perpendicular to forward), forward. Right-handed: left x up = forward.
glm::dmat3 Frame(const glm::dvec3& forwardIn, const glm::dvec3& upIn, const char* what)
{
  const double f = glm::length(forwardIn);
  if (!(f > 1e-12) || !std::isfinite(f))
  {
    throw InputError(std::string(what) + ": the forward direction is zero or not finite");
  }
  const glm::dvec3 forward = forwardIn / f;
  const glm::dvec3 left = glm::cross(upIn, forward);
  const double l = glm::length(left);
  if (!(l > 1e-6 * glm::length(upIn)) || !std::isfinite(l))
  {
    throw InputError(std::string(what) + ": the up direction is zero or parallel to forward");
  }
  const glm::dvec3 x = left / l;
  const glm::dvec3 y = glm::cross(forward, x);
  return glm::dmat3(x, y, forward); // columns
}

template <typename In, typename Out>
void TurnPointsImpl(const RigidTurn& t, const In* in, Out* out, size_t n)
{
  const auto& r = t.Rotation;
  const auto& c = t.Origin;
  for (size_t i = 0; i < n; ++i)
  {
    const double x = static_cast<double>(in[3 * i]) - c[0];
    const double y = static_cast<double>(in[3 * i + 1]) - c[1];
    const double z = static_cast<double>(in[3 * i + 2]) - c[2];
    out[3 * i] = static_cast<Out>(c[0] + r[0] * x + r[1] * y + r[2] * z);
    out[3 * i + 1] = static_cast<Out>(c[1] + r[3] * x + r[4] * y + r[5] * z);
    out[3 * i + 2] = static_cast<Out>(c[2] + r[6] * x + r[7] * y + r[8] * z);
  }
}

template <typename T>
void TurnVectorsImpl(const RigidTurn& t, const T* in, T* out, size_t n)
{
  const auto& r = t.Rotation;
  for (size_t i = 0; i < n; ++i)
  {
    const double x = in[3 * i], y = in[3 * i + 1], z = in[3 * i + 2];
    out[3 * i] = static_cast<T>(r[0] * x + r[1] * y + r[2] * z);
    out[3 * i + 1] = static_cast<T>(r[3] * x + r[4] * y + r[5] * z);
    out[3 * i + 2] = static_cast<T>(r[6] * x + r[7] * y + r[8] * z);
  }
}
} // namespace

void RigidTurn::TurnPoints(const float* in, float* out, size_t n) const
{
  TurnPointsImpl(*this, in, out, n);
}
void RigidTurn::TurnPoints(const double* in, float* out, size_t n) const
{
  TurnPointsImpl(*this, in, out, n);
}
void RigidTurn::TurnPoints(const double* in, double* out, size_t n) const
{
  TurnPointsImpl(*this, in, out, n);
}
void RigidTurn::TurnPoints(const float* in, double* out, size_t n) const
{
  TurnPointsImpl(*this, in, out, n);
}
void RigidTurn::TurnVectors(const float* in, float* out, size_t n) const
{
  TurnVectorsImpl(*this, in, out, n);
}
void RigidTurn::TurnVectors(const double* in, double* out, size_t n) const
{
  TurnVectorsImpl(*this, in, out, n);
}

std::array<double, 3> GazeDirection(const GazeAngles& a)
{
  const double yaw = a.Yaw * DegreesToRadians, pitch = a.Pitch * DegreesToRadians;
  return { std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw) };
}

GazeAngles EyeAngles(const GazeAngles& gaze, double vergence, EyeSide side, const EyeLimits& limits)
{
  if (!std::isfinite(vergence) || vergence < 0.0)
  {
    throw InputError("the vergence must be finite and >= 0 degrees");
  }
  GazeAngles eye = gaze;
  if (side == EyeSide::Left)
  {
    eye.Yaw -= 0.5 * vergence;
  }
  else if (side == EyeSide::Right)
  {
    eye.Yaw += 0.5 * vergence;
  }
  return limits.Clamp(eye);
}

std::array<double, 9> EyeRotationMatrix(const GazeAngles& angles, const std::array<double, 9>& axes,
  const std::array<double, 3>& forward, const std::array<double, 3>& up)
{
  if (!std::isfinite(angles.Yaw) || !std::isfinite(angles.Pitch))
  {
    throw InputError("gaze angles must be finite");
  }
  if (!Finite(axes.data(), 9) || !Finite(forward.data(), 3) || !Finite(up.data(), 3))
  {
    throw InputError("an eye's node axes and directions must be finite");
  }
  // The node's axes, orthonormalized (z kept, y made perpendicular to it, x = y x z).
  const glm::dvec3 nodeX(axes[0], axes[1], axes[2]);
  const glm::dvec3 nodeY(axes[3], axes[4], axes[5]);
  const glm::dvec3 nodeZ(axes[6], axes[7], axes[8]);
  glm::dmat3 node = Frame(nodeZ, nodeY, "the eye node's axes");
  if (glm::dot(node[0], nodeX) < 0.0)
  {
    node[0] = -node[0]; // a mirroring node stays mirrored
  }
  const glm::dmat3 eye = node * Frame(Vec(forward), Vec(up), "the eye's directions");

  // R = Ry(yaw) * Rx(-pitch) in the eye's frame (left, up, forward).
  const glm::dmat4 ry =
    glm::rotate(glm::dmat4(1.0), angles.Yaw * DegreesToRadians, glm::dvec3(0, 1, 0));
  const glm::dmat4 rx =
    glm::rotate(glm::dmat4(1.0), -angles.Pitch * DegreesToRadians, glm::dvec3(1, 0, 0));
  const glm::dmat3 local = glm::dmat3(ry * rx);
  // The eye frame is orthogonal (a mirroring node gives det -1): its inverse is its transpose.
  const glm::dmat3 world = eye * local * glm::transpose(eye);
  std::array<double, 9> r{};
  for (int row = 0; row < 3; ++row)
  {
    for (int col = 0; col < 3; ++col)
    {
      r[3 * row + col] = world[col][row]; // glm is column-major
    }
  }
  return r;
}

RigidTurn EyeTurn(const GazeAngles& angles, const std::array<double, 3>& origin,
  const std::array<double, 9>& axes, const EyeSpec& eye)
{
  if (!Finite(origin.data(), 3))
  {
    throw InputError("an eye's centre (NodeOrigin) must be finite");
  }
  RigidTurn turn;
  turn.Rotation = EyeRotationMatrix(angles, axes, eye.Forward, eye.Up);
  turn.Origin = origin;
  return turn;
}
} // namespace morphnode
