// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file PhonemeRecognizer.h
/// @brief The route without a transcript: English phoneme recognition with PocketSphinx
/// (Debian libpocketsphinx-dev 5prealpha, its `-allphone` search with the en-us acoustic
/// model and phonetic language model of pocketsphinx-en-us). Much less precise than
/// aligning a transcript (docs/speech.md gives the figures); for English only.

#include "audio/AudioBuffer.h"
#include "speech/SpeechTypes.h"
#include "speech/Warning.h"

#include <functional>
#include <string>
#include <vector>

namespace morphnode
{
struct RecognitionOptions
{
  /// The folder holding the en-us acoustic model (`en-us/`) and `en-us-phone.lm.bin`;
  /// empty: the one pocketsphinx-en-us installs (/usr/share/pocketsphinx/model/en-us).
  std::string ModelDirectory;
  /// Language-model weight of the phone search: higher favours likely phone sequences.
  double LanguageWeight = 2.0;
  std::function<bool(double)> Progress; ///< fraction done; false cancels (InputError)
  WarningHandler Warn;
};

struct PhonemeRecognition
{
  /// English SAMPA phonemes (ARPAbet mapped), pauses `_`, tiling [0, Duration].
  std::vector<TimedPhoneme> Phonemes;
  double Duration = 0.0;
};

/// False when MorphNode was built without PocketSphinx (MORPHNODE_ENABLE_POCKETSPHINX=OFF).
bool IsPhonemeRecognitionAvailable();

/// Recognizes the phonemes of an English recording (any rate and channel count; it is
/// resampled to 16 kHz mono). InputError when recognition is unavailable, the model folder
/// lacks the model, the recording is empty or holds no speech, or on cancellation.
PhonemeRecognition RecognizePhonemes(
  const AudioBuffer& recording, const RecognitionOptions& options = {});
} // namespace morphnode
