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

TEST(MorphDistanceRender, AnimatedRegionAndTargetDistances)
{
  const std::string ict = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  if (!std::ifstream(ict))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found";
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(ict.c_str());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->GenerateDistanceArraysOn();
  morph->Update();
  auto* face = vtkPolyData::SafeDownCast(morph->GetOutput());
  ASSERT_NE(face->GetPointData()->GetArray("AnimatedRegion"), nullptr);

  const char* panels[] = { "AnimatedRegion", "Distance_jawOpen", "Distance_mouthSmile_L",
    "Distance_eyeBlink_L", "Distance_browInnerUp_L" };
  const double regionMax = face->GetPointData()->GetArray("AnimatedRegion")->GetRange()[1];
  // The mouth and jaw move most on a face: the animated region peaks there, ~4 cm.
  EXPECT_GT(regionMax, 0.02);
  EXPECT_LT(regionMax, 0.1);

  vtkNew<vtkLookupTable> lut; // one colour scale for all panels, so they compare
  lut->SetHueRange(0.667, 0.0);
  lut->SetTableRange(0.0, regionMax);
  lut->Build();
  vtkNew<vtkRenderWindow> window;
  window->SetSize(1000, 260);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  for (int v = 0; v < 5; ++v)
  {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(face);
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray(panels[v]);
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
  EXPECT_TRUE(morphnode_test::MatchesBaseline(window,
    std::string(MORPHNODE_BASELINE_DIR) + "/TestMorphDistanceRender.png", MORPHNODE_TEST_OUTPUT_DIR));
}
