// SPDX-License-Identifier: BSD-3-Clause
// Tests of the MorphAvatar application (Modules/Applications/MorphAvatar), run as a program:
// the render regression of one frame of a fixed-seed script against a baseline, the
// offscreen mode writing PNG frames, a Theora video and the WAV (with a moving mouth),
// and clear errors for bad arguments. AvatarRun under `xvfb-run -a`.
#include "MorphAvatarRun.h"
#include "audio/AudioBuffer.h"
#include "audio/AudioFile.h"
#include "gltf/GltfScene.h"

#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkXMLMultiBlockDataReader.h"
#include "vtksys/SystemTools.hxx"

#include "MorphNodeMouthPixels.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <regex>
#include <string>

using morphnode_test::AvatarRun;
using morphnode_test::RunAvatar;

namespace
{
const std::string Source = MORPHNODE_SOURCE_DIR;
const std::string Output = MORPHNODE_TEST_OUTPUT_DIR;

std::string Head(const std::string& file, size_t bytes)
{
  std::ifstream in(file, std::ios::binary);
  std::string head(bytes, '\0');
  in.read(&head[0], static_cast<std::streamsize>(bytes));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

vtkSmartPointer<vtkImageData> ReadPng(const std::string& file)
{
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

/// Mean absolute difference of two images of the same size over rows [y0, y1) (VTK's
/// rows run bottom-up).
double MeanDifference(vtkImageData* a, vtkImageData* b, double y0, double y1)
{
  int dims[3];
  a->GetDimensions(dims);
  auto* pa = vtkUnsignedCharArray::SafeDownCast(a->GetPointData()->GetScalars());
  auto* pb = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetScalars());
  if (!pa || !pb || pa->GetNumberOfValues() != pb->GetNumberOfValues())
  {
    return -1.0;
  }
  const int c = pa->GetNumberOfComponents();
  double sum = 0.0;
  size_t count = 0;
  for (int y = static_cast<int>(y0 * dims[1]); y < static_cast<int>(y1 * dims[1]); ++y)
  {
    for (int x = dims[0] / 4; x < 3 * dims[0] / 4; ++x)
    {
      for (int k = 0; k < std::min(c, 3); ++k)
      {
        const vtkIdType i = (static_cast<vtkIdType>(y) * dims[0] + x) * c + k;
        sum += std::abs(int(pa->GetValue(i)) - int(pb->GetValue(i)));
        ++count;
      }
    }
  }
  return count ? sum / count : -1.0;
}
} // namespace

// The image comparison (VTK's legacy metric with a per-channel tolerance of 24 levels, as
// MorphAvatar --compare computes it) forgives small shading differences, and the mouth is
// a small part of the frame. Measured on the default head (its glTF materials drawn with
// PBR) against the baseline (t = 1.33 s, open mouth showing the lower teeth): the same
// frame 0, the frame at 1.40 s (a smile showing both rows of teeth, same pose) 148, at
// 0.5 s 411. So 0.5, and two negative controls: another
// mouth in the same pose (1.40 s) and another time (0.5 s). TestHeadRender proves on
// frames without the overlay that this threshold sees the mouth alone.
const std::string GreetingFrame = "--script '" + Source +
  "/Data/scripts/greeting.txt' --seed 2004 --size 400x400 --method adjusted --threshold 0.1 " +
  "--compare '" + MORPHNODE_BASELINE_DIR + "/TestMorphAvatar.png' --compare-threshold 0.5 ";

TEST(MorphAvatar, FrameOfGreetingMatchesBaseline)
{
  // One frame of the greeting script (seed 2004) while it says "Hello!" (mouth open),
  // smiling, glancing at the user; the paper's adjusted threshold; overlay included.
  const AvatarRun run =
    RunAvatar(GreetingFrame + "--at 1.33 --png '" + Output + "/TestMorphAvatar.png'");
  EXPECT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("matches"), std::string::npos) << run.Text;
}

TEST(MorphAvatar, FrameAtAnotherTimeDiffersFromBaseline)
{
  // 0.5 s: before the speech, mouth closed.
  const AvatarRun run =
    RunAvatar(GreetingFrame + "--at 0.5 --png '" + Output + "/TestMorphAvatarOther.png'");
  EXPECT_EQ(run.ExitCode, 1) << run.Text;
  EXPECT_NE(run.Text.find("differs from"), std::string::npos) << run.Text;
}

TEST(MorphAvatar, FrameWithAnotherMouthDiffersFromBaseline)
{
  // 1.40 s: the same pose and gaze, the mouth nearly closed in a smile instead of open.
  const AvatarRun run =
    RunAvatar(GreetingFrame + "--at 1.4 --png '" + Output + "/TestMorphAvatarOtherMouth.png'");
  EXPECT_EQ(run.ExitCode, 1) << run.Text;
  EXPECT_NE(run.Text.find("differs from"), std::string::npos) << run.Text;
}

