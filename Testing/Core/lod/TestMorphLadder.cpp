// SPDX-License-Identifier: BSD-3-Clause
// The ladder: levels of the animation-aware reduction over one vertex buffer and one set of
// targets; their geomorphs; the target level of detail and the level chosen on screen
// (FrameBudgetController over the ladder's levels).
#include "Core/reduction/ReductionTestMesh.h"
#include "base/Error.h"
#include "budget/DeviceProfile.h"
#include "budget/FrameBudgetController.h"
#include "lod/MorphLadder.h"
#include "lod/ScalableMorph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>

using morphnode::MorphLadder;

namespace
{
const MorphLadder& Ladder()
{
  static const MorphLadder ladder =
    morphnode::BuildMorphLadder(reductiontest::MakeFace(), morphnode::LadderSettings());
  return ladder;
}

/// Triangles as sorted triples (orientation kept by rotation to the smallest id first).
std::multiset<std::array<uint32_t, 3>> TriangleSet(const std::vector<uint32_t>& t)
{
  std::multiset<std::array<uint32_t, 3>> set;
  for (size_t i = 0; i + 2 < t.size(); i += 3)
  {
    std::array<uint32_t, 3> tri = { t[i], t[i + 1], t[i + 2] };
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    set.insert(tri);
  }
  return set;
}

/// Blend of the shared buffer's prefix [0, n) with absolute weights.
std::vector<float> Blend(const MorphLadder& ladder, const std::vector<double>& w, size_t n)
{
  const auto& positions = reductiontest::PositionsOf(ladder.Mesh);
  std::vector<float> out(3 * ladder.Mesh.GetNumberOfPoints(), 0.0f);
  positions.Blend(w.data(), w.size(), out.data(), 0, n);
  return out;
}
} // namespace

TEST(MorphLadder, OneVertexBufferAndOneSetOfTargets)
{
  const morphnode::MorphMesh input = reductiontest::MakeFace();
  const MorphLadder& ladder = Ladder();
  ASSERT_EQ(ladder.Levels.size(), 4u);
  // One buffer: as many points and targets as the input, the same memory (no level copies).
  EXPECT_EQ(ladder.Mesh.GetNumberOfPoints(), input.GetNumberOfPoints());
  EXPECT_EQ(ladder.Mesh.GetNumberOfTargets(), input.GetNumberOfTargets());
  EXPECT_EQ(ladder.Mesh.GetNumberOfAttributes(), input.GetNumberOfAttributes());
  EXPECT_LE(ladder.Mesh.GetMemorySize(), input.GetMemorySize() * 11 / 10);
  // A permutation of the input's points, each with its own position and deltas, exactly.
  std::vector<uint32_t> sorted = ladder.OriginalPointIds;
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 0; i < sorted.size(); ++i)
  {
    ASSERT_EQ(sorted[i], i);
  }
  const auto& in = reductiontest::PositionsOf(input);
  const auto& out = reductiontest::PositionsOf(ladder.Mesh);
  for (size_t k = 1; k < input.GetNumberOfTargets(); ++k)
  {
    const std::vector<float> a = reductiontest::DeltasOf(input, k);
    const std::vector<float> b = reductiontest::DeltasOf(ladder.Mesh, k);
    for (size_t p = 0; p < ladder.OriginalPointIds.size(); ++p)
    {
      for (int c = 0; c < 3; ++c)
      {
        ASSERT_EQ(b[3 * p + c], a[3 * ladder.OriginalPointIds[p] + c]);
        ASSERT_EQ(out.GetNeutral()[3 * p + c], in.GetNeutral()[3 * ladder.OriginalPointIds[p] + c]);
      }
    }
  }
  // Every level is a prefix of the buffer; its index buffer stays in it; levels shrink.
  for (size_t l = 0; l < ladder.Levels.size(); ++l)
  {
    const auto& level = ladder.Levels[l];
    ASSERT_FALSE(level.Triangles.empty());
    EXPECT_LT(
      *std::max_element(level.Triangles.begin(), level.Triangles.end()), level.NumberOfPoints);
    if (l > 0)
    {
      EXPECT_LT(level.NumberOfPoints, ladder.Levels[l - 1].NumberOfPoints);
      EXPECT_LT(level.Triangles.size(), ladder.Levels[l - 1].Triangles.size());
      EXPECT_GT(level.MaxError, 0.0);
      EXPECT_GE(level.MaxError, ladder.Levels[l - 1].MaxError);
    }
  }
  EXPECT_EQ(ladder.Levels[0].NumberOfPoints, input.GetNumberOfPoints());
  EXPECT_EQ(ladder.Levels[0].MaxError, 0.0);
  // Parents lie in the coarser prefix, below their children.
  for (size_t p = ladder.Levels.back().NumberOfPoints; p < ladder.Parent.size(); ++p)
  {
    ASSERT_LT(ladder.Parent[p], p);
  }
}

