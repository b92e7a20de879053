// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphSkinFilter on the shared MakeHuman avatar (vtkMorphTargetReader ->
// vtkMorphNodeFilter -> vtkMorphSkinFilter): at rest it passes every part on; the gaze turns
// each eyeball about its eye joint (centre fixed within 0.5 mm, the cornea towards the gaze
// within a degree, the eyes never leave the head) while vtkEyeGazeFilter leaves skinned eyes
// alone; the head pose turns head, neck and eyes together and leaves the feet; morph then
// skin (an open jaw turns with the head); relaxed arms hang down; bad skins are refused with
// an empty output; the skinned quad re-skinned as hand-computed; PrintSelf.
#include "vtkEyeGazeFilter.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"

#include "Core/gltf/GltfSkinnedTestFiles.h"
#include "MorphNodeTestScenes.h"
#include "gltf/GltfSkin.h"

#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTransform.h"
#include "vtkTransformFilter.h"
#include "vtkUnsignedShortArray.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace
{
using Vec3 = std::array<double, 3>;
const std::string Avatar = morphnode_test::AvatarFile();

#define SKIP_WITHOUT_AVATAR() MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar)

std::map<std::string, vtkSmartPointer<vtkPolyData>> Parts(vtkDataObject* data)
{
  std::map<std::string, vtkSmartPointer<vtkPolyData>> parts;
  auto* composite = vtkCompositeDataSet::SafeDownCast(data);
  if (!composite)
  {
    return parts;
  }
  for (vtkPolyData* poly : vtkCompositeDataSet::GetDataSets<vtkPolyData>(composite))
  {
    parts[vtkMorphPartData::GetPartName(poly->GetFieldData(), std::to_string(parts.size()))] = poly;
  }
  return parts;
}

Vec3 Centroid(vtkPolyData* p)
{
  Vec3 c{ 0, 0, 0 };
  for (vtkIdType i = 0; i < p->GetNumberOfPoints(); ++i)
  {
    double q[3];
    p->GetPoint(i, q);
    for (int k = 0; k < 3; ++k)
    {
      c[k] += q[k] / double(p->GetNumberOfPoints());
    }
  }
  return c;
}

double Distance(const Vec3& a, const double* b)
{
  return std::sqrt(
    (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

double Distance(const Vec3& a, const Vec3& b)
{
  return Distance(a, b.data());
}

/// The eyeball point furthest along +Z (the cornea) at rest, by index.
vtkIdType Cornea(vtkPolyData* eye)
{
  vtkIdType best = 0;
  double z = -1e30;
  for (vtkIdType i = 0; i < eye->GetNumberOfPoints(); ++i)
  {
    double q[3];
    eye->GetPoint(i, q);
    if (q[2] > z)
    {
      z = q[2];
      best = i;
    }
  }
  return best;
}

struct Pipeline
{
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkMorphSkinFilter> Skin;
  Pipeline()
  {
    this->Reader->SetFileName(Avatar.c_str());
    this->Morph->SetInputConnection(this->Reader->GetOutputPort());
    this->Morph->SetWeightModeToRelative();
    this->Skin->SetInputConnection(this->Morph->GetOutputPort());
  }
  std::map<std::string, vtkSmartPointer<vtkPolyData>> Run()
  {
    EXPECT_EQ(this->Skin->GetExecutive()->Update(), 1);
    return Parts(this->Skin->GetOutputDataObject(0));
  }
};

/// A glTF file written to the test output folder (`name`), read and skinned; the filter is
/// not updated yet.
struct SkinnedFile
{
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphSkinFilter> Skin;
  SkinnedFile(const std::string& name, const std::string& glb)
  {
    std::filesystem::create_directories(MORPHNODE_TEST_OUTPUT_DIR);
    this->Reader->SetFileName(morphnode_test::scenes::WriteFile(name, glb).c_str());
    this->Skin->SetInputConnection(this->Reader->GetOutputPort());
  }
};
} // namespace

TEST(MorphSkinFilter, AtRestEveryPartPassesAndTheBonesAreFound)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  const auto parts = p.Run();
  ASSERT_EQ(parts.size(), 7u);
  EXPECT_EQ(p.Skin->GetNumberOfSkinnedParts(), 7);
  EXPECT_TRUE(p.Skin->GetHasEyeBones());
  EXPECT_NE(std::string(p.Skin->GetBones()).find("left eye 'LeftEye'"), std::string::npos)
    << p.Skin->GetBones();
  // The morph node passed the skin arrays on.
  EXPECT_NE(parts.at("Body")->GetPointData()->GetArray("SkinWeights"), nullptr);
  // At rest nothing is re-skinned: the morph output's points are shared.
  const auto morphed = Parts(p.Morph->GetOutputDataObject(0));
  EXPECT_EQ(parts.at("Body")->GetPoints(), morphed.at("Body")->GetPoints());
}

TEST(MorphSkinFilter, EyesTurnAboutTheirJointsWithinTheLimits)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  const auto rest = p.Run();
  // The eye joint's position, from the core's skeleton.
  const morphnode::GltfScene scene = morphnode::LoadGltfScene(Avatar);
  const morphnode::Skeleton bones = morphnode::GltfSkeleton(scene);
  const glm::dvec3 joint(
    bones.World(bones.RestLocals())[static_cast<size_t>(bones.FindJoint("LeftEye"))][3]);
  const double leftEyeJoint[3] = { joint.x, joint.y, joint.z };
  const Vec3 restCentre = Centroid(rest.at("EyeLeft"));
  const vtkIdType cornea = Cornea(rest.at("EyeLeft"));
  double restCornea[3];
  rest.at("EyeLeft")->GetPoint(cornea, restCornea);
  EXPECT_LT(Distance(restCentre, leftEyeJoint), 0.01);

  for (double yaw : { 20.0, -15.0, 60.0 })
  {
    p.Skin->SetEyeYaw(yaw);
    p.Skin->SetEyePitch(10.0);
    const auto turned = p.Run();
    vtkPolyData* eye = turned.at("EyeLeft");
    // It turns about its joint, the sphere's centre: every point keeps its distance to it.
    double worst = 0.0;
    for (vtkIdType i = 0; i < eye->GetNumberOfPoints(); ++i)
    {
      double a[3];
      rest.at("EyeLeft")->GetPoint(i, a);
      worst = std::max(worst,
        std::abs(Distance(Vec3{ a[0], a[1], a[2] }, leftEyeJoint) -
          Distance(
            Vec3{ eye->GetPoint(i)[0], eye->GetPoint(i)[1], eye->GetPoint(i)[2] }, leftEyeJoint)));
    }
    EXPECT_LT(worst, 1e-5) << yaw;
    EXPECT_GT(Distance(Centroid(eye), restCentre), 0.0005) << yaw; // and it did turn
    // The cornea looks towards the gaze (clamped to 40 degrees), within a degree.
    double q[3];
    eye->GetPoint(cornea, q);
    const double c = yaw > 40 ? 40 : yaw;
    const double pitch = 10.0 * M_PI / 180, y = c * M_PI / 180;
    const Vec3 want{ std::cos(pitch) * std::sin(y), std::sin(pitch),
      std::cos(pitch) * std::cos(y) };
    const Vec3 restDir{ restCornea[0] - leftEyeJoint[0], restCornea[1] - leftEyeJoint[1],
      restCornea[2] - leftEyeJoint[2] };
    const Vec3 dir{ q[0] - leftEyeJoint[0], q[1] - leftEyeJoint[1], q[2] - leftEyeJoint[2] };
    // The rest cornea direction is not exactly +Z: compare the turn, not the direction.
    const double restYaw = std::atan2(restDir[0], restDir[2]),
                 restPitch = std::atan2(restDir[1], std::hypot(restDir[0], restDir[2]));
    const double yawNow = std::atan2(dir[0], dir[2]),
                 pitchNow = std::atan2(dir[1], std::hypot(dir[0], dir[2]));
    EXPECT_NEAR((yawNow - restYaw) * 180 / M_PI, c, 1.0) << yaw;
    EXPECT_NEAR((pitchNow - restPitch) * 180 / M_PI, 10.0, 1.0) << yaw;
    (void)want;
    // The body does not move with the eyes, but where its weights say (around the eye).
    vtkIdType moved = 0;
    double farthest = 0.0;
    for (vtkIdType i = 0; i < rest.at("Body")->GetNumberOfPoints(); ++i)
    {
      double a[3], b[3];
      rest.at("Body")->GetPoint(i, a);
      turned.at("Body")->GetPoint(i, b);
      if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])
      {
        ++moved;
        farthest = std::max(farthest, Distance(Vec3{ a[0], a[1], a[2] }, leftEyeJoint));
      }
    }
    EXPECT_LT(moved, rest.at("Body")->GetNumberOfPoints() / 50) << yaw;
    EXPECT_LT(farthest, 0.1) << yaw; // both eyes turn: within the head
  }

  // vtkEyeGazeFilter leaves skinned eyes alone (their node origin is at the feet).
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(p.Morph->GetOutputPort());
  gaze->SetEyeYaw(30);
  ASSERT_EQ(gaze->GetExecutive()->Update(), 1);
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 0);
  EXPECT_LT(
    Distance(Centroid(Parts(gaze->GetOutputDataObject(0)).at("EyeLeft")), restCentre), 1e-9);
}

