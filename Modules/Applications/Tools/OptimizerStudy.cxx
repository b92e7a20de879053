// SPDX-License-Identifier: BSD-3-Clause
// OptimizerStudy: the paper's future work. Runs a whole weight track through every
// optimization method and measures, per frame, the active targets, the RMS and largest
// vertex error against the unoptimized face, and the morph time.
//
//   OptimizerStudy --face face.glb --track weights.csv --out DIR
//                  [--thresholds 0.1,0.2,0.3,0.4,0.5] [--bounds 0.0005,0.001,0.002]
//                  [--budgets 4,8] [--figure5-threshold 0.3] [--figure5-window 10,20]
//                  [--sweep 0.02]
//
// The track holds relative (glTF) target weights, one column per target name. Methods are
// named by the optimizer presets (StudyMethods.h). Writes DIR/frames.csv (every frame of
// every method), DIR/summary.md, DIR/summary.csv, and the plots DIR/weights_over_time.png
// (the paper's Figure 5, over the window in seconds; the whole track when no window is
// given), DIR/error_vs_active.png (mean RMS error) and DIR/max_error_vs_active.png (mean
// of the per-frame largest vertex error).
//
// Thresholds move the active-target count, so "adjusted beats fixed" must be judged at an
// equal count: --sweep STEP also runs fixed-remaining and adjusted at thresholds STEP,
// 2 STEP, ... 0.7 (curves in the plots, DIR/sweep.csv) and writes DIR/matched.md / .csv:
// for each threshold's adjusted run, the fixed-remaining errors interpolated at the same
// mean active-target count. --sweep 0 turns this off.
//
// Every method with an error bound eps also gets the number of frames whose largest
// vertex error exceeds eps ("frames over bound"): it must be 0.
#include "CommandLine.h"
#include "OptimizerStudyPlots.h"
#include "Progress.h"
#include "StudyMethods.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "base/Error.h"
#include "morph/MorphMesh.h"
#include "morph/OptimizerQuality.h"

#include "vtkNew.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

namespace
{
using namespace morphnode;
using namespace morphnode::study;

struct Options
{
  std::string Face, Track, Out = "optimizer-study";
  std::vector<double> Thresholds{ 0.1, 0.2, 0.3, 0.4, 0.5 }, Bounds{ 0.0005, 0.001, 0.002 },
    Budgets{ 4, 8 }, Window;
  double Figure5 = 0.3, Sweep = 0.02;
};

Options ParseOptions(int argc, char* argv[])
{
  Options o;
  CLI::App app("OptimizerStudy: every optimizer method over a weight track, vertex error "
               "against the unoptimized face, tables and plots (docs/optimizer-study.md).",
    "OptimizerStudy");
  app.add_option("--face", o.Face, "the face (glTF/GLB)")->required()->check(CLI::ExistingFile);
  app.add_option("--track", o.Track, "relative target weights, CSV (MakeSpeechTrack)")
    ->required()
    ->check(CLI::ExistingFile);
  app.add_option("--out", o.Out, "output folder")->capture_default_str();
  appkit::AddNumberListOption(
    app, "--thresholds", o.Thresholds, 0.0, 1.0, "th_fix of the threshold methods");
  appkit::AddNumberListOption(
    app, "--bounds", o.Bounds, 0.0, 1e30, "eps of error-bounded, model units");
  appkit::AddNumberListOption(app, "--budgets", o.Budgets, 1.0, 1e6, "target counts of the budget");
  appkit::AddNumberOption(app, "--figure5-threshold", o.Figure5, 0.0, 1.0,
    "the threshold of Figure 5's fixed-remaining and adjusted panels");
  appkit::AddNumberListOption(app, "--figure5-window", o.Window, 0.0, 1e6,
    "FROM,TO seconds of Figure 5 (default: the whole track)")
    ->default_str("");
  appkit::AddNumberOption(app, "--sweep", o.Sweep, 0.0, 0.7,
    "threshold step of the sweep comparing fixed-remaining and adjusted at equal active "
    "targets; 0: no sweep");
  appkit::ParseCommandLine(app, argc, argv);
  if (!o.Window.empty() && o.Window.size() != 2)
  {
    appkit::FailUsage(app, "--figure5-window takes two times, FROM,TO");
  }
  return o;
}

struct Summary
{
  double Active = 0, Rms = 0, RmsMax = 0, MeanMax = 0, MaxError = 0, Bound = 0, Time = 0;
  int OverBound = 0; ///< frames whose largest vertex error exceeds the method's eps
};

Summary Summarize(const std::vector<FrameQuality>& result, double eps)
{
  Summary s;
  for (const auto& q : result)
  {
    s.Active += q.ActiveTargets;
    s.Rms += q.RmsError;
    s.RmsMax = std::max(s.RmsMax, q.RmsError);
    s.MeanMax += q.MaxError;
    s.MaxError = std::max(s.MaxError, q.MaxError);
    s.Bound = std::max(s.Bound, q.ErrorBound);
    s.Time += q.MorphSeconds;
    if (eps > 0.0 && q.MaxError > eps)
    {
      ++s.OverBound;
    }
  }
  const double n = std::max<double>(1.0, static_cast<double>(result.size()));
  s.Active /= n;
  s.Rms /= n;
  s.MeanMax /= n;
  return s;
}

/// Linear interpolation of (x, y) points (any order) at x; NaN outside their range.
double Interpolate(std::vector<std::pair<double, double>> points, double x)
{
  std::sort(points.begin(), points.end());
  for (size_t k = 1; k < points.size(); ++k)
  {
    const auto& [x0, y0] = points[k - 1];
    const auto& [x1, y1] = points[k];
    if (x >= x0 && x <= x1)
    {
      return x1 > x0 ? y0 + (y1 - y0) * (x - x0) / (x1 - x0) : y0;
    }
  }
  return std::nan("");
}

constexpr double Mm = 1000.0; // the faces are in metres

/// The face's positions and target distances, read through the VTK filter.
struct Face
{
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphNodeFilter> Morph;
  const MorphMesh* Model = nullptr;
  const MorphAttribute<float>* Positions = nullptr;
  TargetDistances Distances;