TEST(MorphAvatar, OffscreenWritesFramesVideoAndAudio)
{
  const std::string dir = Output + "/TestMorphAvatarOffscreen";
  vtksys::SystemTools::RemoveADirectory(dir);
  // About a second of speech: 1.2 s at 20 fps = frames 0..24.
  const AvatarRun run = RunAvatar("--say 'Hello, my friend.' --seed 3 --duration 1.2 --fps 20 " +
    std::string("--size 320x320 --method fixed-remaining --threshold 0.05 --offscreen ") +
    "--frames '" + dir + "' --video '" + dir + "/avatar.ogv'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("100%"), std::string::npos) << "no progress bar:\n" << run.Text;
  EXPECT_NE(run.Text.find("25/25 frames"), std::string::npos) << run.Text;
  for (int f = 0; f < 25; ++f)
  {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
    EXPECT_TRUE(vtksys::SystemTools::FileExists(dir + name)) << name;
  }
  EXPECT_FALSE(vtksys::SystemTools::FileExists(dir + "/frame_00025.png"));
  EXPECT_EQ(Head(dir + "/avatar.ogv", 4), "OggS");
  EXPECT_GT(vtksys::SystemTools::FileLength(dir + "/avatar.ogv"), 10000u);
  EXPECT_EQ(Head(dir + "/avatar.wav", 4), "RIFF");
  EXPECT_GT(vtksys::SystemTools::FileLength(dir + "/avatar.wav"), 20000u); // 1.2 s of 16-bit audio
  if (run.Text.find("ffmpeg is not on PATH") == std::string::npos)
  {
    EXPECT_TRUE(vtksys::SystemTools::FileExists(dir + "/avatar.mp4")) << run.Text;
  }

  // The mouth moves: the lower face (not the overlay at the top) changes while speaking.
  auto first = ReadPng(dir + "/frame_00000.png");
  int dims[3];
  first->GetDimensions(dims);
  EXPECT_EQ(dims[0], 320);
  EXPECT_EQ(dims[1], 320);
  double largest = 0.0;
  for (int f = 5; f < 25; f += 2)
  {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
    largest = std::max(largest, MeanDifference(first, ReadPng(dir + name), 0.15, 0.45));
  }
  EXPECT_GT(largest, 2.0) << "the mouth region does not change while the avatar speaks";
}

TEST(MorphAvatar, BadArgumentsFailClearly)
{
  const struct
  {
    const char* Arguments;
    const char* Message;
  } cases[] = {
    { "--size 12", "--size: expects WxH" },
    { "--size 640x", "--size: expects WxH" },
    { "--method 7", "--method: unknown optimizer method '7' (known: 0|none, 1|fixed-maximum" },
    { "--method fixed+maximum", "--method: unknown optimizer method" }, // one spelling
    { "--threshold 2", "--threshold: must be in [0, 1]" },
    { "--threshold abc", "--threshold: expects a number" },
    { "--fps 0", "--fps: must be in" },
    { "--seed -3", "--seed: expects an unsigned integer" },
    { "--say ' '", "--say: needs a non-empty text" },
    { "--script /nonexistent/script.txt", "--script: File does not exist" },
    { "--face /nonexistent/face.glb", "--face: Path does not exist" },
    { "--frobnicate", "not expected: --frobnicate" },
    { "--offscreen", "--offscreen needs somewhere to write" },
    { "--duration", "--duration: 1 required" },
    { "--visemes klingon --png x.png", "--visemes: klingon not in {paper6,oculus15,german16}" },
    { "--pvd x.vtp", "--pvd takes a file name ending in .pvd" },
    { "--at 1 --frames x", "--at renders one frame" },
    { "--text hi", "--text requires --audio" },
    { "--audio /nonexistent/speech.wav", "--audio: File does not exist" },
  };
  for (const auto& c : cases)
  {
    const AvatarRun run = RunAvatar(c.Arguments);
    EXPECT_EQ(run.ExitCode, 2) << c.Arguments << " gave:\n" << run.Text;
    EXPECT_NE(run.Text.find("(see MorphAvatar --help)"), std::string::npos) << c.Arguments;
    EXPECT_NE(run.Text.find(c.Message), std::string::npos) << c.Arguments << " gave:\n" << run.Text;
  }
  const AvatarRun help = RunAvatar("--help");
  EXPECT_EQ(help.ExitCode, 0);
  EXPECT_NE(help.Text.find("--method"), std::string::npos);
}

TEST(MorphAvatar, BadScriptFails)
{
  const std::string dir = Output + "/TestMorphAvatarErrors";
  vtksys::SystemTools::MakeDirectory(dir);
  {
    std::ofstream script(dir + "/broken.txt");
    script << "seed 1\nat 0.5 gesture moonwalk\n";
  }
  AvatarRun run = RunAvatar("--script '" + dir + "/broken.txt' --png '" + dir + "/x.png'");
  EXPECT_NE(run.ExitCode, 0);
  EXPECT_NE(run.Text.find("cannot load the script"), std::string::npos) << run.Text;
}

/// Mean grey-level change of the lower face that counts as a moving mouth. Measured (seed 3):
/// 7.3 with the rig, 1.2 when the rig's weights do not reach the face (idle head motion only).
constexpr double RigMouthChange = 5.0;

TEST(MorphAvatar, OtherFaceThroughRig)
{
  const std::string ict = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  if (!vtksys::SystemTools::FileExists(ict))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << ict;
  }
  const std::string png = Output + "/TestMorphAvatarIct.png";
  // Without a rig the rig is chosen from the ARKit names (docs/avatars.md) and printed.
  AvatarRun run = RunAvatar("--face '" + ict + "' --png '" + png + "'");
  EXPECT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("face naming: ARKit (51 of 52 shapes)"), std::string::npos) << run.Text;
  EXPECT_NE(run.Text.find("rig: chosen from the face's names"), std::string::npos) << run.Text;
  // With the ARKit rig it speaks: the mouth region while it says "Hello" differs from the
  // same face before the speech (a rig that does not reach the face leaves only the idle
  // head motion; see RigMouthChange).
  const std::string arguments = "--face '" + ict + "' --rig '" + Source +
    "/Data/rigs/arkit.json' --say 'Hello there.' --seed 3 --size 256x256 --no-overlay ";
  run = RunAvatar(arguments + "--at 0.9 --png '" + png + "'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  const std::string still = Output + "/TestMorphAvatarIctStill.png";
  run = RunAvatar(arguments + "--at 0.0 --png '" + still + "'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  const double change = MeanDifference(ReadPng(png), ReadPng(still), 0.15, 0.45);
  std::cout << "mouth-region change, speaking against before the speech: " << change << "\n";
  EXPECT_GT(change, RigMouthChange) << "the rig does not move the ICT face's mouth";
}

/// Teeth and tongue pixels (MorphNodeMouthPixels.h) in the frames of the ICT head saying
/// "Hello there, how are you?" (400 x 400, 10 fps, frames 1-16). Measured: before the speech
/// (frame 0) teeth 6, tongue/gums 0; the most while it speaks teeth 115, tongue/gums 742.
constexpr int IctTeethPixels = 60;
constexpr int IctTonguePixels = 120;

TEST(MorphAvatar, IctHeadTalksWithTeethAndTongue)
{
  const std::string head = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
  if (!vtksys::SystemTools::FileExists(head))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << head << " (the CI requires it)";
  }
  const std::string dir = Output + "/TestMorphAvatarIctHead";
  vtksys::SystemTools::RemoveADirectory(dir);
  // The whole head (11 parts: skin, mouth interior, teeth, eyes, lashes) through the ARKit
  // rig: jawOpen and the lips' targets move the teeth and the tongue with the skin.
  const AvatarRun run = RunAvatar("--face '" + head + "' --rig '" + Source +
    "/Data/rigs/arkit.json' --say 'Hello there, how are you?' --seed 3 --duration 1.6 --fps 10 " +
    "--size 400x400 --no-overlay --quiet --frames '" + dir + "'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  morphnode_test::MouthPixels most;
  for (int f = 1; f <= 16; ++f)
  {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
    const morphnode_test::MouthPixels frame = morphnode_test::CountMouthPixels(ReadPng(dir + name));
    most.Teeth = std::max(most.Teeth, frame.Teeth);
    most.Tongue = std::max(most.Tongue, frame.Tongue);
  }
  const morphnode_test::MouthPixels still =
    morphnode_test::CountMouthPixels(ReadPng(dir + "/frame_00000.png"));
  std::cout << "ICT head: teeth pixels " << still.Teeth << " before the speech, at most "
            << most.Teeth << " while speaking; tongue/gums " << still.Tongue << ", at most "
            << most.Tongue << "\n";
  EXPECT_GT(most.Teeth, IctTeethPixels) << "no teeth seen while the ICT head speaks";
  EXPECT_GT(most.Tongue, IctTonguePixels) << "no tongue seen while the ICT head speaks";
  // Negative control: the closed mouth before the speech shows neither.
  EXPECT_LT(still.Teeth, IctTeethPixels);
  EXPECT_LT(still.Tongue, IctTonguePixels);
}

TEST(MorphAvatar, InteractiveWindowRunsAndKeysSwitchTheMethod)
{
  // The window for two seconds, time in real time; keys 4 (error-bounded), then 2 and + + -
  // (fixed threshold + remaining, 0.1 + 0.025). A timer that never fires leaves the first
  // frame alone; the window's first render (shaders under llvmpipe) can take most of a second
  // on a loaded machine, so two seconds and more than one frame, not a frame rate.
  const AvatarRun run = RunAvatar("--say 'Hi.' --size 320x320 --exit-after 2 --keys '42++-'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("method 2: fixed threshold + remaining"), std::string::npos) << run.Text;
  EXPECT_NE(run.Text.find("threshold 0.125"), std::string::npos) << run.Text;
  int frames = 0;
  ASSERT_EQ(
    std::sscanf(run.Text.substr(run.Text.find("rendered")).c_str(), "rendered %d", &frames), 1);
  EXPECT_GT(frames, 1) << "the timer did not advance the animation";
}

// The window plays the speech on the sound device (playback/AudioPlayer), and its clock is
// the sound's. SDL's disk driver writes what a sound card would play (32-bit float mono):
// silence until the sentence starts at 0.5 s, then the voice. --mute: no sound at all.
TEST(MorphAvatar, InteractiveWindowPlaysTheSpeech)
{
  const std::string raw = Output + "/MorphAvatarSound.raw";
  auto played = [&](const std::string& extra)
  {
    vtksys::SystemTools::RemoveFile(raw);
    setenv("SDL_AUDIODRIVER", "disk", 1);
    setenv("SDL_DISKAUDIOFILE", raw.c_str(), 1);
    const AvatarRun run =
      RunAvatar("--say 'Hello there, my friend.' --size 160x160 --exit-after 2.5 " + extra);
    unsetenv("SDL_AUDIODRIVER");
    unsetenv("SDL_DISKAUDIOFILE");
    EXPECT_EQ(run.ExitCode, 0) << run.Text;
    std::vector<float> samples;
    std::ifstream in(raw, std::ios::binary);
    float value = 0.0f;
    while (in.read(reinterpret_cast<char*>(&value), sizeof(value)))
    {
      samples.push_back(value);
    }
    return std::make_pair(run, samples);
  };
  const auto [run, samples] = played("");
  if (run.Text.find("sound through disk") == std::string::npos)
  {
    GTEST_SKIP() << "no SDL disk driver (built without SDL2?): " << run.Text;
  }
  ASSERT_GT(samples.size(), 22050u) << "the device took less than a second of sound";
  size_t first = samples.size();
  double energy = 0.0;
  for (size_t i = 0; i < samples.size(); ++i)
  {
    if (std::abs(samples[i]) > 1e-3f && first == samples.size())
    {
      first = i;
    }
    energy += double(samples[i]) * samples[i];
  }
  ASSERT_LT(first, samples.size()) << "the window played no sound";
  // 22050 Hz: the first sound at 0.5 s of the clock, after the window opened (up to ~0.4 s
  // of the device running before the clock starts on a loaded machine).
  EXPECT_GT(first, 0.45 * 22050) << "the speech starts at 0.5 s, not at once";
  EXPECT_GT(std::sqrt(energy / samples.size()), 0.01) << "a voice, not a click";

  const auto [muted, silence] = played("--mute");
  EXPECT_EQ(muted.Text.find("sound through"), std::string::npos) << muted.Text;
  for (float v : silence)
  {
    ASSERT_EQ(v, 0.0f) << "--mute played sound";
  }
}

TEST(MorphAvatar, TimeSeriesForParaView)
{
  const std::string pvd = Output + "/avatar_series/talk.pvd";
  vtksys::SystemTools::RemoveADirectory(Output + "/avatar_series");
  const AvatarRun run =
    RunAvatar("--say 'Bob, mama!' --duration 1.5 --fps 10 --quiet --pvd '" + pvd + "'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;

  // The collection lists every frame with its time, in order: one multiblock per frame.
  std::ifstream in(pvd);
  ASSERT_TRUE(in) << pvd;
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::regex entry("<DataSet timestep=\"([^\"]+)\"[^>]*file=\"([^\"]+)\"");
  std::vector<std::pair<double, std::string>> steps;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), entry); it != std::sregex_iterator();
       ++it)
  {
    steps.emplace_back(std::stod((*it)[1]), (*it)[2]);
  }
  ASSERT_EQ(steps.size(), 16u) << xml;

  // Every part of the default head, named, in every frame (skin first).
  const std::vector<std::string> parts = { "Head", "MouthInterior", "UpperTeeth", "LowerTeeth",
    "Tongue", "EyeLeft/Sclera", "EyeLeft/Iris", "EyeLeft/Pupil", "EyeRight/Sclera", "EyeRight/Iris",
    "EyeRight/Pupil", "Eyelashes", "Brows", "Hair", "Ears" };
  double largestMotion = 0.0, largestTeethMotion = 0.0;
  vtkSmartPointer<vtkMultiBlockDataSet> first;
  for (size_t i = 0; i < steps.size(); ++i)
  {
    EXPECT_NEAR(steps[i].first, 0.1 * static_cast<double>(i), 1e-9);
    EXPECT_NE(steps[i].second.find(".vtm"), std::string::npos) << steps[i].second;
    vtkNew<vtkXMLMultiBlockDataReader> reader;
    reader->SetFileName((Output + "/avatar_series/" + steps[i].second).c_str());
    reader->Update();
    auto* head = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
    ASSERT_NE(head, nullptr) << steps[i].second;
    ASSERT_EQ(head->GetNumberOfBlocks(), parts.size()) << steps[i].second;
    for (unsigned int b = 0; b < head->GetNumberOfBlocks(); ++b)
    {
      auto* part = vtkPolyData::SafeDownCast(head->GetBlock(b));
      ASSERT_NE(part, nullptr) << steps[i].second << " block " << b;
      EXPECT_GT(part->GetNumberOfPoints(), 50) << parts[b];
      ASSERT_TRUE(head->HasMetaData(b));
      EXPECT_STREQ(head->GetMetaData(b)->Get(vtkCompositeDataSet::NAME()), parts[b].c_str());
      // Distance maps to colour by, and the weights and the time as field data, on every part.
      EXPECT_NE(part->GetPointData()->GetArray("AnimatedRegion"), nullptr) << parts[b];
      EXPECT_NE(part->GetPointData()->GetArray("Distance_O"), nullptr) << parts[b];
      vtkFieldData* fd = part->GetFieldData();
      ASSERT_NE(fd->GetArray("EffectiveWeights"), nullptr) << parts[b];
      EXPECT_EQ(fd->GetArray("EffectiveWeights")->GetNumberOfTuples(), 13);
      vtkDataArray* weights = fd->GetArray("BehaviorWeights");
      auto* channels = vtkStringArray::SafeDownCast(fd->GetAbstractArray("BehaviorChannels"));
      ASSERT_NE(weights, nullptr);
      ASSERT_NE(channels, nullptr);
      EXPECT_EQ(weights->GetNumberOfTuples(), channels->GetNumberOfValues());
      EXPECT_EQ(channels->GetValue(0), "EyesClosed");
      ASSERT_NE(fd->GetArray("TimeValue"), nullptr);
      EXPECT_NEAR(fd->GetArray("TimeValue")->GetTuple1(0), steps[i].first, 1e-12);
    }
    auto* skin = vtkPolyData::SafeDownCast(head->GetBlock(0));
    ASSERT_GT(skin->GetNumberOfCells(), 1000);
    if (i == 0)
    {
      first = head;
      continue;
    }
    auto motion = [&](unsigned int b)
    {
      auto* now = vtkPolyData::SafeDownCast(head->GetBlock(b));
      auto* then = vtkPolyData::SafeDownCast(first->GetBlock(b));
      double largest = 0.0;
      for (vtkIdType p = 0; p < now->GetNumberOfPoints(); ++p)
      {
        const double* a = now->GetPoint(p);
        double c[3];
        then->GetPoint(p, c);
        largest = std::max(largest,
          std::sqrt((a[0] - c[0]) * (a[0] - c[0]) + (a[1] - c[1]) * (a[1] - c[1]) +
            (a[2] - c[2]) * (a[2] - c[2])));
      }
      return largest;
    };
    largestMotion = std::max(largestMotion, motion(0));
    largestTeethMotion = std::max(largestTeethMotion, motion(3));
  }
  EXPECT_GT(largestMotion, 1e-3) << "the face speaks: the series must not be frozen";
  EXPECT_GT(largestTeethMotion, 1e-3) << "the lower teeth follow the jaw in the series";

  const AvatarRun bad = RunAvatar("--pvd '" + Output + "/x.vtp' --quiet");
  EXPECT_NE(bad.ExitCode, 0);
  EXPECT_NE(bad.Text.find("--pvd takes a file name ending in .pvd"), std::string::npos) << bad.Text;
}