TEST(MorphSkinFilter, HeadPoseCarriesTheEyesAndLeavesTheFeet)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  p.Morph->SetWeightByName("jawOpen", 1.0);
  const auto rest = p.Run();
  p.Skin->SetHeadYaw(30);
  p.Skin->SetHeadPitch(-10);
  const auto turned = p.Run();
  // The nose tip (the body's foremost point above the chin) moves with the head.
  vtkPolyData* restBody = rest.at("Body");
  vtkIdType nose = 0;
  for (vtkIdType i = 0; i < restBody->GetNumberOfPoints(); ++i)
  {
    const double* q = restBody->GetPoint(i);
    nose = q[1] > 1.45 && q[2] > restBody->GetPoint(nose)[2] ? i : nose;
  }
  double n0[3], n1[3];
  restBody->GetPoint(nose, n0);
  turned.at("Body")->GetPoint(nose, n1);
  EXPECT_GT(Distance(Vec3{ n0[0], n0[1], n0[2] }, n1), 0.03);
  for (const char* eye : { "EyeLeft", "EyeRight" })
  {
    const Vec3 a = Centroid(rest.at(eye)), b = Centroid(turned.at(eye));
    EXPECT_GT(Distance(a, b), 0.02) << eye;                     // the eyes moved with the head
    EXPECT_NEAR(Distance(b, n1), Distance(a, n0), 1e-4) << eye; // and stay in it
  }
  EXPECT_NEAR(Distance(Centroid(turned.at("EyeLeft")), Centroid(turned.at("EyeRight"))),
    Distance(Centroid(rest.at("EyeLeft")), Centroid(rest.at("EyeRight"))), 1e-5);
  // The lowest body vertex (a foot) does not move.
  vtkPolyData* body = rest.at("Body");
  vtkIdType lowest = 0;
  for (vtkIdType i = 0; i < body->GetNumberOfPoints(); ++i)
  {
    lowest = body->GetPoint(i)[1] < body->GetPoint(lowest)[1] ? i : lowest;
  }
  double a[3], b[3];
  body->GetPoint(lowest, a);
  turned.at("Body")->GetPoint(lowest, b);
  EXPECT_LT(Distance(Vec3{ a[0], a[1], a[2] }, b), 1e-7);
  // Morph then skin: the open jaw's teeth turn with the head (lower teeth left of rest).
  EXPECT_GT(Centroid(turned.at("Teeth"))[0], Centroid(rest.at("Teeth"))[0] + 0.01);
  // Field data says what was used.
  auto* used = turned.at("Body")->GetFieldData()->GetArray("SkinPose");
  ASSERT_NE(used, nullptr);
  EXPECT_EQ(used->GetComponent(0, 0), 30.0);
}

/// Every part's points and normals as numbers, the output let go (so that the filter may
/// write its arrays in place next frame).
std::map<std::string, std::vector<float>> Snapshot(vtkMorphSkinFilter* skin)
{
  EXPECT_EQ(skin->GetExecutive()->Update(), 1);
  std::map<std::string, std::vector<float>> out;
  for (const auto& [name, poly] : Parts(skin->GetOutputDataObject(0)))
  {
    std::vector<float>& v = out[name];
    for (vtkDataArray* a : { poly->GetPoints()->GetData(), poly->GetPointData()->GetNormals() })
    {
      for (vtkIdType i = 0; a && i < a->GetNumberOfValues(); ++i)
      {
        v.push_back(static_cast<float>(a->GetComponent(i / 3, static_cast<int>(i % 3))));
      }
    }
  }
  return out;
}

