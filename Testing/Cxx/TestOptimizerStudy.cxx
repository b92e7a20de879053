// SPDX-License-Identifier: BSD-3-Clause
// The optimizer study's claims, checked on its long speech-driven animation of the ICT face
// (docs/optimizer-study.md): Data/scripts/long-text.txt spoken with eSpeak NG, seeded
// behaviour on top, expanded through the ARKit rig (the track of MakeSpeechTrack,
// Modules/Applications/Tools/SpeechTrack.h). Skipped when the ICT face is absent. Also the
// study's methods, named by the optimizer presets.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "SpeechTrack.h"
#include "StudyMethods.h"
#include "morph/MorphMesh.h"

#include "base/Text.h"
#include "morph/OptimizerPresets.h"
#include "morph/OptimizerQuality.h"
#include "rig/Rig.h"

#include "vtkNew.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace
{
const std::string Face = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

/// The face's model and a ~50 s speech-driven track of absolute weights, built once.
class OptimizerStudy : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    if (!std::filesystem::exists(Face))
    {
      return;
    }
    Reader = vtkSmartPointer<vtkMorphTargetReader>::New();
    Reader->SetFileName(Face.c_str());
    Reader->SetMeshIndex(0); // one mesh, one vtkPolyData
    Reader->SetNormalsMode(vtkMorphTargetReader::NORMALS_FROM_FILE);
    Morph = vtkSmartPointer<vtkMorphNodeFilter>::New();
    Morph->SetInputConnection(Reader->GetOutputPort());
    Morph->SetWeightModeToRelative();
    Morph->Update();
    const morphnode::MorphMesh* model = Morph->GetMorphModel();
    ASSERT_NE(model, nullptr);
    ASSERT_GE(model->GetPositionAttribute(), 0);
    Positions = std::get_if<morphnode::MorphAttribute<float>>(
      &model->GetAttribute(static_cast<size_t>(model->GetPositionAttribute())));
    ASSERT_NE(Positions, nullptr);
    Distances = model->ComputeDistances();

    // The study's track (Modules/Applications/Tools/SpeechTrack.h, as MakeSpeechTrack
    // writes it with its defaults): the long text, seed 2004, 30 fps.
    morphnode::study::SpeechTrackOptions options;
    options.Text =
      morphnode::text::ReadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/long-text.txt");
    morphnode::Rig rig =
      morphnode::Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
    rig.Bind(*model);
    const morphnode::WeightTrack semantic = morphnode::study::MakeBehaviorTrack(options);
    ASSERT_GT(semantic.GetNumberOfFrames() / semantic.GetFrameRate(), 30.0)
      << "not a long animation";
    const std::vector<std::string> names(
      model->GetTargetNames().begin() + 1, model->GetTargetNames().end());
    const morphnode::WeightTrack relative =
      morphnode::study::ExpandThroughRig(semantic, rig, names);
    Absolute = std::make_unique<morphnode::WeightTrack>(
      morphnode::ToAbsoluteWeights(relative, model->GetTargetNames()));
  }
  static void TearDownTestSuite()
  {
    Absolute.reset();
    Morph = nullptr;
    Reader = nullptr;
  }
  void SetUp() override
  {
    if (!std::filesystem::exists(Face))
    {
      GTEST_SKIP() << "ICT face not found: " << Face;
    }
    ASSERT_TRUE(Absolute && Positions) << "the face or the track could not be built";
  }

  static std::vector<morphnode::FrameQuality> Run(
    const std::string& name, const morphnode::OptimizerSettings& s)
  {
    return morphnode::MeasureOptimizerQuality(*Positions, Distances, *Absolute, { name, s });
  }

  static vtkSmartPointer<vtkMorphTargetReader> Reader;
  static vtkSmartPointer<vtkMorphNodeFilter> Morph;
  static const morphnode::MorphAttribute<float>* Positions;
  static morphnode::TargetDistances Distances;
  static std::unique_ptr<morphnode::WeightTrack> Absolute;
};
vtkSmartPointer<vtkMorphTargetReader> OptimizerStudy::Reader;
vtkSmartPointer<vtkMorphNodeFilter> OptimizerStudy::Morph;
const morphnode::MorphAttribute<float>* OptimizerStudy::Positions = nullptr;
morphnode::TargetDistances OptimizerStudy::Distances;
std::unique_ptr<morphnode::WeightTrack> OptimizerStudy::Absolute;

