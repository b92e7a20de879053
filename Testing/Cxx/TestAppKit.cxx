// SPDX-License-Identifier: BSD-3-Clause
// AppKit (Modules/Applications/AppKit), the code the programs share: the command-line
// option types and their messages, the head pose on a VTK transform, the ParaView time
// series.
#include "CommandLine.h"
#include "HeadActors.h"
#include "TimeSeriesWriter.h"

#include "vtkActor.h"
#include "vtkCompositeDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMapper.h"
#include "vtkMatrix4x4.h"
#include "vtkMorphAvatarPipeline.h"
#include "vtkMorphPartData.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSphereSource.h"
#include "vtkTable.h"
#include "vtkTransform.h"
#include "vtkUnsignedCharArray.h"
#include "vtkXMLMultiBlockDataReader.h"
#include "vtkXMLPolyDataReader.h"

#include "Messages.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace
{
using namespace morphnode;

/// Parses `args` into `app`; the error message, or "" when it parsed.
std::string Parse(CLI::App& app, std::vector<std::string> args)
{
  std::vector<char*> argv{ const_cast<char*>("program") };
  for (auto& a : args)
  {
    argv.push_back(a.data());
  }
  try
  {
    app.parse(static_cast<int>(argv.size()), argv.data());
  }
  catch (const CLI::ParseError& e)
  {
    return e.what();
  }
  return std::string();
}
} // namespace

TEST(AppKitCommandLine, NumbersInARange)
{
  double v = 0.5;
  CLI::App app;
  appkit::AddNumberOption(app, "--threshold", v, 0.0, 1.0, "");
  EXPECT_EQ(Parse(app, { "--threshold", "0.25" }), "");
  EXPECT_EQ(v, 0.25);
  EXPECT_EQ(Parse(app, { "--threshold", "2" }), "--threshold: must be in [0, 1], got 2");
  EXPECT_EQ(Parse(app, { "--threshold", "0,5" }), "--threshold: expects a number, got '0,5'");
  EXPECT_EQ(Parse(app, { "--threshold", "nan" }), "--threshold: expects a number, got 'nan'");
  EXPECT_EQ(v, 0.25) << "a refused value must not be stored";
}

TEST(AppKitCommandLine, SizesListsSeeds)
{
  int w = 1, h = 1;
  std::vector<double> list{ 0.1 };
  unsigned long long seed = 0;
  CLI::App app;
  appkit::AddSizeOption(app, "--size", w, h, "");
  appkit::AddNumberListOption(app, "--list", list, 0.0, 1.0, "");
  app.add_option("--seed", seed)->check(appkit::UnsignedInteger());
  EXPECT_EQ(Parse(app, { "--size", "320x240", "--list", "0.2,0.4", "--seed", "7" }), "");
  EXPECT_EQ(w, 320);
  EXPECT_EQ(h, 240);
  EXPECT_EQ(list, (std::vector<double>{ 0.2, 0.4 }));
  EXPECT_EQ(seed, 7u);
  for (const char* bad : { "12", "640x", "x480", "8x8", "100000x100" })
  {
    EXPECT_NE(Parse(app, { "--size", bad }).find("--size: expects WxH"), std::string::npos) << bad;
  }
  EXPECT_NE(
    Parse(app, { "--list", "0.2,abc" }).find("expects a number, got 'abc'"), std::string::npos);
  EXPECT_NE(Parse(app, { "--list", "0.2,3" }).find("must be in [0, 1]"), std::string::npos);
  EXPECT_NE(Parse(app, { "--seed", "-3" }).find("expects an unsigned integer"), std::string::npos);
}

