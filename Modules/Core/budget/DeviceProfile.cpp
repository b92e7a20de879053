// SPDX-License-Identifier: BSD-3-Clause
#include "budget/DeviceProfile.h"

#include "base/Error.h"
#include "base/Text.h"

namespace morphnode
{
const std::vector<DeviceProfile>& DeviceProfiles()
{
  // Budgets from the device classes; pixel bounds: half a pixel is invisible on a desktop
  // monitor, a phone's small, dense screen hides two (docs/lod.md). A phone never shows the
  // full mesh: its finest level is the first reduction (half the triangles).
  static const std::vector<DeviceProfile> profiles = {
    { "desktop", DeviceFrameBudget(DeviceClass::Desktop), 0, 0.5, 0.25 },
    { "laptop", DeviceFrameBudget(DeviceClass::Laptop), 0, 1.0, 0.5 },
    { "phone", DeviceFrameBudget(DeviceClass::Mobile), 1, 2.0, 1.0 },
  };
  return profiles;
}

std::string DeviceProfileNames()
{
  std::string names;
  for (const auto& p : DeviceProfiles())
  {
    names += (names.empty() ? "" : "|") + p.Name;
  }
  return names;
}

const DeviceProfile& FindDeviceProfile(const std::string& name)
{
  const std::string lower = text::ToLower(name);
  for (const auto& p : DeviceProfiles())
  {
    if (p.Name == lower)
    {
      return p;
    }
  }
  throw InputError("Unknown device profile '" + name + "' (known: " + DeviceProfileNames() + ").");
}

void ApplyDeviceProfile(const DeviceProfile& profile, ControllerSettings& settings)
{
  settings.FrameBudget = profile.FrameBudget;
  settings.FinestLevel = profile.FinestLevel;
  settings.PixelBound = profile.PixelBound;
  settings.TargetPixelBound = profile.TargetPixelBound;
}
} // namespace morphnode
