// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphNodeFilter on a whole head (a composite of parts, each with its own targets):
// weights by name reach every part that has the target and no other, the optimizer decides
// once for all parts exactly as for one mesh holding them all, distance arrays per part,
// other composite types, bad parts.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeMergeParts.h"
#include "MorphNodeTestScenes.h"
#include "MorphNodeTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataAssembly.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>

using morphnode_test::MessageCollector;
using namespace morphnode_test::scenes;

namespace
{
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
const std::string DefaultHead =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";

vtkSmartPointer<vtkPartitionedDataSetCollection> ReadHead(const std::string& file)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
}

std::vector<double> Values(vtkFieldData* fd, const char* name)
{
  std::vector<double> values;
  vtkDataArray* a = fd->GetArray(name);
  for (vtkIdType i = 0; a && i < a->GetNumberOfTuples(); ++i)
  {
    values.push_back(a->GetComponent(i, 0));
  }
  return values;
}

/// A new collection holding the same parts (with their names).
vtkSmartPointer<vtkPartitionedDataSetCollection> CopyOf(vtkPartitionedDataSetCollection* head)
{
  auto copy = vtkSmartPointer<vtkPartitionedDataSetCollection>::New();
  for (unsigned int i = 0; i < head->GetNumberOfPartitionedDataSets(); ++i)
  {
    copy->SetPartition(i, 0, head->GetPartition(i, 0));
    copy->GetMetaData(i)->Set(
      vtkCompositeDataSet::NAME(), head->GetMetaData(i)->Get(vtkCompositeDataSet::NAME()));
  }
  return copy;
}

/// The head's extent: the diagonal of its bounds.
double Size(vtkPolyData* merged)
{
  double b[6];
  merged->GetBounds(b);
  return std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
}