TEST(AppKitCommandLine, OptimizerMethodsByPresetName)
{
  OptimizerPreset preset = OptimizerPreset::None;
  CLI::App app;
  appkit::AddOptimizerPresetOption(app, "--method", preset, "");
  EXPECT_EQ(Parse(app, { "--method", "fixed-remaining" }), "");
  EXPECT_EQ(preset, OptimizerPreset::FixedRemaining);
  EXPECT_EQ(Parse(app, { "--method", "4" }), "");
  EXPECT_EQ(preset, OptimizerPreset::ErrorBounded);
  EXPECT_NE(Parse(app, { "--method", "fixed+maximum" }).find("unknown optimizer method"),
    std::string::npos);
  EXPECT_EQ(appkit::OptimizerPresetChoices(),
    "0|none, 1|fixed-maximum, 2|fixed-remaining, 3|adjusted, 4|error-bounded");
}

TEST(HeadPoseFromWeights, TheTransformIsTheCoreConvention)
{
  // The head pose of every avatar program: vtkMorphAvatarPipeline::SetHeadPoseFromWeights
  // (AppKit had it until the pipeline was assembled in one class).
  vtkNew<vtkTable> weights;
  for (const auto& [name, value] : { std::pair<const char*, double>{ "HeadYaw", 12.0 },
         { "HeadPitch", -7.0 }, { "HeadRoll", 4.0 } })
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->InsertNextValue(value);
    weights->AddColumn(column);
  }
  const double pivot[3] = { 0.1, -0.2, 0.3 };
  vtkNew<vtkTransform> pose;
  vtkMorphAvatarPipeline::SetHeadPoseFromWeights(pose, weights, pivot);
  // The composition the programs used before the convention had one home: the same matrix.
  vtkNew<vtkTransform> before;
  before->Translate(pivot);
  before->RotateY(12.0);
  before->RotateX(7.0);
  before->RotateZ(-4.0);
  before->Translate(-pivot[0], -pivot[1], -pivot[2]);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      EXPECT_NEAR(
        pose->GetMatrix()->GetElement(i, j), before->GetMatrix()->GetElement(i, j), 1e-12);
    }
  }
  // No table, no angles: the identity.
  vtkMorphAvatarPipeline::SetHeadPoseFromWeights(pose, nullptr, pivot);
  EXPECT_TRUE(pose->GetMatrix()->IsIdentity());
  // Seen from the character: a yaw to its left moves the nose (+Z) towards +X.
  vtkNew<vtkTable> yaw;
  vtkNew<vtkDoubleArray> column;
  column->SetName("HeadYaw");
  column->InsertNextValue(30.0);
  yaw->AddColumn(column);
  const double origin[3] = { 0, 0, 0 };
  vtkMorphAvatarPipeline::SetHeadPoseFromWeights(pose, yaw, origin);
  double nose[3] = { 0, 0, 1 };
  pose->TransformPoint(nose, nose);
  EXPECT_GT(nose[0], 0.4);
}

TEST(AppKitTimeSeries, WritesTheCollectionAndTheSteps)
{
  const std::string dir = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/TestAppKitSeries";
  std::filesystem::remove_all(dir);
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  vtkPolyData* face = sphere->GetOutput();
  vtkNew<vtkTable> weights;
  vtkNew<vtkDoubleArray> column;
  column->SetName("A");
  column->InsertNextValue(0.75);
  weights->AddColumn(column);
  {
    appkit::TimeSeriesWriter series(dir + "/talk.pvd");
    series.Write(face, weights, 0.0);
    series.Write(face, nullptr, 0.5);
    series.Close();
  }
  EXPECT_EQ(face->GetFieldData()->GetNumberOfArrays(), 0) << "the input must not be modified";
  std::ifstream in(dir + "/talk.pvd");
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(xml.find("timestep=\"0\" group=\"\" part=\"0\" file=\"talk/face_00000.vtp\""),
    std::string::npos)
    << xml;
  EXPECT_NE(xml.find("timestep=\"0.5\" group=\"\" part=\"0\" file=\"talk/face_00001.vtp\""),
    std::string::npos)
    << xml;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir + "/talk/face_00000.vtp").c_str());
  reader->Update();
  vtkFieldData* fd = reader->GetOutput()->GetFieldData();
  ASSERT_NE(fd->GetArray("BehaviorWeights"), nullptr);
  EXPECT_EQ(fd->GetArray("BehaviorWeights")->GetTuple1(0), 0.75);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), face->GetNumberOfPoints());

  EXPECT_THROW(appkit::TimeSeriesWriter(dir + "/talk.vtp"), std::runtime_error);
}