TEST(MorphSkinFilter, ReskinsOnlyWhatChangedAndEqualsAFullReskin)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  // A full re-skin of the same frame: a new filter, whose first execution re-skins all.
  auto full = [&p]()
  {
    vtkNew<vtkMorphSkinFilter> fresh;
    fresh->SetInputConnection(p.Morph->GetOutputPort());
    fresh->SetHeadYaw(p.Skin->GetHeadYaw());
    fresh->SetEyeYaw(p.Skin->GetEyeYaw());
    fresh->SetEyePitch(p.Skin->GetEyePitch());
    return Snapshot(fresh);
  };
  p.Skin->SetEyeYaw(10.0);
  // A weight from the start: the morph node blends every frame, so its MorphedPointRanges
  // tell the filter what the morph can change (a part that starts to be blended is re-skinned
  // whole once).
  p.Morph->SetWeightByName("jawOpen", 0.1);
  auto last = Snapshot(p.Skin);
  EXPECT_EQ(last, full());
  const vtkIdType total = p.Skin->GetNumberOfReskinnedPoints();
  EXPECT_GT(total, 0);
  struct Step
  {
    const char* What;
    double HeadYaw, EyeYaw, EyePitch, JawOpen;
    const char* Moves; // a part that must change
  };
  for (const Step& step : { Step{ "only the eyes turn", 0.0, 25.0, 0.0, 0.1, "EyeLeft" },
         Step{ "only the head turns", 15.0, 25.0, 0.0, 0.1, "Body" },
         Step{ "only the eyes look down", 15.0, 25.0, -12.0, 0.1, "EyeRight" },
         Step{ "only a weight changes", 15.0, 25.0, -12.0, 0.6, "Body" },
         Step{ "nothing changes", 15.0, 25.0, -12.0, 0.6, nullptr } })
  {
    SCOPED_TRACE(step.What);
    p.Skin->SetHeadYaw(step.HeadYaw);
    p.Skin->SetEyeYaw(step.EyeYaw);
    p.Skin->SetEyePitch(step.EyePitch);
    p.Morph->SetWeightByName("jawOpen", step.JawOpen);
    p.Skin->Modified(); // executes even when nothing changed
    const auto now = Snapshot(p.Skin);
    const vtkIdType reskinned = p.Skin->GetNumberOfReskinnedPoints();
    // Bit for bit what a full re-skin gives: a point whose joint or input changed and was
    // not written again would differ here.
    const auto expected = full();
    ASSERT_EQ(now.size(), expected.size());
    for (const auto& [name, values] : expected)
    {
      EXPECT_TRUE(now.at(name) == values) << name << " differs from a full re-skin";
    }
    if (step.Moves)
    {
      EXPECT_NE(now.at(step.Moves), last.at(step.Moves)) << step.Moves << " did not move";
      EXPECT_GT(reskinned, 0);
      // Incremental: far fewer points than a full re-skin (the legs and arms stay).
      EXPECT_LT(reskinned, total) << "every point was re-skinned";
    }
    else
    {
      EXPECT_EQ(reskinned, 0);
    }
    last = now;
  }
}

// A filter between the morph node and the skin filter that moves every point (here a
// translation changing each frame) passes the morph's MorphedPointRanges on; the skin
// filter must not trust them for points that filter wrote (MorphedArraysTime): with the head
// held, the legs move with the translation as a full re-skin moves them.
TEST(MorphSkinFilter, AFilterBetweenTheMorphAndTheSkinIsNotTakenForTheMorph)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  vtkNew<vtkTransform> shift;
  vtkNew<vtkTransformFilter> move;
  move->SetTransform(shift);
  move->SetInputConnection(p.Morph->GetOutputPort());
  p.Skin->SetInputConnection(move->GetOutputPort());
  p.Skin->SetHeadYaw(10.0);
  p.Morph->SetWeightByName("jawOpen", 0.1);
  Snapshot(p.Skin);
  move->Update();
  const auto moved = Parts(move->GetOutputDataObject(0));
  ASSERT_EQ(moved.count("Body"), 1u);
  ASSERT_NE(moved.at("Body")->GetFieldData()->GetArray("MorphedPointRanges"), nullptr)
    << "the ranges do not reach the skin filter: the check could not fail";
  for (int step = 1; step <= 3; ++step)
  {
    SCOPED_TRACE("step " + std::to_string(step));
    shift->Identity();
    shift->Translate(0.01 * step, 0.0, 0.0);
    p.Morph->SetWeightByName("jawOpen", 0.1 + 0.1 * step);
    const auto now = Snapshot(p.Skin);
    vtkNew<vtkMorphSkinFilter> fresh;
    fresh->SetInputConnection(move->GetOutputPort());
    fresh->SetHeadYaw(10.0);
    const auto expected = Snapshot(fresh);
    ASSERT_EQ(now.size(), expected.size());
    for (const auto& [name, values] : expected)
    {
      EXPECT_TRUE(now.at(name) == values) << name << " differs from a full re-skin";
    }
  }
}

