// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphSkinMapper: skinning in the vertex shader.
// - A two-joint bar built by hand: a square blended half and half between a joint that stays
//   and one moved 0.8 along x is drawn 0.4 to the right (read back pixels), one bound to a
//   joint turned 90 degrees about z lands where the turn puts it (and the mapper's bounds
//   follow); its normal is turned too (the lit colour matches the same square moved on the
//   CPU).
// - The shared MakeHuman avatar, framed on the face, head turned and eyes left: drawn once
//   re-skinned on the CPU (vtkMorphSkinFilter, plain mappers) and once posed only with this
//   mapper: the images agree within a tight threshold; the negative control, posed only and
//   drawn by plain mappers (the head not turned), differs clearly.
// - A new pose changes uniforms only: no shader source built per frame.
// - A damaged convention (wrong tuple count, NaN deltas, 8 influences): an error, nothing
//   drawn; too many joints for the uniforms: drawn as given, with a warning.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphSkinMapper.h"
#include "vtkMorphTargetReader.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"
#include "vtkWindowToImageFilter.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>
#include <vector>

namespace
{
const std::string Avatar = morphnode_test::AvatarFile();

using Delta = std::array<float, 12>; // rows of a 3x4

Delta Identity()
{
  return { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0 };
}

/// A square of side 0.2 centred at (cx, cy) in z = 0, facing +z, its 4 points bound to
/// joints (j0, j1) with weights (w, 1 - w), and a skin of `deltas`.
vtkSmartPointer<vtkPolyData> Square(double cx, double cy, int j0, int j1, float w,
  const std::vector<Delta>& deltas, bool withDeltas = true)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  vtkNew<vtkUnsignedShortArray> joints;
  joints->SetName("SkinJoints");
  joints->SetNumberOfComponents(4);
  vtkNew<vtkFloatArray> weights;
  weights->SetName("SkinWeights");
  weights->SetNumberOfComponents(4);
  for (auto [dx, dy] : { std::pair{ -0.1, -0.1 }, { 0.1, -0.1 }, { 0.1, 0.1 }, { -0.1, 0.1 } })
  {
    points->InsertNextPoint(cx + dx, cy + dy, 0.0);
    normals->InsertNextTuple3(0, 0, 1);
    const unsigned short j[4] = { static_cast<unsigned short>(j0), static_cast<unsigned short>(j1),
      0, 0 };
    joints->InsertNextTypedTuple(j);
    const float wt[4] = { w, 1.0f - w, 0.0f, 0.0f };
    weights->InsertNextTypedTuple(wt);
  }
  vtkNew<vtkCellArray> polys;
  const vtkIdType quad[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, quad);
  poly->SetPoints(points);
  poly->SetPolys(polys);
  poly->GetPointData()->SetNormals(normals);
  poly->GetPointData()->AddArray(joints);
  poly->GetPointData()->AddArray(weights);
  vtkNew<vtkIntArray> indices;
  indices->SetName("SkinJointIndices");
  vtkNew<vtkFloatArray> d;
  d->SetName("SkinJointDeltas");
  d->SetNumberOfComponents(12);
  for (size_t k = 0; k < deltas.size(); ++k)
  {
    indices->InsertNextValue(static_cast<int>(k));
    d->InsertNextTypedTuple(deltas[k].data());
  }
  poly->GetFieldData()->AddArray(indices);
  if (withDeltas)
  {
    poly->GetFieldData()->AddArray(d);
  }
  return poly;
}

/// An orthographic view of [-1, 1]^2 (z = 0) in a 200 x 200 window: pixel (px, py) of a
/// point (x, y) is (100 (x + 1), 100 (y + 1)).
/// One offscreen window for the whole test program: VTK 9.1 opens an X connection per
/// window, and opening a dozen in a row now and then fails ("bad X server connection").
vtkRenderWindow* SharedWindow()
{
  static vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  return window;
}

