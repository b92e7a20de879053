// SPDX-License-Identifier: BSD-3-Clause
// Gaze: the eye rig's default convention and named eyes, limits and vergence, the eye's
// rigid turn (the head's convention of behavior/HeadPose.h, rotated node frames, other rest
// directions), bad input; and on real heads (the default head, ICT-FaceKit's when present):
// the eyes are found, turn rigidly about their centre, and look where they are told.
#include "gaze/EyeRig.h"
#include "gaze/EyeRotation.h"

#include "MorphNodeTestErrors.h"
#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "behavior/BehaviorTypes.h"
#include "behavior/HeadPose.h"
#include "gltf/GltfScene.h"
#include "rig/Rig.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <random>

using morphnode::EyeAngles;
using morphnode::EyeLimits;
using morphnode::EyeRig;
using morphnode::EyeSide;
using morphnode::EyeSpec;
using morphnode::EyeTurn;
using morphnode::GazeAngles;
using morphnode::GazeDirection;
using morphnode::InputError;
using morphnode::RigidTurn;

using morphnode_test::ErrorOf;

namespace
{
using Vec3 = std::array<double, 3>;
const std::array<double, 9> Identity{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };

Vec3 Apply(const std::array<double, 9>& r, const Vec3& v)
{
  return { r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
    r[6] * v[0] + r[7] * v[1] + r[8] * v[2] };
}

double Dot(const Vec3& a, const Vec3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double Norm(const Vec3& a)
{
  return std::sqrt(Dot(a, a));
}

/// The angle between two directions in degrees.
double AngleDegrees(const Vec3& a, const Vec3& b)
{
  const double c = Dot(a, b) / (Norm(a) * Norm(b));
  return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / 3.14159265358979323846;
}

/// The rotation (row-major) of a unit quaternion (x, y, z, w).
std::array<double, 9> FromQuaternion(double x, double y, double z, double w)
{
  const double n = std::sqrt(x * x + y * y + z * z + w * w);
  x /= n, y /= n, z /= n, w /= n;
  return { 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 2 * (x * y + z * w),
    1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 2 * (x * z - y * w), 2 * (y * z + x * w),
    1 - 2 * (x * x + y * y) };
}

/// NodeAxes (x, y, z axes, 3 values each) of a rotation: its columns.
std::array<double, 9> AxesOf(const std::array<double, 9>& r)
{
  return { r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8] };
}
} // namespace

TEST(EyeRig, DefaultConventionFindsCommonEyeNames)
{
  for (const char* name :
    { "EyeLeft", "EyeRight", "eye_L", "eye_R", "LeftEye", "RightEye", "mixamorig:LeftEye", "Eye.L",
      "lEye", "rEye", "EYE", "Wolf3D_Eye", "eyeball_left", "Eye_Sclera_L" })
  {
    EXPECT_TRUE(EyeRig::MatchesDefaultConvention(name)) << name;
  }
  for (const char* name :
    { "Head", "Eyelashes", "EyeLashes", "Eyebrows", "Brows", "Eyelid_L", "EyeSocket", "M_EyeSocket",
      "Lacrimal_Eye", "EyeBlend", "EyeOcclusion", "TearLine_L", "", "Teeth", "ey e" })
  {
    EXPECT_FALSE(EyeRig::MatchesDefaultConvention(name)) << name;
  }
}

TEST(EyeRig, SideFromName)
{
  const std::map<std::string, EyeSide> expected = { { "EyeLeft", EyeSide::Left },
    { "EyeRight", EyeSide::Right }, { "eye_L", EyeSide::Left }, { "eye_R", EyeSide::Right },
    { "Eye.L", EyeSide::Left }, { "Eye.r", EyeSide::Right }, { "L_Eye", EyeSide::Left },
    { "R-eye", EyeSide::Right }, { "lEye", EyeSide::Left }, { "rEye", EyeSide::Right },
    { "EyeL", EyeSide::Left }, { "EyeR", EyeSide::Right }, { "mixamorig:LeftEye", EyeSide::Left },
    { "Eye", EyeSide::Unknown }, { "Eyes", EyeSide::Unknown }, { "L_eye_R", EyeSide::Unknown },
    { "LeftRightEye", EyeSide::Unknown }, { "", EyeSide::Unknown } };
  for (const auto& [name, side] : expected)
  {
    EXPECT_EQ(EyeRig::SideFromName(name), side) << name;
  }
}

