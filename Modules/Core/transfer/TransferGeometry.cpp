// SPDX-License-Identifier: BSD-3-Clause
#include "transfer/TransferGeometry.h"

#include "base/Error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace morphnode
{
// Ericson, "Real-Time Collision Detection", 5.1.5: the Voronoi regions of the triangle.
glm::dvec3 ClosestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
  const glm::dvec3& c, glm::dvec3& bary)
{
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0)
  {
    bary = { 1, 0, 0 };
    return a;
  }
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3)
  {
    bary = { 0, 1, 0 };
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
  {
    const double v = d1 / (d1 - d3);
    bary = { 1 - v, v, 0 };
    return a + v * ab;
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6)
  {
    bary = { 0, 0, 1 };
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
  {
    const double w = d2 / (d2 - d6);
    bary = { 1 - w, 0, w };
    return a + w * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
  {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    bary = { 0, 1 - w, w };
    return b + w * (c - b);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0))
  {
    bary = { 1, 0, 0 };
    return a;
  }
  const double v = vb / denom, w = vc / denom;
  bary = { 1 - v - w, v, w };
  return a + ab * v + ac * w;
}

TriangleGrid::TriangleGrid(const TransferSurface& surface)
  : Surface(surface)
{
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const auto& p : surface.Points)
  {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (surface.Points.empty())
  {
    lo = hi = glm::dvec3(0.0);
  }
  const size_t nt = surface.GetNumberOfTriangles();
  // Cells about the mean edge, at most ~2M of them.
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-12));
  double cell = std::max(MeanEdgeLength(surface), 1e-12);
  const double maxCells = 2.0e6;
  while ((extent.x / cell + 1) * (extent.y / cell + 1) * (extent.z / cell + 1) > maxCells)
  {
    cell *= 1.25;
  }
  this->CellSize = cell;
  this->Origin = lo;
  for (int k = 0; k < 3; ++k)
  {
    this->Dims[k] = std::max(1, int(std::floor(extent[k] / cell)) + 1);
  }
  const size_t numCells = size_t(this->Dims[0]) * this->Dims[1] * this->Dims[2];
  auto cellRange = [&](uint32_t t, int lo3[3], int hi3[3])
  {
    glm::dvec3 a = surface.Points[surface.Triangles[3 * t]];
    glm::dvec3 mn = a, mx = a;
    for (int v = 1; v < 3; ++v)
    {
      mn = glm::min(mn, surface.Points[surface.Triangles[3 * t + v]]);
      mx = glm::max(mx, surface.Points[surface.Triangles[3 * t + v]]);
    }
    for (int k = 0; k < 3; ++k)
    {
      lo3[k] = std::clamp(int(std::floor((mn[k] - lo[k]) / cell)), 0, this->Dims[k] - 1);
      hi3[k] = std::clamp(int(std::floor((mx[k] - lo[k]) / cell)), 0, this->Dims[k] - 1);
    }
  };
  // Bounding spheres reject most triangles before the exact test.
  this->Spheres.resize(nt);
  for (size_t t = 0; t < nt; ++t)
  {
    const glm::dvec3 c =
      (surface.Points[surface.Triangles[3 * t]] + surface.Points[surface.Triangles[3 * t + 1]] +
        surface.Points[surface.Triangles[3 * t + 2]]) /
      3.0;
    double r = 0;
    for (int k = 0; k < 3; ++k)
      r = std::max(r, glm::length(surface.Points[surface.Triangles[3 * t + size_t(k)]] - c));
    this->Spheres[t] = glm::dvec4(c, r);
  }
  std::vector<uint32_t> count(numCells + 1, 0);
  for (int pass = 0; pass < 2; ++pass)
  {
    if (pass == 1)
    {
      this->CellStart.assign(numCells + 1, 0);
      for (size_t c = 0; c < numCells; ++c)
      {
        this->CellStart[c + 1] = this->CellStart[c] + count[c];
      }
      this->CellTriangles.resize(this->CellStart[numCells]);
      std::fill(count.begin(), count.end(), 0);
    }
    for (uint32_t t = 0; t < nt; ++t)
    {
      int a[3], b[3];
      cellRange(t, a, b);
      for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
          for (int x = a[0]; x <= b[0]; ++x)
          {
            const size_t c = (size_t(z) * this->Dims[1] + y) * this->Dims[0] + x;
            if (pass == 1)
            {
              this->CellTriangles[this->CellStart[c] + count[c]] = t;
            }
            ++count[c];
          }
    }
  }
}

