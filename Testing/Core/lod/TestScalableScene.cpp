// SPDX-License-Identifier: BSD-3-Clause
// Every part of an avatar on its own ladder under one controller (ScalableScene), and a
// skinned part's ladder: its influences follow the ladder's renumbering, so a reduced level
// skins as the full mesh does, within the level's error.
#include "Core/reduction/ReductionTestMesh.h"
#include "base/Error.h"
#include "lod/MorphLadder.h"
#include "lod/ScalableScene.h"
#include "skin/Skinning.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

using morphnode::MorphLadder;
using morphnode::ScalableScene;

namespace
{
/// A flat face scaled and moved, with the targets `keep` of the four, renamed `names`.
morphnode::MorphMesh Part(int n, float scale, float dx, const std::vector<size_t>& keep,
  const std::vector<std::string>& names)
{
  reductiontest::FlatFace f = reductiontest::MakeFlatFace(n);
  for (size_t i = 0; i < f.Positions.size(); ++i)
  {
    f.Positions[i] = f.Positions[i] * scale + (i % 3 == 0 ? dx : 0.0f);
  }
  std::vector<std::vector<float>> deltas;
  for (size_t k : keep)
  {
    deltas.push_back(f.PositionDeltas[k]);
    for (float& v : deltas.back())
    {
      v *= scale;
    }
  }
  f.PositionDeltas = deltas;
  morphnode::MorphMesh mesh = f.ToMesh();
  mesh.SetTargetNames(names);
  return mesh;
}

struct Scene
{
  ScalableScene::Ladders Parts;
  Scene()
  {
    // A: the face with its four targets. B: a smaller mesh three times as large (so its
    // level errors are the largest), with target1 and a target of its own. C: too small to
    // reduce, one level.
    morphnode::LadderSettings one;
    one.TriangleFractions.clear();
    this->Parts = {
      std::make_shared<const MorphLadder>(
        morphnode::BuildMorphLadder(reductiontest::MakeFace(41), {})),
      std::make_shared<const MorphLadder>(morphnode::BuildMorphLadder(
        Part(21, 3.0f, 4.0f, { 1, 0 }, { "Neutral", "target1", "extra" }), {})),
      std::make_shared<const MorphLadder>(morphnode::BuildMorphLadder(
        Part(5, 0.2f, -1.0f, { 0, 1, 2, 3 }, morphnode::DefaultTargetNames(5)), one)),
    };
  }
};

const Scene& TheScene()
{
  static const Scene scene;
  return scene;
}

/// Speech-like absolute weights over the scene's six targets (neutral first).
std::vector<double> SceneWeights(int frame)
{
  std::vector<double> w(6, 0.0);
  for (size_t k = 1; k < w.size(); ++k)
  {
    const double s =
      std::sin(0.05 * frame * (1.0 + 0.37 * static_cast<double>(k)) + static_cast<double>(k));
    w[k] = std::max(0.0, s) * 0.3;
  }
  double sum = 0.0;
  for (size_t k = 1; k < w.size(); ++k)
  {
    sum += w[k];
  }
  w[0] = 1.0 - sum;
  return w;
}

/// The largest part error (Error99) at scene level l.
double SceneError(const ScalableScene::Ladders& parts, size_t l)
{
  double e = 0.0;
  for (const auto& p : parts)
  {
    e = std::max(e, p->Levels[std::min(l, p->Levels.size() - 1)].Error99);
  }
  return e;
}
} // namespace