TEST(EyeRig, NamedEyesReplaceTheConvention)
{
  EyeRig rig;
  EyeSpec eye;
  ASSERT_TRUE(rig.UsesDefaultConvention());
  ASSERT_TRUE(rig.FindEye("EyeLeft", "EyeLeft/Iris", eye));
  EXPECT_EQ(eye.Side, EyeSide::Left);
  ASSERT_TRUE(rig.FindEye("", "EyeRight/Iris", eye)) << "the part name's node prefix";
  EXPECT_EQ(eye.Side, EyeSide::Right);
  EXPECT_FALSE(rig.FindEye("Head", "Head/M_EyeSocket", eye));
  EXPECT_FALSE(rig.FindEye("", "", eye));

  EyeSpec left;
  left.Name = "Orb_A";
  left.Side = EyeSide::Left;
  left.Forward = { 0, -1, 0 };
  left.Up = { 0, 0, 1 };
  rig.AddEye(left);
  EyeSpec iris;
  iris.Name = "Orbs/IrisB";
  rig.AddEye(iris);
  EXPECT_FALSE(rig.UsesDefaultConvention());
  EXPECT_FALSE(rig.FindEye("EyeLeft", "EyeLeft/Iris", eye)) << "the convention is off";
  ASSERT_TRUE(rig.FindEye("Orb_A", "Orb_A/Sclera", eye));
  EXPECT_EQ(eye.Side, EyeSide::Left);
  EXPECT_EQ(eye.Forward[1], -1.0);
  ASSERT_TRUE(rig.FindEye("Orb_A", "", eye));
  ASSERT_TRUE(rig.FindEye("Orbs", "Orbs/IrisB", eye));
  EXPECT_EQ(eye.Name, "Orbs/IrisB");
  EXPECT_FALSE(rig.FindEye("Orbs", "Orbs/IrisA", eye)) << "another part of that node";
  EXPECT_FALSE(rig.FindEye("orb_a", "", eye)) << "names are case-sensitive";

  EXPECT_NE(ErrorOf([&] { rig.AddEye(left); }).find("named twice"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { rig.AddEye(EyeSpec()); }).find("no name"), std::string::npos);
  EyeSpec parallel;
  parallel.Name = "P";
  parallel.Up = { 0, 0, 2 };
  EXPECT_NE(ErrorOf([&] { rig.AddEye(parallel); }).find("parallel"), std::string::npos);
  parallel.Up = { 0, std::nan(""), 0 };
  EXPECT_NE(ErrorOf([&] { rig.AddEye(parallel); }).find("finite"), std::string::npos);
  EXPECT_NE(ErrorOf(
              [&] {
                rig.SetDefaultDirections({ 0, 0, 0 }, { 0, 1, 0 });
              })
              .find("zero"),
    std::string::npos);
}

TEST(EyeLimits, ClampAndVergence)
{
  const EyeLimits limits; // 40, 25 up, 35 down
  GazeAngles a = limits.Clamp({ 60.0, 40.0 });
  EXPECT_EQ(a.Yaw, 40.0);
  EXPECT_EQ(a.Pitch, 25.0);
  a = limits.Clamp({ -60.0, -50.0 });
  EXPECT_EQ(a.Yaw, -40.0);
  EXPECT_EQ(a.Pitch, -35.0);
  a = limits.Clamp({ 12.5, -7.0 });
  EXPECT_EQ(a.Yaw, 12.5);
  EXPECT_EQ(a.Pitch, -7.0);

  // Vergence: both eyes turn inward (the left eye, at +X, to -yaw), then the limits apply.
  EXPECT_EQ(EyeAngles({ 10.0, 5.0 }, 8.0, EyeSide::Left, limits).Yaw, 6.0);
  EXPECT_EQ(EyeAngles({ 10.0, 5.0 }, 8.0, EyeSide::Right, limits).Yaw, 14.0);
  EXPECT_EQ(EyeAngles({ 10.0, 5.0 }, 8.0, EyeSide::Unknown, limits).Yaw, 10.0);
  EXPECT_EQ(EyeAngles({ 38.0, 5.0 }, 8.0, EyeSide::Right, limits).Yaw, 40.0);
  EXPECT_EQ(EyeAngles({ 10.0, 5.0 }, 8.0, EyeSide::Left, limits).Pitch, 5.0);

  EXPECT_NE(ErrorOf(
              [&] {
                EyeAngles({ 0, 0 }, -1.0, EyeSide::Left, limits);
              })
              .find("vergence"),
    std::string::npos);
  EXPECT_NE(ErrorOf([&] { limits.Clamp({ std::nan(""), 0 }); }).find("finite"), std::string::npos);
  for (const double bad : { 0.0, -5.0, 91.0, std::nan(""), HUGE_VAL })
  {
    EyeLimits l;
    l.MaxUp = bad;
    EXPECT_NE(ErrorOf([&] { l.Validate(); }).find("(0, 90]"), std::string::npos) << bad;
    EyeRig rig;
    EXPECT_THROW(rig.SetLimits(l), InputError);
  }
}