SurfaceHit TriangleGrid::Closest(
  const glm::dvec3& p, double maxDistance, const std::function<bool(uint32_t)>& allowed) const
{
  SurfaceHit best;
  double bestDistance = maxDistance;
  int center[3];
  for (int k = 0; k < 3; ++k)
  {
    center[k] = int(std::floor((p[k] - this->Origin[k]) / this->CellSize));
  }
  const int maxRing = std::max({ this->Dims[0], this->Dims[1], this->Dims[2] }) + 1;
  const auto& pts = this->Surface.Points;
  const auto& tris = this->Surface.Triangles;
  for (int ring = 0; ring <= maxRing; ++ring)
  {
    // Every point of a cell in this ring is at least (ring - 1) cells away from p.
    if (ring > 0 && (ring - 1) * this->CellSize > bestDistance)
    {
      break;
    }
    for (int z = center[2] - ring; z <= center[2] + ring; ++z)
    {
      if (z < 0 || z >= this->Dims[2])
        continue;
      for (int y = center[1] - ring; y <= center[1] + ring; ++y)
      {
        if (y < 0 || y >= this->Dims[1])
          continue;
        const bool shellYZ = std::abs(z - center[2]) == ring || std::abs(y - center[1]) == ring;
        // Inside the shell's y-z extent only its two x ends are on the shell.
        const int xStep = shellYZ || ring == 0 ? 1 : 2 * ring;
        for (int x = center[0] - ring; x <= center[0] + ring; x += xStep)
        {
          if (x < 0 || x >= this->Dims[0])
            continue;
          const size_t c = (size_t(z) * this->Dims[1] + y) * this->Dims[0] + x;
          for (uint32_t i = this->CellStart[c]; i < this->CellStart[c + 1]; ++i)
          {
            const uint32_t t = this->CellTriangles[i];
            const glm::dvec4& sphere = this->Spheres[t];
            if (glm::length(glm::dvec3(sphere) - p) - sphere.w > bestDistance)
              continue;
            if (allowed && !allowed(t))
              continue;
            glm::dvec3 bary;
            const glm::dvec3 q = ClosestPointOnTriangle(
              p, pts[tris[3 * t]], pts[tris[3 * t + 1]], pts[tris[3 * t + 2]], bary);
            const double d = glm::length(q - p);
            if (d < bestDistance || (best.Triangle < 0 && d <= bestDistance))
            {
              bestDistance = d;
              best.Triangle = int(t);
              best.Point = q;
              best.Barycentric = bary;
              best.Distance = d;
            }
          }
        }
      }
    }
  }
  return best;
}

std::vector<glm::dvec3> ComputeTriangleNormals(const TransferSurface& s)
{
  std::vector<glm::dvec3> n(s.GetNumberOfTriangles(), glm::dvec3(0.0));
  for (size_t t = 0; t < n.size(); ++t)
  {
    const auto& a = s.Points[s.Triangles[3 * t]];
    const glm::dvec3 c =
      glm::cross(s.Points[s.Triangles[3 * t + 1]] - a, s.Points[s.Triangles[3 * t + 2]] - a);
    const double l = glm::length(c);
    if (l > 0)
      n[t] = c / l;
  }
  return n;
}

std::vector<glm::dvec3> ComputeVertexNormals(const TransferSurface& s)
{
  std::vector<glm::dvec3> n(s.GetNumberOfPoints(), glm::dvec3(0.0));
  for (size_t t = 0; t < s.GetNumberOfTriangles(); ++t)
  {
    const uint32_t* v = &s.Triangles[3 * t];
    const glm::dvec3 c =
      glm::cross(s.Points[v[1]] - s.Points[v[0]], s.Points[v[2]] - s.Points[v[0]]);
    for (int k = 0; k < 3; ++k)
      n[v[k]] += c;
  }
  for (auto& x : n)
  {
    const double l = glm::length(x);
    x = l > 0 ? x / l : glm::dvec3(0.0);
  }
  return n;
}

double MeanEdgeLength(const TransferSurface& s)
{
  double sum = 0;
  const size_t nt = s.GetNumberOfTriangles();
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      sum +=
        glm::length(s.Points[s.Triangles[3 * t + k]] - s.Points[s.Triangles[3 * t + (k + 1) % 3]]);
  return nt ? sum / (3.0 * nt) : 0.0;
}

SurfaceEdges ComputeEdges(const TransferSurface& s)
{
  std::vector<uint64_t> keys;
  keys.reserve(s.Triangles.size());
  for (size_t t = 0; t < s.GetNumberOfTriangles(); ++t)
    for (int k = 0; k < 3; ++k)
    {
      uint64_t a = s.Triangles[3 * t + k], b = s.Triangles[3 * t + (k + 1) % 3];
      if (a > b)
        std::swap(a, b);
      keys.push_back((a << 32) | b);
    }
  std::sort(keys.begin(), keys.end());
  SurfaceEdges e;
  for (size_t i = 0; i < keys.size();)
  {
    size_t j = i;
    while (j < keys.size() && keys[j] == keys[i])
      ++j;
    e.Edges.emplace_back(uint32_t(keys[i] >> 32), uint32_t(keys[i] & 0xffffffffu));
    e.TriangleCount.push_back(uint32_t(j - i));
    i = j;
  }
  return e;
}

