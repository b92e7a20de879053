// SPDX-License-Identifier: BSD-3-Clause
// Lip sync in ten languages, measured on a real face's geometry (as TestLipSyncOnFace does
// for English): eSpeak NG speaks a sentence of each language, its phonemes find their
// visemes by articulation (no table written for the language), the ARKit rig turns them
// into the ICT face's targets and vtkMorphNodeFilter blends them. At every bilabial stop
// or nasal the lips touch as at rest; at every close rounded vowel the lips push forward
// (the face's own pucker direction) clearly more than at the spread vowels; at every
// labiodental the lower lip rolls in.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "rig/Rig.h"
#include "speech/Articulation.h"
#include "speech/Speech.h"

#include "MorphNodeRigTrackPose.h"
#include "MorphNodeTestSkips.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

vtkDataArray* TargetDelta(
  vtkPolyData* face, const std::vector<std::string>& names, const std::string& name)
{
  for (size_t k = 1; k < names.size(); ++k)
  {
    if (names[k] == name)
    {
      return face->GetPointData()->GetArray(
        ("target" + std::to_string(k - 1) + "_position").c_str());
    }
  }
  return nullptr;
}

/// The vertex a target moves the most, optionally only near the face's midline.
vtkIdType MostMoved(vtkPolyData* face, vtkDataArray* delta, bool midlineOnly)
{
  double bounds[6];
  face->GetBounds(bounds);
  const double centre = 0.5 * (bounds[0] + bounds[1]), midline = 0.01 * (bounds[1] - bounds[0]);
  vtkIdType best = -1;
  double largest = 0.0;
  for (vtkIdType i = 0; delta && i < face->GetNumberOfPoints(); ++i)
  {
    if (midlineOnly && std::abs(face->GetPoint(i)[0] - centre) > midline)
    {
      continue;
    }
    const double* v = delta->GetTuple3(i);
    const double moved = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (moved > largest)
    {
      largest = moved;
      best = i;
    }
  }
  return best;
}

struct Sentence
{
  const char* Voice;
  const char* Text;
};

class LipSyncLanguages : public ::testing::TestWithParam<Sentence>
{
};
} // namespace

