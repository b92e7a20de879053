// SPDX-License-Identifier: BSD-3-Clause
// glTF animations in vtkMorphTargetReader: default weights, the animations listed after
// UpdateInformation, TIME_STEPS on both ports, the weights table at UPDATE_TIME_STEP, the
// animated geometry (ApplyAnimation), bad choices as clear errors; and the cross-check
// against VTK 9.1's own vtkGLTFReader (ApplyDeformationsToGeometry, EnableAnimation,
// UpdateTimeStep) on a small head made here: weights LINEAR, STEP and CUBICSPLINE (with
// non-zero tangents), node translation LINEAR, rotation LINEAR (slerp), scale CUBICSPLINE,
// the eye's rotation STEP. Points agree within 1e-6 at every time tried, between keys and
// outside them, except where VTK 9.1 departs from the glTF specification:
//  - STEP at a key time t_k (k >= 1): VTK still shows key k-1 (it switches just after the
//    key); the spec (t_k <= t < t_k+1) shows key k. Both agree strictly between keys.
//  - VTK 9.1 crashes (out-of-bounds memcpy in Sampler::GetInterpolatedData) when a weights
//    channel animates a mesh that has no `weights` array: the generated head gives every
//    mesh with targets its `weights`. VTK also refuses an animation input accessor without
//    `min`/`max` (the spec requires them).

#include "Core/gltf/GltfAnimatedTestFiles.h"
#include "MorphNodeTestUtilities.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphTargetReader.h"

#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkGLTFReader.h"
#include "vtkInformation.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace
{
using namespace gltftest;
using morphnode_test::MessageCollector;

/// Writes into a folder of the running test's own: ctest runs each test as a process of its
/// own, in parallel, and two of them must not write the same file at once.
std::string WriteHead(const std::string& name, const std::string& bytes)
{
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path folder = std::filesystem::path(MORPHNODE_TEST_OUTPUT_DIR) /
    "GltfAnimationCrossCheck" / (std::string(test->test_suite_name()) + "." + test->name());
  std::filesystem::create_directories(folder);
  const std::string file = (folder / name).string();
  std::ofstream(file, std::ios::binary) << bytes;
  return file;
}

std::string HeadFile()
{
  return WriteHead("animated_head.glb", AnimatedHead().Glb());
}

std::vector<vtkPolyData*> Leaves(vtkDataObject* data)
{
  std::vector<vtkPolyData*> leaves;
  auto* composite = vtkCompositeDataSet::SafeDownCast(data);
  if (!composite)
  {
    return leaves;
  }
  for (vtkPolyData* poly : vtkCompositeDataSet::GetDataSets<vtkPolyData>(composite))
  {
    leaves.push_back(poly);
  }
  return leaves;
}

double Column(vtkTable* table, const char* name, int component = 0)
{
  vtkAbstractArray* column = table->GetColumnByName(name);
  auto* values = vtkDataArray::SafeDownCast(column);
  EXPECT_NE(values, nullptr) << name;
  return values ? values->GetComponent(0, component) : std::nan("");
}

double MaxDifference(vtkPolyData* a, vtkPolyData* b)
{
  EXPECT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  double worst = 0;
  for (vtkIdType i = 0; i < std::min(a->GetNumberOfPoints(), b->GetNumberOfPoints()); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    for (int k = 0; k < 3; ++k)
    {
      worst = std::max(worst, std::abs(p[k] - q[k]));
    }
  }
  return worst;
}

/// VTK's reader with its animation `index` applied to the geometry at `t`.
struct VtkReader
{
  vtkNew<vtkGLTFReader> Reader;
  explicit VtkReader(int index)
  {
    this->Reader->SetFileName(HeadFile().c_str());
    this->Reader->SetApplyDeformationsToGeometry(true);
    this->Reader->UpdateInformation();
    this->Reader->EnableAnimation(index);
  }
  std::vector<vtkPolyData*> At(double t)
  {
    this->Reader->UpdateTimeStep(t);
    return Leaves(this->Reader->GetOutputDataObject(0));
  }
};

/// Our reader with its animation `index`, applied per `apply`.
struct OurReader
{
  vtkNew<vtkMorphTargetReader> Reader;
  OurReader(int index, int apply)
  {
    this->Reader->SetFileName(HeadFile().c_str());
    this->Reader->SetAnimationIndex(index);
    this->Reader->SetApplyAnimation(apply);
  }
  std::vector<vtkPolyData*> At(double t)
  {
    this->Reader->UpdateTimeStep(t);
    return Leaves(this->Reader->GetOutputDataObject(0));
  }
};

/// Face weights recovered from a face's points (the targets move distinct coordinates:
/// blink alone moves point 3, smile alone point 1's x, jaw and smile point 1's y).
std::vector<double> FaceWeightsFromPoints(vtkPolyData* face, const double origin[3])
{
  double p1[3], p3[3];
  face->GetPoint(1, p1);
  face->GetPoint(3, p3);
  const double smile = (p1[0] - origin[0] - 0.5) / 0.1;
  const double jaw = (p1[1] - origin[1] + 0.5 - 0.05 * smile) / -0.2;
  const double blink = (p3[1] - origin[1] - 0.5) / -0.1;
  return { jaw, smile, blink };
}
} // namespace