// The blends are float; a vertex error computed from them carries rounding of well
// under a micrometre (the face is in metres, ~0.3 m across).
constexpr double FloatSlack = 1e-6;

double MeanMaxError(const std::vector<morphnode::FrameQuality>& frames)
{
  double sum = 0.0;
  for (const auto& q : frames)
  {
    sum += q.MaxError;
  }
  return frames.empty() ? 0.0 : sum / static_cast<double>(frames.size());
}
} // namespace

TEST_F(OptimizerStudy, ErrorBoundHoldsOnEveryFrame)
{
  struct Case
  {
    std::string Name;
    morphnode::OptimizerSettings Settings;
  };
  std::vector<Case> cases;
  for (double eps : { 0.0005, 0.001, 0.002 })
  {
    // The bound alone (the error-bounded method): greedy pruning, neutral redistribution.
    cases.push_back({ "error-bounded " + std::to_string(eps),
      morphnode::MakeOptimizerSettings(morphnode::OptimizerPreset::ErrorBounded, 0.0, eps) });
  }
  {
    morphnode::OptimizerSettings s; // with a threshold: restoring, paper's redistribution
    s.Threshold = 0.3;
    s.AdjustThreshold = true;
    s.Strategy = morphnode::Redistribution::Remaining;
    s.MaxVertexError = 0.001;
    cases.push_back({ "adjusted 0.3, eps 1 mm", s });
    s.AdjustThreshold = false;
    s.Strategy = morphnode::Redistribution::Maximum;
    cases.push_back({ "fixed-maximum 0.3, eps 1 mm", s });
  }
  {
    morphnode::OptimizerSettings s; // with a budget and hysteresis: the bound wins
    s.MaxActiveTargets = 4;
    s.Hysteresis = 0.25;
    s.Strategy = morphnode::Redistribution::Neutral;
    s.MaxVertexError = 0.0005;
    cases.push_back({ "budget 4, eps 0.5 mm", s });
  }
  for (const auto& c : cases)
  {
    const auto frames = Run(c.Name, c.Settings);
    ASSERT_EQ(frames.size(), Absolute->GetNumberOfFrames());
    int pruning = 0;
    for (size_t f = 0; f < frames.size(); ++f)
    {
      const auto& q = frames[f];
      ASSERT_LE(q.ErrorBound, c.Settings.MaxVertexError + 1e-12) << c.Name << ", frame " << f;
      ASSERT_LE(q.MaxError, q.ErrorBound + FloatSlack) << c.Name << ", frame " << f;
      ASSERT_LE(q.MaxError, c.Settings.MaxVertexError + FloatSlack) << c.Name << ", frame " << f;
      pruning += q.ErrorBound > 0.0 ? 1 : 0;
    }
    // Not vacuous: the method did change the weights on most frames.
    EXPECT_GT(pruning, static_cast<int>(frames.size() / 2)) << c.Name;
  }
}

