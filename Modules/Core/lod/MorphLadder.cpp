// SPDX-License-Identifier: BSD-3-Clause
#include "lod/MorphLadder.h"

#include "base/Error.h"
#include "skin/Skinning.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <variant>

namespace morphnode
{
namespace
{
/// Closest point to p on triangle abc as barycentric weights (by Voronoi regions, Ericson,
/// "Real-Time Collision Detection" 5.1.5); returns the squared distance. Written here
/// because the core has no geometry library that does it (VTK's vtkTriangle is outside the
/// VTK-free core).
double ClosestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
  const glm::dvec3& c, glm::dvec3& bary)
{
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto at = [&](double u, double v, double w)
  {
    bary = glm::dvec3(u, v, w);
    const glm::dvec3 q = u * a + v * b + w * c;
    return glm::dot(p - q, p - q);
  };
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    return at(1, 0, 0);
  }
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3)
  {
    return at(0, 1, 0);
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    const double v = d1 / (d1 - d3);
    return at(1 - v, v, 0);
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6)
  {
    return at(0, 0, 1);
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    const double w = d2 / (d2 - d6);
    return at(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
  {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(0, 1 - w, w);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0))
  {
    // Degenerate triangle: its first corner.
    return at(1, 0, 0);
  }
  const double v = vb / denom, w = vc / denom;
  return at(1 - v - w, v, w);
}

/// Dense position deltas per target (1..n) and the neutral, as doubles.
struct DensePositions
{
  std::vector<double> Neutral;
  std::vector<std::vector<double>> Deltas;
};

DensePositions ReadPositions(const MorphMesh& mesh)
{
  const int index = mesh.GetPositionAttribute();
  if (index < 0)
  {
    throw InputError("MorphLadder: the mesh has no Position attribute.");
  }
  DensePositions out;
  std::visit(
    [&](const auto& positions)
    {
      using T = typename std::decay_t<decltype(positions.GetNeutral())>::value_type;
      const size_t n = positions.GetNeutral().size();
      out.Neutral.assign(positions.GetNeutral().begin(), positions.GetNeutral().end());
      std::vector<T> dense(n);
      for (size_t k = 1; k < positions.GetNumberOfTargets(); ++k)
      {
        positions.GetTarget(k).ToDense(dense.data());
        out.Deltas.emplace_back(dense.begin(), dense.end());
      }
    },
    mesh.GetAttribute(static_cast<size_t>(index)));
  return out;
}

/// Distances and moved points of every target over the points [0, n).
void LevelDistances(const DensePositions& positions, size_t n, LadderLevel& level)
{
  const size_t targets = positions.Deltas.size() + 1;
  TargetDistances& d = level.Distances;
  d.DistMorph.assign(targets, 0.0);
  d.DistNorm.assign(targets, 0.0);
  d.MaxDisplacement.assign(targets, 0.0);
  level.MovedPoints.assign(targets, 0.0);
  double largest = 0.0;
  for (size_t k = 1; k < targets; ++k)
  {
    const auto& delta = positions.Deltas[k - 1];
    for (size_t p = 0; p < n; ++p)
    {
      const double x = delta[3 * p], y = delta[3 * p + 1], z = delta[3 * p + 2];
      if (x != 0.0 || y != 0.0 || z != 0.0)
      {
        const double norm = std::sqrt(x * x + y * y + z * z);
        d.DistMorph[k] += norm;
        d.MaxDisplacement[k] = std::max(d.MaxDisplacement[k], norm);
        level.MovedPoints[k] += 1.0;
      }
    }
    largest = std::max(largest, d.DistMorph[k]);
  }
  for (size_t k = 1; k < targets && largest > 0.0; ++k)
  {
    d.DistNorm[k] = d.DistMorph[k] / largest;
  }
}

