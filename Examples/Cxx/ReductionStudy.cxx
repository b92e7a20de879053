// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: scalable avatars. Reduces a face with morph targets to several triangle
// budgets three ways (animation-aware, plain OpenMesh quadric decimation, VTK's
// vtkQuadricDecimation with targets transferred by nearest original vertex), animates every
// result over a weight track and measures its error against the full-resolution animated
// face. Then runs the frame-budget controller over a chain of reduced levels at three
// budgets.
//
//   ReductionStudy [--face face.glb] [--track relative_weights.csv] [--out DIR]
//                  [--budgets 0.5,0.25,0.1] [--weight 1] [--stride 2] [--seconds 20]
//
// Without --track, a speech-like track is generated (see MakeSpeechTrack) and written to
// DIR/speech_track.csv. Writes DIR/reduction.md (tables), DIR/reduction_errors.csv,
// DIR/reduction_error_vs_budget.png, DIR/reduction_error_over_time.png and
// DIR/controller.csv.
#include "ExampleUtilities.h"

#include "vtkAnimationAwareDecimation.h"
#include "vtkMorphTargetReader.h"

#include "morph/Distances.h"
#include "base/Error.h"
#include "morph/MorphAttribute.h"
#include "morph/OptimizerQuality.h"
#include "track/WeightTrack.h"
#include "reduction/AnimationAwareReduction.h"
#include "budget/FrameBudgetController.h"

#include "vtkAxis.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticPointLocator.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"

#include <algorithm>
#include <array>
#include <memory>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

namespace
{
using morphnode_examples::WritePng;
using morphnode_examples::ParseList;

/// The face in flat arrays, as the study measures it.
struct ReductionMesh
{
  std::vector<float> Positions;    ///< neutral, NumberOfPoints * 3
  std::vector<uint32_t> Triangles; ///< NumberOfTriangles * 3 point ids
  /// Position deltas, one array of NumberOfPoints * 3 per target (neutral excluded).
  std::vector<std::vector<float>> PositionDeltas;

  size_t GetNumberOfPoints() const { return this->Positions.size() / 3; }
  size_t GetNumberOfTriangles() const { return this->Triangles.size() / 3; }
  size_t GetNumberOfTargets() const { return this->PositionDeltas.size(); }
};

morphnode::MorphMesh ToMorphMesh(const ReductionMesh& flat)
{
  morphnode::MorphMesh mesh(flat.GetNumberOfPoints());
  mesh.SetTargetNames(morphnode::DefaultTargetNames(flat.GetNumberOfTargets() + 1));
  auto& positions = mesh.AddAttribute<float>("Position", morphnode::AttributeRole::Position, 3);
  positions.SetNeutral(flat.Positions.data());
  for (const auto& d : flat.PositionDeltas)
  {
    positions.AddRelativeTarget(d.data(), morphnode::MorphMesh::DefaultSparseCoverage);
  }
  mesh.SetTriangles(flat.Triangles);
  return mesh;
}

ReductionMesh FromMorphMesh(const morphnode::MorphMesh& mesh)
{
  const auto& positions = std::get<morphnode::MorphAttribute<float>>(mesh.GetAttribute(0));
  ReductionMesh flat{ positions.GetNeutral(), mesh.GetTriangles(), {} };
  for (size_t k = 1; k < positions.GetNumberOfTargets(); ++k)
  {
    flat.PositionDeltas.emplace_back(flat.Positions.size());
    positions.GetTarget(k).ToDense(flat.PositionDeltas.back().data());
  }
  return flat;
}

struct Face
{
  ReductionMesh Mesh;
  std::vector<std::string> Names; // neutral first
};

Face LoadFace(const std::string& path)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  if (poly->GetNumberOfPoints() == 0)
  {
    throw morphnode::InputError("could not read a face from '" + path + "'");
  }
  Face face;
  for (int i = 0; i < reader->GetNumberOfTargets(); ++i)
  {
    face.Names.emplace_back(reader->GetTargetName(i));
  }
  const vtkIdType np = poly->GetNumberOfPoints();
  for (vtkIdType p = 0; p < np; ++p)
  {
    double x[3];
    poly->GetPoint(p, x);
    face.Mesh.Positions.insert(face.Mesh.Positions.end(), { float(x[0]), float(x[1]), float(x[2]) });
  }
  auto it = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType c = 0; c < n; ++c)
    {
      face.Mesh.Triangles.push_back(static_cast<uint32_t>(ids[c]));
    }
  }
  for (size_t k = 0; k + 1 < face.Names.size(); ++k)
  {
    vtkDataArray* d = poly->GetPointData()->GetArray(("target" + std::to_string(k) + "_position").c_str());
    std::vector<float> deltas(3 * np);
    for (vtkIdType p = 0; p < np; ++p)
    {
      double v[3];
      d->GetTuple(p, v);
      for (int c = 0; c < 3; ++c)
      {
        deltas[3 * p + c] = static_cast<float>(v[c]);
      }
    }
    face.Mesh.PositionDeltas.push_back(std::move(deltas));
  }
  return face;
}

// --- the weight track ------------------------------------------------------------------

