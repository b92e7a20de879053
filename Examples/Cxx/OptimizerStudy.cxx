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
// The track holds relative (glTF) target weights, one column per target name. Writes
// DIR/frames.csv (every frame of every method), DIR/summary.md, DIR/summary.csv, and the
// plots DIR/weights_over_time.png (the paper's Figure 5, over the window in seconds; the
// whole track when no window is given), DIR/error_vs_active.png (mean RMS error) and
// DIR/max_error_vs_active.png (mean of the per-frame largest vertex error).
//
// Thresholds move the active-target count, so "adjusted beats fixed" must be judged at an
// equal count: --sweep STEP also runs fixed+remaining and adjusted+remaining at thresholds
// STEP, 2 STEP, ... 0.7 (curves in the plots, DIR/sweep.csv) and writes DIR/matched.md /
// .csv: for each threshold's adjusted+remaining run, the fixed+remaining errors
// interpolated at the same mean active-target count. --sweep 0 turns this off.
//
// Every method with an error bound eps also gets the number of frames whose largest
// vertex error exceeds eps ("frames over bound"): it must be 0.
#include "ExampleUtilities.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "base/Error.h"
#include "morph/MorphMesh.h"
#include "morph/OptimizerQuality.h"

#include "vtkAxis.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <iostream>
#include <numeric>
#include <sstream>

namespace
{
using morphnode_examples::WritePng;
using morphnode_examples::ParseList;
void Progress(size_t done, size_t total, const std::string& what)
{
  const int width = 30;
  const int filled = static_cast<int>(width * done / std::max<size_t>(total, 1));
  std::cerr << "\r[" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done
            << "/" << total << " " << std::left << std::setw(28) << what << std::flush;
  if (done == total)
  {
    std::cerr << "\n";
  }
}

/// The paper's Figure 5: one chart per method, a line per target, weight over time.
void PlotWeightsOverTime(const std::vector<std::pair<std::string, std::vector<morphnode::FrameQuality>>>& runs,
  const std::vector<std::string>& names, double frameRate, double from, double to, const std::string& file)
{
  // The targets that matter: largest total weight in the unoptimized run.
  const auto& none = runs.front().second;
  std::vector<size_t> order(names.size() - 1);
  std::iota(order.begin(), order.end(), 1);
  std::vector<double> total(names.size(), 0.0);
  for (const auto& f : none)
  {
    for (size_t t = 1; t < names.size(); ++t)
    {
      total[t] += f.Weights[t];
    }
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return total[a] > total[b]; });
  order.resize(std::min<size_t>(order.size(), 8));

  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(1000, 250 * static_cast<int>(runs.size()));
  view->GetRenderer()->SetBackground(1, 1, 1);
  const unsigned char colors[8][3] = { { 31, 119, 180 }, { 255, 127, 14 }, { 44, 160, 44 },
    { 214, 39, 40 }, { 148, 103, 189 }, { 140, 86, 75 }, { 227, 119, 194 }, { 127, 127, 127 } };
  for (size_t r = 0; r < runs.size(); ++r)
  {
    vtkNew<vtkTable> table;
    vtkNew<vtkFloatArray> time;
    time->SetName("time (s)");
    table->AddColumn(time);
    for (size_t t : order)
    {
      vtkNew<vtkFloatArray> column;
      column->SetName(names[t].c_str());
      table->AddColumn(column);
    }
    const auto& frames = runs[r].second;
    for (size_t f = 0; f < frames.size(); ++f)
    {
      const double t = f / frameRate;
      if (to > from && (t < from || t > to))
      {
        continue;
      }
      const vtkIdType row = table->InsertNextBlankRow();
      table->SetValue(row, 0, t);
      for (size_t k = 0; k < order.size(); ++k)
      {
        table->SetValue(row, static_cast<vtkIdType>(k + 1), frames[f].Weights[order[k]]);
      }
    }
    vtkNew<vtkChartXY> chart;
    chart->SetTitle(runs[r].first);
    chart->GetTitleProperties()->SetFontSize(14);
    chart->GetAxis(vtkAxis::LEFT)->SetTitle("weight");
    chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::LEFT)->SetRange(0.0, 1.05);
    chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
    chart->SetShowLegend(r == 0);
    for (size_t k = 0; k < order.size(); ++k)
    {
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(table, 0, static_cast<vtkIdType>(k + 1));
      line->SetColor(colors[k][0], colors[k][1], colors[k][2], 255);
      line->SetWidth(1.5);
    }
    const float h = 1.0f / runs.size();
    chart->SetAutoSize(false);
    chart->SetSize(vtkRectf(0, (runs.size() - 1 - r) * h * 250 * runs.size(), 1000, h * 250 * runs.size()));
    view->GetScene()->AddItem(chart);
  }
  WritePng(view, file);
}