// A recording with its transcript (issue "speech from anywhere"): the mouth moves while the
// recording plays and the video's sound is the recording, placed at 0.5 s.
TEST(MorphAvatar, SpeaksARecordingWithItsSound)
{
#if !MORPHNODE_TEST_ESPEAK
  GTEST_SKIP() << "built without eSpeak NG: the transcript is aligned with eSpeak's rendering";
#endif
  const std::string recording = MORPHNODE_TEST_RECORDING;
  if (!vtksys::SystemTools::FileExists(recording))
  {
    GTEST_SKIP() << "the recording " << recording << " is missing (Debian pocketsphinx-testdata)";
  }
  const std::string dir = Output + "/MorphAvatarRecording";
  vtksys::SystemTools::RemoveADirectory(dir);
  const AvatarRun run = RunAvatar("--audio '" + recording +
    "' --text 'he was not an ill disposed young man' --fps 10 --size 200x200 --duration 4 " +
    "--frames '" + dir + "' --video '" + dir + "/avatar.ogv' --quiet");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;

  // The sound: silence before 0.5 s, then the recording (about 3 s of speech).
  const morphnode::AudioBuffer recorded = morphnode::ReadAudioFile(recording);
  const morphnode::AudioBuffer written = morphnode::ReadAudioFile(dir + "/avatar.wav");
  EXPECT_GT(written.GetDuration(), 0.5 + recorded.GetDuration() - 0.05);
  auto rms = [&](double t0, double t1)
  {
    morphnode::AudioBuffer span;
    span.SampleRate = written.SampleRate;
    span.Channels = 1;
    const morphnode::AudioBuffer mono = morphnode::MixToMono(written);
    const size_t a = static_cast<size_t>(t0 * mono.SampleRate);
    const size_t b = std::min(mono.Samples.size(), static_cast<size_t>(t1 * mono.SampleRate));
    span.Samples.assign(mono.Samples.begin() + static_cast<std::ptrdiff_t>(a),
      mono.Samples.begin() + static_cast<std::ptrdiff_t>(std::max(a, b)));
    return morphnode::RootMeanSquare(span);
  };
  EXPECT_LT(rms(0.0, 0.45), 1e-4) << "the recording starts at 0.5 s";
  EXPECT_GT(rms(0.6, 3.4), 0.01) << "the video's sound must be the recording";

  // The mouth: frames while the recording plays differ from the first (silent) frame.
  auto first = ReadPng(dir + "/frame_00000.png");
  double largest = 0.0;
  for (int f = 8; f < 34; f += 3)
  {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
    largest = std::max(largest, MeanDifference(first, ReadPng(dir + name), 0.15, 0.45));
  }
  EXPECT_GT(largest, 2.0) << "the mouth region does not change while the recording plays";
}

