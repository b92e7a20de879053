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
using morphnode::MorphMesh;
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
std::vector<double> Region(const MorphMesh& mesh)
{
  std::vector<double> region(mesh.GetNumberOfPoints(), 0.0);
  for (size_t t = 1; t < mesh.GetNumberOfTargets(); ++t)
  {
    const std::vector<float> d = reductiontest::DeltasOf(mesh, t);
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
  const MorphMesh mesh = reductiontest::MakeFace();
  const auto& positions = reductiontest::PositionsOf(mesh).GetNeutral();
  for (double weight : { 0.0, 1.0 })
  {
    const size_t budget = mesh.GetNumberOfTriangles() / 4;
    const ReductionResult r = ReduceAnimationAware(mesh, Budget(budget, weight));
    const size_t np = r.Mesh.GetNumberOfPoints();
    ASSERT_EQ(r.OriginalPointIds.size(), np);
    EXPECT_LE(r.Mesh.GetNumberOfTriangles(), budget);
    EXPECT_GT(r.Mesh.GetNumberOfTriangles(), budget - 4);
    ASSERT_EQ(r.Mesh.GetNumberOfTargets(), mesh.GetNumberOfTargets());
    EXPECT_EQ(r.Mesh.GetTargetNames(), mesh.GetTargetNames());
    ASSERT_NO_THROW(r.Mesh.Validate());
    EXPECT_TRUE(std::is_sorted(r.OriginalPointIds.begin(), r.OriginalPointIds.end()));
    const auto& reducedPositions = reductiontest::PositionsOf(r.Mesh).GetNeutral();
    for (size_t t = 1; t < mesh.GetNumberOfTargets(); ++t)
    {
      const std::vector<float> full = reductiontest::DeltasOf(mesh, t);
      const std::vector<float> reduced = reductiontest::DeltasOf(r.Mesh, t);
      for (size_t k = 0; k < np; ++k)
      {
        for (int c = 0; c < 3; ++c)
        {
          ASSERT_EQ(reduced[3 * k + c], full[3 * r.OriginalPointIds[k] + c])
            << "target " << t << " reduced point " << k;
        }
      }
    }
    for (size_t k = 0; k < np; ++k)
    {
      const uint32_t o = r.OriginalPointIds[k];
      for (int c = 0; c < 3; ++c)
      {
        ASSERT_EQ(reducedPositions[3 * k + c], positions[3 * o + c]);
      }
      // a kept point represents itself
      ASSERT_EQ(r.Representatives[o], k);
    }
    ASSERT_EQ(r.Representatives.size(), mesh.GetNumberOfPoints());
    for (uint32_t rep : r.Representatives)
    {
      ASSERT_LT(rep, np);
    }
    std::set<uint32_t> used(r.Mesh.GetTriangles().begin(), r.Mesh.GetTriangles().end());
    ASSERT_LT(*used.rbegin(), np);
    EXPECT_EQ(used.size(), np); // a grid has no isolated points, nor does its reduction
  }
}

TEST(AnimationAwareReduction, GatherCarriesAnyAttribute)
{
  const MorphMesh mesh = reductiontest::MakeFace(11);
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
  EXPECT_THROW(
    morphnode::GatherPoints(uv, 3, mesh.GetNumberOfPoints(), r.OriginalPointIds), InputError);
}

TEST(AnimationAwareReduction, KeepsMoreOfTheAnimatedRegions)
{
  const MorphMesh mesh = reductiontest::MakeFace();
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
    const auto ours =
      ReduceAnimationAware(mesh, Budget(budget, ReductionSettings().AnimationWeight));
    const size_t keptPlain = KeptAnimated(plain, region, animated);
    const size_t keptOurs = KeptAnimated(ours, region, animated);
    EXPECT_GT(keptOurs, keptPlain + keptPlain / 5)
      << "budget 1/" << divisor << ": animated points kept, ours " << keptOurs << ", plain "
      << keptPlain;
    // the same budget, spent elsewhere
    EXPECT_NEAR(
      double(ours.Mesh.GetNumberOfTriangles()), double(plain.Mesh.GetNumberOfTriangles()), 2.0);
  }
}