TEST(MorphSkinFilter, EyeLookTargetsMoveTheLidsWhileTheEyeJointsTurnTheEyeballsOnce)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  p.Run();
  // The eye joints turn the eyeballs, not the head with its lids.
  std::vector<std::string> eyeParts;
  for (int i = 0; i < p.Skin->GetNumberOfEyeParts(); ++i)
  {
    eyeParts.emplace_back(p.Skin->GetEyePart(i));
  }
  EXPECT_NE(std::find(eyeParts.begin(), eyeParts.end(), "EyeLeft"), eyeParts.end());
  EXPECT_NE(std::find(eyeParts.begin(), eyeParts.end(), "EyeRight"), eyeParts.end());
  EXPECT_EQ(std::find(eyeParts.begin(), eyeParts.end(), "Body"), eyeParts.end());
  std::vector<std::string> looks;
  for (int t = 1; t < p.Reader->GetNumberOfTargets(); ++t)
  {
    const std::string name = p.Reader->GetTargetName(t);
    if (name.rfind("eyeLookDown", 0) == 0)
    {
      looks.push_back(name);
    }
  }
  ASSERT_EQ(looks.size(), 2u);
  auto frame = [&p, &looks](double pitch, double look)
  {
    p.Skin->SetEyePitch(pitch);
    for (const auto& name : looks)
    {
      p.Morph->SetWeightByName(name.c_str(), look);
    }
    return Snapshot(p.Skin);
  };
  // Without the targets off the eyeballs turn twice (by the joints and by their targets):
  // what the rig's eyeLook* terms did before they were dropped in bones mode.
  const auto bonesOnly = frame(-15.0, 0.0);
  const auto twice = frame(-15.0, 0.8);
  EXPECT_NE(twice.at("EyeLeft"), bonesOnly.at("EyeLeft"));
  for (const auto& part : eyeParts)
  {
    for (const auto& name : looks)
    {
      p.Morph->SetTargetOffInPart(part.c_str(), name.c_str());
    }
  }
  const auto ahead = frame(0.0, 0.0);
  const auto down = frame(-15.0, 0.8);
  // The eyeballs turn once: exactly where the joints alone put them.
  for (const auto& part : eyeParts)
  {
    EXPECT_EQ(down.at(part), bonesOnly.at(part)) << part << " turned twice";
  }
  // The lids (the head's points the eyeLookDown targets move) go down against the eyes ahead.
  const std::vector<float>& body = down.at("Body");
  const std::vector<float>& still = bonesOnly.at("Body");
  const std::vector<float>& front = ahead.at("Body");
  const size_t n = body.size() / 2; // points, then normals
  size_t moved = 0;
  double dy = 0.0;
  for (size_t i = 0; i < n; i += 3)
  {
    if (body[i] != still[i] || body[i + 1] != still[i + 1] || body[i + 2] != still[i + 2])
    {
      ++moved;
      dy += body[i + 1] - front[i + 1];
    }
  }
  EXPECT_GT(moved, 20u) << "the eyeLookDown targets moved no lid";
  EXPECT_LT(dy / std::max<size_t>(moved, 1), -1e-4) << "the lids did not go down";
  // Off again: the eyeballs turn twice as before.
  p.Morph->RemoveAllTargetsOffInParts();
  EXPECT_EQ(frame(-15.0, 0.8).at("EyeLeft"), twice.at("EyeLeft"));
}

TEST(MorphSkinFilter, RelaxedArmsHangDown)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  const auto rest = p.Run();
  p.Skin->RelaxArmsOn();
  const auto relaxed = p.Run();
  double rb[6], bb[6];
  rest.at("Body")->GetBounds(rb);
  relaxed.at("Body")->GetBounds(bb);
  // A-pose hands reach +-0.496 m; hanging arms stay much closer to the body.
  EXPECT_LT(bb[1] - bb[0], 0.8 * (rb[1] - rb[0]));
  EXPECT_NEAR(bb[3], rb[3], 1e-4); // the head stays
}

TEST(MorphSkinFilter, SkinnedQuadAndDamagedSkins)
{
  SkinnedFile quad("skin_filter_quad.glb", gltftest::SkinnedQuad().Glb());
  vtkMorphSkinFilter* skin = quad.Skin;
  ASSERT_EQ(skin->GetExecutive()->Update(), 1);
  auto parts = Parts(skin->GetOutputDataObject(0));
  ASSERT_EQ(parts.size(), 1u);
  const std::vector<double> hand = gltftest::SkinnedQuadRest();
  for (vtkIdType i = 0; i < 4; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_NEAR(
        parts.begin()->second->GetPoint(i)[k], hand[static_cast<size_t>(3 * i + k)], 1e-6);
    }
  }
  EXPECT_STREQ(skin->GetBones(),
    "head none, neck none, left eye none, right eye none, jaw none, left arm none, right arm none");

  // A joint index out of range in the skin arrays: an error, and nothing drawn.
  vtkNew<vtkMorphSkinFilter> bad;
  vtkSmartPointer<vtkPolyData> damaged = vtkSmartPointer<vtkPolyData>::New();
  damaged->DeepCopy(parts.begin()->second);
  auto* joints =
    vtkUnsignedShortArray::SafeDownCast(damaged->GetPointData()->GetArray("SkinJoints"));
  ASSERT_NE(joints, nullptr);
  joints->SetTypedComponent(0, 0, 7);
  bad->SetInputData(damaged);
  bad->SetHeadYaw(10);
  testing::internal::CaptureStderr();
  EXPECT_EQ(bad->GetExecutive()->Update(), 0);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("bound to joint 7"), std::string::npos) << err;
  EXPECT_EQ(vtkPolyData::SafeDownCast(bad->GetOutputDataObject(0))->GetNumberOfPoints(), 0);

  // A pose table without rows (and without any pose column): an error, nothing drawn.
  vtkNew<vtkMorphSkinFilter> unposed;
  unposed->SetInputData(parts.begin()->second);
  vtkNew<vtkTable> empty;
  vtkNew<vtkDoubleArray> other;
  other->SetName("Other");
  empty->AddColumn(other);
  unposed->SetInputData(1, empty);
  testing::internal::CaptureStderr();
  EXPECT_EQ(unposed->GetExecutive()->Update(), 0);
  const std::string rows = testing::internal::GetCapturedStderr();
  EXPECT_NE(rows.find("the pose table has no rows"), std::string::npos) << rows;
  EXPECT_EQ(vtkPolyData::SafeDownCast(unposed->GetOutputDataObject(0))->GetNumberOfPoints(), 0);

  std::ostringstream os;
  skin->Print(os);
  EXPECT_NE(os.str().find("NeckShare: 0.4"), std::string::npos);
}

/// The parts' points and normals, copied.
std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> Copy(
  const std::map<std::string, vtkSmartPointer<vtkPolyData>>& parts)
{
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> out;
  for (const auto& [name, poly] : parts)
  {
    for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
    {
      double q[3], n[3];
      poly->GetPoint(i, q);
      poly->GetPointData()->GetNormals()->GetTuple(i, n);
      out[name].first.insert(out[name].first.end(), q, q + 3);
      out[name].second.insert(out[name].second.end(), n, n + 3);
    }
  }
  return out;
}