  void Read(const std::string& file)
  {
    this->Reader->SetFileName(file.c_str());
    this->Reader->SetMeshIndex(0); // the face mesh as one vtkPolyData
    this->Reader->SetNormalsMode(
      vtkMorphTargetReader::NORMALS_FROM_FILE); // vertex error: positions only
    this->Morph->SetInputConnection(this->Reader->GetOutputPort());
    this->Morph->SetWeightModeToRelative();
    this->Morph->Update();
    this->Model = this->Morph->GetMorphModel();
    if (!this->Model || this->Model->GetPositionAttribute() < 0)
    {
      throw InputError("could not read a face from " + file);
    }
    this->Positions = std::get_if<MorphAttribute<float>>(
      &this->Model->GetAttribute(static_cast<size_t>(this->Model->GetPositionAttribute())));
    if (!this->Positions)
    {
      throw InputError("the study expects float positions");
    }
    this->Distances = this->Model->ComputeDistances();
  }
};

/// What the runs collect for the plots and the matched comparison.
struct Results
{
  std::vector<MethodRun> Figure5Runs;
  std::vector<std::tuple<std::string, double, double>> RmsPoints, MaxPoints;
  std::map<double, Summary> AdjustedAt;                      // threshold -> adjusted summary
  std::vector<std::pair<double, double>> FixedRms, FixedMax; // sweep: active -> error
};

/// The study's methods: frames.csv, summary.csv/.md, and what the plots need.
std::string RunMethods(const Options& o, const Face& face, const WeightTrack& absolute,
  const std::vector<OptimizerMethod>& methods, bool sweep, appkit::ProgressBar& progress,
  Results& r)
{
  std::ofstream frames(o.Out + "/frames.csv");
  frames << "method,frame,time,active_targets,rms_error,max_error,error_bound,morph_us\n";
  std::ofstream summaryCsv(o.Out + "/summary.csv");
  summaryCsv
    << "method,mean_active_targets,mean_rms_error_mm,max_rms_error_mm,mean_max_vertex_error_mm,"
       "max_vertex_error_mm,max_error_bound_mm,frames_over_bound,mean_morph_us,morph_speedup\n";
  std::ostringstream md;
  md << "| method | mean active targets | mean RMS error (mm) | max RMS error (mm) | mean max "
        "vertex error (mm) | max vertex error (mm) | max bound B (mm) | frames over eps | morph "
        "speed-up |\n"
     << "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  double noneTime = 0.0;
  for (size_t m = 0; m < methods.size(); ++m)
  {
    progress.Show(static_cast<int>(m), methods[m].Name);
    const auto& settings = methods[m].Settings;
    const auto result =
      MeasureOptimizerQuality(*face.Positions, face.Distances, absolute, methods[m]);
    for (size_t f = 0; f < result.size(); ++f)
    {
      const auto& q = result[f];
      frames << methods[m].Name << "," << f << "," << absolute.GetTime(f) << "," << q.ActiveTargets
             << "," << q.RmsError << "," << q.MaxError << "," << q.ErrorBound << ","
             << q.MorphSeconds * 1e6 << "\n";
    }
    const Summary s = Summarize(result, settings.MaxVertexError);
    const double n = std::max<double>(1.0, static_cast<double>(result.size()));
    if (m == 0)
    {
      noneTime = s.Time;
    }
    const double speedup = s.Time > 0 ? noneTime / s.Time : 0.0;
    const std::string over = settings.MaxVertexError > 0.0 ? std::to_string(s.OverBound) : "-";
    summaryCsv << methods[m].Name << "," << s.Active << "," << s.Rms * Mm << "," << s.RmsMax * Mm
               << "," << s.MeanMax * Mm << "," << s.MaxError * Mm << "," << s.Bound * Mm << ","
               << over << "," << s.Time / n * 1e6 << "," << speedup << "\n";
    md << std::fixed << "| " << methods[m].Name << " | " << std::setprecision(2) << s.Active
       << " | " << std::setprecision(3) << s.Rms * Mm << " | " << s.RmsMax * Mm << " | "
       << s.MeanMax * Mm << " | " << s.MaxError * Mm << " | " << s.Bound * Mm << " | " << over
       << " | " << std::setprecision(2) << speedup << " x |\n";
    md.unsetf(std::ios::floatfield);
    // With a sweep, its finer curves stand for fixed-remaining and adjusted in the plots.
    if (m > 0 && (!sweep || settings.Strategy != Redistribution::Remaining))
    {
      r.RmsPoints.emplace_back(methods[m].Name, s.Active, s.Rms * Mm);
      r.MaxPoints.emplace_back(methods[m].Name, s.Active, s.MeanMax * Mm);
    }
    if (settings.AdjustThreshold && settings.Strategy == Redistribution::Remaining)
    {
      r.AdjustedAt[settings.Threshold] = s;
    }
    const bool figure5Method = m == 0 ||
      (std::abs(settings.Threshold - o.Figure5) < 1e-12 &&
        settings.Strategy == Redistribution::Remaining);
    if (figure5Method)
    {
      r.Figure5Runs.emplace_back(methods[m].Name, result);
    }
  }
  std::ofstream(o.Out + "/summary.md") << md.str();
  return md.str();
}

/// The sweep: sweep.csv and the fixed-remaining curve the matched comparison reads.
void RunSweep(const Options& o, const Face& face, const WeightTrack& absolute,
  const std::vector<OptimizerMethod>& sweep, int done, appkit::ProgressBar& progress, Results& r)
{
  std::ofstream sweepCsv(o.Out + "/sweep.csv");
  sweepCsv << "method,threshold,mean_active_targets,mean_rms_error_mm,mean_max_vertex_error_mm\n";
  for (size_t k = 0; k < sweep.size(); ++k)
  {
    progress.Show(done + static_cast<int>(k), sweep[k].Name);
    const auto s =
      Summarize(MeasureOptimizerQuality(*face.Positions, face.Distances, absolute, sweep[k]), 0.0);
    const auto& settings = sweep[k].Settings;
    sweepCsv << sweep[k].Name << "," << settings.Threshold << "," << s.Active << "," << s.Rms * Mm
             << "," << s.MeanMax * Mm << "\n";
    r.RmsPoints.emplace_back(sweep[k].Name, s.Active, s.Rms * Mm);
    r.MaxPoints.emplace_back(sweep[k].Name, s.Active, s.MeanMax * Mm);
    if (!settings.AdjustThreshold)
    {
      r.FixedRms.emplace_back(s.Active, s.Rms * Mm);
      r.FixedMax.emplace_back(s.Active, s.MeanMax * Mm);
    }
  }
}

/// matched.md/.csv: each adjusted run against fixed-remaining at the same active count.
std::string WriteMatched(const Options& o, const Results& r)
{
  std::ostringstream matched;
  std::ofstream matchedCsv(o.Out + "/matched.csv");
  matchedCsv << "threshold,mean_active_targets,adjusted_rms_mm,fixed_rms_mm,adjusted_mean_max_mm,"
                "fixed_mean_max_mm\n";
  matched << "| threshold | mean active targets (adjusted) | mean RMS error: adjusted / fixed (mm) "
             "| mean max vertex error: adjusted / fixed (mm) |\n"
          << "| --- | --- | --- | --- |\n";
  for (const auto& [th, s] : r.AdjustedAt)
  {
    const double rms = Interpolate(r.FixedRms, s.Active), mx = Interpolate(r.FixedMax, s.Active);
    matchedCsv << th << "," << s.Active << "," << s.Rms * Mm << "," << rms << "," << s.MeanMax * Mm
               << "," << mx << "\n";
    matched << std::fixed << "| " << std::setprecision(2) << th << " | " << s.Active << " | "
            << std::setprecision(3) << s.Rms * Mm << " / " << rms << " (" << std::setprecision(0)
            << 100.0 * (s.Rms * Mm / rms - 1.0) << " %) | " << std::setprecision(3)
            << s.MeanMax * Mm << " / " << mx << " (" << std::setprecision(0)
            << 100.0 * (s.MeanMax * Mm / mx - 1.0) << " %) |\n";
  }
  std::ofstream(o.Out + "/matched.md") << matched.str();
  return matched.str();
}
} // namespace