/// Corners, Barycentrics, MaxError and RmsError of `level` (l > 0), see LadderLevel; the
/// poses skinned by `skinPoseList` too when the ladder has influences.
void LevelErrors(const MorphLadder& ladder, size_t l, const DensePositions& positions,
  const std::vector<std::vector<glm::dmat4>>& skinPoseList, LadderLevel& level)
{
  const size_t n = level.NumberOfPoints;
  const size_t np = ladder.Mesh.GetNumberOfPoints();
  std::vector<std::vector<uint32_t>> fan(n); // vertex -> triangles
  const auto& tris = level.Triangles;
  for (size_t t = 0; 3 * t < tris.size(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      fan[tris[3 * t + c]].push_back(static_cast<uint32_t>(t));
    }
  }
  auto neutral = [&](size_t p)
  {
    return glm::dvec3(
      positions.Neutral[3 * p], positions.Neutral[3 * p + 1], positions.Neutral[3 * p + 2]);
  };
  level.Corners.resize(3 * np);
  level.Barycentrics.resize(3 * np);
  std::vector<uint32_t> ring;
  for (size_t p = 0; p < np; ++p)
  {
    const uint32_t r = ladder.Representative(l, static_cast<uint32_t>(p));
    // A point the level keeps is its own carried point.
    uint32_t corners[3] = { r, r, r };
    glm::dvec3 best(1, 0, 0);
    if (p >= n)
    {
      ring.clear();
      for (uint32_t t : fan[r])
      {
        for (int c = 0; c < 3; ++c)
        {
          const auto& more = fan[tris[3 * t + c]];
          ring.insert(ring.end(), more.begin(), more.end());
        }
      }
      double bestD = HUGE_VAL;
      const glm::dvec3 q = neutral(p);
      for (uint32_t t : ring)
      {
        glm::dvec3 bary;
        const double d = ClosestOnTriangle(
          q, neutral(tris[3 * t]), neutral(tris[3 * t + 1]), neutral(tris[3 * t + 2]), bary);
        if (d < bestD)
        {
          bestD = d;
          best = bary;
          std::copy_n(&tris[3 * t], 3, corners);
        }
      }
    }
    for (int c = 0; c < 3; ++c)
    {
      level.Corners[3 * p + c] = corners[c];
      level.Barycentrics[3 * p + c] = static_cast<float>(best[c]);
    }
  }
  // The carried points' distances in every pose: the neutral and each target at weight 1,
  // as they are and skinned by each of the settings' poses.
  std::vector<double> worst(np, 0.0); // per point, over the poses (squared)
  double maxError = 0.0, sum2 = 0.0;
  size_t count = 0;
  std::vector<double> pose(positions.Neutral.size()), skinned(pose.size());
  const size_t skinPoses = ladder.Influences.Empty() ? 0 : skinPoseList.size();
  for (size_t s = 0; s <= skinPoses; ++s)
  {
    for (size_t k = 0; k <= positions.Deltas.size(); ++k)
    {
      for (size_t i = 0; i < pose.size(); ++i)
      {
        pose[i] = positions.Neutral[i] + (k > 0 ? positions.Deltas[k - 1][i] : 0.0);
      }
      if (s > 0)
      {
        SkinPoints(ladder.Influences, skinPoseList[s - 1], pose.data(),
          static_cast<const double*>(nullptr), skinned.data(), static_cast<double*>(nullptr), 0,
          np);
        pose.swap(skinned);
      }
      for (size_t p = n; p < np; ++p)
      {
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c)
        {
          double q = 0.0;
          for (int i = 0; i < 3; ++i)
          {
            q += double(level.Barycentrics[3 * p + i]) * pose[3 * level.Corners[3 * p + i] + c];
          }
          d2 += (q - pose[3 * p + c]) * (q - pose[3 * p + c]);
        }
        maxError = std::max(maxError, d2);
        worst[p] = std::max(worst[p], d2);
        sum2 += d2;
      }
      count += np; // kept points count with distance 0
    }
  }
  level.MaxError = std::sqrt(maxError);
  const size_t q = (np * 99) / 100;
  std::nth_element(worst.begin(), worst.begin() + static_cast<std::ptrdiff_t>(q), worst.end());
  level.Error99 = std::sqrt(worst[q]);
  level.RmsError = count ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0;
}

/// GeomorphReach of level l towards l + 1.
void Reach(const MorphLadder& ladder, size_t l, const DensePositions& positions, LadderLevel& level)
{
  const size_t begin = ladder.Levels[l + 1].NumberOfPoints, end = level.NumberOfPoints;
  level.GeomorphReach.assign(positions.Deltas.size() + 1, 0.0);
  for (size_t k = 0; k <= positions.Deltas.size(); ++k)
  {
    const std::vector<double>& v = k == 0 ? positions.Neutral : positions.Deltas[k - 1];
    double reach = 0.0;
    for (size_t p = begin; p < end; ++p)
    {
      const size_t r = ladder.Parent[p];
      const double dx = v[3 * p] - v[3 * r], dy = v[3 * p + 1] - v[3 * r + 1],
                   dz = v[3 * p + 2] - v[3 * r + 2];
      reach = std::max(reach, dx * dx + dy * dy + dz * dz);
    }
    level.GeomorphReach[k] = std::sqrt(reach);
  }
}
} // namespace

uint32_t MorphLadder::Representative(size_t level, uint32_t point) const
{
  if (level >= this->Levels.size() || point >= this->Parent.size())
  {
    throw InputError("MorphLadder: level or point out of range.");
  }
  const size_t n = this->Levels[level].NumberOfPoints;
  while (point >= n)
  {
    point = this->Parent[point];
  }
  return point;
}

