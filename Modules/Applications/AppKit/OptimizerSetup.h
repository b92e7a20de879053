// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file OptimizerSetup.h
/// @brief Optimizer settings of the core (morph/OptimizerPresets.h makes them from a
/// method's name) on a vtkMorphNodeFilter.

#include "morph/WeightOptimizer.h"

class vtkMorphNodeFilter;

namespace morphnode
{
namespace appkit
{
/// Sets every optimizer setting of the filter (threshold, redistribution, adjusted
/// threshold, error bound, budget, hysteresis) and forgets its hysteresis history.
void ApplyOptimizerSettings(vtkMorphNodeFilter* filter, const OptimizerSettings& settings);
} // namespace appkit
} // namespace morphnode
