// SPDX-License-Identifier: BSD-3-Clause
// Cross-check of MorphNode's skinning (MorphNode::Skin through the glTF loader) against an
// implementation MorphNode did not write: VTK 9.1's vtkGLTFReader, which skins on the CPU
// (ApplyDeformationsToGeometry on) with JOINTS_0/WEIGHTS_0 only.
//
// - The shared MakeHuman avatar at rest: every vertex of the 7 parts within 1e-6 of the
//   avatar's height.
// - An animated frame written into a copy of the avatar: mesh weights (jawOpen, viseme_O,
//   eyeBlinkLeft) and joint rotations (Neck, Head, LeftEye, LeftArm, RightForeArm). MorphNode
//   agrees twice: loading the copy (skinned at its stored pose, then morphed in rest space),
//   and posing the ORIGINAL avatar's joints and re-skinning its rest geometry (RestSkin),
//   the path the VTK filters take.
// - The skinned quad (Core/gltf/GltfSkinnedTestFiles.h): without its second weight set and
//   its skinned node's transform, VTK and MorphNode agree; with them VTK 9.1 is wrong: it
//   ignores JOINTS_1/WEIGHTS_1, so a point bound by both sets follows set 0 alone ((1, 3, 0)
//   instead of (1.8, 3, 0)) and a point bound by set 1 alone is not skinned but moved by the
//   skinned node's transform ((100, 1, 0) instead of (1, 1, 0); glTF 2.0 says to ignore that
//   transform). MorphNode matches the hand-computed points (TestCoreGltfSkin too).
#include "Core/gltf/GltfSkinnedTestFiles.h"
#include "MorphNodeGltfReaderParts.h"
#include "gltf/GltfSkin.h"
#include "skin/Skinning.h"

#include "vtkPoints.h"
#include "vtkPolyData.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace morphnode;
using json = nlohmann::json;

