// SPDX-License-Identifier: BSD-3-Clause
// Live Link Face CSV in and out, the ARKit names in three spellings, and a capture driving
// the ICT-FaceKit head through the ARKit capture rig (docs/capture.md).
#include "base/Error.h"
#include "capture/ArkitNames.h"
#include "capture/CaptureMapping.h"
#include "capture/LiveLinkCsv.h"
#include "gltf/GltfScene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
// Live Link Face's header as the app writes it (checked against takes recorded with the
// app, docs/capture.md).
const char* const AppHeader =
  "Timecode,BlendShapeCount,EyeBlinkLeft,EyeLookDownLeft,EyeLookInLeft,EyeLookOutLeft,"
  "EyeLookUpLeft,EyeSquintLeft,EyeWideLeft,EyeBlinkRight,EyeLookDownRight,EyeLookInRight,"
  "EyeLookOutRight,EyeLookUpRight,EyeSquintRight,EyeWideRight,JawForward,JawRight,JawLeft,"
  "JawOpen,MouthClose,MouthFunnel,MouthPucker,MouthRight,MouthLeft,MouthSmileLeft,"
  "MouthSmileRight,MouthFrownLeft,MouthFrownRight,MouthDimpleLeft,MouthDimpleRight,"
  "MouthStretchLeft,MouthStretchRight,MouthRollLower,MouthRollUpper,MouthShrugLower,"
  "MouthShrugUpper,MouthPressLeft,MouthPressRight,MouthLowerDownLeft,MouthLowerDownRight,"
  "MouthUpperUpLeft,MouthUpperUpRight,BrowDownLeft,BrowDownRight,BrowInnerUp,BrowOuterUpLeft,"
  "BrowOuterUpRight,CheekPuff,CheekSquintLeft,CheekSquintRight,NoseSneerLeft,NoseSneerRight,"
  "TongueOut,HeadYaw,HeadPitch,HeadRoll,LeftEyeYaw,LeftEyePitch,LeftEyeRoll,RightEyeYaw,"
  "RightEyePitch,RightEyeRoll";

const double Pi = 3.14159265358979323846;

// The ICT-FaceKit's 53 targets (its README and Data/rigs/arkit.json).
const std::vector<std::string> IctTargets = { "browDown_L", "browDown_R", "browInnerUp_L",
  "browInnerUp_R", "browOuterUp_L", "browOuterUp_R", "cheekPuff_L", "cheekPuff_R", "cheekSquint_L",
  "cheekSquint_R", "eyeBlink_L", "eyeBlink_R", "eyeLookDown_L", "eyeLookDown_R", "eyeLookIn_L",
  "eyeLookIn_R", "eyeLookOut_L", "eyeLookOut_R", "eyeLookUp_L", "eyeLookUp_R", "eyeSquint_L",
  "eyeSquint_R", "eyeWide_L", "eyeWide_R", "jawForward", "jawLeft", "jawOpen", "jawRight",
  "mouthClose", "mouthDimple_L", "mouthDimple_R", "mouthFrown_L", "mouthFrown_R", "mouthFunnel",
  "mouthLeft", "mouthLowerDown_L", "mouthLowerDown_R", "mouthPress_L", "mouthPress_R",
  "mouthPucker", "mouthRight", "mouthRollLower", "mouthRollUpper", "mouthShrugLower",
  "mouthShrugUpper", "mouthSmile_L", "mouthSmile_R", "mouthStretch_L", "mouthStretch_R",
  "mouthUpperUp_L", "mouthUpperUp_R", "noseSneer_L", "noseSneer_R" };