// --audio with the cues Rhubarb Lip Sync computed from the recording (its main use): TSV,
// JSON and XML, and a file whose extension does not tell with --timings-format. The mouth
// is closed where the cues say A and open where they say D, with the recording's sound.
TEST(MorphAvatar, SpeaksARecordingWithRhubarbCues)
{
  const std::string dir = Output + "/MorphAvatarRhubarb";
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir);
  morphnode::AudioBuffer tone;
  tone.SampleRate = 16000;
  tone.Channels = 1;
  for (int i = 0; i < 32000; ++i)
  {
    tone.Samples.push_back(
      0.2f * static_cast<float>(std::sin(2.0 * 3.14159265 * 220.0 * i / 16000.0)));
  }
  morphnode::WriteWavFile(dir + "/take.wav", tone);
  // X (rest) 0-0.4, A (closed) 0.4-0.8, D (wide open) 0.8-1.6, X to the end; the avatar
  // places the recording at 0.5 s.
  std::ofstream(dir + "/take.tsv") << "0.00\tX\n0.40\tA\n0.80\tD\n1.60\tX\n";
  std::ofstream(dir + "/take.xml")
    << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<rhubarbResult><metadata><soundFile>take.wav"
       "</soundFile><duration>2.00</duration></metadata><mouthCues>\n"
       "<mouthCue start=\"0.00\" end=\"0.40\">X</mouthCue>\n<mouthCue start=\"0.40\" "
       "end=\"0.80\">A</mouthCue>\n"
       "<mouthCue start=\"0.80\" end=\"1.60\">D</mouthCue>\n<mouthCue start=\"1.60\" "
       "end=\"2.00\">X</mouthCue>\n"
       "</mouthCues></rhubarbResult>\n";
  std::ofstream(dir + "/take.cues") << "0.00\tX\n0.40\tA\n0.80\tD\n1.60\tX\n";
  double openMinusClosed = 0.0;
  for (const std::string& cues : { std::string("take.tsv"), std::string("take.xml"),
         std::string("take.cues' --timings-format 'rhubarb-tsv") })
  {
    const std::string frames = dir + "/frames_" + cues.substr(5, 3);
    const AvatarRun run = RunAvatar("--audio '" + dir + "/take.wav' --timings '" + dir + "/" +
      cues + "' --fps 10 --size 200x200 --duration 3 --no-overlay --seed 3 --frames '" + frames +
      "' --quiet");
    ASSERT_EQ(run.ExitCode, 0) << cues << ": " << run.Text;
    // 0.5 s + 0.6 s (closed) and 0.5 s + 1.2 s (open) against the first frame (rest).
    auto rest = ReadPng(frames + "/frame_00000.png");
    const double closed = MeanDifference(rest, ReadPng(frames + "/frame_00011.png"), 0.15, 0.45);
    const double open = MeanDifference(rest, ReadPng(frames + "/frame_00017.png"), 0.15, 0.45);
    EXPECT_GT(open, closed + 1.0) << cues << ": closed " << closed << ", open " << open;
    openMinusClosed = open - closed;
  }
  EXPECT_GT(openMinusClosed, 0.0);
  // A file whose extension and content do not tell, without --timings-format: a clear error.
  std::ofstream(dir + "/take.bin") << "hello\n";
  const AvatarRun bad = RunAvatar("--audio '" + dir + "/take.wav' --timings '" + dir +
    "/take.bin' --fps 10 --size 64x64 --duration 1 --frames '" + dir + "/bad' --quiet");
  EXPECT_NE(bad.ExitCode, 0);
  EXPECT_NE(bad.Text.find("--timings-format"), std::string::npos) << bad.Text;
}

