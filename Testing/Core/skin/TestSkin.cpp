// SPDX-License-Identifier: BSD-3-Clause
// Skins: skeletons (world transforms, turns about a joint's pivot), linear blend skinning
// against hand-computed points, normals by the inverse transpose, renormalized weights of two
// sets, re-skinning of rest-posed geometry equal to skinning the bind-space mesh, bad skins;
// a head's bones found by name in every naming family and turned by head pose and gaze (the
// eye's centre fixed, its direction within a degree, the head carrying the eyes).
#include "skin/AvatarBones.h"
#include "skin/Skeleton.h"
#include "skin/Skinning.h"

#include "MorphNodeTestErrors.h"
#include "base/Error.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>

using namespace morphnode;
using morphnode_test::ErrorOf;

namespace
{
constexpr double Pi = 3.14159265358979323846;

glm::dquat AxisAngle(double degrees, const glm::dvec3& axis)
{
  return glm::angleAxis(degrees * Pi / 180.0, glm::normalize(axis));
}

Joint MakeJoint(
  const std::string& name, int parent, glm::dvec3 t, glm::dquat r = glm::dquat(1, 0, 0, 0))
{
  Joint j;
  j.Name = name;
  j.Parent = parent;
  j.Translation = t;
  j.Rotation = r;
  return j;
}

void ExpectNear(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-9)
{
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}
} // namespace

TEST(Skeleton, WorldTransformsNestAndParentsMayFollowChildren)
{
  Skeleton s;
  // The child first: Validate orders them.
  s.AddJoint(MakeJoint("Child", 1, { 0, 1, 0 }));
  s.AddJoint(MakeJoint("Root", -1, { 1, 0, 0 }, AxisAngle(90, { 0, 0, 1 })));
  s.Validate();
  const auto world = s.World(s.RestLocals());
  // Root turns +Y into -X: the child at (0, 1, 0) in the root's frame lies at (0, 0, 0).
  ExpectNear(glm::dvec3(world[0][3]), { 0, 0, 0 });
  ExpectNear(glm::dvec3(world[1][3]), { 1, 0, 0 });
  EXPECT_EQ(s.FindJoint("Root"), 1);
  EXPECT_TRUE(s.IsAncestor(1, 0));
  EXPECT_FALSE(s.IsAncestor(0, 1));
}

TEST(Skeleton, BadSkeletonsAreRefused)
{
  Skeleton cycle;
  cycle.AddJoint(MakeJoint("A", 1, {}));
  cycle.AddJoint(MakeJoint("B", 0, {}));
  EXPECT_NE(ErrorOf([&] { cycle.Validate(); }).find("cycle"), std::string::npos);
  Skeleton nan;
  nan.AddJoint(MakeJoint("A", -1, { std::nan(""), 0, 0 }));
  EXPECT_NE(ErrorOf([&] { nan.Validate(); }).find("not finite"), std::string::npos);
  Skeleton parent;
  parent.AddJoint(MakeJoint("A", 3, {}));
  EXPECT_NE(ErrorOf([&] { parent.Validate(); }).find("parent 3"), std::string::npos);
}

TEST(Skeleton, TurnJointKeepsThePivotAndCarriesChildren)
{
  Skeleton s;
  s.AddJoint(MakeJoint("Neck", -1, { 0, 1, 0 }, AxisAngle(30, { 1, 0, 0 })));
  s.AddJoint(MakeJoint("Head", 0, { 0, 0.5, 0 }));
  s.Validate();
  SkeletonPose pose(s);
  const auto rest = pose.World();
  pose.TurnJoint(0, AxisAngle(90, { 0, 1, 0 }));
  const auto world = pose.World();
  ExpectNear(glm::dvec3(world[0][3]), glm::dvec3(rest[0][3])); // the pivot stays
  // The head turns with the neck: its offset from the neck turned by 90 degrees about +Y.
  const glm::dvec3 offset = glm::dvec3(rest[1][3]) - glm::dvec3(rest[0][3]);
  ExpectNear(
    glm::dvec3(world[1][3]) - glm::dvec3(world[0][3]), AxisAngle(90, { 0, 1, 0 }) * offset);
}

