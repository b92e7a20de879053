// SPDX-License-Identifier: BSD-3-Clause
// Contact sheets of the paper's 13 morph targets (Table 1 order, each at weight 1): the
// default head (every part, in its colours) with its own targets, and the ICT face with the paper's
// shapes baked through the ARKit rig. Offscreen render tests against Testing/Baseline/*.png; run
// under `xvfb-run -a`. The rendered sheets are also written to the test output directory.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigBaker.h"
#include "vtkMorphTargetReader.h"

#include "HeadActors.h"
#include "MorphNodeTestUtilities.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkPNGWriter.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <vector>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
const std::string ArkitRig = std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json";
const std::string DefaultFace =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
const char* const PaperShapes[13] = { "Neutral", "EyesClosed", "BrowsUp", "S", "F", "BrowsFright",
  "BrowsAngry", "L", "E", "A", "MouthSmile", "MouthSad", "O" };
constexpr int Columns = 5;
constexpr int Rows = 3;
constexpr int CellWidth = 200;
constexpr int CellHeight = 230;

struct View
{
  double Zoom = 1.0;
  double Elevation = 0.0;
  double Azimuth = 0.0;
};

/// VTK's legacy image metric with a per-channel tolerance of 24 levels
/// (morphnode_test::SensitiveBaselineError; glTF materials drawn gamma-correct are too pale
/// for vtkTesting's 105). Measured with the "O" cell showing "A" (MouthSwappedFailsTheBaseline)
/// the default head's sheet scores 11.8; the baselines' own renders score 0.
constexpr double Threshold = 0.5;

/// Renders the 13 shapes of `face` (a dataset with relative targets named as in Table 1)
/// into a 5 x 3 grid, one renderer per cell sharing one camera, and compares with the
/// baseline. Returns the largest point displacement of each shape (neutral first).
/// Negative control: with `shapeInOCell` the last cell (labelled "O") shows that shape
/// instead, and the comparison must fail.
std::vector<double> RenderSheet(vtkAlgorithmOutput* face, const View& view,
  const std::string& title, const std::string& baseline, const char* shapeInOCell = nullptr)
{
  vtkNew<vtkRenderWindow> window;
  window->SetSize(Columns * CellWidth, Rows * CellHeight);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  vtkNew<vtkCamera> camera;
  std::vector<vtkSmartPointer<vtkMorphNodeFilter>> keep;
  std::vector<double> moved;
  std::vector<vtkPolyData*> neutral;
  std::vector<std::unique_ptr<morphnode::appkit::HeadActors>> heads;
  for (int cell = 0; cell < Columns * Rows; ++cell)
  {
    const int col = cell % Columns;
    const int row = cell / Columns;
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(static_cast<double>(col) / Columns,
      1.0 - static_cast<double>(row + 1) / Rows, static_cast<double>(col + 1) / Columns,
      1.0 - static_cast<double>(row) / Rows);
    renderer->SetBackground(0.15, 0.16, 0.2);
    renderer->SetActiveCamera(camera);
    window->AddRenderer(renderer);
    if (cell >= 13)
    {
      if (cell == 14)
      {
        vtkNew<vtkTextActor> text;
        text->SetInput(title.c_str());
        text->GetTextProperty()->SetFontSize(15);
        text->GetTextProperty()->SetColor(0.8, 0.8, 0.8);
        text->GetTextProperty()->SetJustificationToRight();
        text->SetPosition(CellWidth - 10, 10);
        renderer->AddViewProp(text);
      }
      continue;
    }
    auto morph = vtkSmartPointer<vtkMorphNodeFilter>::New();
    morph->SetInputConnection(face);
    morph->SetWeightModeToRelative();
    if (cell > 0)
    {
      morph->SetWeightByName(cell == 12 && shapeInOCell ? shapeInOCell : PaperShapes[cell], 1.0);
    }
    morph->Update();
    keep.push_back(morph);
    // A head of parts (a composite) or one mesh: its parts, in the input's order.
    const std::vector<vtkPolyData*> out =
      morphnode::appkit::HeadParts(morph->GetOutputDataObject(0));
    if (out.empty())
    {
      ADD_FAILURE() << "the morph output has no polydata part";
      return moved;
    }
    if (cell == 0)
    {
      neutral = out;
    }
    double worst = 0.0;
    for (size_t k = 0; k < out.size() && k < neutral.size(); ++k)
    {
      for (vtkIdType i = 0; i < out[k]->GetNumberOfPoints(); ++i)
      {
        double p[3], q[3];
        out[k]->GetPoint(i, p);
        neutral[k]->GetPoint(i, q);
        worst = std::max(worst,
          std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
            (p[2] - q[2]) * (p[2] - q[2])));
      }
    }
    moved.push_back(worst);

    // Every part in its own colour (a face without materials is skin-coloured), as the
    // avatar draws it (AppKit/HeadActors).
    heads.push_back(std::make_unique<morphnode::appkit::HeadActors>());
    EXPECT_TRUE(heads.back()->Build(morph->GetOutputDataObject(0), renderer, nullptr))
      << PaperShapes[cell];
    // The avatar's lights; no image-based lighting, which takes seconds per cell to prepare.
    morphnode::appkit::HeadActors::SetUpLights(renderer, false);
    renderer->GradientBackgroundOff();

    vtkNew<vtkTextActor> label;
    label->SetInput(PaperShapes[cell]);
    label->GetTextProperty()->SetFontSize(18);
    label->GetTextProperty()->SetColor(1.0, 1.0, 1.0);
    label->GetTextProperty()->BoldOn();
    label->SetPosition(8, 6);
    renderer->AddViewProp(label);

    if (cell == 0)
    {
      // One camera for all cells, framed on the neutral.
      renderer->ResetCamera();
      camera->Azimuth(view.Azimuth);
      camera->Elevation(view.Elevation);
      camera->OrthogonalizeViewUp();
      camera->Zoom(view.Zoom);
    }
  }
  for (int r = 0; r < window->GetRenderers()->GetNumberOfItems(); ++r)
  {
    static_cast<vtkRenderer*>(window->GetRenderers()->GetItemAsObject(r))
      ->ResetCameraClippingRange();
  }
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  const std::string written = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/" +
    (shapeInOCell ? std::string("Swapped") : std::string()) + baseline;
  writer->SetFileName(written.c_str());
  writer->Write();

  const std::string expected = std::string(MORPHNODE_BASELINE_DIR) + "/" + baseline;
  const double error =
    morphnode_test::SensitiveBaselineError(window, expected, MORPHNODE_TEST_OUTPUT_DIR);
  std::cout << "image error against " << baseline << (shapeInOCell ? " (O cell swapped): " : ": ")
            << error << "\n";
  if (shapeInOCell)
  {
    EXPECT_GT(error, Threshold) << "the comparison does not see the mouth of the O cell";
    EXPECT_FALSE(error >= 0 && error <= Threshold);
  }
  else
  {
    EXPECT_TRUE(error >= 0 && error <= Threshold) << "rendered sheet: " << written;
  }
  return moved;
}

