// SPDX-License-Identifier: BSD-3-Clause
#include "transfer/Transfer.h"

#include "base/Error.h"
#include "base/Text.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <set>

namespace morphnode
{
using text::FormatNumber;
using text::ParseNumber;
using text::Quote;
using text::SplitWhitespace;
namespace
{
using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double Percentile(std::vector<double> v, double q)
{
  if (v.empty())
    return 0.0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

struct Similarity
{
  double Scale = 1.0;
  glm::dmat3 R{ 1.0 };
  glm::dvec3 T{ 0.0 };
  glm::dvec3 Apply(const glm::dvec3& p) const { return this->Scale * (this->R * p) + this->T; }
  Similarity Then(const Similarity& b) const // b after this
  {
    Similarity c;
    c.Scale = b.Scale * this->Scale;
    c.R = b.R * this->R;
    c.T = b.Scale * (b.R * this->T) + b.T;
    return c;
  }
};

/// Umeyama's least-squares similarity (or rigid, withScale false) taking from onto to.
Similarity FitSimilarity(
  const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to, bool withScale)
{
  Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
  for (size_t i = 0; i < from.size(); ++i)
  {
    a.col(long(i)) << from[i].x, from[i].y, from[i].z;
    b.col(long(i)) << to[i].x, to[i].y, to[i].z;
  }
  const Eigen::Matrix4d m = Eigen::umeyama(a, b, withScale);
  Similarity s;
  const Eigen::Matrix3d sr = m.topLeftCorner<3, 3>();
  s.Scale = withScale ? std::cbrt(sr.determinant()) : 1.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      s.R[c][r] = sr(r, c) / s.Scale; // glm: [column][row]
  s.T = { m(0, 3), m(1, 3), m(2, 3) };
  return s;
}

// The source face's features: where its mouth and lids open, which side is which, its
// landmarks and its face region, all from its own targets.
struct Seam
{
  std::vector<uint32_t> Loop;
  std::vector<TransferSide> LoopSide; // +s upper, -s lower
  double Width = 0.0;
};

struct SourceFeatures
{
  std::vector<Seam> Seams;    // [0] the mouth, then lids
  std::vector<int> SeamLabel; // the label s of each seam
  std::vector<std::pair<std::string, uint32_t>> Landmarks;
  std::vector<bool> FaceRegion;
  /// Points that some target moves by at least 20 % of its largest motion: where the
  /// registration must fit.
  std::vector<bool> AnimatedRegion;
  std::vector<bool> RigidComponentOfPoint;
  std::vector<int> Component;
  std::vector<bool> RigidComponent;
};

int FindName(const std::vector<std::string>& names, const std::string& name)
{
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name)
      return int(i);
  return -1;
}

/// The loop's two arcs between its corners (its two points furthest apart): true for the
/// points of the first arc (corners included). Also gives the width (the corners' distance).
std::vector<bool> SplitLoop(
  const std::vector<glm::dvec3>& pts, const std::vector<uint32_t>& loop, double& width)
{
  size_t a = 0, b = 0;
  width = 0;
  for (size_t i = 0; i < loop.size(); ++i)
    for (size_t j = i + 1; j < loop.size(); ++j)
    {
      const double d = glm::length(pts[loop[i]] - pts[loop[j]]);
      if (d > width)
      {
        width = d;
        a = i;
        b = j;
      }
    }
  std::vector<bool> first(loop.size(), false);
  for (size_t i = a; i <= b; ++i)
    first[i] = true;
  return first;
}

Seam FindSeam(const TransferSource& source, const std::vector<std::vector<uint32_t>>& loops,
  int target, int label, const std::set<size_t>& taken, size_t& chosen)
{
  const auto& d = source.Deltas[size_t(target)];
  double best = 0.0;
  chosen = loops.size();
  for (size_t l = 0; l < loops.size(); ++l)
  {
    if (taken.count(l))
      continue;
    // The opening whose sides move most unlike each other for its size: the mouth
    // (jawOpen: the lower lip moves, the upper does not), not an outer border.
    double lo = std::numeric_limits<double>::infinity(), hi = 0, width = 0;
    for (uint32_t v : loops[l])
    {
      lo = std::min(lo, glm::length(d[v]));
      hi = std::max(hi, glm::length(d[v]));
      for (uint32_t w : loops[l])
        width = std::max(width, glm::length(source.Surface.Points[v] - source.Surface.Points[w]));
    }
    const double score = width > 0 ? (hi - lo) / width : 0.0;
    if (score > best)
    {
      best = score;
      chosen = l;
    }
  }
  Seam seam;
  if (chosen == loops.size())
    return seam;
  seam.Loop = loops[chosen];
  // Two arcs between the corners; the mouth target moves the lower lip more, the lid
  // targets the upper lid.
  const std::vector<bool> inFirst = SplitLoop(source.Surface.Points, seam.Loop, seam.Width);
  double first = 0, second = 0;
  size_t nFirst = 0;
  for (size_t i = 0; i < seam.Loop.size(); ++i)
  {
    (inFirst[i] ? first : second) += glm::length(d[seam.Loop[i]]);
    nFirst += inFirst[i];
  }
  first /= double(std::max<size_t>(1, nFirst));
  second /= double(std::max<size_t>(1, seam.Loop.size() - nFirst));
  const bool firstMovesMore = first > second;
  const bool firstIsUpper = (label == 1) ? !firstMovesMore : firstMovesMore;
  for (size_t i = 0; i < seam.Loop.size(); ++i)
    seam.LoopSide.push_back(TransferSide(inFirst[i] == firstIsUpper ? label : -label));
  return seam;
}

SourceFeatures AnalyzeSource(const TransferSource& source, const TransferOptions& options)
{
  SourceFeatures f;
  const auto& pts = source.Surface.Points;
  const size_t n = pts.size();
  const int mouth = FindName(source.TargetNames, options.MouthTarget);
  if (mouth < 0)
    throw InputError("source: not a face MorphNode can transfer from: it has no '" +
      options.MouthTarget + "' target to find the mouth with");
  const auto loops = ComputeBoundaryLoops(source.Surface);
  std::set<size_t> taken;
  size_t chosen = 0;
  Seam mouthSeam = FindSeam(source, loops, mouth, 1, taken, chosen);
  if (mouthSeam.Loop.empty())
    throw InputError("source: not a face MorphNode can transfer from: '" + options.MouthTarget +
      "' moves no opening of the mesh (the mouth must be an opening)");
  taken.insert(chosen);
  f.Seams.push_back(mouthSeam);
  f.SeamLabel.push_back(1);
  std::vector<int> lidTargets;
  for (size_t i = 0; i < options.LidTargets.size() && i < 2; ++i)
  {
    const int t = FindName(source.TargetNames, options.LidTargets[i]);
    if (t < 0)
      throw InputError("source: not a face MorphNode can transfer from: it has no '" +
        options.LidTargets[i] + "' target to find the lids with");
    Seam lid = FindSeam(source, loops, t, int(i) + 2, taken, chosen);
    if (lid.Loop.empty())
      throw InputError("source: '" + options.LidTargets[i] + "' moves no opening of the mesh");
    taken.insert(chosen);
    f.Seams.push_back(lid);
    f.SeamLabel.push_back(int(i) + 2);
    lidTargets.push_back(t);
  }

  // Landmarks.
  auto argmaxMotion = [&](int t)
  {
    uint32_t best = 0;
    double bm = -1;
    for (size_t i = 0; i < n; ++i)
    {
      const double m = glm::length(source.Deltas[size_t(t)][i]);
      if (m > bm)
      {
        bm = m;
        best = uint32_t(i);
      }
    }
    return best;
  };
  glm::dvec3 eyeMid(0.0), right(1, 0, 0);
  if (lidTargets.size() == 2)
  {
    const uint32_t l = argmaxMotion(lidTargets[0]), r = argmaxMotion(lidTargets[1]);
    f.Landmarks.emplace_back("eye_L", l);
    f.Landmarks.emplace_back("eye_R", r);
    eyeMid = 0.5 * (pts[l] + pts[r]);
    right = glm::normalize(pts[l] - pts[r]);
  }
  // Mouth corners: the loop's extremes along the eyes' axis.
  const Seam& ms = f.Seams[0];
  uint32_t cl = ms.Loop[0], cr = ms.Loop[0];
  for (uint32_t v : ms.Loop)
  {
    if (glm::dot(pts[v], right) > glm::dot(pts[cl], right))
      cl = v;
    if (glm::dot(pts[v], right) < glm::dot(pts[cr], right))
      cr = v;
  }
  f.Landmarks.emplace_back("mouthCorner_L", cl);
  f.Landmarks.emplace_back("mouthCorner_R", cr);
  const glm::dvec3 mouthMid = 0.5 * (pts[cl] + pts[cr]);
  uint32_t upper = ms.Loop[0], lower = ms.Loop[0];
  double bu = 1e300, bl = 1e300;
  for (size_t i = 0; i < ms.Loop.size(); ++i)
  {
    const double d = glm::length(pts[ms.Loop[i]] - mouthMid);
    if (ms.LoopSide[i] > 0 && d < bu)
    {
      bu = d;
      upper = ms.Loop[i];
    }
    if (ms.LoopSide[i] < 0 && d < bl)
    {
      bl = d;
      lower = ms.Loop[i];
    }
  }
  f.Landmarks.emplace_back("upperLip", upper);
  f.Landmarks.emplace_back("lowerLip", lower);
  f.Landmarks.emplace_back("chin", argmaxMotion(mouth));
  if (lidTargets.size() == 2)
  {
    // The nose tip: the point furthest forward between the mouth and the eyes, near the
    // middle. Forward is where the skin the targets move most faces, on average (the
    // mesh's centre says nothing on a whole body).
    const std::vector<glm::dvec3> normals = ComputeVertexNormals(source.Surface);
    glm::dvec3 facing(0.0);
    for (const auto& d : source.Deltas)
    {
      double largest = 0;
      for (const auto& v : d)
        largest = std::max(largest, glm::length(v));
      for (size_t i = 0; i < n; ++i)
        if (glm::length(d[i]) > 0.2 * largest)
          facing += normals[i];
    }
    glm::dvec3 up = glm::normalize(eyeMid - mouthMid);
    up = glm::normalize(up - glm::dot(up, right) * right);
    glm::dvec3 forward = glm::cross(right, up);
    if (glm::dot(forward, facing) < 0)
      forward = -forward;
    const double eyeDistance = glm::length(pts[f.Landmarks[0].second] - pts[f.Landmarks[1].second]);
    const double h = glm::dot(eyeMid - mouthMid, up);
    uint32_t nose = 0;
    double bf = -1e300;
    for (size_t i = 0; i < n; ++i)
    {
      const glm::dvec3 q = pts[i] - mouthMid;
      const double u = glm::dot(q, up);
      if (std::abs(glm::dot(q, right)) < 0.25 * eyeDistance && u > 0.2 * h && u < 0.9 * h &&
        glm::dot(q, forward) > bf)
      {
        bf = glm::dot(q, forward);
        nose = uint32_t(i);
      }
    }
    f.Landmarks.emplace_back("noseTip", nose);
  }

  // Face region: every point some target moves.
  f.FaceRegion.assign(n, false);
  double maxMotion = 0;
  for (const auto& d : source.Deltas)
    for (const auto& v : d)
      maxMotion = std::max(maxMotion, glm::length(v));
  for (const auto& d : source.Deltas)
    for (size_t i = 0; i < n; ++i)
      if (glm::length(d[i]) > 1e-4 * maxMotion)
        f.FaceRegion[i] = true;

  f.AnimatedRegion.assign(n, false);
  for (const auto& d : source.Deltas)
  {
    double largest = 0;
    for (const auto& v : d)
      largest = std::max(largest, glm::length(v));
    for (size_t i = 0; i < n; ++i)
      if (glm::length(d[i]) > 0.2 * largest)
        f.AnimatedRegion[i] = true;
  }

  // Rigid parts: components that every target moves rigidly (or not at all).
  const int nc = ComputeComponents(source.Surface, f.Component);
  f.RigidComponent.assign(size_t(nc), false);
  if (nc > 1)
  {
    std::vector<std::vector<uint32_t>> members(static_cast<size_t>(nc));
    for (size_t i = 0; i < n; ++i)
      members[size_t(f.Component[i])].push_back(uint32_t(i));
    for (int c = 0; c < nc; ++c)
    {
      const auto& m = members[size_t(c)];
      if (m.size() < 4)
        continue;
      bool rigid = true, moves = false;
      for (const auto& d : source.Deltas)
      {
        double mm = 0;
        std::vector<glm::dvec3> a, b;
        for (uint32_t v : m)
        {
          mm = std::max(mm, glm::length(d[v]));
          a.push_back(pts[v]);
          b.push_back(pts[v] + d[v]);
        }
        if (mm == 0)
          continue;
        moves = true;
        const Similarity s = FitSimilarity(a, b, false);
        double err = 0;
        for (size_t k = 0; k < a.size(); ++k)
          err = std::max(err, glm::length(s.Apply(a[k]) - b[k]));
        if (err > 1e-3 * mm + 1e-9)
        {
          rigid = false;
          break;
        }
      }
      f.RigidComponent[size_t(c)] = rigid && moves;
    }
  }
  return f;
}

/// Geodesic (edge path) distance from the seeds, up to `radius` (infinity beyond).
std::vector<double> EdgeDistance(const std::vector<glm::dvec3>& pts,
  const std::vector<uint32_t>& offsets, const std::vector<uint32_t>& neighbours,
  const std::vector<uint32_t>& seeds, double radius)
{
  std::vector<double> dist(pts.size(), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (uint32_t v : seeds)
  {
    dist[v] = 0;
    queue.emplace(0.0, v);
  }
  while (!queue.empty())
  {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v])
      continue;
    for (uint32_t k = offsets[v]; k < offsets[v + 1]; ++k)
    {
      const uint32_t w = neighbours[k];
      const double nd = d + glm::length(pts[w] - pts[v]);
      if (nd < dist[w] && nd <= radius)
      {
        dist[w] = nd;
        queue.emplace(nd, w);
      }
    }
  }
  return dist;
}

/// The sides around one seam: a point within `radius` of an arc (along the mesh) takes that
/// arc's side when the other arc is clearly further (beyond the corners both are about as
/// far, and the point stays unlabelled).
void LabelSides(const std::vector<glm::dvec3>& pts, const std::vector<uint32_t>& offsets,
  const std::vector<uint32_t>& neighbours, const std::vector<uint32_t>& loop,
  const std::vector<TransferSide>& loopSide, double radius, double width,
  std::vector<TransferSide>& labels)
{
  std::vector<uint32_t> upper, lower;
  TransferSide label = 0;
  for (size_t i = 0; i < loop.size(); ++i)
  {
    (loopSide[i] > 0 ? upper : lower).push_back(loop[i]);
    label = TransferSide(std::abs(loopSide[i]));
  }
  const std::vector<double> du = EdgeDistance(pts, offsets, neighbours, upper, 4 * radius);
  const std::vector<double> dl = EdgeDistance(pts, offsets, neighbours, lower, 4 * radius);
  for (size_t i = 0; i < pts.size(); ++i)
  {
    const double near = std::min(du[i], dl[i]), far = std::max(du[i], dl[i]);
    if (near <= radius && far > 2.0 * near + 0.05 * width)
      labels[i] = TransferSide(du[i] < dl[i] ? label : -label);
  }
}

std::vector<glm::dvec3> Interpolate(const std::vector<glm::dvec3>& values,
  const std::vector<uint32_t>& tris, const std::vector<int>& hit,
  const std::vector<glm::dvec3>& bary)
{
  std::vector<glm::dvec3> out(hit.size(), glm::dvec3(0.0));
  for (size_t i = 0; i < hit.size(); ++i)
    if (hit[i] >= 0)
    {
      const uint32_t* t = &tris[3 * size_t(hit[i])];
      out[i] = bary[i].x * values[t[0]] + bary[i].y * values[t[1]] + bary[i].z * values[t[2]];
    }
  return out;
}

std::vector<float> ToFloats(const std::vector<glm::dvec3>& v)
{
  std::vector<float> f(3 * v.size());
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k)
      f[3 * i + size_t(k)] = float(v[i][k]);
  return f;
}
} // namespace