// Pose only (SkinPoints off): the skeleton is posed as before (every report the same) but no
// point moves: each part passes the morph's arrays on (the same objects) with
// SkinJointDeltas; blending those per point as a renderer does (linear blend skinning of the
// first four influences, normals by the cofactor) gives the CPU's re-skin. Turned on again,
// the filter re-skins as before. The skinned quad (two sets of influences) is re-skinned on
// the CPU all the same, and reported.
TEST(MorphSkinFilter, PoseOnlyKeepsThePointsAndItsDeltasGiveTheCpuSkin)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  p.Morph->SetWeightByName("jawOpen", 0.6);
  p.Skin->SetHeadYaw(25);
  p.Skin->SetHeadPitch(-8);
  p.Skin->SetEyeYaw(20);
  p.Skin->SetRelaxArms(true);
  const auto cpu = Copy(p.Run());
  const std::string bones = p.Skin->GetBones();
  double headBounds[6];
  ASSERT_TRUE(p.Skin->GetHeadBounds(headBounds));
  const int eyeParts = p.Skin->GetNumberOfEyeParts();
  EXPECT_GT(p.Skin->GetNumberOfReskinnedPoints(), 0);

  p.Skin->SkinPointsOff();
  const auto posed = p.Run();
  EXPECT_EQ(p.Skin->GetNumberOfSkinnedParts(), 7);
  EXPECT_EQ(p.Skin->GetNumberOfPosedOnlyParts(), 7);
  EXPECT_EQ(p.Skin->GetNumberOfCPUSkinnedParts(), 0);
  EXPECT_EQ(p.Skin->GetNumberOfReskinnedPoints(), 0);
  EXPECT_EQ(p.Skin->GetBones(), bones);
  EXPECT_EQ(p.Skin->GetNumberOfEyeParts(), eyeParts);
  double b[6];
  ASSERT_TRUE(p.Skin->GetHeadBounds(b));
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_EQ(b[k], headBounds[k]);
  }
  const auto morphed = Parts(p.Morph->GetOutputDataObject(0));
  ASSERT_EQ(posed.size(), 7u);
  for (const auto& [name, poly] : posed)
  {
    SCOPED_TRACE(name);
    // The morph's arrays, shared.
    EXPECT_EQ(poly->GetPoints()->GetData(), morphed.at(name)->GetPoints()->GetData());
    EXPECT_EQ(poly->GetPointData()->GetNormals(), morphed.at(name)->GetPointData()->GetNormals());
    EXPECT_EQ(poly->GetFieldData()->GetArray("SkinPose")->GetComponent(0, 0), 25.0);
    auto* deltas = vtkFloatArray::SafeDownCast(poly->GetFieldData()->GetArray("SkinJointDeltas"));
    ASSERT_NE(deltas, nullptr);
    ASSERT_EQ(deltas->GetNumberOfComponents(), 12);
    ASSERT_EQ(deltas->GetNumberOfTuples(),
      poly->GetFieldData()->GetArray("SkinJointIndices")->GetNumberOfTuples());
    auto* joints = poly->GetPointData()->GetArray("SkinJoints");
    auto* weights = poly->GetPointData()->GetArray("SkinWeights");
    ASSERT_EQ(joints->GetNumberOfComponents(), 4);
    const auto& [cpuPoints, cpuNormals] = cpu.at(name);
    double worst = 0.0, worstNormal = 0.0;
    for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
    {
      double m[12] = { 0 };
      for (int k = 0; k < 4; ++k)
      {
        const double w = weights->GetComponent(i, k);
        const auto j = static_cast<vtkIdType>(joints->GetComponent(i, k));
        for (int e = 0; w != 0.0 && e < 12; ++e)
        {
          m[e] += w * deltas->GetComponent(j, e);
        }
      }
      double q[3], n[3];
      poly->GetPoint(i, q);
      poly->GetPointData()->GetNormals()->GetTuple(i, n);
      // Rows: m[4 r + c]; the cofactor's rows are the cross products of M's rows.
      const Vec3 r0{ m[0], m[1], m[2] }, r1{ m[4], m[5], m[6] }, r2{ m[8], m[9], m[10] };
      auto cross = [](const Vec3& a, const Vec3& c) {
        return Vec3{ a[1] * c[2] - a[2] * c[1], a[2] * c[0] - a[0] * c[2],
          a[0] * c[1] - a[1] * c[0] };
      };
      const Vec3 c0 = cross(r1, r2), c1 = cross(r2, r0), c2 = cross(r0, r1);
      const Vec3 nn{ c0[0] * n[0] + c0[1] * n[1] + c0[2] * n[2],
        c1[0] * n[0] + c1[1] * n[1] + c1[2] * n[2], c2[0] * n[0] + c2[1] * n[1] + c2[2] * n[2] };
      const double len = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
      for (int r = 0; r < 3; ++r)
      {
        const double x = m[4 * r] * q[0] + m[4 * r + 1] * q[1] + m[4 * r + 2] * q[2] + m[4 * r + 3];
        worst = std::max(worst, std::abs(x - cpuPoints[static_cast<size_t>(3 * i + r)]));
        worstNormal =
          std::max(worstNormal, std::abs(nn[r] / len - cpuNormals[static_cast<size_t>(3 * i + r)]));
      }
    }
    EXPECT_LT(worst, 2e-6);
    EXPECT_LT(worstNormal, 1e-4);
  }
  // Points skinned again, as before.
  p.Skin->SkinPointsOn();
  const auto again = Copy(p.Run());
  EXPECT_EQ(p.Skin->GetNumberOfPosedOnlyParts(), 0);
  for (const auto& [name, arrays] : cpu)
  {
    EXPECT_EQ(again.at(name).first, arrays.first) << name;
  }
  EXPECT_EQ(
    Parts(p.Skin->GetOutputDataObject(0)).at("Body")->GetFieldData()->GetArray("SkinJointDeltas"),
    nullptr);

  // Two sets of influences: re-skinned on the CPU, and said.
  SkinnedFile twoSets("skin_filter_quad_pose.glb", gltftest::SkinnedQuad().Glb());
  vtkMorphSkinFilter* skin = twoSets.Skin;
  skin->SkinPointsOff();
  ASSERT_EQ(skin->GetExecutive()->Update(), 1);
  EXPECT_EQ(skin->GetNumberOfPosedOnlyParts(), 0);
  ASSERT_EQ(skin->GetNumberOfCPUSkinnedParts(), 1);
  EXPECT_STREQ(skin->GetCPUSkinnedPart(0), "Mesh"); // the part (node) name
  EXPECT_EQ(skin->GetCPUSkinnedPart(1), nullptr);
  auto quad = Parts(skin->GetOutputDataObject(0));
  EXPECT_EQ(quad.begin()->second->GetFieldData()->GetArray("SkinJointDeltas"), nullptr);
  std::ostringstream os;
  skin->Print(os);
  EXPECT_NE(os.str().find("CPUSkinnedParts: Mesh"), std::string::npos) << os.str();
}

