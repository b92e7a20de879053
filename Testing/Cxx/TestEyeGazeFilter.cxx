// SPDX-License-Identifier: BSD-3-Clause
// vtkEyeGazeFilter: on the default head (and ICT-FaceKit's when present) the eyes turn
// rigidly about their centres (pairwise distances, the centre, the pupil towards the gaze
// within a degree), the limits clamp, every other part is passed on untouched and shared,
// the input is never modified; eyes by name, by a rig file's "eyes" section; one mesh and
// multiblock input; the gaze from a vtkBehaviorTimeSource at the requested time; MTime,
// PrintSelf and bad input.
#include "vtkBehaviorTimeSource.h"
#include "vtkEyeGazeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestUtilities.h"

#include "gaze/EyeRotation.h"

#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace
{
using Vec3 = std::array<double, 3>;
const std::string DefaultHead =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";

double AngleDegrees(const Vec3& a, const Vec3& b)
{
  const double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double n = std::sqrt(
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]));
  return std::acos(std::max(-1.0, std::min(1.0, d / n))) * 180.0 / M_PI;
}

std::string StringOf(vtkDataObject* leaf, const char* name)
{
  return vtkMorphPartData::GetString(leaf->GetFieldData(), name);
}

Vec3 OriginOf(vtkDataObject* leaf)
{
  Vec3 origin{ 0, 0, 0 };
  std::array<double, 9> axes{};
  vtkMorphPartData::GetNodeFrame(leaf->GetFieldData(), origin, axes);
  return origin;
}

/// The leaves of a composite by part name.
std::map<std::string, vtkPolyData*> Leaves(vtkDataObject* data)
{
  std::map<std::string, vtkPolyData*> leaves;
  auto* composite = vtkCompositeDataSet::SafeDownCast(data);
  if (!composite)
  {
    return leaves;
  }
  for (vtkPolyData* pd : vtkCompositeDataSet::GetDataSets<vtkPolyData>(composite))
  {
    leaves[StringOf(pd, vtkMorphPartData::PartNameArray)] = pd;
  }
  return leaves;
}

/// The mean of the points a predicate picks, from the eye's centre.
template <typename Pick>
Vec3 Direction(vtkPolyData* pd, const Vec3& origin, Pick pick)
{
  Vec3 sum{ 0, 0, 0 };
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    if (pick(pd, i))
    {
      double p[3];
      pd->GetPoint(i, p);
      for (int c = 0; c < 3; ++c)
      {
        sum[c] += p[c] - origin[c];
      }
    }
  }
  return sum;
}

/// The pupil's points: the whole Pupil part (default head), the dark COLOR_0 of the iris
/// (ICT-FaceKit).
bool IsPupil(vtkPolyData* pd, vtkIdType i)
{
  if (StringOf(pd, vtkMorphPartData::PartNameArray).find("Pupil") != std::string::npos)
  {
    return true;
  }
  vtkDataArray* colors = pd->GetPointData()->GetArray("COLOR_0");
  return colors &&
    StringOf(pd, vtkMorphPartData::PartNameArray).find("Iris") != std::string::npos &&
    colors->GetComponent(i, 0) < 0.2 * colors->GetDataTypeMax();
}

