// SPDX-License-Identifier: BSD-3-Clause
// Offscreen render test: the ICT face morphed from the neutral to an expression, in three
// viewports (weights 0, 0.5, 1), against a baseline PNG. Run under `xvfb-run -a`.
#include "vtkMorphNodeFilter.h"

#include "MorphNodeTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataIterator.h"
#include "vtkGLTFReader.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataNormals.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

#include <gtest/gtest.h>

#include <fstream>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

vtkSmartPointer<vtkPolyData> ReadTargets(const std::string& file)
{
  vtkNew<vtkGLTFReader> reader;
  reader->SetFileName(file.c_str());
  reader->ApplyDeformationsToGeometryOff();
  reader->Update();
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(reader->GetOutput()->NewIterator());
  it->InitTraversal();
  return vtkPolyData::SafeDownCast(it->GetCurrentDataObject());
}
} // namespace

TEST(MorphNodeRender, FaceMorphedBetweenTargets)
{
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  auto targets = ReadTargets(IctGlb);
  ASSERT_TRUE(targets);

  vtkNew<vtkRenderWindow> window;
  window->SetSize(900, 400);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  std::vector<vtkSmartPointer<vtkMorphNodeFilter>> keep;
  const double amounts[3] = { 0.0, 0.5, 1.0 };
  for (int v = 0; v < 3; ++v)
  {
    auto morph = vtkSmartPointer<vtkMorphNodeFilter>::New();
    morph->SetInputData(targets);
    morph->SetWeightModeToRelative();
    // Open jaw, funnelled lips, left eye closed, raised inner brows (glTF target k -> weight k+1).
    morph->SetWeight(26 + 1, 0.7 * amounts[v]);
    morph->SetWeight(33 + 1, 0.4 * amounts[v]);
    morph->SetWeight(10 + 1, 1.0 * amounts[v]);
    morph->SetWeight(2 + 1, 0.8 * amounts[v]);
    morph->SetWeight(3 + 1, 0.8 * amounts[v]);
    keep.push_back(morph);
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputConnection(morph->GetOutputPort());
    normals->SplittingOff();
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(normals->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(0.86, 0.72, 0.62);
    actor->GetProperty()->SetSpecular(0.2);
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(v / 3.0, 0.0, (v + 1) / 3.0, 1.0);
    renderer->SetBackground(0.15, 0.16, 0.2);
    renderer->AddActor(actor);
    window->AddRenderer(renderer);
    mapper->Update();
    renderer->ResetCamera();
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->Zoom(1.9);
    camera->Elevation(5);
    renderer->ResetCameraClippingRange();
    EXPECT_EQ(morph->GetActiveTargetCount(), v == 0 ? 0 : 5);
  }
  window->Render();
  EXPECT_TRUE(morphnode_test::MatchesBaseline(window,
    std::string(MORPHNODE_BASELINE_DIR) + "/TestMorphNodeRender.png", MORPHNODE_TEST_OUTPUT_DIR));
}
