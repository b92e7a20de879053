// SPDX-License-Identifier: BSD-3-Clause
#include "lod/MorphLadder.h"

#include "base/Error.h"

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
/// Squared distance from p to triangle abc (the closest point by Voronoi regions, Ericson,
/// "Real-Time Collision Detection" 5.1.5). Written here because the core has no geometry
/// library that does it (VTK's vtkTriangle is outside the VTK-free core).
double PointTriangleDistance2(
  const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto dist2 = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    return dist2(a);
  }
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3)
  {
    return dist2(b);
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    return dist2(a + (d1 / (d1 - d3)) * ab);
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6)
  {
    return dist2(c);
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    return dist2(a + (d2 / (d2 - d6)) * ac);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
  {
    return dist2(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0))
  {
    // Degenerate triangle: its closest vertex.
    return std::min({ dist2(a), dist2(b), dist2(c) });
  }
  const double v = vb / denom, w = vc / denom;
  return dist2(a + v * ab + w * ac);
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
    [&](const auto& positions) {
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

/// MaxError and RmsError of `level` (l > 0): every shared point against the level's
/// triangles around its representative (its two-ring), in the neutral and every target's
/// pose at weight 1. A local search, so a lip point is measured against its own lip's
/// triangles, not the other lip's that a global closest point might find.
void LevelErrors(const MorphLadder& ladder, size_t l, const DensePositions& positions, LadderLevel& level)
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
  std::vector<std::vector<uint32_t>> ring(n); // representative -> triangles of its two-ring
  std::vector<uint32_t> reps(np);
  for (size_t p = 0; p < np; ++p)
  {
    reps[p] = ladder.Representative(l, static_cast<uint32_t>(p));
    auto& r = ring[reps[p]];
    if (!r.empty())
    {
      continue;
    }
    for (uint32_t t : fan[reps[p]])
    {
      for (int c = 0; c < 3; ++c)
      {
        const auto& more = fan[tris[3 * t + c]];
        r.insert(r.end(), more.begin(), more.end());
      }
    }
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  double maxError = 0.0, sum2 = 0.0;
  size_t count = 0;
  std::vector<double> pose(positions.Neutral.size());
  for (size_t k = 0; k <= positions.Deltas.size(); ++k)
  {
    for (size_t i = 0; i < pose.size(); ++i)
    {
      pose[i] = positions.Neutral[i] + (k > 0 ? positions.Deltas[k - 1][i] : 0.0);
    }
    auto at = [&](size_t p) { return glm::dvec3(pose[3 * p], pose[3 * p + 1], pose[3 * p + 2]); };
    for (size_t p = 0; p < np; ++p)
    {
      double best = p < n ? 0.0 : HUGE_VAL; // a kept point lies on its own triangles
      if (p >= n)
      {
        const glm::dvec3 q = at(p);
        for (uint32_t t : ring[reps[p]])
        {
          best = std::min(best,
            PointTriangleDistance2(q, at(tris[3 * t]), at(tris[3 * t + 1]), at(tris[3 * t + 2])));
        }
        if (!std::isfinite(best)) // a representative with no triangle: its distance
        {
          best = glm::dot(q - at(reps[p]), q - at(reps[p]));
        }
      }
      maxError = std::max(maxError, best);
      sum2 += best;
      ++count;
    }
  }
  level.MaxError = std::sqrt(maxError);
  level.RmsError = count ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0;
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

MorphLadder BuildMorphLadder(const MorphMesh& mesh, const LadderSettings& settings)
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
  std::vector<uint32_t> kept(np); // this level's point -> input id
  std::iota(kept.begin(), kept.end(), 0u);
  MorphMesh current;
  for (size_t l = 1; l < levels; ++l)
  {
    ReductionSettings rs = settings.Reduction;
    rs.TargetPoints = 0;
    rs.TargetTriangles = std::max<size_t>(1,
      static_cast<size_t>(std::llround(settings.TriangleFractions[l - 1] * fullTriangles)));
    ReductionResult r = ReduceAnimationAware(l == 1 ? mesh : current, rs);
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
  }
  ladder.Mesh = GatherMorphMesh(
    mesh, ladder.OriginalPointIds, ladder.Levels[0].Triangles, settings.Reduction.SparseCoverage);
  const DensePositions positions = ReadPositions(ladder.Mesh);
  for (size_t l = 0; l < levels; ++l)
  {
    LevelDistances(positions, ladder.Levels[l].NumberOfPoints, ladder.Levels[l]);
    if (l > 0)
    {
      LevelErrors(ladder, l, positions, ladder.Levels[l]);
    }
  }
  return ladder;
}

template <typename T>
void GeomorphLadder(const MorphLadder& ladder, size_t level, double alpha, T* positions)
{
  if (level + 1 >= ladder.Levels.size())
  {
    throw InputError("GeomorphLadder: level " + std::to_string(level) +
      " has no coarser level to morph towards.");
  }
  const T a = static_cast<T>(std::clamp(alpha, 0.0, 1.0));
  const size_t begin = ladder.Levels[level + 1].NumberOfPoints;
  const size_t end = ladder.Levels[level].NumberOfPoints;
  for (size_t p = begin; p < end; ++p)
  {
    // The parent is in the coarser level's prefix, which this loop never writes.
    const size_t r = ladder.Parent[p];
    for (int c = 0; c < 3; ++c)
    {
      positions[3 * p + c] = (T(1) - a) * positions[3 * p + c] + a * positions[3 * r + c];
    }
  }
}

LevelOfDetail ToLevelOfDetail(const MorphLadder& ladder, size_t l, const CostModel& cost)
{
  const LadderLevel& level = ladder.Levels.at(l);
  LevelOfDetail lod;
  lod.Name = l == 0 ? "full" : "level " + std::to_string(l);
  lod.NumberOfPoints = level.NumberOfPoints;
  lod.MovedPoints = level.MovedPoints;
  lod.Distances = level.Distances;
  lod.GeometricError = level.MaxError;
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
} // namespace morphnode