/// A plausible 30 fps speech track over ARKit-named targets (relative weights), made
/// without any recorded data: visemes (Meta/Oculus set, as ARKit blends) every 70-170 ms
/// with pauses, blended by Cohen-Massaro-style dominance functions (coarticulation);
/// blinks (Poisson, ~17/min, 100 ms closing, 150 ms opening); brow raises every few
/// seconds; small gaze shifts; a slow smile. Deterministic (seed).
morphnode::WeightTrack MakeSpeechTrack(const std::vector<std::string>& names, double seconds, unsigned seed)
{
  const double fps = 30.0;
  using Shape = std::map<std::string, double>;
  const std::vector<Shape> visemes = {
    { { "mouthClose", 0.5 }, { "mouthPress_L", 0.4 }, { "mouthPress_R", 0.4 }, { "jawOpen", 0.05 } }, // PP
    { { "mouthRollLower", 0.5 }, { "mouthUpperUp_L", 0.25 }, { "mouthUpperUp_R", 0.25 }, { "jawOpen", 0.1 } }, // FF
    { { "jawOpen", 0.2 }, { "mouthShrugUpper", 0.2 }, { "mouthStretch_L", 0.15 }, { "mouthStretch_R", 0.15 } }, // TH/DD/nn
    { { "jawOpen", 0.25 }, { "mouthShrugLower", 0.2 } }, // kk
    { { "mouthFunnel", 0.45 }, { "mouthPucker", 0.25 }, { "jawOpen", 0.15 } }, // CH
    { { "jawOpen", 0.1 }, { "mouthStretch_L", 0.3 }, { "mouthStretch_R", 0.3 }, { "mouthClose", 0.1 } }, // SS
    { { "jawOpen", 0.6 }, { "mouthLowerDown_L", 0.35 }, { "mouthLowerDown_R", 0.35 } }, // aa
    { { "jawOpen", 0.3 }, { "mouthStretch_L", 0.35 }, { "mouthStretch_R", 0.35 }, { "mouthSmile_L", 0.2 },
      { "mouthSmile_R", 0.2 } }, // E
    { { "jawOpen", 0.2 }, { "mouthStretch_L", 0.3 }, { "mouthStretch_R", 0.3 } }, // ih
    { { "jawOpen", 0.4 }, { "mouthFunnel", 0.55 } }, // oh
    { { "mouthPucker", 0.7 }, { "mouthFunnel", 0.3 }, { "jawOpen", 0.15 } }, // ou
  };
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // Viseme keys: centre time and shape; pauses are keys with no shape.
  struct Key
  {
    double Time;
    int Viseme; // -1 = silence
  };
  std::vector<Key> keys;
  double t = 0.3;
  double nextPause = 1.5 + 1.5 * uniform(rng);
  while (t < seconds - 0.3)
  {
    if (t > nextPause)
    {
      keys.push_back({ t + 0.2, -1 });
      t += 0.35 + 0.3 * uniform(rng);
      nextPause = t + 1.5 + 1.5 * uniform(rng);
      continue;
    }
    keys.push_back({ t, static_cast<int>(uniform(rng) * visemes.size()) % int(visemes.size()) });
    t += 0.07 + 0.1 * uniform(rng);
  }
  // Blinks, brow raises, gaze shifts.
  std::vector<double> blinks, brows;
  for (double b = 1.0 + 3.0 * uniform(rng); b < seconds; b += 1.0 + 5.0 * uniform(rng))
  {
    blinks.push_back(b);
  }
  for (double b = 2.0 + 2.0 * uniform(rng); b < seconds; b += 3.0 + 4.0 * uniform(rng))
  {
    brows.push_back(b);
  }
  struct Gaze
  {
    double Time, X, Y;
  };
  std::vector<Gaze> gaze = { { 0.0, 0.0, 0.0 } };
  for (double g = 0.8; g < seconds; g += 0.5 + 2.0 * uniform(rng))
  {
    gaze.push_back({ g, 0.5 * (uniform(rng) - 0.5), 0.4 * (uniform(rng) - 0.5) });
  }

  std::vector<std::string> channels(names.begin() + 1, names.end());
  morphnode::WeightTrack track(channels, fps);
  auto channel = [&](const std::string& n) { return track.FindChannel(n); };
  const size_t frames = static_cast<size_t>(seconds * fps);
  for (size_t f = 0; f < frames; ++f)
  {
    const double time = f / fps;
    std::vector<double> w(channels.size(), 0.0);
    // Coarticulation: dominance exp(-theta |t - c|) per key; bilabial closure dominates
    // more strongly so the lips do close.
    double total = 0.0;
    std::vector<double> shape(channels.size(), 0.0);
    for (const Key& k : keys)
    {
      const double dt = std::abs(time - k.Time);
      if (dt > 0.5)
      {
        continue;
      }
      const double dominance = (k.Viseme == 0 ? 2.0 : 1.0) * std::exp(-dt / 0.05);
      total += dominance;
      if (k.Viseme >= 0)
      {
        for (const auto& [name, value] : visemes[k.Viseme])
        {
          const int c = channel(name);
          if (c >= 0)
          {
            shape[c] += dominance * value;
          }
        }
      }
    }
    if (total > 1e-6)
    {
      // Fade out far from any key (long pauses).
      const double presence = std::min(1.0, total);
      for (size_t c = 0; c < w.size(); ++c)
      {
        w[c] = presence * shape[c] / total;
      }
    }
    auto add = [&](const std::string& n, double v) {
      const int c = channel(n);
      if (c >= 0)
      {
        w[c] = std::clamp(w[c] + v, 0.0, 1.0);
      }
    };
    for (double b : blinks)
    {
      const double dt = time - b;
      double lid = 0.0;
      if (dt >= 0.0 && dt < 0.1)
      {
        lid = dt / 0.1;
      }
      else if (dt >= 0.1 && dt < 0.15)
      {
        lid = 1.0;
      }
      else if (dt >= 0.15 && dt < 0.3)
      {
        lid = 1.0 - (dt - 0.15) / 0.15;
      }
      add("eyeBlink_L", lid);
      add("eyeBlink_R", lid);
    }
    for (double b : brows)
    {
      const double dt = time - b;
      if (dt >= 0.0 && dt < 0.8)
      {
        const double v = 0.5 * std::sin(M_PI * dt / 0.8);
        add("browInnerUp_L", v);
        add("browInnerUp_R", v);
        add("browOuterUp_L", 0.6 * v);
        add("browOuterUp_R", 0.6 * v);
      }
    }
    const Gaze* g = &gaze.front();
    for (const Gaze& candidate : gaze)
    {
      if (candidate.Time <= time)
      {
        g = &candidate;
      }
    }
    add(g->X > 0 ? "eyeLookOut_L" : "eyeLookIn_L", std::abs(g->X));
    add(g->X > 0 ? "eyeLookIn_R" : "eyeLookOut_R", std::abs(g->X));
    add(g->Y > 0 ? "eyeLookUp_L" : "eyeLookDown_L", std::abs(g->Y));
    add(g->Y > 0 ? "eyeLookUp_R" : "eyeLookDown_R", std::abs(g->Y));
    const double smile = 0.25 * (1.0 + std::sin(2.0 * M_PI * time / 9.0)) * 0.5;
    add("mouthSmile_L", smile);
    add("mouthSmile_R", smile);
    add("cheekSquint_L", 0.5 * smile);
    add("cheekSquint_R", 0.5 * smile);
    track.AppendFrame(w);
  }
  return track;
}

