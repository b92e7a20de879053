// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphTargetReader: whole glTF scenes (parts, nested TRS and matrix transforms, names,
// colours, the node tree), one mesh as before (names, normals, mesh choice), OBJ sets, bad
// files and bad scenes.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestScenes.h"
#include "MorphNodeTestUtilities.h"

#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataAssembly.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>

using morphnode_test::MessageCollector;
using namespace morphnode_test::scenes;

namespace
{
const std::string FaceKit = MORPHNODE_FACEKIT_DIR;
const std::string IctGlb = FaceKit + "/ict_face11248_sparse53.glb";
const std::string IctHead = FaceKit + "/ict_head_full53.glb";
const std::string DefaultHead =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";

bool HaveIct()
{
  return static_cast<bool>(std::ifstream(IctGlb));
}

vtkPolyData* Part(vtkPartitionedDataSetCollection* c, unsigned int i)
{
  return vtkPolyData::SafeDownCast(c->GetPartition(i, 0));
}

std::string FieldString(vtkDataObject* d, const char* name)
{
  return vtkMorphPartData::GetString(d->GetFieldData(), name);
}

std::vector<std::string> Names(vtkDataObject* d)
{
  std::vector<std::string> names;
  auto* a = vtkStringArray::SafeDownCast(d->GetFieldData()->GetAbstractArray("TargetNames"));
  for (vtkIdType i = 0; a && i < a->GetNumberOfValues(); ++i)
  {
    names.push_back(a->GetValue(i));
  }
  return names;
}

std::vector<double> FieldDoubles(vtkDataObject* d, const char* name)
{
  return vtkMorphPartData::GetNumbers(d->GetFieldData(), name);
}

void ExpectPoint(vtkDataArray* array, vtkIdType i, const Vec3& expected, const std::string& what)
{
  double p[3];
  array->GetTuple(i, p);
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_NEAR(p[c], expected[static_cast<size_t>(c)], 1e-6)
      << what << " point " << i << " component " << c;
  }
}

/// Reads `file` as a whole scene; nullptr (after an error) when the output is not a
/// collection with parts.
vtkPartitionedDataSetCollection* ReadScene(vtkMorphTargetReader* reader, const std::string& file)
{
  reader->SetFileName(file.c_str());
  reader->Update();
  auto* c = vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
  return c && c->GetNumberOfPartitionedDataSets() > 0 ? c : nullptr;
}
} // namespace