namespace
{
/// The largest mean difference of the mouth region between the first frame of `dir` and
/// frames first..last (step 1) at 10 fps.
double LargestMouthChange(const std::string& dir, int first, int last)
{
  auto rest = ReadPng(dir + "/frame_00000.png");
  double largest = 0.0;
  for (int f = first; f <= last; ++f)
  {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
    if (vtksys::SystemTools::FileExists(dir + name))
    {
      largest = std::max(largest, MeanDifference(rest, ReadPng(dir + name), 0.15, 0.45));
    }
  }
  return largest;
}
} // namespace

// An exported performance read back plays its own animation with its sound (it spoke the
// default greeting instead); an animation the file lacks is named with the ones it has.
TEST(MorphAvatar, PlaysTheFilesOwnAnimation)
{
  const std::string dir = Output + "/MorphAvatarAnimation";
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir);
  // The performance: a closure then wide open vowels, as Rhubarb cues (no eSpeak needed).
  std::ofstream(dir + "/cues.tsv") << "0.00\tX\n0.60\tA\n0.90\tD\n2.00\tX\n";
  const AvatarRun exported = RunAvatar("--timings '" + dir +
    "/cues.tsv' --duration 3 --fps 10 --gltf '" + dir + "/performance.glb' --quiet");
  ASSERT_EQ(exported.ExitCode, 0) << exported.Text;
  // A sound for it.
  morphnode::AudioBuffer tone;
  tone.SampleRate = 16000;
  tone.Channels = 1;
  for (int i = 0; i < 40000; ++i)
  {
    tone.Samples.push_back(
      0.2f * static_cast<float>(std::sin(2.0 * 3.14159265 * 220.0 * i / 16000.0)));
  }
  morphnode::WriteWavFile(dir + "/sound.wav", tone);
  for (const std::string& animation : { std::string("0"), std::string("performance") })
  {
    const std::string frames = dir + "/frames_" + animation;
    const AvatarRun run =
      RunAvatar("--face '" + dir + "/performance.glb' --animation " + animation + " --audio '" +
        dir + "/sound.wav' --fps 10 --size 200x200 --no-overlay --frames '" + frames +
        "' --video '" + frames + "/take.ogv' --quiet");
    ASSERT_EQ(run.ExitCode, 0) << run.Text;
    // The animation: rest at 0 s, wide open in 1.0-1.9 s (the cues were placed at 0.5 s).
    EXPECT_GT(LargestMouthChange(frames, 14, 24), 2.0) << animation << ": the mouth does not open";
    EXPECT_LT(LargestMouthChange(frames, 1, 3), 1.0)
      << animation << ": the mouth moves before the performance";
    // The sound: the recording (2.5 s) from 0 s; the run lasts the animation's 3 s.
    const morphnode::AudioBuffer written = morphnode::ReadAudioFile(frames + "/take.wav");
    EXPECT_NEAR(written.GetDuration(), 3.0, 0.15) << animation;
    EXPECT_GT(morphnode::RootMeanSquare(morphnode::MixToMono(written)), 0.05) << animation;
  }
  const AvatarRun missing = RunAvatar(
    "--face '" + dir + "/performance.glb' --animation walk --png '" + dir + "/x.png' --at 1");
  EXPECT_NE(missing.ExitCode, 0);
  EXPECT_NE(missing.Text.find("no animation 'walk' (it has 0 'performance')"), std::string::npos)
    << missing.Text;
}

