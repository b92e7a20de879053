// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: the plots of the errors against the budget and over time.
#include "ReductionStudy.h"

#include "ImageOutput.h"

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

namespace reductionstudy
{
namespace appkit = morphnode::appkit;

namespace
{
const unsigned char Colors[4][3] = { { 214, 39, 40 }, { 31, 119, 180 }, { 127, 127, 127 },
  { 44, 160, 44 } };

} // namespace

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
      line->GetPen()->SetLineType(
        c == 1 ? vtkPen::SOLID_LINE : (c == 2 ? vtkPen::DASH_LINE : vtkPen::DOT_LINE));
    }
    tables.push_back(table);
  }
  view->GetScene()->AddItem(chart);
  appkit::WritePng(view, file);
}

void PlotOverTime(const std::vector<Errors>& all, const std::vector<std::string>& methods,
  double budget, const morphnode::WeightTrack& track, size_t stride, const std::string& file)
{
  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(1000, 420);
  view->GetRenderer()->SetBackground(1, 1, 1);
  vtkNew<vtkChartXY> chart;
  std::ostringstream title;
  title << "Motion error per frame (95th percentile over points) at " << 100.0 * budget
        << " % of the triangles (jawOpen x 0.5 mm in black)";
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
    table->SetValue(
      r, methods.size() + 1, jawChannel >= 0 ? 0.5 * track.GetValue(r * stride, jawChannel) : 0.0);
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
  appkit::WritePng(view, file);
}
} // namespace reductionstudy