namespace
{
const std::string Avatar = morphnode_test::AvatarFile();
constexpr double AvatarHeight = 1.666;

std::string ReadBytes(const std::string& file)
{
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A GLB's JSON and BIN chunks.
void SplitGlb(const std::string& glb, json& doc, std::vector<unsigned char>& bin)
{
  uint32_t jsonLength;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  doc = json::parse(glb.substr(20, jsonLength));
  const size_t binStart = 20 + jsonLength;
  uint32_t binLength;
  std::memcpy(&binLength, glb.data() + binStart, 4);
  bin.assign(glb.begin() + static_cast<long>(binStart + 8),
    glb.begin() + static_cast<long>(binStart + 8 + binLength));
}

std::string Write(const std::string& name, const std::string& bytes)
{
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/" + name;
  std::filesystem::create_directories(MORPHNODE_TEST_OUTPUT_DIR);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// Each part's points morphed by its default weights (the file's mesh weights), in the
/// loader's space: base + sum w delta.
std::vector<std::vector<double>> Morphed(const GltfScene& scene)
{
  std::vector<std::vector<double>> out;
  for (const GltfPart& part : scene.Parts)
  {
    std::vector<double> p(part.Positions.begin(), part.Positions.end());
    for (size_t t = 0; t < part.Targets.size(); ++t)
    {
      const double w = part.DefaultWeights[t];
      if (w != 0.0)
      {
        for (size_t k = 0; k < p.size(); ++k)
        {
          p[k] += w * part.Targets[t].PositionDeltas[k];
        }
      }
    }
    out.push_back(std::move(p));
  }
  return out;
}

/// The largest distance between MorphNode's parts and vtkGLTFReader's.
double Worst(const std::vector<std::vector<double>>& ours,
  const std::vector<vtkSmartPointer<vtkPolyData>>& theirs)
{
  EXPECT_EQ(ours.size(), theirs.size());
  double worst = 0.0;
  for (size_t p = 0; p < std::min(ours.size(), theirs.size()); ++p)
  {
    EXPECT_EQ(static_cast<size_t>(theirs[p]->GetNumberOfPoints()) * 3, ours[p].size());
    for (vtkIdType i = 0;
         i < theirs[p]->GetNumberOfPoints() && static_cast<size_t>(3 * i + 2) < ours[p].size(); ++i)
    {
      double q[3];
      theirs[p]->GetPoint(i, q);
      for (int k = 0; k < 3; ++k)
      {
        worst = std::max(worst, std::abs(q[k] - ours[p][static_cast<size_t>(3 * i + k)]));
      }
    }
  }
  return worst;
}

struct Turn
{
  const char* Joint;
  double Degrees;
  glm::dvec3 Axis; ///< in the joint's own frame
};
const Turn Turns[] = { { "Neck", 12, { 0, 0, 1 } }, { "Head", 20, { 1, 0, 1 } },
  { "LeftEye", 15, { 0, 0, 1 } }, { "LeftArm", 35, { 1, 0, 0 } },
  { "RightForeArm", 50, { 0, 0, 1 } } };

glm::dquat Local(const Turn& t)
{
  return glm::angleAxis(t.Degrees * glm::pi<double>() / 180.0, glm::normalize(t.Axis));
}
} // namespace

TEST(GltfSkinCrossCheck, AvatarAtRestAgreesWithVtkGltfReader)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  const GltfScene scene = LoadGltfScene(Avatar);
  const double worst = Worst(Morphed(scene), morphnode_test::VtkGltfReaderParts(Avatar, true));
  std::cout << "avatar at rest: largest difference to vtkGLTFReader " << worst * 1e3 << " mm\n";
  EXPECT_LT(worst, 1e-6 * AvatarHeight);
}

TEST(GltfSkinCrossCheck, AnimatedAvatarAgreesWithVtkGltfReader)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  json doc;
  std::vector<unsigned char> bin;
  SplitGlb(ReadBytes(Avatar), doc, bin);
  // The frame: weights on every mesh, joint rotations on the nodes.
  const std::vector<std::string> names =
    doc["meshes"][0]["extras"]["targetNames"].get<std::vector<std::string>>();
  auto index = [&](const std::string& n)
  { return static_cast<size_t>(std::find(names.begin(), names.end(), n) - names.begin()); };
  for (auto& mesh : doc["meshes"])
  {
    std::vector<double> w(names.size(), 0.0);
    w[index("jawOpen")] = 0.8;
    w[index("viseme_O")] = 1.0;
    w[index("eyeBlinkLeft")] = 0.6;
    mesh["weights"] = w;
  }
  for (const Turn& t : Turns)
  {
    for (auto& node : doc["nodes"])
    {
      if (node.value("name", "") == t.Joint)
      {
        const auto r = node["rotation"].get<std::vector<double>>();
        const glm::dquat q = glm::dquat(r[3], r[0], r[1], r[2]) * Local(t);
        node["rotation"] = { q.x, q.y, q.z, q.w };
      }
    }
  }
  const std::string file =
    Write("skin_crosscheck_avatar_frame.glb", gltftest::Builder::MakeGlb(doc.dump(), bin));
  const auto theirs = morphnode_test::VtkGltfReaderParts(file, true);

  // 1. The copy, read by MorphNode: skinned at its stored pose, morphed in rest space.
  const GltfScene posed = LoadGltfScene(file);
  const double worstFile = Worst(Morphed(posed), theirs);

