// SPDX-License-Identifier: BSD-3-Clause
// glTF skins read by the loader (gltf/GltfSkin.cpp): the hand-computed skinned quad (nested
// joints, two weight sets of different types, a bind pose unlike the node pose, the skinned
// node's own transform ignored, morph then skin), re-skinning it, damaged skins refused, and
// the shared MakeHuman avatar at rest (its bind pose is its rest pose) with its bones found.
#include "gltf/GltfPerformanceExport.h"
#include "gltf/GltfSkin.h"
#include "gltf/GltfVrm.h"

#include "GltfSkinnedTestFiles.h"
#include "MorphNodeTestErrors.h"
#include "base/Error.h"
#include "skin/AvatarBones.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

using namespace morphnode;
using morphnode_test::ErrorOf;

namespace
{
GltfScene Load(const std::string& glb, bool apply = true)
{
  GltfLoadOptions options;
  options.ApplyTransforms = apply;
  return LoadGltfSceneFromMemory(glb.data(), glb.size(), std::string(), options, "skinned.glb");
}

std::string Error(const gltftest::Builder& b)
{
  return ErrorOf([&] { Load(b.Glb()); });
}
} // namespace

TEST(GltfSkin, SkinnedQuadAtRestMatchesHandComputedPoints)
{
  const GltfScene scene = Load(gltftest::SkinnedQuad().Glb());
  ASSERT_EQ(scene.Skins.size(), 1u);
  EXPECT_EQ(scene.Skins[0].Joints, (std::vector<int>{ 1, 2 }));
  ASSERT_EQ(scene.Parts.size(), 1u);
  const GltfPart& part = scene.Parts[0];
  EXPECT_EQ(part.Skin, 0);
  EXPECT_EQ(part.Influences.PerPoint, 8u); // both sets
  EXPECT_NEAR(part.Influences.Weights[3 * 8 + 0], 0.2f, 1e-6);
  EXPECT_NEAR(part.Influences.Weights[3 * 8 + 4], 0.8f, 1e-6);
  const std::vector<double> expected = gltftest::SkinnedQuadRest();
  for (size_t k = 0; k < expected.size(); ++k)
  {
    // 100 off in x if the mesh node's transform were applied; (1, 1, 0) for p3 if set 1 were
    // ignored.
    EXPECT_NEAR(part.Positions[k], expected[k], 1e-6) << k;
  }
  // Morph first, then skin: the rest delta of `Up` at p3 is Rz(90)(0, 1, 0) = (-1, 0, 0).
  EXPECT_NEAR(part.Targets[0].PositionDeltas[9], -1.0, 1e-6);
  EXPECT_NEAR(part.Targets[0].PositionDeltas[10], 0.0, 1e-6);
  EXPECT_NEAR(part.Targets[1].PositionDeltas[0], 0.0, 1e-6); // Rz(90)(1, 0, 0) = (0, 1, 0)
  EXPECT_NEAR(part.Targets[1].PositionDeltas[1], 1.0, 1e-6);
  // Normals +Z stay +Z under rotations about Z.
  EXPECT_NEAR(part.Normals[2], 1.0, 1e-6);

  // Without ApplyTransforms the part stays in bind space, as in the file.
  const GltfScene bind = Load(gltftest::SkinnedQuad().Glb(), false);
  EXPECT_FLOAT_EQ(bind.Parts[0].Positions[9], 3.0f);
  EXPECT_EQ(bind.Parts[0].Skin, 0);
}

TEST(GltfSkin, ReskinnedQuadFollowsItsJoints)
{
  const GltfScene rest = Load(gltftest::SkinnedQuad().Glb());
  Skeleton skeleton = GltfSkeleton(rest);
  const SkinJoints joints = GltfSkinJoints(rest, 0);
  SkeletonPose pose(skeleton);
  const std::vector<glm::dmat4> restMatrices = joints.Matrices(pose.World());
  // Turn J2 by 90 degrees about +Z about its pivot: p2 (J2 only) turns about J2's origin.
  pose.TurnJoint(2, glm::angleAxis(glm::half_pi<double>(), glm::dvec3(0, 0, 1)));
  const glm::dvec3 pivot(pose.World()[2][3]);
  RestSkin skin(rest.Parts[0].Influences, restMatrices, "quad");
  ASSERT_TRUE(skin.SetPose(joints.Matrices(pose.World())));
  std::vector<float> out(12);
  skin.Apply<float>(rest.Parts[0].Positions.data(), nullptr, out.data(), nullptr, 0, 4);
  // p2 at rest (1, 1, 0); J2 stands at (0, 1, 0) (Root) + (1, 0, 0) + Rz90 (0, 1, 0) = (0, 1, 0).
  EXPECT_NEAR(pivot.x, 0.0, 1e-9);
  EXPECT_NEAR(pivot.y, 1.0, 1e-9);
  // (1, 1, 0) - (0, 1, 0) = (1, 0, 0) turned by 90 degrees -> (0, 1, 0), plus the pivot.
  EXPECT_NEAR(out[6], 0.0, 1e-6);
  EXPECT_NEAR(out[7], 2.0, 1e-6);
  // p0 and p1 follow J1 only, which did not move.
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_EQ(out[static_cast<size_t>(k)], rest.Parts[0].Positions[static_cast<size_t>(k)]);
  }
}