/// The gaze checks of the issue on every eye part of `out` against `in`: rigid (pairwise
/// distances of a sample of pairs), the centre fixed, the pupil towards the gaze (its rest
/// offset from +Z kept, which is under a degree on the default head). Returns the number of
/// eye parts; every other part must share its input's points.
int CheckGaze(vtkDataObject* inData, vtkDataObject* outData, const morphnode::GazeAngles& expected,
  double pupilTolerance)
{
  auto in = Leaves(inData);
  auto out = Leaves(outData);
  EXPECT_EQ(in.size(), out.size());
  int eyes = 0, pupils = 0;
  for (const auto& [name, inLeaf] : in)
  {
    vtkPolyData* outLeaf = out[name];
    if (!outLeaf)
    {
      ADD_FAILURE() << "no output part " << name;
      continue;
    }
    vtkDataArray* gaze = outLeaf->GetFieldData()->GetArray("EyeGaze");
    if (!gaze)
    {
      EXPECT_EQ(outLeaf->GetPoints(), inLeaf->GetPoints())
        << name << ": not an eye, must be shared";
      EXPECT_EQ(outLeaf->GetPointData()->GetNormals(), inLeaf->GetPointData()->GetNormals())
        << name;
      continue;
    }
    ++eyes;
    EXPECT_NE(outLeaf, inLeaf);
    EXPECT_NEAR(gaze->GetComponent(0, 0), expected.Yaw, 1e-12) << name;
    EXPECT_NEAR(gaze->GetComponent(1, 0), expected.Pitch, 1e-12) << name;
    const vtkIdType n = inLeaf->GetNumberOfPoints();
    EXPECT_EQ(outLeaf->GetNumberOfPoints(), n);
    EXPECT_EQ(outLeaf->GetPolys(), inLeaf->GetPolys()) << "the triangles are shared";
    const Vec3 origin = OriginOf(inLeaf);
    double worst = 0.0;
    for (vtkIdType i = 0; i < n; i += 5)
    {
      const vtkIdType j = (i * 37 + 11) % n;
      double a[3], b[3], c[3], d[3];
      inLeaf->GetPoint(i, a);
      inLeaf->GetPoint(j, b);
      outLeaf->GetPoint(i, c);
      outLeaf->GetPoint(j, d);
      worst = std::max(worst,
        std::abs(std::sqrt(vtkMath::Distance2BetweenPoints(a, b)) -
          std::sqrt(vtkMath::Distance2BetweenPoints(c, d))));
      // Every point keeps its distance from the centre.
      worst = std::max(worst,
        std::abs(std::sqrt(vtkMath::Distance2BetweenPoints(a, origin.data())) -
          std::sqrt(vtkMath::Distance2BetweenPoints(c, origin.data()))));
    }
    EXPECT_LT(worst, 1e-6) << name << ": not rigid about its centre (m)";
    // Normals turned with the points: the normal at a point keeps its angle to the radius.
    vtkDataArray* n0 = inLeaf->GetPointData()->GetNormals();
    vtkDataArray* n1 = outLeaf->GetPointData()->GetNormals();
    if (!n0 || !n1)
    {
      ADD_FAILURE() << name << ": no normals";
      continue;
    }
    EXPECT_NE(n0, n1);
    for (vtkIdType i = 0; i < n; i += 97)
    {
      double a[3], c[3];
      inLeaf->GetPoint(i, a);
      outLeaf->GetPoint(i, c);
      const Vec3 r0{ a[0] - origin[0], a[1] - origin[1], a[2] - origin[2] };
      const Vec3 r1{ c[0] - origin[0], c[1] - origin[1], c[2] - origin[2] };
      const Vec3 m0{ n0->GetComponent(i, 0), n0->GetComponent(i, 1), n0->GetComponent(i, 2) };
      const Vec3 m1{ n1->GetComponent(i, 0), n1->GetComponent(i, 1), n1->GetComponent(i, 2) };
      EXPECT_NEAR(AngleDegrees(r0, m0), AngleDegrees(r1, m1), 0.01) << name << " point " << i;
    }
    const Vec3 pupil0 = Direction(inLeaf, origin, IsPupil);
    if (pupil0[0] != 0.0 || pupil0[1] != 0.0 || pupil0[2] != 0.0)
    {
      ++pupils;
      const Vec3 pupil1 = Direction(outLeaf, origin, IsPupil);
      const Vec3 target = morphnode::GazeDirection(expected);
      const double rest = AngleDegrees(pupil0, { 0, 0, 1 });
      EXPECT_LT(rest, pupilTolerance) << name << ": the pupil at rest is off +Z";
      EXPECT_NEAR(AngleDegrees(pupil1, target), rest, 0.01) << name;
      EXPECT_LT(AngleDegrees(pupil1, target), pupilTolerance) << name << ": not towards the gaze";
    }
  }
  EXPECT_EQ(pupils, 2);
  return eyes;
}

vtkSmartPointer<vtkMorphTargetReader> Read(const std::string& file)
{
  auto reader = vtkSmartPointer<vtkMorphTargetReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader;
}

