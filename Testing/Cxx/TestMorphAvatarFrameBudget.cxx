// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar --frame-budget MS (Modules/Applications/MorphAvatar/AvatarFrameBudget.h): the
// morph filter chooses its threshold every frame from the morph times it measured. The same
// fixed-seed animation runs with a budget no morph can miss (1 s) and one no morph can meet
// (0.1 us); the per-frame log must show the choices adapt: the loose run never prunes, the
// tight one prunes on every frame at least as much and, when there is anything to prune,
// more. Both extremes hold on a loaded machine (timing noise cannot move a morph across
// either budget). Run under `xvfb-run -a`.
#include "MorphAvatarRun.h"
#include "MorphNodeImageSimilarity.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"

#include "vtksys/SystemTools.hxx"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using morphnode_test::AvatarRun;
using morphnode_test::RunAvatar;

namespace
{
const std::string Output = MORPHNODE_TEST_OUTPUT_DIR;

struct Frame
{
  double Threshold = -1.0;
  int Active = -1;
  double Milliseconds = -1.0;
  int Level = -1;   ///< the mesh level shown
  long Points = -1; ///< the morph output's points
};

std::vector<Frame> ReadLog(const std::string& file)
{
  std::vector<Frame> frames;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line))
  {
    std::istringstream fields(line);
    std::string index, threshold, active, ms, budget, level, points;
    std::getline(fields, index, ',');
    std::getline(fields, threshold, ',');
    std::getline(fields, active, ',');
    std::getline(fields, ms, ',');
    std::getline(fields, budget, ',');
    std::getline(fields, level, ',');
    std::getline(fields, points, ',');
    frames.push_back({ std::stod(threshold), std::stoi(active), std::stod(ms), std::stoi(level),
      std::stol(points) });
  }
  return frames;
}

std::vector<Frame> RunWithBudget(const std::string& budget, std::string& text)
{
  const std::string dir = Output + "/TestMorphAvatarFrameBudget_" + budget;
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir);
  const std::string log = dir + "/budget.csv";
  // Speech when eSpeak NG is there (many targets to choose among), idle behaviour else.
  const std::string behaviour = MORPHNODE_TEST_ESPEAK
    ? "--say 'Hello, how are you today?' --duration 2 "
    : "--script '" + std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/idle.txt' --duration 3 ";
  const AvatarRun run = RunAvatar(behaviour + "--seed 11 --fps 20 --size 96x96 --method adjusted " +
    "--offscreen --frames '" + dir + "' --frame-budget " + budget + " --frame-budget-log '" + log +
    "'");
  text = run.Text;
  EXPECT_EQ(run.ExitCode, 0) << run.Text;
  return ReadLog(log);
}
} // namespace

TEST(MorphAvatarFrameBudget, ChoicesAdaptToTheBudget)
{
  std::string looseText, tightText;
  const std::vector<Frame> loose = RunWithBudget("1000", looseText);
  const std::vector<Frame> tight = RunWithBudget("0.0001", tightText);
  std::cout << looseText << tightText;
  ASSERT_GE(loose.size(), 30u);
  ASSERT_EQ(loose.size(), tight.size());
  int looseActive = 0, tightActive = 0, pruning = 0;
  for (size_t f = 0; f < loose.size(); ++f)
  {
    // Every frame's morph was measured.
    EXPECT_GT(loose[f].Milliseconds, 0.0) << f;
    EXPECT_GT(tight[f].Milliseconds, 0.0) << f;
    // 1 s always fits: the least error, no pruning.
    EXPECT_EQ(loose[f].Threshold, 0.0) << f;
    // Nothing fits: the cheapest choice, never more targets than the loose run's.
    EXPECT_LE(tight[f].Active, loose[f].Active) << f;
    looseActive += loose[f].Active;
    tightActive += tight[f].Active;
    pruning += loose[f].Active >= 2 ? 1 : 0; // a target the threshold may take
  }
  if (pruning > 0)
  {
    EXPECT_LT(tightActive, looseActive) << pruning << " frames with two or more active targets";
  }
  // The summary of each run.
  EXPECT_NE(looseText.find("within budget 100.0 %"), std::string::npos) << looseText;
  EXPECT_NE(tightText.find("within budget 0.0 %"), std::string::npos) << tightText;
}

TEST(MorphAvatarFrameBudget, BadLogIsAUsageError)
{
  const AvatarRun run = RunAvatar("--duration 1 --offscreen --frames '" + Output +
    "' --frame-budget 1 --frame-budget-log /nonexistent/dir/budget.csv");
  EXPECT_EQ(run.ExitCode, 2) << run.Text;
  EXPECT_NE(run.Text.find("--frame-budget-log"), std::string::npos) << run.Text;
}

