// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SpeechTrack.h
/// @brief The long speech-driven animation of the optimizer study (docs/optimizer-study.md):
/// a text spoken by eSpeak NG with what a lively speaker does besides talking, expanded
/// through a rig onto a face's own targets. MakeSpeechTrack writes it; TestOptimizerStudy
/// checks the study's claims on the very same track.

#include "rig/Rig.h"
#include "speech/Speech.h"
#include "track/WeightTrack.h"

#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
namespace study
{
struct SpeechTrackOptions
{
  std::string Text; ///< what is said (line breaks are spaces)
  std::string Voice = "en";
  int Rate = SpeechSynthesizer::DefaultRate; ///< words per minute
  uint64_t Seed = 2004;
  double FrameRate = 30.0;
};

/// The behaviour's semantic channels (visemes, EyesClosed, BrowsUp, LookLeft, HeadYaw, ...):
/// the text spoken from 0.6 s with a happy mood, idle blinks and saccades, and seeded
/// gestures every 1.5-4 s (brow raises, smiles, nods, frowns, glances), a warm ending and
/// one second after the speech. The same options give the same track.
WeightTrack MakeBehaviorTrack(const SpeechTrackOptions& options);

/// The semantic channels through a bound rig: relative (glTF) weights of the face's
/// targets `targetNames` (the rig's bound targets, in its order). Channels without a
/// shape (head and eye angles) are left out and named in `dropped` when given.
WeightTrack ExpandThroughRig(const WeightTrack& semantic, const Rig& rig,
  const std::vector<std::string>& targetNames, std::vector<std::string>* dropped = nullptr);
} // namespace study
} // namespace morphnode