TEST(ScalableScene, EveryPartOnItsOwnBufferSwitchingTogether)
{
  const ScalableScene::Ladders& parts = TheScene().Parts;
  ScalableScene scene;
  morphnode::ControllerSettings s;
  s.FrameBudget = 1.0; // the screen decides
  s.Thresholds = { 0.0 };
  s.PixelBound = 1.0;
  s.MinFramesPerLevel = 1;
  scene.SetSettings(s);
  scene.SetParts(parts, ScalableScene::Calibrate(parts));
  ASSERT_EQ(scene.GetNumberOfParts(), 3u);
  ASSERT_EQ(scene.GetNumberOfLevels(), 4u);
  // Targets matched by name: B's target1 drives the scene's target1, its own is new.
  const std::vector<std::string> names = { "Neutral", "target0", "target1", "target2", "target3",
    "extra" };
  EXPECT_EQ(scene.GetTargetNames(), names);
  EXPECT_EQ(scene.GetTargetMap(1), (std::vector<size_t>{ 0, 2, 5 }));
  // B is three times as large: its errors set the scene's.
  for (size_t l = 1; l < 4; ++l)
  {
    EXPECT_GT(parts[1]->Levels[l].Error99, parts[0]->Levels[l].Error99) << "level " << l;
    EXPECT_DOUBLE_EQ(scene.GetSceneLevel(l, {}).GeometricError, SceneError(parts, l));
  }

  int switches = 0, lastLevel = 0, transitions = 0;
  for (int f = 0; f < 400; ++f)
  {
    const std::vector<double> w = SceneWeights(f);
    const double ppu = 20000.0 * std::pow(1e-4, f / 399.0);
    const morphnode::SceneFrame& frame = scene.Update(w, ppu);
    const auto& d = frame.Decision;
    // The level's pixel error is the largest part's (during a geomorph, on the way to the
    // coarser level's).
    double error = SceneError(parts, static_cast<size_t>(d.Level));
    if (d.MorphTowards >= 0)
    {
      error +=
        d.Alpha * std::max(0.0, SceneError(parts, static_cast<size_t>(d.MorphTowards)) - error);
    }
    EXPECT_NEAR(d.LevelPixelError, error * ppu, 1e-9 * ppu);
    switches += d.Level != lastLevel;
    lastLevel = d.Level;
    transitions += d.MorphTowards >= 0;
    size_t total = 0;
    for (size_t p = 0; p < parts.size(); ++p)
    {
      const MorphLadder& ladder = *parts[p];
      // Every part at the scene's level (a part with fewer levels at its coarsest).
      const int pl = std::min(d.Level, static_cast<int>(ladder.Levels.size()) - 1);
      ASSERT_EQ(frame.PartLevels[p], pl) << "frame " << f << " part " << p;
      const size_t n = ladder.Levels[static_cast<size_t>(pl)].NumberOfPoints;
      ASSERT_EQ(frame.PartPoints[p], n);
      total += n;
      EXPECT_EQ(&scene.GetTriangles(p), &ladder.Levels[static_cast<size_t>(pl)].Triangles);
      // One vertex buffer per part: its positions span the part's points once, whatever
      // the level.
      ASSERT_EQ(scene.GetPositions(p).size(), 3 * ladder.Mesh.GetNumberOfPoints());
      // The part's prefix is its own blend under the scene's weights mapped by name (the
      // targets it lacks weigh on its neutral), geomorphed when it has a coarser level.
      const std::vector<size_t>& map = scene.GetTargetMap(p);
      std::vector<double> pw(map.size(), 0.0);
      double mapped = 0.0;
      for (size_t k = 1; k < map.size(); ++k)
      {
        pw[k] = d.Weights[map[k]];
        mapped += pw[k];
      }
      double all = 0.0;
      for (size_t k = 1; k < d.Weights.size(); ++k)
      {
        all += d.Weights[k];
      }
      pw[0] = d.Weights[0] + (all - mapped);
      std::vector<float> expected(3 * ladder.Mesh.GetNumberOfPoints(), 0.0f);
      reductiontest::PositionsOf(ladder.Mesh).Blend(pw.data(), pw.size(), expected.data(), 0, n);
      if (d.MorphTowards >= 0 && pl == d.Level &&
        static_cast<size_t>(pl) + 1 < ladder.Levels.size())
      {
        morphnode::GeomorphLadder(ladder, static_cast<size_t>(pl), d.Alpha, expected.data());
      }
      for (size_t i = 0; i < 3 * n; ++i)
      {
        ASSERT_NEAR(scene.GetPositions(p)[i], expected[i], 1e-5f) << "frame " << f << " part " << p;
      }
    }
    EXPECT_EQ(frame.NumberOfPoints, total);
  }
  // The dolly-out walks the whole ladder, with geomorphs.
  EXPECT_EQ(scene.GetController().GetCurrentLevel(), 3);
  EXPECT_GE(switches, 3);
  EXPECT_GE(transitions, 3 * (s.GeomorphFrames - 1));

  // On screen, the LARGEST part error decides: at a distance where A alone could go two
  // levels coarser than B allows, the scene stays where B's error is within the bound.
  ScalableScene still;
  still.SetSettings(s);
  still.SetParts(parts, ScalableScene::Calibrate(parts));
  const double ppu = 0.8 / parts[1]->Levels[1].Error99; // B's level 1 at 0.8 px
  ASSERT_GT(parts[1]->Levels[2].Error99 * ppu, 1.0);
  ASSERT_LT(parts[0]->Levels[3].Error99 * ppu, 0.85) << "A alone would show its coarsest level";
  morphnode::SceneFrame last;
  for (int f = 0; f < 200; ++f)
  {
    last = still.Update(SceneWeights(f), ppu);
  }
  EXPECT_EQ(last.Decision.ScreenLevel, 1);
  EXPECT_EQ(last.Decision.Level, 1);
  EXPECT_EQ(last.PartLevels, (std::vector<int>{ 1, 1, 0 }));
  // A part shown as in the last frame is not blended again; its positions stay the blend.
  // Weights that leave part B's targets at 0 and then move only them: B, then A and C, keep.
  std::vector<double> w(6, 0.0);
  w[0] = 0.7;
  w[1] = 0.3; // target0: A and C only
  still.Update(w, ppu);
  still.Update(w, ppu);
  const std::vector<float> keptB = still.GetPositions(1);
  w[0] = 0.5;
  w[5] = 0.2; // extra: B only
  const morphnode::SceneFrame& moved = still.Update(w, ppu);
  ASSERT_LT(moved.Decision.MorphTowards, 0);
  EXPECT_NE(still.GetPositions(1), keptB) << "B's own target moved it";
  for (size_t p = 0; p < parts.size(); ++p)
  {
    const MorphLadder& ladder = *parts[p];
    const std::vector<double>& pw = still.GetPartWeights(p);
    std::vector<float> expected(3 * ladder.Mesh.GetNumberOfPoints(), 0.0f);
    reductiontest::PositionsOf(ladder.Mesh)
      .Blend(pw.data(), pw.size(), expected.data(), 0, moved.PartPoints[p]);
    for (size_t i = 0; i < 3 * moved.PartPoints[p]; ++i)
    {
      ASSERT_NEAR(still.GetPositions(p)[i], expected[i], 1e-5f) << "part " << p;
    }
  }
}

