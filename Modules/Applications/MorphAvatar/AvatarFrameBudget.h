// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarFrameBudget.h
/// @brief MorphAvatar's --frame-budget MS: the morph filter chooses the optimizer's
/// threshold every frame so that its morph stays within MS milliseconds, from the times it
/// measured (vtkMorphNodeFilter::FrameBudget, morphnode::FrameBudgetController). Every
/// frame's choice is recorded; --frame-budget-log FILE writes them as CSV and a summary
/// goes to stdout when the avatar ends (docs/avatar.md).

#include "AvatarOptions.h"

class vtkMorphNodeFilter;

namespace morphavatar
{
/// Sets the filter's budget from the options and watches its executions (nothing without
/// --frame-budget). Exits with a usage error when the log cannot be written.
void WatchFrameBudget(vtkMorphNodeFilter* morph, const Options& options);
/// Completes --frame-budget-log (every write checked, renamed onto the path when complete);
/// false, with a message, when it could not be written (a full disk): no partial log.
bool FinishFrameBudget();
} // namespace morphavatar
