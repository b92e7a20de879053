// SPDX-License-Identifier: BSD-3-Clause
// The transfer study (docs/transfer.md): ICT-FaceKit's 53 targets transferred onto faces
// whose right answer comes from the source itself, three methods side by side on one
// correspondence (nearest-vertex copy, barycentric copy, deformation transfer):
//
// - identity: the face onto itself;
// - subset: ict_face_dec70_sparse53.glb, a vertex subset (matched by position for the
//   truth only; the transfer does not see it);
// - remesh: the face subdivided (edge midpoints) and decimated by vertex removal
//   (vtkDecimatePro), every point on the original surface: truth by interpolation;
// - rotation, 0.9x, 1.1x: similarity copies (truth: the deltas turned and scaled);
// - landmarks +-2 mm: the remesh aligned by landmarks with uniform noise.
//
// Errors in mm and in % of each target's largest displacement, over the points the truth
// or the result moves; the lips and lids (the seams' labelled zones) apart; "swaps": points
// of the lip and lid zones whose jawOpen/eyeBlink error exceeds half that target's largest
// displacement; the animated face over a spoken track (eSpeak NG, ARKit rig) when built
// with it. Prints markdown tables.
//
//   TransferStudy [--quick] [--csv FILE]
#include "CommandLine.h"
#include "DataPaths.h"
#include "SpeechTrack.h"

#include "base/Text.h"
#include "gltf/GltfMorphMesh.h"
#include "gltf/GltfScene.h"
#include "rig/Rig.h"
#include "transfer/Transfer.h"

#include "vtkCellArray.h"
#include "vtkDecimatePro.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <random>

using namespace morphnode;