TEST(Skinning, TwoJointsBlendAsTheSpecificationSays)
{
  // Joint matrices by hand: J0 = translate(1, 0, 0), J1 = rotate 90 degrees about Z.
  const std::vector<glm::dmat4> m = { glm::translate(glm::dmat4(1.0), glm::dvec3(1, 0, 0)),
    glm::dmat4(glm::mat4_cast(AxisAngle(90, { 0, 0, 1 }))) };
  SkinInfluences inf;
  // Point 0: all J0; point 1: 1/4 J0 + 3/4 J1 (weights 1 and 3, renormalized).
  inf.AddSet({ 0, 1, 0, 0, 0, 1, 0, 0 }, { 1, 0, 0, 0, 1, 3, 0, 0 }, 2);
  inf.Normalize(2, "test");
  EXPECT_FLOAT_EQ(inf.Weights[4], 0.25f);
  EXPECT_FLOAT_EQ(inf.Weights[5], 0.75f);
  const float points[] = { 1, 0, 0, 1, 0, 0 };
  float out[6];
  SkinPoints<float>(inf, m, points, nullptr, out, nullptr, 0, 2);
  EXPECT_NEAR(out[0], 2.0, 1e-6);
  EXPECT_NEAR(out[1], 0.0, 1e-6);
  // 0.25 (2, 0, 0) + 0.75 (0, 1, 0)
  EXPECT_NEAR(out[3], 0.5, 1e-6);
  EXPECT_NEAR(out[4], 0.75, 1e-6);
  EXPECT_NEAR(out[5], 0.0, 1e-6);
}

TEST(Skinning, NormalsGoByTheInverseTransposeAndAreRenormalized)
{
  const std::vector<glm::dmat4> m = { glm::scale(glm::dmat4(1.0), glm::dvec3(2, 1, 1)) };
  SkinInfluences inf;
  inf.AddSet({ 0, 0, 0, 0 }, { 1, 0, 0, 0 }, 1);
  inf.Normalize(1, "test");
  const double s = std::sqrt(0.5);
  const double points[] = { 0, 0, 0 }, normals[] = { s, s, 0 };
  double p[3], n[3];
  SkinPoints<double>(inf, m, points, normals, p, n, 0, 1);
  // diag(1/2, 1, 1) (1, 1, 0), renormalized; a plain transform would give (2, 1, 0).
  const glm::dvec3 expected = glm::normalize(glm::dvec3(0.5, 1, 0));
  ExpectNear({ n[0], n[1], n[2] }, expected, 1e-12);
}

TEST(Skinning, TwoWeightSetsAreBothUsed)
{
  const std::vector<glm::dmat4> m = { glm::dmat4(1.0),
    glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 4)) };
  SkinInfluences inf;
  inf.AddSet({ 0, 0, 0, 0 }, { 0.5f, 0, 0, 0 }, 1);
  inf.AddSet({ 1, 0, 0, 0 }, { 0.5f, 0, 0, 0 }, 1);
  inf.Normalize(2, "test");
  ASSERT_EQ(inf.PerPoint, 8u);
  const float points[] = { 0, 0, 0 };
  float out[3];
  SkinPoints<float>(inf, m, points, nullptr, out, nullptr, 0, 1);
  EXPECT_NEAR(out[2], 2.0, 1e-6); // JOINTS_0 alone would give 0
}

TEST(Skinning, ReskinningTheRestPoseEqualsSkinningTheBindPose)
{
  // A bind pose unlike the rest pose: the rest matrices are not identity.
  const std::vector<glm::dmat4> rest = { glm::translate(glm::dmat4(1.0), glm::dvec3(0, 1, 0)),
    glm::dmat4(glm::mat4_cast(AxisAngle(40, { 1, 1, 0 }))) *
      glm::scale(glm::dmat4(1.0), glm::dvec3(1, 2, 1)) };
  const std::vector<glm::dmat4> posed = { glm::dmat4(glm::mat4_cast(AxisAngle(-25, { 0, 1, 0 }))),
    glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0, 0)) * rest[1] };
  SkinInfluences inf;
  inf.AddSet(
    { 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0 }, { 1, 0, 0, 0, 0.3f, 0.7f, 0, 0, 1, 0, 0, 0 }, 3);
  inf.Normalize(2, "test");
  const double bind[] = { 1, 2, 3, -1, 0.5, 2, 0, 0, 1 };
  const double bindNormals[] = { 0, 0, 1, 0, 1, 0, 1, 0, 0 };
  const double delta[] = { 0.1, 0, 0, 0, 0.2, 0, 0, 0, -0.3 };
  // Rest pose of base and delta (what the loader gives), then morph there and re-skin.
  double restPoints[9], restNormals[9], expected[9], expectedNormals[9], morphedBind[9];
  SkinPoints<double>(inf, rest, bind, bindNormals, restPoints, restNormals, 0, 3);
  for (size_t i = 0; i < 3; ++i)
  {
    const glm::dmat3 l(BlendedMatrix(inf, rest, i));
    const glm::dvec3 d = l * glm::dvec3(delta[3 * i], delta[3 * i + 1], delta[3 * i + 2]);
    for (int k = 0; k < 3; ++k)
    {
      restPoints[3 * i + k] += d[k];
      morphedBind[3 * i + k] = bind[3 * i + k] + delta[3 * i + k];
    }
  }
  SkinPoints<double>(inf, posed, morphedBind, bindNormals, expected, expectedNormals, 0, 3);
  RestSkin skin(inf, rest, "test");
  EXPECT_TRUE(skin.SetPose(posed));
  double out[9], outNormals[9];
  skin.Apply<double>(restPoints, restNormals, out, outNormals, 0, 3);
  for (int k = 0; k < 9; ++k)
  {
    EXPECT_NEAR(out[k], expected[k], 1e-6) << k;
    EXPECT_NEAR(outNormals[k], expectedNormals[k], 1e-6) << k;
  }
  // Skinning after morphing differs from morphing after skinning (the order matters here).
  double skinnedFirst[9];
  SkinPoints<double>(inf, posed, bind, nullptr, skinnedFirst, nullptr, 0, 3);
  EXPECT_GT(std::abs(skinnedFirst[0] + delta[0] - expected[0]) +
      std::abs(skinnedFirst[1] - expected[1]) + std::abs(skinnedFirst[2] - expected[2]),
    1e-3);
  // At rest nothing moves, and points are copied.
  EXPECT_FALSE(skin.SetPose(rest));
  skin.Apply<double>(restPoints, restNormals, out, outNormals, 0, 3);
  for (int k = 0; k < 9; ++k)
  {
    EXPECT_EQ(out[k], restPoints[k]);
  }
}

