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

/// True for German and English voices ("de", "en-us", "en+f2", ...), whose eSpeak mnemonics
/// this file translates to SAMPA by table. Every other voice reports its phonemes in IPA
/// (SpeechSynthesizer), which becomes X-SAMPA (NormalizeIpaPhonemes).
bool HasSampaTables(const std::string& voice);

/// An eSpeak mnemonic of a language without SAMPA tables -> X-SAMPA: Kirshenbaum's ASCII
/// IPA, which eSpeak's mnemonics follow, differs from X-SAMPA in a few letters (`&` æ, `0`
/// ɒ, `Q` ɣ, `W` œ, `Y` ø, `L` ɫ, ...) and in eSpeak's suffixes (`n^` ɲ, `t.` ʈ, `S;` ɕ,
/// variant marks); where eSpeak's own IPA reads a mnemonic otherwise for a language (Polish
/// "y" is ɨ), the voice decides. Pauses give `_`. Checked against eSpeak's IPA events for
/// every voice: the same viseme for 95 % of the phonemes (docs/speech.md).
std::string EspeakMnemonicToXSampa(
  const std::string& name, const std::string& voice = std::string());

/// One IPA name of eSpeak's IPA events -> X-SAMPA (IpaToSampa): an empty name is a pause
/// `_`, eSpeak's ASCII variant marks are dropped; a lone modifier (ʲ, ː) gives "" (it joins
/// the previous phoneme).
std::string NormalizeIpaPhoneme(const std::string& ipaName, const std::string& voice);

/// The languages eSpeak NG switched to while speaking in `voice`: its phoneme stream marks
/// a switch as an event "(en)" (and "(cmn)" back). A voice without rules for part of the
/// text reads it in another language: eSpeak NG 1.51's Mandarin reads tone numbers ("ni3")
/// as English digits, its Japanese reads kanji as "Chinese letter". Switches to the voice's
/// own language are left out; each language once, in order of appearance.
std::vector<std::string> EspeakLanguageSwitches(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& voice);

/// eSpeak's events of a voice: NormalizeEspeakPhonemes for German and English voices, else
/// EspeakMnemonicToXSampa on every name (a lone modifier joins the previous phoneme).
std::vector<TimedPhoneme> NormalizeVoicePhonemes(
  const std::vector<TimedPhoneme>& espeakPhonemes, const std::string& voice);

/// NormalizeEspeakPhonemes for IPA events (eSpeak's espeakINITIALIZE_PHONEME_IPA).
std::vector<TimedPhoneme> NormalizeIpaPhonemes(
  const std::vector<TimedPhoneme>& ipaPhonemes, const std::string& voice);
} // namespace morphnode
