// SPDX-License-Identifier: BSD-3-Clause
// Device profiles (the presets of MorphAvatar --profile, vtkMorphNodeFilter's DeviceProfile and
// a browser client) and the screen's pixels per unit.
#include "base/Error.h"
#include "budget/DeviceProfile.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace morphnode;

TEST(DeviceProfile, PresetsFixBudgetFinestLevelAndPixelBounds)
{
  ASSERT_EQ(DeviceProfiles().size(), 3u);
  EXPECT_EQ(DeviceProfileNames(), "desktop|laptop|phone");
  const DeviceProfile& desktop = FindDeviceProfile("desktop");
  const DeviceProfile& laptop = FindDeviceProfile("Laptop");
  const DeviceProfile& phone = FindDeviceProfile("PHONE");
  EXPECT_EQ(desktop.FrameBudget, DeviceFrameBudget(DeviceClass::Desktop));
  EXPECT_EQ(laptop.FrameBudget, DeviceFrameBudget(DeviceClass::Laptop));
  EXPECT_EQ(phone.FrameBudget, DeviceFrameBudget(DeviceClass::Mobile));
  // Smaller devices: less time, coarser finest level, larger pixel bounds.
  EXPECT_GT(desktop.FrameBudget, laptop.FrameBudget);
  EXPECT_GT(laptop.FrameBudget, phone.FrameBudget);
  EXPECT_EQ(desktop.FinestLevel, 0);
  EXPECT_EQ(phone.FinestLevel, 1);
  EXPECT_LT(desktop.PixelBound, laptop.PixelBound);
  EXPECT_LT(laptop.PixelBound, phone.PixelBound);
  EXPECT_LE(phone.TargetPixelBound, phone.PixelBound);
  ControllerSettings s;
  ApplyDeviceProfile(phone, s);
  EXPECT_EQ(s.FrameBudget, phone.FrameBudget);
  EXPECT_EQ(s.FinestLevel, 1);
  EXPECT_EQ(s.PixelBound, phone.PixelBound);
  EXPECT_EQ(s.TargetPixelBound, phone.TargetPixelBound);
  FrameBudgetController c;
  EXPECT_NO_THROW(c.SetSettings(s));
  try
  {
    FindDeviceProfile("watch");
    FAIL() << "an unknown profile was accepted";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("desktop|laptop|phone"), std::string::npos);
  }
}

TEST(DeviceProfile, ScreenPixelsPerUnit)
{
  // 90 degrees, 1000 px high, 1 unit away: the view is 2 units high.
  EXPECT_NEAR(ScreenPixelsPerUnit(1000.0, 90.0, 1.0), 500.0, 1e-9);
  EXPECT_NEAR(ScreenPixelsPerUnit(1000.0, 90.0, 4.0), 125.0, 1e-9);
  EXPECT_THROW(ScreenPixelsPerUnit(0.0, 30.0, 1.0), InputError);
  EXPECT_THROW(ScreenPixelsPerUnit(100.0, 180.0, 1.0), InputError);
  EXPECT_THROW(ScreenPixelsPerUnit(100.0, 30.0, -1.0), InputError);
  EXPECT_THROW(ScreenPixelsPerUnit(100.0, 30.0, NAN), InputError);
  ControllerSettings s;
  s.PixelBound = -1.0;
  FrameBudgetController c;
  EXPECT_THROW(c.SetSettings(s), InputError);
}