/// A synthetic take: rows at 30 Hz on a 60 fps timecode with a sub-frame phase, shape s of
/// row r weighing (s + r) % 10 / 10, the head turning.
std::string SyntheticTake(size_t rows)
{
  std::ostringstream out;
  out << AppHeader << "\r\n"; // the app's files may end lines with CRLF
  for (size_t r = 0; r < rows; ++r)
  {
    const size_t frame = ((12 * 60 + 21) * 60 + 59) * 60 + 6 + 2 * r;
    char timecode[32];
    std::snprintf(timecode, sizeof(timecode), "%02zu:%02zu:%02zu:%02zu.595", frame / 216000,
      frame / 3600 % 60, frame / 60 % 60, frame % 60);
    out << timecode << ",61";
    for (size_t s = 0; s < ArkitShapeCount; ++s)
    {
      out << "," << static_cast<double>((s + r) % 10) / 10.0;
    }
    // HeadYaw, HeadPitch, HeadRoll in radians; eyes: left yaw 0.1, right 0.3, pitch -0.2.
    out << "," << 0.01 * static_cast<double>(r) << ",-0.05,0.02,0.1,-0.2,0,0.3,-0.2,0\r\n";
  }
  return out.str();
}

std::string ErrorOf(const std::string& csv, const LiveLinkOptions& options = {})
{
  std::istringstream in(csv);
  try
  {
    ReadLiveLinkCsv(in, options);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}

bool Contains(const std::string& s, const std::string& part)
{
  return s.find(part) != std::string::npos;
}
} // namespace

TEST(ArkitNames, OneTableThreeSpellings)
{
  ASSERT_EQ(ArkitShapeNames().size(), ArkitShapeCount);
  // The Live Link names are the app's header, in its order.
  std::string header = "Timecode,BlendShapeCount";
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    header += "," + ArkitLiveLinkName(s);
  }
  for (const auto& p : LiveLinkPoseNames())
  {
    header += "," + p;
  }
  EXPECT_EQ(header, AppHeader);
  // Each spelling finds its shape; split halves find the whole; others find nothing.
  EXPECT_EQ(FindArkitShape("EyeBlinkLeft"), 0);
  EXPECT_EQ(FindArkitShape("eyeBlinkLeft"), 0);
  EXPECT_EQ(FindArkitShape("eyeBlink_L"), 0);
  EXPECT_EQ(ArkitShapeNames()[static_cast<size_t>(FindArkitShape("browInnerUp_R"))], "browInnerUp");
  EXPECT_EQ(ArkitShapeNames()[static_cast<size_t>(FindArkitShape("CheekPuff"))], "cheekPuff");
  EXPECT_EQ(ArkitShapeNames()[static_cast<size_t>(FindArkitShape("jawLeft"))], "jawLeft");
  EXPECT_EQ(FindArkitShape("jaw_L"), -1);
  EXPECT_EQ(FindArkitShape("EyesClosed"), -1);
  EXPECT_EQ(FindArkitShape("HeadYaw"), -1);
  // The ICT names of the 52 shapes are exactly ICT-FaceKit's 53 targets plus tongueOut.
  std::set<std::string> ict;
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    for (const auto& n : ArkitIctNames(s))
    {
      EXPECT_TRUE(ict.insert(n).second) << n;
    }
  }
  std::set<std::string> expected(IctTargets.begin(), IctTargets.end());
  expected.insert("tongueOut");
  EXPECT_EQ(ict, expected);
}

