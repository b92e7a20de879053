// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ServiceTimings.h
/// @brief Timings that neural and cloud voices return with their audio, beyond Polly's
/// speech marks (SpeechMarks.h):
///
/// - Azure / SAPI viseme IDs: the Speech SDK's VisemeReceived events, each a `VisemeId`
///   (0..21, SAPI's SPVISEMES: 0 silence, 1 ae ax ah, 2 aa, 3 ao, 4 ey eh uh, 5 er,
///   6 y iy ih ix, 7 w uw, 8 ow, 9 aw, 10 oy, 11 ay, 12 h, 13 r, 14 l, 15 s z,
///   16 sh ch jh zh, 17 th dh, 18 f v, 19 d t n, 20 k g ng, 21 p b m) at an `AudioOffset`
///   in 100-nanosecond ticks, as a program collects them into JSON: an array of
///   `{"AudioOffset": ticks, "VisemeId": id}` (keys in either case: audioOffset, visemeId),
///   or an object holding that array as "visemes". An `offsetMs` (milliseconds) may stand
///   for the offset. Each ID becomes a representative SAMPA phoneme (21 -> p: closure).
/// - ElevenLabs-style character alignments (text-to-speech "with timestamps"):
///   `{"characters": [...], "character_start_times_seconds": [...],
///   "character_end_times_seconds": [...]}`, alone or as the "alignment" (or
///   "normalized_alignment") of the service's response. Characters make words (split at
///   white space); each word is read by eSpeak NG in the voice's language and its phonemes
///   are spread over the word's time in proportion to eSpeak's own durations.
///
/// Readers throw InputError naming the entry at fault (wrong type, a missing field, an ID
/// out of range, negative or decreasing times, arrays of different lengths).

#include "speech/SpeechTypes.h"

#include <string>
#include <vector>

namespace morphnode
{
/// The SAMPA phoneme standing for an Azure/SAPI viseme ID; empty outside 0..21.
std::string AzureVisemeToSampa(int visemeId);

/// Azure viseme events (JSON text, see above) as timed SAMPA phonemes: each lasts until the
/// next, the last `lastDuration` seconds; a leading `_` from 0 when the first is later.
std::vector<TimedPhoneme> ParseAzureVisemes(const std::string& json, double lastDuration = 0.15);

struct AlignedWord
{
  std::string Text; ///< UTF-8
  double Start = 0.0;
  double End = 0.0;
};

/// The words of a character alignment (JSON text, see above), in order.
std::vector<AlignedWord> ParseCharacterAlignment(const std::string& json);

/// Timed SAMPA phonemes of aligned words: each word read by eSpeak NG in `voice` and its
/// phonemes fitted into the word's time; gaps between words become pauses. InputError when
/// eSpeak NG is not available or the voice is unknown.
std::vector<TimedPhoneme> PhonemesOfAlignedWords(
  const std::vector<AlignedWord>& words, const std::string& voice);
} // namespace morphnode