// --- reductions ------------------------------------------------------------------------

struct Reduced
{
  ReductionMesh Mesh;
  /// Reduced point -> nearest original point (exact origin for the halfedge collapses).
  std::vector<uint32_t> Source;
  bool ExactPoints = true;
};

double MotionWeight = 1.0;
double BoundaryWeight = 1.0;
bool PoseQuadrics = true;

Reduced ReduceOpenMesh(const ReductionMesh& mesh, size_t triangles, double weight)
{
  morphnode::ReductionSettings s;
  s.MotionWeight = MotionWeight;
  s.BoundaryWeight = BoundaryWeight;
  s.PoseQuadrics = PoseQuadrics;
  s.TargetTriangles = triangles;
  s.AnimationWeight = weight;
  auto r = morphnode::ReduceAnimationAware(ToMorphMesh(mesh), s);
  return { FromMorphMesh(r.Mesh), std::move(r.OriginalPointIds), true };
}

vtkSmartPointer<vtkPolyData> ToPolyData(const float* positions, size_t np, const std::vector<uint32_t>& tris)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(static_cast<vtkIdType>(np));
  std::copy_n(positions, 3 * np, static_cast<float*>(points->GetVoidPointer(0)));
  poly->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  for (size_t t = 0; t + 2 < tris.size(); t += 3)
  {
    const vtkIdType ids[3] = { tris[t], tris[t + 1], tris[t + 2] };
    polys->InsertNextCell(3, ids);
  }
  poly->SetPolys(polys);
  return poly;
}

/// VTK's quadric decimation of the neutral; targets by the nearest original vertex.
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
    r.Mesh.PositionDeltas.push_back(morphnode::GatherPoints(d, 3, mesh.GetNumberOfPoints(), r.Source));
  }
  return r;
}

// --- errors ------------------------------------------------------------------------------

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

/// Where every full-resolution point sits on a reduced mesh in the neutral: a triangle and
/// barycentric weights (the closest point). Animating the reduced mesh carries that point
/// along; its distance from the full-resolution point is the correspondence error, which,
/// unlike the surface distance, also sees motion along the surface.
struct Correspondence
{
  std::vector<std::array<uint32_t, 3>> Corners;
  std::vector<std::array<float, 3>> Weights;
};

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

struct Errors
{
  std::string Method;
  double Budget = 0.0;
  size_t Triangles = 0, Points = 0;
  double StaticRms = 0, StaticMax = 0;
  double AnimRms = 0, AnimMax = 0, AnimRegionRms = 0;
  double CorrRms = 0, CorrMax = 0, CorrRegionRms = 0;
  double KeptRms = 0;
  double MotionRms = 0, MotionMax = 0, MotionRegionRms = 0, MotionP95 = 0, MotionP99 = 0;
  std::vector<double> PerFrameMotionRms; // 95th percentile over points, per frame
  std::vector<double> PerFrameAnimRms;
  std::vector<double> PerFrameCorrRms;
};

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

