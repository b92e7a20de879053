// SPDX-License-Identifier: BSD-3-Clause
// The optimizer study's claims, checked on a long speech-driven animation of the ICT face
// (docs/optimizer-study.md): Data/scripts/long-text.txt spoken with eSpeak NG, seeded
// behaviour on top, expanded through the ARKit rig (as Examples/Cxx/MakeSpeechTrack does).
// Skipped when the ICT face is absent.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "morph/MorphMesh.h"
#include "morph/OptimizerQuality.h"
#include "behavior/BehaviorController.h"
#include "rig/Rig.h"
#include "speech/Speech.h"

#include "vtkNew.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
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

    std::ifstream in(std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/long-text.txt");
    ASSERT_TRUE(in);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (char& c : text)
    {
      c = c == '\n' ? ' ' : c;
    }
    morphnode::Rig rig = morphnode::Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
    rig.Bind(*model);
    morphnode::BehaviorController behavior;
    behavior.SetSeed(2004);
    behavior.SetFrameRate(30.0);
    behavior.SetSynthesizer([](const std::string& t) { return morphnode::SpeakText(t); });
    behavior.SetMood("happy", 0.3, 0.0);
    behavior.Say(text, 0.6);
    const double end = behavior.GetUtterances().back().End;
    // A brow raise, a smile, a frown and a glance every few seconds.
    for (double t = 1.5; t < end - 1.0; t += 2.5)
    {
      switch (static_cast<int>(t) % 4)
      {
        case 0:
          behavior.Gesture("raise_brows", t, 0.9, 0.7);
          break;
        case 1:
          behavior.Gesture("smile", t, 1.8, 0.6);
          break;
        case 2:
          behavior.Gesture("frown", t, 0.8, 0.5);
          break;
        default:
          behavior.LookAt(15.0, 5.0, t, 1.0);
      }
    }
    const morphnode::WeightTrack semantic = behavior.GenerateTrack();
    ASSERT_GT(semantic.GetNumberOfFrames() / semantic.GetFrameRate(), 30.0) << "not a long animation";

    std::vector<int> shapeOf(semantic.GetNumberOfChannels());
    for (size_t c = 0; c < shapeOf.size(); ++c)
    {
      shapeOf[c] = rig.FindShape(semantic.GetChannels()[c]);
    }
    std::vector<std::string> names(model->GetTargetNames().begin() + 1, model->GetTargetNames().end());
    morphnode::WeightTrack relative(names, semantic.GetFrameRate());
    std::vector<double> shapes(rig.GetNumberOfShapes()), weights(rig.GetNumberOfBoundTargets());
    for (size_t f = 0; f < semantic.GetNumberOfFrames(); ++f)
    {
      std::fill(shapes.begin(), shapes.end(), 0.0);
      for (size_t c = 0; c < shapeOf.size(); ++c)
      {
        if (shapeOf[c] >= 0)
        {
          shapes[static_cast<size_t>(shapeOf[c])] += semantic.GetValue(f, c);
        }
      }
      rig.Expand(shapes.data(), weights.data());
      relative.AppendFrame(weights);
    }
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

  static std::vector<morphnode::FrameQuality> Run(const std::string& name, const morphnode::OptimizerSettings& s)
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
    morphnode::OptimizerSettings s; // the bound alone: greedy pruning (neutral)
    s.MaxVertexError = eps;
    s.Strategy = morphnode::Redistribution::Neutral;
    cases.push_back({ "error-bounded " + std::to_string(eps), s });
  }
  {
    morphnode::OptimizerSettings s; // with a threshold: restoring, paper's redistribution
    s.Threshold = 0.3;
    s.AdjustThreshold = true;
    s.Strategy = morphnode::Redistribution::Remaining;
    s.MaxVertexError = 0.001;
    cases.push_back({ "adjusted+remaining 0.3, eps 1 mm", s });
    s.AdjustThreshold = false;
    s.Strategy = morphnode::Redistribution::Maximum;
    cases.push_back({ "fixed+maximum 0.3, eps 1 mm", s });
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

TEST_F(OptimizerStudy, AdjustedBeatsFixedAtTheSameThreshold)
{
  morphnode::OptimizerSettings s;
  s.Threshold = 0.3;
  s.Strategy = morphnode::Redistribution::Remaining;
  const auto fixed = Run("fixed+remaining 0.3", s);
  s.AdjustThreshold = true;
  const auto adjusted = Run("adjusted+remaining 0.3", s);
  const double fixedError = MeanMaxError(fixed), adjustedError = MeanMaxError(adjusted);
  EXPECT_LT(adjustedError, fixedError) << "mean largest vertex error (m), adjusted against fixed";
  // The triangle-inequality bound B holds for the paper's methods too.
  for (const auto* frames : { &fixed, &adjusted })
  {
    for (size_t f = 0; f < frames->size(); ++f)
    {
      ASSERT_LE((*frames)[f].MaxError, (*frames)[f].ErrorBound + FloatSlack) << "frame " << f;
    }
  }
}