TEST(EyeRotation, TheHeadsConvention)
{
  // Yaw > 0 looks to the character's left (+X), pitch > 0 up (+Y).
  EyeSpec eye;
  const Vec3 origin{ 0.03, 0.016, 0.06 };
  RigidTurn t = EyeTurn({ 30.0, 0.0 }, origin, Identity, eye);
  Vec3 forward = Apply(t.Rotation, { 0, 0, 1 });
  EXPECT_NEAR(forward[0], 0.5, 1e-12);
  EXPECT_NEAR(forward[1], 0.0, 1e-12);
  t = EyeTurn({ 0.0, 20.0 }, origin, Identity, eye);
  forward = Apply(t.Rotation, { 0, 0, 1 });
  EXPECT_NEAR(forward[1], std::sin(20.0 * M_PI / 180.0), 1e-12);
  EXPECT_NEAR(forward[0], 0.0, 1e-12);

  // The same rotation as the head's (HeadPoseMatrix, roll 0) for every yaw and pitch.
  std::mt19937 random(14);
  std::uniform_real_distribution<double> angle(-60.0, 60.0);
  for (int k = 0; k < 50; ++k)
  {
    const GazeAngles a{ angle(random), angle(random) };
    const auto head = morphnode::HeadPoseMatrix({ a.Yaw, a.Pitch, 0.0 }, { 0, 0, 0 });
    const auto r = morphnode::EyeRotationMatrix(a, Identity, eye.Forward, eye.Up);
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        EXPECT_NEAR(r[3 * i + j], head[4 * i + j], 1e-12) << a.Yaw << " " << a.Pitch;
      }
    }
    const Vec3 d = GazeDirection(a);
    const Vec3 f = Apply(r, { 0, 0, 1 });
    EXPECT_LT(AngleDegrees(d, f), 1e-6);
  }
}

TEST(EyeRotation, RigidAboutTheCentreInRotatedFramesAndOtherRestDirections)
{
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // A node rotated arbitrarily: the eye's rest direction is the node's +Z in world space,
  // yaw turns it about the node's +Y, and the turn keeps distances and the centre.
  const auto q = FromQuaternion(0.3, -0.5, 0.2, 0.8);
  const auto axes = AxesOf(q);
  const Vec3 origin{ 0.1, -0.2, 0.3 };
  EyeSpec eye;
  const GazeAngles a{ 25.0, -15.0 };
  const RigidTurn t = EyeTurn(a, origin, axes, eye);
  const Vec3 expected = Apply(q, GazeDirection(a)); // the node frame's gaze in world space
  EXPECT_LT(AngleDegrees(Apply(t.Rotation, Apply(q, { 0, 0, 1 })), expected), 1e-9);

  std::vector<double> points(3 * 50), turned(points.size());
  for (size_t i = 0; i < 50; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      points[3 * i + c] = origin[c] + 0.012 * u(random);
    }
  }
  points[0] = origin[0], points[1] = origin[1], points[2] = origin[2];
  t.TurnPoints(points.data(), turned.data(), 50);
  EXPECT_NEAR(turned[0], origin[0], 1e-15);
  EXPECT_NEAR(turned[1], origin[1], 1e-15);
  EXPECT_NEAR(turned[2], origin[2], 1e-15);
  for (size_t i = 0; i < 50; ++i)
  {
    for (size_t j = i + 1; j < 50; ++j)
    {
      const Vec3 before{ points[3 * i] - points[3 * j], points[3 * i + 1] - points[3 * j + 1],
        points[3 * i + 2] - points[3 * j + 2] };
      const Vec3 after{ turned[3 * i] - turned[3 * j], turned[3 * i + 1] - turned[3 * j + 1],
        turned[3 * i + 2] - turned[3 * j + 2] };
      EXPECT_NEAR(Norm(before), Norm(after), 1e-15);
    }
  }
  // In place, float.
  std::vector<float> f(points.begin(), points.end());
  t.TurnPoints(f.data(), f.data(), 50);
  EXPECT_NEAR(f[30], turned[30], 1e-6);

  // An eye that looks along -Y of its node with +Z up (a bone's frame) turns as a +Z eye in
  // the node frame turned to match.
  EyeSpec bone;
  bone.Forward = { 0, -2, 0 };
  bone.Up = { 0, 0, 5 };
  const auto rb = morphnode::EyeRotationMatrix(a, Identity, bone.Forward, bone.Up);
  // That frame: left = up x forward = (z) x (-y) = +x, up = +z, forward = -y.
  const std::array<double, 9> frame{ { 1, 0, 0, 0, 0, -1, 0, 1, 0 } }; // columns x, z, -y
  const Vec3 want = Apply(frame, GazeDirection(a));
  EXPECT_LT(AngleDegrees(Apply(rb, { 0, -1, 0 }), want), 1e-9);
}