TEST_P(LipSyncLanguages, LipsCloseRoundAndBiteOnTheFace)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found: " << IctGlb;
  }
  const Sentence sentence = GetParam();
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0);
  reader->Update();
  vtkPolyData* face = reader->GetOutput();
  std::vector<std::string> names;
  for (int k = 0; k < reader->GetNumberOfTargets(); ++k)
  {
    names.emplace_back(reader->GetTargetName(k));
  }
  // Landmarks from the targets themselves: lip centres, mouth corners, the rolled lower lip.
  const vtkIdType upper = MostMoved(face, TargetDelta(face, names, "mouthUpperUp_L"), true);
  const vtkIdType lower = MostMoved(face, TargetDelta(face, names, "mouthLowerDown_L"), true);
  vtkDataArray* roll = TargetDelta(face, names, "mouthRollLower");
  vtkDataArray* pucker = TargetDelta(face, names, "mouthPucker");
  const vtkIdType rolled = MostMoved(face, roll, true);
  const vtkIdType puckered = MostMoved(face, pucker, true);
  ASSERT_TRUE(upper >= 0 && lower >= 0 && rolled >= 0 && puckered >= 0);
  // How far a vertex moved along a target's own delta there, in units of that delta.
  auto along = [&](vtkPointSet* out, vtkIdType i, vtkDataArray* delta)
  {
    const double* d = delta->GetTuple3(i);
    double dot = 0.0, length2 = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      dot += (out->GetPoint(i)[k] - face->GetPoint(i)[k]) * d[k];
      length2 += d[k] * d[k];
    }
    return dot / length2;
  };

  morphnode::Rig rig =
    morphnode::Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
  rig.Bind(std::vector<std::string>(names.begin() + 1, names.end()));
  morphnode::SpeechOptions options;
  options.Voice = sentence.Voice;
  std::vector<std::string> warnings;
  options.Warn = morphnode::CollectWarnings(warnings);
  const morphnode::VisemeMap map = morphnode::SelectVisemeMap(options);
  const morphnode::Utterance speech = morphnode::SpeakText(sentence.Text, options);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const morphnode::WeightTrack& visemes = speech.Visemes;
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morphnode_test::RigTrackPose pose(rig, visemes, morph);
  ASSERT_EQ(pose.GetMissingShape(), "");
  struct Measure
  {
    double Gap, Pucker, Roll;
  };
  auto measure = [&](double t)
  {
    vtkPointSet* out = pose.At(t);
    return Measure{ out->GetPoint(upper)[1] - out->GetPoint(lower)[1], along(out, puckered, pucker),
      along(out, rolled, roll) };
  };
  const Measure rest = measure(-1.0); // before the utterance: the neutral face
  const double lead = options.Coarticulation.Lead;
  const double frame = 1.0 / visemes.GetFrameRate();
  int closures = 0, rounded = 0, bites = 0;
  double roundedPucker = 0.0, spreadPucker = 0.0;
  int spread = 0;
  for (const auto& p : speech.Phonemes)
  {
    const std::vector<std::string> parts = morphnode::SplitPhone(p.Sampa);
    if (parts.size() != 1)
    {
      continue; // diphthongs move on
    }
    const morphnode::Articulation a = morphnode::DescribePhone(parts[0]);
    const double centre = p.Start + 0.5 * p.Duration - lead;
    auto best = [&](auto&& value, bool smallest)
    {
      double v = value(measure(centre));
      for (double t : { centre - frame, centre + frame })
      {
        v = smallest ? std::min(v, value(measure(t))) : std::max(v, value(measure(t)));
      }
      return v;
    };
    if (map.IsClosurePhoneme(p.Sampa))
    {
      EXPECT_LT(best([](const Measure& m) { return m.Gap; }, true), rest.Gap + 0.001)
        << sentence.Voice << " " << p.Sampa << " at " << p.Start << " s: lips not closed";
      ++closures;
    }
    else if (a.Type == morphnode::Articulation::Kind::Vowel && p.Duration >= 0.05)
    {
      // Close rounded vowels (u, y, ʊ, ʏ) push the lips forward (the face's own pucker
      // direction): at least a fifth of the full pucker, and more than the spread vowels on
      // average. (The rig's open-mid rounded shape, oh, opens the jaw more than it rounds,
      // so o and ɔ are checked on the viseme track only, in TestArticulation.)
      const double forward = best([](const Measure& m) { return m.Pucker; }, false);
      if (a.Rounded && a.Height <= 0.2)
      {
        EXPECT_GT(forward, 0.2) << sentence.Voice << " " << p.Sampa << " at " << p.Start
                                << " s: lips not rounded";
        roundedPucker += forward;
        ++rounded;
      }
      else if (a.Backness < 0.3)
      {
        spreadPucker += forward;
        ++spread;
      }
    }
    else if (a.Type == morphnode::Articulation::Kind::Consonant &&
      a.Place == morphnode::ArticulationPlace::Labiodental)
    {
      EXPECT_GT(best([](const Measure& m) { return m.Roll; }, false), 0.3)
        << sentence.Voice << " " << p.Sampa << " at " << p.Start
        << " s: lower lip not at the teeth";
      ++bites;
    }
  }
  if (rounded > 0 && spread > 0)
  {
    EXPECT_GT(roundedPucker / rounded, spreadPucker / spread + 0.15) << sentence.Voice;
  }
  EXPECT_GE(closures, 1) << sentence.Voice;
  EXPECT_GE(rounded, 1) << sentence.Voice;
  EXPECT_GE(bites, 1) << sentence.Voice;
}

INSTANTIATE_TEST_SUITE_P(Languages, LipSyncLanguages,
  ::testing::Values(Sentence{ "fr", "Vous avez bu du beau vin, mon ami." },
    Sentence{ "es", "Un buen vino fuerte para Pablo y su amigo." },
    Sentence{ "it", "Il lupo buono beve vino fuori con Paolo." },
    Sentence{ "pt", "O bom vinho fica para o povo da vila." },
    Sentence{ "nl", "De boer fietst voor de molen met zijn vriend." },
    Sentence{ "pl", "Mój brat pije wodę w fabryce i mówi dużo." },
    Sentence{ "sv", "Fem bullar och ost på bordet i kväll." },
    Sentence{ "fi", "Vuori on pieni ja puu on vanha, sanoi isä." },
    Sentence{ "tr", "Bu ufak köpek vapurda oturuyor, bence iyi." },
    Sentence{ "cs", "Pes bude vařit polévku pro mého bratra." }),
  [](const auto& info) { return std::string(info.param.Voice); });
