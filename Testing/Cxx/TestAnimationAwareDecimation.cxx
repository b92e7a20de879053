// SPDX-License-Identifier: BSD-3-Clause
// vtkAnimationAwareDecimation on the ICT face (skipped without it) and on bad input.
#include "MorphNodeTestUtilities.h"

#include "vtkAnimationAwareDecimation.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

namespace
{
std::string FacePath()
{
  return std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
}

vtkSmartPointer<vtkPolyData> ReadFace()
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(FacePath().c_str());
  reader->SetMeshIndex(0); // one mesh, one vtkPolyData
  reader->Update();
  return reader->GetOutput();
}

vtkSmartPointer<vtkPolyData> Decimate(vtkPolyData* face, vtkIdType triangles, double weight)
{
  vtkNew<vtkAnimationAwareDecimation> decimation;
  decimation->SetInputData(face);
  decimation->SetNumberOfTriangles(triangles);
  decimation->SetAnimationWeight(weight);
  decimation->Update();
  return decimation->GetOutput();
}

/// A 4 x 4 grid of triangles with two targets.
vtkSmartPointer<vtkPolyData> SmallMesh()
{
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 5; ++i)
    {
      points->InsertNextPoint(i, j, 0.1 * ((i * j) % 3));
    }
  }
  mesh->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  for (int j = 0; j < 4; ++j)
  {
    for (int i = 0; i < 4; ++i)
    {
      const vtkIdType a = j * 5 + i, b = a + 1, c = a + 5, d = c + 1;
      const vtkIdType t0[3] = { a, b, d }, t1[3] = { a, d, c };
      polys->InsertNextCell(3, t0);
      polys->InsertNextCell(3, t1);
    }
  }
  mesh->SetPolys(polys);
  for (int k = 0; k < 2; ++k)
  {
    vtkNew<vtkFloatArray> deltas;
    deltas->SetName(("target" + std::to_string(k) + "_position").c_str());
    deltas->SetNumberOfComponents(3);
    deltas->SetNumberOfTuples(25);
    for (vtkIdType p = 0; p < 25; ++p)
    {
      deltas->SetTuple3(p, 0.0, p < 10 ? 0.2 * (k + 1) : 0.0, 0.0);
    }
    mesh->GetPointData()->AddArray(deltas);
  }
  vtkNew<vtkStringArray> names;
  names->SetName("TargetNames");
  names->InsertNextValue("Neutral");
  names->InsertNextValue("a");
  names->InsertNextValue("b");
  mesh->GetFieldData()->AddArray(names);
  return mesh;
}

/// Runs the filter on `input` and expects an error containing `fragment` and an empty output.
void ExpectError(vtkPolyData* input, const std::string& fragment, vtkIdType triangles = 8)
{
  vtkNew<vtkAnimationAwareDecimation> decimation;
  vtkNew<morphnode_test::MessageCollector> messages;
  messages->Watch(decimation);
  decimation->SetInputData(input);
  decimation->SetNumberOfTriangles(triangles);
  decimation->Update();
  EXPECT_TRUE(messages->HasError(fragment))
    << "expected '" << fragment << "', got: " << messages->AllErrors();
  EXPECT_EQ(decimation->GetOutput()->GetNumberOfPoints(), 0);
}
} // namespace

