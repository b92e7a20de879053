// SPDX-License-Identifier: BSD-3-Clause
// The paper's Figure 3 (Berner, WSCG 2004): frame rate against threshold per optimization
// method, for the whole avatar -- morph and offscreen render -- speaking a long text.
//
//   BenchAvatarFrameRate [--smoke] [--text FILE] [--fps 25] [--seconds S]
//                        [--face default.glb] [--ict ict.glb] [--rig arkit.json]
//                        [--csv FILE] [--markdown FILE] [--images DIR] [--size WxH]
//                        [--levels [--head ict_head.glb] [--avatar makehuman.glb]
//                                  [--avatar-rig readyplayerme.json]]
//
// Run under `xvfb-run -a`. Faces: the default face (its own 13 targets A E O S F L ...)
// and, when present, the ICT face with the paper's 12 shapes baked through the ARKit rig
// (vtkMorphRigBaker, set "paper"). The text is spoken by morphnode::SpeakText with the
// Paper6 visemes (channels sil A E O S F L; sil is the neutral). Every frame of the track
// is played as fast as possible: SetWeight per channel, vtkMorphNodeFilter Update (the
// morph stage, optimizer included), then Render and glFinish (the whole frame).
//
// Methods, by the optimizer presets (morph/OptimizerPresets.h): none and error-bounded
// (neutral redistribution within a vertex-error bound eps = 0.5 % of the face's diagonal;
// no threshold, so a flat line like none); and for thresholds 0.1..0.5 fixed-maximum,
// fixed-remaining, adjusted (the paper's three) and adjusted-bounded, a combination that is
// no preset: the adjusted threshold with neutral redistribution, and the bound eps restoring
// pruned targets. Reported per face, method and threshold: frames per second of the morph
// stage and of the whole frame, mean active targets, and both speed-ups against "none".
// --smoke plays a handful of frames of one threshold (CI; asserts nothing timed).
//
// --levels (docs/benchmarks.md, "Figure 3 with mesh levels"): the same frames for the mesh
// levels of vtkMorphNodeFilter (MeshLevels, docs/lod.md), on the default face, the ICT head
// (--head, every mesh) and the MakeHuman avatar (--avatar, every part, at rest), the latter
// two with the paper's shapes expanded into their ARKit targets every frame by a rig
// (Data/rigs/arkit.json, readyplayerme.json; morphnode::Rig::Expand, relative weights). Per face,
// one run: full resolution (levels off, the yardstick), each ladder level shown alone (FinestLevel
// l, a screen that asks for full resolution) and each device profile (desktop, laptop, phone: their
// own filter, pixels per unit from the camera); per configuration ms per frame (morph, render,
// total), points and triangles drawn, targets blended, level shown. Then the paper's Figure 3 with
// levels: whole frames per second against the adjusted threshold, one line per level and levels
// off, each with its line without the optimizer.
#include "CommandLine.h"
#include "ImageOutput.h"
#include "OptimizerSetup.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigBaker.h"
#include "vtkMorphTargetReader.h"

#include "budget/DeviceProfile.h"
#include "morph/OptimizerPresets.h"
#include "rig/Rig.h"
#include "speech/Speech.h"

#include "vtkActor.h"
#include "vtkAxis.h"
#include "vtkCamera.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;
using morphnode::OptimizerPreset;

/// The combination of the adjusted threshold and the error bound (no preset).
const char* const AdjustedBounded = "adjusted-bounded";

struct Method
{
  std::string Name;       ///< a preset's name, or AdjustedBounded
  double Threshold = 0.0; ///< 0 for the methods without one (none, error-bounded)
};

Method PresetMethod(OptimizerPreset preset, double threshold)
{
  return { morphnode::OptimizerPresetName(preset), threshold };
}

struct Result
{
  std::string Face;
  Method M;
  size_t Frames = 0;
  double MorphFps = 0.0;
  double FrameFps = 0.0;
  double MeanActive = 0.0;
  double MorphSpeedup = 1.0;
  double FrameSpeedup = 1.0;
};

