// SPDX-License-Identifier: BSD-3-Clause
// Cross-check of MorphNode's glTF loader (MorphNode::Gltf) against a reader MorphNode did
// not write: VTK 9.1's vtkGLTFReader. On ict_face11248_sparse53.glb (sparse targets WITH
// bufferViews, which VTK reads right) the neutral points, the triangles and every target's
// deltas must agree; on the whole head (ict_head_full53.glb) the points of all 11 parts,
// with and without their node transforms (VTK reads those right; only its targets without
// bufferView are wrong there).
#include "MorphNodeGltfReaderParts.h"
#include "gltf/GltfScene.h"

#include "vtkCellArray.h"
#include "vtkCompositeDataIterator.h"
#include "vtkDataArray.h"
#include "vtkGLTFReader.h"
#include "vtkIdList.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace
{
const std::string FaceKit = MORPHNODE_FACEKIT_DIR;

std::vector<vtkSmartPointer<vtkPolyData>> VtkParts(const std::string& file, bool deform = false)
{
  return morphnode_test::VtkGltfReaderParts(file, deform);
}
} // namespace

TEST(GltfSceneCrossCheck, IctFaceAgreesWithVtkGltfReader)
{
  const std::string file = FaceKit + "/ict_face11248_sparse53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit not found at " << FaceKit << " (set MORPHNODE_FACEKIT_DIR)";
  }
  const morphnode::GltfScene scene = morphnode::LoadGltfScene(file);
  const auto vtkParts = VtkParts(file);
  ASSERT_EQ(scene.Parts.size(), 1u);
  ASSERT_EQ(vtkParts.size(), 1u);
  const morphnode::GltfPart& part = scene.Parts[0];
  vtkPolyData* poly = vtkParts[0];
  ASSERT_EQ(static_cast<size_t>(poly->GetNumberOfPoints()), part.GetNumberOfPoints());
  EXPECT_EQ(part.GetNumberOfPoints(), 11248u);

  double worst = 0;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
  {
    double p[3];
    poly->GetPoint(i, p);
    for (int k = 0; k < 3; ++k)
    {
      worst = std::max(worst,
        std::abs(p[k] - part.Positions[3 * static_cast<size_t>(i) + static_cast<size_t>(k)]));
    }
  }
  EXPECT_EQ(worst, 0.0) << "neutral points differ";

  // Triangles, in the same order.
  ASSERT_EQ(static_cast<size_t>(poly->GetNumberOfPolys()), part.GetNumberOfTriangles());
  vtkNew<vtkIdList> ids;
  auto* polys = poly->GetPolys();
  size_t t = 0;
  size_t mismatches = 0;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++t)
  {
    ASSERT_EQ(ids->GetNumberOfIds(), 3);
    for (vtkIdType k = 0; k < 3; ++k)
    {
      mismatches +=
        static_cast<size_t>(ids->GetId(k)) != part.Triangles[3 * t + static_cast<size_t>(k)];
    }
  }
  EXPECT_EQ(mismatches, 0u);

  // Every target's deltas: VTK's point arrays target<i>_position.
  ASSERT_EQ(part.Targets.size(), 53u);
  EXPECT_EQ(part.Targets[26].Name, "jawOpen");
  for (size_t target = 0; target < part.Targets.size(); ++target)
  {
    const std::string name = "target" + std::to_string(target) + "_position";
    vtkDataArray* deltas = poly->GetPointData()->GetArray(name.c_str());
    ASSERT_NE(deltas, nullptr) << name;
    ASSERT_EQ(deltas->GetNumberOfComponents(), 3);
    double worstDelta = 0;
    for (vtkIdType i = 0; i < deltas->GetNumberOfTuples(); ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        worstDelta = std::max(worstDelta,
          std::abs(deltas->GetComponent(i, k) -
            part.Targets[target]
              .PositionDeltas[3 * static_cast<size_t>(i) + static_cast<size_t>(k)]));
      }
    }
    EXPECT_EQ(worstDelta, 0.0) << part.Targets[target].Name;
  }
}

TEST(GltfSceneCrossCheck, IctHeadPartsAndTransformsAgreeWithVtkGltfReader)
{
  const std::string file = FaceKit + "/ict_head_full53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit not found at " << FaceKit << " (set MORPHNODE_FACEKIT_DIR)";
  }
  // VTK 9.1 applies node transforms only together with the deformations (whose default
  // weights are all 0 in this file, so its garbage targets add nothing); without them its
  // points are in each node's own frame, as MorphNode's are with ApplyTransforms off.
  for (bool apply : { true, false })
  {
    morphnode::GltfLoadOptions options;
    options.ApplyTransforms = apply;
    const morphnode::GltfScene scene = morphnode::LoadGltfScene(file, options);
    const auto vtkParts = VtkParts(file, apply);
    ASSERT_EQ(scene.Parts.size(), 11u);
    ASSERT_EQ(vtkParts.size(), scene.Parts.size());
    for (size_t i = 0; i < scene.Parts.size(); ++i)
    {
      const morphnode::GltfPart& part = scene.Parts[i];
      vtkPolyData* poly = vtkParts[i];
      ASSERT_EQ(static_cast<size_t>(poly->GetNumberOfPoints()), part.GetNumberOfPoints())
        << part.Name;
      double worst = 0;
      for (vtkIdType p = 0; p < poly->GetNumberOfPoints(); ++p)
      {
        double x[3];
        poly->GetPoint(p, x);
        for (int k = 0; k < 3; ++k)
        {
          worst = std::max(worst,
            std::abs(x[k] - part.Positions[3 * static_cast<size_t>(p) + static_cast<size_t>(k)]));
        }
      }
      // VTK transforms in float, MorphNode in double then rounds to float.
      EXPECT_LT(worst, apply ? 1e-7 : 1e-12) << part.Name << (apply ? " (world)" : " (node frame)");
      EXPECT_EQ(static_cast<size_t>(poly->GetNumberOfPolys()), part.GetNumberOfTriangles())
        << part.Name;
    }
  }
}
