// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file BehaviorLibrary.h
/// @brief Gestures and moods as data (JSON), with override rules in the spirit of VRM 1.0
/// expressions, so that expressions never fight. The built-in library (Default()) is the
/// data file behavior/data/behavior.json compiled in: it works without any file.
///
/// File format (docs/behavior.md, "Behaviour as data"):
///
///   { "gestures": { "smile": { "aliases": ["grin"], "duration": 1.5, "attack": 0.3,
///                              "release": 0.4, "shapes": { "MouthSmile": 1.0 },
///                              "overrideMouth": "blend", "mouthShapes": ["ou", "oh"] },
///                   "nod":   { "duration": 0.8, "attack": 0.2, "release": 0.2,
///                              "head": { "motion": "nod", "amplitude": "NodAmplitude",
///                                        "cycle": 0.5 } },
///                   "close_eyes": { "shapes": { "EyesClosed": 1.0 },
///                                   "overrideBlink": "block", "overrideLookAt": "block" },
///                   "blink": { "blink": true } },
///     "moods":    { "sad": { "shapes": { "MouthSad": 0.7, ... }, "head": { "pitch": -4 },
///                            "blinkRate": 0.8, "saccadeRange": 0.7, "fixation": 1.4,
///                            "gaze": { "yaw": 0, "pitch": -6 }, "headMotion": 0.6,
///                            "idleSmiles": 0.0 } } }
///
/// Override rules (VRM 1.0 "overrideBlink/overrideLookAt/overrideMouth"): "none" (the
/// default), "blend" (the overridden behaviour is multiplied by 1 - w, w = the gesture's
/// intensity x envelope) or "block" (it is 0 while w > 0). The mouth override acts on the
/// viseme channels named in "mouthShapes" (every non-silent viseme when absent): a strong
/// expression limits the mouth shapes it clashes with. Speech in turn limits a mood's (and a
/// gesture's) mouth: MouthSmile/MouthSad *= 1 - SpeechExpressionDamping x speech activity
/// (Blackboard::Resolve).
///
/// Errors name the JSON path: "behaviour library: gestures.nod.head.motion: unknown
/// motion 'spin' (known: hold, nod, shake)".

#include "behavior/BehaviorTypes.h"
#include "behavior/Blackboard.h"

#include <array>
#include <string>
#include <vector>

namespace morphnode
{
/// VRM 1.0's MaterialBindType-like override of one behaviour by an expression.
enum class OverrideMode
{
  None,  ///< no effect
  Blend, ///< the overridden weight x (1 - w)
  Block  ///< the overridden weight is 0 while w > 0
};
/// "none", "blend", "block"; InputError otherwise.
OverrideMode ParseOverrideMode(const std::string& name);
const char* OverrideModeName(OverrideMode mode);
/// The factor an override of weight w (0..1) leaves on what it overrides.
double OverrideFactor(OverrideMode mode, double w);

/// A number in the data that may name a behaviour parameter instead ("NodAmplitude"): a
/// figure the user tunes with the parameters stays one figure.
struct ParameterValue
{
  double Value = 0.0;
  int Parameter = -1; ///< index into BehaviorParameterNames(), -1 for a literal
  double Resolve(const BehaviorParameters& p) const;
};

enum class HeadMotion
{
  Hold, ///< yaw/pitch/roll offsets under the envelope
  Nod,  ///< pitch down by Amplitude and back, one bump per Cycle seconds
  Shake ///< yaw left-right by Amplitude, one swing per Cycle seconds, in a sine window
};

struct GestureDefinition
{
  std::string Name; ///< canonical (lower case, '_' kept)
  std::vector<std::string> Aliases;
  double Duration = 1.5;             ///< used when a command gives none
  ParameterValue Attack{ 0.3, -1 };  ///< seconds; fitted to the duration (SyncPoints::Make)
  ParameterValue Release{ 0.4, -1 }; ///< seconds
  /// Contributions at intensity 1 to the semantic shapes (BehaviorChannel ids 0..5).
  /// EyesClosed acts as "close eyes" (the maximum with the lids, never re-opened by a
  /// blink); brows own the brows group, MouthSmile/MouthSad the expression group.
  std::array<double, Blackboard::NumberOfShapes> Shapes{};
  HeadMotion Motion = HeadMotion::Hold;
  std::array<ParameterValue, 3> Head{}; ///< Hold: yaw, pitch, roll degrees
  ParameterValue Amplitude;             ///< Nod/Shake: degrees
  double Cycle = 0.5;                   ///< Nod/Shake: seconds per bump or swing
  bool HasHead = false;                 ///< owns the head group
  bool Blink = false; ///< one blink at the start (amplitude = intensity; lasts a blink)
  OverrideMode OverrideBlink = OverrideMode::None;
  OverrideMode OverrideLookAt = OverrideMode::None;
  OverrideMode OverrideMouth = OverrideMode::None;
  std::vector<std::string> MouthShapes; ///< viseme names; empty: all non-silent visemes

