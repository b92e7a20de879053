// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: the three reductions and their errors against the full-resolution
// animated face.
#include "ReductionStudy.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkQuadricDecimation.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticPointLocator.h"

#include <algorithm>
#include <cmath>

namespace reductionstudy
{
Reduced ReduceOpenMesh(const ReductionMesh& mesh, size_t triangles, double weight,
  const morphnode::ReductionSettings& base)
{
  morphnode::ReductionSettings s = base;
  s.TargetTriangles = triangles;
  s.AnimationWeight = weight;
  auto r = morphnode::ReduceAnimationAware(ToMorphMesh(mesh), s);
  return { FromMorphMesh(r.Mesh), std::move(r.OriginalPointIds), true };
}

Reduced ReduceVTK(const ReductionMesh& mesh, size_t triangles)
{
  auto neutral = ToPolyData(mesh.Positions.data(), mesh.GetNumberOfPoints(), mesh.Triangles);
  vtkNew<vtkQuadricDecimation> decimation;
  decimation->SetInputData(neutral);
  decimation->SetTargetReduction(1.0 - double(triangles) / mesh.GetNumberOfTriangles());
  decimation->Update();
  vtkPolyData* out = decimation->GetOutput();
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(neutral);
  locator->BuildLocator();
  Reduced r;
  r.ExactPoints = false;
  const vtkIdType np = out->GetNumberOfPoints();
  for (vtkIdType p = 0; p < np; ++p)
  {
    double x[3];
    out->GetPoint(p, x);
    r.Mesh.Positions.insert(r.Mesh.Positions.end(), { float(x[0]), float(x[1]), float(x[2]) });
    r.Source.push_back(static_cast<uint32_t>(locator->FindClosestPoint(x)));
  }
  auto it = vtk::TakeSmartPointer(out->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType c = 0; c < n; ++c)
    {
      r.Mesh.Triangles.push_back(static_cast<uint32_t>(ids[c]));
    }
  }
  for (const auto& d : mesh.PositionDeltas)
  {
    r.Mesh.PositionDeltas.push_back(
      morphnode::GatherPoints(d, 3, mesh.GetNumberOfPoints(), r.Source));
  }
  return r;
}

void Animate(const ReductionMesh& mesh, const double* relative, std::vector<float>& out)
{
  out = mesh.Positions;
  for (size_t k = 0; k < mesh.PositionDeltas.size(); ++k)
  {
    const float w = static_cast<float>(relative[k]);
    if (w == 0.0f)
    {
      continue;
    }
    const auto& d = mesh.PositionDeltas[k];
    for (size_t i = 0; i < out.size(); ++i)
    {
      out[i] += w * d[i];
    }
  }
}

Correspondence Correspond(const ReductionMesh& full, const ReductionMesh& reduced)
{
  auto poly = ToPolyData(reduced.Positions.data(), reduced.GetNumberOfPoints(), reduced.Triangles);
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(poly);
  locator->BuildLocator();
  vtkNew<vtkGenericCell> cell;
  Correspondence c;
  const size_t np = full.GetNumberOfPoints();
  c.Corners.resize(np);
  c.Weights.resize(np);
  for (size_t p = 0; p < np; ++p)
  {
    double x[3] = { full.Positions[3 * p], full.Positions[3 * p + 1], full.Positions[3 * p + 2] };
    double closest[3], d2, pcoords[3], w[3];
    vtkIdType cellId;
    int sub;
    locator->FindClosestPoint(x, closest, cell, cellId, sub, d2);
    poly->GetCell(cellId, cell);
    double dist2;
    cell->EvaluatePosition(closest, nullptr, sub, pcoords, dist2, w);
    for (int i = 0; i < 3; ++i)
    {
      c.Corners[p][i] = static_cast<uint32_t>(cell->GetPointId(i));
      c.Weights[p][i] = static_cast<float>(w[i]);
    }
  }
  return c;
}

double CorrespondenceRms(
  const Correspondence& corr, const std::vector<float>& shown, const std::vector<float>& full)
{
  double sum = 0.0;
  for (size_t p = 0; p < corr.Corners.size(); ++p)
  {
    for (int c = 0; c < 3; ++c)
    {
      double q = 0.0;
      for (int i = 0; i < 3; ++i)
      {
        q += corr.Weights[p][i] * shown[3 * corr.Corners[p][i] + c];
      }
      sum += (q - full[3 * p + c]) * (q - full[3 * p + c]);
    }
  }
  return std::sqrt(sum / corr.Corners.size());
}

