// SPDX-License-Identifier: BSD-3-Clause
// AppKit (Modules/Applications/AppKit), the code the programs share: the command-line
// option types and their messages, the head pose on a VTK transform, the ParaView time
// series.
#include "CommandLine.h"
#include "HeadPoseTransform.h"
#include "TimeSeriesWriter.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkTable.h"
#include "vtkTransform.h"
#include "vtkXMLPolyDataReader.h"

#include <gtest/gtest.h>

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
  EXPECT_NE(Parse(app, { "--list", "0.2,abc" }).find("expects a number, got 'abc'"), std::string::npos);
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
  EXPECT_NE(Parse(app, { "--method", "fixed+maximum" }).find("unknown optimizer method"), std::string::npos);
  EXPECT_EQ(appkit::OptimizerPresetChoices(),
    "0|none, 1|fixed-maximum, 2|fixed-remaining, 3|adjusted, 4|error-bounded");
}

TEST(AppKitHeadPose, TheTransformIsTheCoreConvention)
{
  vtkNew<vtkTable> weights;
  for (const auto& [name, value] : { std::pair<const char*, double>{ "HeadYaw", 12.0 }, { "HeadPitch", -7.0 },
         { "HeadRoll", 4.0 } })
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->InsertNextValue(value);
    weights->AddColumn(column);
  }
  const HeadAngles angles = appkit::ReadHeadAngles(weights);
  EXPECT_EQ(angles.Yaw, 12.0);
  EXPECT_EQ(angles.Pitch, -7.0);
  EXPECT_EQ(angles.Roll, 4.0);
  EXPECT_EQ(appkit::ReadHeadAngles(nullptr).Yaw, 0.0);

  const std::array<double, 3> pivot{ 0.1, -0.2, 0.3 };
  vtkNew<vtkTransform> pose;
  appkit::SetHeadPose(pose, angles, pivot);
  // The composition the programs used before the convention had one home: the same matrix.
  vtkNew<vtkTransform> before;
  before->Translate(pivot.data());
  before->RotateY(12.0);
  before->RotateX(7.0);
  before->RotateZ(-4.0);
  before->Translate(-pivot[0], -pivot[1], -pivot[2]);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      EXPECT_NEAR(pose->GetMatrix()->GetElement(i, j), before->GetMatrix()->GetElement(i, j), 1e-12);
    }
  }
  // Seen from the character: a yaw to its left moves the nose (+Z) towards +X.
  appkit::SetHeadPose(pose, { 30.0, 0.0, 0.0 }, { 0, 0, 0 });
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
  EXPECT_NE(xml.find("timestep=\"0\" group=\"\" part=\"0\" file=\"talk/face_00000.vtp\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("timestep=\"0.5\" group=\"\" part=\"0\" file=\"talk/face_00001.vtp\""), std::string::npos) << xml;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir + "/talk/face_00000.vtp").c_str());
  reader->Update();
  vtkFieldData* fd = reader->GetOutput()->GetFieldData();
  ASSERT_NE(fd->GetArray("BehaviorWeights"), nullptr);
  EXPECT_EQ(fd->GetArray("BehaviorWeights")->GetTuple1(0), 0.75);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), face->GetNumberOfPoints());

  EXPECT_THROW(appkit::TimeSeriesWriter(dir + "/talk.vtp"), std::runtime_error);
}