TEST(AnimationAwareDecimation, CarriesEveryTargetOnTheICTFace)
{
  if (!std::filesystem::exists(FacePath()))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << FacePath();
  }
  vtkSmartPointer<vtkPolyData> face = ReadFace();
  ASSERT_EQ(face->GetNumberOfPoints(), 11248);
  const vtkIdType mtime = face->GetMTime();
  const vtkIdType budget = face->GetNumberOfPolys() / 4;
  vtkSmartPointer<vtkPolyData> reduced = Decimate(face, budget, 1.0);
  EXPECT_EQ(face->GetMTime(), mtime); // input untouched
  ASSERT_GT(reduced->GetNumberOfPoints(), 0);
  EXPECT_LE(reduced->GetNumberOfPolys(), budget);
  EXPECT_GE(reduced->GetNumberOfPolys(), budget - 4);

  auto* ids = vtkIdTypeArray::SafeDownCast(reduced->GetPointData()->GetArray("OriginalPointId"));
  ASSERT_NE(ids, nullptr);
  auto* names =
    vtkStringArray::SafeDownCast(reduced->GetFieldData()->GetAbstractArray("TargetNames"));
  ASSERT_NE(names, nullptr);
  EXPECT_EQ(names->GetNumberOfValues(), 54);
  int arraysChecked = 0;
  for (int a = 0; a < face->GetPointData()->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* in = face->GetPointData()->GetArray(a);
    vtkDataArray* out = reduced->GetPointData()->GetArray(in->GetName());
    ASSERT_NE(out, nullptr) << in->GetName();
    ASSERT_EQ(out->GetNumberOfComponents(), in->GetNumberOfComponents());
    for (vtkIdType k = 0; k < reduced->GetNumberOfPoints(); ++k)
    {
      const vtkIdType o = ids->GetValue(k);
      for (int c = 0; c < in->GetNumberOfComponents(); ++c)
      {
        ASSERT_EQ(out->GetComponent(k, c), in->GetComponent(o, c))
          << in->GetName() << " at reduced point " << k;
      }
    }
    ++arraysChecked;
  }
  EXPECT_GE(arraysChecked, 106); // 53 position and 53 normal delta arrays, plus normals
  for (vtkIdType k = 0; k < reduced->GetNumberOfPoints(); ++k)
  {
    double p[3], q[3];
    reduced->GetPoint(k, p);
    face->GetPoint(ids->GetValue(k), q);
    ASSERT_EQ(p[0], q[0]);
    ASSERT_EQ(p[1], q[1]);
    ASSERT_EQ(p[2], q[2]);
  }

  // The morph node animates the reduced face like the full one at the kept points.
  auto animate = [](vtkPolyData* input)
  {
    vtkNew<vtkMorphNodeFilter> morph;
    morph->SetInputData(input);
    morph->SetWeightModeToRelative();
    morph->SetWeightByName("jawOpen", 0.7);
    morph->SetWeightByName("eyeBlink_L", 1.0);
    morph->Update();
    return vtkSmartPointer<vtkPointSet>(morph->GetOutput());
  };
  auto full = animate(face);
  auto small = animate(reduced);
  ASSERT_EQ(small->GetNumberOfPoints(), reduced->GetNumberOfPoints());
  for (vtkIdType k = 0; k < small->GetNumberOfPoints(); ++k)
  {
    double p[3], q[3];
    small->GetPoint(k, p);
    full->GetPoint(ids->GetValue(k), q);
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_NEAR(p[c], q[c], 1e-7);
    }
  }
}