// A Live Link Face take plays on an ARKit face (its shapes onto the face's targets by name):
// jawOpen rises to 1 at 1 s and falls again.
TEST(MorphAvatar, PlaysALiveLinkTake)
{
  const std::string ict = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  if (!vtksys::SystemTools::FileExists(ict))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found: " << ict;
  }
  const std::string dir = Output + "/MorphAvatarCapture";
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir);
  // The take, 60 rows a second as the app writes them (header and timecodes: docs/capture.md).
  {
    std::ofstream take(dir + "/take.csv");
    take
      << "Timecode,BlendShapeCount,EyeBlinkLeft,EyeLookDownLeft,EyeLookInLeft,EyeLookOutLeft,"
         "EyeLookUpLeft,EyeSquintLeft,EyeWideLeft,EyeBlinkRight,EyeLookDownRight,EyeLookInRight,"
         "EyeLookOutRight,EyeLookUpRight,EyeSquintRight,EyeWideRight,JawForward,JawRight,JawLeft,"
         "JawOpen,MouthClose,MouthFunnel,MouthPucker,MouthRight,MouthLeft,MouthSmileLeft,"
         "MouthSmileRight,MouthFrownLeft,MouthFrownRight,MouthDimpleLeft,MouthDimpleRight,"
         "MouthStretchLeft,MouthStretchRight,MouthRollLower,MouthRollUpper,MouthShrugLower,"
         "MouthShrugUpper,MouthPressLeft,MouthPressRight,MouthLowerDownLeft,MouthLowerDownRight,"
         "MouthUpperUpLeft,MouthUpperUpRight,BrowDownLeft,BrowDownRight,BrowInnerUp,"
         "BrowOuterUpLeft,BrowOuterUpRight,CheekPuff,CheekSquintLeft,CheekSquintRight,"
         "NoseSneerLeft,NoseSneerRight,TongueOut,HeadYaw,HeadPitch,HeadRoll,LeftEyeYaw,"
         "LeftEyePitch,LeftEyeRoll,RightEyeYaw,RightEyePitch,RightEyeRoll\n";
    for (int row = 0; row <= 120; ++row)
    {
      char timecode[32];
      std::snprintf(timecode, sizeof(timecode), "12:00:%02d:%02d.000", row / 60, row % 60);
      take << timecode << ",61";
      const double jaw = std::max(0.0, 1.0 - std::abs(row - 60) / 30.0);
      for (int c = 0; c < 61; ++c)
      {
        take << "," << (c == 17 ? jaw : 0.0);
      }
      take << "\n";
    }
  }
  const AvatarRun run = RunAvatar("--face '" + ict + "' --capture '" + dir +
    "/take.csv' --fps 10 " + "--size 200x200 --no-overlay --frames '" + dir + "/frames'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("51 of 52 ARKit shapes drive 53 of 53 face targets"), std::string::npos)
    << run.Text; // the mapping report
  EXPECT_GT(LargestMouthChange(dir + "/frames", 9, 11), 2.0)
    << "the take's jawOpen does not open the mouth";
  EXPECT_LT(LargestMouthChange(dir + "/frames", 20, 20), 1.0)
    << "the mouth is not closed again at 2 s";
  const AvatarRun bad =
    RunAvatar("--face '" + ict + "' --capture '" + dir + "/take.csv' --say hi --png x.png");
  EXPECT_EQ(bad.ExitCode, 2);
  EXPECT_NE(
    bad.Text.find("--animation and --capture play a recorded performance"), std::string::npos)
    << bad.Text;
}

