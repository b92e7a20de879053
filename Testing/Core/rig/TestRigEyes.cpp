// SPDX-License-Identifier: BSD-3-Clause
// The rig file's "eyes" section (docs/rigs.md): absent = the default convention; names as
// strings or objects (side, forward, up), shared directions and limits; the shipped ARKit
// rig's eyes; every malformed field an InputError naming it.
#include "base/Error.h"
#include "rig/Rig.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace morphnode;

namespace
{
Rig WithEyes(const std::string& eyes)
{
  return Rig::LoadString(
    R"({"name": "R", "shapes": {"A": {"jawOpen": 1}}, "eyes": )" + eyes + "}", "test");
}

std::string ErrorOf(const std::string& eyes)
{
  try
  {
    WithEyes(eyes);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(RigEyes, AbsentMeansTheDefaultConvention)
{
  const Rig rig = Rig::LoadString(R"({"name": "R", "shapes": {}})", "test");
  EXPECT_FALSE(rig.HasEyes());
  EXPECT_TRUE(rig.GetEyes().UsesDefaultConvention());
  EyeSpec eye;
  EXPECT_TRUE(rig.GetEyes().FindEye("EyeLeft", "EyeLeft/Iris", eye));
  EXPECT_EQ(rig.GetEyes().GetLimits().MaxYaw, 40.0);
}

TEST(RigEyes, NamesDirectionsAndLimits)
{
  const Rig rig = WithEyes(R"({
    "parts": ["Orb.L", {"name": "Orb_2", "side": "right", "forward": [0, -1, 0], "up": [0, 0, 1]}],
    "forward": [0, 0, 2], "up": [0, 3, 0],
    "limits": {"yaw": 30, "down": 20}})");
  ASSERT_TRUE(rig.HasEyes());
  const EyeRig& eyes = rig.GetEyes();
  ASSERT_EQ(eyes.GetEyes().size(), 2u);
  EXPECT_EQ(eyes.GetEyes()[0].Name, "Orb.L");
  EXPECT_EQ(eyes.GetEyes()[0].Side, EyeSide::Left) << "from the name";
  EXPECT_EQ(eyes.GetEyes()[0].Forward[2], 2.0) << "the shared direction";
  EXPECT_EQ(eyes.GetEyes()[1].Side, EyeSide::Right) << "given";
  EXPECT_EQ(eyes.GetEyes()[1].Forward[1], -1.0);
  EXPECT_EQ(eyes.GetEyes()[1].Up[2], 1.0);
  EXPECT_EQ(eyes.GetLimits().MaxYaw, 30.0);
  EXPECT_EQ(eyes.GetLimits().MaxUp, 25.0) << "not given: the default";
  EXPECT_EQ(eyes.GetLimits().MaxDown, 20.0);
  EyeSpec eye;
  EXPECT_FALSE(eyes.FindEye("EyeLeft", "EyeLeft", eye)) << "named eyes only";
  EXPECT_TRUE(eyes.FindEye("Orb_2", "Orb_2/Iris", eye));

  // Without parts: the convention, with the section's directions and limits.
  const Rig shared = WithEyes(R"({"forward": [1, 0, 0], "limits": {"up": 10}})");
  ASSERT_TRUE(shared.GetEyes().UsesDefaultConvention());
  ASSERT_TRUE(shared.GetEyes().FindEye("eye_R", "", eye));
  EXPECT_EQ(eye.Forward[0], 1.0);
  EXPECT_EQ(eye.Side, EyeSide::Right);
  EXPECT_EQ(shared.GetEyes().GetLimits().MaxUp, 10.0);
}

TEST(RigEyes, ShippedArkitRigNamesTheEyes)
{
  const Rig rig = Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
  ASSERT_TRUE(rig.HasEyes());
  EyeSpec eye;
  ASSERT_TRUE(rig.GetEyes().FindEye("EyeLeft", "EyeLeft/M_IrisLeft", eye));
  EXPECT_EQ(eye.Side, EyeSide::Left);
  ASSERT_TRUE(rig.GetEyes().FindEye("EyeRight", "EyeRight/M_ScleraRight", eye));
  EXPECT_EQ(eye.Side, EyeSide::Right);
  EXPECT_FALSE(rig.GetEyes().FindEye("Eyelashes", "Eyelashes", eye));
  EXPECT_FALSE(rig.GetEyes().FindEye("Head", "Head/M_EyeSocket", eye));
  EXPECT_EQ(eye.Forward[2], 1.0);
  // The gaze shapes the lids follow with are there.
  for (const char* shape : { "LookUp", "LookDown", "LookLeft", "LookRight" })
  {
    EXPECT_GE(rig.FindShape(shape), 0) << shape;
  }
}

TEST(RigEyes, ErrorsNameTheField)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
    { R"([])", "field 'eyes' must be an object" },
    { R"({"eye": []})", "unknown field 'eye'" },
    { R"({"parts": []})", "non-empty array" },
    { R"({"parts": "EyeLeft"})", "non-empty array" },
    { R"({"parts": [3]})", "parts entry 0" },
    { R"({"parts": [""]})", "no name" },
    { R"({"parts": ["A", "A"]})", "named twice" },
    { R"({"parts": [{"side": "left"}]})", "'name' must be a string" },
    { R"({"parts": [{"name": "A", "side": "middle"}]})", "'side' must be" },
    { R"({"parts": [{"name": "A", "look": 1}]})", "unknown field 'look'" },
    { R"({"parts": [{"name": "A", "forward": [0, 1]}]})", "3 numbers" },
    { R"({"parts": [{"name": "A", "up": [0, 0, 1]}]})", "parallel" },
    { R"({"forward": [0, 0, 0]})", "zero" },
    { R"({"up": "y"})", "'up' must be an array of 3 numbers" },
    { R"({"limits": [40]})", "'limits' must be an object" },
    { R"({"limits": {"yaw": "40"}})", "must be a number" },
    { R"({"limits": {"roll": 10}})", "unknown limit 'roll'" },
    { R"({"limits": {"yaw": 120}})", "(0, 90]" },
    { R"({"limits": {"down": 0}})", "(0, 90]" },
  };
  for (const auto& [eyes, fragment] : cases)
  {
    const std::string message = ErrorOf(eyes);
    EXPECT_NE(message.find(fragment), std::string::npos) << eyes << " gave: " << message;
    EXPECT_EQ(message.rfind("rig test: ", 0), 0u) << message;
  }
}
