// SPDX-License-Identifier: BSD-3-Clause
#include "OptimizerStudyPlots.h"

#include "ImageOutput.h"
#include "StudyMethods.h"

#include "vtkAxis.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPlot.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"

#include <algorithm>
#include <map>
#include <numeric>

namespace morphnode
{
namespace study
{
void PlotWeightsOverTime(const std::vector<MethodRun>& runs, const std::vector<std::string>& names,
  double frameRate, double from, double to, const std::string& file)
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
    chart->SetSize(
      vtkRectf(0, (runs.size() - 1 - r) * h * 250 * runs.size(), 1000, h * 250 * runs.size()));
    view->GetScene()->AddItem(chart);
  }
  appkit::WritePng(view, file);
}

void PlotErrorVsActive(std::vector<std::tuple<std::string, double, double>> points,
  const std::string& title, const std::string& yTitle, const std::string& file)
{
  // One line per family, by increasing active count.
  std::stable_sort(points.begin(), points.end(),
    [](const auto& a, const auto& b) { return std::get<1>(a) < std::get<1>(b); });
  std::map<std::string, vtkSmartPointer<vtkTable>> families;
  for (const auto& [name, active, error] : points)
  {
    const std::string family = MethodFamily(name);
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
  const unsigned char colors[5][3] = { { 31, 119, 180 }, { 255, 127, 14 }, { 44, 160, 44 },
    { 214, 39, 40 }, { 148, 103, 189 } };
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
  appkit::WritePng(view, file);
}
} // namespace study
} // namespace morphnode