TEST(ArkitNames, EveryAppleNameLandsOnTheIctTargetsThroughTheRig)
{
  ArkitFaceMapping mapping;
  Rig rig = MakeArkitRig(IctTargets, &mapping);
  EXPECT_EQ(mapping.UnmappedShapes, std::vector<std::string>{ "tongueOut" });
  EXPECT_TRUE(mapping.UnmappedTargets.empty());
  EXPECT_TRUE(Contains(mapping.Report(), "51 of 52 ARKit shapes drive 53 of 53 face targets"))
    << mapping.Report();
  EXPECT_TRUE(Contains(mapping.Report(), "no target for: tongueOut")) << mapping.Report();
  ASSERT_EQ(rig.GetShapeNames(), ArkitShapeNames());
  // One shape at a time lands on its own target(s), both halves of a split shape.
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    std::vector<double> w(ArkitShapeCount, 0.0);
    w[s] = 0.7;
    const std::vector<double> targets = rig.Expand(w);
    std::set<std::string> moved;
    for (size_t t = 0; t < targets.size(); ++t)
    {
      if (targets[t] != 0.0)
      {
        EXPECT_DOUBLE_EQ(targets[t], 0.7);
        moved.insert(IctTargets[t]);
      }
    }
    const auto& names = ArkitIctNames(s);
    std::set<std::string> want = ArkitShapeNames()[s] == "tongueOut"
      ? std::set<std::string>{}
      : std::set<std::string>(names.begin(), names.end());
    EXPECT_EQ(moved, want) << ArkitShapeNames()[s];
  }
  // Apple-named faces map one to one; names that are no ARKit shape are reported.
  ArkitFaceMapping apple;
  MakeArkitRig({ "jawOpen", "eyeBlinkLeft", "Smile", "EyeBlinkRight" }, &apple);
  EXPECT_EQ(apple.UnmappedTargets, std::vector<std::string>{ "Smile" });
  EXPECT_EQ(apple.UnmappedShapes.size(), ArkitShapeCount - 3);
  EXPECT_TRUE(Contains(apple.Report(), "no ARKit shape for: Smile")) << apple.Report();
}

TEST(LiveLinkCsv, TimecodesWithSubFrames)
{
  EXPECT_DOUBLE_EQ(ParseLiveLinkTimecode("00:00:01:30", 60), 1.5);
  EXPECT_NEAR(
    ParseLiveLinkTimecode("12:21:59:06.595", 60), 12 * 3600 + 21 * 60 + 59 + 6.595 / 60, 1e-9);
  EXPECT_NEAR(ParseLiveLinkTimecode("00:00:00:01.5", 30), 1.5 / 30, 1e-12);
  EXPECT_NEAR(ParseLiveLinkTimecode("00:00:00;10", 30), 10.0 / 30, 1e-12);
  EXPECT_EQ(FormatLiveLinkTimecode(12 * 3600 + 21 * 60 + 59 + 6.595 / 60, 60), "12:21:59:06.595");
  EXPECT_EQ(FormatLiveLinkTimecode(1.5, 60), "00:00:01:30.000");
  // A sub-frame that rounds up to a whole frame carries into the frame and the second.
  EXPECT_EQ(FormatLiveLinkTimecode(1.0 - 1e-9, 60), "00:00:01:00.000");
  EXPECT_EQ(FormatLiveLinkTimecode(1.0 - 2e-5, 60), "00:00:00:59.999");
  EXPECT_EQ(FormatLiveLinkTimecode(-1.0 / 60, 60), "23:59:59:59.000");
  for (const char* bad : { "", "12:00:00", "12:00:00:60", "24:00:00:00", "12:60:00:00",
         "1a:00:00:00", "12:00:00:01.", "12:00:00:01.x", "12:00:00:-1", "12:00:00:01:02" })
  {
    EXPECT_THROW(ParseLiveLinkTimecode(bad, 60), InputError) << bad;
  }
  EXPECT_THROW(ParseLiveLinkTimecode("00:00:00:00", 0), InputError);
}