// Posing only frame after frame, the output held as a renderer holds it: each frame's
// parts carry that frame's morph arrays, field data and pose, never an earlier frame's
// (the kept output leaves are brought up to date, not copied anew), and nothing piles up.
TEST(MorphSkinFilter, PoseOnlyFrameAfterFrameCarriesThatFrame)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  p.Skin->SkinPointsOff();
  std::vector<vtkSmartPointer<vtkPolyData>> held;
  for (int frame = 0; frame < 5; ++frame)
  {
    SCOPED_TRACE("frame " + std::to_string(frame));
    p.Morph->SetWeightByName("jawOpen", 0.1 * frame);
    p.Skin->SetHeadYaw(5.0 * frame);
    const auto posed = p.Run();
    const auto morphed = Parts(p.Morph->GetOutputDataObject(0));
    ASSERT_EQ(posed.size(), 7u);
    // The head's own field data (the morph node's TargetNames), as the input has it.
    EXPECT_EQ(p.Skin->GetOutputDataObject(0)->GetFieldData()->GetAbstractArray("TargetNames"),
      p.Morph->GetOutputDataObject(0)->GetFieldData()->GetAbstractArray("TargetNames"));
    EXPECT_NE(
      p.Skin->GetOutputDataObject(0)->GetFieldData()->GetAbstractArray("TargetNames"), nullptr);
    held.clear();
    for (const auto& [name, poly] : posed)
    {
      SCOPED_TRACE(name);
      vtkPolyData* in = morphed.at(name);
      EXPECT_EQ(poly->GetPoints(), in->GetPoints());
      EXPECT_EQ(poly->GetPointData()->GetNormals(), in->GetPointData()->GetNormals());
      vtkFieldData* fd = poly->GetFieldData();
      vtkFieldData* inFd = in->GetFieldData();
      ASSERT_EQ(fd->GetNumberOfArrays(), inFd->GetNumberOfArrays() + 2);
      for (int a = 0; a < inFd->GetNumberOfArrays(); ++a)
      {
        EXPECT_EQ(fd->GetAbstractArray(a), inFd->GetAbstractArray(a)) << a;
      }
      EXPECT_EQ(fd->GetArray("SkinPose")->GetComponent(0, 0), 5.0 * frame);
      ASSERT_NE(fd->GetArray("SkinJointDeltas"), nullptr);
      auto copy = vtkSmartPointer<vtkPolyData>::New();
      copy->ShallowCopy(poly);
      held.push_back(copy);
    }
  }
}

// The jaw joint: the avatar has a Jaw joint AND a jawOpen target, so by default (JAW_AUTO)
// JawOpen leaves the jaw joint alone (the target opens the mouth; never twice); forced on
// (JAW_ON) the lower teeth, bound to the jaw, go down; the choice is reported.
TEST(MorphSkinFilter, JawJointTurnsOnlyWhereNoJawOpenTargetOpensTheMouth)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline p;
  const auto rest = p.Run();
  p.Skin->SetJawOpen(1.0);
  const auto automatic = p.Run();
  EXPECT_FALSE(p.Skin->GetJawByBone())
    << "the avatar's jawOpen target should open its mouth, not the joint";
  EXPECT_EQ(automatic.at("Teeth")->GetPoints(), rest.at("Teeth")->GetPoints());
  p.Skin->SetTurnJaw(vtkMorphSkinFilter::JAW_ON);
  const auto forced = p.Run();
  EXPECT_TRUE(p.Skin->GetJawByBone());
  vtkPolyData* teeth = forced.at("Teeth");
  vtkPolyData* teethRest = rest.at("Teeth");
  double lowest = 0.0;
  for (vtkIdType i = 0; i < teeth->GetNumberOfPoints(); ++i)
  {
    lowest = std::min(lowest, teeth->GetPoint(i)[1] - teethRest->GetPoint(i)[1]);
  }
  EXPECT_LT(lowest, -0.005) << "no tooth went down with the jaw";
  auto* used = teeth->GetFieldData()->GetArray("SkinPose");
  ASSERT_NE(used, nullptr);
  EXPECT_EQ(used->GetComponent(5, 0), 1.0);
  p.Skin->SetTurnJaw(vtkMorphSkinFilter::JAW_OFF);
  p.Run();
  EXPECT_FALSE(p.Skin->GetJawByBone());
}

// A VRM avatar's own humanoid map and look-at range maps reach the skin filter through the
// reader (vtkMorphSkinArrays' HumanoidBones, LookAtRangeMaps): the skinned quad whose J2
// the VRMC_vrm extension calls the left eye (no name says so) turns by the gaze through
// the outer range map (45 of 90 degrees -> 6 of 12), not the eye limits' 40 degrees.
TEST(MorphSkinFilter, VrmHumanoidBonesAndLookAtRangeMaps)
{
  gltftest::Builder b = gltftest::SkinnedQuad();
  b.Doc["extensions"]["VRMC_vrm"] = { { "specVersion", "1.0" },
    { "humanoid", { { "humanBones", { { "leftEye", { { "node", 2 } } } } } } },
    { "lookAt",
      { { "type", "bone" },
        { "rangeMapHorizontalOuter", { { "inputMaxValue", 90 }, { "outputScale", 12 } } } } } };
  b.Doc["extensionsUsed"] = { "VRMC_vrm" };
  SkinnedFile vrm("skin_filter_vrm_quad.glb", b.Glb());
  vtkMorphSkinFilter* skin = vrm.Skin;
  skin->Update();
  EXPECT_TRUE(skin->GetHasEyeBones()) << skin->GetBones();
  const auto rest = Parts(skin->GetOutputDataObject(0));
  ASSERT_EQ(rest.size(), 1u);
  vtkPolyData* quad = rest.begin()->second;
  ASSERT_NE(quad->GetFieldData()->GetAbstractArray("HumanoidBones"), nullptr);
  skin->SetEyeYaw(45.0);
  skin->Update();
  vtkPolyData* turned = Parts(skin->GetOutputDataObject(0)).begin()->second;
  // p2 is bound to J2 alone: it turns about J2's origin by the mapped angle about the
  // eye's up (+Y of the face).
  const glm::dvec3 pivot(0.0, 1.0, 0.0); // J2 at rest (see ReskinnedQuadFollowsItsJoints)
  double a[3], c[3];
  quad->GetPoint(2, a);
  turned->GetPoint(2, c);
  const glm::dvec3 u = glm::dvec3(a[0], a[1], a[2]) - pivot,
                   v = glm::dvec3(c[0], c[1], c[2]) - pivot;
  EXPECT_NEAR(glm::length(u), glm::length(v), 1e-6);
  const double angle =
    std::acos(glm::clamp(glm::dot(glm::normalize(u), glm::normalize(v)), -1.0, 1.0)) * 180.0 /
    glm::pi<double>();
  EXPECT_NEAR(angle, 6.0, 0.01) << "the VRM range map was not used (the limits would give 40)";
}