TEST(MorphLadder, LevelsAreTheAnimationAwareReduction)
{
  // Level 1 is the reduction of the input to half its triangles, renumbered.
  const morphnode::MorphMesh input = reductiontest::MakeFace();
  morphnode::ReductionSettings rs;
  rs.TargetTriangles = static_cast<size_t>(std::llround(0.5 * input.GetNumberOfTriangles()));
  const morphnode::ReductionResult direct = morphnode::ReduceAnimationAware(input, rs);
  const MorphLadder& ladder = Ladder();
  std::vector<uint32_t> mapped;
  for (uint32_t id : ladder.Levels[1].Triangles)
  {
    mapped.push_back(ladder.OriginalPointIds[id]);
  }
  std::vector<uint32_t> expected;
  for (uint32_t id : direct.Mesh.GetTriangles())
  {
    expected.push_back(direct.OriginalPointIds[id]);
  }
  EXPECT_EQ(TriangleSet(mapped), TriangleSet(expected));
  // The animation-aware levels keep more of the moving points than a plain ladder does.
  morphnode::LadderSettings plain;
  plain.Reduction.AnimationWeight = 0.0;
  const MorphLadder quadric = morphnode::BuildMorphLadder(input, plain);
  const std::vector<double> region = input.ComputeAnimatedRegion();
  auto animatedKept = [&](const MorphLadder& l, size_t level)
  {
    size_t n = 0;
    for (size_t p = 0; p < l.Levels[level].NumberOfPoints; ++p)
    {
      n += region[l.OriginalPointIds[p]] > 0.005 ? 1 : 0;
    }
    return n;
  };
  for (size_t level = 1; level < 4; ++level)
  {
    EXPECT_GT(animatedKept(ladder, level), animatedKept(quadric, level)) << "level " << level;
  }
}

TEST(MorphLadder, EveryLevelTriangleIsAnInputTriangle)
{
  // Per level, each triangle's OriginalTriangleIds entry names the input triangle it is: its
  // corners are that triangle's corners' representatives on the level (a collapse moves a
  // corner onto its representative), so cell data carries over by these ids.
  const morphnode::MorphMesh input = reductiontest::MakeFace();
  const MorphLadder& ladder = Ladder();
  const std::vector<uint32_t>& in = input.GetTriangles();
  std::vector<uint32_t> shared(ladder.OriginalPointIds.size()); // input id -> shared id
  for (size_t i = 0; i < shared.size(); ++i)
  {
    shared[ladder.OriginalPointIds[i]] = static_cast<uint32_t>(i);
  }
  for (size_t l = 0; l < ladder.Levels.size(); ++l)
  {
    const auto& level = ladder.Levels[l];
    ASSERT_EQ(level.OriginalTriangleIds.size(), level.Triangles.size() / 3) << "level " << l;
    std::set<uint32_t> distinct(level.OriginalTriangleIds.begin(), level.OriginalTriangleIds.end());
    EXPECT_EQ(distinct.size(), level.OriginalTriangleIds.size()) << "level " << l;
    size_t moved = 0;
    for (size_t t = 0; t < level.OriginalTriangleIds.size(); ++t)
    {
      const uint32_t o = level.OriginalTriangleIds[t];
      ASSERT_LT(o, in.size() / 3);
      std::multiset<uint32_t> expected, got;
      for (int c = 0; c < 3; ++c)
      {
        expected.insert(ladder.Representative(l, shared[in[3 * o + c]]));
        got.insert(level.Triangles[3 * t + c]);
        moved += shared[in[3 * o + c]] != ladder.Representative(l, shared[in[3 * o + c]]);
      }
      ASSERT_EQ(got, expected) << "level " << l << " triangle " << t;
    }
    EXPECT_EQ(moved > 0, l > 0) << "level " << l; // reduced levels move corners
  }
}