TEST(EyeRotation, BadInput)
{
  EyeSpec eye;
  EXPECT_NE(ErrorOf(
              [&] {
                EyeTurn({ 0, 0 }, { std::nan(""), 0, 0 }, Identity, eye);
              })
              .find("NodeOrigin"),
    std::string::npos);
  EXPECT_NE(ErrorOf(
              [&] {
                EyeTurn({ HUGE_VAL, 0 }, { 0, 0, 0 }, Identity, eye);
              })
              .find("finite"),
    std::string::npos);
  std::array<double, 9> flat = Identity;
  flat[6] = flat[7] = flat[8] = 0.0; // no z axis
  EXPECT_NE(ErrorOf(
              [&] {
                EyeTurn({ 0, 0 }, { 0, 0, 0 }, flat, eye);
              })
              .find("axes"),
    std::string::npos);
  std::array<double, 9> nan = Identity;
  nan[4] = std::nan("");
  EXPECT_NE(ErrorOf(
              [&] {
                EyeTurn({ 0, 0 }, { 0, 0, 0 }, nan, eye);
              })
              .find("finite"),
    std::string::npos);
}

namespace
{
/// The eyes of a head found by the default convention, turned by gaze: the checks of the
/// issue on every eye part (rigid, centre fixed, the iris' direction turned to the gaze).
void CheckHead(const std::string& file, size_t eyeParts)
{
  const morphnode::GltfScene scene = morphnode::LoadGltfScene(file);
  const EyeRig rig;
  const GazeAngles gaze{ 22.0, -12.0 };
  size_t found = 0, pupils = 0;
  std::map<EyeSide, int> sides;
  for (const auto& part : scene.Parts)
  {
    EyeSpec eye;
    const std::string& node = scene.Nodes[part.Node].Name;
    if (!rig.FindEye(node, part.Name, eye))
    {
      continue;
    }
    ++found;
    const auto& m = part.World; // column-major
    const Vec3 origin{ m[12], m[13], m[14] };
    std::array<double, 9> axes{};
    for (int c = 0; c < 3; ++c)
    {
      const double l =
        std::sqrt(m[4 * c] * m[4 * c] + m[4 * c + 1] * m[4 * c + 1] + m[4 * c + 2] * m[4 * c + 2]);
      for (int r = 0; r < 3; ++r)
      {
        axes[3 * c + r] = m[4 * c + r] / l;
      }
    }
    // The side the name tells is the side the eye is on (+X is the character's left).
    ASSERT_NE(eye.Side, EyeSide::Unknown) << part.Name;
    EXPECT_EQ(eye.Side == EyeSide::Left, origin[0] > 0.0) << part.Name;
    ++sides[eye.Side];

    const size_t n = part.GetNumberOfPoints();
    ASSERT_GT(n, 10u);
    Vec3 centroid{ 0, 0, 0 };
    for (size_t i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        centroid[c] += part.Positions[3 * i + c] / static_cast<double>(n);
      }
    }
    const Vec3 rest{ centroid[0] - origin[0], centroid[1] - origin[1], centroid[2] - origin[2] };

    const RigidTurn t = EyeTurn(EyeAngles(gaze, 0.0, eye.Side, rig.GetLimits()), origin, axes, eye);
    std::vector<float> turned(part.Positions.size());
    t.TurnPoints(part.Positions.data(), turned.data(), n);
    Vec3 after{ -origin[0], -origin[1], -origin[2] };
    for (size_t i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        after[c] += turned[3 * i + c] / static_cast<double>(n);
      }
    }
    // Pairwise distances kept (a sample of pairs), the centre fixed.
    double worst = 0.0;
    for (size_t i = 0; i < n; i += 7)
    {
      const size_t j = (i * 31 + 5) % n;
      Vec3 d0, d1;
      for (int c = 0; c < 3; ++c)
      {
        d0[c] = part.Positions[3 * i + c] - part.Positions[3 * j + c];
        d1[c] = turned[3 * i + c] - turned[3 * j + c];
      }
      worst = std::max(worst, std::abs(Norm(d0) - Norm(d1)));
    }
    EXPECT_LT(worst, 1e-6) << part.Name << ": distances change (m)";
    Vec3 centre = origin;
    t.TurnPoints(origin.data(), centre.data(), 1);
    EXPECT_LT(std::abs(centre[0] - origin[0]) + std::abs(centre[1] - origin[1]) +
        std::abs(centre[2] - origin[2]),
      1e-12);