struct View
{
  vtkRenderWindow* Window = SharedWindow();
  vtkNew<vtkRenderer> Renderer;
  int Size[2];
  View(int w = 200, int h = 200)
    : Size{ w, h }
  {
    this->Show();
    this->Renderer->SetBackground(0, 0, 0);
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    camera->SetParallelScale(1.0);
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(0, 0, 5);
    camera->SetViewUp(0, 1, 0);
    this->Renderer->ResetCameraClippingRange(-2, 2, -2, 2, -2, 2);
  }
  ~View() { this->Window->RemoveRenderer(this->Renderer); }
  /// This view's renderer alone in the window, at its size.
  void Show()
  {
    if (this->Window->HasRenderer(this->Renderer) &&
      this->Window->GetRenderers()->GetNumberOfItems() == 1)
    {
      return;
    }
    this->Window->GetRenderers()->InitTraversal();
    while (vtkRenderer* other = this->Window->GetRenderers()->GetNextItem())
    {
      this->Window->RemoveRenderer(other);
      this->Window->GetRenderers()->InitTraversal();
    }
    this->Window->SetSize(this->Size[0], this->Size[1]);
    this->Window->AddRenderer(this->Renderer);
  }
  vtkActor* Add(vtkPolyDataMapper* mapper, vtkPolyData* poly)
  {
    mapper->SetInputData(poly);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    this->Renderer->AddActor(actor);
    return actor;
  }
  /// The window's RGB pixels after a render.
  vtkSmartPointer<vtkImageData> Grab()
  {
    this->Show();
    this->Window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(this->Window);
    grab->SetInputBufferTypeToRGB();
    grab->ReadFrontBufferOff();
    grab->Update();
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->DeepCopy(grab->GetOutput());
    return image;
  }
};

/// The pixel of a point (x, y) of View's square [-1, 1]^2: its red, green, blue summed.
int Lit(vtkImageData* image, double x, double y)
{
  const int px = static_cast<int>(std::lround(100.0 * (x + 1.0)));
  const int py = static_cast<int>(std::lround(100.0 * (y + 1.0)));
  auto* p = static_cast<unsigned char*>(image->GetScalarPointer(px, py, 0));
  return p[0] + p[1] + p[2];
}

/// Pixels that differ by more than `tolerance` in some channel, as a fraction, within the
/// pixels either image covers (not background).
double Differing(vtkImageData* a, vtkImageData* b, int tolerance, double* meanDiff = nullptr)
{
  auto* pa = vtkUnsignedCharArray::SafeDownCast(a->GetPointData()->GetScalars());
  auto* pb = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetScalars());
  EXPECT_EQ(pa->GetNumberOfValues(), pb->GetNumberOfValues());
  vtkIdType covered = 0, differ = 0;
  double sum = 0.0;
  for (vtkIdType i = 0; i + 2 < pa->GetNumberOfValues(); i += 3)
  {
    int d = 0, any = 0;
    for (int c = 0; c < 3; ++c)
    {
      d = std::max(d, std::abs(int(pa->GetValue(i + c)) - int(pb->GetValue(i + c))));
      any += pa->GetValue(i + c) + pb->GetValue(i + c);
    }
    if (any > 0)
    {
      ++covered;
      differ += d > tolerance ? 1 : 0;
      sum += d;
    }
  }
  if (meanDiff)
  {
    *meanDiff = covered ? sum / double(covered) : 0.0;
  }
  return covered ? double(differ) / double(covered) : 0.0;
}