TEST(MorphLadder, GeomorphEndpointsAreTheLevels)
{
  const MorphLadder& ladder = Ladder();
  const std::vector<double> w = { 0.1, 0.6, 0.3, 0.5, -0.5 }; // sums to 1
  for (size_t l = 0; l + 1 < ladder.Levels.size(); ++l)
  {
    const size_t n = ladder.Levels[l].NumberOfPoints;
    const size_t nc = ladder.Levels[l + 1].NumberOfPoints;
    const std::vector<float> blended = Blend(ladder, w, n);
    // alpha = 0: the fine level itself.
    std::vector<float> start = blended;
    morphnode::GeomorphLadder(ladder, l, 0.0, start.data());
    EXPECT_EQ(start, blended);
    // alpha = 1: every point on its representative in the coarse level, and the fine index
    // buffer shows exactly the coarse triangles (the others degenerate).
    std::vector<float> end = blended;
    morphnode::GeomorphLadder(ladder, l, 1.0, end.data());
    std::vector<uint32_t> collapsed;
    for (uint32_t id : ladder.Levels[l].Triangles)
    {
      collapsed.push_back(ladder.Representative(l + 1, id));
    }
    for (size_t p = 0; p < n; ++p)
    {
      const uint32_t r = ladder.Representative(l + 1, static_cast<uint32_t>(p));
      ASSERT_LT(r, nc);
      for (int c = 0; c < 3; ++c)
      {
        ASSERT_EQ(end[3 * p + c], blended[3 * r + c]) << "level " << l << " point " << p;
      }
    }
    std::vector<uint32_t> kept;
    for (size_t i = 0; i < collapsed.size(); i += 3)
    {
      if (collapsed[i] != collapsed[i + 1] && collapsed[i + 1] != collapsed[i + 2] &&
        collapsed[i] != collapsed[i + 2])
      {
        kept.insert(kept.end(), collapsed.begin() + i, collapsed.begin() + i + 3);
      }
    }
    EXPECT_EQ(TriangleSet(kept), TriangleSet(ladder.Levels[l + 1].Triangles)) << "level " << l;
    // Half way: the points the coarse level keeps have not moved.
    std::vector<float> half = blended;
    morphnode::GeomorphLadder(ladder, l, 0.5, half.data());
    EXPECT_TRUE(std::equal(half.begin(), half.begin() + 3 * nc, blended.begin()));
  }
  EXPECT_THROW(morphnode::GeomorphLadder(ladder, ladder.Levels.size() - 1, 0.5,
                 std::vector<float>(3 * ladder.Mesh.GetNumberOfPoints()).data()),
    morphnode::InputError);
}

TEST(MorphLadder, BadSettingsAreReported)
{
  const morphnode::MorphMesh input = reductiontest::MakeFace(11);
  morphnode::LadderSettings s;
  s.TriangleFractions = { 0.5, 0.6 };
  EXPECT_THROW(morphnode::BuildMorphLadder(input, s), morphnode::InputError);
  s.TriangleFractions = { 1.0 };
  EXPECT_THROW(morphnode::BuildMorphLadder(input, s), morphnode::InputError);
  s.TriangleFractions = { 0.0 };
  EXPECT_THROW(morphnode::BuildMorphLadder(input, s), morphnode::InputError);
  EXPECT_THROW(morphnode::BuildMorphLadder(morphnode::MorphMesh(), morphnode::LadderSettings()),
    morphnode::InputError);
}