/// Surface distance from every full-resolution point to the reduced surface.
void SurfaceDistances(const std::vector<float>& full, const std::vector<float>& reduced,
  const std::vector<uint32_t>& tris, std::vector<double>& dist)
{
  auto poly = ToPolyData(reduced.data(), reduced.size() / 3, tris);
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(poly);
  locator->BuildLocator();
  vtkNew<vtkGenericCell> cell;
  dist.resize(full.size() / 3);
  for (size_t p = 0; p < dist.size(); ++p)
  {
    double x[3] = { full[3 * p], full[3 * p + 1], full[3 * p + 2] }, closest[3], d2;
    vtkIdType cellId;
    int sub;
    locator->FindClosestPoint(x, closest, cell, cellId, sub, d2);
    dist[p] = std::sqrt(d2);
  }
}

LipsAndLids FindLipsAndLids(const Face& face)
{
  const ReductionMesh& m = face.Mesh;
  LipsAndLids out;
  out.Lips.assign(m.GetNumberOfPoints(), false);
  out.Lids.assign(m.GetNumberOfPoints(), false);
  for (size_t k = 0; k < m.GetNumberOfTargets(); ++k)
  {
    const std::string& name = face.Names[k + 1];
    const bool lip =
      name.rfind("mouthRoll", 0) == 0 || name == "mouthFunnel" || name == "mouthPucker";
    const bool lid = name.rfind("eyeBlink", 0) == 0;
    if (!lip && !lid)
    {
      continue;
    }
    const auto& d = m.PositionDeltas[k];
    std::vector<double> norm(m.GetNumberOfPoints());
    double reach = 0.0;
    for (size_t p = 0; p < norm.size(); ++p)
    {
      norm[p] = std::sqrt(double(d[3 * p]) * d[3 * p] + double(d[3 * p + 1]) * d[3 * p + 1] +
        double(d[3 * p + 2]) * d[3 * p + 2]);
      reach = std::max(reach, norm[p]);
    }
    for (size_t p = 0; p < norm.size(); ++p)
    {
      if (norm[p] > 0.25 * reach)
      {
        (lip ? out.Lips : out.Lids)[p] = true;
      }
    }
  }
  return out;
}