Errors Measure(const std::string& method, double budget, const ReductionMesh& full, const Reduced& r,
  const morphnode::WeightTrack& track, size_t stride, const std::vector<bool>& animatedRegion)
{
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
      const double d2 = (q[0] - a[3 * p]) * (q[0] - a[3 * p]) + (q[1] - a[3 * p + 1]) * (q[1] - a[3 * p + 1]) +
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
  return e;
}

// --- plots -------------------------------------------------------------------------------

const unsigned char Colors[3][3] = { { 214, 39, 40 }, { 31, 119, 180 }, { 127, 127, 127 } };

void PlotVersusBudget(const std::vector<Errors>& all, const std::vector<std::string>& methods,
  const std::vector<double>& budgets, const std::string& file)
{
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(900, 560);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  chart->SetTitle("ICT face over a speech track: error against the full-resolution animation");
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("error (mm)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("triangles kept (% of 22,288)");
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  std::vector<vtkSmartPointer<vtkTable>> tables;
  for (size_t m = 0; m < methods.size(); ++m)
  {
    auto table = vtkSmartPointer<vtkTable>::New();
    const char* columns[] = { "kept", "motion error p95", "motion error p99", "static RMS" };
    for (const char* c : columns)
    {
      vtkNew<vtkFloatArray> col;
      col->SetName((methods[m] + ", " + c).c_str());
      table->AddColumn(col);
    }
    table->SetNumberOfRows(static_cast<vtkIdType>(budgets.size()));
    vtkIdType row = 0;
    for (double b : budgets)
    {
      for (const auto& e : all)
      {
        if (e.Method == methods[m] && e.Budget == b)
        {
          table->SetValue(row, 0, 100.0 * b);
          table->SetValue(row, 1, 1000.0 * e.MotionP95);
          table->SetValue(row, 2, 1000.0 * e.MotionP99);
          table->SetValue(row, 3, 1000.0 * e.StaticRms);
        }
      }
      ++row;
    }
    for (int c = 1; c <= 3; ++c)
    {
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(table, 0, c);
      line->SetColor(Colors[m][0], Colors[m][1], Colors[m][2], 255);
      line->SetWidth(c == 1 ? 3.0 : 2.0);
      line->GetPen()->SetLineType(c == 1 ? vtkPen::SOLID_LINE : (c == 2 ? vtkPen::DASH_LINE : vtkPen::DOT_LINE));
    }
    tables.push_back(table);
  }
  view->GetScene()->AddItem(chart);
  WritePng(view, file);
}

void PlotOverTime(const std::vector<Errors>& all, const std::vector<std::string>& methods, double budget,
  const morphnode::WeightTrack& track, size_t stride, const std::string& file)
{
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(1000, 420);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  std::ostringstream title;
  title << "Motion error per frame (95th percentile over points) at " << 100.0 * budget << " % of the triangles (jawOpen x 0.5 mm in black)";
  chart->SetTitle(title.str());
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("motion error p95 (mm)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
  chart->SetShowLegend(true);
  vtkNew<vtkTable> table;
  vtkNew<vtkFloatArray> time;
  time->SetName("time");
  table->AddColumn(time);
  for (const auto& m : methods)
  {
    vtkNew<vtkFloatArray> col;
    col->SetName(m.c_str());
    table->AddColumn(col);
  }
  vtkNew<vtkFloatArray> jaw;
  jaw->SetName("jawOpen (x 0.5 mm)");
  table->AddColumn(jaw);
  const int jawChannel = track.FindChannel("jawOpen");
  size_t rows = 0;
  for (const auto& e : all)
  {
    rows = std::max(rows, e.PerFrameCorrRms.size());
  }
  table->SetNumberOfRows(static_cast<vtkIdType>(rows));
  for (size_t r = 0; r < rows; ++r)
  {
    table->SetValue(r, 0, track.GetTime(r * stride));
    table->SetValue(r, methods.size() + 1, jawChannel >= 0 ? 0.5 * track.GetValue(r * stride, jawChannel) : 0.0);
  }
  for (size_t m = 0; m < methods.size(); ++m)
  {
    for (const auto& e : all)
    {
      if (e.Method == methods[m] && e.Budget == budget)
      {
        for (size_t r = 0; r < e.PerFrameMotionRms.size(); ++r)
        {
          table->SetValue(r, m + 1, 1000.0 * e.PerFrameMotionRms[r]);
        }
      }
    }
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, static_cast<vtkIdType>(m + 1));
    line->SetColor(Colors[m][0], Colors[m][1], Colors[m][2], 255);
    line->SetWidth(2.0);
  }
  vtkPlot* line = chart->AddPlot(vtkChart::LINE);
  line->SetInputData(table, 0, static_cast<vtkIdType>(methods.size() + 1));
  line->SetColor(0, 0, 0, 255);
  line->SetWidth(1.0);
  view->GetScene()->AddItem(chart);
  WritePng(view, file);
}

// --- the controller demo ------------------------------------------------------------------

struct Level
{
  ReductionMesh Mesh;
  std::vector<uint32_t> ToFull;      // level point -> full point
  std::vector<uint32_t> ToPrevious;  // level point -> previous level's point
  std::vector<uint32_t> Representatives; // previous level point -> this level's point
  std::unique_ptr<morphnode::MorphAttribute<float>> Attribute;
  Correspondence Corr;
  double Error = 0.0;
};

double Seconds(std::chrono::steady_clock::duration d)
{
  return std::chrono::duration<double>(d).count();
}

/// Median time of blending `weights` on one level.
double TimeBlend(const morphnode::MorphAttribute<float>& attr, const std::vector<double>& weights,
  std::vector<float>& out, int repeats)
{
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    attr.Blend(weights.data(), weights.size(), out.data(), 0, attr.GetNumberOfPoints());
    times.push_back(Seconds(std::chrono::steady_clock::now() - t0));
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  return times[times.size() / 2];
}

double CorrespondenceRms(const Correspondence& corr, const std::vector<float>& shown, const std::vector<float>& full)
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

std::string Mm(double metres, int precision = 3)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << 1000.0 * metres;
  return s.str();
}

