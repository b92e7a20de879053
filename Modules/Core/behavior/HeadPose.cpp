// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/HeadPose.h"

#include "base/Error.h"

#include <cmath>

namespace morphnode
{
namespace
{
using Matrix3 = std::array<double, 9>; // row-major

Matrix3 Multiply(const Matrix3& a, const Matrix3& b)
{
  Matrix3 c{};
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      for (int k = 0; k < 3; ++k)
      {
        c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
      }
    }
  }
  return c;
}

/// Right-handed rotation by `degrees` about the coordinate axis `axis` (0 = X, 1 = Y, 2 = Z).
Matrix3 Rotation(int axis, double degrees)
{
  const double r = degrees * (3.14159265358979323846 / 180.0);
  const double c = std::cos(r), s = std::sin(r);
  switch (axis)
  {
    case 0:
      return { 1, 0, 0, 0, c, -s, 0, s, c };
    case 1:
      return { c, 0, s, 0, 1, 0, -s, 0, c };
    default:
      return { c, -s, 0, s, c, 0, 0, 0, 1 };
  }
}
} // namespace

std::array<double, 16> HeadPoseMatrix(const HeadAngles& a, const std::array<double, 3>& pivot)
{
  if (!std::isfinite(a.Yaw) || !std::isfinite(a.Pitch) || !std::isfinite(a.Roll) ||
    !std::isfinite(pivot[0]) || !std::isfinite(pivot[1]) || !std::isfinite(pivot[2]))
  {
    throw InputError("the head pose needs finite angles and a finite pivot");
  }
  const Matrix3 r =
    Multiply(Multiply(Rotation(1, a.Yaw), Rotation(0, -a.Pitch)), Rotation(2, -a.Roll));
  std::array<double, 16> m{};
  for (int i = 0; i < 3; ++i)
  {
    double rp = 0.0;
    for (int j = 0; j < 3; ++j)
    {
      m[4 * i + j] = r[3 * i + j];
      rp += r[3 * i + j] * pivot[j];
    }
    m[4 * i + 3] = pivot[i] - rp; // pivot + R (p - pivot)
  }
  m[15] = 1.0;
  return m;
}

HeadAngles FiniteHeadAngles(const HeadAngles& a)
{
  const auto finite = [](double v)
  {
    return std::isfinite(v) ? std::remainder(v, 360.0) : 0.0; // remainder: [-180, 180]
  };
  return { finite(a.Yaw), finite(a.Pitch), finite(a.Roll) };
}

std::array<double, 3> HeadPivot(const double bounds[6])
{
  return { 0.5 * (bounds[0] + bounds[1]), bounds[2] + 0.25 * (bounds[3] - bounds[2]),
    0.5 * (bounds[4] + bounds[5]) };
}
} // namespace morphnode