namespace
{
/// A controller over the ladder's levels (cost ~ points moved, given, never timed).
morphnode::FrameBudgetController Controller(const morphnode::ControllerSettings& s)
{
  morphnode::FrameBudgetController c;
  c.SetSettings(s);
  for (size_t l = 0; l < Ladder().Levels.size(); ++l)
  {
    c.AddLevel(morphnode::ToLevelOfDetail(Ladder(), l, { 1e-6, 1e-9 }));
  }
  return c;
}

/// Speech-like weights of the four targets, absolute (neutral first).
std::vector<double> Weights(int frame)
{
  std::vector<double> w(5, 0.0);
  for (int k = 1; k < 5; ++k)
  {
    const double s = std::sin(0.05 * frame * (1.0 + 0.37 * k) + k);
    w[k] = std::max(0.0, s) * (k == 2 ? 0.15 : 0.6);
  }
  w[0] = 1.0 - (w[1] + w[2] + w[3] + w[4]);
  return w;
}

double MaxDeviation(const std::vector<float>& a, const std::vector<float>& b, size_t n)
{
  double worst = 0.0;
  for (size_t p = 0; p < n; ++p)
  {
    const double dx = a[3 * p] - b[3 * p], dy = a[3 * p + 1] - b[3 * p + 1],
                 dz = a[3 * p + 2] - b[3 * p + 2];
    worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return worst;
}
} // namespace

TEST(MorphLadder, TargetLevelOfDetailKeepsTheErrorBound)
{
  // At every distance, the targets the screen cannot see are left out, and no vertex of the
  // shown level moves farther than TargetPixelBound pixels from the unoptimized blend.
  morphnode::ControllerSettings s;
  s.FrameBudget = 1.0; // never the reason
  s.Thresholds = { 0.0 };
  s.Strategy = morphnode::Redistribution::Neutral;
  s.TargetPixelBound = 1.0;
  s.OptimizerHysteresis = 0.2;
  std::map<int, double> activeAtDistance;
  for (double ppu : { 4000.0, 400.0, 100.0, 40.0 })
  {
    morphnode::FrameBudgetController c = Controller(s);
    double active = 0.0;
    for (int f = 0; f < 300; ++f)
    {
      const std::vector<double> w = Weights(f);
      const morphnode::ControllerDecision d = c.Update(w, ppu);
      EXPECT_NEAR(d.TargetErrorBound, 1.0 / ppu, 1e-12);
      const size_t n = Ladder().Levels[d.Level].NumberOfPoints;
      const double err = MaxDeviation(Blend(Ladder(), d.Weights, n), Blend(Ladder(), w, n), n);
      ASSERT_LE(err * ppu, 1.0 + 1e-4) << "ppu " << ppu << " frame " << f;
      active += d.ActiveTargets;
    }
    activeAtDistance[static_cast<int>(ppu)] = active / 300.0;
  }
  // Farther (fewer pixels per unit): fewer targets blended; near: all of them.
  EXPECT_GT(activeAtDistance[4000], activeAtDistance[100]);
  EXPECT_GT(activeAtDistance[100], activeAtDistance[40]);
  EXPECT_LT(activeAtDistance[40], 1.0);
}

TEST(MorphLadder, TargetLevelOfDetailDoesNotPop)
{
  // A weight hovering at the edge of what the screen sees: the optimizer's hysteresis
  // keeps the set of blended targets from flickering.
  auto changes = [](double hysteresis)
  {
    morphnode::ControllerSettings s;
    s.FrameBudget = 1.0;
    s.Thresholds = { 0.0 };
    s.Strategy = morphnode::Redistribution::Neutral;
    s.TargetPixelBound = 1.0;
    s.OptimizerHysteresis = hysteresis;
    morphnode::FrameBudgetController c = Controller(s);
    const double m3 = Ladder().Levels[0].Distances.MaxDisplacement[3];
    const double ppu = 100.0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.04, 0.04);
    int count = 0, last = -1;
    for (int f = 0; f < 200; ++f)
    {
      std::vector<double> w(5, 0.0);
      w[3] = (1.0 + jitter(rng)) / (ppu * m3); // its reach: one pixel +-4 %
      w[0] = 1.0 - w[3];
      const int active = c.Update(w, ppu).ActiveTargets;
      count += (last >= 0 && active != last) ? 1 : 0;
      last = active;
    }
    return count;
  };
  EXPECT_GE(changes(0.0), 20);
  EXPECT_LE(changes(0.2), 1);
}