TEST(MorphTargetReader, WholeSceneWithNestedTransforms)
{
  const std::string file = WriteFile("test_head.glb", TestHead().Glb());
  vtkNew<vtkMorphTargetReader> reader;
  EXPECT_FALSE(reader->GetReadsWholeScene()) << "no file yet";
  reader->SetFileName(file.c_str());
  EXPECT_TRUE(reader->GetReadsWholeScene());
  vtkPartitionedDataSetCollection* head = ReadScene(reader, file);
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(reader->GetOutput(), nullptr) << "a scene is not one vtkPolyData";
  ASSERT_EQ(head->GetNumberOfPartitionedDataSets(), 4u);
  ASSERT_EQ(reader->GetNumberOfParts(), 4);
  const char* const parts[] = { "Jaw/Skin", "Jaw/Lips", "Tooth", "EyeLeft" };
  for (unsigned int i = 0; i < 4; ++i)
  {
    ASSERT_NE(Part(head, i), nullptr) << i;
    EXPECT_STREQ(head->GetMetaData(i)->Get(vtkCompositeDataSet::NAME()), parts[i]);
    EXPECT_STREQ(reader->GetPartName(static_cast<int>(i)), parts[i]);
    EXPECT_EQ(FieldString(Part(head, i), vtkMorphPartData::PartNameArray), parts[i]);
    EXPECT_EQ(Part(head, i)->GetNumberOfPoints(), 4);
    EXPECT_EQ(Part(head, i)->GetNumberOfPolys(), 2);
  }
  EXPECT_EQ(FieldString(Part(head, 1), vtkMorphPartData::NodeNameArray), "Jaw");
  EXPECT_EQ(FieldString(Part(head, 1), vtkMorphPartData::MaterialNameArray), "Lips");
  EXPECT_EQ(FieldDoubles(Part(head, 1), vtkMorphPartData::BaseColorArray),
    (std::vector<double>{ 0.7, 0.3, 0.3, 1 }));
  EXPECT_EQ(FieldDoubles(Part(head, 3), vtkMorphPartData::BaseColorArray),
    (std::vector<double>{ 1, 1, 1, 1 }))
    << "default material";

  // Points in world space through all three levels (matrix, TRS, matrix).
  for (vtkIdType i = 0; i < 4; ++i)
  {
    const Vec3 p{ QuadPoints[3 * i], QuadPoints[3 * i + 1], QuadPoints[3 * i + 2] };
    ExpectPoint(Part(head, 0)->GetPoints()->GetData(), i, JawMap(p), "Jaw/Skin");
    ExpectPoint(Part(head, 1)->GetPoints()->GetData(), i, JawMap(p), "Jaw/Lips");
    ExpectPoint(Part(head, 2)->GetPoints()->GetData(), i, ToothMap(p), "Tooth");
    ExpectPoint(Part(head, 3)->GetPoints()->GetData(), i, EyeMap(p), "EyeLeft");
  }
  // Deltas turn and scale with the node; normals only turn.
  ExpectPoint(Part(head, 0)->GetPointData()->GetArray("target0_position"), 3,
    JawDelta({ 0, 0, 0.4 }), "Lift");
  ExpectPoint(Part(head, 0)->GetPointData()->GetArray("target1_position"), 2,
    JawDelta({ 0, 0.5, 0 }), "Raise (sparse)");
  ExpectPoint(Part(head, 2)->GetPointData()->GetArray("target0_position"), 1,
    JawDelta({ 0.3, 0, 0 }), "Tooth's Raise");
  ExpectPoint(Part(head, 0)->GetPointData()->GetNormals(), 0, { 0, 0, 1 }, "normal");

  // Each part keeps its own targets; the collection names every target of the scene.
  EXPECT_EQ(Names(Part(head, 0)), (std::vector<std::string>{ "Neutral", "Lift", "Raise" }));
  EXPECT_EQ(Names(Part(head, 2)), (std::vector<std::string>{ "Neutral", "Raise" }));
  EXPECT_EQ(Names(Part(head, 3)), (std::vector<std::string>{ "Neutral" }));
  EXPECT_EQ(Part(head, 3)->GetPointData()->GetArray("target0_position"), nullptr);
  EXPECT_EQ(Names(head), (std::vector<std::string>{ "Neutral", "Lift", "Raise" }));
  ASSERT_EQ(reader->GetNumberOfTargets(), 3);
  EXPECT_STREQ(reader->GetTargetName(2), "Raise");
  EXPECT_EQ(reader->GetNumberOfMeshes(), 3);
  EXPECT_STREQ(reader->GetMeshNameByIndex(1), "Teeth");

  // Vertex colours as unsigned char RGBA; node origins and axes in world space.
  auto* colors =
    vtkUnsignedCharArray::SafeDownCast(Part(head, 3)->GetPointData()->GetArray("COLOR_0"));
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->GetNumberOfComponents(), 4);
  EXPECT_EQ(colors->GetValue(4 * 2 + 3), 128) << "alpha 0.5";
  EXPECT_EQ(colors->GetValue(4 * 1 + 1), 255);
  EXPECT_EQ(FieldDoubles(Part(head, 3), vtkMorphPartData::NodeOriginArray),
    (std::vector<double>{ 12, 2, 2 }));
  const std::vector<double> axes = FieldDoubles(Part(head, 0), vtkMorphPartData::NodeAxesArray);
  const std::vector<double> turned{ 0, 1, 0, -1, 0, 0, 0, 0, 1 }; // x to y, y to -x; scale removed
  ASSERT_EQ(axes.size(), 9u);
  for (size_t i = 0; i < 9; ++i)
  {
    EXPECT_NEAR(axes[i], turned[i], 1e-12) << i;
  }
  const Vec3 jawOrigin = JawMap({ 0, 0, 0 });
  EXPECT_EQ(FieldDoubles(Part(head, 0), vtkMorphPartData::NodeOriginArray),
    (std::vector<double>(jawOrigin.begin(), jawOrigin.end())));

  // The node tree, each part on its node.
  vtkDataAssembly* assembly = head->GetDataAssembly();
  ASSERT_NE(assembly, nullptr);
  EXPECT_STREQ(assembly->GetNodeName(vtkDataAssembly::GetRootNode()), "TestHead");
  const int headNode = assembly->FindFirstNodeWithName("Head");
  const int jaw = assembly->FindFirstNodeWithName("Jaw");
  const int tooth = assembly->FindFirstNodeWithName("Tooth");
  const int eye = assembly->FindFirstNodeWithName("EyeLeft");
  ASSERT_TRUE(headNode > 0 && jaw > 0 && tooth > 0 && eye > 0);
  EXPECT_EQ(assembly->GetParent(jaw), headNode);
  EXPECT_EQ(assembly->GetParent(tooth), jaw);
  EXPECT_EQ(assembly->GetParent(eye), headNode);
  EXPECT_EQ(assembly->GetDataSetIndices(jaw, false), (std::vector<unsigned int>{ 0, 1 }));
  EXPECT_EQ(assembly->GetDataSetIndices(tooth, false), (std::vector<unsigned int>{ 2 }));
  EXPECT_EQ(assembly->GetDataSetIndices(headNode, true), (std::vector<unsigned int>{ 0, 1, 2, 3 }));

  // Scale applies to the world: points, deltas and origins.
  reader->SetScale(0.5);
  head = ReadScene(reader, file);
  ASSERT_NE(head, nullptr);
  ExpectPoint(
    Part(head, 2)->GetPoints()->GetData(), 1, { 5, 2, 1 }, "Tooth scaled"); // ToothMap(1, 0, 0) / 2
  EXPECT_EQ(FieldDoubles(Part(head, 3), vtkMorphPartData::NodeOriginArray),
    (std::vector<double>{ 6, 1, 1 }));
}