const std::vector<std::string>& TransferLandmarkNames()
{
  static const std::vector<std::string> names{ "eye_L", "eye_R", "mouthCorner_L", "mouthCorner_R",
    "upperLip", "lowerLip", "chin", "noseTip" };
  return names;
}

std::vector<TransferLandmark> ParseTransferLandmarks(
  const std::string& text, const std::string& sourceName)
{
  std::vector<TransferLandmark> result;
  size_t lineNumber = 0;
  size_t start = 0;
  while (start <= text.size())
  {
    size_t end = text.find('\n', start);
    if (end == std::string::npos)
      end = text.size();
    std::string_view line(text.data() + start, end - start);
    ++lineNumber;
    start = end + 1;
    const size_t hash = line.find('#');
    if (hash != std::string_view::npos)
      line = line.substr(0, hash);
    const auto tokens = SplitWhitespace(line);
    if (tokens.empty())
    {
      if (end == text.size())
        break;
      continue;
    }
    const std::string where = sourceName + ":" + std::to_string(lineNumber) + ": ";
    if (tokens.size() != 4)
      throw InputError(where + "expected 'name x y z'");
    TransferLandmark l;
    l.Name = std::string(tokens[0]);
    if (FindName(TransferLandmarkNames(), l.Name) < 0)
    {
      std::string known;
      for (const auto& n : TransferLandmarkNames())
        known += (known.empty() ? "" : ", ") + n;
      throw InputError(where + "unknown landmark " + Quote(l.Name) + " (known: " + known + ")");
    }
    for (const auto& other : result)
      if (other.Name == l.Name)
        throw InputError(where + "landmark " + Quote(l.Name) + " given twice");
    for (int k = 0; k < 3; ++k)
    {
      double v = 0;
      if (!ParseNumber(tokens[size_t(k) + 1], v) || !std::isfinite(v))
        throw InputError(where + "not a finite number: " + Quote(tokens[size_t(k) + 1]));
      l.Position[k] = v;
    }
    result.push_back(l);
    if (end == text.size())
      break;
  }
  return result;
}

