// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphTargetReader on the ICT face: names, normals, mesh choice, bad files.
#include "vtkMorphTargetReader.h"
#include "vtkMorphNodeFilter.h"

#include "MorphNodeTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using morphnode_test::MessageCollector;

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

bool HaveIct()
{
  return static_cast<bool>(std::ifstream(IctGlb));
}
} // namespace

TEST(MorphTargetReader, ReadsNamesAndComputesNormals)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->Update();
  vtkPolyData* out = reader->GetOutput();
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
    ASSERT_NE(out->GetPointData()->GetArray(("target" + std::to_string(k) + "_normal").c_str()), nullptr) << k;
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
}

TEST(MorphTargetReader, FeedsTheMorphNodeByName)
{
  if (!HaveIct())
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
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
  centimetres->SetScale(100.0);
  metres->Update();
  centimetres->Update();
  double a[3], b[3];
  metres->GetOutput()->GetPoint(10, a);
  centimetres->GetOutput()->GetPoint(10, b);
  EXPECT_NEAR(b[1], 100.0 * a[1], 1e-3);
  const double da = metres->GetOutput()->GetPointData()->GetArray("target26_position")->GetComponent(5000, 1);
  const double db = centimetres->GetOutput()->GetPointData()->GetArray("target26_position")->GetComponent(5000, 1);
  EXPECT_NEAR(db, 100.0 * da, 1e-3);
}

TEST(MorphTargetReader, BadFilesAreClearErrors)
{
  vtkNew<vtkMorphTargetReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetFileName("/nonexistent/face.glb");
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_TRUE(messages->HasError("cannot open")) << messages->AllErrors();

  messages->Clear();
  reader->SetFileName("face.ply");
  reader->Update();
  EXPECT_TRUE(messages->HasError("expected a .glb or .gltf")) << messages->AllErrors();

  // A GLB cut in the middle of its JSON chunk.
  if (HaveIct())
  {
    std::ifstream in(IctGlb, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/truncated.glb";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), 200);
    messages->Clear();
    reader->SetFileName(cut.c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_TRUE(messages->HasError("runs past the end")) << messages->AllErrors();

    messages->Clear();
    reader->SetFileName(IctGlb.c_str());
    reader->SetMeshName("Body");
    reader->Update();
    EXPECT_TRUE(messages->HasError("no mesh named 'Body'; meshes: ICTFace")) << messages->AllErrors();
  }
}

TEST(MorphTargetReader, ObjSetMatchesTheGlbOnSharedTargets)
{
  const std::string objFolder = std::string(MORPHNODE_FACEKIT_DIR) + "/obj";
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
    vtkDataArray* od = o->GetPointData()->GetArray(("target" + std::to_string(k - 1) + "_position").c_str());
    vtkDataArray* gd = g->GetPointData()->GetArray(("target" + std::to_string(inGlb - 1) + "_position").c_str());
    double deltaWorst = 0.0, largest = 0.0;
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        deltaWorst = std::max(deltaWorst, std::abs(od->GetComponent(i, c) - gd->GetComponent(i, c)));
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
  EXPECT_NEAR(reader->GetOutput()->GetPointData()->GetArray("target0_position")->GetComponent(2, 2), 1.0, 1e-9);
}