/// Mean RMS vertex error against mean active targets, one point per method.
void PlotErrorVsActive(std::vector<std::tuple<std::string, double, double>> points, const std::string& title,
  const std::string& yTitle, const std::string& file)
{
  // One line per family (the name up to the first blank), by increasing active count.
  std::stable_sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return std::get<1>(a) < std::get<1>(b); });
  std::map<std::string, vtkSmartPointer<vtkTable>> families;
  for (const auto& [name, active, error] : points)
  {
    const std::string family = name.substr(0, name.find(' '));
    auto& table = families[family];
    if (!table)
    {
      table = vtkSmartPointer<vtkTable>::New();
      vtkNew<vtkFloatArray> x, y;
      x->SetName("mean active targets");
      y->SetName(family.c_str());
      table->AddColumn(x);
      table->AddColumn(y);
    }
    const vtkIdType row = table->InsertNextBlankRow();
    table->SetValue(row, 0, active);
    table->SetValue(row, 1, error);
  }
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(800, 500);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  chart->SetTitle(title);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(yTitle);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("mean active targets");
  chart->SetShowLegend(true);
  const unsigned char colors[5][3] = { { 31, 119, 180 }, { 255, 127, 14 }, { 44, 160, 44 }, { 214, 39, 40 },
    { 148, 103, 189 } };
  int c = 0;
  for (auto& [family, table] : families)
  {
    vtkPlot* plot = chart->AddPlot(vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    plot->SetColor(colors[c][0], colors[c][1], colors[c][2], 255);
    plot->SetWidth(2.0);
    c = (c + 1) % 5;
  }
  view->GetScene()->AddItem(chart);
  WritePng(view, file);
}

struct Summary
{
  double Active = 0, Rms = 0, RmsMax = 0, MeanMax = 0, MaxError = 0, Bound = 0, Time = 0;
  int OverBound = 0; ///< frames whose largest vertex error exceeds the method's eps
};

Summary Summarize(const std::vector<morphnode::FrameQuality>& result, double eps)
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
} // namespace