TEST(LiveLinkCsv, ASyntheticTakeReadsBackExactly)
{
  const size_t rows = 40; // crosses into the next minute
  std::istringstream in(SyntheticTake(rows));
  const LiveLinkCapture capture = ReadLiveLinkCsv(in);
  ASSERT_EQ(capture.GetNumberOfRows(), rows);
  EXPECT_EQ(capture.TimecodeRate, 60);
  EXPECT_NEAR(capture.StartTimecode, 12 * 3600 + 21 * 60 + 59 + 6.595 / 60, 1e-9);
  EXPECT_TRUE(capture.UnknownColumns.empty());
  EXPECT_TRUE(capture.MissingShapes.empty());
  // 52 shapes by Apple's names, 9 angles, 2 gaze channels.
  ASSERT_EQ(capture.Channels.size(), ArkitShapeCount + 9 + 2);
  EXPECT_EQ(capture.Channels[0], "eyeBlinkLeft");
  EXPECT_EQ(capture.Channels[51], "tongueOut");
  EXPECT_EQ(capture.Channels[52], "HeadYaw");
  EXPECT_EQ(capture.Channels.back(), "EyePitch");
  for (size_t r = 0; r < rows; ++r)
  {
    // Two 60 fps frames per row, sub-frame phase constant: exactly 1/30 s apart.
    EXPECT_NEAR(capture.Times[r], static_cast<double>(r) / 30.0, 1e-9) << r;
    for (size_t s = 0; s < ArkitShapeCount; ++s)
    {
      EXPECT_DOUBLE_EQ(capture.GetValue(r, s), static_cast<double>((s + r) % 10) / 10.0);
    }
    // Radians to the behaviour's degrees.
    EXPECT_NEAR(capture.GetValue(r, static_cast<size_t>(capture.FindChannel("HeadYaw"))),
      0.01 * static_cast<double>(r) * 180.0 / Pi, 1e-9);
    EXPECT_NEAR(capture.GetValue(r, static_cast<size_t>(capture.FindChannel("HeadPitch"))),
      -0.05 * 180.0 / Pi, 1e-9);
    EXPECT_NEAR(capture.GetValue(r, static_cast<size_t>(capture.FindChannel("EyeYaw"))),
      0.2 * 180.0 / Pi, 1e-9);
    EXPECT_NEAR(capture.GetValue(r, static_cast<size_t>(capture.FindChannel("EyePitch"))),
      -0.2 * 180.0 / Pi, 1e-9);
  }
  // Between rows: linear interpolation; outside: clamped.
  const size_t jaw = static_cast<size_t>(capture.FindChannel("jawOpen"));
  EXPECT_NEAR(capture.Sample(0.5 / 30.0, jaw),
    0.5 * (capture.GetValue(0, jaw) + capture.GetValue(1, jaw)), 1e-12);
  EXPECT_DOUBLE_EQ(capture.Sample(-1.0, jaw), capture.GetValue(0, jaw));
  EXPECT_DOUBLE_EQ(capture.Sample(100.0, jaw), capture.GetValue(rows - 1, jaw));
  // As a fixed-rate track.
  const WeightTrack track = capture.ToTrack(30.0);
  EXPECT_EQ(track.GetNumberOfFrames(), rows);
  EXPECT_NEAR(track.GetValue(7, jaw), capture.GetValue(7, jaw), 1e-9);

  // Written and read again: the same times (sub-frames included), values and angles.
  std::stringstream written;
  WriteLiveLinkCsv(written, capture);
  EXPECT_EQ(written.str().substr(0, written.str().find('\n')), AppHeader);
  EXPECT_TRUE(Contains(written.str(), "\n12:21:59:06.595,61,0.0000000000,0.1000000000,"))
    << written.str().substr(0, 700);
  const LiveLinkCapture back = ReadLiveLinkCsv(written);
  ASSERT_EQ(back.Channels, capture.Channels);
  ASSERT_EQ(back.GetNumberOfRows(), rows);
  EXPECT_NEAR(back.StartTimecode, capture.StartTimecode, 1e-9);
  for (size_t r = 0; r < rows; ++r)
  {
    EXPECT_NEAR(back.Times[r], capture.Times[r], 1e-7);
    for (size_t c = 0; c < capture.Channels.size(); ++c)
    {
      EXPECT_NEAR(back.GetValue(r, c), capture.GetValue(r, c), 1e-7) << capture.Channels[c];
    }
  }
}

