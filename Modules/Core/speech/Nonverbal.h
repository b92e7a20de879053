// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Nonverbal.h
/// @brief The paper's heuristics: nonverbal facial expression from phoneme information.
///
/// - Pitch accent: a voiced phoneme whose pitch is a local peak (the highest within
///   +-AccentNeighbourhood) and at least AccentRatio times the utterance's mean pitch raises
///   the brows (BrowRaise, starting BrowLead before the phoneme, intensity growing with the
///   excess). Raises closer than AccentMinimumSpacing keep only the stronger one.
/// - Pause: a pause of at least RelaxPause relaxes the face for its length (Relax); one of
///   at least BlinkPause also invites a blink at its start (Blink).
/// - Sentence end: a pause of at least SentencePause after speech, and the end of the
///   utterance, nods (Nod, on the last voiced phoneme) - unless the pitch rises there
///   (the last pitch >= QuestionRise * mean: a question), which gets a brow raise instead.
/// docs/speech.md explains the figures.

#include "speech/SpeechTypes.h"

#include <vector>

namespace morphnode
{
struct NonverbalOptions
{
  double AccentRatio = 1.12;         ///< peak pitch / mean pitch for an accent
  double AccentNeighbourhood = 0.25; ///< seconds either side a peak must dominate
  double AccentMinimumSpacing = 0.8; ///< seconds between brow raises
  double BrowLead = 0.1;             ///< brows start this much before the accent
  double BrowDuration = 0.5;         ///< seconds
  double RelaxPause = 0.15;          ///< seconds of pause that relax the face
  double BlinkPause = 0.25;          ///< seconds of pause that invite a blink
  double BlinkDuration = 0.25;       ///< seconds
  double SentencePause = 0.25;       ///< seconds of pause that end a sentence
  double NodDuration = 0.6;          ///< seconds
  double QuestionRise = 1.1;         ///< final pitch / mean pitch that marks a question
};

/// Cues sorted by start; all starts >= 0 and intensities in [0, 1]. Phonemes without pitch
/// targets give no accents (pauses and sentence ends still work).
std::vector<NonverbalCue> DeriveNonverbalCues(
  const std::vector<TimedPhoneme>& phonemes, const NonverbalOptions& options = {});
} // namespace morphnode