/// A copy of every point of a data object's leaves, to prove the input unchanged.
std::vector<double> AllPoints(vtkDataObject* data)
{
  std::vector<double> all;
  for (const auto& [name, leaf] : Leaves(data))
  {
    for (vtkIdType i = 0; i < leaf->GetNumberOfPoints(); ++i)
    {
      double p[3];
      leaf->GetPoint(i, p);
      all.insert(all.end(), p, p + 3);
    }
  }
  return all;
}
} // namespace

TEST(EyeGazeFilter, DefaultHeadEyesTurnRigidlyTowardsTheGaze)
{
  auto reader = Read(DefaultHead);
  vtkDataObject* head = reader->GetOutputDataObject(0);
  ASSERT_TRUE(vtkPartitionedDataSetCollection::SafeDownCast(head));
  const std::vector<double> before = AllPoints(head);
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(reader->GetOutputPort());
  for (const morphnode::GazeAngles a : { morphnode::GazeAngles{ 25.0, -10.0 },
         morphnode::GazeAngles{ -30.0, 15.0 }, morphnode::GazeAngles{ 0.0, 0.0 } })
  {
    gaze->SetEyeYaw(a.Yaw);
    gaze->SetEyePitch(a.Pitch);
    gaze->Update();
    vtkDataObject* out = gaze->GetOutputDataObject(0);
    ASSERT_TRUE(vtkPartitionedDataSetCollection::SafeDownCast(out));
    EXPECT_EQ(gaze->GetNumberOfEyeParts(), 6) << "EyeLeft and EyeRight: sclera, iris, pupil";
    EXPECT_EQ(CheckGaze(head, out, a, 1.0), 6);
    // The structure is kept: the names of the partitioned data sets and the assembly.
    auto* inCollection = vtkPartitionedDataSetCollection::SafeDownCast(head);
    auto* outCollection = vtkPartitionedDataSetCollection::SafeDownCast(out);
    ASSERT_EQ(outCollection->GetNumberOfPartitionedDataSets(),
      inCollection->GetNumberOfPartitionedDataSets());
    EXPECT_EQ(outCollection->GetDataAssembly(), inCollection->GetDataAssembly());
    for (unsigned int d = 0; d < inCollection->GetNumberOfPartitionedDataSets(); ++d)
    {
      EXPECT_STREQ(outCollection->GetMetaData(d)->Get(vtkCompositeDataSet::NAME()),
        inCollection->GetMetaData(d)->Get(vtkCompositeDataSet::NAME()));
    }
  }
  EXPECT_EQ(AllPoints(head), before) << "the input was modified";
}

TEST(EyeGazeFilter, SidesAndVergence)
{
  auto reader = Read(DefaultHead);
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(reader->GetOutputPort());
  gaze->SetEyeYaw(10.0);
  gaze->SetVergence(8.0);
  gaze->Update();
  std::map<std::string, double> yawOf;
  for (const auto& [name, leaf] : Leaves(gaze->GetOutputDataObject(0)))
  {
    if (vtkDataArray* a = leaf->GetFieldData()->GetArray("EyeGaze"))
    {
      yawOf[StringOf(leaf, "EyeSide")] = a->GetComponent(0, 0);
      EXPECT_EQ(StringOf(leaf, "EyeSide") == "left", OriginOf(leaf)[0] > 0.0) << name;
    }
  }
  EXPECT_EQ(yawOf["left"], 6.0) << "the left eye (+X) turns inward: towards -X";
  EXPECT_EQ(yawOf["right"], 14.0);
}

TEST(EyeGazeFilter, LimitsClamp)
{
  auto reader = Read(DefaultHead);
  vtkDataObject* head = reader->GetOutputDataObject(0);
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(reader->GetOutputPort());
  gaze->SetEyeYaw(80.0);
  gaze->SetEyePitch(-70.0);
  gaze->Update();
  EXPECT_EQ(CheckGaze(head, gaze->GetOutputDataObject(0), { 40.0, -35.0 }, 1.0), 6)
    << "default limits";
  gaze->SetEyeYaw(-80.0);
  gaze->SetEyePitch(70.0);
  gaze->Update();
  EXPECT_EQ(CheckGaze(head, gaze->GetOutputDataObject(0), { -40.0, 25.0 }, 1.0), 6);
  gaze->SetMaxEyeYaw(15.0);
  gaze->SetMaxEyeUp(5.0);
  gaze->Update();
  EXPECT_EQ(CheckGaze(head, gaze->GetOutputDataObject(0), { -15.0, 5.0 }, 1.0), 6) << "set limits";
  EXPECT_EQ(gaze->GetLastEyeYaw(), -80.0) << "the gaze asked for, before the limits";
}