namespace
{
/// A head of two parts as the reader gives it: a collection of one partitioned data set per
/// part, each with PartName, MaterialName and BaseColor; the second with COLOR_0.
vtkSmartPointer<vtkPartitionedDataSetCollection> TwoPartHead()
{
  auto head = vtkSmartPointer<vtkPartitionedDataSetCollection>::New();
  const char* names[2] = { "Head", "EyeLeft/Iris" };
  for (unsigned int i = 0; i < 2; ++i)
  {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(0.1 * i, 0, 0);
    sphere->SetRadius(i ? 0.02 : 0.1);
    sphere->Update();
    auto part = vtkSmartPointer<vtkPolyData>::New();
    part->DeepCopy(sphere->GetOutput());
    vtkMorphPartData::PartFields fields;
    fields.PartName = names[i];
    fields.MaterialName = i ? "Iris" : "Skin";
    fields.BaseColor = std::array<double, 4>{ i ? 0.4 : 0.8, 0.5, i ? 0.6 : 0.4, 1.0 };
    vtkMorphPartData::SetPartFields(part->GetFieldData(), fields);
    if (i == 1)
    {
      vtkNew<vtkUnsignedCharArray> color;
      color->SetName("COLOR_0");
      color->SetNumberOfComponents(4);
      for (vtkIdType p = 0; p < part->GetNumberOfPoints(); ++p)
      {
        const unsigned char c = p % 2 ? 255 : 0; // a pupil-dark and a full point in turn
        color->InsertNextTuple4(c, c, c, 255);
      }
      part->GetPointData()->AddArray(color);
    }
    vtkNew<vtkPartitionedDataSet> partitioned;
    partitioned->SetPartition(0, part);
    head->SetPartitionedDataSet(i, partitioned);
    head->GetMetaData(i)->Set(vtkCompositeDataSet::NAME(), names[i]);
  }
  return head;
}
} // namespace

TEST(AppKitTimeSeries, WritesEveryPartOfAHead)
{
  const std::string dir = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/TestAppKitHeadSeries";
  std::filesystem::remove_all(dir);
  auto head = TwoPartHead();
  {
    appkit::TimeSeriesWriter series(dir + "/talk.pvd");
    series.Write(head, nullptr, 0.25);
    series.Close();
  }
  std::ifstream in(dir + "/talk.pvd");
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(xml.find("timestep=\"0.25\" group=\"\" part=\"0\" file=\"talk/face_00000.vtm\""),
    std::string::npos)
    << xml;
  vtkNew<vtkXMLMultiBlockDataReader> reader;
  reader->SetFileName((dir + "/talk/face_00000.vtm").c_str());
  reader->Update();
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
  ASSERT_NE(blocks, nullptr);
  ASSERT_EQ(blocks->GetNumberOfBlocks(), 2u);
  EXPECT_STREQ(blocks->GetMetaData(1u)->Get(vtkCompositeDataSet::NAME()), "EyeLeft/Iris");
  auto* iris = vtkPolyData::SafeDownCast(blocks->GetBlock(1));
  ASSERT_NE(iris, nullptr);
  EXPECT_NE(iris->GetPointData()->GetArray("COLOR_0"), nullptr);
  ASSERT_NE(iris->GetFieldData()->GetArray("TimeValue"), nullptr);
  EXPECT_EQ(iris->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), 0.25);
  // The input keeps its own field data.
  auto* part = vtkPolyData::SafeDownCast(head->GetPartitionedDataSet(1)->GetPartition(0));
  EXPECT_EQ(part->GetFieldData()->GetArray("TimeValue"), nullptr);
}

