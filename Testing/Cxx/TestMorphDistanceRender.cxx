// SPDX-License-Identifier: BSD-3-Clause
// Distance maps (the paper's Figure 4) on the ICT face: the animated region and the
// per-vertex distance of four targets, coloured blue (still) to red (moving), against a
// baseline PNG. Run under `xvfb-run -a`.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkLookupTable.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iostream>

namespace
{
const char* const Panels[] = { "AnimatedRegion", "Distance_jawOpen", "Distance_mouthSmile_L",
  "Distance_eyeBlink_L", "Distance_browInnerUp_L" };
const std::string Baseline = std::string(MORPHNODE_BASELINE_DIR) + "/TestMorphDistanceRender.png";
/// VTK's legacy image metric at VTK's usual threshold. Measured: the baseline's own
/// render 0, with the mirrored smile's distances in one panel 323.
constexpr double Threshold = 10.0;

/// Five panels of `face` labelled with Panels, coloured by the arrays `colors`.
vtkSmartPointer<vtkRenderWindow> RenderPanels(
  vtkPolyData* face, vtkLookupTable* lut, const char* const colors[5])
{
  const char* const* panels = Panels;
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetSize(1000, 260);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  for (int v = 0; v < 5; ++v)
  {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(face);
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray(colors[v]);
    mapper->SetLookupTable(lut);
    mapper->UseLookupTableScalarRangeOn();
    mapper->ScalarVisibilityOn();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(v / 5.0, 0.0, (v + 1) / 5.0, 1.0);
    renderer->SetBackground(0.15, 0.16, 0.2);
    renderer->AddActor(actor);
    vtkNew<vtkTextActor> label;
    label->SetInput(panels[v]);
    label->GetTextProperty()->SetFontSize(12);
    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->SetPosition(0.04, 0.03);
    renderer->AddActor2D(label);
    if (v == 4)
    {
      vtkNew<vtkScalarBarActor> bar;
      bar->SetLookupTable(lut);
      bar->SetNumberOfLabels(3);
      bar->SetMaximumWidthInPixels(50);
      bar->SetPosition(0.78, 0.1);
      renderer->AddActor2D(bar);
    }
    window->AddRenderer(renderer);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Zoom(2.2);
    renderer->ResetCameraClippingRange();
  }
  window->Render();
  return window;
}

vtkSmartPointer<vtkPolyData> FaceWithDistances(const std::string& file)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetMeshIndex(0); // one mesh, one vtkPolyData
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->GenerateDistanceArraysOn();
  morph->Update();
  return vtkPolyData::SafeDownCast(morph->GetOutput());
}
} // namespace

TEST(MorphDistanceRender, AnimatedRegionAndTargetDistances)
{
  const std::string ict = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  if (!std::ifstream(ict))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  const auto face = FaceWithDistances(ict);
  ASSERT_TRUE(face);
  ASSERT_NE(face->GetPointData()->GetArray("AnimatedRegion"), nullptr);

  const double regionMax = face->GetPointData()->GetArray("AnimatedRegion")->GetRange()[1];
  // The mouth and jaw move most on a face: the animated region peaks there, ~4 cm.
  EXPECT_GT(regionMax, 0.02);
  EXPECT_LT(regionMax, 0.1);

  vtkNew<vtkLookupTable> lut; // one colour scale for all panels, so they compare
  lut->SetHueRange(0.667, 0.0);
  lut->SetTableRange(0.0, regionMax);
  lut->Build();
  const auto window = RenderPanels(face, lut, Panels);
  std::cout << "image error against the baseline: "
            << morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR) << "\n";
  EXPECT_TRUE(
    morphnode_test::MatchesBaseline(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR, Threshold));
}

// Negative control: the mouthSmile_L panel coloured by its mirror twin's distances
// (mouthSmile_R; labels unchanged) must fail the comparison at the threshold used above.
TEST(MorphDistanceRender, MirroredSmileFailsTheBaseline)
{
  const std::string ict = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  if (!std::ifstream(ict))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  const auto face = FaceWithDistances(ict);
  ASSERT_TRUE(face);
  ASSERT_NE(face->GetPointData()->GetArray("Distance_mouthSmile_R"), nullptr);
  vtkNew<vtkLookupTable> lut;
  lut->SetHueRange(0.667, 0.0);
  lut->SetTableRange(0.0, face->GetPointData()->GetArray("AnimatedRegion")->GetRange()[1]);
  lut->Build();
  const char* const colors[] = { Panels[0], Panels[1], "Distance_mouthSmile_R", Panels[3],
    Panels[4] };
  const auto window = RenderPanels(face, lut, colors);
  const double error = morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR);
  std::cout << "image error with mouthSmile_R for mouthSmile_L: " << error << "\n";
  EXPECT_GT(error, Threshold) << "the comparison does not see the mouthSmile_L panel";
  EXPECT_FALSE(
    morphnode_test::MatchesBaseline(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR, Threshold));
}
