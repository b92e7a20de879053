// SPDX-License-Identifier: BSD-3-Clause
// Gestures and moods as data (BehaviorLibrary): the built-in data, files over it, errors
// naming the JSON path, the override rules' arithmetic.
#include "base/Error.h"
#include "behavior/BehaviorLibrary.h"

#include <gtest/gtest.h>

#include <string>

using namespace morphnode;

namespace
{
std::string ErrorOf(const std::string& json)
{
  try
  {
    BehaviorLibrary::FromJson(json, "test.json");
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(BehaviorLibrary, DefaultHoldsEveryCompiledGestureAndMood)
{
  const BehaviorLibrary& library = BehaviorLibrary::Default();
  for (GestureKind kind : { GestureKind::Smile, GestureKind::Sad, GestureKind::Nod,
         GestureKind::Shake, GestureKind::Tilt, GestureKind::RaiseBrows, GestureKind::Frown,
         GestureKind::Fright, GestureKind::CloseEyes, GestureKind::Blink })
  {
    const GestureDefinition& g = library.FindGesture(GestureName(kind));
    EXPECT_DOUBLE_EQ(g.Duration, DefaultGestureDuration(kind)) << GestureName(kind);
  }
  for (MoodKind kind : { MoodKind::Neutral, MoodKind::Happy, MoodKind::Sad, MoodKind::Angry,
         MoodKind::Afraid, MoodKind::Surprised })
  {
    EXPECT_GE(library.FindMoodIndex(MoodName(kind)), 0) << MoodName(kind);
  }
  // Aliases and spelling as ParseGestureName accepts them.
  EXPECT_EQ(&library.FindGesture("Raise-Brows"), &library.FindGesture("browsup"));
  EXPECT_EQ(&library.FindMood("JOY"), &library.FindMood("happy"));
  EXPECT_EQ(library.FindGesture("close_eyes").OverrideBlink, OverrideMode::Block);
  EXPECT_TRUE(library.FindGesture("blink").Blink);
  try
  {
    library.FindGesture("spin");
    FAIL() << "no error for an unknown gesture";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("nod"), std::string::npos) << e.what();
  }
}

TEST(BehaviorLibrary, ParameterNamesResolve)
{
  const GestureDefinition& nod = BehaviorLibrary::Default().FindGesture("nod");
  BehaviorParameters p;
  p.NodAmplitude = 7.5;
  EXPECT_DOUBLE_EQ(nod.Amplitude.Resolve(p), 7.5);
  const GestureDefinition& close = BehaviorLibrary::Default().FindGesture("close_eyes");
  p.BlinkCloseTime = 0.2;
  EXPECT_DOUBLE_EQ(close.Attack.Resolve(p), 0.2);
}

TEST(BehaviorLibrary, FileOverDefaults)
{
  const BehaviorLibrary library = BehaviorLibrary::FromJson(R"({
      "gestures": { "shrug": { "duration": 1.0, "shapes": { "BrowsUp": 0.5 },
                               "head": { "motion": "hold", "pitch": 3, "roll": "TiltAmplitude" } },
                    "nod": { "duration": 2.0, "head": { "motion": "nod", "amplitude": 4 } } },
      "moods": { "bored": { "blinkRate": 0.5, "gaze": { "pitch": -10 } } } })",
    "test.json", &BehaviorLibrary::Default());
  EXPECT_DOUBLE_EQ(library.FindGesture("shrug").Shapes[BehaviorChannel::BrowsUp], 0.5);
  EXPECT_DOUBLE_EQ(library.FindGesture("nod").Duration, 2.0); // replaced
  EXPECT_GE(library.FindGestureIndex("smile"), 0);            // kept
  EXPECT_DOUBLE_EQ(library.FindMood("bored").BlinkRate, 0.5);
  EXPECT_GE(library.FindMoodIndex("neutral"), 0);
  // A library without moods still knows neutral.
  EXPECT_GE(BehaviorLibrary::FromJson("{}").FindMoodIndex("neutral"), 0);
}

TEST(BehaviorLibrary, ErrorsNameTheJsonPath)
{
  EXPECT_NE(ErrorOf("{").find("test.json: not valid JSON"), std::string::npos);
  EXPECT_NE(ErrorOf("[]").find("expected an object"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gesture": {}})").find("unknown key 'gesture'"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"nod": {"head": {"motion": "spin", "amplitude": 1}}}})")
              .find("gestures.nod.head.motion: unknown motion 'spin'"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"x": {"shapes": {"Mouth": 1}}}})")
              .find("gestures.x.shapes: unknown shape 'Mouth'"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"x": {"shapes": {"BrowsUp": "a"}}}})")
              .find("gestures.x.shapes.BrowsUp: expected a number"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"moods": {"sad": {"blinkRate": 0}}})").find("moods.sad.blinkRate: value 0"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"x": {"overrideBlink": "maybe"}}})")
              .find("gestures.x.overrideBlink: unknown override 'maybe'"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"x": {"attack": "Speed"}}})")
              .find("gestures.x.attack: unknown behaviour parameter 'Speed'"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"x": {"mouthShapes": ["ou", 3]}}})")
              .find("gestures.x.mouthShapes[1]: expected a string"),
    std::string::npos);
  EXPECT_NE(
    ErrorOf(R"({"gestures": {"x": {"head": {"motion": "nod"}}}})").find("needs an amplitude"),
    std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gestures": {"--": {}}})").find("needs a name"), std::string::npos);
  EXPECT_THROW(BehaviorLibrary::Load("/nonexistent/behavior.json"), InputError);
}

TEST(BehaviorLibrary, OverrideArithmetic)
{
  EXPECT_DOUBLE_EQ(OverrideFactor(OverrideMode::None, 0.7), 1.0);
  EXPECT_DOUBLE_EQ(OverrideFactor(OverrideMode::Blend, 0.7), 1.0 - 0.7);
  EXPECT_DOUBLE_EQ(OverrideFactor(OverrideMode::Block, 0.01), 0.0);
  EXPECT_DOUBLE_EQ(OverrideFactor(OverrideMode::Block, 0.0), 1.0);
  EXPECT_EQ(ParseOverrideMode("Block"), OverrideMode::Block);
  EXPECT_THROW(ParseOverrideMode("sometimes"), InputError);
}

TEST(BehaviorLibrary, MoodEffectBlendsFromNeutral)
{
  const MoodDefinition& sad = BehaviorLibrary::Default().FindMood("sad");
  const auto half = MoodEffect::Of(sad, 0.5);
  EXPECT_DOUBLE_EQ(half[MoodEffect::BlinkRate], 1.0 + 0.5 * (sad.BlinkRate - 1.0));
  EXPECT_DOUBLE_EQ(half[MoodEffect::Shape0 + BehaviorChannel::MouthSad], 0.5 * sad.Shapes[5]);
  EXPECT_EQ(MoodEffect::Of(sad, 0.0), MoodEffect::Neutral());
}