  /// The gesture's sync points for a start, a duration (<= 0: Duration) and parameters.
  SyncPoints Sync(double start, double duration, const BehaviorParameters& p) const;
  /// Adds the gesture's contribution at t to the blackboard (explicit layer). `sync` from
  /// Sync(). Blink gestures add nothing here (their blink is played with the others).
  void Contribute(const SyncPoints& sync, double intensity, double t, const BehaviorParameters& p,
    Blackboard& bb) const;
};

/// What a mood changes at intensity 1. Shapes and head posture add up; the factors are
/// relative (1 = no change) and blend as 1 + w (factor - 1).
struct MoodDefinition
{
  std::string Name;
  std::vector<std::string> Aliases;
  std::array<double, Blackboard::NumberOfShapes> Shapes{};
  std::array<double, 3> Head{}; ///< posture: yaw, pitch, roll degrees
  double BlinkRate = 1.0;       ///< x the blink rates
  double SaccadeRange = 1.0;    ///< x SaccadeRange and SaccadeMaxAmplitude
  double Fixation = 1.0;        ///< x FixationMean (longer: a calmer gaze)
  std::array<double, 2> Gaze{}; ///< yaw, pitch degrees added to where the eyes rest
  double HeadMotion = 1.0;      ///< x head micro-motion amplitudes
  double IdleSmiles = 1.0;      ///< x idle smile intensity (0 holds them back)
};

/// A mood's effect as one vector, so that moods fade and blend linearly (FadeTrack).
struct MoodEffect
{
  enum Index : int
  {
    Shape0 = 0, // + NumberOfShapes
    HeadYaw = Blackboard::NumberOfShapes,
    HeadPitch,
    HeadRoll,
    BlinkRate,
    SaccadeRange,
    Fixation,
    GazeYaw,
    GazePitch,
    HeadMotion,
    IdleSmiles,
    Size
  };
  using Vector = std::array<double, Size>;
  /// No mood: zero shapes and posture, factors 1.
  static Vector Neutral();
  /// Neutral + intensity x (definition - neutral).
  static Vector Of(const MoodDefinition& mood, double intensity);
};

class BehaviorLibrary
{
public:
  /// The built-in gestures and moods (the JSON text of DefaultJson(), parsed once).
  static const BehaviorLibrary& Default();
  /// The built-in library as JSON text (identical to behavior/data/behavior.json).
  static const char* DefaultJson();
  /// Parses a library. A file may hold "gestures", "moods" or both; with `base` given,
  /// its entries are added to (or replace, by name) a copy of `base`. InputError naming
  /// `origin` and the JSON path of the problem.
  static BehaviorLibrary FromJson(const std::string& text,
    const std::string& origin = "behaviour library", const BehaviorLibrary* base = nullptr);
  /// Reads a file (InputError when it cannot be read), over the defaults.
  static BehaviorLibrary Load(const std::string& path);

  const std::vector<GestureDefinition>& GetGestures() const { return this->Gestures; }
  const std::vector<MoodDefinition>& GetMoods() const { return this->Moods; }
  /// By name or alias (case, '_' and '-' do not matter); InputError listing the known
  /// names. "neutral" is always a mood (no effect).
  const GestureDefinition& FindGesture(const std::string& name) const;
  const MoodDefinition& FindMood(const std::string& name) const;
  /// -1 when absent.
  int FindGestureIndex(const std::string& name) const;
  int FindMoodIndex(const std::string& name) const;

private:
  std::vector<GestureDefinition> Gestures;
  std::vector<MoodDefinition> Moods;
};
} // namespace morphnode
