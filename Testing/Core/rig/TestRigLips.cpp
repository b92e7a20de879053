// SPDX-License-Identifier: BSD-3-Clause
// Lips that close on every face: a long text spoken by eSpeak NG, its visemes through each
// shipped or shared face's rig, and the lip gap (measured on the geometry: the midline
// vertices of the upper and lower lip that touch at rest) at every bilabial (p, b, m).
// Every optimizer method deciding per rig shape (rig/RigOptimizer.h) must close them; the
// default method (adjusted) deciding per face target left the ICT head's open (its PP lost
// mouthClose and kept jawOpen), which the negative control shows the measure sees.
// Also: the ICT head's rounded vowel oh is narrower than the mouth at rest and than aa.
#include "LipGapStudy.h"

#include "MorphNodeTestSkips.h"
#include "base/Text.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iomanip>
#include <iostream>

using namespace morphnode_lips;

namespace
{
const std::string Source = MORPHNODE_SOURCE_DIR;
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
const std::string Avatar = std::string(MORPHNODE_AVATAR_DIR) + "/makehuman_avatar.glb";

std::vector<FaceSpec> Faces()
{
  return {
    { "default face", Source + "/Data/DefaultFace/default_head.glb", "", VisemeSet::Paper6, "A",
      "MouthSmile", 1000.0 },
    { "ICT head", IctHead, Source + "/Data/rigs/arkit.json", VisemeSet::Oculus15, "aa",
      "MouthSmile", 1000.0 },
    { "MakeHuman avatar", Avatar, Source + "/Data/rigs/readyplayerme.json", VisemeSet::Oculus15,
      "aa", "MouthSmile", 1000.0 },
  };
}

const Utterance& Speech(VisemeSet set)
{
  static std::map<VisemeSet, Utterance> spoken;
  auto found = spoken.find(set);
  if (found == spoken.end())
  {
    SpeechOptions options;
    options.Voice = "en";
    options.Visemes = set;
    options.Coarticulation.FrameRate = 30.0;
    const std::string text = text::ReadFile(Source + "/Data/scripts/long-text.txt", "text");
    found = spoken.emplace(set, SpeakText(text, options)).first;
  }
  return found->second;
}

bool Present(const FaceSpec& face)
{
  return std::ifstream(face.File).good();
}
} // namespace

TEST(RigLips, EveryMethodDecidingPerShapeClosesEveryBilabialOnEveryFace)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  int faces = 0;
  for (const FaceSpec& spec : Faces())
  {
    if (!Present(spec))
    {
      std::cout << "[ SKIPPED  ] " << spec.Name << ": not found at " << spec.File << "\n";
      continue;
    }
    ++faces;
    const auto face = LoadStudyFace(spec);
    SpeechOptions options;
    options.Visemes = spec.Visemes;
    const VisemeMap map = SelectVisemeMap(options);
    const Utterance& speech = Speech(spec.Visemes);
    const std::vector<size_t> bilabials = BilabialFrames(speech, map, options.Coarticulation.Lead);
    ASSERT_GE(bilabials.size(), 20u) << "the long text has many bilabials";
    const double closed = face->RestGap() + 0.5; // touching as at rest, within 0.5 mm
    const double eps = 0.005 * face->Diagonal;   // MorphAvatar's default bound
    for (int m = 0; m < NumberOfOptimizerPresets; ++m)
    {
      const auto preset = static_cast<OptimizerPreset>(m);
      const OptimizerSettings s = MakeOptimizerSettings(preset, 0.1, eps);
      const std::vector<double> gaps = LipGaps(*face, speech.Visemes, s, Decide::PerShape);
      int open = 0;
      for (size_t f : bilabials)
      {
        open += GapNear(gaps, f) > closed ? 1 : 0;
      }
      EXPECT_EQ(open, 0) << spec.Name << ", " << OptimizerPresetName(preset) << ": " << open
                         << " of " << bilabials.size() << " bilabials open (rest gap "
                         << face->RestGap() << " mm)";
    }
  }
  if (faces < 3 && std::getenv("CI"))
  {
    FAIL() << "CI needs the shared faces (ICT-FaceKit, MakeHuman avatar)";
  }
}

// The negative control: the same measure sees the ICT head's open lips when the default
// method decides per face target (the fault this file guards against).
TEST(RigLips, DecidingPerTargetOpensTheIctHeadsBilabials)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  const FaceSpec spec = Faces()[1];
  if (!Present(spec))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found: " << spec.File;
  }
  const auto face = LoadStudyFace(spec);
  SpeechOptions options;
  const VisemeMap map = SelectVisemeMap(options);
  const Utterance& speech = Speech(VisemeSet::Oculus15);
  const auto bilabials = BilabialFrames(speech, map, options.Coarticulation.Lead);
  const OptimizerSettings s = MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.1, 0.0);
  const std::vector<double> gaps = LipGaps(*face, speech.Visemes, s, Decide::PerTarget);
  int open = 0;
  for (size_t f : bilabials)
  {
    open += GapNear(gaps, f) > face->RestGap() + 0.5 ? 1 : 0;
  }
  EXPECT_GT(open, static_cast<int>(bilabials.size()) / 2);
}

// Method 1 (fixed threshold, pruned weight to the largest) hands pruned weight to a whole
// shape: the lips open at most a little more than unoptimized (per target it was jawOpen
// that received it: up to 23 mm more).
TEST(RigLips, FixedMaximumDecidingPerShapeDoesNotOverOpen)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  for (const FaceSpec& spec : Faces())
  {
    if (!Present(spec))
    {
      continue;
    }
    const auto face = LoadStudyFace(spec);
    const Utterance& speech = Speech(spec.Visemes);
    const auto none = LipGaps(*face, speech.Visemes, OptimizerSettings{}, Decide::PerShape);
    const auto maximum = LipGaps(*face, speech.Visemes,
      MakeOptimizerSettings(OptimizerPreset::FixedMaximum, 0.1, 0.0), Decide::PerShape);
    double worst = 0.0;
    for (size_t f = 0; f < none.size(); ++f)
    {
      worst = std::max(worst, maximum[f] - none[f]);
    }
    EXPECT_LT(worst, 5.0) << spec.Name << ": the lips open " << worst
                          << " mm more than unoptimized";
  }
}

TEST(RigLips, RoundedVowelsRoundTheIctHead)
{
  const FaceSpec spec = Faces()[1];
  if (!Present(spec))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found: " << spec.File;
  }
  const auto face = LoadStudyFace(spec);
  const double rest = face->MouthWidth(std::vector<double>(face->Targets.size(), 0.0));
  const double oh = face->MouthWidth(face->ExpandShape("oh"));
  const double ou = face->MouthWidth(face->ExpandShape("ou"));
  const double aa = face->MouthWidth(face->ExpandShape("aa"));
  std::cout << "mouth width (mm): rest " << rest << ", aa " << aa << ", oh " << oh << ", ou " << ou
            << "\n";
  // Rounded: at least 12 % narrower than at rest (ou: 17 %; the rig's earlier oh, jawOpen 0.4,
  // mouthFunnel 0.4, mouthPucker 0.1, was 10 % narrower and opened nearly like aa).
  EXPECT_LT(oh, 0.88 * rest);
  EXPECT_LT(oh, aa - 3.0);
  EXPECT_LT(ou, oh);
}