TEST(AnimationAwareReduction, WeightZeroIsPlainQuadricDecimation)
{
  // The module with weight 0 would compute ModQuadricT's cost; weight 0 uses ModQuadricT
  // itself. Without targets the animation terms vanish, so both must agree.
  auto flat = reductiontest::MakeFlatFace(21);
  flat.PositionDeltas.clear();
  const MorphMesh mesh = flat.ToMesh();
  const auto a = ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 3, 0.0));
  const auto b = ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 3, 1.0));
  EXPECT_EQ(a.OriginalPointIds, b.OriginalPointIds);
}

TEST(AnimationAwareReduction, GeomorphEndsOnTheReducedShape)
{
  const MorphMesh mesh = reductiontest::MakeFace(21);
  const auto r = ReduceAnimationAware(mesh, Budget(mesh.GetNumberOfTriangles() / 3, 1.0));
  const size_t np = mesh.GetNumberOfPoints();
  const std::vector<float>& positions = reductiontest::PositionsOf(mesh).GetNeutral();
  std::vector<uint32_t> rep(np);
  for (size_t v = 0; v < np; ++v)
  {
    rep[v] = r.OriginalPointIds[r.Representatives[v]];
  }
  std::vector<float> out(3 * np);
  morphnode::Geomorph(positions.data(), np, rep, 1.0, out.data());
  for (size_t v = 0; v < np; ++v)
  {
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_FLOAT_EQ(out[3 * v + c], positions[3 * rep[v] + c]);
    }
  }
  morphnode::Geomorph(positions.data(), np, rep, 0.0, out.data());
  EXPECT_EQ(out, positions);
  // Every triangle of the fine mesh at alpha 1 is degenerate or a triangle of the reduced
  // mesh: the shapes are identical.
  std::set<std::array<uint32_t, 3>> reduced;
  for (size_t t = 0; t < r.Mesh.GetNumberOfTriangles(); ++t)
  {
    std::array<uint32_t, 3> tri;
    for (int c = 0; c < 3; ++c)
    {
      tri[c] = r.OriginalPointIds[r.Mesh.GetTriangles()[3 * t + c]];
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    reduced.insert(tri);
  }
  for (size_t t = 0; t < mesh.GetNumberOfTriangles(); ++t)
  {
    std::array<uint32_t, 3> tri;
    for (int c = 0; c < 3; ++c)
    {
      tri[c] = rep[mesh.GetTriangles()[3 * t + c]];
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
  const auto flat = reductiontest::MakeFlatFace(11);
  const MorphMesh good = flat.ToMesh();
  const size_t half = good.GetNumberOfTriangles() / 2;
  auto message = [](const MorphMesh& m, const ReductionSettings& s)
  {
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
  auto noTriangles = flat;
  noTriangles.Triangles.clear();
  EXPECT_NE(message(noTriangles.ToMesh(), Budget(10, 1.0)).find("no triangles"), std::string::npos);

  EXPECT_NE(message(MorphMesh(), Budget(10, 1.0)).find("no points"), std::string::npos);

  MorphMesh noPositions(good.GetNumberOfPoints());
  noPositions.SetTargetNames({ "Neutral" });
  noPositions.AddAttribute<float>("uv", morphnode::AttributeRole::Generic, 2);
  noPositions.SetTriangles(good.GetTriangles());
  EXPECT_NE(
    message(noPositions, Budget(half, 1.0)).find("no Position attribute"), std::string::npos);

  EXPECT_NE(
    message(good, Budget(good.GetNumberOfTriangles(), 1.0)).find("budget"), std::string::npos);
  EXPECT_NE(message(good, Budget(good.GetNumberOfTriangles() + 100, 1.0)).find("must be below"),
    std::string::npos);
  ReductionSettings pointBudget;
  pointBudget.TargetPoints = good.GetNumberOfPoints();
  EXPECT_NE(message(good, pointBudget).find("point budget"), std::string::npos);
  EXPECT_NE(message(good, ReductionSettings()).find("no budget"), std::string::npos);

  MorphMesh mismatched = good;
  auto names = good.GetTargetNames();
  names.push_back("extra");
  mismatched.SetTargetNames(names);
  EXPECT_NE(message(mismatched, Budget(half, 1.0)).find("has 5 targets, the model has 6"),
    std::string::npos);

  auto outOfRange = flat;
  outOfRange.Triangles[7] = 100000;
  EXPECT_NE(
    message(outOfRange.ToMesh(), Budget(half, 1.0)).find("point id 100000"), std::string::npos);

  auto notFinite = flat;
  notFinite.Positions[5] = std::nanf("");
  EXPECT_NE(message(notFinite.ToMesh(), Budget(half, 1.0)).find("NaN"), std::string::npos);

  EXPECT_NE(message(good, Budget(half, -1.0)).find("animation weight"), std::string::npos);

  auto nonManifold = flat;
  // a third triangle on the edge (0, 1)
  nonManifold.Positions.insert(nonManifold.Positions.end(), { 0.05f, 0.0f, 1.0f });
  for (auto& d : nonManifold.PositionDeltas)
  {
    d.insert(d.end(), { 0.0f, 0.0f, 0.0f });
  }
  const uint32_t extra = static_cast<uint32_t>(nonManifold.GetNumberOfPoints() - 1);
  nonManifold.Triangles.insert(nonManifold.Triangles.end(), { 0, 1, extra, 1, 0, extra });
  EXPECT_NE(
    message(nonManifold.ToMesh(), Budget(half, 1.0)).find("non-manifold"), std::string::npos);

  auto degenerate = flat;
  degenerate.Triangles.insert(degenerate.Triangles.end(), { 3, 3, 4 });
  const auto r = ReduceAnimationAware(degenerate.ToMesh(), Budget(half, 1.0));
  EXPECT_EQ(r.DroppedDegenerateTriangles, 1u);
}

TEST(AnimationAwareReduction, DoublePositionsAndEveryAttributeAreCarried)
{
  // The same face in double, with a second attribute (normals-like, 3 components) and a
  // 2-component one: the collapses are the same as in float (the costs are computed in
  // double either way), and every attribute is gathered in its own type.
  const auto flat = reductiontest::MakeFlatFace(21);
  const MorphMesh single = flat.ToMesh();
  const size_t np = flat.GetNumberOfPoints();
  MorphMesh twice(np);
  twice.SetTargetNames(single.GetTargetNames());
  // (AddAttribute's reference holds only until the next AddAttribute.)
  auto& positions = twice.AddAttribute<double>("Position", morphnode::AttributeRole::Position, 3);
  std::vector<double> neutral(flat.Positions.begin(), flat.Positions.end());
  positions.SetNeutral(neutral.data());
  for (const auto& d : flat.PositionDeltas)
  {
    const std::vector<double> dd(d.begin(), d.end());
    positions.AddRelativeTarget(dd.data(), 0.3);
  }
  auto& uv = twice.AddAttribute<float>("uv", morphnode::AttributeRole::Generic, 2);
  std::vector<float> uvNeutral(2 * np), uvDelta(2 * np);
  for (size_t p = 0; p < np; ++p)
  {
    uvNeutral[2 * p] = float(p);
    uvNeutral[2 * p + 1] = -float(p);
    uvDelta[2 * p] = p % 7 == 0 ? 0.5f : 0.0f;
  }
  uv.SetNeutral(uvNeutral.data());
  for (size_t k = 0; k < flat.PositionDeltas.size(); ++k)
  {
    uv.AddRelativeTarget(uvDelta.data(), 0.3);
  }
  twice.SetTriangles(flat.Triangles);

  const auto budget =
    Budget(single.GetNumberOfTriangles() / 3, ReductionSettings().AnimationWeight);
  const auto a = ReduceAnimationAware(single, budget);
  const auto b = ReduceAnimationAware(twice, budget);
  EXPECT_EQ(a.OriginalPointIds, b.OriginalPointIds);
  EXPECT_EQ(a.Mesh.GetTriangles(), b.Mesh.GetTriangles());
  ASSERT_EQ(b.Mesh.GetNumberOfAttributes(), 2u);
  const auto& reducedUv = std::get<morphnode::MorphAttribute<float>>(b.Mesh.GetAttribute(1));
  EXPECT_EQ(reducedUv.GetName(), "uv");
  std::vector<float> reducedDelta(2 * b.Mesh.GetNumberOfPoints());
  reducedUv.GetTarget(2).ToDense(reducedDelta.data());
  for (size_t k = 0; k < b.OriginalPointIds.size(); ++k)
  {
    const uint32_t o = b.OriginalPointIds[k];
    ASSERT_EQ(reducedUv.GetNeutral()[2 * k], float(o));
    ASSERT_EQ(reducedDelta[2 * k], uvDelta[2 * o]);
    const auto& reducedPositions =
      std::get<morphnode::MorphAttribute<double>>(b.Mesh.GetAttribute(0)).GetNeutral();
    ASSERT_EQ(reducedPositions[3 * k + 1], neutral[3 * o + 1]);
  }
}