std::string Us(double seconds)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << 1e6 * seconds;
  return s.str();
}
} // namespace

int main(int argc, char* argv[])
{
  std::string facePath = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  std::string trackPath, outDir = "reduction-study";
  std::vector<double> budgets = { 0.5, 0.25, 0.1 };
  double weight = morphnode::ReductionSettings().AnimationWeight, seconds = 20.0;
  size_t stride = 2;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        throw std::runtime_error("missing value after " + arg);
      }
      return argv[++i];
    };
    if (arg == "--face")
      facePath = next();
    else if (arg == "--track")
      trackPath = next();
    else if (arg == "--out")
      outDir = next();
    else if (arg == "--budgets")
      budgets = ParseList(next());
    else if (arg == "--weight")
      weight = std::stod(next());
    else if (arg == "--stride")
      stride = std::max(1, std::stoi(next()));
    else if (arg == "--motion")
      MotionWeight = std::stod(next());
    else if (arg == "--boundary")
      BoundaryWeight = std::stod(next());
    else if (arg == "--no-poses")
      PoseQuadrics = false;
    else if (arg == "--seconds")
      seconds = std::stod(next());
    else
    {
      std::cerr << "usage: ReductionStudy [--face F.glb] [--track T.csv] [--out DIR] [--budgets 0.5,0.25,0.1]"
                   " [--weight 1] [--stride 2] [--seconds 20]\n";
      return 2;
    }
  }
  try
  {
    std::filesystem::create_directories(outDir);
    const Face face = LoadFace(facePath);
    const ReductionMesh& full = face.Mesh;
    std::cerr << "face: " << full.GetNumberOfPoints() << " points, " << full.GetNumberOfTriangles()
              << " triangles, " << full.GetNumberOfTargets() << " targets\n";

    // Relative weights, one channel per target in the face's order.
    morphnode::WeightTrack track;
    if (!trackPath.empty())
    {
      std::ifstream in(trackPath);
      const morphnode::WeightTrack given = morphnode::WeightTrack::ReadCsv(in);
      const morphnode::WeightTrack absolute = morphnode::ToAbsoluteWeights(given, face.Names);
      track = morphnode::WeightTrack(
        std::vector<std::string>(face.Names.begin() + 1, face.Names.end()), absolute.GetFrameRate());
      for (size_t f = 0; f < absolute.GetNumberOfFrames(); ++f)
      {
        track.AppendFrame(absolute.GetFrame(f) + 1);
      }
    }
    else
    {
      track = MakeSpeechTrack(face.Names, seconds, 7);
      std::ofstream out(outDir + "/speech_track.csv");
      track.WriteCsv(out);
    }
    std::cerr << "track: " << track.GetNumberOfFrames() << " frames at " << track.GetFrameRate() << " fps\n";

    // Animated region: points some target moves by more than 10 % of the largest motion.
    std::vector<double> region(full.GetNumberOfPoints(), 0.0);
    for (const auto& d : full.PositionDeltas)
    {
      for (size_t p = 0; p < region.size(); ++p)
      {
        region[p] = std::max(region[p],
          std::sqrt(double(d[3 * p]) * d[3 * p] + double(d[3 * p + 1]) * d[3 * p + 1] + double(d[3 * p + 2]) * d[3 * p + 2]));
      }
    }
    const double regionCut = 0.1 * *std::max_element(region.begin(), region.end());
    std::vector<bool> animated(region.size());
    size_t animatedCount = 0;
    for (size_t p = 0; p < region.size(); ++p)
    {
      animated[p] = region[p] > regionCut;
      animatedCount += animated[p] ? 1 : 0;
    }

    const std::vector<std::string> methods = { "animation-aware (ours)", "OpenMesh quadric",
      "vtkQuadricDecimation + nearest" };
    std::vector<Errors> all;
    std::map<double, size_t> keptAnimated[3];
    for (double b : budgets)
    {
      const size_t triangles = static_cast<size_t>(std::round(b * full.GetNumberOfTriangles()));
      Reduced reduced[3] = { ReduceOpenMesh(full, triangles, weight), ReduceOpenMesh(full, triangles, 0.0),
        ReduceVTK(full, triangles) };
      for (int m = 0; m < 3; ++m)
      {
        const auto t0 = std::chrono::steady_clock::now();
        all.push_back(Measure(methods[m], b, full, reduced[m], track, stride, animated));
        size_t kept = 0;
        for (uint32_t s : reduced[m].Source)
        {
          kept += animated[s] ? 1 : 0;
        }
        keptAnimated[m][b] = kept;
        std::cerr << methods[m] << " at " << b << ": corr " << Mm(all.back().CorrRms) << " mm, anim "
                  << Mm(all.back().AnimRms) << " mm, motion " << Mm(all.back().MotionRms) << " / region "
                  << Mm(all.back().MotionRegionRms) << " / max " << Mm(all.back().MotionMax) << " / p95 " << Mm(all.back().MotionP95) << " / p99 "
                  << Mm(all.back().MotionP99) << " mm, static " << Mm(all.back().StaticRms) << " mm ("
                  << Seconds(std::chrono::steady_clock::now() - t0) << " s)\n";
      }
    }

    // Tables.
    std::ofstream md(outDir + "/reduction.md");
    md << "Face: " << full.GetNumberOfPoints() << " points, " << full.GetNumberOfTriangles() << " triangles, "
       << full.GetNumberOfTargets() << " targets. Track: " << track.GetNumberOfFrames() << " frames at "
       << track.GetFrameRate() << " fps, every " << stride << ". frame measured. AnimationWeight " << weight
       << ". Animated region: " << animatedCount << " points (some target moves them > "
       << Mm(regionCut, 2) << " mm). Distances in mm.\n\n";
    md << "| triangles kept | method | triangles | points | points kept in animated region "
          "| static RMS | static max | motion error p95 | motion error p99 | motion error RMS "
          "| motion error RMS, animated region | animated surface distance RMS | animated surface distance max "
          "| correspondence RMS | kept-vertex RMS |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::ofstream csv(outDir + "/reduction_errors.csv");
    csv << "budget,method,triangles,points,kept_animated,static_rms_mm,static_max_mm,anim_rms_mm,anim_max_mm,"
           "anim_region_rms_mm,corr_rms_mm,corr_max_mm,corr_region_rms_mm,kept_rms_mm,motion_p95_mm,motion_p99_mm,"
           "motion_rms_mm,motion_region_rms_mm,motion_max_mm\n";
    for (const auto& e : all)
    {
      const int m = static_cast<int>(std::find(methods.begin(), methods.end(), e.Method) - methods.begin());
      md << "| " << 100.0 * e.Budget << " % | " << e.Method << " | " << e.Triangles << " | " << e.Points << " | "
         << keptAnimated[m][e.Budget] << " | " << Mm(e.StaticRms) << " | " << Mm(e.StaticMax) << " | "
         << Mm(e.MotionP95) << " | " << Mm(e.MotionP99) << " | " << Mm(e.MotionRms) << " | "
         << Mm(e.MotionRegionRms) << " | " << Mm(e.AnimRms) << " | " << Mm(e.AnimMax) << " | " << Mm(e.CorrRms)
         << " | " << Mm(e.KeptRms) << " |\n";
      csv << e.Budget << "," << e.Method << "," << e.Triangles << "," << e.Points << ","
          << keptAnimated[m][e.Budget] << "," << Mm(e.StaticRms, 5) << "," << Mm(e.StaticMax, 5) << ","
          << Mm(e.AnimRms, 5) << "," << Mm(e.AnimMax, 5) << "," << Mm(e.AnimRegionRms, 5) << ","
          << Mm(e.CorrRms, 5) << "," << Mm(e.CorrMax, 5) << "," << Mm(e.CorrRegionRms, 5) << ","
          << Mm(e.KeptRms, 5) << "," << Mm(e.MotionP95, 5) << "," << Mm(e.MotionP99, 5) << ","
          << Mm(e.MotionRms, 5) << "," << Mm(e.MotionRegionRms, 5) << "," << Mm(e.MotionMax, 5) << "\n";
    }
    PlotVersusBudget(all, methods, budgets, outDir + "/reduction_error_vs_budget.png");
    PlotOverTime(all, methods, *std::min_element(budgets.begin(), budgets.end()), track, stride,
      outDir + "/reduction_error_over_time.png");

    // --- the frame-budget controller over a chain of levels ---------------------------------
    std::vector<Level> levels(1);
    levels[0].Mesh = full;
    levels[0].ToFull.resize(full.GetNumberOfPoints());
    std::iota(levels[0].ToFull.begin(), levels[0].ToFull.end(), 0u);
    std::vector<double> sorted = budgets;
    std::sort(sorted.rbegin(), sorted.rend());
    for (double b : sorted)
    {
      const Level& prev = levels.back();
      morphnode::ReductionSettings s;
      s.TargetTriangles = static_cast<size_t>(std::round(b * full.GetNumberOfTriangles()));
      s.AnimationWeight = weight;
      auto r = morphnode::ReduceAnimationAware(ToMorphMesh(prev.Mesh), s);
      Level next;
      next.Mesh = FromMorphMesh(r.Mesh);
      next.ToPrevious = r.OriginalPointIds;
      next.Representatives = r.Representatives;
      for (uint32_t id : r.OriginalPointIds)
      {
        next.ToFull.push_back(prev.ToFull[id]);
      }
      levels.push_back(std::move(next));
    }
    // Level point sets in the full face's ids, for the correspondence error.
    std::vector<morphnode::LevelOfDetail> lods;
    std::mt19937 rng(3);
    std::ofstream cal(outDir + "/controller_calibration.csv");
    cal << "level,active_targets,target_points,seconds\n";
    for (size_t l = 0; l < levels.size(); ++l)
    {
      Level& level = levels[l];
      const size_t np = level.Mesh.GetNumberOfPoints();
      level.Attribute = std::make_unique<morphnode::MorphAttribute<float>>(
        "positions", morphnode::AttributeRole::Position, 3, np);
      level.Attribute->SetNeutral(level.Mesh.Positions.data());
      for (const auto& d : level.Mesh.PositionDeltas)
      {
        level.Attribute->AddRelativeTarget(d.data(), 0.3);
      }
      level.Corr = Correspond(full, level.Mesh);
      morphnode::LevelOfDetail lod;
      lod.Name = l == 0 ? "full" : Mm(0.0).substr(0, 0) + std::to_string(int(std::round(100.0 * sorted[l - 1]))) + " %";
      lod.NumberOfPoints = np;
      lod.MovedPoints = morphnode::MovedPointsPerTarget(level.Mesh.PositionDeltas);
      lod.Distances = morphnode::ComputeTargetDistances(*level.Attribute);
      // Calibrate: time random active sets of several sizes.
      std::vector<double> xs, ys;
      std::vector<float> out(3 * np);
      const size_t nt = level.Mesh.GetNumberOfTargets();
      for (size_t active : { size_t(0), size_t(1), size_t(2), size_t(4), size_t(8), size_t(16), size_t(32), nt })
      {
        for (int trial = 0; trial < 3; ++trial)
        {
          std::vector<size_t> order(nt);
          std::iota(order.begin(), order.end(), size_t(1));
          std::shuffle(order.begin(), order.end(), rng);
          std::vector<double> w(nt + 1, 0.0);
          double x = 0.0;
          for (size_t i = 0; i < std::min(active, nt); ++i)
          {
            w[order[i]] = 0.5 / double(std::max<size_t>(active, 1));
            x += lod.MovedPoints[order[i]];
          }
          w[0] = 1.0 - std::accumulate(w.begin() + 1, w.end(), 0.0);
          const double t = TimeBlend(*level.Attribute, w, out, 41);
          xs.push_back(x);
          ys.push_back(t);
          cal << l << "," << active << "," << x << "," << t << "\n";
        }
      }
      lod.Cost = morphnode::CostModel::Fit(xs, ys);
      // The level's own error: RMS correspondence error over the track (unoptimized weights).
      if (l > 0)
      {
        double sum = 0.0;
        size_t n = 0;
        std::vector<float> a, b;
        for (size_t f = 0; f < track.GetNumberOfFrames(); f += stride)
        {
          Animate(full, track.GetFrame(f), a);
          Animate(level.Mesh, track.GetFrame(f), b);
          const double rms = CorrespondenceRms(level.Corr, b, a);
          sum += rms * rms;
          ++n;
        }
        level.Error = std::sqrt(sum / n);
      }
      lod.GeometricError = level.Error;
      if (l + 1 < levels.size())
      {
        // This level's point -> the next level's point it collapses into, in this level's ids.
        const Level& next = levels[l + 1];
        for (uint32_t rep : next.Representatives)
        {
          lod.RepresentativeInThisLevel.push_back(next.ToPrevious[rep]);
        }
        lod.CoarserToThis = next.ToPrevious;
      }
      lods.push_back(lod);
      std::cerr << "level " << lod.Name << ": " << np << " points, cost " << Us(lod.Cost.Fixed) << " us + "
                << lod.Cost.PerTargetPoint * 1e9 << " ns per target point, error " << Mm(level.Error) << " mm\n";
    }

    const morphnode::WeightTrack absolute = [&] {
      morphnode::WeightTrack relativeNamed(
        std::vector<std::string>(face.Names.begin() + 1, face.Names.end()), track.GetFrameRate());
      for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
      {
        relativeNamed.AppendFrame(track.GetFrame(f));
      }
      return morphnode::ToAbsoluteWeights(relativeNamed, face.Names);
    }();
    // Budgets relative to the full face's predicted cost on this track: its 95th percentile.
    std::vector<double> fullCosts;
    for (size_t f = 0; f < absolute.GetNumberOfFrames(); ++f)
    {
      double x = 0.0;
      for (size_t i = 1; i < absolute.GetNumberOfChannels(); ++i)
      {
        x += absolute.GetValue(f, i) != 0.0 ? lods[0].MovedPoints[i] : 0.0;
      }
      fullCosts.push_back(lods[0].Cost.Predict(x));
    }
    std::sort(fullCosts.begin(), fullCosts.end());
    const double p95 = fullCosts[fullCosts.size() * 95 / 100];
    const std::vector<std::pair<std::string, double>> frameBudgets = { { "generous (100 % of full p95)", p95 },
      { "medium (45 %)", 0.45 * p95 }, { "tight (18 %)", 0.18 * p95 } };

    std::ofstream ctl(outDir + "/controller.csv");
    ctl << "budget,frame,level,morph_towards,alpha,threshold,active,predicted_us,measured_us,predicted_error_mm,"
           "measured_error_mm\n";
    md << "\n## Frame-budget controller\n\nLevels (chained reductions, each from the previous one):\n\n"
       << "| level | points | cost model a | b (ns per target point) | level error (correspondence RMS, mm) |\n"
       << "|---|---|---|---|---|\n";
    for (const auto& lod : lods)
    {
      md << "| " << lod.Name << " | " << lod.NumberOfPoints << " | " << Us(lod.Cost.Fixed) << " us | "
         << std::setprecision(3) << lod.Cost.PerTargetPoint * 1e9 << " | " << Mm(lod.GeometricError) << " |\n";
    }
    md << "\nFull face, 95th percentile of the predicted per-frame cost on the track: " << Us(p95) << " us.\n\n";
    md << "| budget | us | frames per level (full/...) | switches | mean threshold | mean active targets "
          "| measured time mean / p95 (us) | frames over budget (measured) | predicted error mean (mm) "
          "| measured error mean / max (mm) |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [label, budget] : frameBudgets)
    {
      morphnode::FrameBudgetController controller;
      morphnode::ControllerSettings cs;
      cs.FrameBudget = budget;
      controller.SetSettings(cs);
      for (const auto& lod : lods)
      {
        controller.AddLevel(lod);
      }
      std::vector<size_t> perLevel(lods.size(), 0);
      std::vector<double> times;
      double thresholdSum = 0, activeSum = 0, predictedSum = 0, measuredSum = 0, measuredMax = 0;
      size_t over = 0;
      std::vector<float> shown, morphed, truth;
      for (size_t f = 0; f < absolute.GetNumberOfFrames(); ++f)
      {
        std::vector<double> w(absolute.GetFrame(f), absolute.GetFrame(f) + absolute.GetNumberOfChannels());
        const morphnode::ControllerDecision d = controller.Update(w);
        const Level& level = levels[d.Level];
        shown.resize(3 * level.Mesh.GetNumberOfPoints());
        const auto t0 = std::chrono::steady_clock::now();
        level.Attribute->Blend(d.Weights.data(), d.Weights.size(), shown.data(), 0, level.Mesh.GetNumberOfPoints());
        if (d.MorphTowards >= 0)
        {
          morphed.resize(shown.size());
          morphnode::Geomorph(shown.data(), level.Mesh.GetNumberOfPoints(),
            lods[d.Level].RepresentativeInThisLevel, d.Alpha, morphed.data());
          shown.swap(morphed);
        }
        const double t = Seconds(std::chrono::steady_clock::now() - t0);
        times.push_back(t);
        over += t > budget ? 1 : 0;
        Animate(full, track.GetFrame(f), truth);
        const double err = CorrespondenceRms(level.Corr, shown, truth);
        ++perLevel[d.Level];
        thresholdSum += d.Threshold;
        activeSum += d.ActiveTargets;
        predictedSum += d.PredictedError;
        measuredSum += err;
        measuredMax = std::max(measuredMax, err);
        ctl << std::quoted(label) << "," << f << "," << d.Level << "," << d.MorphTowards << "," << d.Alpha << ","
            << d.Threshold << "," << d.ActiveTargets << "," << Us(d.PredictedSeconds) << "," << Us(t) << ","
            << Mm(d.PredictedError, 5) << "," << Mm(err, 5) << "\n";
      }
      const double n = static_cast<double>(absolute.GetNumberOfFrames());
      std::vector<double> sortedTimes = times;
      std::sort(sortedTimes.begin(), sortedTimes.end());
      std::ostringstream levelsText;
      for (size_t l = 0; l < perLevel.size(); ++l)
      {
        levelsText << (l ? " / " : "") << perLevel[l];
      }
      md << "| " << label << " | " << Us(budget) << " | " << levelsText.str() << " | "
         << controller.GetNumberOfSwitches() << " | " << std::setprecision(3) << thresholdSum / n << " | "
         << std::setprecision(3) << activeSum / n << " | "
         << Us(std::accumulate(times.begin(), times.end(), 0.0) / n) << " / "
         << Us(sortedTimes[sortedTimes.size() * 95 / 100]) << " | " << over << " of " << times.size() << " | "
         << Mm(predictedSum / n) << " | " << Mm(measuredSum / n) << " / " << Mm(measuredMax) << " |\n";
      std::cerr << "controller " << label << ": levels " << levelsText.str() << ", switches "
                << controller.GetNumberOfSwitches() << ", over budget " << over << "\n";
    }
    std::cerr << "wrote " << outDir << "/reduction.md\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "ReductionStudy: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