TEST(GltfAnimationReader, DefaultWeightsWithoutAnimation)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(HeadFile().c_str());
  reader->UpdateInformation();
  EXPECT_EQ(reader->GetNumberOfAnimations(), 4);
  EXPECT_STREQ(reader->GetAnimationNameByIndex(2), "Cubic");
  EXPECT_EQ(reader->GetAnimationNameByIndex(4), nullptr);
  EXPECT_EQ(reader->GetChosenAnimation(), -1);
  EXPECT_FALSE(
    reader->GetOutputInformation(0)->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  EXPECT_FALSE(
    reader->GetOutputInformation(1)->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  reader->Update();
  const auto parts = Leaves(reader->GetOutputDataObject(0));
  ASSERT_EQ(parts.size(), 3u);
  auto* defaults = vtkDataArray::SafeDownCast(
    parts[0]->GetFieldData()->GetAbstractArray(vtkMorphPartData::DefaultWeightsArray));
  ASSERT_NE(defaults, nullptr);
  ASSERT_EQ(defaults->GetNumberOfTuples(), 3);
  EXPECT_DOUBLE_EQ(defaults->GetComponent(0, 0), 0.1);
  EXPECT_EQ(
    parts[0]->GetFieldData()->GetAbstractArray(vtkMorphPartData::AppliedWeightsArray), nullptr);
  // The rest pose, as the reader always gave it: points not morphed, transforms applied.
  double p[3];
  parts[0]->GetPoint(0, p);
  EXPECT_NEAR(p[1], 0.5, 1e-7);
  vtkTable* table = reader->GetWeightsOutput();
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(table->GetNumberOfRows(), 1);
  EXPECT_EQ(table->GetNumberOfColumns(), 3);
  EXPECT_DOUBLE_EQ(Column(table, "jawOpen"), 0.1);
  EXPECT_DOUBLE_EQ(Column(table, "smile"), 0.0);
}

TEST(GltfAnimationReader, TimeStepsAndWeightsTable)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(HeadFile().c_str());
  reader->SetAnimationName("Linear");
  reader->UpdateInformation();
  EXPECT_EQ(reader->GetChosenAnimation(), 0);
  EXPECT_DOUBLE_EQ(reader->GetAnimationEndTime(), 2.0);
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* info = reader->GetOutputInformation(port);
    ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
    ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 4);
    EXPECT_DOUBLE_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS())[2], 1.25);
    EXPECT_DOUBLE_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE())[1], 2.0);
  }
  reader->UpdateTimeStep(0.9);
  vtkTable* table = reader->GetWeightsOutput();
  // 0.9 in [0.5, 1.25]: u = 0.4/0.75 between (0.8, 0.5, 0.1) and (0.3, 1, 0.9).
  const double u = 0.4 / 0.75;
  EXPECT_NEAR(Column(table, "jawOpen"), 0.8 + u * (0.3 - 0.8), 1e-7);
  EXPECT_NEAR(Column(table, "smile"), 0.5 + u * 0.5, 1e-7);
  EXPECT_NEAR(Column(table, "eyeBlinkLeft"), 0.1 + u * 0.8, 1e-7);
  auto* time = vtkDataArray::SafeDownCast(table->GetFieldData()->GetAbstractArray("Time"));
  ASSERT_NE(time, nullptr);
  EXPECT_DOUBLE_EQ(time->GetComponent(0, 0), 0.9);
  EXPECT_DOUBLE_EQ(table->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 0.9);
  // A regular grid when asked: 0, 0.1, ..., 2.
  reader->SetFrameRate(10);
  reader->UpdateInformation();
  EXPECT_EQ(
    reader->GetOutputInformation(1)->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 21);
  // Node transforms of the pose animation as columns.
  reader->SetAnimationName("Pose");
  reader->UpdateTimeStep(0.25);
  table = reader->GetWeightsOutput();
  EXPECT_NEAR(Column(table, "Head.translation", 0), 0.05, 1e-7);
  EXPECT_NEAR(2 * std::atan2(Column(table, "Head.rotation", 1), Column(table, "Head.rotation", 3)) *
      180 / M_PI,
    20.0, 1e-5);
  EXPECT_NE(table->GetColumnByName("EyeLeft.rotation"), nullptr);
  EXPECT_NE(table->GetColumnByName("Head.scale"), nullptr);
  EXPECT_EQ(table->GetColumnByName("Teeth.rotation"), nullptr);
}

