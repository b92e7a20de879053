// SPDX-License-Identifier: BSD-3-Clause
// LodStudy: the scalable avatar's ladder at work (docs/lod.md).
//
// 1. Dolly-out: the talking face (a speech track) moves away from a perspective camera, from
//    filling the screen to a few dozen pixels, while morphnode::ScalableMorph chooses level
//    and targets on screen and on time, at three frame budgets, with and without geomorphs.
//    Per frame: level, geomorph, active targets, measured blend time, the largest
//    screen-space jump of any vertex caused by a change of level or geomorph step (vertex
//    view: a point the shown level lacks sits on the point it collapsed into), and the
//    pixel error against the full-resolution, unoptimized animation (every full-resolution
//    point carried on the shown surface through its closest point on the level's neutral).
// 2. Benchmark: the whole frame (morph + offscreen render) at each level and each device
//    profile against full resolution, in the same run; and the paper's Figure 3 (frame rate
//    against the optimizer's threshold) redrawn with one line per level.
//
// xvfb-run -a build/bin/LodStudy --out DIR [--face F.glb] [--seconds S] [--bench-frames N]
#include "ReductionStudy.h"

#include "CommandLine.h"
#include "DataPaths.h"
#include "ImageOutput.h"

#include "base/Error.h"
#include "budget/DeviceProfile.h"
#include "lod/MorphLadder.h"
#include "lod/ScalableMorph.h"

#include "vtkActor.h"
#include "vtkAxis.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numeric>