Errors Measure(const std::string& method, double budget, const ReductionMesh& full,
  const Reduced& r, const morphnode::WeightTrack& track, size_t stride,
  const std::vector<bool>& animatedRegion, const LipsAndLids* regions)
{
  std::vector<float> lips, lids;
  Errors e;
  e.Method = method;
  e.Budget = budget;
  e.Triangles = r.Mesh.GetNumberOfTriangles();
  e.Points = r.Mesh.GetNumberOfPoints();
  std::vector<double> dist;
  SurfaceDistances(full.Positions, r.Mesh.Positions, r.Mesh.Triangles, dist);
  double sum = 0.0;
  for (double d : dist)
  {
    sum += d * d;
    e.StaticMax = std::max(e.StaticMax, d);
  }
  e.StaticRms = std::sqrt(sum / dist.size());

  const Correspondence corr = Correspond(full, r.Mesh);
  std::vector<float> a, b;
  double animSum = 0, regionSum = 0, corrSum = 0, corrRegionSum = 0, keptSum = 0;
  double motionSum = 0, motionRegionSum = 0;
  std::vector<float> motionAll;
  size_t animCount = 0, regionCount = 0, corrCount = 0, corrRegionCount = 0, keptCount = 0;
  for (size_t f = 0; f < track.GetNumberOfFrames(); f += stride)
  {
    Animate(full, track.GetFrame(f), a);
    Animate(r.Mesh, track.GetFrame(f), b);
    SurfaceDistances(a, b, r.Mesh.Triangles, dist);
    double frameSum = 0.0, corrFrame = 0.0, motionFrame = 0.0;
    for (size_t p = 0; p < dist.size(); ++p)
    {
      frameSum += dist[p] * dist[p];
      e.AnimMax = std::max(e.AnimMax, dist[p]);
      if (animatedRegion[p])
      {
        regionSum += dist[p] * dist[p];
        ++regionCount;
      }
      double q[3] = { 0, 0, 0 };
      for (int i = 0; i < 3; ++i)
      {
        for (int c = 0; c < 3; ++c)
        {
          q[c] += corr.Weights[p][i] * b[3 * corr.Corners[p][i] + c];
        }
      }
      const double d2 = (q[0] - a[3 * p]) * (q[0] - a[3 * p]) +
        (q[1] - a[3 * p + 1]) * (q[1] - a[3 * p + 1]) +
        (q[2] - a[3 * p + 2]) * (q[2] - a[3 * p + 2]);
      corrFrame += d2;
      e.CorrMax = std::max(e.CorrMax, std::sqrt(d2));
      // The motion alone: interpolated displacement against the point's own displacement.
      double m2 = 0.0;
      for (int c = 0; c < 3; ++c)
      {
        double moved = 0.0;
        for (int i = 0; i < 3; ++i)
        {
          const uint32_t k = corr.Corners[p][i];
          moved += corr.Weights[p][i] * (double(b[3 * k + c]) - r.Mesh.Positions[3 * k + c]);
        }
        const double diff = moved - (double(a[3 * p + c]) - full.Positions[3 * p + c]);
        m2 += diff * diff;
      }
      motionFrame += m2;
      motionAll.push_back(static_cast<float>(std::sqrt(m2)));
      if (regions && regions->Lips[p])
      {
        lips.push_back(static_cast<float>(std::sqrt(m2)));
      }
      if (regions && regions->Lids[p])
      {
        lids.push_back(static_cast<float>(std::sqrt(m2)));
      }
      e.MotionMax = std::max(e.MotionMax, std::sqrt(m2));
      if (animatedRegion[p])
      {
        motionRegionSum += m2;
      }
      if (animatedRegion[p])
      {
        corrRegionSum += d2;
        ++corrRegionCount;
      }
    }
    animSum += frameSum;
    animCount += dist.size();
    corrSum += corrFrame;
    corrCount += dist.size();
    motionSum += motionFrame;
    {
      // per-frame 95th percentile of the points' motion error
      std::vector<float> frame(motionAll.end() - static_cast<long>(dist.size()), motionAll.end());
      std::nth_element(frame.begin(), frame.begin() + frame.size() * 95 / 100, frame.end());
      e.PerFrameMotionRms.push_back(frame[frame.size() * 95 / 100]);
    }
    e.PerFrameAnimRms.push_back(std::sqrt(frameSum / dist.size()));
    e.PerFrameCorrRms.push_back(std::sqrt(corrFrame / dist.size()));
    for (size_t k = 0; k < r.Source.size(); ++k)
    {
      const uint32_t o = r.Source[k];
      for (int c = 0; c < 3; ++c)
      {
        const double d = double(b[3 * k + c]) - a[3 * o + c];
        keptSum += d * d;
      }
      ++keptCount;
    }
  }
  e.AnimRms = std::sqrt(animSum / animCount);
  e.AnimRegionRms = std::sqrt(regionSum / std::max<size_t>(regionCount, 1));
  e.CorrRms = std::sqrt(corrSum / corrCount);
  e.CorrRegionRms = std::sqrt(corrRegionSum / std::max<size_t>(corrRegionCount, 1));
  e.KeptRms = std::sqrt(keptSum / std::max<size_t>(keptCount, 1));
  e.MotionRms = std::sqrt(motionSum / corrCount);
  std::sort(motionAll.begin(), motionAll.end());
  e.MotionP95 = motionAll[motionAll.size() * 95 / 100];
  e.MotionP99 = motionAll[motionAll.size() * 99 / 100];
  e.MotionRegionRms = std::sqrt(motionRegionSum / std::max<size_t>(corrRegionCount, 1));
  auto percentile = [](std::vector<float>& v, int q)
  {
    if (v.empty())
    {
      return 0.0;
    }
    std::nth_element(v.begin(), v.begin() + v.size() * q / 100, v.end());
    return double(v[v.size() * q / 100]);
  };
  e.LipsP95 = percentile(lips, 95);
  e.LipsP99 = percentile(lips, 99);
  e.LidsP95 = percentile(lids, 95);
  e.LidsP99 = percentile(lids, 99);
  return e;
}
} // namespace reductionstudy