TEST(MorphTargetReader, OneMeshIsOnePolyDataInItsNodeFrame)
{
  const std::string file = WriteFile("test_head_one_mesh.glb", TestHead().Glb());
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetMeshName("Teeth");
  EXPECT_FALSE(reader->GetReadsWholeScene());
  reader->Update();
  vtkPolyData* teeth = reader->GetOutput();
  ASSERT_NE(teeth, nullptr);
  ASSERT_EQ(teeth->GetNumberOfPoints(), 4);
  ExpectPoint(teeth->GetPoints()->GetData(), 2, { 1, 1, 0 }, "in the node's frame");
  ExpectPoint(
    teeth->GetPointData()->GetArray("target0_position"), 0, { 0.3, 0, 0 }, "delta as in the file");
  EXPECT_EQ(Names(teeth), (std::vector<std::string>{ "Neutral", "Raise" }));
  EXPECT_EQ(FieldString(teeth, vtkMorphPartData::MaterialNameArray), "Enamel");
  EXPECT_EQ(teeth->GetFieldData()->GetArray(vtkMorphPartData::NodeOriginArray), nullptr)
    << "no world data in the node's frame";

  // Mesh 0's second primitive; then back to the whole scene.
  reader->SetMeshName(nullptr);
  reader->SetPrimitiveIndex(1);
  reader->Update();
  ASSERT_NE(reader->GetOutput(), nullptr);
  EXPECT_EQ(FieldString(reader->GetOutput(), vtkMorphPartData::PartNameArray), "Jaw/Lips");
  reader->SetPrimitiveIndex(-1);
  reader->SetMeshIndex(2);
  reader->Update();
  EXPECT_EQ(FieldString(reader->GetOutput(), vtkMorphPartData::PartNameArray), "EyeLeft");
  reader->SetMeshIndex(-1);
  reader->Update();
  EXPECT_NE(vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0)), nullptr);

  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetMeshIndex(0);
  reader->SetPrimitiveIndex(2);
  EXPECT_EQ(reader->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("primitive 2 out of range: mesh 'Skin' has 2"))
    << messages->AllErrors();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(MorphTargetReader, BadScenesAreClearErrors)
{
  vtkNew<vtkMorphTargetReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  auto expectError = [&](
                       const std::string& name, const std::string& glb, const std::string& fragment)
  {
    messages->Clear();
    reader->SetFileName(WriteFile(name, glb).c_str());
    reader->Modified();
    EXPECT_EQ(reader->GetExecutive()->Update(), 0) << name;
    EXPECT_TRUE(messages->HasError(fragment)) << name << ": " << messages->AllErrors();
    auto* c = vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->GetNumberOfPartitionedDataSets(), 0u) << name << ": the output is empty";
  };

  // A part whose target has another vertex count than its points.
  gltftest::Builder b = TestHead();
  b.Doc["meshes"][1]["primitives"][0]["targets"][0]["POSITION"] =
    b.Vec3({ 0.3f, 0, 0, 0.3f, 0, 0, 0, 0, 0 });
  expectError("bad_target_count.glb", b.Glb(), "/meshes/1/primitives/0/targets/0/POSITION");

  // Transforms that make no points: a matrix beyond float (1e200: refused where it is, before
  // the world transform would pass double), a rotation of length 0 (NaN when normalized), a
  // NaN (not JSON at all).
  b = TestHead();
  b.Doc["nodes"][0]["matrix"] = { 1e200, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  b.Doc["nodes"][2]["matrix"] = { 1e200, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  expectError(
    "infinite_transform.glb", b.Glb(), "/nodes/0/matrix/0: 1e+200 is beyond the range of float");
  b = TestHead();
  b.Doc["nodes"][1]["rotation"] = { 0, 0, 0, 0 };
  expectError("zero_rotation.glb", b.Glb(), "/nodes/1/rotation");
  b = TestHead();
  std::string text = b.Finished().dump();
  const std::string translation = "\"translation\":[1,1,1]";
  ASSERT_NE(text.find(translation), std::string::npos) << text;
  text.replace(text.find(translation), translation.size(), "\"translation\":[1,NaN,1]");
  expectError("nan_transform.glb", gltftest::Builder::MakeGlb(text, b.PaddedBin()), "JSON");

  // A scene that places no mesh.
  b = TestHead();
  b.Doc["scenes"][0]["nodes"] = gltftest::json::array();
  expectError("empty_scene.glb", b.Glb(), "has no mesh on a node of its scene");

  // Good again: the reader recovers.
  messages->Clear();
  reader->SetFileName(WriteFile("good_again.glb", TestHead().Glb()).c_str());
  EXPECT_EQ(reader->GetExecutive()->Update(), 1) << messages->AllErrors();
}

TEST(MorphTargetReader, IctHeadHasElevenPartsInMetres)
{
  if (!std::ifstream(IctHead))
  {
    GTEST_SKIP() << "ICT-FaceKit head not found at " << IctHead;
  }
  vtkNew<vtkMorphTargetReader> reader;
  vtkPartitionedDataSetCollection* head = ReadScene(reader, IctHead);
  ASSERT_NE(head, nullptr);
  ASSERT_EQ(head->GetNumberOfPartitionedDataSets(), 11u);
  vtkIdType points = 0;
  double bounds[6] = { VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX,
    VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  int withTargets = 0;
  for (unsigned int i = 0; i < 11; ++i)
  {
    vtkPolyData* part = Part(head, i);
    ASSERT_NE(part, nullptr);
    points += part->GetNumberOfPoints();
    double b[6];
    part->GetBounds(b);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
    }
    const size_t targets = Names(part).size() - 1;
    EXPECT_TRUE(targets == 0 || targets == 53)
      << FieldString(part, vtkMorphPartData::PartNameArray);
    withTargets += targets == 53;
    ASSERT_NE(part->GetPointData()->GetNormals(), nullptr);
  }
  EXPECT_EQ(points, 26041);
  EXPECT_EQ(withTargets, 7);
  EXPECT_LT(bounds[3] - bounds[2], 0.5) << "metres: the root's scale 0.01 applied";
  EXPECT_GT(bounds[3] - bounds[2], 0.15);
  EXPECT_EQ(Names(head).size(), 54u);
  EXPECT_EQ(Names(head)[27], "jawOpen");

  // The eyes: no targets, an origin at the eyeball's centre, the iris coloured.
  const int iris = 7;
  EXPECT_EQ(FieldString(Part(head, iris), vtkMorphPartData::PartNameArray), "EyeLeft/M_IrisLeft");
  EXPECT_NE(Part(head, iris)->GetPointData()->GetArray("COLOR_0"), nullptr);
  const std::vector<double> origin =
    FieldDoubles(Part(head, iris), vtkMorphPartData::NodeOriginArray);
  ASSERT_EQ(origin.size(), 3u);
  double centre[3] = { 0, 0, 0 };
  vtkPolyData* sclera = Part(head, 6);
  for (vtkIdType i = 0; i < sclera->GetNumberOfPoints(); ++i)
  {
    double p[3];
    sclera->GetPoint(i, p);
    for (int k = 0; k < 3; ++k)
    {
      centre[k] += p[k] / double(sclera->GetNumberOfPoints());
    }
  }
  EXPECT_LT(std::sqrt(vtkMath::Distance2BetweenPoints(centre, origin.data())), 0.006)
    << "the node's origin is near the eyeball's centre (the sclera's points, without the corneal "
       "cap, "
       "lean backwards)";
}

TEST(MorphTargetReader, DefaultHeadHasTheDefaultFacesTargets)
{
  vtkNew<vtkMorphTargetReader> reader;
  vtkPartitionedDataSetCollection* head = ReadScene(reader, DefaultHead);
  ASSERT_NE(head, nullptr);
  EXPECT_GT(head->GetNumberOfPartitionedDataSets(), 5u);
  const std::vector<std::string> names = Names(head);
  for (const char* name : { "Neutral", "EyesClosed", "BrowsUp", "S", "F", "BrowsFright",
         "BrowsAngry", "L", "E", "A", "MouthSmile", "MouthSad", "O" })
  {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
  int eyes = 0;
  for (unsigned int i = 0; i < head->GetNumberOfPartitionedDataSets(); ++i)
  {
    eyes += FieldString(Part(head, i), vtkMorphPartData::NodeNameArray).find("Eye") == 0;
  }
  EXPECT_GE(eyes, 2);
}

TEST(MorphTargetReader, OneIctMeshReadsNamesAndComputesNormals)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0);
  reader->Update();
  vtkPolyData* out = reader->GetOutput();
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->GetNumberOfPoints(), 11248);
  EXPECT_EQ(out->GetNumberOfPolys(), 22288);
  ASSERT_EQ(reader->GetNumberOfTargets(), 54);
  EXPECT_STREQ(reader->GetTargetName(0), "Neutral");
  EXPECT_STREQ(reader->GetTargetName(1), "browDown_L");
  EXPECT_STREQ(reader->GetTargetName(27), "jawOpen");
  EXPECT_STREQ(reader->GetTargetName(53), "noseSneer_R");
  auto* names = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_NE(names, nullptr);
  EXPECT_EQ(names->GetNumberOfValues(), 54);
  EXPECT_EQ(reader->GetNumberOfMeshes(), 1);
  EXPECT_STREQ(reader->GetMeshNameByIndex(0), "ICTFace");

  // The file has no normals: unit normals for the base, deltas for every target.
  vtkDataArray* normals = out->GetPointData()->GetNormals();
  ASSERT_NE(normals, nullptr);
  double n[3];
  normals->GetTuple(100, n);
  EXPECT_NEAR(vtkMath::Norm(n), 1.0, 1e-5);
  for (int k = 0; k < 53; ++k)
  {
    ASSERT_NE(
      out->GetPointData()->GetArray(("target" + std::to_string(k) + "_normal").c_str()), nullptr)
      << k;
  }
  // jawOpen tilts the chin's normals: some normal delta is substantial.
  vtkDataArray* jaw = out->GetPointData()->GetArray("target26_normal");
  double largest = 0.0;
  for (vtkIdType i = 0; i < jaw->GetNumberOfTuples(); ++i)
  {
    jaw->GetTuple(i, n);
    largest = std::max(largest, vtkMath::Norm(n));
  }
  EXPECT_GT(largest, 0.1);

  // The same face read as a scene: one part, the same points and arrays.
  vtkNew<vtkMorphTargetReader> scene;
  vtkPartitionedDataSetCollection* whole = ReadScene(scene, IctGlb);
  ASSERT_NE(whole, nullptr);
  ASSERT_EQ(whole->GetNumberOfPartitionedDataSets(), 1u);
  vtkPolyData* part = Part(whole, 0);
  ASSERT_EQ(part->GetNumberOfPoints(), out->GetNumberOfPoints());
  EXPECT_EQ(part->GetPointData()->GetNumberOfArrays(), out->GetPointData()->GetNumberOfArrays());
  double a[3], b[3];
  part->GetPoint(9000, a);
  out->GetPoint(9000, b);
  EXPECT_EQ(vtkMath::Distance2BetweenPoints(a, b), 0.0) << "the face's node has no transform";
}