TEST(GltfSkin, DamagedSkinsAreRefusedWithAClearError)
{
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    b.Doc["skins"][0]["joints"] = { 1 }; // point 2 and 3 are bound to joint 1
    EXPECT_NE(Error(b).find("bound to joint 1, but the skin has only 1 joints"), std::string::npos)
      << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    b.Doc["skins"][0]["joints"] = { 1, 9 };
    EXPECT_NE(Error(b).find("/skins/0/joints/1: node 9 does not exist"), std::string::npos)
      << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    const std::vector<float> zero(32, 0.0f);
    b.Doc["accessors"][b.Doc["skins"][0]["inverseBindMatrices"].get<int>()]["bufferView"] =
      b.View(zero);
    EXPECT_NE(Error(b).find("is not affine"), std::string::npos) << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    std::vector<float> singular(32, 0.0f);
    singular[15] = singular[31] = 1.0f;
    b.Doc["accessors"][b.Doc["skins"][0]["inverseBindMatrices"].get<int>()]["bufferView"] =
      b.View(singular);
    EXPECT_NE(Error(b).find("singular"), std::string::npos) << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    const int weights = b.Doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"].get<int>();
    b.Doc["accessors"][weights]["bufferView"] = b.View(std::vector<float>(16, std::nanf("")));
    EXPECT_NE(Error(b).find("NaN"), std::string::npos) << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    b.Doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_1");
    EXPECT_NE(Error(b).find("JOINTS_1 needs WEIGHTS_1"), std::string::npos) << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    b.Doc["nodes"][3]["skin"] = 4;
    EXPECT_NE(Error(b).find("skin 4 does not exist"), std::string::npos) << Error(b);
  }
  {
    gltftest::Builder b = gltftest::SkinnedQuad();
    const int joints = b.Doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"].get<int>();
    b.Doc["accessors"][joints]["componentType"] = gltftest::Float;
    b.Doc["accessors"][joints]["bufferView"] = b.View(std::vector<float>(16, 0.0f));
    EXPECT_NE(Error(b).find("must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT"), std::string::npos)
      << Error(b);
  }
}

TEST(GltfSkin, MakeHumanAvatarAtRestAndItsBones)
{
  const std::string file = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(file);
  const GltfScene scene = LoadGltfScene(file);
  const GltfScene bind = LoadGltfScene(file, GltfLoadOptions{ false });
  ASSERT_EQ(scene.Skins.size(), 1u);
  EXPECT_EQ(scene.Skins[0].Joints.size(), 76u);
  double largest = 0.0;
  for (size_t p = 0; p < scene.Parts.size(); ++p)
  {
    EXPECT_EQ(scene.Parts[p].Skin, 0) << scene.Parts[p].Name;
    // Rest pose = bind pose: skinning at rest keeps the stored points.
    for (size_t k = 0; k < scene.Parts[p].Positions.size(); ++k)
    {
      largest = std::max(
        largest, double(std::abs(scene.Parts[p].Positions[k] - bind.Parts[p].Positions[k])));
    }
  }
  EXPECT_LT(largest, 1e-6 * 1.666);
  const Skeleton skeleton = GltfSkeleton(scene);
  const AvatarBoneRoles roles = FindAvatarBones(skeleton);
  EXPECT_EQ(skeleton.GetJoint(static_cast<size_t>(roles.Head)).Name, "Head");
  EXPECT_EQ(skeleton.GetJoint(static_cast<size_t>(roles.Neck)).Name, "Neck");
  EXPECT_EQ(skeleton.GetJoint(static_cast<size_t>(roles.LeftEye)).Name, "LeftEye");
  EXPECT_EQ(skeleton.GetJoint(static_cast<size_t>(roles.RightEye)).Name, "RightEye");
  EXPECT_EQ(skeleton.GetJoint(static_cast<size_t>(roles.Jaw)).Name, "Jaw");
}