TEST(EyeGazeFilter, FaceKitHead)
{
  if (!std::filesystem::exists(IctHead))
  {
    GTEST_SKIP() << "ICT-FaceKit head not found: " << IctHead;
  }
  auto reader = Read(IctHead);
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(reader->GetOutputPort());
  gaze->SetEyeYaw(-20.0);
  gaze->SetEyePitch(12.0);
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 4) << "EyeLeft and EyeRight: sclera and iris";
  // The ICT pupils are modelled 1.7 degrees outwards of +Z: within 2 of the gaze.
  EXPECT_EQ(
    CheckGaze(reader->GetOutputDataObject(0), gaze->GetOutputDataObject(0), { -20.0, 12.0 }, 2.0),
    4);
}

TEST(EyeGazeFilter, EyesByNameAndByRigFile)
{
  auto reader = Read(DefaultHead);
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(reader->GetOutputPort());
  gaze->SetEyeYaw(20.0);
  gaze->AddEyeName("EyeLeft");
  gaze->AddEyeName("EyeRight/Pupil");
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 4) << "a node's three parts and one part";
  EXPECT_EQ(gaze->GetNumberOfEyeNames(), 2);
  EXPECT_STREQ(gaze->GetEyeName(1), "EyeRight/Pupil");
  EXPECT_EQ(gaze->GetEyeName(2), nullptr);
  gaze->RemoveAllEyeNames();
  gaze->AddEyeName("NoSuchNode");
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 0) << "named eyes turn the convention off";

  // A rig file's eyes: the right eye only, 10 degrees at most.
  const std::string rigFile =
    std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/TestEyeGazeFilter_rig.json";
  std::ofstream(rigFile) << R"({"name": "eyes", "shapes": {},
    "eyes": {"parts": ["EyeRight"], "limits": {"yaw": 10}}})";
  gaze->RemoveAllEyeNames();
  gaze->SetRigFileName(rigFile.c_str());
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 3);
  for (const auto& [name, leaf] : Leaves(gaze->GetOutputDataObject(0)))
  {
    if (vtkDataArray* a = leaf->GetFieldData()->GetArray("EyeGaze"))
    {
      EXPECT_EQ(name.rfind("EyeRight/", 0), 0u) << name;
      EXPECT_EQ(a->GetComponent(0, 0), 10.0) << "the rig's limit";
    }
  }
  // A rig without eyes: the filter's own settings (the default convention).
  std::ofstream(rigFile) << R"({"name": "no eyes", "shapes": {}})";
  gaze->Modified(); // the file changed under the same name
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 6);
  std::remove(rigFile.c_str());
}