namespace
{
/// `a` and `b` hold the same values exactly: both absent, or the same tuples and components.
void ExpectSameValues(vtkDataArray* a, vtkDataArray* b, const std::string& what)
{
  ASSERT_EQ(a == nullptr, b == nullptr) << what;
  if (!a)
  {
    return;
  }
  ASSERT_EQ(a->GetNumberOfTuples(), b->GetNumberOfTuples()) << what;
  const int nc = a->GetNumberOfComponents();
  ASSERT_EQ(nc, b->GetNumberOfComponents()) << what;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    ASSERT_EQ(a->GetComponent(i / nc, static_cast<int>(i % nc)),
      b->GetComponent(i / nc, static_cast<int>(i % nc)))
      << what << " value " << i;
  }
}

/// The names of a field data's arrays.
std::set<std::string> FieldNames(vtkFieldData* fd)
{
  std::set<std::string> names;
  for (int k = 0; k < fd->GetNumberOfArrays(); ++k)
  {
    names.insert(fd->GetAbstractArray(k)->GetName());
  }
  return names;
}

/// Parts posed in a second pass (`a`) and in the morph node's (`b`) are the same: points
/// and normals bit for bit, the field data's names, SkinPose and SkinJointDeltas values.
void ExpectSameParts(const std::map<std::string, vtkSmartPointer<vtkPolyData>>& a,
  const std::map<std::string, vtkSmartPointer<vtkPolyData>>& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, pa] : a)
  {
    SCOPED_TRACE(name);
    ASSERT_EQ(b.count(name), 1u);
    vtkPolyData* pb = b.at(name);
    ExpectSameValues(pa->GetPoints()->GetData(), pb->GetPoints()->GetData(), "points");
    ExpectSameValues(pa->GetPointData()->GetNormals(), pb->GetPointData()->GetNormals(), "normals");
    EXPECT_EQ(FieldNames(pa->GetFieldData()), FieldNames(pb->GetFieldData()));
    for (const char* array : { "SkinPose", "SkinJointDeltas" })
    {
      ExpectSameValues(
        pa->GetFieldData()->GetArray(array), pb->GetFieldData()->GetArray(array), array);
    }
  }
}

/// The reports of two skin filters agree.
void ExpectSameReports(vtkMorphSkinFilter* a, vtkMorphSkinFilter* b)
{
  EXPECT_EQ(a->GetNumberOfSkinnedParts(), b->GetNumberOfSkinnedParts());
  EXPECT_EQ(a->GetNumberOfPosedOnlyParts(), b->GetNumberOfPosedOnlyParts());
  EXPECT_EQ(a->GetNumberOfCPUSkinnedParts(), b->GetNumberOfCPUSkinnedParts());
  EXPECT_STREQ(a->GetBones(), b->GetBones());
  EXPECT_EQ(a->GetNumberOfEyeParts(), b->GetNumberOfEyeParts());
  EXPECT_EQ(a->GetHasHeadBones(), b->GetHasHeadBones());
  EXPECT_EQ(a->GetJawByBone(), b->GetJawByBone());
  double ba[6] = { 0 }, bb[6] = { 0 };
  EXPECT_EQ(a->GetHeadBounds(ba), b->GetHeadBounds(bb));
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_EQ(ba[k], bb[k]);
  }
}
} // namespace