// What docs/optimizer-study.md finds, at the same threshold: the adjusted threshold keeps
// more targets than the fixed one at both 0.3 and 0.5; at 0.3 it has the lower mean
// largest vertex error (study: 7.31 against 8.09 mm), at 0.5 the *higher* (9.73 against
// 9.33 mm), although it still keeps more targets (2.00 against 0.88). So "adjusted beats
// fixed" holds at 0.3 only, and only because it keeps more targets (see the matched
// comparison there). The orderings are checked, not the figures: the track follows the
// speech code (on 2026-11-23 this test measured 6.74 / 7.61 mm and 9.13 / 8.54 mm).
TEST_F(OptimizerStudy, AdjustedAgainstFixedAtTheSameThreshold)
{
  using morphnode::OptimizerPreset;
  auto meanActive = [](const std::vector<morphnode::FrameQuality>& frames)
  {
    double sum = 0.0;
    for (const auto& q : frames)
    {
      sum += q.ActiveTargets;
    }
    return frames.empty() ? 0.0 : sum / static_cast<double>(frames.size());
  };
  for (double threshold : { 0.3, 0.5 })
  {
    const std::string th = std::to_string(threshold).substr(0, 3);
    const auto fixed = Run("fixed-remaining " + th,
      morphnode::MakeOptimizerSettings(OptimizerPreset::FixedRemaining, threshold, 0.0));
    const auto adjusted = Run("adjusted " + th,
      morphnode::MakeOptimizerSettings(OptimizerPreset::Adjusted, threshold, 0.0));
    const double fixedError = 1e3 * MeanMaxError(fixed),
                 adjustedError = 1e3 * MeanMaxError(adjusted);
    // The adjusted threshold keeps more targets at both thresholds...
    EXPECT_GT(meanActive(adjusted), meanActive(fixed)) << "threshold " << th;
    // ... and beats the fixed one at 0.3 but not at 0.5.
    if (threshold < 0.4)
    {
      EXPECT_LT(adjustedError, fixedError) << "mean largest vertex error (mm) at " << th;
    }
    else
    {
      EXPECT_GT(adjustedError, fixedError) << "mean largest vertex error (mm) at " << th;
    }
    // The triangle-inequality bound B holds for the paper's methods too.
    for (const auto* frames : { &fixed, &adjusted })
    {
      for (size_t i = 0; i < frames->size(); ++i)
      {
        ASSERT_LE((*frames)[i].MaxError, (*frames)[i].ErrorBound + FloatSlack) << "frame " << i;
      }
    }
  }
}

TEST(OptimizerStudyMethods, NamedByThePresets)
{
  using morphnode::OptimizerPreset;
  const auto methods = morphnode::study::StudyMethods({ 0.1, 0.3 }, { 0.05 }, { 2 });
  ASSERT_EQ(methods.size(), 1u + 2 * 3 + 1 + 1);
  const struct
  {
    const char* Name;
    OptimizerPreset Preset;
    double Threshold, Bound;
  } expected[] = { { "none", OptimizerPreset::None, 0, 0 },
    { "fixed-maximum 0.1", OptimizerPreset::FixedMaximum, 0.1, 0 },
    { "fixed-remaining 0.1", OptimizerPreset::FixedRemaining, 0.1, 0 },
    { "adjusted 0.1", OptimizerPreset::Adjusted, 0.1, 0 },
    { "fixed-maximum 0.3", OptimizerPreset::FixedMaximum, 0.3, 0 },
    { "fixed-remaining 0.3", OptimizerPreset::FixedRemaining, 0.3, 0 },
    { "adjusted 0.3", OptimizerPreset::Adjusted, 0.3, 0 },
    { "error-bounded 0.05", OptimizerPreset::ErrorBounded, 0, 0.05 } };
  for (size_t m = 0; m < std::size(expected); ++m)
  {
    const auto& e = expected[m];
    EXPECT_EQ(methods[m].Name, e.Name);
    const auto s = morphnode::MakeOptimizerSettings(e.Preset, e.Threshold, e.Bound);
    EXPECT_EQ(methods[m].Settings.Threshold, s.Threshold) << e.Name;
    EXPECT_EQ(methods[m].Settings.Strategy, s.Strategy) << e.Name;
    EXPECT_EQ(methods[m].Settings.AdjustThreshold, s.AdjustThreshold) << e.Name;
    EXPECT_EQ(methods[m].Settings.MaxVertexError, s.MaxVertexError) << e.Name;
    EXPECT_EQ(
      morphnode::study::MethodFamily(methods[m].Name), morphnode::OptimizerPresetName(e.Preset));
  }
  EXPECT_EQ(methods.back().Name, "budget 2");
  EXPECT_EQ(methods.back().Settings.MaxActiveTargets, 2);
  EXPECT_EQ(methods.back().Settings.Strategy, morphnode::Redistribution::Neutral);

  // The sweep: fixed-remaining and adjusted at 0.25 and 0.5 for a step of 0.25.
  const auto sweep = morphnode::study::SweepMethods(0.25, 0.5);
  ASSERT_EQ(sweep.size(), 4u);
  EXPECT_EQ(sweep[0].Name, "fixed-remaining 0.25");
  EXPECT_EQ(sweep[3].Name, "adjusted 0.5");
  EXPECT_TRUE(sweep[3].Settings.AdjustThreshold);
  EXPECT_TRUE(morphnode::study::SweepMethods(0.0).empty());
}