TEST(MorphTargetReader, FeedsTheMorphNodeByName)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0);
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  morph->SetWeightByName("jawOpen", 1.0);
  morph->Update();
  vtkPolyData* out = vtkPolyData::SafeDownCast(morph->GetOutput());
  ASSERT_EQ(out->GetNumberOfPoints(), 11248);
  EXPECT_EQ(morph->GetActiveTargetCount(), 1);
  // Blended normals stay unit length; no target arrays reach the output.
  double n[3];
  out->GetPointData()->GetNormals()->GetTuple(5000, n);
  EXPECT_NEAR(vtkMath::Norm(n), 1.0, 1e-5);
  EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 1);
}

TEST(MorphTargetReader, ScaleConvertsUnits)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> metres, centimetres;
  metres->SetFileName(IctGlb.c_str());
  centimetres->SetFileName(IctGlb.c_str());
  metres->SetMeshIndex(0);
  centimetres->SetMeshIndex(0);
  centimetres->SetScale(100.0);
  metres->Update();
  centimetres->Update();
  double a[3], b[3];
  metres->GetOutput()->GetPoint(10, a);
  centimetres->GetOutput()->GetPoint(10, b);
  EXPECT_NEAR(b[1], 100.0 * a[1], 1e-3);
  const double da =
    metres->GetOutput()->GetPointData()->GetArray("target26_position")->GetComponent(5000, 1);
  const double db =
    centimetres->GetOutput()->GetPointData()->GetArray("target26_position")->GetComponent(5000, 1);
  EXPECT_NEAR(db, 100.0 * da, 1e-3);
}

