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

/// How well an English transcript fits a recording, relative to what the audio supports: the
/// acoustic cost (minus log-likelihood) of the transcript forced through the recording
/// (PocketSphinx: its words in order from the CMU dictionary, triphones, optional pauses
/// between words) against that of a free phone-loop decode of the same audio (phones in
/// any order). A recording of the transcript fits it better than the free decode
/// (ratio below 1: on pocketsphinx-testdata's cards 0.37 to 0.73); another text costs more
/// (0.94 to 2.8), or cannot be forced through the recording at all.
struct TranscriptFit
{
  bool Completed = false; ///< the forced path reached the transcript's end
  double Ratio = 0.0;     ///< forced cost / free cost (when Completed)
  int Frames = 0;         ///< 10-ms frames decoded
};

/// InputError when recognition is unavailable, the model is missing, a word of the
/// transcript is not in the CMU dictionary (then nothing can be said), or the transcript
/// has no words.
TranscriptFit FitTranscript(const AudioBuffer& recording, const std::string& transcript,
  const RecognitionOptions& options = {});

/// Recognizes the phonemes of an English recording (any rate and channel count; it is
/// resampled to 16 kHz mono). InputError when recognition is unavailable, the model folder
/// lacks the model, the recording is empty or holds no speech, or on cancellation.
PhonemeRecognition RecognizePhonemes(
  const AudioBuffer& recording, const RecognitionOptions& options = {});
} // namespace morphnode