// A content error reaches the terminal as `MorphAvatar: what: why` lines: no VTK log
// decoration (time stamps, colour codes, source files, addresses), no pipeline echo.
TEST(MorphAvatar, ContentErrorsReadAsProgramLines)
{
  const std::string dir = Output + "/MorphAvatarMessages";
  vtksys::SystemTools::MakeDirectory(dir);
  std::ofstream(dir + "/bad.pho") << "a 100\np not-a-number\n";
  std::ofstream(dir + "/bad.json") << "{\"name\": \"bad\", \"shapes\": {\"A\": {\"jawOpn\": 1}}}";
  for (const std::string& arguments :
    { "--timings '" + dir + "/bad.pho' --png '" + dir + "/x.png' --at 1",
      "--face '" + std::string(MORPHNODE_SOURCE_DIR) +
        "/Data/DefaultFace/default_head.glb' --rig '" + dir + "/bad.json' --png '" + dir +
        "/x.png' --at 1" })
  {
    const AvatarRun run = RunAvatar(arguments);
    EXPECT_NE(run.ExitCode, 0) << arguments;
    EXPECT_EQ(run.Text.find("\x1b["), std::string::npos) << run.Text;
    EXPECT_EQ(run.Text.find("ERR|"), std::string::npos) << run.Text;
    EXPECT_EQ(run.Text.find("(0x"), std::string::npos) << run.Text;
    EXPECT_EQ(run.Text.find(".cxx"), std::string::npos) << run.Text;
    EXPECT_EQ(run.Text.find("returned failure"), std::string::npos) << run.Text;
    std::istringstream lines(run.Text);
    std::string line;
    int count = 0;
    while (std::getline(lines, line))
    {
      if (!line.empty())
      {
        EXPECT_EQ(line.rfind("MorphAvatar: ", 0), 0u) << "not a program line: " << line;
        ++count;
      }
    }
    EXPECT_GE(count, 1) << arguments;
  }
}