TEST(GltfSkin, QuantizedAndMeshoptVariantsAreReadOrRefusedClearly)
{
  // gltfpack's variants: positions in the quantization grid, the dequantization folded into
  // the inverse bind matrices (and a transform on the skinned nodes, which must be ignored).
  // Read, the avatar at rest has the plain avatar's bounds (within 1 mm); refused (until the
  // loader decodes the extensions), the message names the extension.
  const std::string dir = MORPHNODE_AVATAR_DIR;
  MORPHNODE_SKIP_WITHOUT_AVATAR(dir + "/makehuman_avatar.glb");
  auto bounds = [](const GltfScene& scene)
  {
    std::array<double, 6> b{ 1e30, -1e30, 1e30, -1e30, 1e30, -1e30 };
    for (const auto& part : scene.Parts)
    {
      for (size_t i = 0; i < part.Positions.size(); ++i)
      {
        const size_t k = i % 3;
        b[2 * k] = std::min(b[2 * k], double(part.Positions[i]));
        b[2 * k + 1] = std::max(b[2 * k + 1], double(part.Positions[i]));
      }
    }
    return b;
  };
  const auto plain = bounds(LoadGltfScene(dir + "/makehuman_avatar.glb"));
  for (const char* variant : { "makehuman_avatar_quantized.glb", "makehuman_avatar_meshopt.glb" })
  {
    const std::string file = dir + "/" + variant;
    std::string error;
    GltfScene scene;
    try
    {
      scene = LoadGltfScene(file);
    }
    catch (const InputError& e)
    {
      error = e.what();
    }
    if (!error.empty())
    {
      EXPECT_NE(error.find("extension"), std::string::npos) << variant << ": " << error;
      std::cout << variant << ": refused: " << error << "\n";
      continue;
    }
    const auto b = bounds(scene);
    for (int k = 0; k < 6; ++k)
    {
      EXPECT_NEAR(b[k], plain[k], 1e-3) << variant << " bound " << k;
    }
  }
}

// GltfUnskinPart undoes the loader's skinning at rest on the skinned quad, whose bind pose
// is unlike its node pose (J2 turned by 90 degrees): the points, normals and deltas come
// back to the file's bind space. Without the inverse the points stay rotated (p3 would be
// (1.8, 3, 0) at rest instead of the file's (1, 3, 0)). And the skeleton goes back to nodes
// with the same names, parents and local transforms (TRS where the matrix is one).
TEST(GltfSkin, UnskinnedQuadIsTheFilesBindSpaceAndNodesComeBackFromTheSkeleton)
{
  const GltfScene bind = Load(gltftest::SkinnedQuad().Glb(), false);
  GltfScene rest = Load(gltftest::SkinnedQuad().Glb());
  std::vector<GltfMatrix> worlds;
  for (const auto& node : rest.Nodes)
  {
    worlds.push_back(node.World);
  }
  GltfPart part = rest.Parts[0];
  GltfUnskinPart(part, rest, worlds, "quad");
  EXPECT_FALSE(part.TransformApplied);
  for (size_t k = 0; k < part.Positions.size(); ++k)
  {
    EXPECT_NEAR(part.Positions[k], bind.Parts[0].Positions[k], 1e-5) << k;
    EXPECT_NEAR(part.Normals[k], bind.Parts[0].Normals[k], 1e-5) << k;
    for (size_t t = 0; t < part.Targets.size(); ++t)
    {
      EXPECT_NEAR(
        part.Targets[t].PositionDeltas[k], bind.Parts[0].Targets[t].PositionDeltas[k], 1e-5)
        << k;
    }
  }
  // Skinned again, it is the rest pose.
  GltfSkinPart(part, rest, worlds, "quad");
  for (size_t k = 0; k < part.Positions.size(); ++k)
  {
    EXPECT_NEAR(part.Positions[k], rest.Parts[0].Positions[k], 1e-5) << k;
  }
  EXPECT_NE(ErrorOf([&] { GltfUnskinPart(part, rest, {}, "quad"); }), "");

  const std::vector<GltfNode> nodes = GltfNodesFromSkeleton(GltfSkeleton(rest));
  ASSERT_EQ(nodes.size(), rest.Nodes.size());
  for (size_t n = 0; n < nodes.size(); ++n)
  {
    EXPECT_EQ(nodes[n].Name, rest.Nodes[n].Name);
    EXPECT_EQ(nodes[n].Parent, rest.Nodes[n].Parent);
    EXPECT_EQ(nodes[n].Children, rest.Nodes[n].Children);
    for (size_t c = 0; c < 16; ++c)
    {
      EXPECT_NEAR(nodes[n].Local[c], rest.Nodes[n].Local[c], 1e-12) << n;
      EXPECT_NEAR(nodes[n].World[c], rest.Nodes[n].World[c], 1e-12) << n;
    }
    EXPECT_FALSE(nodes[n].HasMatrix) << n;
    for (size_t c = 0; c < 4; ++c)
    {
      EXPECT_NEAR(std::abs(nodes[n].Rotation[c]), std::abs(rest.Nodes[n].Rotation[c]), 1e-12) << n;
    }
  }
}

