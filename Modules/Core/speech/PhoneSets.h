// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file PhoneSets.h
/// @brief Phone labels of other tools into the SAMPA the viseme tables use: ARPAbet (CMU
/// dictionary, PocketSphinx, Montreal Forced Aligner's english_us_arpa models) and IPA
/// (MFA's *_mfa models, WebMAUS, Praat), plus the alphabet guess for a set of labels.

#include <string>
#include <vector>

namespace morphnode
{
enum class PhoneAlphabet
{
  Auto,    ///< guess from the labels (GuessPhoneAlphabet)
  Sampa,   ///< labels are SAMPA already
  Arpabet, ///< CMU ARPAbet, stress digits allowed (AH0, IY1)
  Ipa      ///< IPA in UTF-8
};

/// "auto", "sampa", "arpabet", "ipa".
const char* PhoneAlphabetName(PhoneAlphabet alphabet);
/// Parses those names (case-insensitive); InputError for others.
PhoneAlphabet ParsePhoneAlphabet(const std::string& name);

/// True for labels that mean silence or noise in aligners' output: empty, "sil", "sp",
/// "spn", "<eps>", "<sil>", "#", "_" (any case), and SAMPA pauses.
bool IsSilenceLabel(const std::string& label);

/// ARPAbet -> English SAMPA (AH0 -> @, AH1 -> V, ER0 -> @, ER1 -> 3:, OW -> @U, ...).
/// Silence labels give "_". A label that is not ARPAbet is returned unchanged.
std::string ArpabetToSampa(const std::string& label);

/// IPA (UTF-8) -> SAMPA: X-SAMPA per symbol (length mark -> ':', aspiration, dentals,
/// syllabic marks and tie bars dropped), then the language's usual SAMPA spelling ("en":
/// ɹ -> r, oʊ -> @U, ɚ -> @, ɾ -> d; "de": ʁ -> R, ɐ -> 6, ...). Silence gives "_". A symbol
/// without an X-SAMPA equivalent is kept as it is (the viseme mapping then warns about it).
std::string IpaToSampa(const std::string& label, const std::string& language);

/// Arpabet when every non-silence label is upper-case ASCII letters with an optional stress
/// digit and at least one is a two-letter ARPAbet name or carries a digit; Ipa when any
/// label holds a non-ASCII byte; else Sampa.
PhoneAlphabet GuessPhoneAlphabet(const std::vector<std::string>& labels);

/// One label to SAMPA in the given alphabet (Auto is treated as Sampa).
std::string PhoneLabelToSampa(
  const std::string& label, PhoneAlphabet alphabet, const std::string& language);
} // namespace morphnode