namespace
{
struct Case
{
  std::string Name;
  TransferSurface Target;
  std::vector<std::vector<glm::dvec3>> Truth; // per source target, per target point
  std::vector<TransferLandmark> Landmarks;
};

using Key = std::tuple<float, float, float>;
Key KeyOf(const glm::dvec3& p)
{
  return { float(p.x), float(p.y), float(p.z) };
}

Case Similar(const TransferSource& s, const std::string& name, double scale, const glm::dmat3& r)
{
  Case c;
  c.Name = name;
  c.Target = s.Surface;
  const glm::dvec3 t(0.01, -0.02, 0.03);
  for (auto& p : c.Target.Points)
    p = scale * (r * p) + t;
  for (const auto& d : s.Deltas)
  {
    std::vector<glm::dvec3> v(d.size());
    for (size_t i = 0; i < d.size(); ++i)
      v[i] = scale * (r * d[i]);
    c.Truth.push_back(v);
  }
  return c;
}

Case Subset(const TransferSource& s, const TransferSurface& small)
{
  std::map<Key, size_t> index;
  for (size_t i = 0; i < s.Surface.Points.size(); ++i)
    index[KeyOf(s.Surface.Points[i])] = i;
  Case c;
  c.Name = "subset";
  c.Target = small;
  c.Truth.assign(s.Deltas.size(), std::vector<glm::dvec3>(small.Points.size()));
  for (size_t i = 0; i < small.Points.size(); ++i)
  {
    const auto it = index.find(KeyOf(small.Points[i]));
    if (it == index.end())
      throw InputError("subset: a point of the decimated face is not one of the full face's");
    for (size_t k = 0; k < s.Deltas.size(); ++k)
      c.Truth[k][i] = s.Deltas[k][it->second];
  }
  return c;
}

/// Subdivided (edge midpoints) then decimated by vertex removal: every point stays where the
/// subdivision put it, on the original surface.
Case Remesh(const TransferSource& s, double reduction)
{
  const auto& src = s.Surface;
  std::vector<glm::dvec3> pts = src.Points;
  std::vector<std::pair<uint32_t, uint32_t>> parents(pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    parents[i] = { uint32_t(i), uint32_t(i) };
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
  auto midpoint = [&](uint32_t a, uint32_t b)
  {
    const auto key = std::minmax(a, b);
    const auto it = mid.find(key);
    if (it != mid.end())
      return it->second;
    pts.push_back(0.5 * (pts[a] + pts[b]));
    parents.emplace_back(a, b);
    return mid[key] = uint32_t(pts.size() - 1);
  };
  vtkNew<vtkCellArray> polys;
  for (size_t t = 0; t < src.GetNumberOfTriangles(); ++t)
  {
    const uint32_t a = src.Triangles[3 * t], b = src.Triangles[3 * t + 1],
                   c = src.Triangles[3 * t + 2];
    const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    const vtkIdType tris[4][3] = { { a, ab, ca }, { ab, b, bc }, { ca, bc, c }, { ab, bc, ca } };
    for (const auto& tri : tris)
      polys->InsertNextCell(3, tri);
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (const auto& p : pts)
    points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkPolyData> fine;
  fine->SetPoints(points);
  fine->SetPolys(polys);
  vtkNew<vtkDecimatePro> decimate;
  decimate->SetInputData(fine);
  decimate->SetTargetReduction(reduction);
  decimate->PreserveTopologyOn();
  decimate->SplittingOff();
  decimate->BoundaryVertexDeletionOff();
  decimate->Update();
  vtkPolyData* out = decimate->GetOutput();
  std::map<Key, size_t> index;
  for (size_t i = 0; i < pts.size(); ++i)
  {
    double p[3];
    points->GetPoint(vtkIdType(i), p);
    index[KeyOf({ p[0], p[1], p[2] })] = i;
  }
  Case c;
  c.Name = "remesh";
  c.Truth.assign(s.Deltas.size(), std::vector<glm::dvec3>(size_t(out->GetNumberOfPoints())));
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    c.Target.Points.emplace_back(p[0], p[1], p[2]);
    const auto it = index.find(KeyOf({ p[0], p[1], p[2] }));
    if (it == index.end())
      throw InputError("remesh: the decimation moved a point");
    const auto [a, b] = parents[it->second];
    for (size_t k = 0; k < s.Deltas.size(); ++k)
      c.Truth[k][size_t(i)] = 0.5 * (s.Deltas[k][a] + s.Deltas[k][b]);
  }
  vtkIdType npts = 0;
  const vtkIdType* ids = nullptr;
  for (out->GetPolys()->InitTraversal(); out->GetPolys()->GetNextCell(npts, ids);)
    if (npts == 3)
      for (int k = 0; k < 3; ++k)
        c.Target.Triangles.push_back(uint32_t(ids[k]));
  return c;
}

struct Stats
{
  double Mean = 0, P95 = 0, Max = 0;
};

Stats Measure(std::vector<double> v)
{
  Stats s;
  if (v.empty())
    return s;
  std::sort(v.begin(), v.end());
  for (double x : v)
    s.Mean += x;
  s.Mean /= double(v.size());
  s.P95 = v[size_t(0.95 * double(v.size() - 1))];
  s.Max = v.back();
  return s;
}

glm::dvec3 At(const std::vector<float>& d, size_t i)
{
  return { d[3 * i], d[3 * i + 1], d[3 * i + 2] };
}

struct Row
{
  std::string Case, Method;
  Stats All, Percent, Lips, Lids, Track;
  size_t Swaps = 0;
  std::vector<Stats> PerTarget, PerTargetPercent;
};

Row Evaluate(const Case& c, const TransferResult& r, const std::vector<std::vector<float>>& deltas,
  const std::string& method, const std::vector<std::string>& names, const WeightTrack* track)
{
  Row row;
  row.Case = c.Name;
  row.Method = method;
  std::vector<double> all, percent, lips, lids;
  const size_t n = c.Target.Points.size();
  for (size_t k = 0; k < c.Truth.size(); ++k)
  {
    double largest = 0;
    for (const auto& v : c.Truth[k])
      largest = std::max(largest, glm::length(v));
    std::vector<double> e, ep;
    const bool seamTarget =
      names[k] == "jawOpen" || names[k] == "eyeBlink_L" || names[k] == "eyeBlink_R";
    for (size_t i = 0; i < n; ++i)
    {
      const glm::dvec3 got = At(deltas[k], i);
      if (glm::length(c.Truth[k][i]) <= 0.01 * largest && glm::length(got) <= 0.01 * largest)
        continue;
      const double err = 1000.0 * glm::length(got - c.Truth[k][i]);
      e.push_back(err);
      ep.push_back(largest > 0 ? 100.0 * err / (1000.0 * largest) : 0.0);
      if (std::abs(r.TargetSide[i]) == 1)
        lips.push_back(err);
      else if (r.TargetSide[i] != 0)
        lids.push_back(err);
      if (seamTarget && r.TargetSide[i] != 0 && err > 0.5 * 1000.0 * largest)
        ++row.Swaps;
    }
    row.PerTarget.push_back(Measure(e));
    row.PerTargetPercent.push_back(Measure(ep));
    all.insert(all.end(), e.begin(), e.end());
    percent.insert(percent.end(), ep.begin(), ep.end());
  }
  row.All = Measure(all);
  row.Percent = Measure(percent);
  row.Lips = Measure(lips);
  row.Lids = Measure(lids);
  if (track)
  {
    // The animated face: per frame, the error of every point the truth or result moves.
    std::vector<int> channel(names.size(), -1);
    for (size_t k = 0; k < names.size(); ++k)
      channel[k] = track->FindChannel(names[k]);
    std::vector<double> e;
    for (size_t f = 0; f < track->GetNumberOfFrames(); f += 3)
    {
      for (size_t i = 0; i < n; i += 2)
      {
        glm::dvec3 diff(0.0), truth(0.0);
        for (size_t k = 0; k < names.size(); ++k)
        {
          if (channel[k] < 0)
            continue;
          const double w = track->GetValue(f, size_t(channel[k]));
          if (w == 0)
            continue;
          diff += w * (At(deltas[k], i) - c.Truth[k][i]);
          truth += w * c.Truth[k][i];
        }
        if (glm::length(truth) > 1e-4 || glm::length(diff) > 1e-4)
          e.push_back(1000.0 * glm::length(diff));
      }
    }
    row.Track = Measure(e);
  }
  return row;
}

std::string F(double v)
{
  char b[32];
  std::snprintf(b, sizeof b, v < 10 ? "%.3f" : "%.1f", v);
  return b;
}
} // namespace

int main(int argc, char** argv)
{
  CLI::App app{ "TransferStudy: the transfer's error against ground truth from the source itself "
                "(docs/transfer.md)." };
  bool quick = false;
  std::string csvFile;
  app.add_flag("--quick", quick,
    "the identity and subset cases only, without the spoken track (the smoke test)");
  app.add_option("--csv", csvFile, "per target and case: the errors as CSV");
  appkit::ParseCommandLine(app, argc, argv);
  try
  {
    const std::string full = appkit::FaceKitPath("ict_face11248_sparse53.glb");
    const std::string dec = appkit::FaceKitPath("ict_face_dec70_sparse53.glb");
    const GltfScene a = LoadGltfScene(full);
    const TransferSource source = MakeTransferSource(GltfPartToMorphMesh(a.Parts.at(0)));
    const TransferSource small =
      MakeTransferSource(GltfPartToMorphMesh(LoadGltfScene(dec).Parts.at(0)));

    std::unique_ptr<WeightTrack> track;
    if (!quick && SpeechSynthesizer::IsAvailable())
    {
      study::SpeechTrackOptions so;
      so.Text = text::ReadFile(appkit::DataPath("scripts/greeting.txt"), "text");
      Rig rig = Rig::LoadFile(appkit::DataPath("rigs/arkit.json"));
      rig.Bind(source.TargetNames);
      track = std::make_unique<WeightTrack>(
        study::ExpandThroughRig(study::MakeBehaviorTrack(so), rig, source.TargetNames));
      std::printf(
        "spoken track: %zu frames at %g fps (Data/scripts/greeting.txt through the ARKit rig)\n\n",
        track->GetNumberOfFrames(), track->GetFrameRate());
    }

    std::vector<Case> cases;
    cases.push_back(Similar(source, "identity", 1.0, glm::dmat3(1.0)));
    cases.push_back(Subset(source, small.Surface));
    if (!quick)
    {
      cases.push_back(Remesh(source, 0.75));
      const glm::dmat3 rot(glm::rotate(
        glm::dmat4(1.0), glm::radians(30.0), glm::normalize(glm::dvec3(0.2, 1.0, 0.1))));
      cases.push_back(Similar(source, "rotation 30 deg", 1.0, rot));
      cases.push_back(Similar(source, "scale 0.9", 0.9, glm::dmat3(1.0)));
      cases.push_back(Similar(source, "scale 1.1", 1.1, glm::dmat3(1.0)));
      Case noisy = Remesh(source, 0.75);
      noisy.Name = "landmarks +-2 mm";
      TransferOptions probe;
      probe.Stiffness.clear();
      const TransferResult p = TransferTargets(source, source.Surface, probe);
      std::mt19937 random(2004);
      std::uniform_real_distribution<double> noise(-0.002, 0.002);
      for (const auto& l : p.SourceLandmarks)
        noisy.Landmarks.push_back(
          { l.Name, l.Position + glm::dvec3(noise(random), noise(random), noise(random)) });
      cases.push_back(noisy);
    }

    std::vector<Row> rows;
    std::printf("| case | points | alignment | residual p95 (mm) | wall s | CPU s "
                "|\n|---|---|---|---|---|---|\n");
    for (const auto& c : cases)
    {
      TransferOptions options;
      options.ComputeAllMethods = true;
      options.TargetLandmarks = c.Landmarks;
      const auto wall = std::chrono::steady_clock::now();
      const std::clock_t cpu = std::clock();
      const TransferResult r = TransferTargets(source, c.Target, options);
      const double cpuSeconds = double(std::clock() - cpu) / CLOCKS_PER_SEC;
      const double wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
      std::printf("| %s | %zu | %s | %s | %.2f (align %.2f, register %.2f, transfer %.2f, resample "
                  "%.2f) | %.2f |\n",
        c.Name.c_str(), c.Target.Points.size(), c.Landmarks.empty() ? "automatic" : "landmarks",
        F(1000 * r.ResidualP95).c_str(), wallSeconds, r.AlignSeconds, r.RegisterSeconds,
        r.TransferSeconds, r.ResampleSeconds, cpuSeconds);
      std::fflush(stdout);
      rows.push_back(
        Evaluate(c, r, r.NearestDeltas, "nearest vertex", source.TargetNames, track.get()));
      rows.push_back(
        Evaluate(c, r, r.BarycentricDeltas, "barycentric", source.TargetNames, track.get()));
      rows.push_back(
        Evaluate(c, r, r.Deltas, "deformation transfer", source.TargetNames, track.get()));
    }
    std::printf("\n| case | method | mean mm | p95 mm | max mm | p95 %% | lips p95 mm | lids p95 "
                "mm | swaps | track p95 mm | track max mm |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& row : rows)
      std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %zu | %s | %s |\n", row.Case.c_str(),
        row.Method.c_str(), F(row.All.Mean).c_str(), F(row.All.P95).c_str(), F(row.All.Max).c_str(),
        F(row.Percent.P95).c_str(), F(row.Lips.P95).c_str(), F(row.Lids.P95).c_str(), row.Swaps,
        track ? F(row.Track.P95).c_str() : "n/a", track ? F(row.Track.Max).c_str() : "n/a");
    if (!csvFile.empty())
    {
      std::ofstream csv(csvFile);
      csv << "case,method,target,mean_mm,p95_mm,max_mm,p95_percent\n";
      for (const auto& row : rows)
        for (size_t k = 0; k < row.PerTarget.size(); ++k)
          csv << row.Case << "," << row.Method << "," << source.TargetNames[k] << ","
              << row.PerTarget[k].Mean << "," << row.PerTarget[k].P95 << "," << row.PerTarget[k].Max
              << "," << row.PerTargetPercent[k].P95 << "\n";
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "TransferStudy: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
