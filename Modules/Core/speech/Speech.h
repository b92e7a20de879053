// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Speech.h
/// @brief Text (or phonemes, or Rhubarb cues) to an Utterance in one call: synthesize with
/// eSpeak NG, normalize to SAMPA, map to visemes, coarticulate, derive nonverbal cues.

#include "speech/Coarticulation.h"
#include "speech/Nonverbal.h"
#include "speech/Rhubarb.h"
#include "speech/SpeechSynthesizer.h"
#include "speech/SpeechTypes.h"
#include "speech/VisemeMap.h"
#include "speech/Warning.h"

#include <string>
#include <vector>

namespace morphnode
{
struct SpeechOptions
{
  std::string Voice = "en";                  ///< eSpeak voice
  int Rate = SpeechSynthesizer::DefaultRate; ///< words per minute, clamped to <= 450
  std::string DataPath;                      ///< espeak-ng-data folder; empty: default
  /// Language of the SAMPA normalization and viseme table; empty: from Voice.
  std::string Language;
  VisemeSet Visemes = VisemeSet::Oculus15;
  /// A viseme table file overriding the built-in one of `Visemes` (empty: built-in).
  std::string VisemeTablePath;
  CoarticulationOptions Coarticulation;
  NonverbalOptions Nonverbal;
  bool EstimatePitch = true; ///< pitch from the audio, for pitch accents
  WarningHandler Warn;       ///< unknown phonemes and the like
};

/// The viseme table the options select.
VisemeMap SelectVisemeMap(const SpeechOptions& options);

/// Builds an utterance from SAMPA phonemes and (possibly empty) audio. When the mouth
/// lead is longer than the silence before the first spoken phoneme, the phonemes and the
/// audio are delayed by the difference (audio padded with silence), so the mouth can
/// still move first. Duration = the longer of the audio and the phonemes.
Utterance BuildUtterance(std::vector<TimedPhoneme> phonemes, std::vector<int16_t> audio,
  int sampleRate, const VisemeMap& map, const SpeechOptions& options);

/// Text -> utterance: SpeechSynthesizer, then BuildUtterance. InputError when eSpeak fails.
Utterance SpeakText(const std::string& text, const SpeechOptions& options = {});

/// SAMPA phonemes (e.g. ParsePho's) -> utterance without audio (BuildUtterance at 22050 Hz).
/// InputError when there are none.
Utterance UtteranceFromPhonemes(
  std::vector<TimedPhoneme> phonemes, const SpeechOptions& options = {});

/// A .pho file -> utterance without audio (UtteranceFromPhonemes).
Utterance LoadPhoUtterance(const std::string& path, const SpeechOptions& options = {});

/// Rhubarb cues -> utterance without audio: Phonemes empty, Visemes blended from the cues,
/// no nonverbal cues (shapes carry no pitch or pauses worth reading). InputError when there
/// are no cues.
Utterance UtteranceFromMouthCues(
  const std::vector<MouthCue>& cues, const SpeechOptions& options = {});
} // namespace morphnode