// The performance export turns a jaw joint by the table's jawOpen when no part has a
// jawOpen target (the skinned quad with J2 named "Jaw"): a rotation track on Jaw about its
// own origin, chin down by jawOpen * 25 degrees; with a jawOpen target on the mesh the
// column is a weight and the jaw joint stays.
TEST(GltfSkin, PerformanceOpensAJawJointOnlyWithoutAJawOpenTarget)
{
  gltftest::Builder b = gltftest::SkinnedQuad();
  b.Doc["nodes"][2]["name"] = "Jaw";
  GltfScene scene = Load(b.Glb(), false);
  GltfPerformanceTable table;
  table.Times = { 0.0, 1.0 };
  table.Names = { "jawOpen" };
  table.Columns = { { 0.0, 0.8 } };
  GltfPerformanceReport report;
  const GltfPerformance p = MakeGltfPerformance(scene, table, GltfPerformanceSettings(), &report);
  EXPECT_TRUE(report.Bones);
  ASSERT_EQ(p.Rotations.size(), 1u);
  EXPECT_EQ(p.Rotations[0].Node, "Jaw");
  EXPECT_EQ(p.Rotations[0].Pivot, scene.Nodes[2].Translation);
  EXPECT_TRUE(p.TargetNames.empty());
  const double* q = p.Rotations[0].Rotations.data() + 4;
  // In the parent's frame (J1 is turned 90 degrees about z): the angle is 20 degrees.
  EXPECT_NEAR(
    2.0 * std::acos(std::min(1.0, std::abs(q[3]))) * 180.0 / glm::pi<double>(), 20.0, 1e-6);
  EXPECT_NEAR(p.Rotations[0].Rotations[3], 1.0, 1e-12); // closed at t = 0

  scene.Parts[0].Targets[0].Name = "jawOpen";
  const GltfPerformance q2 = MakeGltfPerformance(scene, table, GltfPerformanceSettings(), &report);
  EXPECT_TRUE(q2.Rotations.empty());
  EXPECT_EQ(q2.TargetNames, std::vector<std::string>{ "jawOpen" });
  EXPECT_FALSE(report.Bones);
}

namespace
{
/// The skinned quad as a VRM: its mesh's targets "Up" and "Right", J1 and J2 as the
/// humanoid head and jaw.
gltftest::Builder VrmQuad(bool one)
{
  gltftest::Builder b = gltftest::SkinnedQuad();
  if (one)
  {
    b.Doc["extensions"]["VRMC_vrm"] = { { "specVersion", "1.0" },
      { "humanoid",
        { { "humanBones", { { "head", { { "node", 1 } } }, { "jaw", { { "node", 2 } } } } } } },
      { "expressions",
        { { "preset",
            { { "oh",
                { { "morphTargetBinds",
                  { { { "node", 3 }, { "index", 1 }, { "weight", 0.5 } } } } } },
              { "blink",
                { { "morphTargetBinds",
                  { { { "node", 3 }, { "index", 0 }, { "weight", 1.0 } } } } } } } },
          { "custom",
            { { "smirk",
              { { "morphTargetBinds", { { { "node", 3 }, { "index", 0 } } } } } } } } } },
      { "lookAt",
        { { "type", "bone" }, { "offsetFromHeadBone", { 0, 0.06, 0 } },
          { "rangeMapHorizontalOuter", { { "inputMaxValue", 90 }, { "outputScale", 12 } } } } } };
    b.Doc["extensionsUsed"] = { "VRMC_vrm" };
  }
  else
  {
    b.Doc["extensions"]["VRM"] = {
      { "humanoid", { { "humanBones", { { { "bone", "head" }, { "node", 1 } } } } } },
      { "blendShapeMaster",
        { { "blendShapeGroups",
          { { { "name", "O" }, { "presetName", "o" },
              { "binds", { { { "mesh", 0 }, { "index", 1 }, { "weight", 50 } } } } },
            { { "name", "Joy" }, { "presetName", "joy" },
              { "binds", { { { "mesh", 0 }, { "index", 0 }, { "weight", 100 } } } } } } } } },
      { "firstPerson",
        { { "lookAtTypeName", "BlendShape" },
          { "lookAtHorizontalOuter", { { "xRange", 30 }, { "yRange", 1 } } } } }
    };
    b.Doc["extensionsUsed"] = { "VRM" };
  }
  return b;
}

std::string WriteTemp(const std::string& name, const std::string& bytes)
{
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}
} // namespace

