// SPDX-License-Identifier: BSD-3-Clause
// Lip sync end to end on a real face: eSpeak NG speaks an English sentence, its phonemes
// become Meta/Oculus visemes with coarticulation, the ARKit rig turns them into the ICT
// face's own targets, and vtkMorphNodeFilter blends them. Measured on the geometry: at
// every p, b and m the lips touch as in the (closed-mouth) neutral; at every open vowel
// they are apart.
#include "MorphNodeRigTrackPose.h"
#include "MorphNodeTestUtilities.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "rig/Rig.h"
#include "speech/Speech.h"

#include "MorphNodeTestSkips.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

/// The midline vertex (|x| small) that a pair of targets moves the most: the centre of
/// the upper lip for mouthUpperUp_L/R, of the lower lip for mouthLowerDown_L/R.
vtkIdType MostMovedMidlineVertex(vtkPolyData* face, const std::vector<std::string>& names,
  const std::string& left, const std::string& right)
{
  vtkDataArray* deltas[2] = { nullptr, nullptr };
  for (size_t k = 1; k < names.size(); ++k)
  {
    const std::string array = "target" + std::to_string(k - 1) + "_position";
    if (names[k] == left)
    {
      deltas[0] = face->GetPointData()->GetArray(array.c_str());
    }
    if (names[k] == right)
    {
      deltas[1] = face->GetPointData()->GetArray(array.c_str());
    }
  }
  if (!deltas[0] || !deltas[1])
  {
    return -1;
  }
  double bounds[6];
  face->GetBounds(bounds);
  const double midline = 0.01 * (bounds[1] - bounds[0]);
  vtkIdType best = -1;
  double largest = 0.0;
  for (vtkIdType i = 0; i < face->GetNumberOfPoints(); ++i)
  {
    if (std::abs(face->GetPoint(i)[0] - 0.5 * (bounds[0] + bounds[1])) > midline)
    {
      continue;
    }
    double moved = 0.0;
    for (vtkDataArray* d : deltas)
    {
      const double* v = d->GetTuple3(i);
      moved += std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    if (moved > largest)
    {
      largest = moved;
      best = i;
    }
  }
  return best;
}
} // namespace

TEST(LipSyncOnFace, BilabialsCloseAndOpenVowelsOpenTheLips)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found: " << IctGlb;
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctGlb.c_str());
  reader->SetMeshIndex(0); // one mesh, one vtkPolyData
  reader->Update();
  vtkPolyData* face = reader->GetOutput();
  std::vector<std::string> names;
  for (int k = 0; k < reader->GetNumberOfTargets(); ++k)
  {
    names.emplace_back(reader->GetTargetName(k));
  }
  ASSERT_EQ(names.size(), 54u);

  const vtkIdType upper = MostMovedMidlineVertex(face, names, "mouthUpperUp_L", "mouthUpperUp_R");
  const vtkIdType lower =
    MostMovedMidlineVertex(face, names, "mouthLowerDown_L", "mouthLowerDown_R");
  ASSERT_GE(upper, 0);
  ASSERT_GE(lower, 0);
  ASSERT_NE(upper, lower);

  morphnode::Rig rig =
    morphnode::Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
  rig.Bind(std::vector<std::string>(names.begin() + 1, names.end()));

  morphnode::SpeechOptions options;
  options.Voice = "en";
  options.Visemes = morphnode::VisemeSet::Oculus15;
  const morphnode::VisemeMap map = morphnode::SelectVisemeMap(options);
  const morphnode::Utterance speech =
    morphnode::SpeakText("Maybe Bob parked the big boat by the palm, Pam.", options);
  const morphnode::WeightTrack& visemes = speech.Visemes;
  ASSERT_GT(visemes.GetNumberOfFrames(), 10u);

  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morphnode_test::RigTrackPose pose(rig, visemes, morph); // viseme channel -> rig shape
  ASSERT_EQ(pose.GetMissingShape(), "") << "the ARKit rig has no shape " << pose.GetMissingShape();
  // The vertical gap between the lip centres at time t of the viseme track.
  auto lipGap = [&](double t)
  {
    vtkPointSet* out = pose.At(t);
    return out->GetPoint(upper)[1] - out->GetPoint(lower)[1];
  };

  const double restingGap = face->GetPoint(upper)[1] - face->GetPoint(lower)[1]; // the neutral
  const double lead = options.Coarticulation.Lead;
  const double frame = 1.0 / visemes.GetFrameRate();
  int closures = 0, openings = 0;
  for (const auto& p : speech.Phonemes)
  {
    // The mouth leads the sound: the viseme of a phoneme centred at c shows at c - lead.
    const double centre = p.Start + 0.5 * p.Duration - lead;
    if (map.IsClosurePhoneme(p.Sampa))
    {
      // Closed within one frame of the phoneme's centre: no wider than at rest + 1 mm.
      const double gap =
        std::min({ lipGap(centre - frame), lipGap(centre), lipGap(centre + frame) });
      EXPECT_LT(gap, restingGap + 0.001) << p.Sampa << " at " << p.Start << " s";
      ++closures;
    }
    else if (map.GetVisemes()[static_cast<size_t>(map.MapPhoneme(p.Sampa))] == "aa")
    {
      EXPECT_GT(lipGap(centre), restingGap + 0.004) << p.Sampa << " at " << p.Start << " s";
      ++openings;
    }
  }
  EXPECT_GE(closures, 8) << "the sentence has at least 8 bilabials";
  EXPECT_GE(openings, 2) << "the sentence has open vowels";
}
