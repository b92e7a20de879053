// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar --frame-budget MS (Modules/Applications/MorphAvatar/AvatarFrameBudget.h): the
// morph filter chooses its threshold every frame from the morph times it measured. The same
// fixed-seed animation runs with a budget no morph can miss (1 s) and one no morph can meet
// (0.1 us); the per-frame log must show the choices adapt: the loose run never prunes, the
// tight one prunes on every frame at least as much and, when there is anything to prune,
// more. Both extremes hold on a loaded machine (timing noise cannot move a morph across
// either budget). Run under `xvfb-run -a`.
#include "MorphAvatarRun.h"

#include "vtksys/SystemTools.hxx"

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
    std::string index, threshold, active, ms;
    std::getline(fields, index, ',');
    std::getline(fields, threshold, ',');
    std::getline(fields, active, ',');
    std::getline(fields, ms, ',');
    frames.push_back({ std::stod(threshold), std::stoi(active), std::stod(ms) });
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
  const std::string common = "--duration 1 --fps 10 --size 96x96 --offscreen --frames '" + dir + "' ";
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