    // Normals turn with the points and stay unit.
    if (!part.Normals.empty())
    {
      std::vector<float> normals(part.Normals.size());
      t.TurnVectors(part.Normals.data(), normals.data(), n);
      EXPECT_NEAR(Norm({ normals[0], normals[1], normals[2] }),
        Norm({ part.Normals[0], part.Normals[1], part.Normals[2] }), 1e-6);
    }

    // The part's direction from the centre turns as the rig's rest direction does.
    const Vec3 want = Apply(t.Rotation, rest);
    EXPECT_LT(AngleDegrees(after, want), 1e-3) << part.Name;

    // The pupil (the default head's Pupil part; ICT-FaceKit's dark COLOR_0 in the iris):
    // at rest it looks along +Z, the rig's rest direction (within 2 degrees: the ICT pupils
    // are modelled 1.7 degrees outwards), and turned it looks at the gaze target as well as
    // it did at rest (a rotation keeps the angle).
    const bool wholePupil = part.Name.find("Pupil") != std::string::npos;
    Vec3 pupil0{ 0, 0, 0 }, pupil1{ 0, 0, 0 };
    size_t pupilPoints = 0;
    for (size_t i = 0; i < n; ++i)
    {
      if (wholePupil || (!part.Colors.empty() && part.Colors[4 * i] < 0.2f))
      {
        ++pupilPoints;
        for (int c = 0; c < 3; ++c)
        {
          pupil0[c] += part.Positions[3 * i + c] - origin[c];
          pupil1[c] += turned[3 * i + c] - origin[c];
        }
      }
    }
    if (pupilPoints > 0)
    {
      ++pupils;
      const double restError = AngleDegrees(pupil0, { 0, 0, 1 });
      EXPECT_LT(restError, 2.0) << part.Name << " at rest";
      const Vec3 target = GazeDirection(gaze);
      EXPECT_NEAR(AngleDegrees(pupil1, target), restError, 0.01) << part.Name;
      EXPECT_GT(AngleDegrees(pupil0, target), 20.0) << part.Name << ": the gaze moved it";
    }
  }
  EXPECT_EQ(pupils, 2u) << file;
  EXPECT_EQ(found, eyeParts) << file;
  EXPECT_EQ(sides[EyeSide::Left], sides[EyeSide::Right]);
}
} // namespace

TEST(EyeRotation, DefaultHeadEyesTurnRigidlyTowardsTheGaze)
{
  CheckHead(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb", 6);
}

TEST(EyeRotation, FaceKitHeadEyesTurnRigidlyTowardsTheGaze)
{
  const std::string file = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit head not found: " << file;
  }
  CheckHead(file, 4);
}