int main(int argc, char* argv[])
{
  const Options o = ParseOptions(argc, argv);
  try
  {
    Face face;
    face.Read(o.Face);
    std::ifstream csv(o.Track);
    if (!csv)
    {
      throw InputError("cannot open " + o.Track);
    }
    const WeightTrack absolute =
      ToAbsoluteWeights(WeightTrack::ReadCsv(csv), face.Model->GetTargetNames());
    const std::vector<int> budgets(o.Budgets.begin(), o.Budgets.end());
    const auto methods = StudyMethods(o.Thresholds, o.Bounds, budgets);
    const auto sweep = SweepMethods(o.Sweep);

    std::filesystem::create_directories(o.Out);
    appkit::ProgressBar progress(static_cast<int>(methods.size() + sweep.size()), "methods");
    Results results;
    const std::string summary =
      RunMethods(o, face, absolute, methods, !sweep.empty(), progress, results);
    RunSweep(o, face, absolute, sweep, static_cast<int>(methods.size()), progress, results);
    progress.Show(static_cast<int>(methods.size() + sweep.size()));
    std::cout << summary;
    if (!sweep.empty())
    {
      std::cout << "\nadjusted against fixed-remaining at the same mean active-target count\n"
                << WriteMatched(o, results);
    }

    const double from = o.Window.empty() ? 0.0 : o.Window[0],
                 to = o.Window.empty() ? 0.0 : o.Window[1];
    PlotWeightsOverTime(results.Figure5Runs, face.Model->GetTargetNames(), absolute.GetFrameRate(),
      from, to, o.Out + "/weights_over_time.png");
    PlotErrorVsActive(results.RmsPoints, "Mean RMS vertex error against mean active targets",
      "RMS vertex error (mm)", o.Out + "/error_vs_active.png");
    PlotErrorVsActive(results.MaxPoints, "Mean largest vertex error against mean active targets",
      "largest vertex error per frame, mean (mm)", o.Out + "/max_error_vs_active.png");
    std::cout << "wrote " << o.Out
              << "/{frames.csv,summary.csv,summary.md,sweep.csv,matched.csv,matched.md,weights_"
                 "over_time.png,"
                 "error_vs_active.png,max_error_vs_active.png}\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "OptimizerStudy: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