TEST(Skinning, DamagedSkinsAreRefused)
{
  Skeleton s;
  s.AddJoint(MakeJoint("A", -1, {}));
  s.Validate();
  SkinJoints joints;
  joints.Joints = { 0 };
  joints.InverseBind = { glm::dmat4(0.0) };
  joints.InverseBind[0][3][3] = 1.0;
  EXPECT_NE(ErrorOf([&] { joints.Validate(s, "skin"); }).find("singular"), std::string::npos);
  joints.InverseBind = { glm::dmat4(1.0) };
  joints.InverseBind[0][1][1] = std::nan("");
  EXPECT_NE(ErrorOf([&] { joints.Validate(s, "skin"); }).find("not finite"), std::string::npos);
  joints.Joints = { 4 };
  joints.InverseBind = { glm::dmat4(1.0) };
  EXPECT_NE(ErrorOf([&] { joints.Validate(s, "skin"); }).find("does not exist"), std::string::npos);

  SkinInfluences range;
  range.AddSet({ 0, 3, 0, 0 }, { 0.5f, 0.5f, 0, 0 }, 1);
  EXPECT_NE(
    ErrorOf([&] { range.Normalize(2, "skin"); }).find("bound to joint 3"), std::string::npos);
  SkinInfluences nan;
  nan.AddSet({ 0, 0, 0, 0 }, { std::nanf(""), 0, 0, 0 }, 1);
  EXPECT_NE(ErrorOf([&] { nan.Normalize(1, "skin"); }).find("weight"), std::string::npos);
  SkinInfluences zero;
  zero.AddSet({ 0, 0, 0, 0 }, { 0, 0, 0, 0 }, 1);
  EXPECT_NE(ErrorOf([&] { zero.Normalize(1, "skin"); }).find("no weight"), std::string::npos);
  SkinInfluences fraction;
  EXPECT_NE(ErrorOf(
              [&] {
                fraction.AddSet({ 0.5f, 0, 0, 0 }, { 1, 0, 0, 0 }, 1);
              })
              .find("16-bit"),
    std::string::npos);
}

TEST(AvatarBones, EveryNamingFamilyIsFound)
{
  struct Family
  {
    const char* Head;
    const char* Neck;
    const char* Left;
    const char* Right;
    const char* Jaw;
  };
  const Family families[] = {
    { "Head", "Neck", "LeftEye", "RightEye", "Jaw" }, // RPM, Avaturn, MPFB
    { "mixamorig:Head", "mixamorig:Neck", "mixamorig:LeftEye", "mixamorig:RightEye",
      "mixamorig:Jaw" },                              // Mixamo
    { "head", "neck", "leftEye", "rightEye", "jaw" }, // VRM humanoid
    { "J_Bip_C_Head", "J_Bip_C_Neck", "J_Adj_L_FaceEye", "J_Adj_R_FaceEye",
      "J_Bip_C_Jaw" }, // VRoid
    { "CC_Base_Head", "CC_Base_NeckTwist01", "CC_Base_L_Eye", "CC_Base_R_Eye",
      "CC_Base_JawRoot" },                                                   // CC
    { "Bip01 Head", "Bip01 Neck", "Bip01 LEye", "Bip01 REye", "Bip01 Jaw" }, // Rocketbox
    { "head", "neck", "eye.L", "eye.R", "jaw" },                             // Blender
  };
  for (const Family& f : families)
  {
    Skeleton s;
    s.AddJoint(MakeJoint("Hips", -1, { 0, 1, 0 }));
    const int neck = s.AddJoint(MakeJoint(f.Neck, 0, { 0, 0.4, 0 }));
    const int head = s.AddJoint(MakeJoint(f.Head, neck, { 0, 0.1, 0 }));
    s.AddJoint(MakeJoint("LeftEyelid", head, { 0.03, 0.08, 0.09 }));
    const int left = s.AddJoint(MakeJoint(f.Left, head, { 0.03, 0.08, 0.1 }));
    const int right = s.AddJoint(MakeJoint(f.Right, head, { -0.03, 0.08, 0.1 }));
    const int jaw = s.AddJoint(MakeJoint(f.Jaw, head, { 0, 0, 0.05 }));
    s.Validate();
    const AvatarBoneRoles roles = FindAvatarBones(s);
    EXPECT_EQ(roles.Head, head) << f.Head;
    EXPECT_EQ(roles.Neck, neck) << f.Neck;
    EXPECT_EQ(roles.LeftEye, left) << f.Left;
    EXPECT_EQ(roles.RightEye, right) << f.Right;
    EXPECT_EQ(roles.Jaw, jaw) << f.Jaw;
  }
}

