// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DeviceProfile.h
/// @brief Named device presets for the scalable avatar: the morph stage's frame budget, the
/// finest level of detail shown and the pixel bounds of the level and target level of
/// detail. One spelling everywhere (MorphAvatar --profile, vtkMorphNodeFilter's
/// DeviceProfile, a browser client asking for one).

#include "budget/FrameBudgetController.h"

#include <string>
#include <vector>

namespace morphnode
{
struct DeviceProfile
{
  std::string Name;
  /// Seconds for the morph stage (DeviceFrameBudget of the device class).
  double FrameBudget = 0.0;
  /// The finest level shown: 0 the full mesh, 1 the first reduction, ...
  int FinestLevel = 0;
  /// Largest projected geometric error of the shown level, pixels.
  double PixelBound = 0.0;
  /// Largest projected error the target level of detail may add, pixels.
  double TargetPixelBound = 0.0;
};

/// desktop, laptop, phone, finest (largest budget) first.
const std::vector<DeviceProfile>& DeviceProfiles();
/// The names joined by "|" (for usage texts).
std::string DeviceProfileNames();
/// Case-insensitive. Throws InputError naming the known profiles for an unknown name.
const DeviceProfile& FindDeviceProfile(const std::string& name);
/// Writes the profile's budget, finest level and pixel bounds into `settings`.
void ApplyDeviceProfile(const DeviceProfile& profile, ControllerSettings& settings);
} // namespace morphnode
