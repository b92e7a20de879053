// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The lip-gap study of docs/optimizer-study.md, shared by its test (TestRigLips) and its
// program (LipGapStudy): a face (a glTF scene, a rig onto its targets), a spoken text, and
// the lip gap at every frame for the unoptimized blend and for every optimizer method,
// deciding per face target (the optimizer on the rig's expansion) or per rig shape
// (rig/RigOptimizer.h).

#include "base/Error.h"
#include "gltf/GltfMorphMesh.h"
#include "gltf/GltfScene.h"
#include "morph/MorphScene.h"
#include "morph/OptimizerPresets.h"
#include "morph/WeightOptimizer.h"
#include "rig/LipMeasures.h"
#include "rig/Rig.h"
#include "rig/RigOptimizer.h"
#include "speech/Speech.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace morphnode_lips
{
using namespace morphnode;

struct FaceSpec
{
  std::string Name;
  std::string File;
  std::string RigFile; ///< empty: the face's own targets are the shapes
  VisemeSet Visemes = VisemeSet::Oculus15;
  std::string Open;   ///< an open vowel's shape (finds the lips)
  std::string Spread; ///< a shape that pulls the mouth corners apart (finds them)
  double MillimetresPerUnit = 1000.0;
};

/// A face read for the study: its targets, the rig onto them, the lips and the corners.
struct StudyFace
{
  FaceSpec Spec;
  GltfScene Scene;
  Rig Shapes;
  std::vector<std::string> Targets; ///< the face's targets (no neutral), union over parts
  TargetDistances TargetFigures;    ///< neutral first, per face target
  TargetDistances ShapeFigures;     ///< neutral first, per rig shape
  size_t LipPart = 0;
  LipPair Lips;
  std::array<size_t, 2> Corners{ { 0, 0 } };
  std::vector<const float*> LipDeltas; ///< per face target: the lip part's deltas or nullptr
  double Diagonal = 0.0;               ///< of the whole scene, in units

  /// Relative target weights -> the lip gap in millimetres.
  double Gap(const std::vector<double>& targetWeights) const
  {
    const auto& points = this->Scene.Parts[this->LipPart].Positions;
    const auto u = BlendPoint(points, this->LipDeltas, targetWeights.data(), this->Lips.Upper);
    const auto l = BlendPoint(points, this->LipDeltas, targetWeights.data(), this->Lips.Lower);
    return (u[1] - l[1]) * this->Spec.MillimetresPerUnit;
  }
  double RestGap() const { return this->Lips.RestGap * this->Spec.MillimetresPerUnit; }
  /// Corner to corner in millimetres.
  double MouthWidth(const std::vector<double>& targetWeights) const
  {
    const auto& points = this->Scene.Parts[this->LipPart].Positions;
    const auto a = BlendPoint(points, this->LipDeltas, targetWeights.data(), this->Corners[0]);
    const auto b = BlendPoint(points, this->LipDeltas, targetWeights.data(), this->Corners[1]);
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
             (a[2] - b[2]) * (a[2] - b[2])) *
      this->Spec.MillimetresPerUnit;
  }
  std::vector<double> ExpandShape(const std::string& shape, double weight = 1.0) const
  {
    return this->Shapes.Expand(std::map<std::string, double>{ { shape, weight } });
  }
};

/// An identity rig: one shape per target, named like it.
inline Rig IdentityRig(const std::vector<std::string>& targets)
{
  std::ostringstream json;
  json << "{\"name\": \"identity\", \"shapes\": {";
  for (size_t t = 0; t < targets.size(); ++t)
  {
    json << (t ? ", " : "") << "\"" << targets[t] << "\": {\"" << targets[t] << "\": 1.0}";
  }
  json << "}}";
  return Rig::LoadString(json.str(), "identity rig");
}

inline std::vector<double> DenseOpening(
  const StudyFace& face, size_t part, const std::vector<double>& w)
{
  const GltfPart& p = face.Scene.Parts[part];
  std::vector<double> d(p.Positions.size(), 0.0);
  for (const auto& target : p.Targets)
  {
    const auto it = std::find(face.Targets.begin(), face.Targets.end(), target.Name);
    const double weight = w[static_cast<size_t>(it - face.Targets.begin())];
    for (size_t v = 0; weight != 0.0 && v < d.size(); ++v)
    {
      d[v] += weight * target.PositionDeltas[v];
    }
  }
  return d;
}

