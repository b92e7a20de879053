// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file RecordingSpeech.h
/// @brief A recording becomes an Utterance (visemes, nonverbal cues, the recording as its
/// sound), timed by whichever route fits: a transcript aligned to it (any eSpeak language),
/// a timing file (TextGrid, speech marks, .pho, Rhubarb), or, without either, English
/// phoneme recognition (PhonemeRecognizer.h). What vtkBehaviorTimeSource::SpeakAudioFile,
/// MorphAvatar --audio and the Python avatar call.

#include "align/TranscriptAligner.h"
#include "audio/AudioBuffer.h"
#include "speech/Speech.h"
#include "speech/TimingFiles.h"

#include <functional>
#include <string>

namespace morphnode
{
enum class RecordingRoute
{
  Auto,       ///< timing file if given, else transcript if given, else recognition
  Transcript, ///< eSpeak NG synthesis of the transcript + DTW
  TimingFile, ///< timings read from a file
  Recognition ///< PocketSphinx phoneme recognition (English only)
};

struct RecordingOptions
{
  RecordingRoute Route = RecordingRoute::Auto;
  std::string Transcript; ///< UTF-8, in the language of SpeechOptions::Voice
  std::string TimingFile; ///< a .TextGrid, .marks, .pho, .tsv, .json
  /// The timings' bytes in memory (e.g. inline in a dialog command) instead of reading
  /// TimingFile, which then only names them in messages (empty: "inline timings").
  std::string TimingData;
  TimingFileOptions Timing;
  /// Passed to the aligner (its Voice, Warn and Progress are taken from here and the
  /// SpeechOptions when left at their defaults).
  TranscriptAlignOptions Align;
  /// Fraction done (0..1) over the whole job; returning false cancels with InputError.
  std::function<bool(double)> Progress;
};

/// What was done, for the user and for tests.
struct RecordingReport
{
  RecordingRoute Route = RecordingRoute::Auto;
  double Score = 0.0;   ///< alignment or recognition confidence (0..1); 1 for timing files
  bool Reliable = true; ///< false when the route doubts its own result (a warning was sent)
  std::vector<SynthesizedWord> Words; ///< timed words when the route knows them
};

/// The utterance of a recording: its phonemes timed by the route, the viseme track and the
/// cues of BuildUtterance, and the recording (mono, at its own rate up to 48 kHz) as the
/// sound. InputError for every bad input of the route (the message says which); a route
/// that is not available in this build (no eSpeak NG, no PocketSphinx) says so.
Utterance SpeakRecording(const AudioBuffer& recording, const SpeechOptions& speech,
  const RecordingOptions& options = {}, RecordingReport* report = nullptr);

/// Same, reading the recording from a WAV, FLAC or OGG file.
Utterance SpeakAudioFile(const std::string& path, const SpeechOptions& speech,
  const RecordingOptions& options = {}, RecordingReport* report = nullptr);

/// "auto", "transcript", "timing-file", "recognition".
const char* RecordingRouteName(RecordingRoute route);
RecordingRoute ParseRecordingRoute(const std::string& name);
} // namespace morphnode