// The skinned avatar in MorphAvatar: by default the skin filter poses only and every part is
// skinned in the vertex shader (vtkMorphSkinMapper); --cpu-skin re-skins on the CPU. The
// greeting's frame at 1.33 s (the head turned to the user, eyes and mouth moving) must be
// the same picture both ways (the threshold of the frame tests above); the control: the
// frame at 0.5 s differs from it.
TEST(MorphAvatar, SkinnedAvatarOnTheGpuLooksAsOnTheCpu)
{
  const std::string avatar = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(avatar);
  const std::string frame = "--face '" + avatar + "' --script '" + Source +
    "/Data/scripts/greeting.txt' --seed 2004 --size 320x320 ";
  const std::string cpu = Output + "/MorphAvatarSkinCpu.png";
  AvatarRun run = RunAvatar(frame + "--at 1.33 --cpu-skin --png '" + cpu + "'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("skin: 7 parts, re-skinned on the CPU"), std::string::npos) << run.Text;
  run = RunAvatar(frame + "--at 1.33 --png '" + Output + "/MorphAvatarSkinGpu.png' --compare '" +
    cpu + "' --compare-threshold 0.5");
  EXPECT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("skin: 7 parts, 7 skinned in the vertex shader"), std::string::npos)
    << run.Text;
  EXPECT_NE(run.Text.find("matches"), std::string::npos) << run.Text;
  run = RunAvatar(frame + "--at 0.5 --quiet --png '" + Output +
    "/MorphAvatarSkinGpuOther.png' --compare '" + cpu + "' --compare-threshold 0.5");
  EXPECT_EQ(run.ExitCode, 1) << run.Text;
  EXPECT_NE(run.Text.find("differs from"), std::string::npos) << run.Text;
}

// --gltf writes the face's own materials and images back (vtkMorphTargetReader's
// MaterialIndex/MaterialSource, vtkMorphGltfWriter): the MakeHuman avatar's export re-read by
// the core loader has the source's materials, in the same order on the same parts, and every
// base colour texture with the source's pixels and the part's texture coordinates. Without
// them the export had one untextured material per base colour.
TEST(MorphAvatar, GltfExportKeepsTheFacesMaterials)
{
  const std::string avatar = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(avatar);
  const std::string dir = Output + "/MorphAvatarGltfMaterials";
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir);
  std::ofstream(dir + "/cues.tsv") << "0.00\tX\n0.30\tA\n0.60\tX\n";
  const AvatarRun run = RunAvatar("--face '" + avatar + "' --timings '" + dir +
    "/cues.tsv' --duration 1 --fps 10 --gltf '" + dir + "/avatar.glb' --quiet");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  const morphnode::GltfScene source = morphnode::LoadGltfScene(avatar);
  const morphnode::GltfScene back = morphnode::LoadGltfScene(dir + "/avatar.glb");
  // The control: what is compared is the avatar's materials and textures, not empty lists.
  ASSERT_EQ(source.Materials.size(), 6u);
  ASSERT_EQ(source.Images.size(), 3u);
  EXPECT_EQ(back.Materials.size(), source.Materials.size());
  EXPECT_EQ(back.Images.size(), source.Images.size());
  ASSERT_EQ(back.Parts.size(), source.Parts.size());
  int textured = 0;
  for (const morphnode::GltfPart& part : back.Parts)
  {
    const auto it = std::find_if(source.Parts.begin(), source.Parts.end(),
      [&](const morphnode::GltfPart& p) { return p.Name == part.Name; });
    ASSERT_NE(it, source.Parts.end()) << part.Name;
    ASSERT_GE(part.Material, 0) << part.Name;
    ASSERT_EQ(part.Material, it->Material) << part.Name;
    const morphnode::GltfMaterial& was = source.Materials[static_cast<size_t>(it->Material)];
    const morphnode::GltfMaterial& is = back.Materials[static_cast<size_t>(part.Material)];
    EXPECT_EQ(is.Name, was.Name) << part.Name;
    EXPECT_EQ(is.AlphaMode, was.AlphaMode) << part.Name;
    EXPECT_EQ(is.BaseColorTexture.IsSet(), was.BaseColorTexture.IsSet()) << part.Name;
    if (!was.BaseColorTexture.IsSet() || !is.BaseColorTexture.IsSet())
    {
      continue;
    }
    ++textured;
    const morphnode::GltfImage& a = source.Images[static_cast<size_t>(was.BaseColorTexture.Image)];
    const morphnode::GltfImage& b = back.Images[static_cast<size_t>(is.BaseColorTexture.Image)];
    EXPECT_EQ(b.Width, a.Width) << part.Name;
    EXPECT_EQ(b.Height, a.Height) << part.Name;
    EXPECT_TRUE(b.Pixels == a.Pixels) << part.Name << ": the base colour image differs";
    EXPECT_EQ(part.TexCoords0.size(), it->TexCoords0.size())
      << part.Name << ": no texture coordinates";
  }
  // The eyes, eyebrows and eyelashes are the avatar's textured parts.
  EXPECT_EQ(textured, 4);
}