// The lids follow the eyes where the face has eyeLook targets: a look to the character's
// left (EyeYaw > 0, the eyes turn towards +X) gives the behaviour's LookLeft, which the
// ARKit rig turns into eyeLookOut_L + eyeLookIn_R, and on ICT-FaceKit's head those move
// the skin around both eyes towards +X too; LookUp/LookDown move it up and down. (The
// mapping is the behaviour's Blackboard and the rig's Look shapes: not duplicated here.)
TEST(EyeRotation, FaceKitLidsFollowTheEyes)
{
  const std::string file = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit head not found: " << file;
  }
  // The behaviour: looking at yaw 20, pitch 10 gives EyeYaw > 0, LookLeft and LookUp > 0.
  morphnode::BehaviorController behavior;
  behavior.SetSeed(5);
  behavior.SetDuration(3.0);
  behavior.LookAt(20.0, 10.0, 0.5, 2.0);
  behavior.Prepare();
  std::vector<double> channels;
  behavior.Sample(1.5, channels);
  using C = morphnode::BehaviorChannel;
  const GazeAngles gaze{ channels[C::EyeYaw], channels[C::EyePitch] };
  ASSERT_GT(gaze.Yaw, 2.0);
  ASSERT_GT(gaze.Pitch, 1.0);
  ASSERT_GT(channels[C::LookLeft], 0.0);
  ASSERT_GT(channels[C::LookUp], 0.0);
  ASSERT_EQ(channels[C::LookRight], 0.0);

  const morphnode::GltfScene scene = morphnode::LoadGltfScene(file);
  morphnode::Rig rig =
    morphnode::Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
  const int face = scene.FindPart("Head/M_Face");
  ASSERT_GE(face, 0);
  const auto& part = scene.Parts[face];
  std::vector<std::string> names;
  for (const auto& target : part.Targets)
  {
    names.push_back(target.Name);
  }
  rig.Bind(names);
  const EyeRig eyes = rig.GetEyes();

  // The mean displacement of the face's points within 2.2 cm of each eye's centre under
  // the behaviour's Look weights expanded by the rig.
  const std::vector<double> weights = rig.Expand(std::map<std::string, double>{
    { "LookUp", channels[C::LookUp] }, { "LookDown", channels[C::LookDown] },
    { "LookLeft", channels[C::LookLeft] }, { "LookRight", channels[C::LookRight] } });
  for (const auto& eyePart : scene.Parts)
  {
    EyeSpec eye;
    if (!eyes.FindEye(scene.Nodes[eyePart.Node].Name, eyePart.Name, eye) ||
      eyePart.Name.find("Sclera") == std::string::npos)
    {
      continue;
    }
    const Vec3 centre{ eyePart.World[12], eyePart.World[13], eyePart.World[14] };
    Vec3 mean{ 0, 0, 0 };
    size_t near = 0;
    for (size_t i = 0; i < part.GetNumberOfPoints(); ++i)
    {
      Vec3 d{ 0, 0, 0 };
      for (size_t t = 0; t < weights.size(); ++t)
      {
        for (int c = 0; c < 3; ++c)
        {
          d[c] += weights[t] * part.Targets[t].PositionDeltas[3 * i + c];
        }
      }
      const Vec3 p{ part.Positions[3 * i] - centre[0], part.Positions[3 * i + 1] - centre[1],
        part.Positions[3 * i + 2] - centre[2] };
      if (Norm(p) < 0.022 && Norm(d) > 1e-5)
      {
        ++near;
        for (int c = 0; c < 3; ++c)
        {
          mean[c] += d[c];
        }
      }
    }
    ASSERT_GT(near, 20u) << eyePart.Name << ": the look shapes move the skin around the eye";
    // The eye's own turn moves its front the same ways.
    const RigidTurn turn = EyeTurn(
      EyeAngles(gaze, 0.0, eye.Side, eyes.GetLimits()), centre, { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, eye);
    const Vec3 front = Apply(turn.Rotation, { 0, 0, 1 });
    EXPECT_GT(front[0], 0.0);
    EXPECT_GT(front[1], 0.0);
    EXPECT_GT(mean[0], 0.0) << eyePart.Name << ": the lids move towards +X with the eye";
    EXPECT_GT(mean[1], 0.0) << eyePart.Name << ": the lids move up with the eye";
    std::cout << eyePart.Name << ": " << near << " skin points follow, mean move ("
              << mean[0] / near * 1000 << ", " << mean[1] / near * 1000 << ", "
              << mean[2] / near * 1000 << ") mm\n";
  }
}
