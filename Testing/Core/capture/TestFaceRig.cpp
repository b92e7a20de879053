// SPDX-License-Identifier: BSD-3-Clause
// The rig chosen from a face's target names (capture/FaceRig.h), for each naming family:
// ARKit in its three spellings, Oculus visemes, both together (the MakeHuman avatar's
// names), VRoid Fcl_*, VRM 1.0 and 0.x expressions, the paper's own shapes, and none.
#include "capture/FaceRig.h"

#include "capture/ArkitNames.h"

#include "MorphNodeTestErrors.h"
#include "base/Error.h"
#include "base/Text.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>

using namespace morphnode;
using morphnode_test::ErrorOf;

namespace
{
const Rig& ArkitRig()
{
  static const Rig rig = Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
  return rig;
}

std::vector<std::string> OculusVisemes()
{
  return { "viseme_sil", "viseme_PP", "viseme_FF", "viseme_TH", "viseme_DD", "viseme_kk",
    "viseme_CH", "viseme_SS", "viseme_nn", "viseme_RR", "viseme_aa", "viseme_E", "viseme_I",
    "viseme_O", "viseme_U" };
}

bool Has(const std::vector<std::string>& v, const std::string& s)
{
  return std::find(v.begin(), v.end(), s) != v.end();
}

/// The face targets shape `shape` drives at weight 1, with their weights.
std::map<std::string, double> Drive(
  const FaceRigChoice& choice, const std::vector<std::string>& face, const std::string& shape)
{
  Rig rig = Rig::LoadString(choice.RigJson, "chosen");
  rig.Bind(face);
  const std::vector<double> w = rig.Expand(std::map<std::string, double>{ { shape, 1.0 } });
  std::map<std::string, double> out;
  for (size_t t = 0; t < face.size(); ++t)
  {
    if (w[t] != 0.0)
    {
      out[face[t]] = w[t];
    }
  }
  return out;
}
} // namespace

TEST(FaceRig, ArkitInEverySpelling)
{
  std::vector<std::string> camel = ArkitShapeNames(), pascal, ict;
  for (size_t s = 0; s < ArkitShapeCount; ++s)
  {
    pascal.push_back(ArkitLiveLinkName(s));
    for (const auto& n : ArkitIctNames(s))
    {
      ict.push_back(n);
    }
  }
  for (const auto* face : { &camel, &pascal, &ict })
  {
    const FaceRigChoice choice = ChooseFaceRig(*face, ArkitRig());
    EXPECT_TRUE(choice.NeedsRig);
    EXPECT_NE(choice.Families.find("ARKit (52 of 52 shapes)"), std::string::npos)
      << choice.Families;
    EXPECT_FALSE(choice.HasOwnVisemes);
    // Every shape of the ARKit rig is synthesized; none is missing.
    EXPECT_TRUE(choice.Missing.empty()) << choice.Report();
    EXPECT_TRUE(Has(choice.Synthesized, "oh"));
    // "O" drives the jaw and the funnel in the face's own spelling.
    const auto o = Drive(choice, *face, "O");
    const bool jaw = std::any_of(o.begin(), o.end(),
      [](const auto& kv) { return morphnode::text::ToLower(kv.first) == "jawopen"; });
    EXPECT_TRUE(jaw) << (*face)[0];
  }
  // The split brows of ICT land on one whole target of Apple's spelling at the same value,
  // not twice it.
  const auto up = Drive(ChooseFaceRig(camel, ArkitRig()), camel, "BrowsUp");
  EXPECT_DOUBLE_EQ(up.at("browInnerUp"), 0.8);
}

TEST(FaceRig, OculusVisemesAloneAndWithArkit)
{
  const std::vector<std::string> oculus = OculusVisemes();
  const FaceRigChoice alone = ChooseFaceRig(oculus, ArkitRig());
  EXPECT_TRUE(alone.HasOwnVisemes);
  EXPECT_TRUE(Has(alone.Own, "oh"));
  EXPECT_TRUE(Has(alone.Own, "O"));
  EXPECT_TRUE(Has(alone.Missing, "EyesClosed")) << alone.Report(); // nothing to close the eyes with
  EXPECT_EQ(Drive(alone, oculus, "ou"), (std::map<std::string, double>{ { "viseme_U", 1.0 } }));

  // The avatar's names: Ready Player Me's order, visemes then ARKit.
  std::vector<std::string> avatar = oculus;
  for (const auto& n : ArkitShapeNames())
  {
    avatar.push_back(n);
  }
  const FaceRigChoice both = ChooseFaceRig(avatar, ArkitRig());
  EXPECT_TRUE(both.HasOwnVisemes);
  EXPECT_TRUE(both.Missing.empty()) << both.Report();
  EXPECT_TRUE(Has(both.Own, "PP"));              // the face's own viseme
  EXPECT_TRUE(Has(both.Synthesized, "BrowsUp")); // from ARKit
  EXPECT_TRUE(Has(both.Synthesized, "M"));       // German M: no viseme of its own, from ARKit
  EXPECT_EQ(Drive(both, avatar, "PP"), (std::map<std::string, double>{ { "viseme_PP", 1.0 } }));
  EXPECT_NE(both.Report().find("shapes synthesized from ARKit shapes"), std::string::npos);
}