TEST(ScalableScene, BadPartsAreReported)
{
  const ScalableScene::Ladders& parts = TheScene().Parts;
  ScalableScene scene;
  EXPECT_THROW(scene.SetParts({}, {}), morphnode::InputError);
  EXPECT_THROW(scene.SetParts({ nullptr }, { {} }), morphnode::InputError);
  EXPECT_THROW(scene.SetParts(parts, { {}, {} }), morphnode::InputError);
  EXPECT_THROW(scene.Update(SceneWeights(0), 10.0), morphnode::InputError);
  scene.SetParts(parts, ScalableScene::Calibrate(parts));
  EXPECT_THROW(scene.Update({ 1.0, 0.0 }, 10.0), morphnode::InputError);
  EXPECT_THROW(scene.GetSceneLevel(4, {}), morphnode::InputError);
  // A name twice in one part: the morph node's scene refuses it, so does this one.
  morphnode::LadderSettings one;
  one.TriangleFractions.clear();
  auto twice = std::make_shared<const MorphLadder>(
    morphnode::BuildMorphLadder(Part(5, 1.0f, 0.0f, { 0, 1 }, { "Neutral", "a", "a" }), one));
  EXPECT_THROW(scene.SetParts({ twice }, { {} }), morphnode::InputError);
  EXPECT_EQ(scene.GetNumberOfParts(), 3u) << "a refused set of parts changes nothing";
}

namespace
{
/// Two joints: a "jaw" (joint 1) weighted in smoothly below y = 0.35 .. 0.65 of the face.
morphnode::SkinInfluences JawSkin(const morphnode::MorphMesh& mesh)
{
  const auto& positions = reductiontest::PositionsOf(mesh).GetNeutral();
  const size_t n = mesh.GetNumberOfPoints();
  std::vector<float> joints(4 * n, 0.0f), weights(4 * n, 0.0f);
  for (size_t p = 0; p < n; ++p)
  {
    const double t = std::clamp((0.65 - positions[3 * p + 1]) / 0.3, 0.0, 1.0);
    const double jaw = t * t * (3.0 - 2.0 * t);
    joints[4 * p + 1] = 1.0f;
    weights[4 * p] = static_cast<float>(1.0 - jaw);
    weights[4 * p + 1] = static_cast<float>(jaw);
  }
  morphnode::SkinInfluences skin;
  skin.AddSet(joints, weights, n);
  skin.Normalize(2, "jaw skin");
  return skin;
}

/// The jaw opened by `degrees` about the x axis through (0.5, 0.7, 0).
std::vector<glm::dmat4> JawPose(double degrees)
{
  glm::dmat4 jaw = glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0.7, 0.0));
  jaw = glm::rotate(jaw, glm::radians(degrees), glm::dvec3(1.0, 0.0, 0.0));
  jaw = glm::translate(jaw, glm::dvec3(-0.5, -0.7, 0.0));
  return { glm::dmat4(1.0), jaw };
}