TEST(AvatarBones, EyesTurnAboutTheirJointAndTheHeadCarriesThem)
{
  // Eye bones as Blender writes them: local +Y along the bone, pointing forward.
  Skeleton s;
  const int hips = s.AddJoint(MakeJoint("Hips", -1, { 0, 0.9, 0 }));
  const int neck = s.AddJoint(MakeJoint("Neck", hips, { 0, 0.5, 0 }, AxisAngle(-10, { 1, 0, 0 })));
  const int head = s.AddJoint(MakeJoint("Head", neck, { 0, 0.06, 0 }, AxisAngle(10, { 1, 0, 0 })));
  const int eye =
    s.AddJoint(MakeJoint("LeftEye", head, { 0.031, 0.08, 0.1 }, AxisAngle(90, { 1, 0, 0 })));
  s.Validate();
  const AvatarBoneRoles roles = FindAvatarBones(s);
  ASSERT_EQ(roles.LeftEye, eye);
  SkeletonPose rest(s);
  const auto restWorld = rest.World();
  const glm::dvec3 centre(restWorld[eye][3]);
  const glm::dvec3 cornea = centre + glm::dvec3(0, 0, 0.012); // a point in front of the eye

  // Gaze left by 20 degrees: the centre stays, the cornea turns 20 degrees to +X.
  SkeletonPose pose(s);
  AvatarBonePose angles;
  angles.EyeYaw = 20;
  PoseAvatarBones(pose, roles, angles);
  auto world = pose.World();
  const glm::dmat4 eyeMove = world[eye] * glm::inverse(restWorld[eye]);
  ExpectNear(glm::dvec3(eyeMove * glm::dvec4(centre, 1)), centre, 1e-12);
  glm::dvec3 dir = glm::normalize(glm::dvec3(eyeMove * glm::dvec4(cornea, 1)) - centre);
  EXPECT_LT(
    std::acos(glm::dot(dir, glm::dvec3(std::sin(20 * Pi / 180), 0, std::cos(20 * Pi / 180)))) *
      180 / Pi,
    1.0);

  // Beyond the limits (40 degrees by default) the eye stops at them.
  SkeletonPose far(s);
  angles.EyeYaw = 70;
  PoseAvatarBones(far, roles, angles);
  world = far.World();
  dir = glm::normalize(
    glm::dvec3(world[eye] * glm::inverse(restWorld[eye]) * glm::dvec4(cornea, 1)) - centre);
  EXPECT_NEAR(std::atan2(dir.x, dir.z) * 180 / Pi, 40.0, 1e-6);

  // A head turn of 30 degrees (shared with the neck) carries the eye: its centre turns
  // about the neck and head pivots, and it looks 30 degrees to the left without a gaze.
  SkeletonPose turned(s);
  AvatarBonePose headTurn;
  headTurn.HeadYaw = 30;
  PoseAvatarBones(turned, roles, headTurn);
  world = turned.World();
  const glm::dmat4 move = world[eye] * glm::inverse(restWorld[eye]);
  const glm::dvec3 movedCentre(move * glm::dvec4(centre, 1));
  EXPECT_GT(glm::length(movedCentre - centre), 0.01);
  dir = glm::normalize(glm::dvec3(move * glm::dvec4(cornea, 1)) - movedCentre);
  EXPECT_NEAR(std::atan2(dir.x, dir.z) * 180 / Pi, 30.0, 1e-6);
  // The head as a whole turned by R: the head joint's rotation relative to rest is R.
  const glm::dmat3 headMove = glm::dmat3(world[head]) * glm::inverse(glm::dmat3(restWorld[head]));
  const glm::dmat3 r = glm::mat3_cast(HeadRotation(30, 0, 0));
  for (int c = 0; c < 3; ++c)
  {
    ExpectNear(headMove[c], r[c], 1e-9);
  }
  EXPECT_NE(ErrorOf(
              [&]
              {
                AvatarBonePose bad;
                bad.HeadYaw = std::nan("");
                PoseAvatarBones(turned, roles, bad);
              })
              .find("finite"),
    std::string::npos);
}