namespace
{
MorphLadder BuildLadder(
  const MorphMesh& mesh, const SkinInfluences* influences, const LadderSettings& settings)
{
  double previous = 1.0;
  for (double f : settings.TriangleFractions)
  {
    if (!std::isfinite(f) || f <= 0.0 || f >= previous)
    {
      throw InputError("MorphLadder: triangle fractions must decrease within (0, 1).");
    }
    previous = f;
  }
  mesh.Validate();
  const size_t np = mesh.GetNumberOfPoints();
  const size_t fullTriangles = mesh.GetNumberOfTriangles();
  const size_t levels = settings.TriangleFractions.size() + 1;

  // Chain the reductions; everything in the input's ids.
  std::vector<size_t> keptUntil(np, levels - 1); // last level a point is in
  std::vector<uint32_t> parentFull(np);
  std::iota(parentFull.begin(), parentFull.end(), 0u);
  std::vector<std::vector<uint32_t>> trianglesFull(levels);
  trianglesFull[0] = mesh.GetTriangles();
  std::vector<std::vector<uint32_t>> originalTriangles(levels); // level triangle -> input's
  originalTriangles[0].resize(fullTriangles);
  std::iota(originalTriangles[0].begin(), originalTriangles[0].end(), 0u);
  std::vector<uint32_t> kept(np); // this level's point -> input id
  std::iota(kept.begin(), kept.end(), 0u);
  MorphMesh current;
  size_t skipped = 0;
  for (size_t l = 1; l < levels; ++l)
  {
    ReductionSettings rs = settings.Reduction;
    rs.TargetPoints = 0;
    rs.TargetTriangles = std::max<size_t>(
      1, static_cast<size_t>(std::llround(settings.TriangleFractions[l - 1] * fullTriangles)));
    ReductionResult r = ReduceAnimationAware(l == 1 ? mesh : current, rs);
    if (l == 1)
    {
      skipped = r.SkippedNonManifoldTriangles;
    }
    std::vector<uint32_t> next(r.OriginalPointIds.size());
    for (size_t i = 0; i < next.size(); ++i)
    {
      next[i] = kept[r.OriginalPointIds[i]];
    }
    std::vector<bool> stays(kept.size(), false);
    for (uint32_t i : r.OriginalPointIds)
    {
      stays[i] = true;
    }
    for (size_t j = 0; j < kept.size(); ++j)
    {
      if (!stays[j])
      {
        keptUntil[kept[j]] = l - 1;
        parentFull[kept[j]] = next[r.Representatives[j]];
      }
    }
    originalTriangles[l].resize(r.OriginalTriangleIds.size());
    for (size_t i = 0; i < r.OriginalTriangleIds.size(); ++i)
    {
      originalTriangles[l][i] = originalTriangles[l - 1][r.OriginalTriangleIds[i]];
    }
    const auto& t = r.Mesh.GetTriangles();
    trianglesFull[l].resize(t.size());
    for (size_t i = 0; i < t.size(); ++i)
    {
      trianglesFull[l][i] = next[t[i]];
    }
    kept = std::move(next);
    current = std::move(r.Mesh);
  }

  // Renumber: coarsest level's points first, then what each finer level adds.
  MorphLadder ladder;
  ladder.SkippedTriangles = skipped;
  ladder.OriginalPointIds.reserve(np);
  for (size_t l = levels; l-- > 0;)
  {
    for (size_t p = 0; p < np; ++p)
    {
      if (keptUntil[p] == l)
      {
        ladder.OriginalPointIds.push_back(static_cast<uint32_t>(p));
      }
    }
  }
  std::vector<uint32_t> newId(np);
  for (size_t i = 0; i < np; ++i)
  {
    newId[ladder.OriginalPointIds[i]] = static_cast<uint32_t>(i);
  }
  ladder.Parent.resize(np);
  for (size_t i = 0; i < np; ++i)
  {
    ladder.Parent[i] = newId[parentFull[ladder.OriginalPointIds[i]]];
  }
  ladder.Levels.resize(levels);
  for (size_t l = 0; l < levels; ++l)
  {
    LadderLevel& level = ladder.Levels[l];
    level.NumberOfPoints = static_cast<size_t>(
      std::count_if(keptUntil.begin(), keptUntil.end(), [&](size_t k) { return k >= l; }));
    level.Triangles.resize(trianglesFull[l].size());
    for (size_t i = 0; i < level.Triangles.size(); ++i)
    {
      level.Triangles[i] = newId[trianglesFull[l][i]];
    }
    level.OriginalTriangleIds = std::move(originalTriangles[l]);
  }
  ladder.Mesh = GatherMorphMesh(
    mesh, ladder.OriginalPointIds, ladder.Levels[0].Triangles, settings.Reduction.SparseCoverage);
  if (influences && !influences->Empty())
  {
    ladder.Influences = influences->Gather(ladder.OriginalPointIds);
  }
  const DensePositions positions = ReadPositions(ladder.Mesh);
  for (size_t l = 0; l < levels; ++l)
  {
    LevelDistances(positions, ladder.Levels[l].NumberOfPoints, ladder.Levels[l]);
    if (l > 0)
    {
      LevelErrors(ladder, l, positions, settings.SkinPoses, ladder.Levels[l]);
    }
    if (l + 1 < levels)
    {
      Reach(ladder, l, positions, ladder.Levels[l]);
    }
  }
  return ladder;
}

} // namespace