TEST(MorphAvatarFrameBudget, ProfilesSetTheBudget)
{
  // --profile phone: the phone's 0.4 ms budget and its pixel bound, with the target level of
  // detail from the camera; --frame-budget overrides the budget; an unknown profile is a
  // usage error naming the known ones.
  const std::string dir = Output + "/TestMorphAvatarFrameBudget_profile";
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir);
  const std::string log = dir + "/budget.csv";
  const std::string common =
    "--duration 1 --fps 10 --size 96x96 --offscreen --frames '" + dir + "' ";
  AvatarRun run = RunAvatar(common + "--profile phone --frame-budget-log '" + log + "'");
  EXPECT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("frame budget 0.4 ms"), std::string::npos) << run.Text;
  EXPECT_GE(ReadLog(log).size(), 9u);
  run = RunAvatar(common + "--profile laptop --frame-budget 3");
  EXPECT_EQ(run.ExitCode, 0) << run.Text;
  EXPECT_NE(run.Text.find("frame budget 3 ms"), std::string::npos) << run.Text;
  run = RunAvatar(common + "--profile watch");
  EXPECT_EQ(run.ExitCode, 2) << run.Text;
  EXPECT_NE(run.Text.find("desktop|laptop|phone"), std::string::npos) << run.Text;
}

namespace
{
vtkSmartPointer<vtkImageData> ReadFrame(const std::string& file)
{
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

/// --profile phone with the face about 150 px high against the full mesh (a 1 s budget, no
/// levels), the same track: the mesh levels (vtkMorphNodeFilter's MeshLevels) draw a level
/// coarser than the full mesh on every frame (the log's level and the morph output's
/// points), and the picture stays the face's: its mouth region is closer (SSIM) to the full
/// mesh's render of the same frame than the full mesh's own render a third of a second
/// later is (the negative control: the mouth moved). `face`: --face's argument, or empty.
void PhoneAgainstFull(const std::string& face, const std::string& name)
{
  const std::string dir = Output + "/TestMorphAvatarFrameBudget_" + name;
  vtksys::SystemTools::RemoveADirectory(dir);
  vtksys::SystemTools::MakeDirectory(dir + "/full");
  vtksys::SystemTools::MakeDirectory(dir + "/phone");
  // Speech when eSpeak NG is there (a moving mouth for the negative control), idle else.
  const std::string behaviour = MORPHNODE_TEST_ESPEAK
    ? "--say 'Hello, how are you today?' "
    : "--script '" + std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/idle.txt' ";
  const std::string common = behaviour + (face.empty() ? "" : "--face '" + face + "' ") +
    "--duration 1.5 --seed 11 --fps 6 --size 192x192 --no-overlay --offscreen ";
  AvatarRun run = RunAvatar(common + "--frames '" + dir +
    "/full' --frame-budget 1000 --frame-budget-log '" + dir + "/full.csv'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  const std::vector<Frame> full = ReadLog(dir + "/full.csv");
  run = RunAvatar(common + "--frames '" + dir + "/phone' --profile phone --frame-budget-log '" +
    dir + "/phone.csv'");
  ASSERT_EQ(run.ExitCode, 0) << run.Text;
  const std::vector<Frame> phone = ReadLog(dir + "/phone.csv");
  ASSERT_GE(full.size(), 8u);
  ASSERT_EQ(phone.size(), full.size());
  for (size_t f = 0; f < full.size(); ++f)
  {
    EXPECT_EQ(full[f].Level, 0) << f;
    EXPECT_GE(phone[f].Level, 1) << f;
    EXPECT_LT(phone[f].Points, full[f].Points * 3 / 4) << f;
  }
  std::cout << name << ": full mesh " << full[0].Points << " points, phone level "
            << phone.back().Level << " " << phone.back().Points << " points\n";
  EXPECT_NE(run.Text.find("mesh levels shown: level"), std::string::npos) << run.Text;
  if (!MORPHNODE_TEST_ESPEAK)
  {
    return;
  }
  auto frame = [&](const std::string& which, int i)
  {
    char file[32];
    std::snprintf(file, sizeof(file), "/frame_%05d.png", i);
    return ReadFrame(dir + "/" + which + file);
  };
  // The mouth: the middle third across, from a fifth to two fifths up the frame.
  const int w = 192, h = 192;
  auto mouth = [&](vtkImageData* a, vtkImageData* b)
  { return morphnode_test::Ssim(a, b, w / 3, 2 * w / 3, h / 5, 2 * h / 5); };
  double same = 1.0, later = 1.0;
  for (int i = 2; i + 2 < static_cast<int>(full.size()); ++i)
  {
    same = std::min(same, mouth(frame("phone", i), frame("full", i)));
    later = std::min(later, mouth(frame("full", i + 2), frame("full", i)));
  }
  std::cout << name << ": mouth SSIM, phone vs full, same frame (worst) " << same
            << "; full vs full 1/3 s later (worst) " << later << "\n";
  EXPECT_GT(same, later);
  EXPECT_GT(same, 0.93);
}
} // namespace

TEST(MorphAvatarFrameBudget, PhoneDrawsACoarserLevel)
{
  PhoneAgainstFull("", "phone");
}

TEST(MorphAvatarFrameBudget, PhoneDrawsTheSkinnedAvatarCoarser)
{
  // The MakeHuman avatar's skinned parts reduced: their gathered joints and weights still
  // skin them (vtkMorphSkinFilter downstream), so the face stays where the full one is.
  const std::string avatar = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(avatar);
  PhoneAgainstFull(avatar, "phone_skinned");
}