TEST(MorphSkinMapper, KnownVerticesGoWhereTheirJointsPutThem)
{
  // Joint 0 stays, joint 1 moves 0.8 along +x, joint 2 turns 90 degrees about z.
  Delta moved = Identity();
  moved[3] = 0.8f;
  const Delta turned = { 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0 };
  const std::vector<Delta> deltas = { Identity(), moved, turned };
  View view;
  vtkNew<vtkMorphSkinMapper> blended, rigid;
  // Blended half and half: the square at (-0.5, 0.5) is drawn at (-0.1, 0.5).
  view.Add(blended, Square(-0.5, 0.5, 0, 1, 0.5f, deltas));
  // Bound to the turned joint: the square at (0.5, -0.5) is drawn at (0.5, 0.5)
  // (x, y) -> (-y, x).
  view.Add(rigid, Square(0.5, -0.5, 2, 2, 1.0f, deltas));
  auto image = view.Grab();
  EXPECT_EQ(blended->GetSkinState(), vtkMorphSkinMapper::SKIN_GPU);
  EXPECT_EQ(blended->GetNumberOfJoints(), 3);
  EXPECT_EQ(Lit(image, -0.5, 0.5), 0);  // not at rest
  EXPECT_GT(Lit(image, -0.1, 0.5), 60); // halfway to the joint
  EXPECT_EQ(Lit(image, 0.3, 0.5), 0);   // nor where joint 1 alone would put it
  EXPECT_EQ(Lit(image, 0.5, -0.5), 0);
  EXPECT_GT(Lit(image, 0.5, 0.5), 60);
  // Edges within a pixel: the blended square spans x in [-0.2, 0.0].
  EXPECT_GT(Lit(image, -0.19, 0.5), 60);
  EXPECT_EQ(Lit(image, -0.23, 0.5), 0);
  EXPECT_GT(Lit(image, -0.01, 0.5), 60);
  EXPECT_EQ(Lit(image, 0.03, 0.5), 0);
  // The bounds hold where the squares are drawn: the blended one between its joints' images
  // (x in [-0.6, 0.4]), the turned one where the turn puts it.
  double bounds[6];
  blended->GetBounds(bounds);
  EXPECT_NEAR(bounds[0], -0.6, 1e-6);
  EXPECT_NEAR(bounds[1], 0.4, 1e-6);
  EXPECT_NEAR(bounds[2], 0.4, 1e-6);
  EXPECT_NEAR(bounds[3], 0.6, 1e-6);
  rigid->GetBounds(bounds);
  EXPECT_NEAR(bounds[0], 0.4, 1e-6);
  EXPECT_NEAR(bounds[1], 0.6, 1e-6);
  EXPECT_NEAR(bounds[2], 0.4, 1e-6);
  EXPECT_NEAR(bounds[3], 0.6, 1e-6);

  // The normal: a joint that tilts the square 60 degrees about y darkens it as the same
  // square tilted on the CPU.
  const double c = 0.5, s = std::sqrt(3.0) / 2.0;
  const Delta tilt = { float(c), 0, float(s), 0, 0, 1, 0, 0, float(-s), 0, float(c), 0 };
  View gpu, cpu;
  vtkNew<vtkMorphSkinMapper> tilted;
  gpu.Add(tilted, Square(0, 0, 1, 1, 1.0f, { Identity(), tilt }));
  auto moved2 = Square(0, 0, 1, 1, 1.0f, { Identity(), tilt }, false);
  for (vtkIdType i = 0; i < 4; ++i)
  {
    double p[3];
    moved2->GetPoint(i, p);
    moved2->GetPoints()->SetPoint(i, c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2]);
    moved2->GetPointData()->GetNormals()->SetTuple3(i, s, 0, c);
  }
  vtkNew<vtkPolyDataMapper> plain;
  cpu.Add(plain, moved2);
  auto a = gpu.Grab(), b = cpu.Grab();
  EXPECT_GT(Lit(b, 0, 0), 30);
  EXPECT_LT(Lit(b, 0, 0), Lit(image, 0.5, 0.5) - 30); // tilted: darker than facing the light
  EXPECT_NEAR(Lit(a, 0, 0), Lit(b, 0, 0), 6);
  EXPECT_LT(Differing(a, b, 8), 0.02);
}

TEST(MorphSkinMapper, APoseChangesUniformsOnly)
{
  Delta moved = Identity();
  auto poly = Square(0, 0, 1, 1, 1.0f, { Identity(), moved });
  View view;
  vtkNew<vtkMorphSkinMapper> mapper;
  view.Add(mapper, poly);
  view.Window->Render();
  const int builds = mapper->GetNumberOfShaderBuilds();
  EXPECT_GE(builds, 1);
  auto* d = vtkFloatArray::SafeDownCast(poly->GetFieldData()->GetArray("SkinJointDeltas"));
  for (int frame = 1; frame <= 10; ++frame)
  {
    d->SetComponent(1, 3, 0.05 * frame); // joint 1 moves along x
    d->Modified();
    poly->Modified();
    if (frame < 10)
    {
      view.Window->Render();
    }
  }
  auto image = view.Grab();
  EXPECT_EQ(mapper->GetNumberOfShaderBuilds(), builds);
  EXPECT_EQ(Lit(image, 0, 0), 0);
  EXPECT_GT(Lit(image, 0.5, 0), 60); // the last pose: 0.5 along x
  // Another number of joints builds the shader again, once.
  vtkNew<vtkFloatArray> three;
  three->DeepCopy(d);
  three->InsertNextTypedTuple(Identity().data());
  poly->GetFieldData()->AddArray(three);
  vtkNew<vtkIntArray> indices;
  indices->SetName("SkinJointIndices");
  for (int k = 0; k < 3; ++k)
  {
    indices->InsertNextValue(k);
  }
  poly->GetFieldData()->AddArray(indices);
  view.Window->Render();
  view.Window->Render();
  EXPECT_EQ(mapper->GetNumberOfJoints(), 3);
  EXPECT_EQ(mapper->GetNumberOfShaderBuilds(), builds + 1);
}

