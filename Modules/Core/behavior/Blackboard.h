// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Blackboard.h
/// @brief Where every behaviour writes its contribution for one instant, by channel group
/// and priority layer, and the one place where the blending rules live (docs/behavior.md).
///
/// Layers, lowest first: Background (mood and idle behaviour), Speech (visemes and the
/// cues of an utterance), Explicit (gestures and looks). Rules, by group:
/// - Brows, Expression (MouthSmile, MouthSad): an explicit gesture owns its group: the
///   background and speech contributions fade out by (1 - ownership), ownership being the
///   strongest envelope of the group's explicit gestures. A Relax cue halves the background.
/// - Mouth: speech activity a (sum of non-silent visemes, <= 1) damps the expression:
///   MouthSmile and MouthSad *= 1 - SpeechExpressionDamping * a, so a smile never fights
///   an open vowel.
/// - Lids: blinks merge into the background lid (lid + (1 - lid) * blink); an explicit
///   close-eyes takes the maximum, so nothing re-opens closed eyes. (Idle and speech blinks
///   overlapping a close-eyes gesture are also dropped when the schedule is built.)
/// - Head: idle micro-motion fades out by (1 - ownership) under explicit head gestures;
///   mood posture, the head's share of a look, speech nods and gestures add up.
/// - Gaze: the eyes hold the gaze target against the head (vestibulo-ocular reflex):
///   eye = gaze + saccade * (1 - look ownership) - head; idle saccades pause during a look.
///   Eye angles are clamped to the eye ranges; Look* shapes are eye angle / range in [0, 1].

#include "behavior/BehaviorTypes.h"
#include "behavior/Timeline.h"
#include "speech/SpeechTypes.h"

#include <array>

namespace morphnode
{
struct Blackboard
{
  /// The semantic shapes EyesClosed..MouthSad (BehaviorChannel ids 0..5).
  static constexpr int NumberOfShapes = 6;
  enum Group : int
  {
    BrowsGroup = 0,
    ExpressionGroup,
    HeadGroup,
    GazeGroup,
    NumberOfGroups
  };

  std::array<double, NumberOfShapes> Background{}; ///< mood + idle smiles
  std::array<double, NumberOfShapes> Speech{};     ///< speech cues (brow raises)
  std::array<double, NumberOfShapes> Explicit{};   ///< gestures: intensity x envelope
  std::array<double, NumberOfGroups> Ownership{};  ///< explicit envelope per group, 0..1
  double Blink = 0.0;          ///< strongest blink curve (idle, speech cue, blink gesture)
  double CloseEyes = 0.0;      ///< explicit close-eyes: intensity x envelope
  double Relax = 0.0;          ///< speech Relax cue, 0..1
  double SpeechActivity = 0.0; ///< 0..1

  // Degrees: yaw, pitch, roll.
  std::array<double, 3> HeadIdle{};       ///< micro-motion
  std::array<double, 3> HeadBackground{}; ///< mood posture
  std::array<double, 3> HeadGaze{};       ///< the head's share of a look
  std::array<double, 3> HeadSpeech{};     ///< speech nods
  std::array<double, 3> HeadExplicit{};   ///< nod, shake, tilt
  // Degrees: yaw, pitch.
  std::array<double, 2> Gaze{};    ///< where the eyes look, head-independent
  std::array<double, 2> Saccade{}; ///< idle offset

  /// The explicit gaze at t (the `look` gestures of both behaviour engines): Gaze and the
  /// gaze group's ownership from `eye` (yaw, pitch, ownership), HeadGaze from `head`.
  void SetExplicitGaze(const FadeTrack<3>& eye, const FadeTrack<2>& head, double t);

  /// Writes the base channels (BehaviorChannel ids) from the contributions.
  void Resolve(const BehaviorParameters& parameters, double* out) const;

  /// Adds a speech cue at t (speech layer): a brow raise, a relaxation, a nod. Blink cues
  /// add nothing here (they are played with the other blinks).
  void AddSpeechCue(NonverbalCue::Kind kind, const SyncPoints& sync, double intensity, double t,
    const BehaviorParameters& parameters);
};

/// The sync points of a speech cue that starts at `start` on the behaviour's time axis.
SyncPoints SpeechCueSync(
  const NonverbalCue& cue, double start, const BehaviorParameters& parameters);
} // namespace morphnode
