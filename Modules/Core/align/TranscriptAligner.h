// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TranscriptAligner.h
/// @brief A recording plus its transcript -> the transcript's phonemes timed on the
/// recording, in any language eSpeak NG speaks.
///
/// The route: eSpeak NG synthesizes the transcript (its phoneme timings are exact), both
/// sounds become MFCC frames, dynamic time warping aligns the synthetic frames to the
/// recorded ones, and every phoneme boundary is carried across the warping path. Beyond the
/// textbook version: silence is found in each sound and trimmed at the ends, silent frames
/// compare as equal whatever their noise (canonical silence features) and may stretch
/// freely inside the slope constraint (pauses of any length); the transcript is synthesized
/// a second time at the speaking rate measured on the recording, so the warping only has to
/// absorb local differences; long files are aligned coarse-to-fine in windows (Dtw.h).

#include "align/Dtw.h"
#include "align/Mfcc.h"
#include "audio/AudioBuffer.h"
#include "speech/SpeechSynthesizer.h"
#include "speech/SpeechTypes.h"
#include "speech/Warning.h"

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace morphnode
{
struct TranscriptAlignOptions
{
  std::string Voice = "en"; ///< eSpeak voice of the transcript's language
  std::string DataPath;     ///< espeak-ng-data folder; empty: eSpeak's default
  /// Words per minute of the first synthesis; 0: eSpeak's default (175).
  int Rate = 0;
  /// Re-synthesize at the recording's measured rate when it differs by more than 10 %.
  bool AdaptRate = true;
  MfccOptions Mfcc;
  DtwOptions Dtw;
  /// A frame is silent below this many dB under the loud frames (95th percentile), or
  /// when it is close to the noise floor of a noisy recording.
  double SilenceDecibels = 35.0;
  /// Weight of the log-energy feature against the 12 normalized cepstra.
  double EnergyWeight = 1.5;
  /// Alignments scoring below this are reported as not matching the transcript
  /// (Reliable = false and a warning), unless the acoustic check below finds that the
  /// transcript fits. Calibrated in docs/speech.md.
  double MinimumScore = 0.2;
  /// The acoustic check (English, with PocketSphinx, recordings up to MaximumCheckSeconds,
  /// every word in the CMU dictionary): the transcript fits when it can be forced through
  /// the recording at most this times the acoustic cost of a free phone decode of the same
  /// audio (FitTranscript, PhonemeRecognizer.h). Relative to what the audio supports, so a
  /// short recording of natural speech, whose alignment Score is low even for its own
  /// words, does not warn falsely. Calibrated on pocketsphinx-testdata's cards
  /// (docs/speech.md).
  double MaximumFitRatio = 0.83;
  double MaximumCheckSeconds = 30.0;
  bool AcousticCheck = true; ///< off: the Score alone decides
  /// Called with the fraction done (0..1); returning false cancels with InputError.
  std::function<bool(double)> Progress;
  WarningHandler Warn;
};

struct TranscriptAlignment
{
  /// SAMPA phonemes (language of the voice) on the recording's time axis; the first starts at
  /// 0 and the last ends at Duration.
  std::vector<TimedPhoneme> Phonemes;
  /// The transcript's words on the same axis.
  std::vector<SynthesizedWord> Words;
  double Duration = 0.0;    ///< seconds of the recording
  double SpeechStart = 0.0; ///< first and last speech found in the recording, seconds
  double SpeechEnd = 0.0;
  /// 1 - (mean distance along the path) / (mean distance between random frames): near 0.5
  /// for a recording of the transcript, near 0 for a transcript that does not match it.
  double Score = 0.0;
  /// The acoustic check's forced / free cost ratio (TranscriptAlignOptions::MaximumFitRatio);
  /// +inf when the transcript could not be forced through the recording; NaN when the check
  /// did not run (another language, no PocketSphinx, a word not in its dictionary, a long
  /// recording): then Score alone decided.
  double FitRatio = std::numeric_limits<double>::quiet_NaN();
  /// Score >= MinimumScore or FitRatio <= MaximumFitRatio (and the tempo was plausible).
  bool Reliable = false;
  int SynthesisRate = 0;   ///< words per minute of the synthesis aligned
  double TempoRatio = 1.0; ///< recorded speech duration / synthetic, before rate adaption
  size_t CellsEvaluated = 0;
};

/// True when the route can run (built with eSpeak NG, MORPHNODE_ENABLE_ESPEAK=ON).
bool IsTranscriptAlignmentAvailable();

/// Aligns `transcript` (UTF-8) to `recording` (any rate and channel count). InputError for:
/// no eSpeak NG in this build, an empty recording or transcript, a recording without speech
/// (silence or steady noise only), a transcript eSpeak finds nothing to say in, a tempo
/// beyond what a matching transcript can have (speech 3x longer or shorter than the
/// synthesis), or cancellation. A low Score only warns (Reliable false): the caller decides.
TranscriptAlignment AlignTranscript(const AudioBuffer& recording, const std::string& transcript,
  const TranscriptAlignOptions& options = {});

/// The frames of `audio` that are silence by the rule above (exposed for tests and plots).
std::vector<bool> FindSilentFrames(const MfccFeatures& features, double silenceDecibels);
} // namespace morphnode
