// SPDX-License-Identifier: BSD-3-Clause
// The shared MakeHuman avatar drawn as MorphAvatar draws it (vtkMorphTargetReader ->
// vtkMorphNodeFilter -> vtkMorphSkinFilter -> AppKit/HeadActors, framed on the face from its
// head joint, AppKit/Framing.h), saying "O" (viseme_O, jawOpen 0.45) with the eyes turned 30
// degrees to its left by the eye joints, compared with a baseline. Two negative controls must fail
// at the same threshold: the eyes not turned, and the mouth at rest. Textures are not drawn here,
// so the test paints each eyeball's iris (the points within 35 degrees of its rest forward
// direction) dark as vertex colours; they turn with the eye as a texture would. Run under `xvfb-run
// -a`.
#include "Framing.h"
#include "HeadActors.h"
#include "MorphNodeTestUtilities.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

namespace
{
namespace appkit = morphnode::appkit;
const std::string Avatar = morphnode_test::AvatarFile();
const std::string Output = MORPHNODE_TEST_OUTPUT_DIR;
const std::string BaselineName = "TestAvatarRenderEyesLeftO.png";

/// VTK's legacy image metric. Measured (the test prints them): the baseline's own render 0,
/// the eyes not turned 14.4, the mouth at rest 58.3. The threshold of the other render
/// tests (0.5) lies far below both controls.
constexpr double Threshold = 0.5;

/// Dark irises as COLOR_0 on the eye parts of the reader's output (in place: the test owns it).
void PaintIrises(vtkDataObject* head)
{
  for (vtkPolyData* part : appkit::HeadParts(head))
  {
    const std::string name = vtkMorphPartData::GetPartName(part->GetFieldData());
    if (name.rfind("Eye", 0) != 0 || name.find("lash") != std::string::npos ||
      name.find("brow") != std::string::npos)
    {
      continue;
    }
    double b[6];
    part->GetBounds(b);
    // The eyeball's centre: the middle of its bounds in x and y, its back plus the radius in z.
    const double r = 0.25 * ((b[1] - b[0]) + (b[3] - b[2]));
    const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), b[4] + r };
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetName("COLOR_0");
    colours->SetNumberOfComponents(4);
    colours->SetNumberOfTuples(part->GetNumberOfPoints());
    for (vtkIdType i = 0; i < part->GetNumberOfPoints(); ++i)
    {
      const double* p = part->GetPoint(i);
      const double d[3] = { p[0] - c[0], p[1] - c[1], p[2] - c[2] };
      const double cosine = d[2] / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const bool iris = cosine > std::cos(35.0 * M_PI / 180.0);
      const unsigned char rgba[4] = { static_cast<unsigned char>(iris ? 60 : 245),
        static_cast<unsigned char>(iris ? 35 : 245), static_cast<unsigned char>(iris ? 20 : 240),
        255 };
      colours->SetTypedTuple(i, rgba);
    }
    part->GetPointData()->AddArray(colours);
  }
}

struct Scene
{
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkMorphSkinFilter> Skin;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  appkit::HeadActors Head;
};

std::unique_ptr<Scene> Render(double o, double eyeYaw)
{
  auto s = std::make_unique<Scene>();
  s->Reader->SetFileName(Avatar.c_str());
  s->Reader->Update();
  PaintIrises(s->Reader->GetOutputDataObject(0));
  s->Morph->SetInputConnection(s->Reader->GetOutputPort());
  s->Morph->SetWeightModeToRelative();
  // "O" as a speaker says it: the viseme with the jaw open (viseme_O alone barely parts the lips).
  s->Morph->SetWeightByName("viseme_O", o);
  s->Morph->SetWeightByName("jawOpen", 0.45 * o);
  s->Skin->SetInputConnection(s->Morph->GetOutputPort());
  s->Skin->SetEyeYaw(eyeYaw);
  s->Skin->RelaxArmsOn();
  s->Skin->Update();
  double head[6], all[6], box[6];
  EXPECT_TRUE(s->Skin->GetHeadBounds(head));
  EXPECT_TRUE(appkit::HeadBounds(s->Reader->GetOutputDataObject(0), all));
  appkit::FramingBox(head, all, "face", box);
  EXPECT_TRUE(s->Head.Build(s->Skin->GetOutputDataObject(0), s->Renderer, nullptr));
  s->Window->SetSize(400, 400);
  s->Window->SetMultiSamples(0);
  s->Window->OffScreenRenderingOn();
  s->Window->AddRenderer(s->Renderer);
  appkit::HeadActors::SetUpView(s->Renderer, box);
  s->Window->Render();
  return s;
}

double ErrorAgainstBaseline(vtkRenderWindow* window, const std::string& label)
{
  std::filesystem::create_directories(Output);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName((Output + "/" + label + "-render.png").c_str());
  writer->Write();
  // With the avatar's textures drawn, the irises' turn changes few pixels by less than the
  // render tests' usual 24 levels: a tolerance of 8 levels sees it (the negative control).
  const double error = morphnode_test::SensitiveBaselineError(
    window, std::string(MORPHNODE_BASELINE_DIR) + "/" + BaselineName, Output, 8);
  std::cout << label << " against " << BaselineName << ": image error " << error << "\n";
  return error;
}
} // namespace

TEST(AvatarRender, FramedOnTheFaceSayingOWithTheEyesLeft)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  auto scene = Render(1.0, 30.0);
  const double error = ErrorAgainstBaseline(scene->Window, "avatar-eyes-left-O");
  EXPECT_GE(error, 0.0) << "no baseline " << BaselineName;
  EXPECT_LT(error, Threshold);

  // Negative controls: each must fail the baseline at the same threshold.
  auto ahead = Render(1.0, 0.0);
  EXPECT_GT(ErrorAgainstBaseline(ahead->Window, "avatar-eyes-ahead-O"), Threshold)
    << "the eyes not turned";
  auto closed = Render(0.0, 30.0);
  EXPECT_GT(ErrorAgainstBaseline(closed->Window, "avatar-eyes-left-rest"), Threshold)
    << "the mouth at rest";
}