TransferSource MakeTransferSource(const MorphMesh& mesh)
{
  mesh.Validate();
  const int pa = mesh.GetPositionAttribute();
  if (pa < 0)
    throw InputError("source: the mesh has no positions");
  if (!mesh.HasTriangles())
    throw InputError("source: the mesh has no triangles");
  if (mesh.GetNumberOfTargets() < 2)
    throw InputError("source: the mesh has no morph targets to transfer");
  TransferSource s;
  const size_t n = mesh.GetNumberOfPoints();
  s.Surface.Triangles = mesh.GetTriangles();
  s.TargetNames.assign(mesh.GetTargetNames().begin() + 1, mesh.GetTargetNames().end());
  std::visit(
    [&](const auto& attribute)
    {
      using T = std::decay_t<decltype(attribute.GetNeutral()[0])>;
      if (attribute.GetNumberOfComponents() != 3)
        throw InputError("source: positions do not have 3 components");
      std::vector<T> buffer(3 * n);
      s.Surface.Points.resize(n);
      const T* neutral = attribute.GetNeutral().data();
      for (size_t i = 0; i < n; ++i)
        s.Surface.Points[i] = { neutral[3 * i], neutral[3 * i + 1], neutral[3 * i + 2] };
      for (size_t t = 1; t < mesh.GetNumberOfTargets(); ++t)
      {
        attribute.GetTarget(t).ToDense(buffer.data());
        std::vector<glm::dvec3> d(n);
        for (size_t i = 0; i < n; ++i)
          d[i] = { buffer[3 * i], buffer[3 * i + 1], buffer[3 * i + 2] };
        s.Deltas.push_back(std::move(d));
      }
    },
    mesh.GetAttribute(size_t(pa)));
  return s;
}