TEST(LiveLinkCsv, OtherLayoutsAndUnits)
{
  // Apple's camelCase in another order, only some shapes, an unknown column, no angles,
  // 30 fps timecode, angles as [-1, 1] = 90 degrees.
  const std::string csv = "Timecode,BlendShapeCount,jawOpen,eyeBlinkRight,Blink,HeadYaw\n"
                          "23:59:59:29.500,3,0.5,0.25,7,1\n"
                          "00:00:00:00.500,3,0.75,0,7,-0.5\n";
  LiveLinkOptions options;
  options.TimecodeRate = 30;
  options.PoseDegreesPerUnit = 90.0;
  std::istringstream in(csv);
  const LiveLinkCapture capture = ReadLiveLinkCsv(in, options);
  EXPECT_EQ(capture.Channels, (std::vector<std::string>{ "jawOpen", "eyeBlinkRight", "HeadYaw" }));
  EXPECT_EQ(capture.UnknownColumns, std::vector<std::string>{ "Blink" });
  EXPECT_EQ(capture.MissingShapes.size(), ArkitShapeCount - 2);
  // Past midnight: 1/30 s later, not a day earlier.
  ASSERT_EQ(capture.GetNumberOfRows(), 2u);
  EXPECT_NEAR(capture.Times[1], 1.0 / 30.0, 1e-9);
  EXPECT_DOUBLE_EQ(capture.GetValue(0, 2), 90.0);
  EXPECT_DOUBLE_EQ(capture.GetValue(1, 2), -45.0);
}

TEST(LiveLinkCsv, BadInputNamesLineAndColumn)
{
  const std::string header = "Timecode,BlendShapeCount,JawOpen,HeadYaw\n";
  const std::string good = "00:00:00:00.000,2,0.5,0.1\n";
  struct Case
  {
    std::string Csv;
    std::vector<std::string> Parts;
  };
  const std::vector<Case> cases = {
    { "", { "empty input" } },
    { header, { "no rows" } },
    { "Time,JawOpen\n" + good, { "line 1, column 1", "Timecode" } },
    { "Timecode,JawOpen,,HeadYaw\n", { "line 1, column 3", "without a name" } },
    { "Timecode,JawOpen,jawOpen\n", { "line 1, column 3", "twice" } },
    { "Timecode,JawOpen,jaw_Open\n", {} }, // unknown column: fine (no rows error below)
    { header + good + "00:00:00:02.000,2,0.5\n", { "line 3, column 4", "'HeadYaw'", "missing" } },
    { header + good + "00:00:00:02.000,2,0.5,0.1,9\n", { "line 3, column 5", "5 cells" } },
    { header + good + "00:00:00:02.000,2,abc,0.1\n",
      { "line 3, column 3", "'JawOpen'", "'abc'", "not a finite number" } },
    { header + good + "00:00:00:02.000,2,0.5,nan\n",
      { "line 3, column 4", "not a finite number" } },
    { header + good + "00:00:00:02.000,2,0.5,\n", { "line 3, column 4", "not a finite number" } },
    { header + good + "00:00:00:61.000,2,0.5,0.1\n",
      { "line 3, column 1", "frame 61", "rate of 60" } },
    { header + good + "0:0:0\n", { "line 3, column 2", "missing" } },
    { header + good + good, { "line 3, column 1", "not later" } },
  };
  for (const auto& c : cases)
  {
    const std::string error = ErrorOf(c.Csv);
    if (c.Parts.empty())
    {
      EXPECT_TRUE(Contains(error, "no rows")) << error;
      continue;
    }
    EXPECT_FALSE(error.empty()) << c.Csv;
    for (const auto& part : c.Parts)
    {
      EXPECT_TRUE(Contains(error, part)) << "'" << error << "' lacks '" << part << "'";
    }
  }
  LiveLinkOptions badRate;
  badRate.TimecodeRate = 0;
  EXPECT_TRUE(Contains(ErrorOf(header + good, badRate), "rate"));
  LiveLinkOptions badUnit;
  badUnit.PoseDegreesPerUnit = -1.0;
  EXPECT_TRUE(Contains(ErrorOf(header + good, badUnit), "degrees per angle unit"));
  EXPECT_THROW(ReadLiveLinkCsvFile("/nonexistent/take.csv"), InputError);
}

