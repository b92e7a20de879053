// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TimingFiles.h
/// @brief One entry for every file of timings other tools write: MBROLA .pho, Rhubarb TSV
/// and JSON, Praat TextGrid (phone tier; Montreal Forced Aligner), speech-mark JSON lines
/// (Amazon Polly). The behaviour control, scripts, MorphAvatar and Python call this.

#include "speech/PhoneSets.h"
#include "speech/Speech.h"

#include <string>

namespace morphnode
{
enum class TimingFormat
{
  Auto,              ///< from the extension, then the content
  Pho,               ///< .pho
  RhubarbTsv,        ///< .tsv, .txt of `start<TAB>shape`
  RhubarbJson,       ///< .json with "mouthCues"
  RhubarbXml,        ///< .xml with <rhubarbResult>
  TextGrid,          ///< .TextGrid
  SpeechMarks,       ///< .marks, .jsonl, .json of one object per line with "time" and "type"
  AzureVisemes,      ///< JSON of Azure/SAPI viseme IDs with audio offsets (ServiceTimings.h)
  CharacterAlignment ///< JSON of ElevenLabs-style character alignments (ServiceTimings.h)
};

/// "auto", "pho", "rhubarb-tsv", "rhubarb-json", "rhubarb-xml", "textgrid", "speech-marks",
/// "azure-visemes", "character-alignment".
const char* TimingFormatName(TimingFormat format);
/// True for the three Rhubarb exports (mouth shapes, not phonemes).
bool IsRhubarbFormat(TimingFormat format);
/// Parses those names (case-insensitive); InputError for others.
TimingFormat ParseTimingFormat(const std::string& name);

/// The format of a file from its name and first bytes. InputError when neither tells.
TimingFormat GuessTimingFormat(const std::string& path, const std::string& bytes);

struct TimingFileOptions
{
  TimingFormat Format = TimingFormat::Auto;
  std::string TierName;                         ///< TextGrid: the phone tier (empty: found by name)
  PhoneAlphabet Alphabet = PhoneAlphabet::Auto; ///< TextGrid and phoneme speech marks
};

/// Reads any of the formats and builds the utterance (no audio): phonemes through the
/// viseme table and coarticulation of `speech`, Rhubarb cues through the table's shapes.
/// InputError naming the file for every problem of the readers.
Utterance LoadTimingFile(
  const std::string& path, const SpeechOptions& speech = {}, const TimingFileOptions& options = {});

/// The timed SAMPA phonemes of a .pho, TextGrid or speech-marks file (InputError for Rhubarb
/// files, which hold mouth shapes, not phonemes).
std::vector<TimedPhoneme> LoadTimedPhonemes(
  const std::string& path, const std::string& language, const TimingFileOptions& options = {});

/// The same two from a timing file's bytes in memory (timings inline in a dialog command):
/// `name` stands for the file in messages, and an extension in it tells the format like a
/// file's (e.g. "inline timings" has none: the content tells).
Utterance LoadTimingData(const std::string& bytes, const std::string& name,
  const SpeechOptions& speech = {}, const TimingFileOptions& options = {});
std::vector<TimedPhoneme> LoadTimedPhonemesData(const std::string& bytes, const std::string& name,
  const std::string& language, const TimingFileOptions& options = {});
} // namespace morphnode
