// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SpeechTypes.h
/// @brief What speech hands to the behaviour control: timed phonemes, a viseme weight
/// track, nonverbal cues and the audio, on one time axis (seconds from the utterance start).

#include "track/WeightTrack.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace morphnode
{
/// One phoneme in SAMPA with its timing, as in an MBROLA .pho line.
struct TimedPhoneme
{
  std::string Sampa;
  double Start = 0.0;    ///< seconds
  double Duration = 0.0; ///< seconds
  /// Pitch targets: (position within the phoneme in [0, 1], frequency in Hz).
  std::vector<std::pair<double, double>> Pitch;
};

/// Nonverbal behaviour derived from the speech (the paper's heuristics).
struct NonverbalCue
{
  enum class Kind
  {
    BrowRaise, ///< pitch accent
    Blink,     ///< a pause invites a blink
    Nod,       ///< sentence end
    Relax      ///< a pause relaxes the face
  };
  Kind Type = Kind::Relax;
  double Start = 0.0;     ///< seconds
  double Duration = 0.0;  ///< seconds
  double Intensity = 1.0; ///< [0, 1]
};

/// A synthesized or loaded utterance.
struct Utterance
{
  std::vector<TimedPhoneme> Phonemes;
  /// Viseme weights over time, one channel per viseme name of the chosen viseme set.
  WeightTrack Visemes;
  std::vector<NonverbalCue> Cues;
  std::vector<int16_t> Audio; ///< mono samples; empty when there is no audio
  int SampleRate = 22050;
  double Duration = 0.0; ///< seconds
};
} // namespace morphnode