TEST(AvatarBones, RelaxedArmsHangDown)
{
  Skeleton s;
  const int hips = s.AddJoint(MakeJoint("Hips", -1, { 0, 1, 0 }));
  const int arm = s.AddJoint(MakeJoint("LeftArm", hips, { 0.2, 0.4, 0 }));
  // A-pose: the forearm 45 degrees down and out, a little forward.
  const int fore = s.AddJoint(MakeJoint("LeftForeArm", arm, { 0.2, -0.2, 0.05 }));
  s.Validate();
  const AvatarBoneRoles roles = FindAvatarBones(s);
  ASSERT_EQ(roles.LeftUpperArm, arm);
  ASSERT_EQ(roles.LeftForeArm, fore);
  SkeletonPose pose(s);
  AvatarBonePose relaxed;
  relaxed.RelaxArms = true;
  PoseAvatarBones(pose, roles, relaxed);
  const auto world = pose.World();
  const glm::dvec3 d = glm::normalize(glm::dvec3(world[fore][3]) - glm::dvec3(world[arm][3]));
  EXPECT_NEAR(std::acos(-d.y) * 180 / Pi, 12.0, 1e-6);    // 12 degrees out from straight down
  EXPECT_GT(d.x, 0.0);                                    // still on its own side
  ExpectNear(glm::dvec3(world[arm][3]), { 0.2, 1.4, 0 }); // the shoulder stays
}

TEST(AvatarBones, PointsUnderTheHeadByTheirStrongestJoint)
{
  // Spine <- Neck <- Head <- Eye; a skin of the spine, the head and the eye.
  Skeleton s;
  s.AddJoint(MakeJoint("Spine", -1, {}));
  s.AddJoint(MakeJoint("Neck", 0, { 0, 1, 0 }));
  s.AddJoint(MakeJoint("Head", 1, { 0, 0.5, 0 }));
  s.AddJoint(MakeJoint("Eye", 2, { 0, 0.1, 0.1 }));
  s.Validate();
  SkinJoints joints;
  joints.Joints = { 0, 2, 3 }; // skin joint k -> skeleton joint
  SkinInfluences inf;
  // Point 0: spine only; 1: head 0.7, spine 0.3; 2: eye; 3: spine 0.6, head 0.4.
  inf.AddSet({ 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0 },
    { 1, 0, 0, 0, 0.7f, 0.3f, 0, 0, 1, 0, 0, 0, 0.6f, 0.4f, 0, 0 }, 4);
  inf.Normalize(3, "test");
  EXPECT_EQ(PointsUnderJoint(s, joints, inf, 2), (std::vector<size_t>{ 1, 2 }))
    << "the head and the eye below it";
  EXPECT_EQ(PointsUnderJoint(s, joints, inf, 0), (std::vector<size_t>{ 0, 1, 2, 3 }))
    << "everything is under the root";
  EXPECT_TRUE(PointsUnderJoint(s, joints, inf, -1).empty());
}

