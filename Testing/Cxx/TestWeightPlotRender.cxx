// SPDX-License-Identifier: BSD-3-Clause
// Offscreen render test of a weight plot (vtkChartXY): eight seconds of a seeded behaviour
// (idle blinks, a brow raise, a smile mood, a nod) plotted channel by channel, against a
// baseline PNG. A second seed must not match it. Run under `xvfb-run -a`.
#include "MorphNodeTestUtilities.h"

#include "behavior/BehaviorController.h"

#include "vtkAxis.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

namespace
{
const char* const Channels[] = { "EyesClosed", "BrowsUp", "MouthSmile", "LookLeft", "LookRight" };
const unsigned char Colors[][3] = { { 31, 119, 180 }, { 214, 39, 40 }, { 44, 160, 44 },
  { 148, 103, 189 }, { 255, 127, 14 } };

/// VTK's legacy image metric at VTK's usual threshold. Measured: the baseline's own plot 0,
/// another seed 789, the happy mood at 0.5 instead of 0.6 (WeakerSmileDoesNotMatch) 308.
constexpr double Threshold = 10.0;

/// Renders the plot of a behaviour with `seed` (and a happy mood of `mood`) and compares it
/// with `baseline`.
bool PlotMatches(
  uint64_t seed, const std::string& baseline, const std::string& outputDir, double mood = 0.6)
{
  morphnode::BehaviorController behavior;
  behavior.SetSeed(seed);
  behavior.SetFrameRate(30.0);
  behavior.SetDuration(8.0);
  behavior.Gesture("raise_brows", 1.0, 1.2, 0.9);
  behavior.SetMood("happy", mood, 3.0);
  behavior.Gesture("nod", 5.5, 0.8, 0.7);
  behavior.LookAt(20.0, 0.0, 6.0, 1.5);
  const morphnode::WeightTrack track = behavior.GenerateTrack();

  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> time;
  time->SetName("time (s)");
  table->AddColumn(time);
  std::vector<int> columns;
  for (const char* name : Channels)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    table->AddColumn(column);
    columns.push_back(track.FindChannel(name));
    EXPECT_GE(columns.back(), 0) << name;
  }
  table->SetNumberOfRows(static_cast<vtkIdType>(track.GetNumberOfFrames()));
  for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
  {
    const vtkIdType row = static_cast<vtkIdType>(f);
    table->SetValue(row, 0, track.GetTime(f));
    for (size_t c = 0; c < columns.size(); ++c)
    {
      table->SetValue(row, static_cast<vtkIdType>(c + 1),
        columns[c] < 0 ? 0.0 : track.GetValue(f, static_cast<size_t>(columns[c])));
    }
  }

  vtkNew<vtkContextView> view;
  view->GetRenderWindow()->SetSize(800, 360);
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetTitle("Behaviour weights over time");
  chart->SetShowLegend(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("weight");
  chart->GetAxis(vtkAxis::LEFT)->SetRange(0.0, 1.05);
  chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  for (size_t c = 0; c < columns.size(); ++c)
  {
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, static_cast<vtkIdType>(c + 1));
    line->SetColor(Colors[c][0], Colors[c][1], Colors[c][2], 255);
    line->SetWidth(2.0);
  }
  view->GetRenderWindow()->Render();
  std::cout << "image error (seed " << seed << ", mood " << mood
            << "): " << morphnode_test::BaselineError(view->GetRenderWindow(), baseline, outputDir)
            << "\n";
  return morphnode_test::MatchesBaseline(view->GetRenderWindow(), baseline, outputDir, Threshold);
}
} // namespace

TEST(WeightPlotRender, BehaviourTrackMatchesBaseline)
{
  const std::string baseline = std::string(MORPHNODE_BASELINE_DIR) + "/TestWeightPlotRender.png";
  EXPECT_TRUE(PlotMatches(2004, baseline, MORPHNODE_TEST_OUTPUT_DIR))
    << "see " << MORPHNODE_TEST_OUTPUT_DIR << "/TestWeightPlotRender*.png";
}

TEST(WeightPlotRender, AnotherSeedDoesNotMatch)
{
  // Other blinks and saccades: the comparison must notice (the test above can fail).
  const std::string baseline = std::string(MORPHNODE_BASELINE_DIR) + "/TestWeightPlotRender.png";
  const std::string scratch = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/other-seed";
  EXPECT_FALSE(PlotMatches(7, baseline, scratch));
}

TEST(WeightPlotRender, WeakerSmileDoesNotMatch)
{
  // The same seed with the happy mood at 0.5 instead of 0.6: the same blinks and glances,
  // a lower MouthSmile plateau (and the mood's other channels). The comparison must notice.
  const std::string baseline = std::string(MORPHNODE_BASELINE_DIR) + "/TestWeightPlotRender.png";
  const std::string scratch = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/weaker-smile";
  EXPECT_FALSE(PlotMatches(2004, baseline, scratch, 0.5));
}