void CheckSurface(const TransferSurface& s, const std::string& what)
{
  if (s.Points.empty() || s.Triangles.empty())
    throw InputError(what + ": no triangles");
  if (s.Triangles.size() % 3 != 0)
    throw InputError(what + ": triangle list is not a multiple of 3");
  for (const auto& p : s.Points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(what + ": a point is not finite");
  for (uint32_t id : s.Triangles)
    if (id >= s.Points.size())
      throw InputError(what + ": triangle references point " + std::to_string(id) + " of " +
        std::to_string(s.Points.size()));
  const SurfaceEdges e = ComputeEdges(s);
  size_t bad = 0;
  size_t example = 0;
  for (size_t i = 0; i < e.Edges.size(); ++i)
    if (e.TriangleCount[i] > 2)
    {
      if (bad == 0)
        example = i;
      ++bad;
    }
  if (bad > 0)
    throw InputError(what + ": non-manifold mesh: " + std::to_string(bad) +
      " edges are shared by more than two triangles (e.g. points " +
      std::to_string(e.Edges[example].first) + "-" + std::to_string(e.Edges[example].second) +
      "); merge or remove the duplicate faces first");
}

std::vector<std::vector<uint32_t>> ComputeBoundaryLoops(const TransferSurface& s)
{
  // Directed boundary edges: an edge used once, in the direction of its triangle.
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t t = 0; t < s.GetNumberOfTriangles(); ++t)
    for (int k = 0; k < 3; ++k)
      ++directed[{ s.Triangles[3 * t + k], s.Triangles[3 * t + (k + 1) % 3] }];
  std::multimap<uint32_t, uint32_t> next;
  for (const auto& [e, n] : directed)
    if (n == 1 && directed.find({ e.second, e.first }) == directed.end())
      next.emplace(e.first, e.second);
  std::vector<std::vector<uint32_t>> loops;
  std::vector<bool> used(s.GetNumberOfPoints(), false);
  for (const auto& [start, unused] : next)
  {
    (void)unused;
    if (used[start] || next.count(start) != 1)
      continue;
    std::vector<uint32_t> loop{ start };
    used[start] = true;
    uint32_t v = start;
    bool closed = false;
    while (true)
    {
      if (next.count(v) != 1)
        break;
      const uint32_t w = next.find(v)->second;
      if (w == start)
      {
        closed = true;
        break;
      }
      if (used[w])
        break;
      used[w] = true;
      loop.push_back(w);
      v = w;
    }
    if (closed && loop.size() >= 3)
      loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<bool> ComputeBoundaryPoints(const TransferSurface& s)
{
  std::vector<bool> b(s.GetNumberOfPoints(), false);
  const SurfaceEdges e = ComputeEdges(s);
  for (size_t i = 0; i < e.Edges.size(); ++i)
    if (e.TriangleCount[i] == 1)
      b[e.Edges[i].first] = b[e.Edges[i].second] = true;
  return b;
}

int ComputeComponents(const TransferSurface& s, std::vector<int>& component)
{
  const size_t n = s.GetNumberOfPoints();
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::function<uint32_t(uint32_t)> find = [&](uint32_t x)
  {
    while (parent[x] != x)
    {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (size_t t = 0; t < s.GetNumberOfTriangles(); ++t)
    for (int k = 1; k < 3; ++k)
    {
      const uint32_t a = find(s.Triangles[3 * t]), b = find(s.Triangles[3 * t + k]);
      if (a != b)
        parent[a] = b;
    }
  component.assign(n, -1);
  std::vector<int> label(n, -1);
  int count = 0;
  for (size_t i = 0; i < n; ++i)
  {
    const uint32_t r = find(uint32_t(i));
    if (label[r] < 0)
      label[r] = count++;
    component[i] = label[r];
  }
  return count;
}

void ComputeAdjacency(
  const TransferSurface& s, std::vector<uint32_t>& offsets, std::vector<uint32_t>& neighbours)
{
  const SurfaceEdges e = ComputeEdges(s);
  offsets.assign(s.GetNumberOfPoints() + 1, 0);
  for (const auto& [a, b] : e.Edges)
  {
    ++offsets[a + 1];
    ++offsets[b + 1];
  }
  for (size_t i = 0; i < s.GetNumberOfPoints(); ++i)
    offsets[i + 1] += offsets[i];
  neighbours.resize(offsets.back());
  std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (const auto& [a, b] : e.Edges)
  {
    neighbours[fill[a]++] = b;
    neighbours[fill[b]++] = a;
  }
}
} // namespace morphnode