// The jaw: JawOpen turns the jaw joint chin-down about its own pivot by JawOpen *
// MaxJawAngle, in the face as the head has turned it; the teeth tip (a point in front of
// and below the pivot) goes down and back; nothing moves without a jaw joint or at 0.
TEST(AvatarBones, JawOpensAboutItsPivotInTheTurnedFace)
{
  Skeleton s;
  const int hips = s.AddJoint(MakeJoint("Hips", -1, { 0, 0.9, 0 }));
  const int neck = s.AddJoint(MakeJoint("Neck", hips, { 0, 0.5, 0 }));
  const int head = s.AddJoint(MakeJoint("Head", neck, { 0, 0.06, 0 }));
  const int jaw = s.AddJoint(MakeJoint("Jaw", head, { 0, 0.0, 0.02 }, AxisAngle(120, { 1, 0, 0 })));
  s.Validate();
  const AvatarBoneRoles roles = FindAvatarBones(s);
  ASSERT_EQ(roles.Jaw, jaw);
  SkeletonPose rest(s);
  const auto restWorld = rest.World();
  const glm::dvec3 pivot(restWorld[jaw][3]);
  const glm::dvec3 chin = pivot + glm::dvec3(0, -0.03, 0.06);

  SkeletonPose pose(s);
  AvatarBonePose angles;
  angles.JawOpen = 0.8; // 20 degrees of the default 25
  PoseAvatarBones(pose, roles, angles);
  auto world = pose.World();
  glm::dmat4 move = world[jaw] * glm::inverse(restWorld[jaw]);
  ExpectNear(glm::dvec3(move * glm::dvec4(pivot, 1)), pivot, 1e-12);
  const glm::dvec3 moved(move * glm::dvec4(chin, 1));
  EXPECT_LT(moved.y, chin.y - 0.01) << "the chin did not go down";
  const glm::dvec3 a = glm::normalize(chin - pivot), b = glm::normalize(moved - pivot);
  EXPECT_NEAR(std::acos(glm::dot(a, b)) * 180 / Pi, 20.0, 1e-6);
  EXPECT_NEAR(moved.x, chin.x, 1e-12); // about the left-right axis
  // The head turned 30 degrees: the jaw opens in the turned face (still about its axis).
  SkeletonPose turned(s);
  angles.HeadYaw = 30;
  PoseAvatarBones(turned, roles, angles);
  world = turned.World();
  const glm::dmat3 jawMove = glm::dmat3(world[jaw]) * glm::inverse(glm::dmat3(restWorld[jaw]));
  const glm::dmat3 expected = glm::mat3_cast(HeadRotation(30, 0, 0) * HeadRotation(0, -20, 0));
  for (int c = 0; c < 3; ++c)
  {
    ExpectNear(jawMove[c], expected[c], 1e-9);
  }
  // Closed: the jaw stays; without a jaw joint nothing else moves either.
  SkeletonPose closed(s);
  AvatarBonePose none;
  PoseAvatarBones(closed, roles, none);
  EXPECT_EQ(closed.World()[jaw], restWorld[jaw]);
  (void)head;
}

// A VRM humanoid map wins over the names' guess (bones named nothing like a head), and VRM
// look-at range maps replace the limits: 45 of 90 input degrees outward turn a bone of
// scale 12 by 6 degrees; inward by the inner map; beyond the input maximum it stops.
TEST(AvatarBones, VrmHumanoidMapAndLookAtRangeMaps)
{
  Skeleton s;
  const int root = s.AddJoint(MakeJoint("Root", -1, { 0, 1.5, 0 }));
  const int b1 = s.AddJoint(MakeJoint("Bone.001", root, { 0, 0.1, 0 }));
  const int b2 = s.AddJoint(MakeJoint("Bone.002", b1, { 0.03, 0.05, 0.08 }));
  s.Validate();
  EXPECT_EQ(FindAvatarBones(s).Head, -1);
  const AvatarBoneRoles roles = FindAvatarBones(
    s, { { "head", "Bone.001" }, { "leftEye", "Bone.002" }, { "jaw", "NoSuchNode" } });
  EXPECT_EQ(roles.Head, b1);
  EXPECT_EQ(roles.LeftEye, b2);
  EXPECT_EQ(roles.Jaw, -1);
  SkeletonPose rest(s);
  const glm::dmat4 restEye = rest.World()[b2];
  auto yawOf = [&](double eyeYaw)
  {
    SkeletonPose pose(s);
    AvatarBonePose a;
    a.EyeYaw = eyeYaw;
    a.RangeMaps.Enabled = true;
    a.RangeMaps.OuterScale = 12.0;
    a.RangeMaps.InnerScale = 4.0;
    PoseAvatarBones(pose, roles, a);
    const glm::dmat3 m = glm::dmat3(pose.World()[b2]) * glm::inverse(glm::dmat3(restEye));
    const glm::dvec3 f = m * glm::dvec3(0, 0, 1);
    return std::atan2(f.x, f.z) * 180 / Pi;
  };
  EXPECT_NEAR(yawOf(45), 6.0, 1e-9);   // outward for the left eye
  EXPECT_NEAR(yawOf(-45), -2.0, 1e-9); // inward
  EXPECT_NEAR(yawOf(200), 12.0, 1e-9);
}

