// SPDX-License-Identifier: BSD-3-Clause
#include "ReductionTestMesh.h"

#include "base/Error.h"
#include "reduction/AnimationAwareReduction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>

using morphnode::InputError;
using morphnode::ReductionMesh;
using morphnode::ReduceAnimationAware;
using morphnode::ReductionResult;
using morphnode::ReductionSettings;

namespace
{
ReductionSettings Budget(size_t triangles, double weight)
{
  ReductionSettings s;
  s.TargetTriangles = triangles;
  s.AnimationWeight = weight;
  return s;
}

/// Largest motion of each point over all targets (morphnode::ComputeAnimatedRegion).
std::vector<double> Region(const ReductionMesh& mesh)
{
  std::vector<double> region(mesh.GetNumberOfPoints(), 0.0);
  for (const auto& d : mesh.PositionDeltas)
  {
    for (size_t p = 0; p < region.size(); ++p)
    {
      region[p] = std::max(region[p],
        std::sqrt(double(d[3 * p]) * d[3 * p] + double(d[3 * p + 1]) * d[3 * p + 1] +
          double(d[3 * p + 2]) * d[3 * p + 2]));
    }
  }
  return region;
}

size_t KeptAnimated(const ReductionResult& r, const std::vector<double>& region, double above)
{
  size_t count = 0;
  for (uint32_t id : r.OriginalPointIds)
  {
    count += region[id] > above ? 1 : 0;
  }
  return count;
}
} // namespace

TEST(AnimationAwareReduction, TargetsAreCarriedExactly)
{
  const ReductionMesh mesh = reductiontest::MakeFace();
  for (double weight : { 0.0, 1.0 })
  {
    const size_t budget = mesh.GetNumberOfTriangles() / 4;
    const ReductionResult r = ReduceAnimationAware(mesh, Budget(budget, weight));
    const size_t np = r.Mesh.GetNumberOfPoints();
    ASSERT_EQ(r.OriginalPointIds.size(), np);
    EXPECT_LE(r.Mesh.GetNumberOfTriangles(), budget);
    EXPECT_GT(r.Mesh.GetNumberOfTriangles(), budget - 4);
    ASSERT_EQ(r.Mesh.GetNumberOfTargets(), mesh.GetNumberOfTargets());
    EXPECT_TRUE(std::is_sorted(r.OriginalPointIds.begin(), r.OriginalPointIds.end()));
    for (size_t k = 0; k < np; ++k)
    {
      const uint32_t o = r.OriginalPointIds[k];
      for (int c = 0; c < 3; ++c)
      {
        ASSERT_EQ(r.Mesh.Positions[3 * k + c], mesh.Positions[3 * o + c]);
        for (size_t t = 0; t < mesh.GetNumberOfTargets(); ++t)
        {
          ASSERT_EQ(r.Mesh.PositionDeltas[t][3 * k + c], mesh.PositionDeltas[t][3 * o + c])
            << "target " << t << " reduced point " << k;
        }
      }
      // a kept point represents itself
      ASSERT_EQ(r.Representatives[o], k);
    }
    ASSERT_EQ(r.Representatives.size(), mesh.GetNumberOfPoints());
    for (uint32_t rep : r.Representatives)
    {
      ASSERT_LT(rep, np);
    }
    std::set<uint32_t> used(r.Mesh.Triangles.begin(), r.Mesh.Triangles.end());
    ASSERT_LT(*used.rbegin(), np);
    EXPECT_EQ(used.size(), np); // a grid has no isolated points, nor does its reduction
  }
}

TEST(AnimationAwareReduction, GatherCarriesAnyAttribute)
{
  const ReductionMesh mesh = reductiontest::MakeFace(11);
  const ReductionResult r =
    ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 2, 1.0));
  std::vector<double> uv(2 * mesh.GetNumberOfPoints());
  for (size_t p = 0; p < mesh.GetNumberOfPoints(); ++p)
  {
    uv[2 * p] = double(p);
    uv[2 * p + 1] = -double(p);
  }
  const auto reduced = morphnode::GatherPoints(uv, 2, mesh.GetNumberOfPoints(), r.OriginalPointIds);
  for (size_t k = 0; k < r.OriginalPointIds.size(); ++k)
  {
    EXPECT_EQ(reduced[2 * k], double(r.OriginalPointIds[k]));
    EXPECT_EQ(reduced[2 * k + 1], -double(r.OriginalPointIds[k]));
  }
  EXPECT_THROW(morphnode::GatherPoints(uv, 3, mesh.GetNumberOfPoints(), r.OriginalPointIds),
    InputError);
}

TEST(AnimationAwareReduction, KeepsMoreOfTheAnimatedRegions)
{
  const ReductionMesh mesh = reductiontest::MakeFace();
  const auto region = Region(mesh);
  const double animated = 0.2 * *std::max_element(region.begin(), region.end());
  size_t animatedPoints = 0;
  for (double r : region)
  {
    animatedPoints += r > animated ? 1 : 0;
  }
  ASSERT_GT(animatedPoints, 100u);
  for (size_t divisor : { 2, 4, 10 })
  {
    const size_t budget = mesh.GetNumberOfTriangles() / divisor;
    const auto plain = ReduceAnimationAware(mesh, Budget(budget, 0.0));
    const auto ours = ReduceAnimationAware(mesh, Budget(budget, ReductionSettings().AnimationWeight));
    const size_t keptPlain = KeptAnimated(plain, region, animated);
    const size_t keptOurs = KeptAnimated(ours, region, animated);
    EXPECT_GT(keptOurs, keptPlain + keptPlain / 5)
      << "budget 1/" << divisor << ": animated points kept, ours " << keptOurs << ", plain "
      << keptPlain;
    // the same budget, spent elsewhere
    EXPECT_NEAR(double(ours.Mesh.GetNumberOfTriangles()), double(plain.Mesh.GetNumberOfTriangles()), 2.0);
  }
}