TEST(MorphLadder, LevelChosenOnScreenWithHysteresis)
{
  morphnode::ControllerSettings s;
  s.FrameBudget = 1.0;
  s.Thresholds = { 0.0 };
  s.PixelBound = 1.0;
  s.MinFramesPerLevel = 2;
  s.GeomorphFrames = 8;
  morphnode::FrameBudgetController c = Controller(s);
  const auto& levels = Ladder().Levels;
  // Dolly out: pixels per unit fall from 20000 to 20 over 1200 frames, with a jittery hand.
  constexpr int frames = 1200;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  int previous = 0, backwards = 0;
  for (int f = 0; f < frames; ++f)
  {
    const double ppu = 20000.0 * std::pow(1e-3, f / (frames - 1.0)) * (1.0 + jitter(rng));
    const morphnode::ControllerDecision d = c.Update(Weights(f), ppu);
    backwards += d.Level < previous ? 1 : 0;
    previous = d.Level;
    // Shown at most one level coarser than the screen allows (the one being left), never
    // finer than it needs beyond a geomorph's frames; in view the error stays in bound
    // whenever the screen's level has been reached.
    if (d.MorphTowards < 0 && d.Level == d.ScreenLevel)
    {
      EXPECT_LE(d.LevelPixelError, s.PixelBound + 1e-9) << "frame " << f;
    }
  }
  EXPECT_EQ(c.GetNumberOfSwitches(), levels.size() - 1) << "each level once on the way out";
  EXPECT_EQ(backwards, 0);
  EXPECT_EQ(c.GetCurrentLevel(), static_cast<int>(levels.size()) - 1);
  // Without hysteresis the same jitter flickers at the edges.
  s.LevelHysteresis = 0.0;
  s.MinFramesPerLevel = 0;
  s.GeomorphFrames = 0;
  morphnode::FrameBudgetController flicker = Controller(s);
  rng.seed(5);
  for (int f = 0; f < frames; ++f)
  {
    const double ppu = 20000.0 * std::pow(1e-3, f / (frames - 1.0)) * (1.0 + jitter(rng));
    flicker.Update(Weights(f), ppu);
  }
  EXPECT_GT(flicker.GetNumberOfSwitches(), levels.size() - 1);
}

TEST(MorphLadder, ProfilesFixBudgetFinestLevelAndPixelBounds)
{
  // The phone never shows the full mesh, even up close with time to spare.
  morphnode::ControllerSettings s;
  s.Thresholds = { 0.0 };
  morphnode::ApplyDeviceProfile(morphnode::FindDeviceProfile("phone"), s);
  s.FrameBudget = 1.0;
  morphnode::FrameBudgetController c = Controller(s);
  for (int f = 0; f < 50; ++f)
  {
    EXPECT_GE(c.Update(Weights(f), 1e6).Level, 1);
  }
  // A tight budget coarsens past what the screen asks for (the budget breaks the tie).
  morphnode::ApplyDeviceProfile(morphnode::FindDeviceProfile("desktop"), s);
  s.FrameBudget = 1.25e-6; // the full mesh never fits; only the coarse levels do
  morphnode::FrameBudgetController tight = Controller(s);
  int over = 0;
  for (int f = 0; f < 200; ++f)
  {
    const morphnode::ControllerDecision d = tight.Update(Weights(f), 1e6);
    EXPECT_EQ(d.ScreenLevel, 0);
    if (f >= 40)
    {
      EXPECT_GE(d.Level, 2) << "frame " << f;
      over += d.WithinBudget ? 0 : 1;
    }
  }
  EXPECT_LE(over, 16);
}

TEST(ScalableMorph, BlendsTheShownLevelAndItsGeomorph)
{
  auto ladder = std::make_shared<const MorphLadder>(Ladder());
  morphnode::ScalableMorph morph;
  morphnode::ControllerSettings s;
  s.Thresholds = { 0.0 };
  s.PixelBound = 1.0;
  s.MinFramesPerLevel = 1;
  morph.SetSettings(s);
  morph.SetLadder(ladder, morphnode::ScalableMorph::Calibrate(*ladder));
  int transitions = 0;
  for (int f = 0; f < 400; ++f)
  {
    const std::vector<double> w = Weights(f);
    const double ppu = 20000.0 * std::pow(1e-3, f / 399.0);
    const morphnode::ScalableFrame& frame = morph.Update(w, ppu);
    const auto& d = frame.Decision;
    ASSERT_EQ(frame.NumberOfPoints, ladder->Levels[d.Level].NumberOfPoints);
    EXPECT_EQ(&morph.GetTriangles(), &ladder->Levels[d.Level].Triangles);
    std::vector<float> expected = Blend(*ladder, d.Weights, frame.NumberOfPoints);
    if (d.MorphTowards >= 0)
    {
      morphnode::GeomorphLadder(*ladder, d.Level, d.Alpha, expected.data());
      ++transitions;
    }
    ASSERT_TRUE(std::equal(
      expected.begin(), expected.begin() + 3 * frame.NumberOfPoints, morph.GetPositions().begin()))
      << "frame " << f;
    EXPECT_GE(frame.BlendSeconds, 0.0);
  }
  EXPECT_EQ(morph.GetController().GetCurrentLevel(), 3);
  EXPECT_GE(transitions, 3 * (s.GeomorphFrames - 1));
  // A phone's profile never shows the full mesh.
  morph.SetProfile(morphnode::FindDeviceProfile("phone"));
  for (int f = 0; f < 20; ++f)
  {
    EXPECT_GE(morph.Update(Weights(f), 1e6).Decision.Level, 1);
  }
  EXPECT_THROW(morph.Update({ 1.0 }, 100.0), morphnode::InputError);
  EXPECT_THROW(morph.SetLadder(ladder, {}), morphnode::InputError);
}

