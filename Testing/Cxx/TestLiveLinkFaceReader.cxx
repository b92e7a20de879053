// SPDX-License-Identifier: BSD-3-Clause
// vtkLiveLinkFaceReader: a synthetic Live Link Face take written by the test, read as a
// temporal weight source; mapped onto the ICT-FaceKit head it drives vtkMorphNodeFilter;
// names that map to nothing are reported; bad rows are errors naming line and column.
#include "MorphNodeMergeParts.h"
#include "MorphNodeTestUtilities.h"

#include "vtkLiveLinkFaceReader.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

using morphnode_test::MessageCollector;

namespace
{
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";

std::string WriteTake(const std::string& name, const std::string& text)
{
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// Three rows 1/30 s apart on a 60 fps timecode: the jaw opens, the head turns (radians),
// an unknown column "Blink" and tongueOut (ICT-FaceKit has no such target).
const char* const Take =
  "Timecode,BlendShapeCount,EyeBlinkLeft,JawOpen,BrowInnerUp,TongueOut,Blink,"
  "HeadYaw,HeadPitch,HeadRoll\n"
  "10:00:00:00.250,4,0,0,0,0,7,0,0,0\n"
  "10:00:00:02.250,4,1,0.8,0.4,1,7,0.1,0,0\n"
  "10:00:00:04.250,4,0.5,0.4,0.2,0,7,0.2,0,0\n";

double Column(vtkTable* table, const char* name, vtkIdType row = 0)
{
  vtkDataArray* a = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
  EXPECT_NE(a, nullptr) << name;
  return a ? a->GetTuple1(row) : NAN;
}
} // namespace

TEST(LiveLinkFaceReader, ATakeIsATemporalWeightSource)
{
  vtkNew<vtkLiveLinkFaceReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetFileName(WriteTake("livelink_take.csv", Take).c_str());
  reader->UpdateInformation();
  vtkInformation* info = reader->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 3);
  const double* steps = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  EXPECT_NEAR(steps[0], 0.0, 1e-9);
  EXPECT_NEAR(steps[1], 1.0 / 30.0, 1e-9);
  EXPECT_NEAR(steps[2], 2.0 / 30.0, 1e-9);

  // Between rows 1 and 2: interpolated; the head angle in degrees.
  reader->UpdateTimeStep(1.5 / 30.0);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  auto* frame = vtkTable::SafeDownCast(reader->GetOutputDataObject(0));
  ASSERT_EQ(frame->GetNumberOfRows(), 1);
  EXPECT_NEAR(Column(frame, "jawOpen"), 0.6, 1e-9);
  EXPECT_NEAR(Column(frame, "browInnerUp"), 0.3, 1e-9);
  EXPECT_NEAR(Column(frame, "HeadYaw"), 0.15 * 180.0 / M_PI, 1e-9);
  EXPECT_EQ(frame->GetColumnByName("Blink"), nullptr);
  ASSERT_EQ(reader->GetNumberOfUnmappedNames(), 1);
  EXPECT_STREQ(reader->GetUnmappedName(0), "Blink");
  EXPECT_EQ(reader->GetNumberOfRows(), 3);

  // Port 1: the whole take.
  reader->GetOutputPort(1);
  reader->Update(1);
  auto* take = vtkTable::SafeDownCast(reader->GetOutputDataObject(1));
  ASSERT_EQ(take->GetNumberOfRows(), 3);
  EXPECT_STREQ(take->GetColumnName(0), "Time");
  EXPECT_NEAR(Column(take, "eyeBlinkLeft", 1), 1.0, 1e-9);
  EXPECT_NEAR(Column(take, "Time", 2), 2.0 / 30.0, 1e-9);

  // The file is read once, not for every time step; Modified() reads it again.
  const std::string path = reader->GetFileName();
  std::ofstream(path) << "Timecode,JawOpen\n10:00:00:00.250,0.125\n10:00:00:02.250,0.125\n";
  reader->UpdateTimeStep(0.0);
  EXPECT_NEAR(
    Column(vtkTable::SafeDownCast(reader->GetOutputDataObject(0)), "jawOpen"), 0.0, 1e-12);
  reader->Modified();
  reader->UpdateTimeStep(0.0);
  EXPECT_NEAR(
    Column(vtkTable::SafeDownCast(reader->GetOutputDataObject(0)), "jawOpen"), 0.125, 1e-12);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
}