namespace
{
namespace appkit = morphnode::appkit;
using namespace reductionstudy;

struct StudyOptions
{
  std::string FacePath;
  std::string OutDir = "lod-study";
  std::string ImageDir;
  double Seconds = 20.0;
  double Fov = 30.0;      ///< vertical field of view, degrees
  double Height = 1080.0; ///< viewport height, pixels
  double PixelBound = 1.0;
  double TargetPixelBound = 0.5;
  double FarFactor = 60.0; ///< the dolly ends this many times farther than it starts
  int BenchFrames = 60;
  bool Bench = true;
};

double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Absolute weights (neutral first) of a track frame of relative weights.
std::vector<double> Absolute(const morphnode::WeightTrack& track, size_t f)
{
  const double* r = track.GetFrame(f);
  std::vector<double> w(track.GetNumberOfChannels() + 1);
  double sum = 0.0;
  for (size_t k = 0; k < track.GetNumberOfChannels(); ++k)
  {
    w[k + 1] = r[k];
    sum += r[k];
  }
  w[0] = 1.0 - sum;
  return w;
}

/// The shown level's state: what a point shows (vertex view).
struct Shown
{
  int Level = 0;
  int MorphTowards = -1;
  double Alpha = 0.0;
};

/// Every shared point's position in state `s` (positions of the level's prefix blended
/// with `w` and geomorphed): a point the level lacks sits on its representative.
void VertexView(const morphnode::MorphLadder& ladder, const morphnode::MorphAttribute<float>& attr,
  const std::vector<double>& w, const Shown& s, std::vector<float>& work, std::vector<float>& out)
{
  const size_t n = ladder.Levels[s.Level].NumberOfPoints;
  work.resize(3 * ladder.Mesh.GetNumberOfPoints());
  attr.Blend(w.data(), w.size(), work.data(), 0, n);
  if (s.MorphTowards >= 0)
  {
    morphnode::GeomorphLadder(ladder, static_cast<size_t>(s.Level), s.Alpha, work.data());
  }
  out.resize(work.size());
  for (size_t p = 0; p < ladder.Mesh.GetNumberOfPoints(); ++p)
  {
    const size_t r =
      p < n ? p : ladder.Representative(static_cast<size_t>(s.Level), static_cast<uint32_t>(p));
    std::copy_n(&work[3 * r], 3, &out[3 * p]);
  }
}

struct Run
{
  std::string Budget;
  double BudgetSeconds = 0.0;
  int Geomorph = 0;
  std::vector<double> Distance, Level, Active, BlendUs, ErrorMaxPx, ErrorP95Px, JumpPx;
  int Over = 0;
  size_t Switches = 0;
  double MaxJump = 0.0;
};

void Plot(const std::vector<Run>& runs, const std::string& file, const std::string& title)
{
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(1000, 560);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  chart->SetTitle(title);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("distance (multiples of the closest)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(true);
  chart->GetAxis(vtkAxis::LEFT)
    ->SetTitle("level (0 = full) / active targets / 10 / pixel error p95");
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  const unsigned char colors[3][3] = { { 31, 119, 180 }, { 255, 127, 14 }, { 214, 39, 40 } };
  std::vector<vtkSmartPointer<vtkTable>> tables;
  int c = 0;
  for (const Run& r : runs)
  {
    if (r.Geomorph == 0)
    {
      continue;
    }
    auto table = vtkSmartPointer<vtkTable>::New();
    const std::string names[] = { "distance", r.Budget + ": level",
      r.Budget + ": active targets / 10", r.Budget + ": pixel error p95" };
    for (const auto& n : names)
    {
      vtkNew<vtkFloatArray> col;
      col->SetName(n.c_str());
      table->AddColumn(col);
    }
    table->SetNumberOfRows(static_cast<vtkIdType>(r.Distance.size()));
    for (size_t f = 0; f < r.Distance.size(); ++f)
    {
      table->SetValue(f, 0, r.Distance[f] / r.Distance[0]);
      table->SetValue(f, 1, r.Level[f]);
      table->SetValue(f, 2, r.Active[f] / 10.0);
      table->SetValue(f, 3, r.ErrorP95Px[f]);
    }
    for (int k = 1; k <= 3; ++k)
    {
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(table, 0, k);
      line->SetColor(colors[c % 3][0], colors[c % 3][1], colors[c % 3][2], 255);
      line->SetWidth(k == 1 ? 3.0 : 1.5);
      line->GetPen()->SetLineType(
        k == 1 ? vtkPen::SOLID_LINE : (k == 2 ? vtkPen::DASH_LINE : vtkPen::DOT_LINE));
    }
    tables.push_back(table);
    ++c;
  }
  view->GetScene()->AddItem(chart);
  appkit::WritePng(view, file);
}

/// The whole frame at a fixed level (or a profile at a fixed screen size): morph + offscreen
/// render, `frames` frames of the track. Returns {morph seconds, frame seconds, targets}.
struct FrameTimes
{
  double Morph = 0.0, Frame = 0.0, Targets = 0.0, Level = 0.0;
};

FrameTimes TimeFrames(const std::shared_ptr<const morphnode::MorphLadder>& ladder,
  const std::vector<morphnode::CostModel>& costs, const morphnode::ControllerSettings& settings,
  double ppu, const morphnode::WeightTrack& track, int frames, vtkRenderWindow* window,
  vtkPolyData* poly)
{
  morphnode::ScalableMorph morph;
  morph.SetSettings(settings);
  morph.SetLadder(ladder, costs);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  poly->SetPoints(points);
  int shownLevel = -1;
  std::vector<double> morphT, frameT;
  double targets = 0.0, levels = 0.0;
  for (int f = 0; f < frames; ++f)
  {
    const double t0 = Now();
    const morphnode::ScalableFrame& fr =
      morph.Update(Absolute(track, static_cast<size_t>(f) % track.GetNumberOfFrames()), ppu);
    // Hand the shown prefix and, on a change of level, its index buffer to VTK.
    points->SetNumberOfPoints(static_cast<vtkIdType>(fr.NumberOfPoints));
    std::copy_n(morph.GetPositions().data(), 3 * fr.NumberOfPoints,
      static_cast<float*>(points->GetData()->GetVoidPointer(0)));
    points->Modified();
    if (fr.Decision.Level != shownLevel)
    {
      shownLevel = fr.Decision.Level;
      vtkNew<vtkCellArray> polys;
      const auto& t = morph.GetTriangles();
      for (size_t i = 0; i < t.size(); i += 3)
      {
        const vtkIdType ids[3] = { t[i], t[i + 1], t[i + 2] };
        polys->InsertNextCell(3, ids);
      }
      poly->SetPolys(polys);
    }
    const double t1 = Now();
    window->Render();
    window->WaitForCompletion();
    const double t2 = Now();
    morphT.push_back(t1 - t0);
    frameT.push_back(t2 - t0);
    targets += fr.Decision.ActiveTargets;
    levels += fr.Decision.Level;
  }
  // The 10th percentile: the frame as it costs when no other job takes the cores (the
  // machine is shared; see docs/benchmarks.md, "Machine and load").
  auto low = [](std::vector<double> v)
  {
    std::nth_element(v.begin(), v.begin() + v.size() / 10, v.end());
    return v[v.size() / 10];
  };
  return { low(morphT), low(frameT), targets / frames, levels / frames };
}
} // namespace

int main(int argc, char* argv[])
{
  StudyOptions o;
  o.FacePath = appkit::FaceKitPath("ict_face11248_sparse53.glb");
  CLI::App app("LodStudy: the scalable avatar's ladder at work (docs/lod.md).", "LodStudy");
  app.add_option("--face", o.FacePath, "a face with morph targets (glTF/GLB; its first mesh)")
    ->check(CLI::ExistingFile)
    ->capture_default_str();
  app.add_option("--out", o.OutDir, "output folder")->capture_default_str();
  app.add_option("--images", o.ImageDir, "folder for the PNGs (default: the output folder)");
  appkit::AddNumberOption(
    app, "--seconds", o.Seconds, 1.0, 3600.0, "length of the synthetic speech track");
  appkit::AddNumberOption(
    app, "--pixel-bound", o.PixelBound, 0.0, 100.0, "level error on screen, px");
  appkit::AddNumberOption(
    app, "--target-pixel-bound", o.TargetPixelBound, 0.0, 100.0, "target LOD bound, px");
  appkit::AddNumberOption(
    app, "--far", o.FarFactor, 1.0, 1000.0, "the dolly's end, in multiples of its start");
  app.add_option("--bench-frames", o.BenchFrames, "frames per benchmark run")
    ->check(CLI::Range(1, 100000));
  app.add_flag_callback(
    "--no-bench", [&o]() { o.Bench = false; }, "skip the rendering benchmark");
  appkit::ParseCommandLine(app, argc, argv);
  if (o.ImageDir.empty())
  {
    o.ImageDir = o.OutDir;
  }
  try
  {
    std::filesystem::create_directories(o.OutDir);
    std::filesystem::create_directories(o.ImageDir);
    const Face face = LoadFace(o.FacePath);
    morphnode::MorphMesh mesh = ToMorphMesh(face.Mesh);
    mesh.SetTargetNames(face.Names);
    const double tb = Now();
    auto ladder = std::make_shared<const morphnode::MorphLadder>(
      morphnode::BuildMorphLadder(mesh, morphnode::LadderSettings()));
    const double buildSeconds = Now() - tb;
    const auto costs = morphnode::ScalableMorph::Calibrate(*ladder);
    morphnode::WeightTrack track = MakeSyntheticSpeechTrack(face.Names, o.Seconds, 7);
    bool moves = false;
    for (size_t f = 0; f < track.GetNumberOfFrames() && !moves; ++f)
    {
      for (size_t k = 0; k < track.GetNumberOfChannels(); ++k)
      {
        moves = moves || track.GetFrame(f)[k] != 0.0;
      }
    }
    if (!moves)
    {
      // A face without ARKit names (the default head's visemes): each target rises and falls
      // in turn, two or three at a time, at speech-like rates (3-6 per second).
      std::vector<std::string> channels(face.Names.begin() + 1, face.Names.end());
      track = morphnode::WeightTrack(channels, 30.0);
      const size_t frames = static_cast<size_t>(o.Seconds * 30.0);
      std::vector<double> w(channels.size());
      for (size_t f = 0; f < frames; ++f)
      {
        const double t = f / 30.0;
        double sum = 0.0;
        for (size_t k = 0; k < w.size(); ++k)
        {
          const double s = std::sin(2.0 * 3.14159265358979 * (0.5 + 0.37 * k) * t + 1.7 * k);
          w[k] = s > 0.6 ? 0.8 * (s - 0.6) / 0.4 : 0.0;
          sum += w[k];
        }
        for (double& x : w)
        {
          x /= std::max(1.0, sum);
        }
        track.AppendFrame(w);
      }
    }
    const auto& attr = std::get<morphnode::MorphAttribute<float>>(
      ladder->Mesh.GetAttribute(static_cast<size_t>(ladder->Mesh.GetPositionAttribute())));
    std::ofstream md(o.OutDir + "/lod.md");
    // The face's height and the closest distance: the face fills 90 % of the view.
    float lo = 1e30f, hi = -1e30f;
    for (size_t p = 0; p < mesh.GetNumberOfPoints(); ++p)
    {
      lo = std::min(lo, face.Mesh.Positions[3 * p + 1]);
      hi = std::max(hi, face.Mesh.Positions[3 * p + 1]);
    }
    const double faceHeight = hi - lo;
    const double near = faceHeight / 0.9 / (2.0 * std::tan(0.5 * o.Fov * 3.14159265358979 / 180.0));
    md << "Face: `" << std::filesystem::path(o.FacePath).filename().string() << "`, "
       << mesh.GetNumberOfPoints() << " points, " << mesh.GetNumberOfTriangles() << " triangles, "
       << mesh.GetNumberOfTargets() - 1 << " targets; ladder built in " << buildSeconds
       << " s. Screen " << o.Height << " px high, field of view " << o.Fov
       << " degrees; the dolly goes from " << near << " to " << near * o.FarFactor
       << " units (the face " << std::lround(0.9 * o.Height) << " to "
       << std::lround(0.9 * o.Height / o.FarFactor) << " px high) over "
       << track.GetNumberOfFrames() << " frames. Pixel bound " << o.PixelBound
       << " px, target pixel bound " << o.TargetPixelBound << " px.\n\n";
    md << "| level | points | triangles | error p99 (units; chosen by) | max error | RMS error | "
          "cost a (us) | b (ns per target point) |\n"
          "|---|---|---|---|---|---|---|---|\n";
    for (size_t l = 0; l < ladder->Levels.size(); ++l)
    {
      const auto& L = ladder->Levels[l];
      md << "| " << l << " | " << L.NumberOfPoints << " | " << L.Triangles.size() / 3 << " | "
         << L.Error99 << " | " << L.MaxError << " | " << L.RmsError << " | " << 1e6 * costs[l].Fixed
         << " | " << 1e9 * costs[l].PerTargetPoint << " |\n";
    }
    // Budgets relative to the full face's 95th percentile predicted cost on the track.
    std::vector<double> fullCost;
    for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
    {
      const auto w = Absolute(track, f);
      double x = 0.0;
      for (size_t k = 1; k < w.size(); ++k)
      {
        x += w[k] != 0.0 ? ladder->Levels[0].MovedPoints[k] : 0.0;
      }
      fullCost.push_back(costs[0].Predict(x));
    }
    std::sort(fullCost.begin(), fullCost.end());
    const double p95 = fullCost[fullCost.size() * 95 / 100];
    md << "\nFull face, 95th percentile of the predicted blend time on the track: " << Us(p95)
       << " us.\n\n";

    std::vector<Run> runs;
    std::ofstream csv(o.OutDir + "/lod_dolly.csv");
    csv
      << "budget,geomorph,frame,distance,pixels_per_unit,level,morph_towards,alpha,active,blend_us,"
         "error_max_px,error_p95_px,jump_px\n";
    const std::pair<std::string, double> budgets[] = { { "generous (100 %)", 1.0 },
      { "medium (45 %)", 0.45 }, { "tight (18 %)", 0.18 } };
    for (const auto& [name, share] : budgets)
    {
      for (int geomorph : { 8, 0 })
      {
        Run run;
        run.Budget = name;
        run.BudgetSeconds = share * p95;
        run.Geomorph = geomorph;
        morphnode::ControllerSettings s;
        s.FrameBudget = run.BudgetSeconds;
        s.PixelBound = o.PixelBound;
        s.TargetPixelBound = o.TargetPixelBound;
        s.Strategy = morphnode::Redistribution::Neutral;
        s.GeomorphFrames = geomorph;
        s.MaxGeomorphPixels = geomorph > 0 ? 1.0 : 0.0;
        s.MaxGeomorphFrames = 300; // 10 s: never reached in these runs
        s.MinFramesPerLevel = 10;
        morphnode::ScalableMorph morph;
        morph.SetSettings(s);
        morph.SetLadder(ladder, costs);
        Shown previous;
        bool first = true;
        std::vector<float> full(3 * mesh.GetNumberOfPoints()), work, now, before, shownPoints;
        for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
        {
          const double distance =
            near * std::pow(o.FarFactor, double(f) / double(track.GetNumberOfFrames() - 1));
          const double ppu = morphnode::ScreenPixelsPerUnit(o.Height, o.Fov, distance);
          const std::vector<double> w = Absolute(track, f);
          const morphnode::ScalableFrame& fr = morph.Update(w, ppu);
          const auto& d = fr.Decision;
          const Shown state{ d.Level, d.MorphTowards, d.Alpha };
          // Jump: this frame's state against the previous one's, same weights.
          double jump = 0.0;
          if (!first &&
            (state.Level != previous.Level || state.MorphTowards != previous.MorphTowards ||
              state.Alpha != previous.Alpha))
          {
            VertexView(*ladder, attr, d.Weights, state, work, now);
            VertexView(*ladder, attr, d.Weights, previous, work, before);
            for (size_t i = 0; i < now.size(); i += 3)
            {
              const double dx = now[i] - before[i], dy = now[i + 1] - before[i + 1],
                           dz = now[i + 2] - before[i + 2];
              jump = std::max(jump, std::sqrt(dx * dx + dy * dy + dz * dz) * ppu);
            }
          }
          first = false;
          previous = state;
          // Pixel error against the full-resolution, unoptimized animation.
          attr.Blend(w.data(), w.size(), full.data(), 0, mesh.GetNumberOfPoints());
          const std::vector<float>& shown = morph.GetPositions();
          std::vector<double> err(mesh.GetNumberOfPoints());
          for (size_t p = 0; p < err.size(); ++p)
          {
            double q[3];
            for (int c = 0; c < 3; ++c)
            {
              if (d.Level == 0)
              {
                q[c] = shown[3 * p + c];
              }
              else
              {
                // Carried on the shown level (its correspondence from the ladder).
                const auto& L = ladder->Levels[d.Level];
                q[c] = 0.0;
                for (int i = 0; i < 3; ++i)
                {
                  q[c] += L.Barycentrics[3 * p + i] * shown[3 * L.Corners[3 * p + i] + c];
                }
              }
            }
            const double dx = q[0] - full[3 * p], dy = q[1] - full[3 * p + 1],
                         dz = q[2] - full[3 * p + 2];
            err[p] = std::sqrt(dx * dx + dy * dy + dz * dz) * ppu;
          }
          std::nth_element(err.begin(), err.begin() + err.size() * 95 / 100, err.end());
          const double e95 = err[err.size() * 95 / 100];
          const double emax = *std::max_element(err.begin(), err.end());
          run.Distance.push_back(distance);
          run.Level.push_back(d.MorphTowards >= 0 ? d.Level + d.Alpha : d.Level);
          run.Active.push_back(d.ActiveTargets);
          run.BlendUs.push_back(1e6 * fr.BlendSeconds);
          run.ErrorMaxPx.push_back(emax);
          run.ErrorP95Px.push_back(e95);
          run.JumpPx.push_back(jump);
          run.Over += fr.BlendSeconds > run.BudgetSeconds ? 1 : 0;
          run.MaxJump = std::max(run.MaxJump, jump);
          csv << name << "," << geomorph << "," << f << "," << distance << "," << ppu << ","
              << d.Level << "," << d.MorphTowards << "," << d.Alpha << "," << d.ActiveTargets << ","
              << 1e6 * fr.BlendSeconds << "," << emax << "," << e95 << "," << jump << "\n";
        }
        run.Switches = morph.GetController().GetNumberOfSwitches();
        std::cerr << name << " geomorph " << geomorph << ": switches " << run.Switches << ", over "
                  << run.Over << ", max jump " << run.MaxJump << " px\n";
        runs.push_back(std::move(run));
      }
    }
    md << "| budget | us | geomorph frames (at least; slower where a step would exceed 1 px) | "
          "frames over budget (measured) | level switches | largest jump of a vertex (px) |\n"
          "|---|---|---|---|---|---|\n";
    for (const Run& r : runs)
    {
      md << "| " << r.Budget << " | " << Us(r.BudgetSeconds) << " | " << r.Geomorph << " | "
         << r.Over << " of " << r.Distance.size() << " | " << r.Switches << " | " << r.MaxJump
         << " |\n";
    }
    // At each distance (five stretches of the dolly), with geomorphs.
    md << "\nAlong the dolly (with geomorphs; means over each fifth of the frames):\n\n"
          "| budget | face height (px) | mean level | mean active targets | blend time (us) | "
          "pixel error p95 / max (px) |\n"
          "|---|---|---|---|---|---|\n";
    for (const Run& r : runs)
    {
      if (r.Geomorph == 0)
      {
        continue;
      }
      const size_t n = r.Distance.size();
      for (int part = 0; part < 5; ++part)
      {
        const size_t b = n * part / 5, e = n * (part + 1) / 5;
        auto mean = [&](const std::vector<double>& v)
        { return std::accumulate(v.begin() + b, v.begin() + e, 0.0) / double(e - b); };
        const double mid = r.Distance[(b + e) / 2];
        std::ostringstream row;
        row << std::fixed << std::setprecision(2) << "| " << r.Budget << " | "
            << std::lround(faceHeight * morphnode::ScreenPixelsPerUnit(o.Height, o.Fov, mid))
            << " | " << mean(r.Level) << " | " << mean(r.Active) << " | " << std::setprecision(1)
            << mean(r.BlendUs) << " | " << std::setprecision(2) << mean(r.ErrorP95Px) << " / "
            << *std::max_element(r.ErrorMaxPx.begin() + b, r.ErrorMaxPx.begin() + e) << " |\n";
        md << row.str();
      }
    }
    Plot(runs, o.ImageDir + "/lod_dolly.png",
      "Dolly-out of the talking face: level, targets and pixel error");

    if (o.Bench)
    {
      vtkNew<vtkRenderWindow> window;
      window->SetOffScreenRendering(1);
      window->SetMultiSamples(0);
      window->SetSize(640, 480);
      vtkNew<vtkRenderer> renderer;
      window->AddRenderer(renderer);
      vtkNew<vtkPolyData> poly;
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputData(poly);
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      renderer->AddActor(actor);
      // Frame the neutral face once.
      {
        vtkNew<vtkPoints> pts;
        for (size_t p = 0; p < mesh.GetNumberOfPoints(); ++p)
        {
          pts->InsertNextPoint(&face.Mesh.Positions[3 * p]);
        }
        poly->SetPoints(pts);
        renderer->ResetCamera();
      }
      // Every configuration runs in each of `rounds` short rounds, in turn, so that all saw
      // the same machine (a shared VM drifts by tens of percent over seconds); figures are
      // medians over the rounds, speed-ups medians of the per-round ratios to full resolution.
      struct Config
      {
        std::string Name;
        morphnode::ControllerSettings Settings;
        double Ppu = 0.0;
        std::vector<FrameTimes> Rounds;
      };
      std::vector<Config> configs;
      for (size_t l = 0; l < ladder->Levels.size(); ++l)
      {
        morphnode::ControllerSettings s;
        s.FrameBudget = 1.0;
        s.Thresholds = { 0.0 };
        s.FinestLevel = static_cast<int>(l);
        configs.push_back({ "level " + std::to_string(l) + (l == 0 ? " (full)" : ""), s, 0.0, {} });
      }
      const double ppu300 = 300.0 / faceHeight;
      for (const auto& profile : morphnode::DeviceProfiles())
      {
        morphnode::ControllerSettings s;
        s.Strategy = morphnode::Redistribution::Neutral;
        morphnode::ApplyDeviceProfile(profile, s);
        configs.push_back({ "profile " + profile.Name, s, ppu300, {} });
      }
      // The paper's Figure 3 with levels: the adjusted threshold at each level.
      const std::vector<double> thresholds = { 0.0, 0.1, 0.2, 0.3, 0.4, 0.5 };
      const size_t figureFirst = configs.size();
      for (double t : thresholds)
      {
        for (size_t l = 0; l < ladder->Levels.size(); ++l)
        {
          morphnode::ControllerSettings s;
          s.FrameBudget = 1.0;
          s.Thresholds = { t };
          s.FinestLevel = static_cast<int>(l);
          configs.push_back({ "", s, 0.0, {} });
        }
      }
      const int rounds = 7;
      const int perRound = std::max(2, o.BenchFrames / rounds);
      TimeFrames(ladder, costs, configs[0].Settings, 0.0, track, perRound, window, poly); // warm-up
      for (int r = 0; r < rounds; ++r)
      {
        for (auto& c : configs)
        {
          c.Rounds.push_back(
            TimeFrames(ladder, costs, c.Settings, c.Ppu, track, perRound, window, poly));
        }
      }
      auto median = [](std::vector<double> v)
      {
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        return v[v.size() / 2];
      };
      auto summary = [&](const Config& c, const Config& base, double& morph, double& frame,
                       double& morphUp, double& frameUp)
      {
        std::vector<double> m, f, mu, fu;
        for (int r = 0; r < rounds; ++r)
        {
          m.push_back(c.Rounds[r].Morph);
          f.push_back(c.Rounds[r].Frame);
          mu.push_back(base.Rounds[r].Morph / c.Rounds[r].Morph);
          fu.push_back(base.Rounds[r].Frame / c.Rounds[r].Frame);
        }
        morph = median(m);
        frame = median(f);
        morphUp = median(mu);
        frameUp = median(fu);
      };
      md << "\nWhole frame (morph + offscreen render, 640x480; " << rounds << " rounds of "
         << perRound
         << " frames of the track, every configuration in every round in turn; per round the 10th "
            "percentile of its frames, then medians over the rounds, "
            "speed-ups the median of the per-round ratios), each level shown alone and each device "
            "profile "
            "with the face 300 px high, against full resolution in the same run:\n\n"
            "| run | mean level | mean active targets | morph (us) | frame (ms) | frames per "
            "second | morph speed-up | frame speed-up |\n"
            "|---|---|---|---|---|---|---|---|\n";
      for (size_t i = 0; i < figureFirst; ++i)
      {
        const Config& c = configs[i];
        double morphS, frameS, morphUp, frameUp;
        summary(c, configs[0], morphS, frameS, morphUp, frameUp);
        double level = 0.0, targets = 0.0;
        for (const auto& r : c.Rounds)
        {
          level += r.Level / rounds;
          targets += r.Targets / rounds;
        }
        std::ostringstream row;
        row << std::fixed << std::setprecision(2) << "| " << c.Name << " | " << level << " | "
            << targets << " | " << std::setprecision(1) << 1e6 * morphS << " | "
            << std::setprecision(2) << 1e3 * frameS << " | " << std::setprecision(1) << 1.0 / frameS
            << " | " << std::setprecision(2) << morphUp << " x | " << frameUp << " x |\n";
        md << row.str();
      }
      vtkNew<vtkTable> table;
      vtkNew<vtkFloatArray> tcol;
      tcol->SetName("threshold");
      table->AddColumn(tcol);
      for (size_t l = 0; l < ladder->Levels.size(); ++l)
      {
        vtkNew<vtkFloatArray> col;
        col->SetName(("level " + std::to_string(l) + " (" +
          std::to_string(ladder->Levels[l].Triangles.size() / 3) + " triangles)")
                       .c_str());
        table->AddColumn(col);
      }
      table->SetNumberOfRows(static_cast<vtkIdType>(thresholds.size()));
      md << "\nThe paper's Figure 3 with levels: whole frames per second (median over the rounds) "
            "against the "
            "adjusted threshold (remaining redistribution), one column per level:\n\n| threshold |";
      std::string rule = "|---|";
      for (size_t l = 0; l < ladder->Levels.size(); ++l)
      {
        md << " level " << l << " |";
        rule += "---|";
      }
      md << "\n" << rule << "\n";
      for (size_t i = 0; i < thresholds.size(); ++i)
      {
        table->SetValue(static_cast<vtkIdType>(i), 0, thresholds[i]);
        md << "| " << thresholds[i] << " |";
        for (size_t l = 0; l < ladder->Levels.size(); ++l)
        {
          const Config& c = configs[figureFirst + i * ladder->Levels.size() + l];
          double morphS, frameS, morphUp, frameUp;
          summary(c, configs[0], morphS, frameS, morphUp, frameUp);
          table->SetValue(static_cast<vtkIdType>(i), static_cast<vtkIdType>(l + 1), 1.0 / frameS);
          md << " " << std::lround(1.0 / frameS) << " |";
        }
        md << "\n";
      }
      md.flush();
      vtkNew<vtkContextView> view;
      view->GetRenderWindow()->SetSize(900, 520);
      view->GetRenderer()->SetBackground(1, 1, 1);
      vtkNew<vtkChartXY> chart;
      chart->SetTitle("Figure 3 with levels: whole frame (morph + render) against the threshold");
      chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("adjusted threshold");
      chart->GetAxis(vtkAxis::LEFT)->SetTitle("frames per second");
      chart->SetShowLegend(true);
      const unsigned char colors[4][3] = { { 0, 0, 0 }, { 31, 119, 180 }, { 255, 127, 14 },
        { 214, 39, 40 } };
      for (size_t l = 0; l < ladder->Levels.size(); ++l)
      {
        vtkPlot* line = chart->AddPlot(vtkChart::LINE);
        line->SetInputData(table, 0, static_cast<vtkIdType>(l + 1));
        line->SetColor(colors[l % 4][0], colors[l % 4][1], colors[l % 4][2], 255);
        line->SetWidth(2.5);
      }
      view->GetScene()->AddItem(chart);
      appkit::WritePng(view, o.ImageDir + "/figure3_levels.png");
    }
    std::cerr << "wrote " << o.OutDir << "/lod.md\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "LodStudy: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
