// SPDX-License-Identifier: BSD-3-Clause
// The shipped Data/rigs/arkit.json: complete viseme/expression sets, valid against the
// ICT-FaceKit target names, bilabials that close the lips.
#include "base/Error.h"
#include "rig/Rig.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
std::string ArkitRigPath()
{
  return std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json";
}

// ICT-FaceKit's 53 targets in file order (its README), the faces this rig is written for.
const std::vector<std::string> IctTargets = { "browDown_L", "browDown_R", "browInnerUp_L",
  "browInnerUp_R", "browOuterUp_L", "browOuterUp_R", "cheekPuff_L", "cheekPuff_R", "cheekSquint_L",
  "cheekSquint_R", "eyeBlink_L", "eyeBlink_R", "eyeLookDown_L", "eyeLookDown_R", "eyeLookIn_L",
  "eyeLookIn_R", "eyeLookOut_L", "eyeLookOut_R", "eyeLookUp_L", "eyeLookUp_R", "eyeSquint_L",
  "eyeSquint_R", "eyeWide_L", "eyeWide_R", "jawForward", "jawLeft", "jawOpen", "jawRight",
  "mouthClose", "mouthDimple_L", "mouthDimple_R", "mouthFrown_L", "mouthFrown_R", "mouthFunnel",
  "mouthLeft", "mouthLowerDown_L", "mouthLowerDown_R", "mouthPress_L", "mouthPress_R",
  "mouthPucker", "mouthRight", "mouthRollLower", "mouthRollUpper", "mouthShrugLower",
  "mouthShrugUpper", "mouthSmile_L", "mouthSmile_R", "mouthStretch_L", "mouthStretch_R",
  "mouthUpperUp_L", "mouthUpperUp_R", "noseSneer_L", "noseSneer_R" };

std::map<std::string, double> TermsOf(const Rig& rig, const std::string& shape)
{
  std::map<std::string, double> terms;
  const int s = rig.FindShape(shape);
  EXPECT_GE(s, 0) << shape;
  if (s >= 0)
  {
    for (const auto& term : rig.GetShapeTerms(static_cast<size_t>(s)))
    {
      terms[term.Target] = term.Coefficient;
    }
  }
  return terms;
}
} // namespace

TEST(ArkitRig, HasEverySetWithTheExactNames)
{
  const Rig rig = Rig::LoadFile(ArkitRigPath());
  EXPECT_EQ(rig.GetName(), "ARKit");
  EXPECT_EQ(rig.GetSet("paper"),
    (std::vector<std::string>{ "EyesClosed", "BrowsUp", "S", "F", "BrowsFright", "BrowsAngry", "L",
      "E", "A", "MouthSmile", "MouthSad", "O" }));
  EXPECT_EQ(rig.GetSet("meta"),
    (std::vector<std::string>{
      "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou" }));
  EXPECT_EQ(rig.GetSet("german"),
    (std::vector<std::string>{
      "sil", "P", "M", "F", "S", "Z", "T", "L", "R", "K", "A", "O", "U", "E", "Y", "Q" }));
  EXPECT_EQ(rig.GetSet("behavior"),
    (std::vector<std::string>{ "EyesClosed", "BrowsUp", "BrowsFright", "BrowsAngry", "MouthSmile",
      "MouthSad", "LookUp", "LookDown", "LookLeft", "LookRight" }));
  // Neutral is implicit (all weights 0), never a shape; sil is the all-zero viseme.
  EXPECT_EQ(rig.FindShape("Neutral"), -1);
  EXPECT_TRUE(rig.GetShapeTerms(static_cast<size_t>(rig.FindShape("sil"))).empty());
  // Every non-silent shape moves something.
  for (size_t s = 0; s < rig.GetNumberOfShapes(); ++s)
  {
    if (rig.GetShapeNames()[s] != "sil")
    {
      EXPECT_FALSE(rig.GetShapeTerms(s).empty()) << rig.GetShapeNames()[s];
    }
  }
}