double Distance(const float* a, const float* b)
{
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}
} // namespace

TEST(ScalableScene, SkinnedLevelSkinsLikeFullResolution)
{
  const morphnode::MorphMesh mesh = reductiontest::MakeFace(41);
  const morphnode::SkinInfluences skin = JawSkin(mesh);
  // The level errors cover the jaw at 10 and 25 degrees; it is shown at 20.
  morphnode::LadderSettings settings;
  settings.SkinPoses = { JawPose(10.0), JawPose(25.0) };
  const MorphLadder ladder = morphnode::BuildMorphLadder(mesh, skin, settings);
  const MorphLadder unskinned = morphnode::BuildMorphLadder(mesh, {});
  const size_t np = mesh.GetNumberOfPoints();
  // One set of influences for every level: the input's, in the ladder's numbering.
  ASSERT_EQ(ladder.Influences.GetNumberOfPoints(), np);
  ASSERT_EQ(ladder.Influences.PerPoint, skin.PerPoint);
  for (size_t p = 0; p < np; ++p)
  {
    for (size_t k = 0; k < skin.PerPoint; ++k)
    {
      ASSERT_EQ(
        ladder.Influences.Joints[p * 4 + k], skin.Joints[ladder.OriginalPointIds[p] * 4 + k]);
      ASSERT_EQ(
        ladder.Influences.Weights[p * 4 + k], skin.Weights[ladder.OriginalPointIds[p] * 4 + k]);
    }
  }

  // The full mesh morphed and skinned, and each level's prefix morphed and skinned.
  const std::vector<double> w = { 0.3, 0.5, 0.2, 0.0, 0.0 }; // jaw target and smile
  const std::vector<glm::dmat4> pose = JawPose(20.0);
  std::vector<float> full(3 * np), fullSkinned(3 * np);
  reductiontest::PositionsOf(mesh).Blend(w.data(), w.size(), full.data(), 0, np);
  morphnode::SkinPoints(skin, pose, full.data(), static_cast<const float*>(nullptr),
    fullSkinned.data(), static_cast<float*>(nullptr), 0, np);
  for (size_t l = 1; l < ladder.Levels.size(); ++l)
  {
    const morphnode::LadderLevel& level = ladder.Levels[l];
    const size_t n = level.NumberOfPoints;
    std::vector<float> blended(3 * np, 0.0f), skinned(3 * np, 0.0f), wrong(3 * np, 0.0f);
    reductiontest::PositionsOf(ladder.Mesh).Blend(w.data(), w.size(), blended.data(), 0, n);
    morphnode::SkinPoints(ladder.Influences, pose, blended.data(),
      static_cast<const float*>(nullptr), skinned.data(), static_cast<float*>(nullptr), 0, n);
    // A ladder that kept the input's order of influences skins its points with other
    // points' joints: the fault this test names.
    morphnode::SkinPoints(skin, pose, blended.data(), static_cast<const float*>(nullptr),
      wrong.data(), static_cast<float*>(nullptr), 0, n);
    double keptWorst = 0.0, wrongWorst = 0.0;
    for (size_t p = 0; p < n; ++p)
    {
      const float* expected = &fullSkinned[3 * ladder.OriginalPointIds[p]];
      keptWorst = std::max(keptWorst, Distance(&skinned[3 * p], expected));
      wrongWorst = std::max(wrongWorst, Distance(&wrong[3 * p], expected));
    }
    // The level's own points skin exactly where the full mesh's do.
    EXPECT_LT(keptWorst, 1e-5) << "level " << l;
    EXPECT_GT(wrongWorst, 0.01) << "level " << l;
    // Every full-resolution point, carried on the level's skinned surface, stays within
    // the level's error (the 99th percentile over points, as the level is chosen by; the
    // jaw's rotation is rigid where one joint holds a point, and bends the surface little
    // where two do).
    std::vector<double> errors(np);
    for (size_t p = 0; p < np; ++p)
    {
      float carried[3] = { 0, 0, 0 };
      for (int i = 0; i < 3; ++i)
      {
        const float b = level.Barycentrics[3 * p + i];
        for (int c = 0; c < 3; ++c)
        {
          carried[c] += b * skinned[3 * level.Corners[3 * p + i] + c];
        }
      }
      errors[p] = Distance(carried, &fullSkinned[3 * ladder.OriginalPointIds[p]]);
    }
    std::sort(errors.begin(), errors.end());
    const double p99 = errors[(np * 99) / 100];
    EXPECT_LE(p99, 1.25 * level.Error99)
      << "level " << l << ": skinned p99 " << p99 << ", level error " << level.Error99;
    EXPECT_LE(errors.back(), 1.25 * level.MaxError) << "level " << l;
    // The skin's bend is in the error: above the error of the morph alone.
    EXPECT_GT(level.Error99, unskinned.Levels[l].Error99) << "level " << l;
  }
  morphnode::LadderSettings onePose;
  onePose.SkinPoses = { { glm::dmat4(1.0) } };
  EXPECT_THROW(morphnode::BuildMorphLadder(mesh, skin, onePose), morphnode::InputError);
  EXPECT_THROW(
    morphnode::BuildMorphLadder(reductiontest::MakeFace(21), skin, {}), morphnode::InputError);
  EXPECT_THROW(skin.Gather({ static_cast<uint32_t>(np) }), morphnode::InputError);
}