TEST(LiveLinkFaceReader, TheTakeDrivesTheIctHeadAndReportsWhatDoesNotMap)
{
  if (!std::ifstream(IctHead).good())
  {
    GTEST_SKIP() << "ICT-FaceKit head not found (" << IctHead << "); set MORPHNODE_FACEKIT_DIR";
  }
  vtkNew<vtkMorphTargetReader> head;
  head->SetFileName(IctHead.c_str());
  vtkNew<vtkLiveLinkFaceReader> reader;
  reader->SetFileName(WriteTake("livelink_ict.csv", Take).c_str());
  reader->SetFaceConnection(head->GetOutputPort());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(head->GetOutputPort());
  morph->SetWeightsConnection(reader->GetOutputPort(0));
  morph->SetWeightModeToRelative();
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  messages->Watch(morph);

  auto points = [&](double time)
  {
    morph->UpdateTimeStep(time);
    std::vector<double> xyz;
    for (vtkPolyData* leaf : morphnode_test::PolyDataLeaves(morph->GetOutputDataObject(0)))
    {
      for (vtkIdType i = 0; i < leaf->GetNumberOfPoints(); ++i)
      {
        double p[3];
        leaf->GetPoint(i, p);
        xyz.insert(xyz.end(), p, p + 3);
      }
    }
    return xyz;
  };
  const std::vector<double> rest = points(0.0);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  // The columns are the head's 53 targets (ICT names), then the angles.
  auto* frame = vtkTable::SafeDownCast(reader->GetOutputDataObject(0));
  EXPECT_NEAR(Column(frame, "jawOpen"), 0.0, 1e-9);
  EXPECT_EQ(frame->GetColumnByName("tongueOut"), nullptr);
  ASSERT_GE(reader->GetNumberOfChannels(), 53);
  EXPECT_STREQ(reader->GetChannelName(53), "HeadYaw");
  const std::vector<double> open = points(1.0 / 30.0);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_NEAR(Column(frame, "jawOpen"), 0.8, 1e-9);
  EXPECT_NEAR(Column(frame, "browInnerUp_L"), 0.4, 1e-9);
  EXPECT_NEAR(Column(frame, "browInnerUp_R"), 0.4, 1e-9);
  EXPECT_NEAR(Column(frame, "eyeBlink_L"), 1.0, 1e-9);
  ASSERT_EQ(rest.size(), open.size());
  ASSERT_FALSE(rest.empty());
  double largest = 0.0;
  for (size_t i = 0; i < rest.size(); i += 3)
  {
    largest = std::max(
      largest, std::hypot(open[i] - rest[i], open[i + 1] - rest[i + 1], open[i + 2] - rest[i + 2]));
  }
  EXPECT_GT(largest, 0.005) << "the jaw opened by the take moves the head by centimetres";

  // Blink (no ARKit shape) and tongueOut (no ICT target) map to nothing, and say so.
  std::vector<std::string> unmapped;
  for (int i = 0; i < reader->GetNumberOfUnmappedNames(); ++i)
  {
    unmapped.push_back(reader->GetUnmappedName(i));
  }
  EXPECT_EQ(unmapped, (std::vector<std::string>{ "Blink", "tongueOut" }));
  const std::string report = reader->GetMappingReport();
  EXPECT_NE(report.find("51 of 52 ARKit shapes drive 53 of 53 face targets"), std::string::npos)
    << report;
  EXPECT_NE(report.find("map to nothing: Blink tongueOut"), std::string::npos) << report;
}

TEST(LiveLinkFaceReader, BadRowsAreErrorsNamingLineAndColumn)
{
  vtkNew<vtkLiveLinkFaceReader> reader;
  vtkNew<MessageCollector> messages;
  messages->Watch(reader);
  reader->SetFileName(WriteTake("livelink_bad.csv",
    "Timecode,BlendShapeCount,JawOpen,HeadYaw\n00:00:00:00.000,2,0.5,0.1\n00:00:00:02.000,2,0.5\n")
                        .c_str());
  reader->Update();
  EXPECT_TRUE(messages->HasError("line 3, column 4")) << messages->AllErrors();
  EXPECT_TRUE(messages->HasError("missing")) << messages->AllErrors();
  EXPECT_EQ(vtkTable::SafeDownCast(reader->GetOutputDataObject(0))->GetNumberOfColumns(), 0);

  messages->Errors.clear();
  reader->SetFileName(WriteTake("livelink_nan.csv",
    "Timecode,BlendShapeCount,JawOpen,HeadYaw\n00:00:00:00.000,2,0.5,0.1\n00:00:00:02.000,2,x,0."
    "1\n")
                        .c_str());
  reader->Update();
  EXPECT_TRUE(messages->HasError("line 3, column 3 ('JawOpen'): 'x' is not a finite number"))
    << messages->AllErrors();
  EXPECT_EQ(vtkTable::SafeDownCast(reader->GetOutputDataObject(0))->GetNumberOfColumns(), 0);

  // A good file after a bad one reads again.
  messages->Errors.clear();
  reader->SetFileName(WriteTake("livelink_good.csv", Take).c_str());
  reader->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_GT(vtkTable::SafeDownCast(reader->GetOutputDataObject(0))->GetNumberOfColumns(), 0);

  messages->Errors.clear();
  reader->SetFileName("/nonexistent/take.csv");
  reader->Update();
  EXPECT_TRUE(messages->HasError("cannot be opened")) << messages->AllErrors();
}