namespace
{
/// Every shared point as a level shows it (a point the level lacks sits on its
/// representative), blended with `w` and geomorphed by (towards, alpha).
std::vector<float> VertexView(const std::vector<double>& w, int level, int towards, double alpha)
{
  const MorphLadder& ladder = Ladder();
  const size_t n = ladder.Levels[level].NumberOfPoints;
  std::vector<float> shown = Blend(ladder, w, n);
  if (towards >= 0)
  {
    morphnode::GeomorphLadder(ladder, level, alpha, shown.data());
  }
  std::vector<float> out(shown.size());
  for (size_t p = 0; p < ladder.Mesh.GetNumberOfPoints(); ++p)
  {
    const size_t r = ladder.Representative(level, static_cast<uint32_t>(p));
    std::copy_n(&shown[3 * r], 3, &out[3 * p]);
  }
  return out;
}

/// The largest screen-space jump of a vertex over a dolly-out (and back in), caused by level
/// changes and geomorph steps alone (both states under the same frame's weights).
double LargestJump(double maxGeomorphPixels, int geomorphFrames)
{
  morphnode::ControllerSettings s;
  s.FrameBudget = 1.0;
  s.Thresholds = { 0.0 };
  s.PixelBound = 1.0;
  s.MinFramesPerLevel = 1;
  s.GeomorphFrames = geomorphFrames;
  s.MaxGeomorphPixels = maxGeomorphPixels;
  s.MaxGeomorphFrames = 4000; // never the limit here (it would be: the camera comes in fast)
  morphnode::FrameBudgetController c = Controller(s);
  int level = 0, towards = -1;
  double alpha = 0.0, largest = 0.0;
  for (int f = 0; f < 800; ++f)
  {
    const double t = f < 400 ? f / 399.0 : (799 - f) / 399.0; // out, then in again
    const double ppu = 20000.0 * std::pow(1e-3, t);
    const morphnode::ControllerDecision d = c.Update(Weights(f), ppu);
    if (d.Level != level || d.MorphTowards != towards || d.Alpha != alpha)
    {
      const std::vector<float> now = VertexView(d.Weights, d.Level, d.MorphTowards, d.Alpha);
      const std::vector<float> before = VertexView(d.Weights, level, towards, alpha);
      const double j = MaxDeviation(now, before, now.size() / 3) * ppu;
      largest = std::max(largest, j);
    }
    level = d.Level;
    towards = d.MorphTowards;
    alpha = d.Alpha;
  }
  EXPECT_EQ(c.GetNumberOfSwitches(), 6u);
  return largest;
}
} // namespace

TEST(MorphLadder, GeomorphKeepsEveryVertexJumpWithinAPixel)
{
  // Without geomorphs a switch jumps by many pixels; with eight fixed frames still by more
  // than one near the camera; sliding by the pixel bound never by more than one pixel.
  const double none = LargestJump(0.0, 0);
  const double fixed = LargestJump(0.0, 8);
  const double bounded = LargestJump(1.0, 8);
  EXPECT_GT(none, 8.0);
  EXPECT_GT(fixed, 1.0);
  EXPECT_LE(bounded, 1.0 + 1e-3); // float positions
  EXPECT_NEAR(fixed, none / 8.0, 0.05 * none);
}