// The skin filter as the morph node's pose filter (vtkMorphNodeFilter::SetPoseFilter): the
// skeleton posed in the morph node's own pass gives, frame after frame, what the same filter
// gives downstream in a second pass: posed only (the GPU's deltas) with the output held as a
// renderer holds it or not, re-skinned on the CPU, at rest; the same reports. Its settings
// re-execute the morph node; a pose table on port 2 wins over the weights table; without
// the pose filter the morph node's parts carry no pose any more.
TEST(MorphSkinFilter, PosedInTheMorphNodesPassAsInASecondPass)
{
  SKIP_WITHOUT_AVATAR();
  Pipeline two;
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(Avatar.c_str());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  vtkNew<vtkMorphSkinFilter> poser;
  morph->SetPoseFilter(poser);
  EXPECT_EQ(morph->GetPoseFilter(), poser.GetPointer());
  auto fused = [&]
  {
    EXPECT_EQ(morph->GetExecutive()->Update(), 1);
    return Parts(morph->GetOutputDataObject(0));
  };
  std::vector<vtkSmartPointer<vtkPolyData>> held;
  for (const bool skinPoints : { false, true })
  {
    two.Skin->SetSkinPoints(skinPoints);
    poser->SetSkinPoints(skinPoints);
    for (int frame = 0; frame < 4; ++frame)
    {
      SCOPED_TRACE(
        std::string(skinPoints ? "re-skinned" : "posed only") + ", frame " + std::to_string(frame));
      for (vtkMorphNodeFilter* m : { two.Morph.GetPointer(), morph.GetPointer() })
      {
        m->SetWeightByName("jawOpen", 0.15 * frame);
        m->SetWeightByName("viseme_O", 0.1 * (3 - frame));
      }
      for (vtkMorphSkinFilter* s : { two.Skin.GetPointer(), poser.GetPointer() })
      {
        s->SetHeadYaw(6.0 * frame);
        s->SetHeadPitch(-2.0 * frame);
        s->SetEyeYaw(-4.0 * frame);
      }
      const auto a = two.Run();
      const auto b = fused();
      ExpectSameParts(a, b);
      ExpectSameReports(two.Skin, poser);
      // (Both morph nodes executed: the weights changed.)
      EXPECT_EQ(two.Skin->GetNumberOfReskinnedPoints(), poser->GetNumberOfReskinnedPoints());
      if (frame > 0)
      {
        EXPECT_EQ(
          b.at("Body")->GetFieldData()->GetArray("SkinPose")->GetComponent(0, 0), 6.0 * frame);
      }
      EXPECT_EQ(b.at("Body")->GetFieldData()->GetArray("SkinJointDeltas") != nullptr,
        !skinPoints && frame > 0 ? true : !skinPoints);
      if (frame % 2 == 1)
      {
        held.clear(); // every other frame, both outputs held as a renderer holds them
        for (const auto* parts : { &a, &b })
        {
          for (const auto& [name, poly] : *parts)
          {
            auto copy = vtkSmartPointer<vtkPolyData>::New();
            copy->ShallowCopy(poly);
            held.push_back(copy);
          }
        }
      }
    }
  }
  EXPECT_EQ(poser->GetNumberOfSkinnedParts(), 7);
  EXPECT_GT(poser->GetNumberOfReskinnedPoints(), 0);

  // At rest, re-skinning: the parts pass as the morph gives them, without a pose.
  poser->SetHeadYaw(0);
  poser->SetHeadPitch(0);
  poser->SetEyeYaw(0);
  two.Skin->SetHeadYaw(0);
  two.Skin->SetHeadPitch(0);
  two.Skin->SetEyeYaw(0);
  ExpectSameParts(two.Run(), fused());
  EXPECT_EQ(fused().at("Body")->GetFieldData()->GetArray("SkinPose"), nullptr);

  // The skin filter's settings re-execute the morph node; port 2's table wins.
  poser->SkinPointsOff();
  poser->SetHeadYaw(12);
  EXPECT_EQ(fused().at("Body")->GetFieldData()->GetArray("SkinPose")->GetComponent(0, 0), 12.0);
  vtkNew<vtkTable> pose;
  vtkNew<vtkDoubleArray> yaw;
  yaw->SetName("HeadYaw");
  yaw->InsertNextValue(-7.0);
  pose->AddColumn(yaw);
  morph->SetInputData(2, pose);
  EXPECT_EQ(fused().at("Body")->GetFieldData()->GetArray("SkinPose")->GetComponent(0, 0), -7.0);
  std::ostringstream os;
  morph->Print(os);
  EXPECT_NE(os.str().find("PoseFilter: vtkMorphSkinFilter"), std::string::npos) << os.str();
  EXPECT_NE(os.str().find("Pose: connected"), std::string::npos) << os.str();

  // Without the pose filter: the morph's parts, no pose.
  morph->SetPoseFilter(nullptr);
  const auto plain = fused();
  for (const auto& [name, poly] : plain)
  {
    SCOPED_TRACE(name);
    EXPECT_EQ(poly->GetFieldData()->GetArray("SkinPose"), nullptr);
    EXPECT_EQ(poly->GetFieldData()->GetArray("SkinJointDeltas"), nullptr);
  }
}

// The same on the skinned quad of the VRM test (a humanoid left eye, two sets of influences:
// re-skinned on the CPU even when posing only), morphed by its `Up` target and turned by the
// eye: one pass gives the second pass's points. A track filter without a fused form
// (vtkEyeGazeFilter) fails the morph node's update with an error and an empty output.
TEST(MorphSkinFilter, PosedInTheMorphNodesPassOnTheSkinnedQuad)
{
  gltftest::Builder b = gltftest::SkinnedQuad();
  b.Doc["extensions"]["VRMC_vrm"] = { { "specVersion", "1.0" },
    { "humanoid", { { "humanBones", { { "leftEye", { { "node", 2 } } } } } } } };
  b.Doc["extensionsUsed"] = { "VRMC_vrm" };
  const std::string path = morphnode_test::scenes::WriteFile("skin_filter_fused_quad.glb", b.Glb());
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkMorphNodeFilter> morph, fusedMorph;
  vtkNew<vtkMorphSkinFilter> skin, poser;
  for (vtkMorphNodeFilter* m : { morph.GetPointer(), fusedMorph.GetPointer() })
  {
    m->SetInputConnection(reader->GetOutputPort());
    m->SetWeightModeToRelative();
    m->SetWeightByName("Up", 1.0);
  }
  skin->SetInputConnection(morph->GetOutputPort());
  fusedMorph->SetPoseFilter(poser);
  for (const bool skinPoints : { true, false })
  {
    SCOPED_TRACE(skinPoints ? "re-skinned" : "posed only");
    for (vtkMorphSkinFilter* s : { skin.GetPointer(), poser.GetPointer() })
    {
      s->SetSkinPoints(skinPoints);
      s->SetEyeYaw(30.0);
    }
    ASSERT_EQ(skin->GetExecutive()->Update(), 1);
    ASSERT_EQ(fusedMorph->GetExecutive()->Update(), 1);
    const auto a = Parts(skin->GetOutputDataObject(0));
    const auto c = Parts(fusedMorph->GetOutputDataObject(0));
    ExpectSameParts(a, c);
    ExpectSameReports(skin, poser);
    EXPECT_EQ(poser->GetNumberOfCPUSkinnedParts(), skinPoints ? 0 : 1);
    // p2, bound to the eye joint alone, moved; the morph node's own arrays were not written.
    const auto morphed = Parts(morph->GetOutputDataObject(0));
    double p[3], q[3];
    morphed.begin()->second->GetPoint(2, p);
    c.begin()->second->GetPoint(2, q);
    EXPECT_GT(std::abs(p[0] - q[0]) + std::abs(p[2] - q[2]), 0.1);
  }

  vtkNew<vtkEyeGazeFilter> gaze;
  fusedMorph->SetPoseFilter(gaze);
  testing::internal::CaptureStderr();
  EXPECT_EQ(fusedMorph->GetExecutive()->Update(), 0);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("cannot move parts inside another filter's pass"), std::string::npos) << err;
  EXPECT_NE(err.find("the pose filter (vtkEyeGazeFilter) failed"), std::string::npos) << err;
  EXPECT_TRUE(Parts(fusedMorph->GetOutputDataObject(0)).empty());
}