TEST(GltfAnimationReader, BadChoicesAreClearErrors)
{
  vtkNew<vtkMorphTargetReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetFileName(HeadFile().c_str());
  reader->SetAnimationName("Talk");
  EXPECT_EQ(reader->GetExecutive()->Update(), 0);
  EXPECT_TRUE(
    messages->HasError("has no animation named 'Talk'; animations: Linear Step Cubic Pose"))
    << messages->AllErrors();
  EXPECT_EQ(Leaves(reader->GetOutputDataObject(0)).size(), 0u);
  EXPECT_EQ(reader->GetWeightsOutput()->GetNumberOfColumns(), 0);
  messages->Clear();
  reader->SetAnimationName(nullptr);
  reader->SetAnimationIndex(9);
  EXPECT_EQ(reader->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("animation index 9 out of range")) << messages->AllErrors();
  // A damaged animation: the file's error, naming the JSON pointer; nothing partial.
  Builder b = AnimatedHead();
  json doc = b.Finished();
  doc["animations"][3]["channels"][3]["target"]["node"] = 7;
  reader->SetFileName(
    WriteHead("bad_channel.glb", Builder::MakeGlb(doc.dump(), b.PaddedBin())).c_str());
  reader->SetAnimationIndex(3);
  messages->Clear();
  EXPECT_EQ(reader->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("/animations/3/channels/3/target/node: there is no node 7"))
    << messages->AllErrors();
  EXPECT_EQ(Leaves(reader->GetOutputDataObject(0)).size(), 0u);
  EXPECT_EQ(reader->GetNumberOfAnimations(), 0);
}

TEST(GltfAnimationCrossCheck, LinearWeightsAgreeWithVtkGltfReaderAtAnyTime)
{
  VtkReader vtk(0);
  OurReader ours(0, vtkMorphTargetReader::ANIMATION_TRANSFORMS_AND_WEIGHTS);
  // The weights through the table and vtkMorphNodeFilter (glTF's relative blend).
  vtkNew<vtkMorphTargetReader> rest;
  rest->SetFileName(HeadFile().c_str());
  rest->SetAnimationIndex(0);
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(rest->GetOutputPort(0));
  morph->SetWeightsConnection(rest->GetOutputPort(1));
  morph->SetWeightModeToRelative();
  morph->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_NONE);
  const double headOrigin[3] = { 0, 1, 0 };
  for (double t : { 0.0, 0.1, 0.3, 0.5, 0.77, 1.0, 1.25, 1.6, 2.0, 2.5 })
  {
    const auto theirs = vtk.At(t);
    const auto mine = ours.At(t);
    ASSERT_EQ(theirs.size(), 3u);
    ASSERT_EQ(mine.size(), 3u);
    for (size_t p = 0; p < 3; ++p)
    {
      EXPECT_LT(MaxDifference(mine[p], theirs[p]), 1e-6) << "t " << t << " part " << p;
    }
    morph->UpdateTimeStep(t);
    const auto blended = Leaves(morph->GetOutputDataObject(0));
    ASSERT_EQ(blended.size(), 3u);
    for (size_t p = 0; p < 3; ++p)
    {
      EXPECT_LT(MaxDifference(blended[p], theirs[p]), 1e-6)
        << "morph filter, t " << t << " part " << p;
    }
    // The weights themselves: the table against the weights VTK's geometry shows.
    const std::vector<double> vtkWeights = FaceWeightsFromPoints(theirs[0], headOrigin);
    vtkTable* table = rest->GetWeightsOutput();
    EXPECT_NEAR(Column(table, "jawOpen"), vtkWeights[0], 1e-6) << t;
    EXPECT_NEAR(Column(table, "smile"), vtkWeights[1], 1e-6) << t;
    EXPECT_NEAR(Column(table, "eyeBlinkLeft"), vtkWeights[2], 1e-6) << t;
  }
}

TEST(GltfAnimationCrossCheck, CubicSplineAgreesAtAnyTime)
{
  const double headOrigin[3] = { 0, 1, 0 };
  VtkReader vtk(2);
  OurReader ours(2, vtkMorphTargetReader::ANIMATION_TRANSFORMS_AND_WEIGHTS);
  for (double t : { -0.5, 0.0, 0.1, 0.25, 0.5, 0.8, 1.0, 1.25, 1.6, 1.99, 2.0, 3.0 })
  {
    const auto theirs = vtk.At(t);
    const auto mine = ours.At(t);
    ASSERT_EQ(theirs.size(), 3u);
    ASSERT_EQ(mine.size(), 3u);
    EXPECT_LT(MaxDifference(mine[0], theirs[0]), 1e-6) << "t " << t;
    auto* applied = vtkDataArray::SafeDownCast(
      mine[0]->GetFieldData()->GetAbstractArray(vtkMorphPartData::AppliedWeightsArray));
    ASSERT_NE(applied, nullptr);
    const std::vector<double> vtkWeights = FaceWeightsFromPoints(theirs[0], headOrigin);
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_NEAR(applied->GetComponent(k, 0), vtkWeights[static_cast<size_t>(k)], 1e-6)
        << "t " << t;
    }
  }
  // Between keys the spline is not the straight line: the tangents count.
  const auto mine = ours.At(0.8);
  auto* applied = vtkDataArray::SafeDownCast(
    mine[0]->GetFieldData()->GetAbstractArray(vtkMorphPartData::AppliedWeightsArray));
  EXPECT_GT(std::abs(applied->GetComponent(1, 0) - (0.5 + 0.4 * 0.5)), 0.01);
}