// VRM 1.0 and 0.x read from the extensions: expressions bound to the targets by name (0.x's
// presets as 1.0's, its 0..100 weights as 0..1), humanoid bones (node and name), look-at
// type and range maps; a bind outside the mesh is refused by name; a plain glTF is no VRM.
TEST(GltfVrm, ExpressionsBonesAndLookAtOfBothVersions)
{
  const GltfVrm one = ReadGltfVrm(WriteTemp("morphnode_vrm1.glb", VrmQuad(true).Glb()));
  EXPECT_EQ(one.Version, 2);
  ASSERT_EQ(one.Expressions.size(), 3u);
  const auto find = [](const GltfVrm& v, const std::string& name)
  {
    const auto it = std::find_if(v.Expressions.begin(), v.Expressions.end(),
      [&name](const GltfVrmExpression& e) { return e.Name == name; });
    return it == v.Expressions.end() ? nullptr : &*it;
  };
  ASSERT_NE(find(one, "oh"), nullptr);
  EXPECT_EQ(
    find(one, "oh")->Binds, (std::vector<std::pair<std::string, double>>{ { "Right", 0.5 } }));
  ASSERT_NE(find(one, "smirk"), nullptr);
  EXPECT_FALSE(find(one, "smirk")->Preset);
  EXPECT_EQ(one.HumanBones.at("head"), 1);
  EXPECT_EQ(one.HumanBoneNodeNames.at("jaw"), "J2");
  EXPECT_EQ(one.LookAtType, "bone");
  EXPECT_NEAR(one.HorizontalOuter.Map(45), 6.0, 1e-12);
  EXPECT_NEAR(one.HorizontalOuter.Map(-200), 12.0, 1e-12);
  EXPECT_NEAR(one.HorizontalInner.Map(90), 10.0, 1e-12); // the default map of a bone look-at
  EXPECT_NEAR(one.LookAtOffset[1], 0.06, 1e-12);

  const GltfVrm zero = ReadGltfVrm(WriteTemp("morphnode_vrm0.glb", VrmQuad(false).Glb()));
  EXPECT_EQ(zero.Version, 1);
  ASSERT_NE(find(zero, "oh"), nullptr);
  EXPECT_EQ(
    find(zero, "oh")->Binds, (std::vector<std::pair<std::string, double>>{ { "Right", 0.5 } }));
  ASSERT_NE(find(zero, "happy"), nullptr);
  EXPECT_EQ(zero.HumanBoneNodeNames.at("head"), "J1");
  EXPECT_EQ(zero.LookAtType, "expression");
  EXPECT_NEAR(zero.HorizontalOuter.Map(15), 0.5, 1e-12);

  EXPECT_FALSE(
    ReadGltfVrm(WriteTemp("morphnode_novrm.glb", gltftest::SkinnedQuad().Glb())).IsVrm());
  gltftest::Builder bad = VrmQuad(true);
  bad.Doc["extensions"]["VRMC_vrm"]["expressions"]["preset"]["oh"]["morphTargetBinds"][0]["index"] =
    7;
  EXPECT_NE(ErrorOf([&] { ReadGltfVrm(WriteTemp("morphnode_badvrm.glb", bad.Glb())); })
              .find("target 7 of mesh 0"),
    std::string::npos);
  gltftest::Builder badBone = VrmQuad(false);
  badBone.Doc["extensions"]["VRM"]["humanoid"]["humanBones"][0]["node"] = 99;
  EXPECT_NE(ErrorOf([&] { ReadGltfVrm(WriteTemp("morphnode_badvrm0.glb", badBone.Glb())); })
              .find("node 99"),
    std::string::npos);
}