TEST(LiveLinkCsv, ATrackOfFaceTargetsGoesOut)
{
  // The behaviour's output expanded onto the ICT face: ICT names, split halves, gaze and
  // head angles in degrees, a channel that is no ARKit shape.
  WeightTrack track({ "jawOpen", "browInnerUp_L", "browInnerUp_R", "eyeBlink_L", "HeadYaw",
                      "EyeYaw", "EyePitch", "sil" },
    30.0);
  track.AppendFrame({ 0.5, 0.2, 0.4, 1.0, 10.0, 5.0, -3.0, 1.0 });
  track.AppendFrame({ 0.25, 0.0, 0.0, 0.0, -10.0, 0.0, 0.0, 0.0 });
  std::vector<std::string> unmapped;
  LiveLinkOptions options;
  options.StartTimecode = 3600.0;
  const LiveLinkCapture capture = CaptureFromTrack(track, options, &unmapped);
  EXPECT_EQ(unmapped, std::vector<std::string>{ "sil" });
  std::stringstream out;
  WriteLiveLinkCsv(out, capture);
  const LiveLinkCapture back = ReadLiveLinkCsv(out);
  ASSERT_EQ(back.GetNumberOfRows(), 2u);
  EXPECT_NEAR(back.StartTimecode, 3600.0, 1e-9);
  EXPECT_NEAR(back.Times[1], 1.0 / 30.0, 1e-6);
  auto value = [&](size_t row, const char* name)
  {
    const int c = back.FindChannel(name);
    EXPECT_GE(c, 0) << name;
    return c < 0 ? NAN : back.GetValue(row, static_cast<size_t>(c));
  };
  EXPECT_NEAR(value(0, "jawOpen"), 0.5, 1e-9);
  EXPECT_NEAR(value(0, "browInnerUp"), 0.3, 1e-9); // the halves' mean
  EXPECT_NEAR(value(0, "eyeBlinkLeft"), 1.0, 1e-9);
  EXPECT_NEAR(value(0, "tongueOut"), 0.0, 1e-9);
  EXPECT_NEAR(value(0, "HeadYaw"), 10.0, 1e-7);
  EXPECT_NEAR(value(1, "HeadYaw"), -10.0, 1e-7);
  // Both eyes follow the gaze channels.
  EXPECT_NEAR(value(0, "LeftEyeYaw"), 5.0, 1e-7);
  EXPECT_NEAR(value(0, "RightEyePitch"), -3.0, 1e-7);
  EXPECT_NEAR(value(0, "EyeYaw"), 5.0, 1e-7);
}

