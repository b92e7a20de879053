// SPDX-License-Identifier: BSD-3-Clause
// The head pose convention (behavior/HeadPose.h): angles seen from the character, degrees,
// roll then pitch then yaw, about the pivot.
#include "base/Error.h"
#include "behavior/HeadPose.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

using namespace morphnode;

namespace
{
using Vec3 = std::array<double, 3>;

Vec3 Apply(const std::array<double, 16>& m, const Vec3& p)
{
  Vec3 q{};
  for (int i = 0; i < 3; ++i)
  {
    q[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3];
  }
  return q;
}

void ExpectNear(const Vec3& a, const Vec3& b)
{
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_NEAR(a[i], b[i], 1e-12) << "component " << i;
  }
}

const Vec3 Origin{ 0, 0, 0 };
const Vec3 Nose{ 0, 0, 1 };  // the face looks along +Z
const Vec3 Crown{ 0, 1, 0 }; // +Y up
} // namespace

TEST(HeadPose, ZeroAnglesAreTheIdentity)
{
  const auto m = HeadPoseMatrix({}, { 1, 2, 3 });
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_NEAR(m[i], i % 5 == 0 ? 1.0 : 0.0, 1e-15) << i;
  }
}

TEST(HeadPose, AnglesAreSeenFromTheCharacter)
{
  // Yaw > 0 turns to its left (+X), in degrees.
  ExpectNear(Apply(HeadPoseMatrix({ 90, 0, 0 }, Origin), Nose), { 1, 0, 0 });
  // Pitch > 0 looks up.
  ExpectNear(Apply(HeadPoseMatrix({ 0, 90, 0 }, Origin), Nose), { 0, 1, 0 });
  // Roll > 0 tilts the crown to its left (+X).
  ExpectNear(Apply(HeadPoseMatrix({ 0, 0, 90 }, Origin), Crown), { 1, 0, 0 });
  // Small angles are small: 10 degrees of yaw moves the nose by sin(10 deg).
  const Vec3 n = Apply(HeadPoseMatrix({ 10, 0, 0 }, Origin), Nose);
  EXPECT_NEAR(n[0], std::sin(10.0 * 3.14159265358979323846 / 180.0), 1e-12);
}

TEST(HeadPose, RollThenPitchThenYaw)
{
  // Pitch up by 90 first points the nose up; a yaw about the vertical leaves it there.
  // The other order (yaw first) would point it to the left.
  ExpectNear(Apply(HeadPoseMatrix({ 90, 90, 0 }, Origin), Nose), { 0, 1, 0 });
  // Roll first: the crown goes to the left (+X); a pitch about X leaves it; yaw 90 turns
  // +X into -Z.
  ExpectNear(Apply(HeadPoseMatrix({ 90, 90, 90 }, Origin), Crown), { 0, 0, -1 });
}

TEST(HeadPose, TurnsAboutThePivot)
{
  const std::array<double, 3> pivot{ 0.5, -1.0, 2.0 };
  const auto m = HeadPoseMatrix({ 17, -8, 5 }, pivot);
  ExpectNear(Apply(m, pivot), pivot);
  // A rigid motion: distances from the pivot are kept, and the last row is (0 0 0 1).
  const Vec3 p{ 1.5, 0.25, 3.0 };
  const Vec3 q = Apply(m, p);
  auto dist = [&](const Vec3& a)
  {
    return std::sqrt((a[0] - pivot[0]) * (a[0] - pivot[0]) + (a[1] - pivot[1]) * (a[1] - pivot[1]) +
      (a[2] - pivot[2]) * (a[2] - pivot[2]));
  };
  EXPECT_NEAR(dist(q), dist(p), 1e-12);
  EXPECT_EQ(m[12], 0.0);
  EXPECT_EQ(m[13], 0.0);
  EXPECT_EQ(m[14], 0.0);
  EXPECT_EQ(m[15], 1.0);
}

TEST(HeadPose, PivotIsTheTopOfTheNeck)
{
  const double bounds[6] = { -1, 1, 0, 4, 2, 6 };
  const auto pivot = HeadPivot(bounds);
  EXPECT_EQ(pivot[0], 0.0);
  EXPECT_EQ(pivot[1], 1.0);
  EXPECT_EQ(pivot[2], 4.0);
}

TEST(HeadPose, NonFiniteAnglesAreAnInputError)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(HeadPoseMatrix({ nan, 0, 0 }, Origin), InputError);
  EXPECT_THROW(
    HeadPoseMatrix({ 0, 0, 0 }, { 0, std::numeric_limits<double>::infinity(), 0 }), InputError);
}

TEST(HeadPose, FiniteHeadAnglesKeepsAFrame)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const HeadAngles a = FiniteHeadAngles({ nan, inf, 370.0 });
  EXPECT_EQ(a.Yaw, 0.0);
  EXPECT_EQ(a.Pitch, 0.0);
  EXPECT_NEAR(a.Roll, 10.0, 1e-12);
  const HeadAngles b = FiniteHeadAngles({ 12.5, -30.0, -180.0 });
  EXPECT_EQ(b.Yaw, 12.5);
  EXPECT_EQ(b.Pitch, -30.0);
  EXPECT_NO_THROW(HeadPoseMatrix(FiniteHeadAngles({ -inf, 1e308, nan }), Origin));
}