/// Runs the same weights and settings on the head as parts and on the head as one mesh, and
/// checks that every decision and every point agree. Returns how many targets the
/// optimizer pruned over all frames (a test that prunes nothing proves nothing).
int CompareWithOneMesh(vtkPartitionedDataSetCollection* head, const std::string& what)
{
  auto merged = morphnode_test::MergeParts(head);
  const double size = Size(merged);
  vtkNew<vtkMorphNodeFilter> parts, one;
  parts->SetInputData(head);
  one->SetInputData(merged);
  for (vtkMorphNodeFilter* f : { parts.GetPointer(), one.GetPointer() })
  {
    f->SetWeightModeToRelative();
    f->GenerateDistanceArraysOn();
  }
  parts->Update();
  one->Update();
  const int n = one->GetNumberOfTargets();
  EXPECT_EQ(parts->GetNumberOfTargets(), n) << what;
  for (int i = 0; i < n; ++i)
  {
    EXPECT_STREQ(parts->GetTargetName(i), one->GetTargetName(i)) << what;
    EXPECT_NEAR(parts->GetDistNorm()->GetValue(i), one->GetDistNorm()->GetValue(i), 1e-12)
      << what << " " << i;
  }
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int pruned = 0;
  struct Setting
  {
    int Preset;
    double Threshold, MaxError;
    int Budget;
    double Hysteresis;
  };
  const Setting settings[] = { { vtkMorphNodeFilter::OPTIMIZER_FIXED_MAXIMUM, 0.15, 0, 0, 0 },
    { vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING, 0.15, 0, 0, 0.3 },
    { vtkMorphNodeFilter::OPTIMIZER_ADJUSTED, 0.3, 0, 0, 0 },
    { vtkMorphNodeFilter::OPTIMIZER_ERROR_BOUNDED, 0, 0.002 * size, 0, 0 },
    { vtkMorphNodeFilter::OPTIMIZER_ADJUSTED, 0.2, 0, 3, 0.2 },
    { vtkMorphNodeFilter::OPTIMIZER_NONE, 0, 0, 4, 0 } };
  for (const Setting& s : settings)
  {
    for (vtkMorphNodeFilter* f : { parts.GetPointer(), one.GetPointer() })
    {
      f->SetOptimizerPreset(s.Preset);
      f->SetThreshold(s.Threshold);
      f->SetMaxVertexError(s.MaxError);
      f->SetMaxActiveTargets(s.Budget);
      f->SetHysteresis(s.Hysteresis);
      f->ResetHysteresis();
    }
    for (int frame = 0; frame < 6; ++frame)
    {
      // A few targets strongly, many weakly: something to prune.
      for (int i = 1; i < n; ++i)
      {
        const double w = u(rng) < 0.2 ? u(rng) : 0.3 * u(rng) * u(rng);
        parts->SetWeight(i, w);
        one->SetWeight(i, w);
      }
      if (parts->GetExecutive()->Update() != 1 || one->GetExecutive()->Update() != 1)
      {
        ADD_FAILURE() << what << ": an update failed";
        return pruned;
      }
      std::vector<double> a(static_cast<size_t>(n)), b(static_cast<size_t>(n));
      for (int i = 0; i < n; ++i)
      {
        a[static_cast<size_t>(i)] = parts->GetEffectiveWeight(i);
        b[static_cast<size_t>(i)] = one->GetEffectiveWeight(i);
      }
      EXPECT_EQ(a, b) << what << ": preset " << s.Preset << " frame " << frame;
      EXPECT_EQ(parts->GetErrorBound(), one->GetErrorBound()) << what;
      EXPECT_EQ(parts->GetActiveTargetCount(), one->GetActiveTargetCount()) << what;
      pruned += n - 1 - one->GetActiveTargetCount();

      // The same points, part by part, and the same field data in every part.
      auto* whole = vtkPolyData::SafeDownCast(one->GetOutputDataObject(0));
      vtkIdType offset = 0;
      double worst = 0.0;
      for (vtkPolyData* leaf : morphnode_test::PolyDataLeaves(parts->GetOutputDataObject(0)))
      {
        for (vtkIdType i = 0; i < leaf->GetNumberOfPoints(); ++i)
        {
          double p[3], q[3];
          leaf->GetPoint(i, p);
          whole->GetPoint(offset + i, q);
          for (int c = 0; c < 3; ++c)
          {
            worst = std::max(worst, std::abs(p[c] - q[c]));
          }
        }
        offset += leaf->GetNumberOfPoints();
        EXPECT_EQ(Values(leaf->GetFieldData(), "EffectiveWeights"), b);
        EXPECT_EQ(Values(leaf->GetFieldData(), "ActiveTargetCount"),
          std::vector<double>{ double(one->GetActiveTargetCount()) });
      }
      EXPECT_EQ(offset, whole->GetNumberOfPoints());
      EXPECT_LE(worst, 1e-6 * size) << what << ": points of the parts against the one mesh";
    }
  }
  return pruned;
}
} // namespace

