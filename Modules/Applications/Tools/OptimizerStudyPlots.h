// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file OptimizerStudyPlots.h
/// @brief OptimizerStudy's plots (vtkChartXY, written as PNG).

#include "morph/OptimizerQuality.h"

#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace morphnode
{
namespace study
{
using MethodRun = std::pair<std::string, std::vector<FrameQuality>>;

/// The paper's Figure 5: one chart per run, a line per target (the eight with the most
/// weight in the first run), weight over time in [from, to] seconds (all when to <= from).
void PlotWeightsOverTime(const std::vector<MethodRun>& runs, const std::vector<std::string>& names,
  double frameRate, double from, double to, const std::string& file);

/// An error against mean active targets, a line per method family (the name's first
/// word), points as (name, mean active targets, error).
void PlotErrorVsActive(std::vector<std::tuple<std::string, double, double>> points,
  const std::string& title, const std::string& yTitle, const std::string& file);
} // namespace study
} // namespace morphnode