// RestSkin's fast paths give what exact skinning gives: rest matrices that differ by float
// rounding (1e-7, as a bind pose's) share the float path; a point on one rigidly turned
// joint (normal turned without renormalizing), a point on one scaled joint (normal by the
// inverse transpose, renormalized), a point blended between both; each against
// SkinPoints of the bind pose (double precision) at the pose.
TEST(Skinning, RestSkinFastPathsEqualExactSkinning)
{
  const glm::dmat4 rest0(1.0);
  glm::dmat4 rest1(1.0);
  rest1[3][0] = 1e-7; // float rounding of an inverse bind matrix
  const std::vector<glm::dmat4> rest = { rest0, rest1 };
  const std::vector<glm::dmat4> pose = { glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(0, 1, 0)) *
      rest0,
    glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0, 0)), glm::dvec3(2, 1, 0.5)) *
      rest1 };
  SkinInfluences inf;
  inf.AddSet(
    { 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0 }, { 1, 0, 0, 0, 1, 0, 0, 0, 0.3f, 0.7f, 0, 0 }, 3);
  inf.Normalize(2, "test");
  RestSkin skin(inf, rest, "test");
  ASSERT_TRUE(skin.SetPose(pose));
  const float s = static_cast<float>(std::sqrt(1.0 / 3.0));
  const float points[] = { 0.1f, 0.2f, 0.3f, -0.2f, 0.5f, 0.1f, 0.3f, -0.1f, 0.2f };
  const float normals[] = { s, s, s, s, -s, s, -s, s, s };
  float p[9], n[9];
  skin.Apply<float>(points, normals, p, n, 0, 3);
  // Exact: the points at rest are the bind points moved by the rest blend; skin those.
  double bindPoints[9], bindNormals[9], q[9], m[9];
  for (int i = 0; i < 9; ++i)
  {
    bindPoints[i] = points[i];
    bindNormals[i] = normals[i];
  }
  bindPoints[0] -= 0.0;        // point 0 on joint 0: rest is the identity
  bindPoints[3] -= 1e-7;       // point 1 on joint 1
  bindPoints[6] -= 0.7 * 1e-7; // point 2: 0.7 on joint 1
  SkinPoints<double>(inf, pose, bindPoints, bindNormals, q, m, 0, 3);
  for (int i = 0; i < 9; ++i)
  {
    EXPECT_NEAR(p[i], q[i], 1e-6) << i;
    EXPECT_NEAR(n[i], m[i], 1e-6) << i;
  }
}

// Lid bones where a rig has them (Character Creator's CC_Base_L_UpperLid, LeftLowerEyelid)
// follow their eye's pitch about their own pivots: looking 20 degrees down turns the upper
// lid 12 degrees down (LidFollow 0.6) and the lower lid 6; a sideways look leaves them;
// they are not taken for eyes.
TEST(AvatarBones, LidBonesFollowTheEyesPitch)
{
  Skeleton s;
  const int head = s.AddJoint(MakeJoint("Head", -1, { 0, 1.6, 0 }));
  const int eye = s.AddJoint(MakeJoint("LeftEye", head, { 0.03, 0.08, 0.08 }));
  const int upper = s.AddJoint(MakeJoint("CC_Base_L_UpperLid", head, { 0.03, 0.09, 0.09 }));
  const int lower = s.AddJoint(MakeJoint("LeftLowerEyelid", head, { 0.03, 0.07, 0.09 }));
  s.Validate();
  const AvatarBoneRoles roles = FindAvatarBones(s);
  ASSERT_EQ(roles.LeftEye, eye);
  ASSERT_EQ(roles.LeftUpperLid, upper);
  ASSERT_EQ(roles.LeftLowerLid, lower);
  EXPECT_NE(roles.Describe(s).find("left upper lid 'CC_Base_L_UpperLid'"), std::string::npos)
    << roles.Describe(s);
  SkeletonPose rest(s);
  const auto restWorld = rest.World();
  auto pitchOf = [&](int joint, double eyeYaw, double eyePitch)
  {
    SkeletonPose pose(s);
    AvatarBonePose a;
    a.EyeYaw = eyeYaw;
    a.EyePitch = eyePitch;
    PoseAvatarBones(pose, roles, a);
    const glm::dmat3 m =
      glm::dmat3(pose.World()[joint]) * glm::inverse(glm::dmat3(restWorld[joint]));
    const glm::dvec3 f = m * glm::dvec3(0, 0, 1);
    ExpectNear(glm::dvec3(pose.World()[joint][3]), glm::dvec3(restWorld[joint][3]), 1e-12);
    return std::asin(f.y) * 180 / Pi;
  };
  EXPECT_NEAR(pitchOf(upper, 0, -20), -12.0, 1e-9);
  EXPECT_NEAR(pitchOf(lower, 0, -20), -6.0, 1e-9);
  EXPECT_NEAR(pitchOf(upper, 25, 0), 0.0, 1e-9);
}

// The one rule for "this avatar opens its mouth by a target": any case, underscores ignored.
TEST(AvatarBones, JawOpenTargetsAreFoundInEverySpelling)
{
  EXPECT_TRUE(NamesJawOpenTarget({ "mouthClose", "jawOpen" }));
  EXPECT_TRUE(NamesJawOpenTarget({ "JawOpen" }));
  EXPECT_TRUE(NamesJawOpenTarget({ "jaw_open" }));
  EXPECT_FALSE(NamesJawOpenTarget({ "jawForward", "mouthOpen", "jawOpenWide" }));
  EXPECT_FALSE(NamesJawOpenTarget({}));
}

