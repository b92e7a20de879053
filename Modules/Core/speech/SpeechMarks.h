// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SpeechMarks.h
/// @brief Speech marks as cloud text-to-speech services return them (Amazon Polly's JSON
/// lines): one JSON object a line, `{"time": ms, "type": "word"|"viseme"|"phoneme"|
/// "sentence"|"ssml", "value": ..., "start": byte, "end": byte}`, as timed SAMPA phonemes.
///
/// Polly's visemes (p t S T f k i r s u @ a e E o O sil) become a representative SAMPA
/// phoneme each (p -> p, whose viseme is the bilabial closure; u -> u:, ...), so that they
/// run through the same viseme table, coarticulation and closure rules as phonemes do.
/// `phoneme` events (other engines) carry SAMPA, ARPAbet or IPA, guessed as for TextGrids.
/// A viseme or phoneme lasts until the next one; the last one `LastDuration`.

#include "speech/PhoneSets.h"
#include "speech/SpeechTypes.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
struct SpeechMarkWord
{
  double Start = 0.0; ///< seconds
  std::string Text;
};

struct SpeechMarks
{
  std::vector<TimedPhoneme> Phonemes; ///< SAMPA, a leading `_` from 0 when the first is later
  std::vector<SpeechMarkWord> Words;
  double Duration = 0.0; ///< end of the last phoneme
};

struct SpeechMarkOptions
{
  double LastDuration = 0.15;                   ///< seconds given to the last viseme or phoneme
  PhoneAlphabet Alphabet = PhoneAlphabet::Auto; ///< of `phoneme` events
  std::string Language = "en";
};

/// The SAMPA phoneme standing for a Polly viseme; empty for an unknown one.
std::string PollyVisemeToSampa(const std::string& viseme);

/// Reads JSON lines. InputError "speech marks line <n>: ..." for a line that is not a JSON
/// object, a missing or negative time, an unknown viseme, a time earlier than the previous
/// event's (out of order), or a file with no viseme or phoneme events at all.
SpeechMarks ReadSpeechMarks(std::istream& in, const SpeechMarkOptions& options = {});
SpeechMarks ParseSpeechMarks(const std::string& text, const SpeechMarkOptions& options = {});
SpeechMarks ReadSpeechMarksFile(const std::string& path, const SpeechMarkOptions& options = {});
} // namespace morphnode