std::string Fmt(double v, int precision = 3)
{
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

std::string ReadText(const std::string& file)
{
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// One face ready to play: the morph node feeding an offscreen renderer.
struct Avatar
{
  std::string Name;
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphRigBaker> Baker;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkPolyDataMapper> Mapper;
  vtkNew<vtkActor> Actor;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  double Diagonal = 1.0;
  std::vector<int> ChannelTarget; // per track channel: target index, -1 unused

  bool Setup(const std::string& face, const std::string& rig,
    const std::vector<std::string>& channels, int w, int h)
  {
    this->Reader->SetFileName(face.c_str());
    this->Reader->SetMeshIndex(0); // the face mesh as one vtkPolyData
    if (rig.empty())
    {
      this->Morph->SetInputConnection(this->Reader->GetOutputPort());
    }
    else
    {
      this->Baker->SetInputConnection(this->Reader->GetOutputPort());
      this->Baker->SetRigFileName(rig.c_str());
      this->Baker->SetShapeSet("paper");
      this->Morph->SetInputConnection(this->Baker->GetOutputPort());
    }
    this->Morph->SetWeightModeToNormalize();
    this->Morph->Update();
    auto* out = vtkPointSet::SafeDownCast(this->Morph->GetOutputDataObject(0));
    if (!out || out->GetNumberOfPoints() == 0)
    {
      std::cerr << "cannot morph " << face << "\n";
      return false;
    }
    this->Diagonal = out->GetLength();
    for (const auto& c : channels)
    {
      this->ChannelTarget.push_back(c == "sil" ? 0 : this->Morph->GetTargetIndex(c.c_str()));
      if (this->ChannelTarget.back() < 0)
      {
        std::cerr << this->Name << ": no target for viseme " << c << " (ignored)\n";
      }
    }
    this->Mapper->SetInputConnection(this->Morph->GetOutputPort());
    this->Actor->SetMapper(this->Mapper);
    this->Renderer->AddActor(this->Actor);
    this->Renderer->SetBackground(0.2, 0.2, 0.25);
    this->Window->SetMultiSamples(0);
    this->Window->OffScreenRenderingOn();
    this->Window->SetSize(w, h);
    this->Window->AddRenderer(this->Renderer);
    this->Renderer->ResetCamera();
    this->Renderer->GetActiveCamera()->Zoom(1.3);
    this->Window->Render();
    return true;
  }

  void Configure(const Method& m)
  {
    const double eps = 0.005 * this->Diagonal;
    if (m.Name == AdjustedBounded)
    {
      morphnode::OptimizerSettings s =
        morphnode::MakeOptimizerSettings(OptimizerPreset::Adjusted, m.Threshold, 0.0);
      s.Strategy = morphnode::Redistribution::Neutral;
      s.MaxVertexError = eps;
      morphnode::appkit::ApplyOptimizerSettings(this->Morph, s);
      return;
    }
    this->Morph->SetThreshold(m.Threshold);
    this->Morph->SetMaxVertexError(eps); // used by error-bounded only
    this->Morph->SetOptimizerPreset(static_cast<int>(morphnode::ParseOptimizerPreset(m.Name)));
  }

  /// Plays frames [begin, end) of the track, adding morph seconds, whole-frame seconds and
  /// active targets.
  void Play(const morphnode::WeightTrack& track, size_t begin, size_t end, double& morph,
    double& whole, double& active)
  {
    for (size_t f = begin; f < end; ++f)
    {
      const auto t0 = Clock::now();
      const double* w = track.GetFrame(f);
      for (size_t c = 0; c < this->ChannelTarget.size(); ++c)
      {
        if (this->ChannelTarget[c] >= 0)
        {
          this->Morph->SetWeight(this->ChannelTarget[c], w[c]);
        }
      }
      this->Morph->Update();
      const auto t1 = Clock::now();
      this->Window->Render();
      this->Window->WaitForCompletion();
      const auto t2 = Clock::now();
      morph += std::chrono::duration<double>(t1 - t0).count();
      whole += std::chrono::duration<double>(t2 - t0).count();
      active += this->Morph->GetActiveTargetCount();
    }
  }
};

/// One line of a Figure 3 chart: (threshold, fps) points, a colour, dashed or solid.
void AddLine(vtkChartXY* chart, const std::string& name,
  const std::vector<std::pair<double, double>>& points, const unsigned char color[3], bool dashed)
{
  vtkNew<vtkTable> table;
  vtkNew<vtkFloatArray> x, y;
  x->SetName("threshold");
  y->SetName(name.c_str());
  table->AddColumn(x);
  table->AddColumn(y);
  table->SetNumberOfRows(static_cast<vtkIdType>(points.size()));
  for (size_t i = 0; i < points.size(); ++i)
  {
    table->SetValue(static_cast<vtkIdType>(i), 0, points[i].first);
    table->SetValue(static_cast<vtkIdType>(i), 1, points[i].second);
  }
  vtkPlot* line = chart->AddPlot(vtkChart::LINE);
  line->SetInputData(table, 0, 1);
  line->SetColor(color[0], color[1], color[2], 255);
  line->SetWidth(2.0);
  if (dashed)
  {
    line->GetPen()->SetLineType(vtkPen::DASH_LINE);
  }
}

/// A Figure 3 chart (frames per second against threshold) ready for its lines.
vtkNew<vtkChartXY> MakeChart(vtkContextView* view, const std::string& title, const char* xTitle,
  int width = 800, int height = 500)
{
  view->GetRenderWindow()->SetSize(width, height);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  chart->SetTitle(title.c_str());
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("frames per second");
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(xTitle);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  view->GetScene()->AddItem(chart);
  return chart;
}

/// fps against threshold, a line per method, "none" as a flat line: the paper's Figure 3.
void Plot(const std::vector<Result>& results, const std::string& face, bool wholeFrame,
  const std::vector<double>& thresholds, const std::string& file)
{
  const std::string names[] = { "none", "fixed-maximum", "fixed-remaining", "adjusted",
    AdjustedBounded, "error-bounded" };
  const unsigned char colors[][3] = { { 0, 0, 0 }, { 228, 26, 28 }, { 55, 126, 184 },
    { 77, 175, 74 }, { 152, 78, 163 }, { 255, 127, 0 } };
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart = MakeChart(
    view, face + (wholeFrame ? ": whole frame (morph + render)" : ": morph stage"), "threshold");
  for (int m = 0; m < 6; ++m)
  {
    std::vector<std::pair<double, double>> points;
    for (const auto& r : results)
    {
      if (r.Face != face || r.M.Name != names[m])
      {
        continue;
      }
      const double fps = wholeFrame ? r.FrameFps : r.MorphFps;
      if (r.M.Threshold == 0.0) // no threshold: a flat line
      {
        points = { { thresholds.front(), fps }, { thresholds.back(), fps } };
      }
      else
      {
        points.emplace_back(r.M.Threshold, fps);
      }
    }
    if (points.size() < 2) // a line needs two thresholds (not in --smoke)
    {
      continue;
    }
    AddLine(chart, names[m], points, colors[m], m == 0 || m == 5);
  }
  morphnode::appkit::WritePng(view, file);
}

std::string Slug(const std::string& face)
{
  std::string s;
  for (char c : face)
  {
    s += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '_';
  }
  return s;
}
// ---- --levels: the whole avatar per mesh level and device profile (docs/benchmarks.md).

/// A configuration of the levels run.
struct LevelRun
{
  std::string Name;       ///< "full resolution", "level 2", "profile phone"
  size_t Pipe = 0;        ///< 0: levels off; 1: the fixed levels; 2+: a profile's own filter
  int Level = -1;         ///< the fixed levels' FinestLevel (-1: levels off)
  std::string Profile;    ///< a device profile's name
  double Threshold = 0.0; ///< the adjusted threshold (Figure 3); 0: no optimizer
  bool Figure3 = false;   ///< a point of Figure 3 only (not in the level table)
};

struct LevelResult
{
  std::string Face;
  LevelRun Run;
  double MorphMs = 0.0, RenderMs = 0.0, FrameMs = 0.0; ///< medians of rounds' 10th percentiles
  double FrameSpeedup = 1.0, MorphSpeedup = 1.0;       ///< medians of the rounds' ratios to full
  double Points = 0.0, Triangles = 0.0, Active = 0.0, Level = 0.0; ///< means per frame
};

/// The 10th percentile (of a round's frame times).
double Percentile10(std::vector<double> v)
{
  if (v.empty())
  {
    return 0.0;
  }
  auto at = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 10);
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

double Median(std::vector<double> v)
{
  if (v.empty())
  {
    return 0.0;
  }
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// A whole avatar (every part of its file, or one mesh) behind several morph nodes sharing
/// one renderer: the yardstick without levels, one with its level fixed, one per profile.
struct LevelledAvatar
{
  struct Pipe
  {
    vtkNew<vtkMorphNodeFilter> Morph;
    vtkSmartPointer<vtkPolyDataMapper> Mapper;
    vtkNew<vtkActor> Actor;
  };
  std::string Name;
  vtkNew<vtkMorphTargetReader> Reader;
  std::vector<std::unique_ptr<Pipe>> Pipes;
  /// With a rig: the paper's shapes expanded into the avatar's ARKit targets every frame
  /// (morphnode::Rig::Expand; baking them would need every part to have targets, and the
  /// ICT head's eyes have none). ChannelShape: per track channel, its shape (-1: none).
  std::unique_ptr<morphnode::Rig> ShapeRig;
  std::vector<int> ChannelShape;
  std::vector<double> ShapeWeights, TargetWeights, LastWeights;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  std::vector<int> ChannelTarget;
  double PixelsPerUnit = 0.0;
  double HeightPixels = 0.0; ///< the avatar's height on the screen
  size_t Active = 0;
  size_t LastPipe = 0;

  /// Every part of `file` (meshIndex -1) or one mesh; `rig`: bake the paper's shapes.
  bool Setup(const std::string& file, int meshIndex, const std::string& rig,
    const std::vector<std::string>& channels, const std::vector<std::string>& profiles, int w,
    int h)
  {
    this->Reader->SetFileName(file.c_str());
    this->Reader->SetMeshIndex(meshIndex);
    vtkAlgorithmOutput* source = this->Reader->GetOutputPort();
    this->Window->SetMultiSamples(0);
    this->Window->OffScreenRenderingOn();
    this->Window->SetSize(w, h);
    this->Window->AddRenderer(this->Renderer);
    this->Renderer->SetBackground(0.2, 0.2, 0.25);
    const size_t pipes = 2 + profiles.size();
    for (size_t p = 0; p < pipes; ++p)
    {
      auto pipe = std::make_unique<Pipe>();
      pipe->Morph->SetInputConnection(source);
      if (rig.empty())
      {
        pipe->Morph->SetWeightModeToNormalize(); // the visemes, as the paper's run
      }
      else
      {
        pipe->Morph->SetWeightModeToRelative(); // ARKit weights, glTF-style
      }
      if (p >= 1)
      {
        pipe->Morph->MeshLevelsOn();
      }
      if (p >= 2)
      {
        pipe->Morph->SetDeviceProfile(profiles[p - 2].c_str());
      }
      else if (p == 1)
      {
        pipe->Morph->SetPixelsPerUnit(1e9); // the screen asks for full resolution
      }
      pipe->Morph->Update(); // with levels: the ladders are built here
      vtkDataObject* out = pipe->Morph->GetOutputDataObject(0);
      if (!out || (p == 1 && pipe->Morph->GetLevel() < 0))
      {
        std::cerr << "cannot morph " << file << (p ? " with mesh levels" : "") << "\n";
        return false;
      }
      if (vtkCompositeDataSet::SafeDownCast(out))
      {
        pipe->Mapper = vtkSmartPointer<vtkCompositePolyDataMapper2>::New();
      }
      else
      {
        pipe->Mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
      }
      pipe->Mapper->SetInputConnection(pipe->Morph->GetOutputPort());
      pipe->Actor->SetMapper(pipe->Mapper);
      pipe->Actor->SetVisibility(p == 0);
      this->Renderer->AddActor(pipe->Actor);
      this->Pipes.push_back(std::move(pipe));
    }
    vtkMorphNodeFilter* first = this->Pipes[0]->Morph;
    if (!rig.empty())
    {
      try
      {
        this->ShapeRig = std::make_unique<morphnode::Rig>(morphnode::Rig::LoadFile(rig));
        std::vector<std::string> targets;
        for (int k = 1; k < first->GetNumberOfTargets(); ++k)
        {
          targets.emplace_back(first->GetTargetName(k));
        }
        this->ShapeRig->Bind(targets);
      }
      catch (const std::exception& e)
      {
        std::cerr << file << ": " << e.what() << "\n";
        return false;
      }
      this->ShapeWeights.assign(this->ShapeRig->GetNumberOfShapes(), 0.0);
      this->TargetWeights.assign(this->ShapeRig->GetNumberOfBoundTargets(), 0.0);
    }
    for (const auto& c : channels)
    {
      if (this->ShapeRig)
      {
        this->ChannelShape.push_back(c == "sil" ? -1 : this->ShapeRig->FindShape(c));
        this->ChannelTarget.push_back(c == "sil" || this->ChannelShape.back() >= 0 ? 0 : -1);
      }
      else
      {
        this->ChannelTarget.push_back(c == "sil" ? 0 : first->GetTargetIndex(c.c_str()));
      }
      if (this->ChannelTarget.back() < 0)
      {
        std::cerr << this->Name << ": no target for viseme " << c << " (ignored)\n";
      }
    }
    this->Renderer->ResetCamera();
    this->Renderer->GetActiveCamera()->Zoom(1.3);
    // Pixels per model unit at the avatar's centre, as MorphAvatar sets them.
    double b[6];
    this->Renderer->ComputeVisiblePropBounds(b);
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    const double center[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
    const double distance =
      std::sqrt(vtkMath::Distance2BetweenPoints(camera->GetPosition(), center));
    this->PixelsPerUnit = morphnode::ScreenPixelsPerUnit(h, camera->GetViewAngle(), distance);
    this->HeightPixels = (b[3] - b[2]) * this->PixelsPerUnit;
    for (size_t p = 2; p < this->Pipes.size(); ++p)
    {
      this->Pipes[p]->Morph->SetPixelsPerUnit(this->PixelsPerUnit);
    }
    this->Window->Render();
    return true;
  }

  void Configure(const LevelRun& run)
  {
    for (size_t p = 0; p < this->Pipes.size(); ++p)
    {
      this->Pipes[p]->Actor->SetVisibility(p == run.Pipe);
    }
    this->Active = run.Pipe;
    vtkMorphNodeFilter* morph = this->Pipes[run.Pipe]->Morph;
    if (run.Pipe == 1)
    {
      morph->SetFinestLevel(run.Level);
    }
    if (run.Pipe < 2) // a profile keeps its own optimizer and budget
    {
      morph->SetThreshold(run.Threshold);
      morph->SetOptimizerPreset(
        static_cast<int>(run.Threshold > 0.0 ? OptimizerPreset::Adjusted : OptimizerPreset::None));
    }
  }

  /// Output points and triangles of the shown pipe.
  void Count(double& points, double& triangles) const
  {
    vtkDataObject* out = this->Pipes[this->Active]->Morph->GetOutputDataObject(0);
    auto add = [&](vtkDataObject* leaf)
    {
      if (auto* poly = vtkPolyData::SafeDownCast(leaf))
      {
        points += static_cast<double>(poly->GetNumberOfPoints());
        triangles += static_cast<double>(poly->GetNumberOfPolys());
      }
    };
    if (auto* composite = vtkCompositeDataSet::SafeDownCast(out))
    {
      for (vtkDataObject* leaf : vtk::Range(composite))
      {
        add(leaf);
      }
    }
    else
    {
      add(out);
    }
  }

  /// Plays frames [begin, end) on the shown pipe: appends each frame's morph and render
  /// seconds, adds points, triangles, active targets and levels.
  void Play(const morphnode::WeightTrack& track, size_t begin, size_t end,
    std::vector<double>& morph, std::vector<double>& render, LevelResult& sums)
  {
    vtkMorphNodeFilter* m = this->Pipes[this->Active]->Morph;
    for (size_t f = begin; f < end; ++f)
    {
      const auto t0 = Clock::now();
      const double* w = track.GetFrame(f);
      if (this->ShapeRig)
      {
        // The shapes' weights expanded into the targets'; only changed weights are set.
        for (size_t c = 0; c < this->ChannelShape.size(); ++c)
        {
          if (this->ChannelShape[c] >= 0)
          {
            this->ShapeWeights[static_cast<size_t>(this->ChannelShape[c])] = w[c];
          }
        }
        this->ShapeRig->Expand(this->ShapeWeights.data(), this->TargetWeights.data());
        this->LastWeights.resize(this->TargetWeights.size(), -1.0);
        for (size_t k = 0; k < this->TargetWeights.size(); ++k)
        {
          if (this->TargetWeights[k] != this->LastWeights[k] || this->Active != this->LastPipe)
          {
            m->SetWeight(static_cast<int>(k) + 1, this->TargetWeights[k]);
          }
        }
        this->LastWeights = this->TargetWeights;
        this->LastPipe = this->Active;
      }
      else
      {
        for (size_t c = 0; c < this->ChannelTarget.size(); ++c)
        {
          if (this->ChannelTarget[c] >= 0)
          {
            m->SetWeight(this->ChannelTarget[c], w[c]);
          }
        }
      }
      m->Update();
      const auto t1 = Clock::now();
      this->Window->Render();
      this->Window->WaitForCompletion();
      const auto t2 = Clock::now();
      morph.push_back(std::chrono::duration<double>(t1 - t0).count());
      render.push_back(std::chrono::duration<double>(t2 - t1).count());
      sums.Active += m->GetActiveTargetCount();
      sums.Level += std::max(0, m->GetLevel());
      this->Count(sums.Points, sums.Triangles);
    }
  }
};

/// Figure 3 with levels: whole frames per second against the adjusted threshold, a line per
/// level (and levels off), each with its flat dashed line without the optimizer.
void PlotLevels(const std::vector<LevelResult>& results, const std::string& face,
  const std::vector<double>& thresholds, const std::string& file)
{
  const unsigned char colors[][3] = { { 0, 0, 0 }, { 55, 126, 184 }, { 77, 175, 74 },
    { 255, 127, 0 }, { 228, 26, 28 } };
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart = MakeChart(view,
    face + ": Figure 3 with levels, whole frame (morph + render); dashed: no optimizer",
    "adjusted threshold", 900, 650);
  // Frames per second from 0, with room above the lines for the legend.
  double top = 0.0;
  for (const auto& r : results)
  {
    if (r.Face == face && r.Run.Pipe <= 1)
    {
      top = std::max(top, 1e3 / std::max(r.FrameMs, 1e-9));
    }
  }
  chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  chart->GetAxis(vtkAxis::LEFT)->SetRange(0.0, 1.7 * top);
  for (int level = -1; level <= 3; ++level)
  {
    std::vector<std::pair<double, double>> adjusted;
    double none = 0.0, triangles = 0.0;
    std::string name;
    for (const auto& r : results)
    {
      if (r.Face != face || r.Run.Pipe > 1 || r.Run.Level != level)
      {
        continue;
      }
      const double fps = 1e3 / std::max(r.FrameMs, 1e-9);
      if (r.Run.Threshold == 0.0)
      {
        none = fps;
        triangles = r.Triangles;
        name = r.Run.Name;
      }
      else
      {
        adjusted.emplace_back(r.Run.Threshold, fps);
      }
    }
    if (none == 0.0 || adjusted.size() < 2)
    {
      continue; // not in --smoke
    }
    const std::string label = name + " (" + std::to_string(std::lround(triangles)) + " triangles)";
    AddLine(chart, label, adjusted, colors[level + 1], false);
    AddLine(chart, label + ", no optimizer",
      { { thresholds.front(), none }, { thresholds.back(), none } }, colors[level + 1], true);
  }
  morphnode::appkit::WritePng(view, file);
}

/// The GL renderer's name (Mesa llvmpipe under Xvfb here), from the window's capabilities.
std::string RendererName(vtkRenderWindow* window)
{
  const std::string caps = window->ReportCapabilities();
  const std::string key = "OpenGL renderer string:";
  const size_t at = caps.find(key);
  if (at == std::string::npos)
  {
    return "unknown";
  }
  const size_t begin = caps.find_first_not_of(' ', at + key.size());
  return caps.substr(begin, caps.find('\n', begin) - begin);
}

struct LevelFace
{
  std::string Name, File, Rig;
  int MeshIndex = -1;
};

int RunLevels(const std::vector<LevelFace>& faces, const morphnode::WeightTrack& track,
  size_t frames, bool smoke, int width, int height, const std::string& textFile, double duration,
  double fps, const std::string& csv, const std::string& markdown, const std::string& images)
{
  std::vector<std::string> profiles; // desktop, laptop, phone
  for (const morphnode::DeviceProfile& profile : morphnode::DeviceProfiles())
  {
    profiles.push_back(profile.Name);
  }
  std::vector<double> thresholds{ 0.1, 0.2, 0.3, 0.4, 0.5 };
  if (smoke)
  {
    thresholds = { 0.3 };
  }
  std::vector<LevelRun> runs{ { "full resolution", 0, -1, "", 0.0, false } };
  for (int l = 0; l <= 3; ++l)
  {
    runs.push_back({ "level " + std::to_string(l), 1, l, "", 0.0, false });
  }
  for (size_t p = 0; p < profiles.size(); ++p)
  {
    runs.push_back({ "profile " + profiles[p], 2 + p, -1, profiles[p], 0.0, false });
  }
  for (double th : thresholds)
  {
    runs.push_back({ "full resolution", 0, -1, "", th, true });
    for (int l = 0; l <= 3; ++l)
    {
      runs.push_back({ "level " + std::to_string(l), 1, l, "", th, true });
    }
  }
  const size_t chunk = smoke ? frames : 25;
  std::vector<LevelResult> results;
  std::string rendererName;
  std::map<std::string, std::string> faceNotes;
  for (const LevelFace& face : faces)
  {
    LevelledAvatar avatar;
    avatar.Name = face.Name;
    const auto started = Clock::now();
    if (!avatar.Setup(
          face.File, face.MeshIndex, face.Rig, track.GetChannels(), profiles, width, height))
    {
      return 1;
    }
    const double setup = std::chrono::duration<double>(Clock::now() - started).count();
    rendererName = RendererName(avatar.Window);
    {
      std::ostringstream note;
      note << avatar.Pipes[0]->Morph->GetNumberOfTargets() << " targets, on screen "
           << std::lround(avatar.HeightPixels) << " px high (" << Fmt(avatar.PixelsPerUnit, 4)
           << " px per unit); setup with the ladders " << Fmt(setup, 3) << " s";
      faceNotes[face.Name] = note.str();
    }
    std::cout << "\n" << face.Name << ": " << faceNotes[face.Name] << "\n";
    // Warm-up: every configuration once (caches, VBOs); the profiles settle on their level.
    for (const LevelRun& run : runs)
    {
      avatar.Configure(run);
      std::vector<double> a, b;
      LevelResult ignored;
      avatar.Play(track, 0, std::min<size_t>(frames, run.Pipe >= 2 ? 150 : 10), a, b, ignored);
    }
    // Rounds: the track in chunks, every configuration on each chunk in turn, so that a
    // change of machine load hits all alike. Per round and configuration the 10th
    // percentile of its frames' morph, render and whole-frame times (the frame as it costs
    // when no other job takes the cores: this VM is shared), then the median over rounds.
    std::vector<std::vector<double>> morphs(runs.size()), renders(runs.size()), wholes(runs.size());
    std::vector<LevelResult> sums(runs.size());
    for (size_t begin = 0; begin < frames; begin += chunk)
    {
      const size_t end = std::min(frames, begin + chunk);
      for (size_t k = 0; k < runs.size(); ++k)
      {
        avatar.Configure(runs[k]);
        std::vector<double> morph, render, whole;
        avatar.Play(track, begin, end, morph, render, sums[k]);
        for (size_t f = 0; f < morph.size(); ++f)
        {
          whole.push_back(morph[f] + render[f]);
        }
        morphs[k].push_back(1e3 * Percentile10(morph));
        renders[k].push_back(1e3 * Percentile10(render));
        wholes[k].push_back(1e3 * Percentile10(whole));
      }
    }
    for (size_t k = 0; k < runs.size(); ++k)
    {
      LevelResult r = sums[k];
      r.Face = face.Name;
      r.Run = runs[k];
      const double n = static_cast<double>(std::max<size_t>(frames, 1));
      r.Points /= n;
      r.Triangles /= n;
      r.Active /= n;
      r.Level = runs[k].Pipe == 0 ? -1.0 : r.Level / n;
      std::vector<double> totals, frameRatios, morphRatios;
      // The yardstick: full resolution with the same optimizer setting.
      size_t base = 0;
      for (size_t j = 0; j < runs.size(); ++j)
      {
        if (runs[j].Pipe == 0 && runs[j].Threshold == (runs[k].Pipe >= 2 ? 0.0 : runs[k].Threshold))
        {
          base = j;
        }
      }
      for (size_t c = 0; c < morphs[k].size(); ++c)
      {
        totals.push_back(wholes[k][c]);
        frameRatios.push_back(wholes[base][c] / std::max(wholes[k][c], 1e-12));
        morphRatios.push_back(morphs[base][c] / std::max(morphs[k][c], 1e-12));
      }
      r.MorphMs = Median(morphs[k]);
      r.RenderMs = Median(renders[k]);
      r.FrameMs = Median(totals);
      r.FrameSpeedup = Median(frameRatios);
      r.MorphSpeedup = Median(morphRatios);
      results.push_back(r);
      std::cout << std::left << std::setw(18) << r.Run.Name << std::setw(5)
                << (r.Run.Threshold == 0.0 ? "-" : Fmt(r.Run.Threshold)) << " level "
                << std::setw(5) << Fmt(r.Level) << " points " << std::setw(7)
                << std::lround(r.Points) << " triangles " << std::setw(7)
                << std::lround(r.Triangles) << " targets " << std::setw(5) << Fmt(r.Active)
                << " morph " << std::setw(6) << Fmt(r.MorphMs) << " ms render " << std::setw(6)
                << Fmt(r.RenderMs) << " ms frame " << std::setw(6) << Fmt(r.FrameMs)
                << " ms speed-up frame " << Fmt(r.FrameSpeedup) << " morph " << Fmt(r.MorphSpeedup)
                << std::endl;
    }
  }
  double load[3] = { 0, 0, 0 };
  if (getloadavg(load, 3) < 0)
  {
    load[0] = load[1] = load[2] = -1.0;
  }
  std::cout << "\nrenderer: " << rendererName << "; load average " << Fmt(load[0]) << " "
            << Fmt(load[1]) << " " << Fmt(load[2]) << "\n";

  if (!csv.empty())
  {
    std::ofstream out(csv);
    out << "face,run,threshold,level,points,triangles,targets,morph_ms,render_ms,frame_ms,"
           "frame_speedup,morph_speedup\n";
    for (const auto& r : results)
    {
      out << '"' << r.Face << "\",\"" << r.Run.Name << "\"," << r.Run.Threshold << "," << r.Level
          << "," << r.Points << "," << r.Triangles << "," << r.Active << "," << r.MorphMs << ","
          << r.RenderMs << "," << r.FrameMs << "," << r.FrameSpeedup << "," << r.MorphSpeedup
          << "\n";
    }
  }
  if (!markdown.empty())
  {
    std::ofstream md(markdown);
    md << "<!-- generated by BenchAvatarFrameRate --levels --markdown; do not edit -->\n";
    if (smoke)
    {
      md << "\n**Smoke run: a handful of frames, not measurements.**\n";
    }
    md << "\nText: `" << textFile.substr(textFile.find_last_of('/') + 1) << "`, " << Fmt(duration)
       << " s of speech, " << frames << " frames at " << fps << " fps per configuration, in "
       << (frames + chunk - 1) / chunk << " rounds of " << chunk
       << " frames (every configuration in each round in turn; per round and configuration "
          "the 10th percentile of its frames' times, then the median over the rounds; "
          "speed-ups are the medians of the rounds' ratios to full resolution with the same "
          "optimizer setting; the frame is timed as a whole, so morph and render need not add "
          "up to it). Rendered offscreen at "
       << width << "x" << height << " by `" << rendererName << "` (Xvfb, software GL: "
       << "the render's cost scales with the triangles and pixels drawn). Load average at the "
       << "end of the run: " << Fmt(load[0]) << " " << Fmt(load[1]) << " " << Fmt(load[2]) << ".\n";
    for (const LevelFace& face : faces)
    {
      md << "\n**" << face.Name << "** (" << faceNotes[face.Name] << ")\n\n"
         << "| run | level shown | points | triangles | targets blended | morph (ms) | render "
            "(ms) | frame (ms) | frames per second | frame speed-up | morph speed-up |\n"
         << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
      for (const auto& r : results)
      {
        if (r.Face != face.Name || r.Run.Figure3)
        {
          continue;
        }
        md << "| " << r.Run.Name << " | " << (r.Level < 0 ? "-" : Fmt(r.Level, 2)) << " | "
           << std::lround(r.Points) << " | " << std::lround(r.Triangles) << " | " << Fmt(r.Active)
           << " | " << Fmt(r.MorphMs) << " | " << Fmt(r.RenderMs) << " | " << Fmt(r.FrameMs)
           << " | " << Fmt(1e3 / r.FrameMs, 4) << " | " << Fmt(r.FrameSpeedup) << " x | "
           << Fmt(r.MorphSpeedup) << " x |\n";
      }
      md << "\nFigure 3 with levels, " << face.Name
         << ": whole frames per second (targets blended) against the adjusted threshold\n\n"
         << "| threshold | full resolution | level 0 | level 1 | level 2 | level 3 |\n"
         << "| --- | --- | --- | --- | --- | --- |\n";
      std::vector<double> rows{ 0.0 };
      rows.insert(rows.end(), thresholds.begin(), thresholds.end());
      for (double th : rows)
      {
        md << "| " << (th == 0.0 ? "no optimizer" : Fmt(th));
        for (int level = -1; level <= 3; ++level)
        {
          for (const auto& r : results)
          {
            if (r.Face == face.Name && r.Run.Pipe <= 1 && r.Run.Level == level &&
              r.Run.Threshold == th)
            {
              md << " | " << Fmt(1e3 / r.FrameMs, 4) << " (" << Fmt(r.Active, 2) << ")";
              break;
            }
          }
        }
        md << " |\n";
      }
    }
  }
  if (!images.empty())
  {
    for (const LevelFace& face : faces)
    {
      try
      {
        PlotLevels(results, face.Name, thresholds,
          images + "/figure3_levels_" + Slug(face.Name.substr(0, face.Name.find(' ', 4))) + ".png");
      }
      catch (const std::exception& e)
      {
        std::cerr << "error: " << e.what() << "\n";
        return 1;
      }
    }
  }
  return 0;
}
} // namespace

int main(int argc, char* argv[])
{
  bool smoke = false;
  std::string textFile = std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/long-text.txt";
  std::string defaultFace =
    std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
  std::string ictFace = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  std::string rig = std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json";
  std::string head = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
  std::string avatarFile = std::string(MORPHNODE_AVATAR_DIR) + "/makehuman_avatar.glb";
  std::string avatarRig = std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/readyplayerme.json";
  std::string csv, markdown, images;
  bool levels = false;
  double fps = 25.0, seconds = 0.0;
  int width = 640, height = 480;
  CLI::App app("BenchAvatarFrameRate: the paper's Figure 3, frame rate against threshold per "
               "optimizer method for the whole avatar (docs/benchmarks.md). Run under xvfb-run -a.",
    "BenchAvatarFrameRate");
  app.add_flag(
    "--smoke", smoke, "a handful of frames of one threshold (CI; nothing timed asserted)");
  app.add_option("--text", textFile, "what is said")->capture_default_str();
  morphnode::appkit::AddNumberOption(app, "--fps", fps, 1.0, 240.0, "frame rate of the track");
  morphnode::appkit::AddNumberOption(
    app, "--seconds", seconds, 0.0, 86400.0, "play only this much (0: all)");
  app.add_option("--face", defaultFace, "the default face")->capture_default_str();
  app.add_option("--ict", ictFace, "the ICT face (skipped when missing)")->capture_default_str();
  app.add_option("--rig", rig, "the ARKit rig")->capture_default_str();
  app.add_flag("--levels", levels,
    "mesh levels: the whole avatar at full resolution, each level and each device profile, "
    "and Figure 3 with levels (default face, ICT head, MakeHuman avatar)");
  app.add_option("--head", head, "--levels: the ICT head (every mesh; skipped when missing)")
    ->capture_default_str();
  app
    .add_option("--avatar", avatarFile,
      "--levels: the MakeHuman avatar (every part, at rest; skipped when missing)")
    ->capture_default_str();
  app.add_option("--avatar-rig", avatarRig, "--levels: the rig of the MakeHuman avatar's targets")
    ->capture_default_str();
  app.add_option("--csv", csv, "write the results as CSV");
  app.add_option("--markdown", markdown, "write the results as markdown (docs/benchmarks.md)");
  app.add_option("--images", images, "write the Figure 3 plots into this folder");
  morphnode::appkit::AddSizeOption(app, "--size", width, height, "offscreen window size");
  morphnode::appkit::ParseCommandLine(app, argc, argv);

  const std::string text = ReadText(textFile);
  if (text.empty())
  {
    std::cerr << "cannot read " << textFile << "\n";
    return 1;
  }
  morphnode::SpeechOptions options;
  options.Voice = "en";
  options.Visemes = morphnode::VisemeSet::Paper6;
  options.Coarticulation.FrameRate = fps;
  options.EstimatePitch = false;
  const morphnode::Utterance u = morphnode::SpeakText(text, options);
  const morphnode::WeightTrack& track = u.Visemes;
  size_t frames = track.GetNumberOfFrames();
  if (seconds > 0)
  {
    frames = std::min(frames, static_cast<size_t>(seconds * fps));
  }
  if (smoke)
  {
    frames = std::min<size_t>(frames, 5);
  }
  std::cout << "Text: " << textFile << " (" << u.Duration << " s spoken, "
            << track.GetNumberOfFrames() << " frames at " << fps << " fps; playing " << frames
            << ")\n";

  if (levels)
  {
    std::vector<LevelFace> levelFaces{ { "default face", defaultFace, "", 0 } };
    const LevelFace more[] = { { "ICT head (paper shapes by the ARKit rig)", head, rig, -1 },
      { "MakeHuman avatar (paper shapes by the Ready Player Me rig)", avatarFile, avatarRig, -1 } };
    for (const LevelFace& face : more)
    {
      if (std::ifstream(face.File) && std::ifstream(face.Rig))
      {
        levelFaces.push_back(face);
      }
      else
      {
        std::cout << "'" << face.File << "' or '" << face.Rig << "' not found: " << face.Name
                  << " skipped\n";
      }
    }
    if (!images.empty())
    {
      std::error_code ec;
      std::filesystem::create_directories(images, ec);
    }
    return RunLevels(levelFaces, track, frames, smoke, width, height, textFile, u.Duration, fps,
      csv, markdown, images);
  }

  std::vector<double> thresholds{ 0.1, 0.2, 0.3, 0.4, 0.5 };
  if (smoke)
  {
    thresholds = { 0.3 };
  }
  std::vector<Method> methods{ PresetMethod(OptimizerPreset::None, 0.0),
    PresetMethod(OptimizerPreset::ErrorBounded, 0.0) };
  for (double th : thresholds)
  {
    methods.push_back(PresetMethod(OptimizerPreset::FixedMaximum, th));
    methods.push_back(PresetMethod(OptimizerPreset::FixedRemaining, th));
    methods.push_back(PresetMethod(OptimizerPreset::Adjusted, th));
    methods.push_back({ AdjustedBounded, th });
  }

  std::vector<std::pair<std::string, std::string>> faces{ { "default face", defaultFace } };
  if (std::ifstream(ictFace) && std::ifstream(rig))
  {
    faces.emplace_back("ICT face (ARKit rig, paper shapes)", ictFace);
  }
  else
  {
    std::cout << "ICT face or rig not found: default face only\n";
  }

  if (!images.empty()) // before minutes of playing, not after
  {
    std::error_code ec;
    std::filesystem::create_directories(images, ec);
    if (ec)
    {
      std::cerr << "error: cannot create the image folder '" << images << "': " << ec.message()
                << "\n";
      return 1;
    }
  }
  std::vector<Result> results;
  for (const auto& [faceName, file] : faces)
  {
    Avatar avatar;
    avatar.Name = faceName;
    if (!avatar.Setup(
          file, faceName == "default face" ? "" : rig, track.GetChannels(), width, height))
    {
      return 1;
    }
    std::cout
      << "\n"
      << faceName << " ("
      << vtkPointSet::SafeDownCast(avatar.Morph->GetOutputDataObject(0))->GetNumberOfPoints()
      << " points, " << avatar.Morph->GetNumberOfTargets() << " targets)\n";
    // Warm up: caches, the GL pipeline, the first VBO upload.
    {
      double a = 0, b = 0, c = 0;
      avatar.Configure(methods[0]);
      avatar.Play(track, 0, std::min<size_t>(frames, 25), a, b, c);
    }
    // The track is played in chunks of 100 frames, every method on each chunk in turn, so
    // that a change of machine load over the run hits all methods alike.
    std::vector<double> morphs(methods.size(), 0.0), wholes(methods.size(), 0.0),
      actives(methods.size(), 0.0);
    for (size_t chunk = 0; chunk < frames; chunk += 100)
    {
      for (size_t k = 0; k < methods.size(); ++k)
      {
        avatar.Configure(methods[k]);
        avatar.Play(track, chunk, std::min(frames, chunk + 100), morphs[k], wholes[k], actives[k]);
      }
    }
    double noneMorph = 0.0, noneFrame = 0.0;
    for (size_t k = 0; k < methods.size(); ++k)
    {
      const Method& m = methods[k];
      const double morph = morphs[k], whole = wholes[k], active = actives[k];
      Result r;
      r.Face = faceName;
      r.M = m;
      r.Frames = frames;
      r.MorphFps = frames / std::max(morph, 1e-12);
      r.FrameFps = frames / std::max(whole, 1e-12);
      r.MeanActive = active / std::max<size_t>(frames, 1);
      if (m.Name == "none")
      {
        noneMorph = r.MorphFps;
        noneFrame = r.FrameFps;
      }
      r.MorphSpeedup = r.MorphFps / noneMorph;
      r.FrameSpeedup = r.FrameFps / noneFrame;
      results.push_back(r);
      std::cout << std::left << std::setw(20) << m.Name << std::setw(6)
                << (m.Threshold == 0.0 ? "-" : Fmt(m.Threshold)) << " morph " << std::setw(9)
                << Fmt(r.MorphFps, 4) << " fps  frame " << std::setw(8) << Fmt(r.FrameFps, 4)
                << " fps  active " << std::setw(6) << Fmt(r.MeanActive) << " speed-up morph "
                << std::setw(6) << Fmt(r.MorphSpeedup) << " frame " << Fmt(r.FrameSpeedup)
                << std::endl;
    }
  }

  if (!csv.empty())
  {
    std::ofstream out(csv);
    out << "face,method,threshold,frames,morph_fps,frame_fps,mean_active_targets,morph_speedup,"
           "frame_speedup\n";
    for (const auto& r : results)
    {
      out << '"' << r.Face << "\"," << r.M.Name << "," << r.M.Threshold << "," << r.Frames << ","
          << r.MorphFps << "," << r.FrameFps << "," << r.MeanActive << "," << r.MorphSpeedup << ","
          << r.FrameSpeedup << "\n";
    }
  }
  if (!markdown.empty())
  {
    std::ofstream md(markdown);
    md << "<!-- generated by BenchAvatarFrameRate --markdown; do not edit -->\n";
    if (smoke)
    {
      md << "\n**Smoke run: a handful of frames, not measurements.**\n";
    }
    md << "\nText: `" << textFile.substr(textFile.find_last_of('/') + 1) << "`, " << Fmt(u.Duration)
       << " s of speech, " << frames << " frames at " << fps << " fps, rendered offscreen at "
       << width << "x" << height
       << ". Error-bounded and adjusted-bounded: eps = 0.5 % of the face's diagonal.\n";
    for (const auto& face : faces)
    {
      md << "\n**" << face.first << "**\n\n"
         << "| method | threshold | morph fps | frame fps | mean active targets | morph speed-up | "
            "frame speed-up |\n"
         << "| --- | --- | --- | --- | --- | --- | --- |\n";
      for (const auto& r : results)
      {
        if (r.Face == face.first)
        {
          md << "| " << r.M.Name << " | " << (r.M.Threshold == 0.0 ? "-" : Fmt(r.M.Threshold))
             << " | " << Fmt(r.MorphFps, 4) << " | " << Fmt(r.FrameFps, 4) << " | "
             << Fmt(r.MeanActive) << " | " << Fmt(r.MorphSpeedup) << " x | " << Fmt(r.FrameSpeedup)
             << " x |\n";
        }
      }
    }
  }
  if (!images.empty())
  {
    for (const auto& face : faces)
    {
      const std::string slug = Slug(face.first.substr(0, face.first.find(' ', 4)));
      try
      {
        Plot(results, face.first, true, thresholds, images + "/figure3_" + slug + "_frame.png");
        Plot(results, face.first, false, thresholds, images + "/figure3_" + slug + "_morph.png");
      }
      catch (const std::exception& e)
      {
        std::cerr << "error: " << e.what() << "\n";
        return 1;
      }
    }
  }
  return 0;
}