TEST(ArkitRig, BindsToTheIctFaceKitTargetNames)
{
  Rig rig = Rig::LoadFile(ArkitRigPath());
  EXPECT_EQ(rig.GetDeclaredTargets(), IctTargets);
  EXPECT_NO_THROW(rig.Bind(IctTargets));
  // Coefficients stay within the sculpted range of an action unit.
  for (size_t s = 0; s < rig.GetNumberOfShapes(); ++s)
  {
    for (const auto& term : rig.GetShapeTerms(s))
    {
      EXPECT_GT(term.Coefficient, 0.0) << rig.GetShapeNames()[s] << " " << term.Target;
      EXPECT_LE(term.Coefficient, 1.0) << rig.GetShapeNames()[s] << " " << term.Target;
    }
  }
}

TEST(ArkitRig, BilabialsCloseTheLips)
{
  const Rig rig = Rig::LoadFile(ArkitRigPath());
  for (const char* shape : { "PP", "P", "M" })
  {
    auto terms = TermsOf(rig, shape);
    // ARKit's mouthClose closes the lips over an open jaw: it must cancel jawOpen fully.
    EXPECT_GE(terms["mouthClose"], terms["jawOpen"]) << shape;
    EXPECT_GT(terms["mouthPress_L"], 0.0) << shape;
    EXPECT_GT(terms["mouthPress_R"], 0.0) << shape;
    EXPECT_GT(terms["mouthRollLower"], 0.0) << shape;
    // No opening shapes.
    EXPECT_EQ(
      terms.count("mouthLowerDown_L") + terms.count("mouthUpperUp_L") + terms.count("mouthFunnel"),
      0u)
      << shape;
  }
}

TEST(ArkitRig, ShapesMatchTheirDescriptions)
{
  Rig rig = Rig::LoadFile(ArkitRigPath());
  rig.Bind(IctTargets);
  auto weight = [&](const std::string& shape, const std::string& target)
  {
    const auto w = rig.Expand(std::map<std::string, double>{ { shape, 1.0 } });
    for (size_t t = 0; t < IctTargets.size(); ++t)
    {
      if (IctTargets[t] == target)
      {
        return w[t];
      }
    }
    return -1.0;
  };
  EXPECT_EQ(weight("EyesClosed", "eyeBlink_L"), 1.0);
  EXPECT_EQ(weight("EyesClosed", "eyeBlink_R"), 1.0);
  // Open vowels: A opens most, then O, E; S keeps the teeth nearly closed.
  EXPECT_GT(weight("A", "jawOpen"), weight("O", "jawOpen"));
  EXPECT_GT(weight("O", "jawOpen"), weight("E", "jawOpen"));
  EXPECT_LT(weight("S", "jawOpen"), 0.1);
  EXPECT_GT(weight("O", "mouthFunnel"), 0.3);
  EXPECT_GT(weight("U", "mouthPucker"), 0.5);
  EXPECT_GT(weight("F", "mouthRollLower"), 0.5);
  EXPECT_GT(weight("BrowsAngry", "browDown_L"), 0.5);
  EXPECT_GT(weight("BrowsFright", "browInnerUp_R"), 0.5);
  EXPECT_GT(weight("MouthSmile", "mouthSmile_R"), 0.5);
  EXPECT_GT(weight("MouthSad", "mouthFrown_L"), 0.5);
  // Gaze: left is the face's own left, the ARKit _L side.
  EXPECT_EQ(weight("LookLeft", "eyeLookOut_L"), 1.0);
  EXPECT_EQ(weight("LookLeft", "eyeLookIn_R"), 1.0);
  EXPECT_EQ(weight("LookRight", "eyeLookOut_R"), 1.0);
  EXPECT_EQ(weight("LookUp", "eyeLookUp_L"), 1.0);
  EXPECT_EQ(weight("LookDown", "eyeLookDown_R"), 1.0);
  // Shared names are one definition: aliases carry the same terms.
  EXPECT_EQ(rig.GetAliasOf(static_cast<size_t>(rig.FindShape("FF"))), "F");
  EXPECT_EQ(rig.GetAliasOf(static_cast<size_t>(rig.FindShape("P"))), "PP");
  EXPECT_EQ(TermsOf(rig, "U"), TermsOf(rig, "ou"));
  EXPECT_EQ(TermsOf(rig, "Z"), TermsOf(rig, "CH"));
}