TEST(EyeGazeFilter, OneMeshAndMultiblockInput)
{
  // One mesh: the head's skin passes through, shared; an eye's mesh in its node's frame
  // (no NodeOrigin) turns about the node's origin.
  vtkNew<vtkMorphTargetReader> skin;
  skin->SetFileName(DefaultHead.c_str());
  skin->SetMeshIndex(0);
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(skin->GetOutputPort());
  gaze->SetEyeYaw(30.0);
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 0);
  auto* skinOut = vtkPolyData::SafeDownCast(gaze->GetOutputDataObject(0));
  ASSERT_TRUE(skinOut);
  EXPECT_EQ(skinOut->GetPoints(), skin->GetOutput()->GetPoints());

  vtkNew<vtkMorphTargetReader> eye;
  eye->SetFileName(DefaultHead.c_str());
  eye->SetMeshName("EyeLeft");
  eye->SetPrimitiveIndex(2); // the pupil
  gaze->SetInputConnection(eye->GetOutputPort());
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 1);
  auto* pupil = vtkPolyData::SafeDownCast(gaze->GetOutputDataObject(0));
  ASSERT_TRUE(pupil);
  const Vec3 d0 =
    Direction(eye->GetOutput(), { 0, 0, 0 }, [](vtkPolyData*, vtkIdType) { return true; });
  const Vec3 d1 = Direction(pupil, { 0, 0, 0 }, [](vtkPolyData*, vtkIdType) { return true; });
  EXPECT_LT(AngleDegrees(d0, { 0, 0, 1 }), 1.0);
  EXPECT_LT(AngleDegrees(d1, morphnode::GazeDirection({ 30.0, 0.0 })), 1.0);

  // A multiblock of the head's parts, names in the blocks' metadata only.
  auto reader = Read(DefaultHead);
  vtkNew<vtkMultiBlockDataSet> blocks;
  unsigned int b = 0;
  for (const auto& [name, leaf] : Leaves(reader->GetOutputDataObject(0)))
  {
    vtkNew<vtkPolyData> copy;
    copy->ShallowCopy(leaf);
    vtkNew<vtkFieldData> field;
    field->AddArray(leaf->GetFieldData()->GetArray(vtkMorphPartData::NodeOriginArray));
    field->AddArray(leaf->GetFieldData()->GetArray(vtkMorphPartData::NodeAxesArray));
    copy->SetFieldData(field);
    blocks->SetBlock(b, copy);
    blocks->GetMetaData(b++)->Set(vtkCompositeDataSet::NAME(), name.c_str());
  }
  gaze->SetInputData(blocks);
  gaze->Update();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 6) << "by block names";
  EXPECT_TRUE(vtkMultiBlockDataSet::SafeDownCast(gaze->GetOutputDataObject(0)));
}

TEST(EyeGazeFilter, GazeFromTheBehaviour)
{
  auto reader = Read(DefaultHead);
  vtkNew<vtkBehaviorTimeSource> behavior;
  behavior->SetSeed(3);
  behavior->SetDuration(4.0);
  ASSERT_TRUE(behavior->LookAt(20.0, -8.0, 1.0, 2.0));
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(reader->GetOutputPort());
  gaze->SetGazeConnection(behavior->GetOutputPort(0));
  gaze->SetEyeYaw(-33.0); // ignored while the table is connected
  gaze->UpdateInformation();
  vtkInformation* info = gaze->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS())) << "the behaviour's time";
  EXPECT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 121);
  for (const double t : { 0.5, 2.0, 2.5 })
  {
    gaze->UpdateTimeStep(t);
    vtkTable* table = vtkTable::SafeDownCast(behavior->GetOutputDataObject(0));
    const double yaw = table->GetColumnByName("EyeYaw")->GetVariantValue(0).ToDouble();
    const double pitch = table->GetColumnByName("EyePitch")->GetVariantValue(0).ToDouble();
    EXPECT_EQ(gaze->GetLastEyeYaw(), yaw) << t;
    EXPECT_EQ(gaze->GetLastEyePitch(), pitch) << t;
    if (t >= 2.0)
    {
      EXPECT_NEAR(
        yaw + table->GetColumnByName("HeadYaw")->GetVariantValue(0).ToDouble(), 20.0, 10.0)
        << "looking at the target, eyes and head together";
    }
    EXPECT_EQ(
      CheckGaze(reader->GetOutputDataObject(0), gaze->GetOutputDataObject(0), { yaw, pitch }, 1.0),
      6);
    EXPECT_EQ(
      gaze->GetOutputDataObject(0)->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), t);
  }
}

