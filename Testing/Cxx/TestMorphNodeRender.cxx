// SPDX-License-Identifier: BSD-3-Clause
// Offscreen render test: the ICT face morphed from the neutral to an expression, in three
// viewports (weights 0, 0.5, 1), against a baseline PNG. Run under `xvfb-run -a`.
#include "vtkMorphNodeFilter.h"

#include "MorphNodeTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataSetRange.h"
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
#include <iostream>
#include <vector>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

vtkSmartPointer<vtkPolyData> ReadTargets(const std::string& file)
{
  vtkNew<vtkGLTFReader> reader;
  reader->SetFileName(file.c_str());
  reader->ApplyDeformationsToGeometryOff();
  reader->Update();
  vtkCompositeDataSet* blocks = reader->GetOutput();
  for (vtkDataObject* leaf : vtk::Range(blocks, vtk::CompositeDataSetOptions::SkipEmptyNodes))
  {
    return vtkPolyData::SafeDownCast(leaf); // the first leaf
  }
  return nullptr;
}

/// The face morphed from the neutral to an expression in three viewports (weights 0, 0.5,
/// 1); `mouth` scales the mouth's targets (jaw open, funnelled lips), 1 for the baseline's.
/// Returns the active target count of each viewport.
std::vector<int> RenderFace(vtkPolyData* targets, vtkRenderWindow* window, double mouth)
{
  std::vector<int> active;
  const double amounts[3] = { 0.0, 0.5, 1.0 };
  for (int v = 0; v < 3; ++v)
  {
    auto makeMorph = [&](double mouthScale)
    {
      auto morph = vtkSmartPointer<vtkMorphNodeFilter>::New();
      morph->SetInputData(targets);
      morph->SetWeightModeToRelative();
      // Open jaw, funnelled lips, left eye closed, raised inner brows (glTF target k -> k+1).
      morph->SetWeight(26 + 1, 0.7 * mouthScale * amounts[v]);
      morph->SetWeight(33 + 1, 0.4 * mouthScale * amounts[v]);
      morph->SetWeight(10 + 1, 1.0 * amounts[v]);
      morph->SetWeight(2 + 1, 0.8 * amounts[v]);
      morph->SetWeight(3 + 1, 0.8 * amounts[v]);
      morph->Update();
      return morph;
    };
    auto morph = makeMorph(mouth);
    // The camera frames the baseline's face (mouth 1), so only the mouth differs.
    double bounds[6];
    makeMorph(1.0)->GetOutput()->GetBounds(bounds);
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
    renderer->ResetCamera(bounds);
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->Zoom(1.9);
    camera->Elevation(5);
    renderer->ResetCameraClippingRange();
    active.push_back(morph->GetActiveTargetCount());
  }
  window->Render();
  return active;
}

/// VTK's legacy image metric at VTK's usual threshold. Measured: the baseline's own
/// render 0, the same face without its mouth targets 55 (MouthlessFaceFailsTheBaseline).
constexpr double Threshold = 10.0;
const std::string Baseline = std::string(MORPHNODE_BASELINE_DIR) + "/TestMorphNodeRender.png";

vtkSmartPointer<vtkRenderWindow> MakeWindow()
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetSize(900, 400);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  return window;
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
  auto window = MakeWindow();
  EXPECT_EQ(RenderFace(targets, window, 1.0), std::vector<int>({ 0, 5, 5 }));
  std::cout << "image error against the baseline: "
            << morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR) << "\n";
  EXPECT_TRUE(
    morphnode_test::MatchesBaseline(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR, Threshold));
}

// Negative control: the same face with the mouth's targets off (jaw closed, lips not
// funnelled) must fail the comparison at the threshold used above: it sees the mouth.
TEST(MorphNodeRender, MouthlessFaceFailsTheBaseline)
{
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  auto targets = ReadTargets(IctGlb);
  ASSERT_TRUE(targets);
  auto window = MakeWindow();
  EXPECT_EQ(RenderFace(targets, window, 0.0), std::vector<int>({ 0, 3, 3 }));
  const double error = morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR);
  std::cout << "image error of the mouthless face against the baseline: " << error << "\n";
  EXPECT_GT(error, Threshold) << "the comparison does not see the mouth";
  EXPECT_FALSE(
    morphnode_test::MatchesBaseline(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR, Threshold));
}