  // 2. The original avatar posed by MorphNode and re-skinned (the VTK filters' path).
  const GltfScene rest = LoadGltfScene(Avatar);
  Skeleton skeleton = GltfSkeleton(rest);
  SkeletonPose pose(skeleton);
  for (const Turn& t : Turns)
  {
    const int j = skeleton.FindJoint(t.Joint);
    ASSERT_GE(j, 0) << t.Joint;
    Joint joint = skeleton.GetJoint(static_cast<size_t>(j));
    joint.Rotation = joint.Rotation * Local(t);
    pose.SetLocal(j, joint.Local());
  }
  const SkinJoints joints = GltfSkinJoints(rest, 0);
  const auto restMatrices = joints.Matrices(SkeletonPose(skeleton).World());
  const auto poseMatrices = joints.Matrices(pose.World());
  std::vector<std::vector<double>> reskinned;
  GltfScene weighted = rest;
  for (size_t p = 0; p < weighted.Parts.size(); ++p)
  {
    weighted.Parts[p].DefaultWeights = posed.Parts[p].DefaultWeights;
  }
  size_t moved = 0;
  for (auto& points : Morphed(weighted))
  {
    const size_t p = reskinned.size();
    RestSkin skin(rest.Parts[p].Influences, restMatrices, rest.Parts[p].Name);
    skin.SetPose(poseMatrices);
    std::vector<double> out(points.size());
    skin.Apply<double>(points.data(), nullptr, out.data(), nullptr, 0, points.size() / 3);
    for (size_t i = 0; i < points.size() / 3; ++i)
    {
      moved += skin.Moves(i);
    }
    reskinned.push_back(std::move(out));
  }
  const double worstPose = Worst(reskinned, theirs);
  std::cout << "animated avatar (" << moved
            << " vertices moved by joints): largest difference to vtkGLTFReader " << worstFile * 1e3
            << " mm (file), " << worstPose * 1e3 << " mm (re-skinned)\n";
  EXPECT_GT(moved, 5000u);
  EXPECT_LT(worstFile, 1e-6 * AvatarHeight);
  EXPECT_LT(worstPose, 1e-6 * AvatarHeight);
  // The frame is not the rest pose: the check can fail.
  EXPECT_GT(Worst(Morphed(rest), theirs), 0.01);
}

TEST(GltfSkinCrossCheck, SkinnedQuadWhereVtkIsRightAndWhereItIsNot)
{
  // Only what VTK 9.1 reads right: JOINTS_0 alone, no transform on the skinned node.
  gltftest::Builder simple = gltftest::SkinnedQuad();
  auto& attributes = simple.Doc["meshes"][0]["primitives"][0]["attributes"];
  attributes.erase("JOINTS_1");
  attributes.erase("WEIGHTS_1");
  // point 2 was bound by set 1 only: bind it to J2 (index 1) in set 0
  const int joints0 = attributes["JOINTS_0"].get<int>();
  simple.Doc["accessors"][joints0]["bufferView"] =
    simple.View(std::vector<uint8_t>{ 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0 });
  const int weights0 = attributes["WEIGHTS_0"].get<int>();
  simple.Doc["accessors"][weights0]["bufferView"] =
    simple.View(std::vector<float>{ 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.2f, 0.8f, 0, 0 });
  simple.Doc["nodes"][3].erase("translation");
  simple.Doc["meshes"][0]["weights"] = { 1.0, 0.5 };
  const std::string simpleFile = Write("skin_crosscheck_quad_simple.glb", simple.Glb());
  const double agree =
    Worst(Morphed(LoadGltfScene(simpleFile)), morphnode_test::VtkGltfReaderParts(simpleFile, true));
  EXPECT_LT(agree, 1e-6) << "VTK and MorphNode should agree on a skin VTK reads right";

  // The full quad: MorphNode gives the hand-computed points; VTK 9.1 does not.
  const std::string fullFile =
    Write("skin_crosscheck_quad_full.glb", gltftest::SkinnedQuad().Glb());
  const auto vtkParts = morphnode_test::VtkGltfReaderParts(fullFile, true);
  const auto ours = Morphed(LoadGltfScene(fullFile));
  const std::vector<double> hand = gltftest::SkinnedQuadRest();
  for (size_t k = 0; k < hand.size(); ++k)
  {
    EXPECT_NEAR(ours[0][k], hand[k], 1e-6) << k;
  }
  ASSERT_EQ(vtkParts.size(), 1u);
  double vtkWorst = 0.0;
  for (vtkIdType i = 0; i < 4; ++i)
  {
    double q[3];
    vtkParts[0]->GetPoint(i, q);
    std::cout << "quad point " << i << ": hand-computed (" << hand[3 * i] << ", " << hand[3 * i + 1]
              << ", " << hand[3 * i + 2] << "), vtkGLTFReader (" << q[0] << ", " << q[1] << ", "
              << q[2] << ")\n";
    for (int k = 0; k < 3; ++k)
    {
      vtkWorst = std::max(vtkWorst, std::abs(q[k] - hand[static_cast<size_t>(3 * i + k)]));
    }
  }
  // A documented VTK 9.1 deviation (docs/avatars.md); if VTK is fixed, this says so.
  EXPECT_GT(vtkWorst, 0.1)
    << "vtkGLTFReader now reads the second weight set and ignores the skinned node's transform";
}
