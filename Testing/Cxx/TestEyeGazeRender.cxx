// SPDX-License-Identifier: BSD-3-Clause
// Offscreen render test of gaze: the default head's eyes looking to the character's left
// (EyeYaw +30) and right (-30), close up, each part in its own colour, against a baseline
// PNG; negative controls (eyes straight, eyes looking the other ways) must fail the same
// comparison, so the threshold sees the eyes. Run under `xvfb-run -a`.
#include "vtkEyeGazeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkLight.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <iostream>

namespace
{
const std::string DefaultHead =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
const std::string Baseline = std::string(MORPHNODE_BASELINE_DIR) + "/TestEyeGazeRender.png";

/// VTK's legacy image metric at VTK's usual threshold. Measured: the baseline's own render
/// 0, eyes straight 34 (EyesStraightFailTheBaseline), eyes the other way 327
/// (EyesTheOtherWayFailTheBaseline).
constexpr double Threshold = 10.0;

/// One actor per part: its COLOR_0 where it has one, else its BaseColor.
void AddHead(vtkRenderer* renderer, vtkDataObject* head)
{
  auto* composite = vtkCompositeDataSet::SafeDownCast(head);
  ASSERT_TRUE(composite);
  for (vtkPolyData* pd : vtkCompositeDataSet::GetDataSets<vtkPolyData>(composite))
  {
    if (pd->GetNumberOfPoints() == 0)
    {
      continue;
    }
    // The glTF colour: BaseColor times COLOR_0 where the part has one.
    std::array<double, 4> base{ { 1.0, 1.0, 1.0, 1.0 } };
    vtkMorphPartData::GetNumbers(
      pd->GetFieldData(), vtkMorphPartData::BaseColorArray, base.data(), 4);
    vtkNew<vtkPolyDataMapper> mapper;
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    if (vtkDataArray* vertex = pd->GetPointData()->GetArray("COLOR_0"))
    {
      vtkNew<vtkPolyData> colored;
      colored->ShallowCopy(pd);
      vtkNew<vtkUnsignedCharArray> rgb;
      rgb->SetName("RGB");
      rgb->SetNumberOfComponents(3);
      rgb->SetNumberOfTuples(pd->GetNumberOfPoints());
      const double scale = 1.0 / vertex->GetDataTypeMax();
      for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
      {
        for (int c = 0; c < 3; ++c)
        {
          rgb->SetValue(3 * i + c,
            static_cast<unsigned char>(
              255.0 * base[c] * std::min(1.0, vertex->GetComponent(i, c) * scale) + 0.5));
        }
      }
      colored->GetPointData()->SetScalars(rgb);
      mapper->SetInputData(colored);
      mapper->SetColorModeToDirectScalars();
      mapper->ScalarVisibilityOn();
    }
    else
    {
      mapper->SetInputData(pd);
      mapper->ScalarVisibilityOff();
      actor->GetProperty()->SetColor(base.data());
    }
    actor->GetProperty()->SetSpecular(0.3);
    actor->GetProperty()->SetSpecularPower(30);
    renderer->AddActor(actor);
  }
}

/// The head with its eyes at `yaw[v]` degrees in viewport v (two viewports), close up on
/// the eyes.
vtkSmartPointer<vtkRenderWindow> Render(const double yaw[2], double pitch)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetSize(640, 200);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultHead.c_str());
  for (int v = 0; v < 2; ++v)
  {
    vtkNew<vtkEyeGazeFilter> gaze;
    gaze->SetInputConnection(reader->GetOutputPort());
    gaze->SetEyeYaw(yaw[v]);
    gaze->SetEyePitch(pitch);
    gaze->Update();
    EXPECT_EQ(gaze->GetNumberOfEyeParts(), 6);
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(v / 2.0, 0.0, (v + 1) / 2.0, 1.0);
    renderer->SetBackground(0.15, 0.16, 0.2);
    AddHead(renderer, gaze->GetOutputDataObject(0));
    window->AddRenderer(renderer);
    // In front of the eyes (at y 0.016, z 0.061 m), looking along -Z.
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->SetFocalPoint(0.0, 0.016, 0.06);
    camera->SetPosition(0.0, 0.02, 0.40);
    camera->SetViewUp(0.0, 1.0, 0.0);
    camera->SetViewAngle(10.0);
    renderer->ResetCameraClippingRange();
  }
  window->Render();
  return window;
}
} // namespace

TEST(EyeGazeRender, EyesLookLeftAndRight)
{
  const double yaw[2] = { 30.0, -30.0 };
  auto window = Render(yaw, 0.0);
  std::cout << "image error against the baseline: "
            << morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR) << "\n";
  EXPECT_TRUE(
    morphnode_test::MatchesBaseline(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR, Threshold));
}

// Negative control: the same head with the eyes straight must fail the comparison.
TEST(EyeGazeRender, EyesStraightFailTheBaseline)
{
  const double yaw[2] = { 0.0, 0.0 };
  auto window = Render(yaw, 0.0);
  const double error = morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR);
  std::cout << "image error of straight eyes against the baseline: " << error << "\n";
  EXPECT_GT(error, Threshold) << "the comparison does not see the eyes";
}

// Negative control: left and right swapped (a sign error) must fail it too.
TEST(EyeGazeRender, EyesTheOtherWayFailTheBaseline)
{
  const double yaw[2] = { -30.0, 30.0 };
  auto window = Render(yaw, 0.0);
  const double error = morphnode_test::BaselineError(window, Baseline, MORPHNODE_TEST_OUTPUT_DIR);
  std::cout << "image error of eyes looking the other way against the baseline: " << error << "\n";
  EXPECT_GT(error, Threshold) << "the comparison does not see which way the eyes look";
}