TEST(AppKitHeadActors, OneActorPerPartInItsColours)
{
  auto head = TwoPartHead();
  double bounds[6];
  ASSERT_TRUE(appkit::HeadBounds(head, bounds));
  EXPECT_NEAR(bounds[0], -0.1, 5e-3); // the spheres' facets
  EXPECT_NEAR(bounds[1], 0.12, 5e-3);
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkTransform> pose;
  appkit::HeadActors actors;
  ASSERT_TRUE(actors.Build(head, renderer, pose));
  ASSERT_EQ(actors.GetNumberOfParts(), 2);
  EXPECT_EQ(actors.GetPartName(1), "EyeLeft/Iris");
  double rgb[3];
  actors.GetActor(0)->GetProperty()->GetColor(rgb);
  EXPECT_DOUBLE_EQ(rgb[0], 0.8);                                 // BaseColor
  EXPECT_EQ(actors.GetActor(0)->GetUserTransform(), pose.Get()); // one pose for all parts
  EXPECT_EQ(actors.GetActor(1)->GetUserTransform(), pose.Get());
  // COLOR_0 x BaseColor as the iris's point colours: a dark and a full point in turn.
  EXPECT_TRUE(actors.GetActor(1)->GetMapper()->GetScalarVisibility());
  EXPECT_FALSE(actors.GetActor(0)->GetMapper()->GetScalarVisibility());
  auto* shown =
    vtkPolyData::SafeDownCast(actors.GetActor(1)->GetMapper()->GetInputDataObject(0, 0));
  ASSERT_NE(shown, nullptr);
  auto* colors =
    vtkUnsignedCharArray::SafeDownCast(shown->GetPointData()->GetArray("DisplayColors"));
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->GetValue(0), 0);
  EXPECT_EQ(colors->GetValue(3), 102); // 0.4 x 255
  EXPECT_EQ(colors->GetValue(5), 153); // 0.6 x 255
  // The display copy, not the input, carries the colours.
  auto* part = vtkPolyData::SafeDownCast(head->GetPartitionedDataSet(1)->GetPartition(0));
  EXPECT_EQ(part->GetPointData()->GetArray("DisplayColors"), nullptr);
  // New geometry of the same parts is taken; other parts are refused.
  EXPECT_TRUE(actors.Update(head));
  vtkNew<vtkSphereSource> other;
  other->Update();
  EXPECT_FALSE(actors.Update(other->GetOutput()));
  // One mesh alone is a head of one part (a face without a material: skin).
  appkit::HeadActors single;
  vtkNew<vtkRenderer> renderer2;
  ASSERT_TRUE(single.Build(other->GetOutput(), renderer2, nullptr));
  single.GetActor(0)->GetProperty()->GetColor(rgb);
  EXPECT_DOUBLE_EQ(rgb[0], appkit::SkinColor[0]);
  // Nothing to show.
  appkit::HeadActors none;
  vtkNew<vtkPartitionedDataSetCollection> empty;
  EXPECT_FALSE(none.Build(empty, renderer2, nullptr));
}

// Content errors read `Program: what: why`: VTK's location, class and address go.
TEST(AppKit, ProgramMessagesDropVtkDecoration)
{
  using morphnode::appkit::ProgramMessage;
  EXPECT_EQ(
    ProgramMessage("ERROR: In /build/vtkMorphRigFilter.cxx, line 412\nvtkMorphRigFilter "
                   "(0x55d1c0ffee00): rig 'x.json': shape 'A', target 'jawOpn': unknown\n\n"),
    "rig 'x.json': shape 'A', target 'jawOpn': unknown");
  EXPECT_EQ(
    ProgramMessage("Warning: In a.cxx, line 3\nvtkBehaviorTimeSource (0x1): the voice is odd\n\n"),
    "the voice is odd");
  EXPECT_EQ(
    ProgramMessage("ERROR: In vtkExecutive.cxx, line 752\nvtkCompositeDataPipeline (0x5): "
                   "Algorithm vtkEyeGazeFilter(0x6) returned failure for request: vtkInformation"),
    "");
  EXPECT_EQ(ProgramMessage("plain text"), "plain text");
}
