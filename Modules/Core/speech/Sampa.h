// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Sampa.h
/// @brief SAMPA inventories of German and English and the translation of eSpeak NG's
/// phoneme mnemonics into SAMPA (docs/speech.md lists the table).

#include "speech/SpeechTypes.h"

#include <string>
#include <vector>

namespace morphnode
{
/// "de" or "en" from a voice or language name ("de", "de-DE", "en-us", ...); other
/// languages give "en" (the tables only know German and English).
std::string SpeechLanguageOf(const std::string& voice);

/// True for pause symbols: every name starting with '_' (`_`, `_:`, `_|`, ...).
bool IsPausePhoneme(const std::string& sampa);

/// True when `sampa` is a phoneme of the language's SAMPA inventory (pauses included).
bool IsSampaPhoneme(const std::string& sampa, const std::string& language);

/// True for SAMPA vowels and diphthongs of either language.
bool IsSampaVowel(const std::string& sampa);

/// Translates one eSpeak NG phoneme mnemonic to SAMPA: pauses become `_`, `_!` (German
/// glottal stop) becomes `?`, then the language's table (e.g. German `3` -> `6`, English
/// `oU` -> `@U`); a name still unknown loses eSpeak's trailing variant marks (`#`, `/`,
/// `-`, digits: `I2` -> `I`). A name that stays unknown is returned unchanged (the viseme
/// mapping then warns about it).
std::string NormalizeEspeakPhoneme(const std::string& espeakName, const std::string& language);

/// Normalizes every name, merges adjacent pauses and drops pauses of zero length.
std::vector<TimedPhoneme> NormalizeEspeakPhonemes(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& language);
} // namespace morphnode