MorphLadder BuildMorphLadder(const MorphMesh& mesh, const LadderSettings& settings)
{
  return BuildLadder(mesh, nullptr, settings);
}

MorphLadder BuildMorphLadder(
  const MorphMesh& mesh, const SkinInfluences& influences, const LadderSettings& settings)
{
  if (!influences.Empty())
  {
    if (influences.GetNumberOfPoints() != mesh.GetNumberOfPoints())
    {
      throw InputError("MorphLadder: skin influences for " +
        std::to_string(influences.GetNumberOfPoints()) + " points on a mesh of " +
        std::to_string(mesh.GetNumberOfPoints()) + ".");
    }
    size_t joints = 0; // joints a pose must have: the largest weighted index + 1
    for (size_t i = 0; i < influences.Weights.size(); ++i)
    {
      if (influences.Weights[i] != 0.0f)
      {
        joints = std::max<size_t>(joints, influences.Joints[i] + 1u);
      }
    }
    for (size_t s = 0; s < settings.SkinPoses.size(); ++s)
    {
      if (settings.SkinPoses[s].size() < joints)
      {
        throw InputError("MorphLadder: skin pose " + std::to_string(s) + " has " +
          std::to_string(settings.SkinPoses[s].size()) + " joint matrices; the influences use " +
          std::to_string(joints) + ".");
      }
    }
  }
  return BuildLadder(mesh, &influences, settings);
}

template <typename T>
void GeomorphLadder(
  const MorphLadder& ladder, size_t level, double alpha, T* values, int components)
{
  if (level + 1 >= ladder.Levels.size())
  {
    throw InputError(
      "GeomorphLadder: level " + std::to_string(level) + " has no coarser level to morph towards.");
  }
  if (components < 1)
  {
    throw InputError("GeomorphLadder: " + std::to_string(components) + " components per point.");
  }
  const T a = static_cast<T>(std::clamp(alpha, 0.0, 1.0));
  const size_t begin = ladder.Levels[level + 1].NumberOfPoints;
  const size_t end = ladder.Levels[level].NumberOfPoints;
  const size_t nc = static_cast<size_t>(components);
  for (size_t p = begin; p < end; ++p)
  {
    // The parent is in the coarser level's prefix, which this loop never writes.
    const size_t r = ladder.Parent[p];
    for (size_t c = 0; c < nc; ++c)
    {
      values[nc * p + c] = (T(1) - a) * values[nc * p + c] + a * values[nc * r + c];
    }
  }
}

template <typename T>
void GeomorphLadder(const MorphLadder& ladder, size_t level, double alpha, T* positions)
{
  GeomorphLadder(ladder, level, alpha, positions, 3);
}

LevelOfDetail ToLevelOfDetail(const MorphLadder& ladder, size_t l, const CostModel& cost)
{
  const LadderLevel& level = ladder.Levels.at(l);
  LevelOfDetail lod;
  lod.Name = l == 0 ? "full" : "level " + std::to_string(l);
  lod.NumberOfPoints = level.NumberOfPoints;
  lod.MovedPoints = level.MovedPoints;
  lod.Distances = level.Distances;
  lod.GeometricError = level.Error99;
  lod.GeomorphReach = level.GeomorphReach;
  lod.Cost = cost;
  if (l + 1 < ladder.Levels.size())
  {
    const size_t coarse = ladder.Levels[l + 1].NumberOfPoints;
    lod.RepresentativeInThisLevel.resize(level.NumberOfPoints);
    for (size_t p = 0; p < level.NumberOfPoints; ++p)
    {
      lod.RepresentativeInThisLevel[p] = p < coarse ? static_cast<uint32_t>(p) : ladder.Parent[p];
    }
    lod.CoarserToThis.resize(coarse);
    std::iota(lod.CoarserToThis.begin(), lod.CoarserToThis.end(), 0u);
  }
  return lod;
}

template void GeomorphLadder(const MorphLadder&, size_t, double, float*);
template void GeomorphLadder(const MorphLadder&, size_t, double, double*);
template void GeomorphLadder(const MorphLadder&, size_t, double, float*, int);
template void GeomorphLadder(const MorphLadder&, size_t, double, double*, int);
} // namespace morphnode