/// Reads the face, binds the rig, measures targets and shapes, finds the lips.
inline std::unique_ptr<StudyFace> LoadStudyFace(const FaceSpec& spec)
{
  auto face = std::make_unique<StudyFace>();
  face->Spec = spec;
  face->Scene = LoadGltfScene(spec.File);
  std::vector<NamedTargetDistances> targetPieces, shapePieces;
  std::vector<MorphMesh> meshes;
  double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
  for (const GltfPart& part : face->Scene.Parts)
  {
    for (size_t p = 0; p < part.Positions.size(); ++p)
    {
      lo[p % 3] = std::min(lo[p % 3], static_cast<double>(part.Positions[p]));
      hi[p % 3] = std::max(hi[p % 3], static_cast<double>(part.Positions[p]));
    }
    if (part.Targets.empty())
    {
      continue;
    }
    meshes.push_back(GltfPartToMorphMesh(part));
    const TargetDistances d = meshes.back().ComputeDistances();
    targetPieces.push_back({ meshes.back().GetTargetNames(), d.DistMorph, d.MaxDisplacement });
  }
  face->Diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  const NamedTargetDistances targets = CombineTargetDistances(targetPieces);
  face->TargetFigures = MakeTargetDistances(targets);
  face->Targets.assign(targets.Names.begin() + 1, targets.Names.end());
  face->Shapes = spec.RigFile.empty() ? IdentityRig(face->Targets) : Rig::LoadFile(spec.RigFile);
  face->Shapes.Bind(face->Targets);
  for (const MorphMesh& mesh : meshes)
  {
    shapePieces.push_back(ComputeShapeDistances(face->Shapes, mesh));
  }
  face->ShapeFigures = MakeTargetDistances(CombineTargetDistances(shapePieces));

  const double unit = 1.0 / spec.MillimetresPerUnit; // one millimetre in units
  const std::vector<double> open = face->ExpandShape(spec.Open);
  double best = 0.0;
  for (size_t part = 0; part < face->Scene.Parts.size(); ++part)
  {
    LipPair pair;
    if (FindLipPair(face->Scene.Parts[part].Positions, DenseOpening(*face, part, open), 1.5 * unit,
          4.0 * unit, pair) &&
      pair.Opening > best)
    {
      best = pair.Opening;
      face->Lips = pair;
      face->LipPart = part;
    }
  }
  if (best == 0.0)
  {
    throw InputError(spec.Name + ": no lips found");
  }
  const GltfPart& lipPart = face->Scene.Parts[face->LipPart];
  face->LipDeltas.assign(face->Targets.size(), nullptr);
  for (const auto& target : lipPart.Targets)
  {
    const auto it = std::find(face->Targets.begin(), face->Targets.end(), target.Name);
    face->LipDeltas[static_cast<size_t>(it - face->Targets.begin())] = target.PositionDeltas.data();
  }
  // The corners, centred on the face's midline (x of the lips).
  std::vector<float> centred = lipPart.Positions;
  const float cx = lipPart.Positions[3 * face->Lips.Upper];
  for (size_t p = 0; p < centred.size(); p += 3)
  {
    centred[p] -= cx;
  }
  if (!FindMouthCorners(
        centred, DenseOpening(*face, face->LipPart, face->ExpandShape(spec.Spread)), face->Corners))
  {
    throw InputError(spec.Name + ": no mouth corners found");
  }
  return face;
}

/// How the optimizer sees the weights.
enum class Decide
{
  PerTarget, ///< on the rig's expansion (the face's targets)
  PerShape   ///< on the rig's shapes (RigOptimizer), then expanded
};

/// The lip gap (mm) at every frame of `visemes` (channels named after rig shapes) with the
/// optimizer's settings `s` (inactive: the unoptimized blend).
inline std::vector<double> LipGaps(
  const StudyFace& face, const WeightTrack& visemes, const OptimizerSettings& s, Decide decide)
{
  const Rig& rig = face.Shapes;
  std::vector<int> shapeOf(visemes.GetNumberOfChannels());
  for (size_t c = 0; c < shapeOf.size(); ++c)
  {
    shapeOf[c] = rig.FindShape(visemes.GetChannels()[c]);
  }
  WeightOptimizer perTarget;
  perTarget.SetSettings(s);
  perTarget.SetTargetDistances(face.TargetFigures);
  RigOptimizer perShape;
  perShape.SetSettings(s);
  perShape.SetShapeDistances(face.ShapeFigures);
  std::vector<double> shapes(rig.GetNumberOfShapes()), effective(shapes.size());
  std::vector<double> targets(face.Targets.size()), absolute(targets.size() + 1);
  std::vector<double> gaps;
  for (size_t f = 0; f < visemes.GetNumberOfFrames(); ++f)
  {
    std::fill(shapes.begin(), shapes.end(), 0.0);
    for (size_t c = 0; c < shapeOf.size(); ++c)
    {
      if (shapeOf[c] >= 0)
      {
        shapes[static_cast<size_t>(shapeOf[c])] += visemes.GetValue(f, c);
      }
    }
    if (decide == Decide::PerShape)
    {
      perShape.Optimize(shapes.data(), effective.data());
      rig.Expand(effective.data(), targets.data());
    }
    else
    {
      rig.Expand(shapes.data(), targets.data());
      if (s.IsActive())
      {
        double sum = 0.0;
        for (size_t t = 0; t < targets.size(); ++t)
        {
          absolute[t + 1] = targets[t];
          sum += targets[t];
        }
        absolute[0] = 1.0 - sum;
        const std::vector<double> e = perTarget.Optimize(absolute);
        std::copy(e.begin() + 1, e.end(), targets.begin());
      }
    }
    gaps.push_back(face.Gap(targets));
  }
  return gaps;
}

/// The frames of the track at the centres of the bilabials (p, b, m): the mouth leads the
/// sound by the coarticulation's lead.
inline std::vector<size_t> BilabialFrames(
  const Utterance& speech, const VisemeMap& map, double lead)
{
  std::vector<size_t> frames;
  const double fps = speech.Visemes.GetFrameRate();
  for (const auto& p : speech.Phonemes)
  {
    if (map.IsClosurePhoneme(p.Sampa))
    {
      const double centre = p.Start + 0.5 * p.Duration - lead;
      const long f = std::lround(centre * fps);
      if (f >= 0 && static_cast<size_t>(f) < speech.Visemes.GetNumberOfFrames())
      {
        frames.push_back(static_cast<size_t>(f));
      }
    }
  }
  return frames;
}

/// The smallest gap within one frame of `frame`.
inline double GapNear(const std::vector<double>& gaps, size_t frame)
{
  double g = gaps[frame];
  if (frame > 0)
  {
    g = std::min(g, gaps[frame - 1]);
  }
  if (frame + 1 < gaps.size())
  {
    g = std::min(g, gaps[frame + 1]);
  }
  return g;
}
} // namespace morphnode_lips