TEST(MorphNodeScene, WeightsByNameReachEveryPartThatHasTheTarget)
{
  auto head = ReadHead(WriteFile("scene_head.glb", TestHead().Glb()));
  ASSERT_TRUE(head && head->GetNumberOfPartitionedDataSets() == 4);
  vtkNew<vtkMorphNodeFilter> morph;
  vtkNew<MessageCollector> messages;
  messages->Watch(morph);
  morph->SetInputData(head);
  EXPECT_EQ(morph->GetNumberOfTargets(), 3) << "Neutral, Lift, Raise: known before the update";
  morph->SetWeightModeToRelative();
  morph->SetWeightByName("Raise", 0.5);
  morph->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  auto* out = vtkPartitionedDataSetCollection::SafeDownCast(morph->GetOutputDataObject(0));
  ASSERT_NE(out, nullptr) << "the output has the input's type";
  EXPECT_EQ(morph->GetOutput(), nullptr);
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), 4u);
  EXPECT_STREQ(out->GetMetaData(2u)->Get(vtkCompositeDataSet::NAME()), "Tooth");
  ASSERT_NE(out->GetDataAssembly(), nullptr);
  EXPECT_EQ(out->GetDataAssembly()->FindFirstNodeWithName("Tooth"),
    head->GetDataAssembly()->FindFirstNodeWithName("Tooth"));
  const std::vector<vtkPolyData*> in = morphnode_test::PolyDataLeaves(head);
  std::vector<vtkPolyData*> blended = morphnode_test::PolyDataLeaves(out);
  ASSERT_EQ(blended.size(), 4u);

  // Raise: the skin's primitives (sparse delta at point 2) and the tooth (points 0, 1) move;
  // the eye, without targets, does not.
  auto moved = [&](size_t part, vtkIdType point, const Vec3& delta)
  {
    double a[3], b[3];
    in[part]->GetPoint(point, a);
    blended[part]->GetPoint(point, b);
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_NEAR(b[c] - a[c], delta[static_cast<size_t>(c)], 1e-6)
        << "part " << part << " point " << point;
    }
  };
  const Vec3 raiseSkin = JawDelta({ 0, 0.25, 0 }), raiseTooth = JawDelta({ 0.15, 0, 0 });
  moved(0, 2, raiseSkin);
  moved(1, 2, raiseSkin);
  moved(0, 3, { 0, 0, 0 });
  moved(2, 0, raiseTooth);
  moved(2, 3, { 0, 0, 0 });
  moved(3, 1, { 0, 0, 0 });
  EXPECT_EQ(blended[3]->GetPoints(), in[3]->GetPoints()) << "the eye passes through unblended";
  EXPECT_NE(blended[3]->GetPointData()->GetArray("COLOR_0"), nullptr) << "its colours pass";

  // Lift: only the skin; the tooth lacks it and is not moved, not an error.
  morph->SetWeightByName("Raise", 0.0);
  morph->SetWeightByName("Lift", 1.0);
  morph->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  blended = morphnode_test::PolyDataLeaves(morph->GetOutputDataObject(0));
  moved(1, 3, JawDelta({ 0, 0, 0.4 }));
  moved(2, 0, { 0, 0, 0 });
  EXPECT_EQ(blended[2]->GetPoints(), in[2]->GetPoints()) << "no active target moves the tooth";
  EXPECT_EQ(morph->GetActiveTargetCount(), 1);

  // Every part holds the same decision and the model's names; no target arrays pass.
  for (vtkPolyData* leaf : blended)
  {
    EXPECT_EQ(morphnode_test::FieldStrings(leaf->GetFieldData(), "TargetNames"),
      (std::vector<std::string>{ "Neutral", "Lift", "Raise" }));
    EXPECT_EQ(Values(leaf->GetFieldData(), "EffectiveWeights"), (std::vector<double>{ 0, 1, 0 }));
    EXPECT_EQ(leaf->GetPointData()->GetArray("target0_position"), nullptr);
    EXPECT_NE(leaf->GetPointData()->GetNormals(), nullptr);
    EXPECT_EQ(
      morphnode_test::FieldStrings(leaf->GetFieldData(), vtkMorphPartData::PartNameArray).size(),
      1u)
      << "the part's own field data passes";
  }
  // An unknown name is still an error.
  morph->SetWeightByName("Blink", 0.3);
  EXPECT_EQ(morph->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("no target has that name; targets: Neutral Lift Raise"))
    << messages->AllErrors();
}