TEST(ScalableScene, OtherAttributesFollowTheShownLevel)
{
  // A second attribute, the positions' x and y (with the targets' x and y deltas): shown at
  // every frame's level and geomorph, it must be the shown positions' x and y.
  reductiontest::FlatFace f = reductiontest::MakeFlatFace(41);
  morphnode::MorphMesh mesh = f.ToMesh();
  const size_t np = mesh.GetNumberOfPoints();
  auto xy = [&](const std::vector<float>& v)
  {
    std::vector<float> out(2 * np);
    for (size_t p = 0; p < np; ++p)
    {
      out[2 * p] = v[3 * p];
      out[2 * p + 1] = v[3 * p + 1];
    }
    return out;
  };
  auto& extra = mesh.AddAttribute<float>("XY", morphnode::AttributeRole::Generic, 2);
  extra.SetNeutral(xy(f.Positions).data());
  for (const auto& d : f.PositionDeltas)
  {
    extra.AddRelativeTarget(xy(d).data(), morphnode::MorphMesh::DefaultSparseCoverage);
  }
  auto ladder = std::make_shared<const MorphLadder>(morphnode::BuildMorphLadder(mesh, {}));
  ScalableScene scene;
  morphnode::ControllerSettings s;
  s.FrameBudget = 1.0;
  s.Thresholds = { 0.0 };
  s.PixelBound = 1.0;
  s.MinFramesPerLevel = 1;
  scene.SetSettings(s);
  std::vector<float> out(2 * np);
  EXPECT_THROW(scene.BlendAttribute(0, 1, out.data()), morphnode::InputError);
  scene.SetParts({ ladder }, ScalableScene::Calibrate({ ladder }));
  EXPECT_THROW(scene.BlendAttribute(0, 1, out.data()), morphnode::InputError) << "no frame yet";
  int morphing = 0;
  for (int f2 = 0; f2 < 300; ++f2)
  {
    std::vector<double> w = SceneWeights(f2);
    w.resize(5);
    w[0] = 1.0 - (w[1] + w[2] + w[3] + w[4]);
    const morphnode::SceneFrame& frame = scene.Update(w, 20000.0 * std::pow(1e-3, f2 / 299.0));
    morphing += frame.Decision.MorphTowards >= 0;
    scene.BlendAttribute(0, 1, out.data());
    const std::vector<float>& positions = scene.GetPositions(0);
    for (size_t p = 0; p < frame.PartPoints[0]; ++p)
    {
      ASSERT_NEAR(out[2 * p], positions[3 * p], 1e-5f) << "frame " << f2 << " point " << p;
      ASSERT_NEAR(out[2 * p + 1], positions[3 * p + 1], 1e-5f) << "frame " << f2 << " point " << p;
    }
  }
  EXPECT_GT(morphing, 0);
  std::vector<double> wrongType(2 * np);
  EXPECT_THROW(scene.BlendAttribute(0, 1, wrongType.data()), morphnode::InputError);
  EXPECT_THROW(scene.BlendAttribute(0, 2, out.data()), morphnode::InputError);
}