// RestSkin's runs (points bound rigidly to one joint) and blend groups (points blended over
// the same joints, wherever they are): ApplyChanged re-skins exactly the points of a joint
// that changed and the points whose input changed, leaves the others' output as it was, and
// gives Apply's values; the groups gather points that are not neighbours.
TEST(Skinning, RunsAndBlendGroupsReskinOnlyWhatChanged)
{
  // 8 points: rigid on joint 0, 0, 1; blended {0, 1}; rigid on 2; blended {0, 1} again
  // (the same group as point 3); blended {1, 2}; blended {0, 1, 2}.
  SkinInfluences inf;
  inf.AddSet({ 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 1, 2, 0, 0,
               0, 1, 2, 0 },
    { 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.4f, 0.6f, 0, 0, 1, 0, 0, 0, 0.2f, 0.8f, 0, 0, 0.5f,
      0.5f, 0, 0, 0.2f, 0.3f, 0.5f, 0 },
    8);
  inf.Normalize(3, "test");
  const std::vector<glm::dmat4> rest(3, glm::dmat4(1.0));
  RestSkin skin(inf, rest, "test");
  size_t rigid = 0, runs = 0;
  for (const auto& run : skin.GetRuns())
  {
    rigid += run.Joint >= 0 ? run.End - run.Begin : 0;
    runs += run.Joint >= 0;
  }
  EXPECT_EQ(rigid, 4u); // points 0, 1, 2, 4: in three runs
  EXPECT_EQ(runs, 3u);

  std::vector<float> points(24), normals(24);
  for (size_t i = 0; i < 8; ++i)
  {
    points[3 * i] = 0.1f * static_cast<float>(i);
    points[3 * i + 1] = 1.0f;
    points[3 * i + 2] = -0.2f;
    normals[3 * i + 2] = 1.0f;
  }
  std::vector<glm::dmat4> pose = { glm::rotate(glm::dmat4(1.0), 0.3, glm::dvec3(0, 1, 0)),
    glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0.1, 0)),
    glm::rotate(glm::dmat4(1.0), -0.5, glm::dvec3(1, 0, 0)) };
  ASSERT_TRUE(skin.SetPose(pose));
  std::vector<float> out(24), outNormals(24), full(24), fullNormals(24);
  EXPECT_EQ(skin.ApplyChanged<float>(
              points.data(), normals.data(), out.data(), outNormals.data(), { 0, 8 }, 0, 8),
    8u);
  skin.Apply<float>(points.data(), normals.data(), full.data(), fullNormals.data(), 0, 8);
  EXPECT_EQ(out, full);
  EXPECT_EQ(outNormals, fullNormals);

  // Only joint 2 turns further: points 4, 6 and 7 (its run and its two groups).
  pose[2] = glm::rotate(glm::dmat4(1.0), -0.6, glm::dvec3(1, 0, 0));
  ASSERT_TRUE(skin.SetPose(pose));
  std::vector<float> marked(24, 1e6f), markedNormals(24, 1e6f);
  EXPECT_EQ(skin.ApplyChanged<float>(
              points.data(), normals.data(), marked.data(), markedNormals.data(), {}, 0, 8),
    3u);
  skin.Apply<float>(points.data(), normals.data(), full.data(), fullNormals.data(), 0, 8);
  for (size_t i = 0; i < 8; ++i)
  {
    const bool reskinned = i == 4 || i == 6 || i == 7;
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(marked[3 * i + k], reskinned ? full[3 * i + k] : 1e6f) << "point " << i;
      EXPECT_EQ(markedNormals[3 * i + k], reskinned ? fullNormals[3 * i + k] : 1e6f) << i;
    }
  }

  // Nothing turns, the input of points 1 and 5 changed (a run's point, a group's point).
  ASSERT_TRUE(skin.SetPose(pose));
  points[3 * 1 + 1] = 1.5f;
  points[3 * 5 + 1] = 1.5f;
  std::fill(marked.begin(), marked.end(), 1e6f);
  EXPECT_EQ(skin.ApplyChanged<float>(points.data(), normals.data(), marked.data(),
              markedNormals.data(), { 1, 2, 5, 6 }, 0, 8),
    2u);
  skin.Apply<float>(points.data(), normals.data(), full.data(), fullNormals.data(), 0, 8);
  for (size_t i = 0; i < 8; ++i)
  {
    const bool reskinned = i == 1 || i == 5;
    EXPECT_EQ(marked[3 * i + 1], reskinned ? full[3 * i + 1] : 1e6f) << "point " << i;
  }
  // Split ranges (as threads cut them) give the same.
  std::vector<float> halves(24, 1e6f), halvesNormals(24);
  EXPECT_EQ(skin.ApplyChanged<float>(points.data(), normals.data(), halves.data(),
              halvesNormals.data(), { 1, 2, 5, 6 }, 0, 3) +
      skin.ApplyChanged<float>(
        points.data(), normals.data(), halves.data(), halvesNormals.data(), { 1, 2, 5, 6 }, 3, 8),
    2u);
  EXPECT_EQ(halves, marked);
}
