// SPDX-License-Identifier: BSD-3-Clause
// OptimizerStudy: the paper's future work. Runs a whole weight track through every
// optimization method and measures, per frame, the active targets, the RMS and largest
// vertex error against the unoptimized face, and the morph time.
//
//   OptimizerStudy --face face.glb --track weights.csv --out DIR
//                  [--thresholds 0.1,0.2,0.3,0.4,0.5] [--bounds 0.0005,0.001,0.002]
//                  [--budgets 4,8] [--figure5-threshold 0.3]
//
// The track holds relative (glTF) target weights, one column per target name. Writes
// DIR/frames.csv (every frame of every method), DIR/summary.md, DIR/summary.csv, and the
// plots DIR/weights_over_time.png (the paper's Figure 5) and DIR/error_vs_active.png.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "morphnode/Error.h"
#include "morphnode/MorphModel.h"
#include "morphnode/OptimizerQuality.h"

#include "vtkAxis.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

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
std::vector<double> ParseList(const std::string& text)
{
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    if (!item.empty())
    {
      values.push_back(std::stod(item));
    }
  }
  return values;
}

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

void WritePng(vtkContextView* view, const std::string& file)
{
  view->GetRenderWindow()->SetMultiSamples(0);
  view->GetRenderWindow()->OffScreenRenderingOn();
  view->GetRenderWindow()->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(view->GetRenderWindow());
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
}

/// The paper's Figure 5: one chart per method, a line per target, weight over time.
void PlotWeightsOverTime(const std::vector<std::pair<std::string, std::vector<morphnode::FrameQuality>>>& runs,
  const std::vector<std::string>& names, double frameRate, const std::string& file)
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
    table->SetNumberOfRows(static_cast<vtkIdType>(frames.size()));
    for (size_t f = 0; f < frames.size(); ++f)
    {
      table->SetValue(static_cast<vtkIdType>(f), 0, f / frameRate);
      for (size_t k = 0; k < order.size(); ++k)
      {
        table->SetValue(static_cast<vtkIdType>(f), static_cast<vtkIdType>(k + 1), frames[f].Weights[order[k]]);
      }
    }
    vtkNew<vtkChartXY> chart;
    chart->SetTitle(runs[r].first);
    chart->GetTitleProperties()->SetFontSize(14);
    chart->GetAxis(vtkAxis::LEFT)->SetTitle("weight");
    chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::LEFT)->SetRange(0.0, 1.0);
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
void PlotErrorVsActive(const std::vector<std::tuple<std::string, double, double>>& points, const std::string& file)
{
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
  chart->SetTitle("Vertex error against active targets (mean over the track)");
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("RMS vertex error (mm)");
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
} // namespace

int main(int argc, char* argv[])
{
  std::string face, track, out = "optimizer-study";
  std::vector<double> thresholds{ 0.1, 0.2, 0.3, 0.4, 0.5 }, bounds{ 0.0005, 0.001, 0.002 }, budgets{ 4, 8 };
  double figure5 = 0.3;
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
    else
    {
      std::cerr << "unknown option " << arg << "\n";
      return 2;
    }
  }
  if (face.empty() || track.empty())
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
    const morphnode::MorphModel* model = morph->GetMorphModel();
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

    std::filesystem::create_directories(out);
    std::ofstream frames(out + "/frames.csv");
    frames << "method,frame,time,active_targets,rms_error,max_error,error_bound,morph_us\n";
    std::ofstream summaryCsv(out + "/summary.csv");
    summaryCsv << "method,mean_active_targets,mean_rms_error_mm,max_rms_error_mm,max_vertex_error_mm,"
                  "max_error_bound_mm,mean_morph_us,morph_speedup\n";
    std::ostringstream md;
    md << "| method | mean active targets | mean RMS error (mm) | max RMS error (mm) | max vertex error (mm) | max bound (mm) | morph speed-up |\n"
       << "| --- | --- | --- | --- | --- | --- | --- |\n";
    std::vector<std::pair<std::string, std::vector<morphnode::FrameQuality>>> figure5Runs;
    std::vector<std::tuple<std::string, double, double>> scatter;
    double noneTime = 0.0;
    const double mm = 1000.0; // the faces are in metres
    for (size_t m = 0; m < methods.size(); ++m)
    {
      Progress(m, methods.size(), methods[m].Name);
      const auto result = morphnode::MeasureOptimizerQuality(*positions, distances, absolute, methods[m]);
      double active = 0, rms = 0, rmsMax = 0, maxError = 0, bound = 0, time = 0;
      for (size_t f = 0; f < result.size(); ++f)
      {
        const auto& q = result[f];
        frames << methods[m].Name << "," << f << "," << absolute.GetTime(f) << "," << q.ActiveTargets << ","
               << q.RmsError << "," << q.MaxError << "," << q.ErrorBound << "," << q.MorphSeconds * 1e6 << "\n";
        active += q.ActiveTargets;
        rms += q.RmsError;
        rmsMax = std::max(rmsMax, q.RmsError);
        maxError = std::max(maxError, q.MaxError);
        bound = std::max(bound, q.ErrorBound);
        time += q.MorphSeconds;
      }
      const double n = std::max<double>(1.0, static_cast<double>(result.size()));
      if (m == 0)
      {
        noneTime = time;
      }
      const double speedup = time > 0 ? noneTime / time : 0.0;
      summaryCsv << methods[m].Name << "," << active / n << "," << rms / n * mm << "," << rmsMax * mm << ","
                 << maxError * mm << "," << bound * mm << "," << time / n * 1e6 << "," << speedup << "\n";
      md << std::fixed << std::setprecision(3) << "| " << methods[m].Name << " | " << std::setprecision(2)
         << active / n << " | " << std::setprecision(4) << rms / n * mm << " | " << rmsMax * mm << " | "
         << maxError * mm << " | " << bound * mm << " | " << std::setprecision(2) << speedup << " x |\n";
      if (m > 0)
      {
        scatter.emplace_back(methods[m].Name, active / n, rms / n * mm);
      }
      const auto& s = methods[m].Settings;
      const bool figure5Method = m == 0 ||
        (std::abs(s.Threshold - figure5) < 1e-12 && s.Strategy == morphnode::Redistribution::Remaining);
      if (figure5Method)
      {
        figure5Runs.emplace_back(methods[m].Name, result);
      }
    }
    Progress(methods.size(), methods.size(), "done");
    std::ofstream(out + "/summary.md") << md.str();
    std::cout << md.str();
    PlotWeightsOverTime(figure5Runs, model->GetTargetNames(), absolute.GetFrameRate(), out + "/weights_over_time.png");
    PlotErrorVsActive(scatter, out + "/error_vs_active.png");
    std::cout << "wrote " << out << "/{frames.csv,summary.csv,summary.md,weights_over_time.png,error_vs_active.png}\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