TEST(MorphNodeScene, DistanceArraysPerPart)
{
  auto head = ReadHead(WriteFile("scene_head_distances.glb", TestHead().Glb()));
  ASSERT_TRUE(head);
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputData(head);
  morph->GenerateDistanceArraysOn();
  morph->Update();
  const std::vector<vtkPolyData*> leaves =
    morphnode_test::PolyDataLeaves(morph->GetOutputDataObject(0));
  ASSERT_EQ(leaves.size(), 4u);
  for (vtkPolyData* leaf : leaves)
  {
    for (const char* name : { "AnimatedRegion", "Distance_Lift", "Distance_Raise" })
    {
      ASSERT_NE(leaf->GetPointData()->GetArray(name), nullptr) << name;
      EXPECT_EQ(leaf->GetPointData()->GetArray(name)->GetNumberOfTuples(), 4);
    }
    EXPECT_EQ(Values(leaf->GetFieldData(), "DistNorm").size(), 3u);
  }
  // The skin's lift at point 3: 0.4 in the file, times the head's scale 2.
  EXPECT_NEAR(leaves[0]->GetPointData()->GetArray("Distance_Lift")->GetComponent(3, 0), 0.8, 1e-6);
  EXPECT_EQ(leaves[2]->GetPointData()->GetArray("Distance_Lift")->GetRange()[1], 0.0)
    << "the tooth has no Lift";
  EXPECT_NEAR(leaves[2]->GetPointData()->GetArray("Distance_Raise")->GetComponent(0, 0), 0.6, 1e-6);
  EXPECT_NEAR(leaves[2]->GetPointData()->GetArray("AnimatedRegion")->GetComponent(0, 0), 0.6, 1e-6);
  EXPECT_EQ(leaves[3]->GetPointData()->GetArray("AnimatedRegion")->GetRange()[1], 0.0) << "the eye";
  // DistNorm over the whole head: Lift moves 2 x (0.2+0.4+0.6+0.8) = 4 in all, Raise 2 x 1 +
  // 0.6 + 0.6 = 3.2.
  const std::vector<double> distNorm = Values(leaves[1]->GetFieldData(), "DistNorm");
  EXPECT_NEAR(distNorm[1], 1.0, 1e-6);
  EXPECT_NEAR(distNorm[2], 3.2 / 4.0, 1e-6);
}

TEST(MorphNodeScene, DefaultHeadDecidesAsOneMesh)
{
  auto head = ReadHead(DefaultHead);
  ASSERT_TRUE(head);
  const int pruned = CompareWithOneMesh(head, "default head");
  EXPECT_GT(pruned, 30);
}

TEST(MorphNodeScene, IctHeadDecidesAsOneMesh)
{
  if (!std::ifstream(IctHead))
  {
    GTEST_SKIP() << "ICT-FaceKit head not found at " << IctHead;
  }
  auto head = ReadHead(IctHead);
  ASSERT_TRUE(head);
  const int pruned = CompareWithOneMesh(head, "ICT head");
  EXPECT_GT(pruned, 100);
}

TEST(MorphNodeScene, OnePartIsThePolyData)
{
  // The same mesh as a polydata and as the only part of a collection: the same output.
  auto head = ReadHead(WriteFile("scene_one_part.glb", TestHead().Glb()));
  ASSERT_TRUE(head);
  vtkPolyData* skin = morphnode_test::PolyDataLeaves(head)[0];
  vtkNew<vtkPartitionedDataSetCollection> single;
  single->SetPartition(0, 0, skin);
  vtkNew<vtkMorphNodeFilter> a, b;
  a->SetInputData(skin);
  b->SetInputData(single);
  for (vtkMorphNodeFilter* f : { a.GetPointer(), b.GetPointer() })
  {
    f->SetWeightModeToRelative();
    f->SetWeightByName("Lift", 0.3);
    f->SetWeightByName("Raise", 0.6);
    f->SetThreshold(0.35);
    f->Update();
  }
  auto* pa = vtkPolyData::SafeDownCast(a->GetOutputDataObject(0));
  vtkPolyData* pb = morphnode_test::PolyDataLeaves(b->GetOutputDataObject(0))[0];
  ASSERT_TRUE(pa && pb);
  EXPECT_EQ(a->GetEffectiveWeight(1), 0.0) << "the threshold prunes Lift";
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_EQ(a->GetEffectiveWeight(i), b->GetEffectiveWeight(i));
  }
  for (vtkIdType i = 0; i < 4; ++i)
  {
    double p[3], q[3];
    pa->GetPoint(i, p);
    pb->GetPoint(i, q);
    EXPECT_TRUE(p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) << i;
  }
}