TEST(GltfAnimationCrossCheck, StepAgreesBetweenTheKeys)
{
  const double headOrigin[3] = { 0, 1, 0 };
  VtkReader vtk(1);
  OurReader ours(1, vtkMorphTargetReader::ANIMATION_TRANSFORMS_AND_WEIGHTS);
  for (double t : { 0.0, 0.1, 0.4999, 0.5001, 0.8, 1.2499, 1.2501, 1.9, 1.9999 })
  {
    const auto theirs = vtk.At(t);
    const auto mine = ours.At(t);
    ASSERT_EQ(theirs.size(), 3u);
    ASSERT_EQ(mine.size(), 3u);
    EXPECT_LT(MaxDifference(mine[0], theirs[0]), 1e-6) << "t " << t;
  }
  // At a key time VTK 9.1 still shows the key before (see the top of this file): shown, so
  // that a VTK that follows the spec is noticed.
  const auto theirs = vtk.At(0.5);
  const auto mine = ours.At(0.5);
  const std::vector<double> vtkWeights = FaceWeightsFromPoints(theirs[0], headOrigin);
  EXPECT_NEAR(vtkWeights[1], AnimatedFaceWeights()[1], 1e-6) << "VTK: key 0";
  auto* applied = vtkDataArray::SafeDownCast(
    mine[0]->GetFieldData()->GetAbstractArray(vtkMorphPartData::AppliedWeightsArray));
  ASSERT_NE(applied, nullptr);
  EXPECT_NEAR(applied->GetComponent(1, 0), AnimatedFaceWeights()[4], 1e-6) << "spec: key 1";
}

TEST(GltfAnimationCrossCheck, NodeTransformsAgreeAtAnyTime)
{
  VtkReader vtk(3);
  // VTK blends the default weights (the face's jawOpen 0.1) into the geometry as well.
  OurReader ours(3, vtkMorphTargetReader::ANIMATION_TRANSFORMS_AND_WEIGHTS);
  OurReader transformsOnly(3, vtkMorphTargetReader::ANIMATION_TRANSFORMS);
  for (double t : { -1.0, 0.0, 0.1, 0.25, 0.4999, 0.5, 0.8, 1.0, 1.25, 1.5, 1.9999, 2.0, 4.0 })
  {
    const auto theirs = vtk.At(t);
    const auto mine = ours.At(t);
    ASSERT_EQ(theirs.size(), 3u);
    ASSERT_EQ(mine.size(), 3u);
    // The head (translation, slerped rotation, CUBICSPLINE scale) and the teeth below it.
    EXPECT_LT(MaxDifference(mine[0], theirs[0]), 1e-6) << "t " << t;
    EXPECT_LT(MaxDifference(mine[1], theirs[1]), 1e-6) << "t " << t;
    // The eye turns by STEP: equal but at its keys 0.5, 1.25 and 2 (VTK's STEP quirk).
    const bool stepKey = t == 0.5 || t == 1.25 || t == 2.0;
    // Without the weights: the same eye (it has no targets); the face without its 0.1 jawOpen
    // (0.02 m at rest scale).
    const auto unweighted = transformsOnly.At(t);
    EXPECT_GT(MaxDifference(unweighted[0], mine[0]), 0.015) << "t " << t;
    EXPECT_LT(MaxDifference(unweighted[2], mine[2]), 1e-12) << "t " << t;
    if (!stepKey)
    {
      EXPECT_LT(MaxDifference(mine[2], theirs[2]), 1e-6) << "t " << t;
    }
  }
  // The part's frame follows: the head's origin is its animated translation.
  const auto mine = ours.At(0.9);
  auto* origin = vtkDataArray::SafeDownCast(
    mine[0]->GetFieldData()->GetAbstractArray(vtkMorphPartData::NodeOriginArray));
  ASSERT_NE(origin, nullptr);
  const double u = 0.4 / 0.75;
  EXPECT_NEAR(origin->GetComponent(0, 1), 1.2 + u * (0.9 - 1.2), 1e-6);
}
