// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Pho.h
/// @brief MBROLA .pho files: SAMPA phonemes with durations and pitch targets.
///
/// One phoneme a line: `name duration_ms [position% pitch_Hz]...`. `;` starts a comment,
/// `;;` a command line (`;; T=<time ratio>` scales later durations, `;; F=<frequency
/// ratio>` later pitch values; other commands are ignored), a line `#` flushes (a no-op
/// here). Times become seconds, pitch positions fractions of the phoneme in [0, 1].

#include "speech/SpeechTypes.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
/// Reads a .pho stream. Throws InputError "pho line <n>: ..." for a malformed line:
/// a missing or negative duration, an odd pitch list, a position outside 0..100 %, a pitch
/// <= 0, a bad command value. Starts are the running sum of the durations.
std::vector<TimedPhoneme> ReadPho(std::istream& in);
/// Same, from a string.
std::vector<TimedPhoneme> ParsePho(const std::string& text);
/// Same, from a file; InputError when it cannot be opened.
std::vector<TimedPhoneme> ReadPhoFile(const std::string& path);

/// Writes one line per phoneme (durations in ms, pitch positions in %). A gap between one
/// phoneme's end and the next start becomes a `_` pause so that starts survive a round
/// trip. Throws InputError for a name that is empty, holds white space or starts with ';'
/// or '#', and for negative or non-finite times.
void WritePho(std::ostream& out, const std::vector<TimedPhoneme>& phonemes);
void WritePhoFile(const std::string& path, const std::vector<TimedPhoneme>& phonemes);
} // namespace morphnode