TransferResult TransferTargets(
  const TransferSource& source, const TransferSurface& target, const TransferOptions& options)
{
  CheckSurface(source.Surface, "source");
  CheckSurface(target, "target");
  if (source.Deltas.size() != source.TargetNames.size() || source.Deltas.empty())
    throw InputError("source: no targets to transfer");
  for (const auto& d : source.Deltas)
    if (d.size() != source.Surface.GetNumberOfPoints())
      throw InputError("source: a target's deltas do not match the points");
  TransferResult result;
  result.TargetNames = source.TargetNames;
  const size_t ns = source.Surface.GetNumberOfPoints();
  const size_t nt = target.GetNumberOfPoints();
  const SourceFeatures features = AnalyzeSource(source, options);
  auto landmarkPoint = [&](const std::string& name) -> int
  {
    for (const auto& [n, v] : features.Landmarks)
      if (n == name)
        return int(v);
    return -1;
  };
  const double sourceEyeDistance = landmarkPoint("eye_L") >= 0
    ? glm::length(source.Surface.Points[size_t(landmarkPoint("eye_L"))] -
        source.Surface.Points[size_t(landmarkPoint("eye_R"))])
    : features.Seams[0].Width;

  // 1. Similarity alignment.
  auto t0 = Clock::now();
  const TriangleGrid targetGrid(target);
  const std::vector<bool> targetBoundary = ComputeBoundaryPoints(target);
  const std::vector<glm::dvec3> targetTriNormals = ComputeTriangleNormals(target);
  auto onBoundary = [&](const SurfaceHit& h)
  {
    // A hit on a border edge or corner of the target (not inside a triangle).
    const uint32_t* t = &target.Triangles[3 * size_t(h.Triangle)];
    int inside = 0;
    bool border = false;
    for (int k = 0; k < 3; ++k)
    {
      if (h.Barycentric[k] > 1e-9)
        ++inside;
      else if (targetBoundary[t[(k + 1) % 3]] && targetBoundary[t[(k + 2) % 3]])
        border = true;
    }
    return inside < 3 && border;
  };
  std::vector<uint32_t> faceIds;
  for (size_t i = 0; i < ns; ++i)
    if (features.FaceRegion[i])
      faceIds.push_back(uint32_t(i));
  const std::vector<glm::dvec3> sourceNormals = ComputeVertexNormals(source.Surface);

  const TriangleGrid sourceGrid(source.Surface);
  const std::vector<glm::dvec3> sourceTriNormals = ComputeTriangleNormals(source.Surface);
  const std::vector<bool> sourceBoundary = ComputeBoundaryPoints(source.Surface);
  std::vector<bool> faceTriangle(source.Surface.GetNumberOfTriangles(), false);
  for (size_t t = 0; t < faceTriangle.size(); ++t)
    faceTriangle[t] = features.FaceRegion[source.Surface.Triangles[3 * t]] &&
      features.FaceRegion[source.Surface.Triangles[3 * t + 1]] &&
      features.FaceRegion[source.Surface.Triangles[3 * t + 2]];
  std::vector<uint32_t> targetSample;
  for (size_t i = 0; i < nt; i += std::max<size_t>(1, nt / 3000))
    targetSample.push_back(uint32_t(i));

  // Trimmed ICP (point to plane, both ways) over at most ~3000 face points, until the
  // points move less than 1e-8 eye distances (at most 60 steps).
  std::vector<uint32_t> icpIds;
  {
    const size_t stride = std::max<size_t>(1, faceIds.size() / 3000);
    for (size_t i = 0; i < faceIds.size(); i += stride)
      icpIds.push_back(faceIds[i]);
  }
  std::vector<std::pair<glm::dvec3, glm::dvec3>> landmarkPairs;
  auto icp = [&](Similarity s, int iterations, bool withScale, double& residual)
  {
    // The search radius stays that of the start: a shrinking face must not see less.
    const double radius = 0.5 * s.Scale * sourceEyeDistance;
    const double startScale = s.Scale;
    for (int it = 0; it < iterations; ++it)
    {
      std::vector<glm::dvec3> from, to, normalsOf;
      std::vector<double> dist;
      for (uint32_t v : icpIds)
      {
        const glm::dvec3 p = s.Apply(source.Surface.Points[v]);
        const SurfaceHit h = targetGrid.Closest(p, radius);
        if (h.Triangle < 0 || onBoundary(h))
          continue;
        if (glm::dot(s.R * sourceNormals[v], targetTriNormals[size_t(h.Triangle)]) < 0.3)
          continue;
        from.push_back(source.Surface.Points[v]);
        to.push_back(h.Point);
        dist.push_back(h.Distance);
        normalsOf.push_back(targetTriNormals[size_t(h.Triangle)]);
      }
      if (from.size() < 10)
      {
        residual = std::numeric_limits<double>::infinity();
        return s;
      }
      const double cut = std::max(3.0 * Percentile(dist, 0.5), 1e-3 * s.Scale * sourceEyeDistance);
      std::vector<glm::dvec3> f2, t2;
      for (size_t k = 0; k < from.size(); ++k)
        if (dist[k] <= cut)
        {
          f2.push_back(from[k]);
          t2.push_back(to[k]);
        }
      // Point to plane (Chen and Medioni), linearized in a small turn w, a scale step and a
      // translation about the points' centroid: 7 unknowns, solved by Eigen.
      std::vector<glm::dvec3> n2;
      for (size_t k = 0; k < from.size(); ++k)
        if (dist[k] <= cut)
          n2.push_back(normalsOf[k]);
      // Both ways: target points near the face pull on the source too. One way alone lets
      // the scale collapse (a shrunken face lies on any surface).
      for (uint32_t q : targetSample)
      {
        const glm::dvec3 local = glm::transpose(s.R) * (target.Points[q] - s.T) / s.Scale;
        const SurfaceHit h =
          sourceGrid.Closest(local, radius / s.Scale, [&](uint32_t t) { return faceTriangle[t]; });
        if (h.Triangle < 0 || h.Distance * s.Scale > cut)
          continue;
        const uint32_t* st = &source.Surface.Triangles[3 * size_t(h.Triangle)];
        if (h.Barycentric[0] * h.Barycentric[1] * h.Barycentric[2] == 0 &&
          (sourceBoundary[st[0]] || sourceBoundary[st[1]] || sourceBoundary[st[2]]))
          continue;
        f2.push_back(h.Point);
        t2.push_back(target.Points[q]);
        n2.push_back(s.R * sourceTriNormals[size_t(h.Triangle)]);
      }
      glm::dvec3 c(0.0);
      std::vector<glm::dvec3> y(f2.size());
      for (size_t k = 0; k < f2.size(); ++k)
      {
        y[k] = s.Apply(f2[k]);
        c += y[k];
      }
      c /= double(y.size());
      Eigen::Matrix<double, 7, 7> ata = Eigen::Matrix<double, 7, 7>::Zero();
      Eigen::Matrix<double, 7, 1> atb = Eigen::Matrix<double, 7, 1>::Zero();
      for (size_t k = 0; k < y.size(); ++k)
      {
        const glm::dvec3 q = y[k] - c;
        const glm::dvec3 nn = n2[k];
        const glm::dvec3 qn = glm::cross(q, nn);
        Eigen::Matrix<double, 7, 1> row;
        row << qn.x, qn.y, qn.z, nn.x, nn.y, nn.z, glm::dot(nn, q);
        ata += row * row.transpose();
        atb += row * glm::dot(nn, t2[k] - y[k]);
      }
      // Landmarks (when given) hold the face where they put it: point to point, together
      // weighing a fifth of the surface.
      for (const auto& [from, to] : landmarkPairs)
      {
        const double wl = 0.2 * double(y.size()) / double(landmarkPairs.size());
        const glm::dvec3 yl = s.Apply(from);
        const glm::dvec3 q = yl - c;
        for (int axis = 0; axis < 3; ++axis)
        {
          glm::dvec3 nn(0.0);
          nn[axis] = 1.0;
          const glm::dvec3 qn = glm::cross(q, nn);
          Eigen::Matrix<double, 7, 1> row;
          row << qn.x, qn.y, qn.z, nn.x, nn.y, nn.z, glm::dot(nn, q);
          ata += wl * row * row.transpose();
          atb += wl * row * glm::dot(nn, to - yl);
        }
      }
      ata += 1e-12 * ata.trace() * Eigen::Matrix<double, 7, 7>::Identity();
      const Eigen::Matrix<double, 7, 1> sol = ata.ldlt().solve(atb);
      const glm::dvec3 w(sol[0], sol[1], sol[2]);
      const double angle = glm::length(w);
      Similarity step; // y -> (1 + sigma) R (y - c) + c + t
      if (angle > 0)
      {
        const Eigen::Matrix3d r =
          Eigen::AngleAxisd(angle, Eigen::Vector3d(w.x, w.y, w.z) / angle).toRotationMatrix();
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            step.R[b][a] = r(a, b);
      }
      step.Scale = withScale ? std::clamp(1.0 + sol[6], 0.8, 1.25) : 1.0;
      // Point to plane sees little of a change of scale on a smooth face and lets it drift:
      // the scale stays within 20 % of where it started (the landmarks' or the axes').
      step.Scale = std::clamp(step.Scale * s.Scale, 0.8 * startScale, 1.25 * startScale) / s.Scale;
      step.T = c + glm::dvec3(sol[3], sol[4], sol[5]) - step.Scale * (step.R * c);
      const Similarity next = s.Then(step);
      // Residual: the trimmed mean, penalized by the share of the face that found nothing.
      double sum = 0;
      for (size_t k = 0; k < from.size(); ++k)
        sum += std::min(dist[k], cut);
      residual = sum / double(from.size()) * double(icpIds.size()) / double(from.size());
      double moved = 0;
      for (size_t k = 0; k < y.size(); k += 7)
        moved = std::max(moved, glm::length(step.Apply(y[k]) - y[k]));
      s = next;
      if (moved < 1e-8 * s.Scale * sourceEyeDistance)
        break;
    }
    return s;
  };

  Similarity align;
  if (!options.TargetLandmarks.empty())
  {
    for (const auto& l : options.TargetLandmarks)
      if (landmarkPoint(l.Name) >= 0)
        landmarkPairs.emplace_back(
          source.Surface.Points[size_t(landmarkPoint(l.Name))], l.Position);
  }
  if (!options.TargetLandmarks.empty())
  {
    std::vector<glm::dvec3> from, to;
    for (const auto& l : options.TargetLandmarks)
    {
      const int v = landmarkPoint(l.Name);
      if (v < 0)
        throw InputError("landmarks: the source has no landmark " + Quote(l.Name));
      from.push_back(source.Surface.Points[size_t(v)]);
      to.push_back(l.Position);
    }
    if (from.size() < 3)
      throw InputError(
        "landmarks: at least 3 are needed, " + std::to_string(from.size()) + " given");
    align = FitSimilarity(from, to, true);
    if (!(align.Scale > 0) || !std::isfinite(align.Scale))
      throw InputError("landmarks: they do not determine a similarity (collinear?)");
  }
  else
  {
    // Principal axes of source and target (all points), the four proper sign choices.
    auto moments =
      [](const std::vector<glm::dvec3>& p, glm::dvec3& mean, Eigen::Matrix3d& axes, double& spread)
    {
      mean = glm::dvec3(0.0);
      for (const auto& q : p)
        mean += q;
      mean /= double(p.size());
      Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
      for (const auto& q : p)
      {
        const Eigen::Vector3d d(q.x - mean.x, q.y - mean.y, q.z - mean.z);
        c += d * d.transpose();
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c / double(p.size()));
      axes = eig.eigenvectors();
      if (axes.determinant() < 0)
        axes.col(0) *= -1;
      spread = std::sqrt(eig.eigenvalues().sum());
    };
    glm::dvec3 ms, mt;
    Eigen::Matrix3d as, at;
    double ss = 0, st = 0;
    moments(source.Surface.Points, ms, as, ss);
    moments(target.Points, mt, at, st);
    double bestResidual = std::numeric_limits<double>::infinity();
    // All 24 proper ways to map the source's axes onto the target's (the spreads of a
    // face's axes can be close, so their order is not trusted), each refined by a few ICP
    // steps over a thinned face; the best fit wins.
    const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
      { 2, 1, 0 } };
    const std::vector<uint32_t> allIds = icpIds, allSample = targetSample;
    icpIds.clear();
    targetSample.clear();
    for (size_t i = 0; i < allIds.size(); i += 10)
      icpIds.push_back(allIds[i]);
    for (size_t i = 0; i < allSample.size(); i += 10)
      targetSample.push_back(allSample[i]);
    for (const auto& pm : perms)
      for (int sg = 0; sg < 8; ++sg)
      {
        Eigen::Matrix3d map = Eigen::Matrix3d::Zero();
        for (int k = 0; k < 3; ++k)
          map(pm[k], k) = (sg >> k) & 1 ? -1.0 : 1.0;
        if (map.determinant() < 0)
          continue;
        const Eigen::Matrix3d r = at * map * as.transpose();
        Similarity s;
        s.Scale = st / ss;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            s.R[b][a] = r(a, b);
        s.T = mt - s.Scale * (s.R * ms);
        double residual = 0;
        s = icp(s, 6, false, residual);
        if (residual < bestResidual)
        {
          bestResidual = residual;
          align = s;
        }
      }
    icpIds = allIds;
    targetSample = allSample;
    if (!std::isfinite(bestResidual))
      throw InputError("target: no automatic alignment found the face (give landmarks)");
  }
  {
    double residual = 0;
    align = icp(align, 60, true, residual);
  }
  result.Scale = align.Scale;
  result.Rotation = align.R;
  result.Translation = align.T;
  result.EyeDistance = align.Scale * sourceEyeDistance;
  const double eyeDistance = result.EyeDistance;
  std::vector<glm::dvec3> aligned(ns);
  for (size_t i = 0; i < ns; ++i)
    aligned[i] = align.Apply(source.Surface.Points[i]);
  std::vector<std::vector<glm::dvec3>> alignedDeltas(source.Deltas.size());
  for (size_t k = 0; k < source.Deltas.size(); ++k)
  {
    alignedDeltas[k].resize(ns);
    for (size_t i = 0; i < ns; ++i)
      alignedDeltas[k][i] = align.Scale * (align.R * source.Deltas[k][i]);
  }
  auto faceResidual = [&](const std::vector<glm::dvec3>& x, double& mean)
  {
    std::vector<double> d;
    const double cap = eyeDistance;
    for (uint32_t v : faceIds)
    {
      if (!features.AnimatedRegion[v])
        continue;
      const SurfaceHit h = targetGrid.Closest(x[v], cap);
      d.push_back(h.Triangle < 0 ? cap : h.Distance);
    }
    double s = 0;
    for (double x : d)
      s += x;
    mean = d.empty() ? 0 : s / double(d.size());
    return Percentile(d, 0.95);
  };
  {
    double mean = 0;
    result.AlignedResidualP95 = faceResidual(aligned, mean);
  }
  result.AlignSeconds = Since(t0);

  // 2. Non-rigid ICP: displacements u of the aligned source, stiffness on edge differences.
  t0 = Clock::now();
  std::vector<uint32_t> sOffsets, sNeighbours;
  ComputeAdjacency(source.Surface, sOffsets, sNeighbours);
  std::vector<glm::dvec3> x = aligned;
  if (!options.Stiffness.empty())
  {
    using Triplet = Eigen::Triplet<double>;
    std::vector<Triplet> laplacian;
    for (size_t i = 0; i < ns; ++i)
    {
      laplacian.emplace_back(int(i), int(i), double(sOffsets[i + 1] - sOffsets[i]));
      for (uint32_t k = sOffsets[i]; k < sOffsets[i + 1]; ++k)
        laplacian.emplace_back(int(i), int(sNeighbours[k]), -1.0);
    }
    Eigen::SparseMatrix<double> L(static_cast<long>(ns), static_cast<long>(ns));
    L.setFromTriplets(laplacian.begin(), laplacian.end());
    std::vector<std::pair<uint32_t, glm::dvec3>> landmarkGoals;
    for (const auto& l : options.TargetLandmarks)
      landmarkGoals.emplace_back(uint32_t(landmarkPoint(l.Name)), l.Position);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    bool analyzed = false;
    for (size_t stage = 0; stage < options.Stiffness.size(); ++stage)
    {
      const double alpha = options.Stiffness[stage];
      // Landmarks guide the first stages only: they are approximate.
      const double beta = stage < 2 ? 1.0 : 0.0;
      for (int it = 0; it < options.IterationsPerStage; ++it)
      {
        const std::vector<glm::dvec3> normals =
          ComputeVertexNormals(TransferSurface{ x, source.Surface.Triangles });
        Eigen::VectorXd w = Eigen::VectorXd::Constant(long(ns), 1e-8);
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(long(ns), 3);
        std::vector<double> dist;
        std::vector<SurfaceHit> hits(ns);
        for (size_t i = 0; i < ns; ++i)
        {
          hits[i] = targetGrid.Closest(x[i], 0.15 * eyeDistance);
          if (hits[i].Triangle >= 0)
            dist.push_back(hits[i].Distance);
        }
        const double cut = std::max(3.0 * Percentile(dist, 0.5), 0.02 * eyeDistance);
        for (size_t i = 0; i < ns; ++i)
        {
          const SurfaceHit& h = hits[i];
          if (h.Triangle < 0 || h.Distance > cut || onBoundary(h) ||
            glm::dot(normals[i], targetTriNormals[size_t(h.Triangle)]) < 0.5)
            continue;
          w[long(i)] = 1.0;
          const glm::dvec3 g = h.Point - aligned[i];
          rhs.row(long(i)) << g.x, g.y, g.z;
        }
        for (const auto& [v, q] : landmarkGoals)
        {
          if (beta == 0)
            break;
          w[long(v)] += beta;
          const glm::dvec3 g = beta * (q - aligned[v]);
          rhs.row(long(v)) += Eigen::RowVector3d(g.x, g.y, g.z);
        }
        Eigen::SparseMatrix<double> A = alpha * L;
        for (size_t i = 0; i < ns; ++i)
          A.coeffRef(long(i), long(i)) += w[long(i)];
        if (!analyzed)
        {
          solver.analyzePattern(A);
          analyzed = true;
        }
        solver.factorize(A);
        if (solver.info() != Eigen::Success)
          throw InputError("registration: the system could not be factored");
        const Eigen::MatrixXd u = solver.solve(rhs);
        for (size_t i = 0; i < ns; ++i)
          x[i] = aligned[i] + glm::dvec3(u(long(i), 0), u(long(i), 1), u(long(i), 2));
      }
    }
  }
  result.Registered = x;
  result.ResidualP95 = faceResidual(x, result.ResidualMean);
  for (const auto& [name, v] : features.Landmarks)
    result.SourceLandmarks.push_back({ name, x[v] });
  if (result.ResidualP95 > options.MaxResidual * eyeDistance)
    throw InputError("target: the source's face does not fit it: registration residual (95th "
                     "percentile) " +
      FormatNumber(result.ResidualP95) + " is above the limit " +
      FormatNumber(options.MaxResidual * eyeDistance) + " (" + FormatNumber(options.MaxResidual) +
      " x the eye distance " + FormatNumber(eyeDistance) +
      "); is it a face? Give landmarks if the automatic alignment failed");
  result.RegisterSeconds = Since(t0);

  // 3. Deformation transfer on the registered source: gradients of the aligned source's
  // targets applied to the registered triangles; K = G^T A G, factored once.
  t0 = Clock::now();
  const auto& tris = source.Surface.Triangles;
  const size_t nTri = source.Surface.GetNumberOfTriangles();
  std::vector<std::vector<glm::dvec3>> dtDeltas;
  if (options.Method == TransferMethod::DeformationTransfer)
  {
    using Triplet = Eigen::Triplet<double>;
    std::vector<Triplet> g;
    std::vector<double> area(nTri, 0.0);
    std::vector<glm::dmat3> projector(nTri, glm::dmat3(0.0));
    for (size_t t = 0; t < nTri; ++t)
    {
      const glm::dvec3 p0 = x[tris[3 * t]], p1 = x[tris[3 * t + 1]], p2 = x[tris[3 * t + 2]];
      const glm::dvec3 c = glm::cross(p1 - p0, p2 - p0);
      const double a2 = glm::length(c);
      if (!(a2 > 1e-14 * eyeDistance * eyeDistance))
        continue;
      const glm::dvec3 nrm = c / a2;
      area[t] = 0.5 * a2;
      const glm::dvec3 grad[3] = { glm::cross(nrm, p2 - p1) / a2, glm::cross(nrm, p0 - p2) / a2,
        glm::cross(nrm, p1 - p0) / a2 };
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d)
          g.emplace_back(int(3 * t) + d, int(tris[3 * t + size_t(k)]), grad[k][d]);
      projector[t] = glm::dmat3(1.0) - glm::outerProduct(nrm, nrm);
    }
    Eigen::SparseMatrix<double> G(static_cast<long>(3 * nTri), static_cast<long>(ns));
    G.setFromTriplets(g.begin(), g.end());
    Eigen::VectorXd areas(long(3 * nTri));
    for (size_t t = 0; t < nTri; ++t)
      for (int d = 0; d < 3; ++d)
        areas[long(3 * t) + d] = area[t];
    const Eigen::SparseMatrix<double> GtA = G.transpose() * areas.asDiagonal();
    Eigen::SparseMatrix<double> K = GtA * G;
    double meanDiag = 0;
    for (long i = 0; i < K.rows(); ++i)
      meanDiag += K.coeff(i, i);
    const double eps = 1e-7 * meanDiag / double(ns);
    for (size_t i = 0; i < ns; ++i)
      K.coeffRef(long(i), long(i)) += eps;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
    if (solver.info() != Eigen::Success)
      throw InputError("deformation transfer: the system could not be factored");
    // The frame of a triangle after Sumner and Popovic: two edges and the scaled normal.
    auto frame = [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    {
      const glm::dvec3 e1 = b - a, e2 = c - a;
      const glm::dvec3 n = glm::cross(e1, e2);
      const double l = std::sqrt(glm::length(n));
      return glm::dmat3(e1, e2, l > 0 ? n / l : glm::dvec3(0.0));
    };
    std::vector<glm::dmat3> inverse(nTri, glm::dmat3(0.0));
    for (size_t t = 0; t < nTri; ++t)
    {
      const glm::dmat3 v =
        frame(aligned[tris[3 * t]], aligned[tris[3 * t + 1]], aligned[tris[3 * t + 2]]);
      if (std::abs(glm::determinant(v)) > 0)
        inverse[t] = glm::inverse(v);
    }
    dtDeltas.resize(source.Deltas.size());
    Eigen::MatrixXd b(long(3 * nTri), 3);
    Eigen::MatrixXd anchor(long(ns), 3);
    for (size_t k = 0; k < source.Deltas.size(); ++k)
    {
      const auto& d = alignedDeltas[k];
      bool moves = false;
      for (const auto& v : d)
        if (v != glm::dvec3(0.0))
        {
          moves = true;
          break;
        }
      dtDeltas[k].assign(ns, glm::dvec3(0.0));
      if (!moves)
        continue;
      for (size_t t = 0; t < nTri; ++t)
      {
        glm::dmat3 j(0.0);
        if (area[t] > 0 && inverse[t] != glm::dmat3(0.0))
        {
          const uint32_t* v = &tris[3 * t];
          const glm::dmat3 q =
            frame(aligned[v[0]] + d[v[0]], aligned[v[1]] + d[v[1]], aligned[v[2]] + d[v[2]]) *
            inverse[t];
          j = q * projector[t]; // columns: spatial direction; rows: coordinate
        }
        for (int c = 0; c < 3; ++c)
          for (int dir = 0; dir < 3; ++dir)
            b(long(3 * t) + dir, c) = j[dir][c]; // row c of J, component dir
      }
      for (size_t i = 0; i < ns; ++i)
        for (int c = 0; c < 3; ++c)
          anchor(long(i), c) = eps * (x[i][c] + d[i][c]);
      const Eigen::MatrixXd rhs = GtA * b + anchor;
      const Eigen::MatrixXd solved = solver.solve(rhs);
      for (size_t i = 0; i < ns; ++i)
        dtDeltas[k][i] =
          glm::dvec3(solved(long(i), 0), solved(long(i), 1), solved(long(i), 2)) - x[i];
    }
  }
  result.TransferSeconds = Since(t0);

  // 4. Seam-aware resampling onto the target's points.
  t0 = Clock::now();
  {
    // The source's sides: around each seam, each point takes its nearest arc's side.
    std::vector<TransferSide> sourceSide(ns, 0);
    for (const auto& seam : features.Seams)
    {
      LabelSides(x, sOffsets, sNeighbours, seam.Loop, seam.LoopSide, 0.3 * align.Scale * seam.Width,
        align.Scale * seam.Width, sourceSide);
    }
    result.SourceSide = sourceSide;
    // The target's openings matched to the source's seams.
    std::vector<TransferSide> targetSide(nt, 0);
    const auto targetLoops = ComputeBoundaryLoops(target);
    std::vector<uint32_t> tOffsets, tNeighbours;
    ComputeAdjacency(target, tOffsets, tNeighbours);
    std::set<size_t> used;
    for (size_t s = 0; s < features.Seams.size(); ++s)
    {
      const Seam& seam = features.Seams[s];
      const double width = align.Scale * seam.Width;
      size_t best = targetLoops.size();
      double bestDistance = std::numeric_limits<double>::infinity();
      for (size_t l = 0; l < targetLoops.size(); ++l)
      {
        if (used.count(l))
          continue;
        // Symmetric mean distance between the loops' points.
        auto meanNearest = [&](const std::vector<uint32_t>& a, const std::vector<glm::dvec3>& pa,
                             const std::vector<uint32_t>& b, const std::vector<glm::dvec3>& pb)
        {
          double sum = 0;
          for (uint32_t i : a)
          {
            double m = std::numeric_limits<double>::infinity();
            for (uint32_t j : b)
              m = std::min(m, glm::length(pa[i] - pb[j]));
            sum += m;
          }
          return sum / double(a.size());
        };
        const double d = 0.5 *
          (meanNearest(targetLoops[l], target.Points, seam.Loop, x) +
            meanNearest(seam.Loop, x, targetLoops[l], target.Points));
        if (d < bestDistance)
        {
          bestDistance = d;
          best = l;
        }
      }
      const bool found = best < targetLoops.size() && bestDistance < 0.2 * width;
      if (!found)
      {
        const std::string what = s == 0 ? "mouth" : "lid (" + options.LidTargets[s - 1] + ")";
        const std::string distance = best < targetLoops.size()
          ? "the nearest opening is " + FormatNumber(bestDistance) + " away on average"
          : "it has no openings";
        if (s == 0 && options.RequireMouthOpening)
          throw InputError(
            "target: closed mouth: no opening of the lips near the source's mouth (" + distance +
            "); cut the lips apart along the mouth line, so that the mouth can open");
        result.Warnings.push_back(
          "target: no " + what + " opening found (" + distance + "): its sides are not kept apart");
        continue;
      }
      used.insert(best);
      const auto& loop = targetLoops[best];
      std::set<uint32_t> onLoop(loop.begin(), loop.end());
      // Each loop point votes by where its inner neighbours land on the source's sides.
      std::vector<uint32_t> sideIds;
      for (size_t i = 0; i < ns; ++i)
        if (std::abs(sourceSide[i]) == features.SeamLabel[s])
          sideIds.push_back(uint32_t(i));
      std::vector<TransferSide> loopSide(loop.size(), 0);
      for (size_t i = 0; i < loop.size(); ++i)
      {
        const uint32_t v = loop[i];
        glm::dvec3 m(0.0);
        int count = 0;
        for (uint32_t k = tOffsets[v]; k < tOffsets[v + 1]; ++k)
          if (!onLoop.count(tNeighbours[k]))
          {
            m += target.Points[tNeighbours[k]];
            ++count;
          }
        m = count ? m / double(count) : target.Points[v];
        double bd = std::numeric_limits<double>::infinity();
        for (uint32_t j : sideIds)
        {
          const double d = glm::length(x[j] - m);
          if (d < bd)
          {
            bd = d;
            loopSide[i] = sourceSide[j];
          }
        }
      }
      // The arcs between the corners, each wholly on the side most of its points vote for.
      double targetWidth = 0;
      const std::vector<bool> inFirst = SplitLoop(target.Points, loop, targetWidth);
      int vote = 0;
      for (size_t i = 0; i < loop.size(); ++i)
        vote += (inFirst[i] ? 1 : -1) * (loopSide[i] > 0 ? 1 : -1);
      const TransferSide label = TransferSide(features.SeamLabel[s]);
      std::vector<TransferSide> sides;
      for (size_t i = 0; i < loop.size(); ++i)
        sides.push_back(TransferSide((inFirst[i] == (vote >= 0)) ? label : -label));
      LabelSides(target.Points, tOffsets, tNeighbours, loop, sides, 0.3 * width, width, targetSide);
    }
    result.TargetSide = targetSide;
    std::vector<double> sideWidth(3, 0.0);
    for (size_t s = 0; s < features.Seams.size(); ++s)
      sideWidth[size_t(features.SeamLabel[s] - 1)] = align.Scale * features.Seams[s].Width;

    // Closest points, each side only onto its own side (and facing alike when possible).
    const TransferSurface registered{ x, tris };
    const TriangleGrid grid(registered);
    const std::vector<glm::dvec3> targetNormals = ComputeVertexNormals(target);
    const std::vector<glm::dvec3> regTriNormals = ComputeTriangleNormals(registered);
    const std::vector<glm::dvec3> regNormals = ComputeVertexNormals(registered);
    result.HitTriangle.assign(nt, -1);
    result.HitBarycentric.assign(nt, glm::dvec3(0.0));
    result.Confidence.assign(nt, 0.0f);
    const double searchRadius = 0.5 * eyeDistance;
    const double sigma = 0.05 * eyeDistance;
    for (size_t i = 0; i < nt; ++i)
    {
      const TransferSide side = targetSide[i];
      // A side lands on no triangle that touches the other side.
      auto sideOk = [&](uint32_t t)
      {
        if (side == 0)
          return true;
        for (int k = 0; k < 3; ++k)
          if (sourceSide[tris[3 * t + size_t(k)]] == -side)
            return false;
        return true;
      };
      const glm::dvec3 nrm = targetNormals[i];
      auto facing = [&](uint32_t t) { return glm::dot(regTriNormals[t], nrm) > 0.0; };
      SurfaceHit h = grid.Closest(target.Points[i], searchRadius, facing);
      if (h.Triangle < 0)
        h = grid.Closest(target.Points[i], searchRadius);
      if (side != 0 && h.Triangle >= 0 && !sideOk(uint32_t(h.Triangle)))
      {
        // On the other side: the closest point on its own side, unless that is clearly
        // further (then the labels are off, e.g. beyond a corner).
        SurfaceHit own = grid.Closest(
          target.Points[i], searchRadius, [&](uint32_t t) { return sideOk(t) && facing(t); });
        if (own.Triangle < 0)
          own = grid.Closest(target.Points[i], searchRadius, sideOk);
        if (own.Triangle >= 0 &&
          own.Distance <= h.Distance + 0.05 * sideWidth[size_t(std::abs(side) - 1)])
          h = own;
      }
      if (h.Triangle < 0)
        continue;
      result.HitTriangle[i] = h.Triangle;
      result.HitBarycentric[i] = h.Barycentric;
      const uint32_t* ht = &tris[3 * size_t(h.Triangle)];
      glm::dvec3 hn = h.Barycentric.x * regNormals[ht[0]] + h.Barycentric.y * regNormals[ht[1]] +
        h.Barycentric.z * regNormals[ht[2]];
      hn = glm::length(hn) > 0 ? glm::normalize(hn) : regTriNormals[size_t(h.Triangle)];
      const double agree = std::max(0.0, glm::dot(hn, nrm));
      result.Confidence[i] = float(std::exp(-(h.Distance / sigma) * (h.Distance / sigma)) * agree);
    }

    // Rigid parts: a target component landing mostly on a rigid source part moves rigidly.
    std::vector<int> tComponent;
    const int ntc = ComputeComponents(target, tComponent);
    std::vector<int> rigidSource(size_t(ntc), -1);
    result.Rigid.assign(nt, false);
    {
      std::vector<std::map<int, size_t>> votes(static_cast<size_t>(ntc));
      std::vector<size_t> sizes(size_t(ntc), 0);
      for (size_t i = 0; i < nt; ++i)
      {
        ++sizes[size_t(tComponent[i])];
        if (result.HitTriangle[i] >= 0)
          ++votes[size_t(tComponent[i])]
                 [features.Component[tris[3 * size_t(result.HitTriangle[i])]]];
      }
      for (int c = 0; c < ntc; ++c)
        for (const auto& [sc, count] : votes[size_t(c)])
          if (features.RigidComponent[size_t(sc)] && 2 * count > sizes[size_t(c)])
            rigidSource[size_t(c)] = sc;
      for (size_t i = 0; i < nt; ++i)
        result.Rigid[i] = rigidSource[size_t(tComponent[i])] >= 0;
    }
    auto finish = [&](const std::vector<std::vector<glm::dvec3>>& perSource, bool nearest)
    {
      std::vector<std::vector<float>> out;
      for (size_t k = 0; k < perSource.size(); ++k)
      {
        std::vector<glm::dvec3> d;
        if (nearest)
        {
          d.assign(nt, glm::dvec3(0.0));
          for (size_t i = 0; i < nt; ++i)
            if (result.HitTriangle[i] >= 0)
            {
              const glm::dvec3& b = result.HitBarycentric[i];
              const int k3 = b.x >= b.y && b.x >= b.z ? 0 : (b.y >= b.z ? 1 : 2);
              d[i] = perSource[k][tris[3 * size_t(result.HitTriangle[i]) + size_t(k3)]];
            }
        }
        else
        {
          d = Interpolate(perSource[k], tris, result.HitTriangle, result.HitBarycentric);
        }
        // Rigid parts: the source part's rigid motion of this target, on the target's points.
        for (int c = 0; c < ntc; ++c)
        {
          const int sc = rigidSource[size_t(c)];
          if (sc < 0)
            continue;
          std::vector<glm::dvec3> a, b;
          for (size_t i = 0; i < ns; ++i)
            if (features.Component[i] == sc)
            {
              a.push_back(aligned[i]);
              b.push_back(aligned[i] + alignedDeltas[k][i]);
            }
          const Similarity s = FitSimilarity(a, b, false);
          for (size_t i = 0; i < nt; ++i)
            if (tComponent[i] == c)
              d[i] = s.Apply(target.Points[i]) - target.Points[i];
        }
        out.push_back(ToFloats(d));
      }
      return out;
    };
    if (options.Method == TransferMethod::DeformationTransfer)
      result.Deltas = finish(dtDeltas, false);
    else
      result.Deltas = finish(alignedDeltas, options.Method == TransferMethod::NearestVertex);
    if (options.ComputeAllMethods)
    {
      result.NearestDeltas = finish(alignedDeltas, true);
      result.BarycentricDeltas = finish(alignedDeltas, false);
    }
  }
  result.ResampleSeconds = Since(t0);
  return result;
}
} // namespace morphnode