TEST(FaceRig, VroidAndVrmExpressions)
{
  const std::vector<std::string> vroid = { "Fcl_ALL_Neutral", "Fcl_ALL_Joy", "Fcl_BRW_Angry",
    "Fcl_BRW_Surprised", "Fcl_EYE_Close", "Fcl_EYE_Close_L", "Fcl_MTH_A", "Fcl_MTH_I", "Fcl_MTH_U",
    "Fcl_MTH_E", "Fcl_MTH_O" };
  const FaceRigChoice v = ChooseFaceRig(vroid, ArkitRig());
  EXPECT_NE(v.Families.find("VRoid Fcl_* (11)"), std::string::npos) << v.Families;
  EXPECT_EQ(Drive(v, vroid, "A"), (std::map<std::string, double>{ { "Fcl_MTH_A", 1.0 } }));
  EXPECT_EQ(
    Drive(v, vroid, "EyesClosed"), (std::map<std::string, double>{ { "Fcl_EYE_Close", 1.0 } }));
  EXPECT_EQ(
    Drive(v, vroid, "MouthSmile"), (std::map<std::string, double>{ { "Fcl_ALL_Joy", 1.0 } }));
  EXPECT_TRUE(Has(v.Missing, "PP"));

  const std::vector<std::string> vrm1 = { "aa", "ih", "ou", "ee", "oh", "blink", "happy", "angry",
    "sad", "surprised" };
  const FaceRigChoice one = ChooseFaceRig(vrm1, ArkitRig());
  EXPECT_NE(one.Families.find("VRM expressions (10)"), std::string::npos) << one.Families;
  EXPECT_EQ(Drive(one, vrm1, "E"), (std::map<std::string, double>{ { "ee", 1.0 } }));
  EXPECT_EQ(Drive(one, vrm1, "BrowsAngry"), (std::map<std::string, double>{ { "angry", 1.0 } }));

  const std::vector<std::string> vrm0 = { "A", "I", "U", "E", "O", "Blink", "Joy", "Angry",
    "Sorrow", "Fun" };
  const FaceRigChoice zero = ChooseFaceRig(vrm0, ArkitRig());
  EXPECT_EQ(Drive(zero, vrm0, "EyesClosed"), (std::map<std::string, double>{ { "Blink", 1.0 } }));
  EXPECT_EQ(Drive(zero, vrm0, "MouthSad"), (std::map<std::string, double>{ { "Sorrow", 1.0 } }));
}

TEST(FaceRig, ThePapersShapesNeedNoRigAndUnknownNamesAreAnError)
{
  const std::vector<std::string> paper = { "EyesClosed", "BrowsUp", "S", "F", "BrowsFright",
    "BrowsAngry", "L", "E", "A", "MouthSmile", "MouthSad", "O" };
  const FaceRigChoice choice = ChooseFaceRig(paper, ArkitRig());
  EXPECT_FALSE(choice.NeedsRig);
  EXPECT_NE(choice.Report().find("none needed"), std::string::npos);
  EXPECT_NE(ErrorOf(
              [] {
                ChooseFaceRig({ "Key 1", "Key 2" }, ArkitRig());
              })
              .find("--rig"),
    std::string::npos);
}

// A VRM's own expressions (gltf/GltfVrm.h) over targets of any name: the shape O drives the
// `oh` expression's binds with their weights, EyesClosed `blink`'s, the behaviour's looks
// the look expressions; an own viseme target still wins over an expression of a later
// candidate; the family is reported. Without the expressions these names are unknown.
TEST(FaceRig, VrmExpressionsFromTheFileDriveTheirBinds)
{
  const std::vector<std::string> targets = { "Face.M_F00_000_00_Fcl_MTH_O_raw", "Face.Mouth_Open",
    "Face.Eye_Close", "Face.Eye_Look_Left" };
  const std::vector<FaceExpression> expressions = {
    { "oh", { { "Face.M_F00_000_00_Fcl_MTH_O_raw", 0.8 }, { "Face.Mouth_Open", 0.3 } } },
    { "blink", { { "Face.Eye_Close", 1.0 } } }, { "lookLeft", { { "Face.Eye_Look_Left", 1.0 } } },
    { "empty", {} }
  };
  EXPECT_THROW(ChooseFaceRig(targets, ArkitRig()), InputError);
  const FaceRigChoice c = ChooseFaceRig(targets, ArkitRig(), expressions);
  EXPECT_NE(c.Families.find("VRM expressions (3, from the file)"), std::string::npos) << c.Families;
  EXPECT_EQ(Drive(c, targets, "O"),
    (std::map<std::string, double>{
      { "Face.M_F00_000_00_Fcl_MTH_O_raw", 0.8 }, { "Face.Mouth_Open", 0.3 } }));
  EXPECT_EQ(
    Drive(c, targets, "EyesClosed"), (std::map<std::string, double>{ { "Face.Eye_Close", 1.0 } }));
  EXPECT_EQ(Drive(c, targets, "LookLeft"),
    (std::map<std::string, double>{ { "Face.Eye_Look_Left", 1.0 } }));
  EXPECT_TRUE(Has(c.Missing, "PP"));
  // An own Oculus viseme comes first.
  std::vector<std::string> both = targets;
  both.push_back("viseme_O");
  const FaceRigChoice d = ChooseFaceRig(both, ArkitRig(), expressions);
  EXPECT_EQ(Drive(d, both, "O"), (std::map<std::string, double>{ { "viseme_O", 1.0 } }));
}
