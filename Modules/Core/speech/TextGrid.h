// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TextGrid.h
/// @brief Praat TextGrid files (what the Montreal Forced Aligner, WebMAUS and Praat write):
/// the long and the short text format, in UTF-8 or UTF-16 (with byte-order mark), and the
/// phone tier of one as timed SAMPA phonemes for the viseme pipeline.

#include "speech/PhoneSets.h"
#include "speech/SpeechTypes.h"

#include <string>
#include <vector>

namespace morphnode
{
struct TextGridInterval
{
  double Start = 0.0; ///< seconds
  double End = 0.0;   ///< seconds
  std::string Text;   ///< UTF-8
};

struct TextGridTier
{
  std::string Name;
  bool IsInterval = true; ///< false for a point tier (TextTier): End == Start
  std::vector<TextGridInterval> Items;
};

struct TextGrid
{
  double Start = 0.0;
  double End = 0.0;
  std::vector<TextGridTier> Tiers;

  /// The tier of that name (ASCII case-insensitive), nullptr when there is none.
  const TextGridTier* FindTier(const std::string& name) const;
};

/// Parses a TextGrid. InputError "textgrid: ..." for a binary TextGrid, a file that is not
/// a TextGrid, a truncated one, intervals whose end precedes their start, that overlap or
/// are out of order, or times outside the grid.
TextGrid ParseTextGrid(const std::string& bytes);
TextGrid ReadTextGridFile(const std::string& path);

struct TextGridPhoneOptions
{
  /// The tier to read; empty: the first interval tier named (case-insensitive) "phones",
  /// "phone", "phonemes", "phoneme", "segments", "MAU" or "PhoneTier".
  std::string TierName;
  PhoneAlphabet Alphabet = PhoneAlphabet::Auto;
  /// Language for IPA -> SAMPA ("en", "de", a voice name).
  std::string Language = "en";
};

/// The phone tier as SAMPA phonemes (silence labels -> `_`, gaps filled with `_`, a
/// leading `_` from the grid start). InputError naming the tiers the file has when there is
/// no phone tier (or the named tier is missing or a point tier).
std::vector<TimedPhoneme> TextGridPhonemes(
  const TextGrid& grid, const TextGridPhoneOptions& options = {});
} // namespace morphnode