TEST(MorphNodeScene, MultiBlockInputGivesMultiBlockOutput)
{
  auto head = ReadHead(WriteFile("scene_multiblock.glb", TestHead().Glb()));
  ASSERT_TRUE(head);
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(3);
  blocks->SetBlock(0, morphnode_test::PolyDataLeaves(head)[0]);
  blocks->SetBlock(2, morphnode_test::PolyDataLeaves(head)[2]); // block 1 stays empty
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputData(blocks);
  morph->SetWeightModeToRelative();
  morph->SetWeightByName("Raise", 1.0);
  morph->Update();
  auto* out = vtkMultiBlockDataSet::SafeDownCast(morph->GetOutputDataObject(0));
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(out->GetNumberOfBlocks(), 3u);
  EXPECT_EQ(out->GetBlock(1), nullptr);
  auto* tooth = vtkPolyData::SafeDownCast(out->GetBlock(2));
  ASSERT_NE(tooth, nullptr);
  double p[3], q[3];
  tooth->GetPoint(1, p);
  morphnode_test::PolyDataLeaves(head)[2]->GetPoint(1, q);
  EXPECT_NEAR(p[1] - q[1], JawDelta({ 0.3, 0, 0 })[1], 1e-6);
}

TEST(MorphNodeScene, BadPartsAreErrorsThatNameThePart)
{
  auto head = ReadHead(WriteFile("scene_bad.glb", TestHead().Glb()));
  ASSERT_TRUE(head);
  vtkNew<vtkMorphNodeFilter> morph;
  vtkNew<MessageCollector> messages;
  messages->Watch(morph);

  // A part whose target has fewer tuples than the part has points.
  auto bad = CopyOf(head);
  vtkNew<vtkPolyData> tooth;
  tooth->DeepCopy(morphnode_test::PolyDataLeaves(head)[2]);
  vtkNew<vtkFloatArray> shortDelta;
  shortDelta->SetName("target0_position");
  shortDelta->SetNumberOfComponents(3);
  shortDelta->SetNumberOfTuples(3);
  shortDelta->Fill(0.1);
  tooth->GetPointData()->AddArray(shortDelta);
  bad->SetPartition(2, 0, tooth);
  morph->SetInputData(bad);
  EXPECT_EQ(morph->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("part 'Tooth': ")) << messages->AllErrors();
  EXPECT_TRUE(messages->HasError("target0_position")) << messages->AllErrors();
  auto* out = vtkPartitionedDataSetCollection::SafeDownCast(morph->GetOutputDataObject(0));
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->GetNumberOfPartitionedDataSets(), 0u) << "the output is empty";

  // A part that is no point set.
  messages->Clear();
  bad = CopyOf(head);
  vtkNew<vtkImageData> image;
  image->SetDimensions(2, 2, 2);
  bad->SetPartition(3, 0, image);
  morph->SetInputData(bad);
  EXPECT_EQ(morph->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("part 'EyeLeft' of the composite input is a vtkImageData"))
    << messages->AllErrors();

  // A part whose points and normals disagree in number.
  messages->Clear();
  bad = CopyOf(head);
  vtkNew<vtkPolyData> skin;
  skin->DeepCopy(morphnode_test::PolyDataLeaves(head)[0]);
  vtkNew<vtkFloatArray> fewNormals;
  fewNormals->SetName("Normals");
  fewNormals->SetNumberOfComponents(3);
  fewNormals->SetNumberOfTuples(2);
  fewNormals->Fill(0.0);
  skin->GetPointData()->SetNormals(fewNormals);
  bad->SetPartition(0, 0, skin);
  morph->SetInputData(bad);
  EXPECT_EQ(morph->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("part 'Jaw/Skin': ")) << messages->AllErrors();

  // Good again.
  messages->Clear();
  morph->SetInputData(head);
  EXPECT_EQ(morph->GetExecutive()->Update(), 1) << messages->AllErrors();
  EXPECT_EQ(morphnode_test::PolyDataLeaves(morph->GetOutputDataObject(0)).size(), 4u);
}