TEST(EyeGazeFilter, PropertiesAndBadInput)
{
  vtkNew<vtkEyeGazeFilter> gaze;
  vtkMTimeType m = gaze->GetMTime();
  gaze->SetEyeYaw(0.0);
  EXPECT_EQ(gaze->GetMTime(), m) << "no change, no modification";
  gaze->SetEyeYaw(5.0);
  EXPECT_GT(gaze->GetMTime(), m);
  m = gaze->GetMTime();
  gaze->RemoveAllEyeNames();
  EXPECT_EQ(gaze->GetMTime(), m);
  gaze->AddEyeName("EyeLeft");
  EXPECT_GT(gaze->GetMTime(), m);
  gaze->SetVergence(-3.0);
  EXPECT_EQ(gaze->GetVergence(), 0.0);
  std::ostringstream os;
  gaze->Print(os);
  for (const char* word :
    { "EyeYaw: 5", "MaxEyeYaw: 40", "MaxEyeUp: 25", "MaxEyeDown: 35", "'EyeLeft'", "RigFileName" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word;
  }
  gaze->RemoveAllEyeNames();

  auto reader = Read(DefaultHead);
  vtkNew<morphnode_test::MessageCollector> messages;
  messages->Watch(gaze);
  gaze->SetInputConnection(reader->GetOutputPort());
  auto expectError = [&](const std::string& fragment)
  {
    messages->Clear();
    gaze->Update();
    EXPECT_TRUE(messages->HasError(fragment)) << fragment << "; got: " << messages->AllErrors();
    auto* out = vtkCompositeDataSet::SafeDownCast(gaze->GetOutputDataObject(0));
    EXPECT_TRUE(!out || out->GetNumberOfCells() == 0) << "the output must be empty";
    EXPECT_EQ(gaze->GetNumberOfEyeParts(), 0);
  };
  gaze->SetEyeYaw(std::nan(""));
  expectError("finite");
  gaze->SetEyeYaw(10.0);
  gaze->SetMaxEyeDown(0.0);
  expectError("(0, 90]");
  gaze->SetMaxEyeDown(35.0);
  gaze->SetEyeUp(0.0, 0.0, 3.0);
  expectError("parallel");
  gaze->SetEyeUp(0.0, 1.0, 0.0);
  gaze->SetRigFileName("/no/such/rig.json");
  expectError("rig");
  gaze->SetRigFileName(nullptr);

  // An eye whose NodeOrigin is not finite, or whose NodeAxes has 3 values.
  vtkNew<vtkPartitionedDataSetCollection> bad;
  bad->ShallowCopy(reader->GetOutputDataObject(0));
  for (const char* fault : { "origin", "axes" })
  {
    bad->ShallowCopy(reader->GetOutputDataObject(0));
    for (unsigned int d = 0; d < bad->GetNumberOfPartitionedDataSets(); ++d)
    {
      vtkPolyData* leaf = vtkPolyData::SafeDownCast(bad->GetPartitionedDataSet(d)->GetPartition(0));
      if (StringOf(leaf, vtkMorphPartData::NodeNameArray) == "EyeRight")
      {
        vtkNew<vtkPolyData> copy;
        copy->ShallowCopy(leaf);
        vtkNew<vtkFieldData> field;
        field->DeepCopy(leaf->GetFieldData());
        vtkNew<vtkDoubleArray> array;
        array->SetName(std::string(fault) == "origin" ? vtkMorphPartData::NodeOriginArray
                                                      : vtkMorphPartData::NodeAxesArray);
        array->SetNumberOfValues(3);
        array->SetValue(0, std::string(fault) == "origin" ? std::nan("") : 1.0);
        array->SetValue(1, 0.0);
        array->SetValue(2, 0.0);
        field->AddArray(array);
        copy->SetFieldData(field);
        vtkNew<vtkPartitionedDataSet> set;
        set->SetPartition(0, copy);
        bad->SetPartitionedDataSet(d, set);
      }
    }
    gaze->SetInputData(bad);
    expectError(
      std::string(fault) == "origin" ? "NodeOrigin is not finite" : "NodeAxes has 3 values");
  }
  // The reader's output is still intact.
  gaze->SetInputConnection(reader->GetOutputPort());
  messages->Clear();
  gaze->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_EQ(gaze->GetNumberOfEyeParts(), 6);

  // A gaze table without the columns.
  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> column;
  column->SetName("HeadYaw");
  column->InsertNextValue(1.0);
  table->AddColumn(column);
  gaze->SetInputData(1, table);
  expectError("EyeYaw");
  // ... with the columns but no row.
  vtkNew<vtkTable> empty;
  for (const char* name : { "EyeYaw", "EyePitch" })
  {
    vtkNew<vtkDoubleArray> angles;
    angles->SetName(name);
    empty->AddColumn(angles);
  }
  gaze->SetInputData(1, empty);
  expectError("no rows");
}