TEST(AnimationAwareReduction, WeightZeroIsPlainQuadricDecimation)
{
  // The module with weight 0 would compute ModQuadricT's cost; weight 0 uses ModQuadricT
  // itself. Without targets the animation terms vanish, so both must agree.
  ReductionMesh mesh = reductiontest::MakeFace(21);
  mesh.PositionDeltas.clear();
  const auto a = ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 3, 0.0));
  const auto b = ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 3, 1.0));
  EXPECT_EQ(a.OriginalPointIds, b.OriginalPointIds);
}

TEST(AnimationAwareReduction, GeomorphEndsOnTheReducedShape)
{
  const ReductionMesh mesh = reductiontest::MakeFace(21);
  const auto r = ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 3, 1.0));
  const size_t np = mesh.GetNumberOfPoints();
  std::vector<uint32_t> rep(np);
  for (size_t v = 0; v < np; ++v)
  {
    rep[v] = r.OriginalPointIds[r.Representatives[v]];
  }
  std::vector<float> out(3 * np);
  morphnode::Geomorph(mesh.Positions.data(), np, rep, 1.0, out.data());
  for (size_t v = 0; v < np; ++v)
  {
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_FLOAT_EQ(out[3 * v + c], mesh.Positions[3 * rep[v] + c]);
    }
  }
  morphnode::Geomorph(mesh.Positions.data(), np, rep, 0.0, out.data());
  EXPECT_EQ(out, mesh.Positions);
  // Every triangle of the fine mesh at alpha 1 is degenerate or a triangle of the reduced
  // mesh: the shapes are identical.
  std::set<std::array<uint32_t, 3>> reduced;
  for (size_t t = 0; t < r.Mesh.GetNumberOfTriangles(); ++t)
  {
    std::array<uint32_t, 3> tri;
    for (int c = 0; c < 3; ++c)
    {
      tri[c] = r.OriginalPointIds[r.Mesh.Triangles[3 * t + c]];
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    reduced.insert(tri);
  }
  for (size_t t = 0; t < mesh.GetNumberOfTriangles(); ++t)
  {
    std::array<uint32_t, 3> tri;
    for (int c = 0; c < 3; ++c)
    {
      tri[c] = rep[mesh.Triangles[3 * t + c]];
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
    {
      continue;
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    EXPECT_EQ(reduced.count(tri), 1u) << "fine triangle " << t;
  }
}

TEST(AnimationAwareReduction, BadInputIsReported)
{
  const ReductionMesh good = reductiontest::MakeFace(11);
  const size_t half = good.GetNumberOfTriangles() / 2;
  auto message = [](const ReductionMesh& m, const ReductionSettings& s) {
    try
    {
      ReduceAnimationAware(m, s);
    }
    catch (const InputError& e)
    {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ReductionMesh noTriangles = good;
  noTriangles.Triangles.clear();
  EXPECT_NE(message(noTriangles, Budget(10, 1.0)).find("no triangles"), std::string::npos);

  ReductionMesh noPoints;
  EXPECT_NE(message(noPoints, Budget(10, 1.0)).find("no points"), std::string::npos);

  EXPECT_NE(message(good, Budget(good.GetNumberOfTriangles(), 1.0)).find("budget"), std::string::npos);
  EXPECT_NE(message(good, Budget(good.GetNumberOfTriangles() + 100, 1.0)).find("must be below"),
    std::string::npos);
  ReductionSettings pointBudget;
  pointBudget.TargetPoints = good.GetNumberOfPoints();
  EXPECT_NE(message(good, pointBudget).find("point budget"), std::string::npos);
  EXPECT_NE(message(good, ReductionSettings()).find("no budget"), std::string::npos);

  ReductionMesh mismatched = good;
  mismatched.PositionDeltas[2].pop_back();
  EXPECT_NE(message(mismatched, Budget(half, 1.0)).find("target 2 has"), std::string::npos);

  ReductionMesh outOfRange = good;
  outOfRange.Triangles[7] = 100000;
  EXPECT_NE(message(outOfRange, Budget(half, 1.0)).find("point id 100000"), std::string::npos);

  EXPECT_NE(message(good, Budget(half, -1.0)).find("animation weight"), std::string::npos);

  ReductionMesh nonManifold = good;
  // a third triangle on the edge (0, 1)
  nonManifold.Positions.insert(nonManifold.Positions.end(), { 0.05f, 0.0f, 1.0f });
  for (auto& d : nonManifold.PositionDeltas)
  {
    d.insert(d.end(), { 0.0f, 0.0f, 0.0f });
  }
  const uint32_t extra = static_cast<uint32_t>(nonManifold.GetNumberOfPoints() - 1);
  nonManifold.Triangles.insert(nonManifold.Triangles.end(), { 0, 1, extra, 1, 0, extra });
  EXPECT_NE(message(nonManifold, Budget(half, 1.0)).find("non-manifold"), std::string::npos);

  ReductionMesh degenerate = good;
  degenerate.Triangles.insert(degenerate.Triangles.end(), { 3, 3, 4 });
  const auto r = ReduceAnimationAware(degenerate, Budget(half, 1.0));
  EXPECT_EQ(r.DroppedDegenerateTriangles, 1u);
}