TEST(MorphSkinMapper, DamagedConventionDrawsNothingAndSaysWhy)
{
  Delta moved = Identity();
  moved[3] = 0.5f;
  struct Case
  {
    const char* Name;
    std::function<void(vtkPolyData*)> Damage;
    const char* Message;
  };
  const std::vector<Case> cases = {
    { "wrong tuple count",
      [](vtkPolyData* p)
      {
        auto* d = vtkFloatArray::SafeDownCast(p->GetFieldData()->GetArray("SkinJointDeltas"));
        d->InsertNextTypedTuple(Identity().data());
      },
      "SkinJointDeltas has 3 joints, the skin (SkinJointIndices) 2" },
    { "NaN deltas",
      [](vtkPolyData* p)
      {
        p->GetFieldData()
          ->GetArray("SkinJointDeltas")
          ->SetComponent(1, 5, std::numeric_limits<double>::quiet_NaN());
      },
      "SkinJointDeltas of joint 1 is not finite" },
    { "8 influences",
      [](vtkPolyData* p)
      {
        vtkNew<vtkFloatArray> w;
        w->SetName("SkinWeights");
        w->SetNumberOfComponents(8);
        w->SetNumberOfTuples(4);
        w->Fill(0.125);
        p->GetPointData()->AddArray(w);
      },
      "SkinJoints and SkinWeights must give 4 influences" },
    { "12 components",
      [](vtkPolyData* p)
      {
        vtkNew<vtkFloatArray> d;
        d->SetName("SkinJointDeltas");
        d->SetNumberOfComponents(9);
        d->SetNumberOfTuples(2);
        d->Fill(0.0);
        p->GetFieldData()->AddArray(d);
      },
      "SkinJointDeltas must be a vtkFloatArray of 12 components" },
  };
  for (const Case& c : cases)
  {
    auto poly = Square(0, 0, 1, 1, 1.0f, { Identity(), moved });
    c.Damage(poly);
    View view;
    vtkNew<vtkMorphSkinMapper> mapper;
    view.Add(mapper, poly);
    testing::internal::CaptureStderr();
    auto image = view.Grab();
    view.Window->Render(); // said once
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find(c.Message), std::string::npos) << c.Name << ": " << err;
    EXPECT_NE(err.find("nothing drawn"), std::string::npos) << c.Name;
    EXPECT_EQ(err.find(c.Message), err.rfind(c.Message)) << c.Name << ": said once";
    EXPECT_EQ(mapper->GetSkinState(), vtkMorphSkinMapper::SKIN_DAMAGED) << c.Name;
    EXPECT_EQ(Lit(image, 0, 0), 0) << c.Name;
    EXPECT_EQ(Lit(image, 0.5, 0), 0) << c.Name;
  }

  // Too many joints for the uniforms: drawn as given (at rest), with a warning.
  auto poly = Square(0, 0, 1, 1, 1.0f, { Identity(), moved });
  View view;
  vtkNew<vtkMorphSkinMapper> mapper;
  mapper->SetMaxJoints(1);
  view.Add(mapper, poly);
  testing::internal::CaptureStderr();
  auto image = view.Grab();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("the skin has 2 joints, the vertex shader takes 1"), std::string::npos) << err;
  EXPECT_EQ(mapper->GetSkinState(), vtkMorphSkinMapper::SKIN_TOO_MANY_JOINTS);
  EXPECT_GT(Lit(image, 0, 0), 60);

  // Without deltas: a plain mapper.
  vtkNew<vtkMorphSkinMapper> plain;
  View view2;
  view2.Add(plain, Square(0, 0, 1, 1, 1.0f, { Identity(), moved }, false));
  auto image2 = view2.Grab();
  EXPECT_EQ(plain->GetSkinState(), vtkMorphSkinMapper::SKIN_NONE);
  EXPECT_GT(Lit(image2, 0, 0), 60);

  std::ostringstream os;
  mapper->Print(os);
  EXPECT_NE(os.str().find("SkinState: too many joints"), std::string::npos) << os.str();
}