int main(int argc, char* argv[])
{
  std::string face, track, out = "optimizer-study";
  std::vector<double> thresholds{ 0.1, 0.2, 0.3, 0.4, 0.5 }, bounds{ 0.0005, 0.001, 0.002 }, budgets{ 4, 8 };
  std::vector<double> window;
  double figure5 = 0.3, sweep = 0.02;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string arg = argv[i], value = argv[i + 1];
    if (arg == "--face")
      face = value;
    else if (arg == "--track")
      track = value;
    else if (arg == "--out")
      out = value;
    else if (arg == "--thresholds")
      thresholds = ParseList(value);
    else if (arg == "--bounds")
      bounds = ParseList(value);
    else if (arg == "--budgets")
      budgets = ParseList(value);
    else if (arg == "--figure5-threshold")
      figure5 = std::stod(value);
    else if (arg == "--figure5-window")
      window = ParseList(value);
    else if (arg == "--sweep")
      sweep = std::stod(value);
    else
    {
      std::cerr << "unknown option " << arg << "\n";
      return 2;
    }
  }
  if (face.empty() || track.empty() || argc % 2 == 0 || (!window.empty() && window.size() != 2))
  {
    std::cerr << "usage: OptimizerStudy --face face.glb --track weights.csv [--out DIR] ...\n";
    return 2;
  }
  try
  {
    vtkNew<vtkMorphTargetReader> reader;
    reader->SetFileName(face.c_str());
    reader->SetNormalsMode(vtkMorphTargetReader::NORMALS_FROM_FILE); // vertex error: positions only
    vtkNew<vtkMorphNodeFilter> morph;
    morph->SetInputConnection(reader->GetOutputPort());
    morph->SetWeightModeToRelative();
    morph->Update();
    const morphnode::MorphMesh* model = morph->GetMorphModel();
    if (!model || model->GetPositionAttribute() < 0)
    {
      std::cerr << "could not read a face from " << face << "\n";
      return 1;
    }
    const auto* positions = std::get_if<morphnode::MorphAttribute<float>>(
      &model->GetAttribute(static_cast<size_t>(model->GetPositionAttribute())));
    if (!positions)
    {
      std::cerr << "the study expects float positions\n";
      return 1;
    }
    std::ifstream csv(track);
    if (!csv)
    {
      std::cerr << "cannot open " << track << "\n";
      return 1;
    }
    const morphnode::WeightTrack absolute =
      morphnode::ToAbsoluteWeights(morphnode::WeightTrack::ReadCsv(csv), model->GetTargetNames());
    const morphnode::TargetDistances distances = model->ComputeDistances();
    std::vector<int> budgetCounts(budgets.begin(), budgets.end());
    const auto methods = morphnode::StudyMethods(thresholds, bounds, budgetCounts);

    // The sweep: fixed+remaining and adjusted+remaining on a fine threshold grid.
    std::vector<morphnode::OptimizerMethod> sweepMethods;
    if (sweep > 0.0)
    {
      for (int k = 1; k * sweep <= 0.7 + 1e-9; ++k)
      {
        std::ostringstream th;
        th << k * sweep;
        morphnode::OptimizerSettings s;
        s.Threshold = k * sweep;
        s.Strategy = morphnode::Redistribution::Remaining;
        sweepMethods.push_back({ "fixed+remaining " + th.str(), s });
        s.AdjustThreshold = true;
        sweepMethods.push_back({ "adjusted+remaining " + th.str(), s });
      }
    }

    std::filesystem::create_directories(out);
    std::ofstream frames(out + "/frames.csv");
    frames << "method,frame,time,active_targets,rms_error,max_error,error_bound,morph_us\n";
    std::ofstream summaryCsv(out + "/summary.csv");
    summaryCsv << "method,mean_active_targets,mean_rms_error_mm,max_rms_error_mm,mean_max_vertex_error_mm,"
                  "max_vertex_error_mm,max_error_bound_mm,frames_over_bound,mean_morph_us,morph_speedup\n";
    std::ostringstream md;
    md << "| method | mean active targets | mean RMS error (mm) | max RMS error (mm) | mean max vertex error (mm) | max vertex error (mm) | max bound B (mm) | frames over eps | morph speed-up |\n"
       << "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    std::vector<std::pair<std::string, std::vector<morphnode::FrameQuality>>> figure5Runs;
    std::vector<std::tuple<std::string, double, double>> rmsPoints, maxPoints;
    std::map<double, Summary> adjustedAt; // threshold -> adjusted+remaining summary
    double noneTime = 0.0;
    const double mm = 1000.0; // the faces are in metres
    const size_t total = methods.size() + sweepMethods.size();
    for (size_t m = 0; m < methods.size(); ++m)
    {
      Progress(m, total, methods[m].Name);
      const auto& settings = methods[m].Settings;
      const auto result = morphnode::MeasureOptimizerQuality(*positions, distances, absolute, methods[m]);
      for (size_t f = 0; f < result.size(); ++f)
      {
        const auto& q = result[f];
        frames << methods[m].Name << "," << f << "," << absolute.GetTime(f) << "," << q.ActiveTargets << ","
               << q.RmsError << "," << q.MaxError << "," << q.ErrorBound << "," << q.MorphSeconds * 1e6 << "\n";
      }
      const Summary s = Summarize(result, settings.MaxVertexError);
      const double n = std::max<double>(1.0, static_cast<double>(result.size()));
      if (m == 0)
      {
        noneTime = s.Time;
      }
      const double speedup = s.Time > 0 ? noneTime / s.Time : 0.0;
      const std::string over = settings.MaxVertexError > 0.0 ? std::to_string(s.OverBound) : "-";
      summaryCsv << methods[m].Name << "," << s.Active << "," << s.Rms * mm << "," << s.RmsMax * mm << ","
                 << s.MeanMax * mm << "," << s.MaxError * mm << "," << s.Bound * mm << "," << over << ","
                 << s.Time / n * 1e6 << "," << speedup << "\n";
      md << std::fixed << "| " << methods[m].Name << " | " << std::setprecision(2) << s.Active << " | "
         << std::setprecision(3) << s.Rms * mm << " | " << s.RmsMax * mm << " | " << s.MeanMax * mm << " | "
         << s.MaxError * mm << " | " << s.Bound * mm << " | " << over << " | " << std::setprecision(2) << speedup
         << " x |\n";
      md.unsetf(std::ios::floatfield);
      if (m > 0 && (sweepMethods.empty() || settings.Strategy != morphnode::Redistribution::Remaining))
      {
        rmsPoints.emplace_back(methods[m].Name, s.Active, s.Rms * mm);
        maxPoints.emplace_back(methods[m].Name, s.Active, s.MeanMax * mm);
      }
      if (settings.AdjustThreshold && settings.Strategy == morphnode::Redistribution::Remaining)
      {
        adjustedAt[settings.Threshold] = s;
      }
      const bool figure5Method = m == 0 ||
        (std::abs(settings.Threshold - figure5) < 1e-12 && settings.Strategy == morphnode::Redistribution::Remaining);
      if (figure5Method)
      {
        figure5Runs.emplace_back(methods[m].Name, result);
      }
    }

    std::vector<std::pair<double, double>> fixedRms, fixedMax;
    std::ofstream sweepCsv(out + "/sweep.csv");
    sweepCsv << "method,threshold,mean_active_targets,mean_rms_error_mm,mean_max_vertex_error_mm\n";
    for (size_t k = 0; k < sweepMethods.size(); ++k)
    {
      Progress(methods.size() + k, total, sweepMethods[k].Name);
      const auto s = Summarize(
        morphnode::MeasureOptimizerQuality(*positions, distances, absolute, sweepMethods[k]), 0.0);
      const auto& settings = sweepMethods[k].Settings;
      sweepCsv << sweepMethods[k].Name << "," << settings.Threshold << "," << s.Active << "," << s.Rms * mm
               << "," << s.MeanMax * mm << "\n";
      rmsPoints.emplace_back(sweepMethods[k].Name, s.Active, s.Rms * mm);
      maxPoints.emplace_back(sweepMethods[k].Name, s.Active, s.MeanMax * mm);
      if (!settings.AdjustThreshold)
      {
        fixedRms.emplace_back(s.Active, s.Rms * mm);
        fixedMax.emplace_back(s.Active, s.MeanMax * mm);
      }
    }
    Progress(total, total, "done");
    std::ofstream(out + "/summary.md") << md.str();
    std::cout << md.str();

    if (!sweepMethods.empty())
    {
      std::ostringstream matched;
      std::ofstream matchedCsv(out + "/matched.csv");
      matchedCsv << "threshold,mean_active_targets,adjusted_rms_mm,fixed_rms_mm,adjusted_mean_max_mm,fixed_mean_max_mm\n";
      matched << "| threshold | mean active targets (adjusted) | mean RMS error: adjusted / fixed (mm) | mean max vertex error: adjusted / fixed (mm) |\n"
              << "| --- | --- | --- | --- |\n";
      for (const auto& [th, s] : adjustedAt)
      {
        const double rms = Interpolate(fixedRms, s.Active), mx = Interpolate(fixedMax, s.Active);
        matchedCsv << th << "," << s.Active << "," << s.Rms * mm << "," << rms << "," << s.MeanMax * mm << "," << mx
                   << "\n";
        matched << std::fixed << "| " << std::setprecision(2) << th << " | " << s.Active << " | "
                << std::setprecision(3) << s.Rms * mm << " / " << rms << " (" << std::setprecision(0)
                << 100.0 * (s.Rms * mm / rms - 1.0) << " %) | " << std::setprecision(3) << s.MeanMax * mm << " / "
                << mx << " (" << std::setprecision(0) << 100.0 * (s.MeanMax * mm / mx - 1.0) << " %) |\n";
      }
      std::ofstream(out + "/matched.md") << matched.str();
      std::cout << "\nadjusted+remaining against fixed+remaining at the same mean active-target count\n"
                << matched.str();
    }

    const double from = window.empty() ? 0.0 : window[0], to = window.empty() ? 0.0 : window[1];
    PlotWeightsOverTime(figure5Runs, model->GetTargetNames(), absolute.GetFrameRate(), from, to,
      out + "/weights_over_time.png");
    PlotErrorVsActive(rmsPoints, "Mean RMS vertex error against mean active targets", "RMS vertex error (mm)",
      out + "/error_vs_active.png");
    PlotErrorVsActive(maxPoints, "Mean largest vertex error against mean active targets",
      "largest vertex error per frame, mean (mm)", out + "/max_error_vs_active.png");
    std::cout << "wrote " << out
              << "/{frames.csv,summary.csv,summary.md,sweep.csv,matched.csv,matched.md,weights_over_time.png,"
                 "error_vs_active.png,max_error_vs_active.png}\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
