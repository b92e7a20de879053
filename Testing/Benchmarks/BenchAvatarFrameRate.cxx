// SPDX-License-Identifier: BSD-3-Clause
// The paper's Figure 3 (Berner, WSCG 2004): frame rate against threshold per optimization
// method, for the whole avatar -- morph and offscreen render -- speaking a long text.
//
//   BenchAvatarFrameRate [--smoke] [--text FILE] [--fps 25] [--seconds S]
//                        [--face default.glb] [--ict ict.glb] [--rig arkit.json]
//                        [--csv FILE] [--markdown FILE] [--images DIR] [--size WxH]
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
#include "CommandLine.h"
#include "ImageOutput.h"
#include "OptimizerSetup.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigBaker.h"
#include "vtkMorphTargetReader.h"

#include "morph/OptimizerPresets.h"
#include "speech/Speech.h"

#include "vtkActor.h"
#include "vtkAxis.h"
#include "vtkCamera.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkPointSet.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
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

/// fps against threshold, a line per method, "none" as a flat line: the paper's Figure 3.
void Plot(const std::vector<Result>& results, const std::string& face, bool wholeFrame,
  const std::vector<double>& thresholds, const std::string& file)
{
  const std::string names[] = { "none", "fixed-maximum", "fixed-remaining", "adjusted",
    AdjustedBounded, "error-bounded" };
  const unsigned char colors[][3] = { { 0, 0, 0 }, { 228, 26, 28 }, { 55, 126, 184 },
    { 77, 175, 74 }, { 152, 78, 163 }, { 255, 127, 0 } };
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(800, 500);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  chart->SetTitle(
    (face + (wholeFrame ? ": whole frame (morph + render)" : ": morph stage")).c_str());
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("frames per second");
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("threshold");
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  view->GetScene()->AddItem(chart);
  for (int m = 0; m < 6; ++m)
  {
    vtkNew<vtkTable> table;
    vtkNew<vtkFloatArray> x, y;
    x->SetName("threshold");
    y->SetName(names[m].c_str());
    table->AddColumn(x);
    table->AddColumn(y);
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
    table->SetNumberOfRows(static_cast<vtkIdType>(points.size()));
    for (size_t i = 0; i < points.size(); ++i)
    {
      table->SetValue(static_cast<vtkIdType>(i), 0, points[i].first);
      table->SetValue(static_cast<vtkIdType>(i), 1, points[i].second);
    }
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, 1);
    line->SetColor(colors[m][0], colors[m][1], colors[m][2], 255);
    line->SetWidth(2.0);
    if (m == 0 || m == 5)
    {
      line->GetPen()->SetLineType(vtkPen::DASH_LINE);
    }
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
} // namespace

int main(int argc, char* argv[])
{
  bool smoke = false;
  std::string textFile = std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/long-text.txt";
  std::string defaultFace =
    std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
  std::string ictFace = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
  std::string rig = std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json";
  std::string csv, markdown, images;
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