/// The avatar's parts after the skin filter, drawn by mappers of `Mapper`, framed on the face
/// (head bounds from the filter), 240 x 240.
template <typename Mapper>
vtkSmartPointer<vtkImageData> DrawAvatar(vtkMorphSkinFilter* skin, int* gpuParts = nullptr)
{
  EXPECT_EQ(skin->GetExecutive()->Update(), 1);
  double b[6];
  EXPECT_TRUE(skin->GetHeadBounds(b));
  View view(240, 240);
  view.Renderer->SetBackground(0, 0, 0);
  std::vector<vtkSmartPointer<Mapper>> mappers;
  auto* composite = vtkCompositeDataSet::SafeDownCast(skin->GetOutputDataObject(0));
  for (vtkPolyData* poly : vtkCompositeDataSet::GetDataSets<vtkPolyData>(composite))
  {
    auto mapper = vtkSmartPointer<Mapper>::New();
    mapper->ScalarVisibilityOff();
    view.Add(mapper, poly)->GetProperty()->SetColor(0.86, 0.72, 0.62);
    mappers.push_back(mapper);
  }
  const double cx = (b[0] + b[1]) / 2, cy = (b[2] + b[3]) / 2, cz = (b[4] + b[5]) / 2;
  const double h = b[3] - b[2];
  vtkCamera* camera = view.Renderer->GetActiveCamera();
  camera->ParallelProjectionOff();
  camera->SetViewAngle(30);
  camera->SetFocalPoint(cx, cy, cz);
  camera->SetPosition(cx, cy, cz + 2.6 * h);
  camera->SetViewUp(0, 1, 0);
  view.Renderer->ResetCameraClippingRange();
  auto image = view.Grab();
  if (gpuParts)
  {
    *gpuParts = 0;
    for (auto& m : mappers)
    {
      if constexpr (std::is_same_v<Mapper, vtkMorphSkinMapper>)
      {
        *gpuParts += m->GetSkinState() == vtkMorphSkinMapper::SKIN_GPU ? 1 : 0;
      }
    }
  }
  return image;
}

TEST(MorphSkinMapper, AvatarOnTheGpuLooksAsReskinnedOnTheCpu)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(Avatar.c_str());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  morph->SetWeightByName("jawOpen", 0.6);
  vtkNew<vtkMorphSkinFilter> skin;
  skin->SetInputConnection(morph->GetOutputPort());
  skin->SetHeadYaw(25);
  skin->SetHeadPitch(-8);
  skin->SetEyeYaw(25);

  auto cpu = DrawAvatar<vtkPolyDataMapper>(skin);
  skin->SkinPointsOff();
  int gpuParts = 0;
  auto gpu = DrawAvatar<vtkMorphSkinMapper>(skin, &gpuParts);
  EXPECT_EQ(skin->GetNumberOfPosedOnlyParts(), 7);
  EXPECT_EQ(skin->GetNumberOfCPUSkinnedParts(), 0);
  EXPECT_EQ(gpuParts, 7);
  auto control = DrawAvatar<vtkPolyDataMapper>(skin);
  double mean = 0.0, meanControl = 0.0;
  const double same = Differing(cpu, gpu, 24, &mean);
  const double differ = Differing(cpu, control, 24, &meanControl);
  std::cout << "GPU vs CPU: " << 100.0 * same << " % of pixels differ by more than 24, mean "
            << mean << "; posed only, drawn as given: " << 100.0 * differ << " %, mean "
            << meanControl << "\n";
  EXPECT_LT(same, 0.003) << "mean " << mean;
  EXPECT_LT(mean, 1.0);
  EXPECT_GT(differ, 0.10) << "mean " << meanControl; // the head not turned
  EXPECT_GT(meanControl, 8.0);
  if (HasFailure() || std::getenv("MORPHNODE_KEEP_IMAGES"))
  {
    // (Look at them when the test fails.)
    std::filesystem::create_directories(MORPHNODE_TEST_OUTPUT_DIR);
    for (auto [name, image] : { std::pair{ "cpu", cpu }, { "gpu", gpu }, { "control", control } })
    {
      vtkNew<vtkPNGWriter> writer;
      writer->SetInputData(image);
      writer->SetFileName(
        (std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/skin_mapper_" + name + ".png").c_str());
      writer->Write();
    }
  }
}
} // namespace