TEST(MorphTargetReader, BadFilesAreClearErrors)
{
  vtkNew<vtkMorphTargetReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetFileName("/nonexistent/face.glb");
  EXPECT_EQ(reader->GetExecutive()->Update(), 0);
  EXPECT_TRUE(messages->HasError("cannot be opened")) << messages->AllErrors();

  messages->Clear();
  reader->SetFileName("face.ply");
  reader->Update();
  EXPECT_TRUE(messages->HasError("expected a .glb or .gltf")) << messages->AllErrors();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);

  // A GLB cut in the middle of its JSON chunk.
  if (HaveIct())
  {
    std::ifstream in(IctGlb, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = WriteFile("truncated.glb", std::string(bytes.data(), 200));
    messages->Clear();
    reader->SetFileName(cut.c_str());
    reader->SetMeshIndex(0);
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_TRUE(messages->HasError("but the file has 200 (truncated?)")) << messages->AllErrors();

    messages->Clear();
    reader->SetFileName(IctGlb.c_str());
    reader->SetMeshName("Body");
    reader->Update();
    EXPECT_TRUE(messages->HasError("no mesh named 'Body'; meshes: ICTFace"))
      << messages->AllErrors();
  }
}

TEST(MorphTargetReader, ObjSetMatchesTheGlbOnSharedTargets)
{
  const std::string objFolder = FaceKit + "/obj";
  if (!HaveIct() || !std::ifstream(objFolder + "/generic_neutral_mesh.obj"))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> obj, glb;
  obj->SetFileName(objFolder.c_str());
  obj->SetScale(0.01); // the OBJ originals are in centimetres, the GLB in metres
  obj->SetNormalsMode(vtkMorphTargetReader::NORMALS_FROM_FILE);
  obj->Update();
  glb->SetFileName(IctGlb.c_str());
  glb->SetMeshIndex(0);
  glb->SetNormalsMode(vtkMorphTargetReader::NORMALS_FROM_FILE);
  glb->Update();
  vtkPolyData* o = obj->GetOutput();
  vtkPolyData* g = glb->GetOutput();
  ASSERT_EQ(o->GetNumberOfPoints(), 26719);
  ASSERT_EQ(obj->GetNumberOfTargets(), 6);
  EXPECT_STREQ(obj->GetTargetName(0), "Neutral");

  // The GLB holds vertices 0..11247 of the OBJ neutral (face, head, neck).
  double worst = 0.0;
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    o->GetPoint(i, a);
    g->GetPoint(i, b);
    for (int c = 0; c < 3; ++c)
    {
      worst = std::max(worst, std::abs(a[c] - b[c]));
    }
  }
  EXPECT_LT(worst, 1e-6) << "neutral positions, metres";

  int compared = 0;
  for (int k = 1; k < obj->GetNumberOfTargets(); ++k)
  {
    const std::string name = obj->GetTargetName(k);
    int inGlb = -1;
    for (int j = 1; j < glb->GetNumberOfTargets(); ++j)
    {
      if (name == glb->GetTargetName(j))
      {
        inGlb = j;
      }
    }
    ASSERT_GE(inGlb, 1) << name << " is not in the GLB";
    vtkDataArray* od =
      o->GetPointData()->GetArray(("target" + std::to_string(k - 1) + "_position").c_str());
    vtkDataArray* gd =
      g->GetPointData()->GetArray(("target" + std::to_string(inGlb - 1) + "_position").c_str());
    double deltaWorst = 0.0, largest = 0.0;
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        deltaWorst =
          std::max(deltaWorst, std::abs(od->GetComponent(i, c) - gd->GetComponent(i, c)));
        largest = std::max(largest, std::abs(gd->GetComponent(i, c)));
      }
    }
    // The GLB dropped deltas below 1e-4 cm (1e-6 m).
    EXPECT_LT(deltaWorst, 2e-6) << name;
    EXPECT_GT(largest, 1e-3) << name << " hardly moves: the comparison proves nothing";
    ++compared;
  }
  EXPECT_EQ(compared, 5);
}

TEST(MorphTargetReader, ObjSetWithMismatchedVertexCountNamesTheFile)
{
  const std::string folder = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/objset_bad";
  std::filesystem::create_directories(folder);
  std::ofstream(folder + "/neutral.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(folder + "/smile.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 1\nf 1 2 3\n";
  std::ofstream(folder + "/broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 3\n";
  vtkNew<vtkMorphTargetReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetFileName(folder.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_TRUE(messages->HasError("broken.obj")) << messages->AllErrors();

  std::filesystem::remove(folder + "/broken.obj");
  messages->Clear();
  reader->Modified();
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 3);
  ASSERT_EQ(reader->GetNumberOfTargets(), 2);
  EXPECT_STREQ(reader->GetTargetName(1), "smile");
  EXPECT_NEAR(reader->GetOutput()->GetPointData()->GetArray("target0_position")->GetComponent(2, 2),
    1.0, 1e-9);
}