TEST(AnimationAwareDecimation, KeepsMoreOfMouthAndEyes)
{
  if (!std::filesystem::exists(FacePath()))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << FacePath();
  }
  vtkSmartPointer<vtkPolyData> face = ReadFace();
  // Mouth and eye regions: where the mouth, jaw and eyelid targets move the face by more
  // than a quarter of their largest motion (the high-AnimatedRegion areas).
  auto* names = vtkStringArray::SafeDownCast(face->GetFieldData()->GetAbstractArray("TargetNames"));
  std::vector<double> region(face->GetNumberOfPoints(), 0.0);
  for (vtkIdType t = 1; t < names->GetNumberOfValues(); ++t)
  {
    const std::string name = names->GetValue(t);
    if (name.rfind("mouth", 0) != 0 && name.rfind("jaw", 0) != 0 && name.rfind("eyeBlink", 0) != 0)
    {
      continue;
    }
    vtkDataArray* d =
      face->GetPointData()->GetArray(("target" + std::to_string(t - 1) + "_position").c_str());
    ASSERT_NE(d, nullptr);
    for (vtkIdType p = 0; p < face->GetNumberOfPoints(); ++p)
    {
      double v[3];
      d->GetTuple(p, v);
      region[p] = std::max(region[p], std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    }
  }
  const double cut = 0.25 * *std::max_element(region.begin(), region.end());
  for (int divisor : { 4, 10 })
  {
    const vtkIdType budget = face->GetNumberOfPolys() / divisor;
    auto count = [&](vtkPolyData* reduced)
    {
      auto* ids =
        vtkIdTypeArray::SafeDownCast(reduced->GetPointData()->GetArray("OriginalPointId"));
      int n = 0;
      for (vtkIdType k = 0; k < ids->GetNumberOfValues(); ++k)
      {
        n += region[ids->GetValue(k)] > cut ? 1 : 0;
      }
      return n;
    };
    const int ours = count(Decimate(face, budget, 0.01));
    const int plain = count(Decimate(face, budget, 0.0));
    EXPECT_GT(ours, plain + plain / 5) << "1/" << divisor << " of the triangles: ours keeps "
                                       << ours << " mouth/eye points, plain " << plain;
  }
}

TEST(AnimationAwareDecimation, SmallMeshAndDefaults)
{
  vtkSmartPointer<vtkPolyData> mesh = SmallMesh();
  vtkNew<vtkAnimationAwareDecimation> decimation;
  EXPECT_EQ(decimation->GetTargetReduction(), 0.5);
  EXPECT_EQ(decimation->GetAnimationWeight(), 0.01);
  decimation->SetInputData(mesh);
  decimation->Update();
  vtkPolyData* out = decimation->GetOutput();
  EXPECT_EQ(out->GetNumberOfPolys(), 16);
  EXPECT_NE(out->GetPointData()->GetArray("target1_position"), nullptr);
  EXPECT_NE(out->GetFieldData()->GetAbstractArray("TargetNames"), nullptr);
  std::ostringstream print;
  decimation->Print(print);
  EXPECT_NE(print.str().find("AnimationWeight: 0.01"), std::string::npos);
}

TEST(AnimationAwareDecimation, BadInputGivesErrorsAndEmptyOutput)
{
  {
    vtkNew<vtkPolyData> empty;
    ExpectError(empty, "no points");
  }
  {
    vtkSmartPointer<vtkPolyData> pointsOnly = SmallMesh();
    pointsOnly->SetPolys(vtkNew<vtkCellArray>());
    ExpectError(pointsOnly, "no triangles");
  }
  {
    vtkSmartPointer<vtkPolyData> quads = SmallMesh();
    vtkNew<vtkCellArray> polys;
    const vtkIdType quad[4] = { 0, 1, 6, 5 };
    polys->InsertNextCell(4, quad);
    quads->SetPolys(polys);
    ExpectError(quads, "must be triangles");
  }
  ExpectError(SmallMesh(), "must be below", 32);
  ExpectError(SmallMesh(), "must be below", 1000);
  {
    vtkSmartPointer<vtkPolyData> mismatched = SmallMesh();
    mismatched->GetPointData()->GetArray("target1_position")->SetNumberOfTuples(20);
    ExpectError(mismatched, "must be numeric with 3 components and 25 tuples");
  }
  {
    vtkSmartPointer<vtkPolyData> gap = SmallMesh();
    gap->GetPointData()->GetArray("target1_position")->SetName("target2_position");
    ExpectError(gap, "gap");
  }
  {
    vtkSmartPointer<vtkPolyData> names = SmallMesh();
    vtkStringArray::SafeDownCast(names->GetFieldData()->GetAbstractArray("TargetNames"))
      ->InsertNextValue("c");
    ExpectError(names, "'TargetNames' has 4 names for 3 targets");
  }
}