void CheckEveryShapeMoves(const std::vector<double>& moved)
{
  ASSERT_EQ(moved.size(), 13u);
  EXPECT_EQ(moved[0], 0.0);
  for (size_t i = 1; i < moved.size(); ++i)
  {
    EXPECT_GT(moved[i], 0.0) << PaperShapes[i] << " does not move the face";
  }
}
} // namespace

TEST(MorphRigContactSheet, DefaultFace)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultFace.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetNumberOfTargets(), 13);
  CheckEveryShapeMoves(RenderSheet(reader->GetOutputPort(), View{ 1.9, 0.0, 20.0 }, "default head",
    "TestRigContactSheetDefaultFace.png"));
}

// Negative control: the default face's sheet with "A" in the cell labelled "O" (another
// mouth, everything else equal) must fail the comparison at the threshold used above.
TEST(MorphRigContactSheet, MouthSwappedFailsTheBaseline)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultFace.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetNumberOfTargets(), 13);
  RenderSheet(reader->GetOutputPort(), View{ 1.9, 0.0, 20.0 }, "default head",
    "TestRigContactSheetDefaultFace.png", "A");
}

TEST(MorphRigContactSheet, IctFaceThroughArkitRig)
{
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0);
  vtkNew<vtkMorphRigBaker> baker;
  baker->SetInputConnection(reader->GetOutputPort());
  baker->SetRigFileName(ArkitRig.c_str());
  baker->SetShapeSet("paper");
  baker->Update();
  CheckEveryShapeMoves(RenderSheet(baker->GetOutputPort(), View{ 1.6, 5.0, 20.0 },
    "ICT face, ARKit rig", "TestRigContactSheetIctFace.png"));
}