TEST(LiveLinkCsv, ACaptureDrivesTheIctHead)
{
  const std::string dir = MORPHNODE_FACEKIT_DIR;
  const std::string path = dir + "/ict_head_full53.glb";
  if (dir.empty() || !std::ifstream(path).good())
  {
    GTEST_SKIP() << "ICT-FaceKit head not found (" << path << "); set MORPHNODE_FACEKIT_DIR";
  }
  const GltfScene scene = LoadGltfScene(path);
  // The skin: the part with the most points.
  const GltfPart* skin = nullptr;
  for (const auto& part : scene.Parts)
  {
    if (!skin || part.GetNumberOfPoints() > skin->GetNumberOfPoints())
    {
      skin = &part;
    }
  }
  ASSERT_NE(skin, nullptr);
  std::vector<std::string> targets;
  for (const auto& t : skin->Targets)
  {
    targets.push_back(t.Name);
  }
  ASSERT_EQ(targets.size(), 53u);
  ArkitFaceMapping mapping;
  Rig rig = MakeArkitRig(targets, &mapping);
  EXPECT_EQ(mapping.UnmappedShapes, std::vector<std::string>{ "tongueOut" }) << mapping.Report();
  EXPECT_TRUE(mapping.UnmappedTargets.empty()) << mapping.Report();

  // A take that opens the jaw on its second row.
  std::ostringstream csv;
  csv << "Timecode,BlendShapeCount,JawOpen,TongueOut,HeadYaw\n"
      << "10:00:00:00.000,3,0,0,0\n"
      << "10:00:00:02.000,3,0.8,1,0.1\n";
  std::istringstream in(csv.str());
  const LiveLinkCapture capture = ReadLiveLinkCsv(in);
  std::vector<double> shapes(ArkitShapeCount, 0.0);
  auto displacement = [&](double time)
  {
    std::fill(shapes.begin(), shapes.end(), 0.0);
    for (size_t c = 0; c < capture.Channels.size(); ++c)
    {
      const int s = FindArkitShape(capture.Channels[c]);
      if (s >= 0)
      {
        shapes[static_cast<size_t>(s)] = capture.Sample(time, c);
      }
    }
    const std::vector<double> w = rig.Expand(shapes);
    double largest = 0.0;
    for (size_t p = 0; p < skin->GetNumberOfPoints(); ++p)
    {
      double d[3] = { 0, 0, 0 };
      for (size_t t = 0; t < w.size(); ++t)
      {
        for (int k = 0; k < 3 && w[t] != 0.0; ++k)
        {
          d[k] += w[t] * skin->Targets[t].PositionDeltas[3 * p + static_cast<size_t>(k)];
        }
      }
      largest = std::max(largest, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    return largest;
  };
  EXPECT_EQ(displacement(0.0), 0.0);
  // jawOpen at 0.8 moves the chin by centimetres (the head is in metres).
  EXPECT_GT(displacement(2.0 / 60.0), 0.005);
  EXPECT_GT(displacement(2.0 / 60.0), displacement(1.0 / 60.0));
}

TEST(CaptureMapping, TakeOntoAFaceAndWithoutOne)
{
  std::istringstream in(SyntheticTake(4));
  const LiveLinkCapture capture = ReadLiveLinkCsv(in);
  // Without a face: the take's channels as they are.
  const CaptureFaceMapping own(capture, {});
  EXPECT_EQ(own.GetChannels(), capture.Channels);
  EXPECT_TRUE(Contains(own.GetReport(), "no face: the 52 ARKit shapes")) << own.GetReport();
  std::vector<double> row(own.GetChannels().size());
  own.Sample(capture.Times[2], row.data());
  for (size_t c = 0; c < row.size(); ++c)
  {
    EXPECT_DOUBLE_EQ(row[c], capture.GetValue(2, c)) << capture.Channels[c];
  }
  // Onto ICT-FaceKit's targets: its 53 targets, then the 11 angles; both halves of
  // browInnerUp from the one shape; tongueOut maps to nothing.
  const CaptureFaceMapping ict(capture, IctTargets);
  ASSERT_EQ(ict.GetChannels().size(), IctTargets.size() + 11);
  EXPECT_EQ(ict.GetChannels()[0], "browDown_L");
  EXPECT_EQ(ict.GetChannels()[IctTargets.size()], "HeadYaw");
  EXPECT_EQ(ict.GetUnmapped(), (std::vector<std::string>{ "tongueOut" }));
  EXPECT_TRUE(Contains(ict.GetReport(), "names that map to nothing: tongueOut")) << ict.GetReport();
  row.assign(ict.GetChannels().size(), -1.0);
  ict.Sample(capture.Times[1], row.data());
  const size_t inner = static_cast<size_t>(FindArkitShape("browInnerUp"));
  const size_t blink = static_cast<size_t>(FindArkitShape("eyeBlinkLeft"));
  EXPECT_DOUBLE_EQ(row[2], capture.GetValue(1, inner)) << "browInnerUp_L";
  EXPECT_DOUBLE_EQ(row[3], capture.GetValue(1, inner)) << "browInnerUp_R";
  EXPECT_DOUBLE_EQ(row[10], capture.GetValue(1, blink)) << "eyeBlink_L";
  EXPECT_DOUBLE_EQ(row[IctTargets.size()], capture.GetValue(1, ArkitShapeCount))
    << "HeadYaw copied";
  // Targets that make no rig.
  EXPECT_THROW(CaptureFaceMapping(capture, { "jawOpen", "jawOpen" }), InputError);
}
