// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file VisemeMap.h
/// @brief SAMPA phoneme -> viseme tables, loaded from JSON (speech/data/*.json).
///
/// Three viseme sets, each for German and English:
/// - Oculus15: Meta/Oculus `sil PP FF TH DD kk CH SS nn RR aa E ih oh ou`
/// - German16: after Aschenberner & Weiss `sil P M F S Z T L R K A O U E Y Q`
/// - Paper6: the paper's morph targets `A E O S F L` plus `sil` (bilabials close to `sil`)
/// The built-in tables are the files of speech/data compiled into the library; a file of
/// the same form overrides them (docs/speech.md documents the format).
///
/// A phoneme the table does not list (any language eSpeak NG speaks, IPA from another
/// tool) takes the viseme of the table's phoneme nearest to it in articulation (rounding,
/// height and backness of vowels, place and manner of consonants: Articulation.h); a
/// diphthong becomes a sequence of its vowels' visemes (MapPhonemeParts). Only a name that
/// is no phone at all warns and shows the fallback.

#include "speech/Articulation.h"
#include "speech/Warning.h"

#include <map>
#include <string>
#include <vector>

namespace morphnode
{
/// One viseme of a phoneme's sequence: a diphthong has two or three.
struct VisemePart
{
  int Viseme = 0;
  double Fraction = 1.0; ///< of the phoneme's duration
  bool Closure = false;  ///< lips fully closed (bilabial stop or nasal)
};

enum class VisemeSet
{
  Oculus15,
  German16,
  Paper6
};

/// "oculus15", "german16", "paper6".
const char* VisemeSetName(VisemeSet set);
/// Parses those names (case-insensitive); InputError for others.
VisemeSet ParseVisemeSet(const std::string& name);

class VisemeMap
{
public:
  /// The built-in table of a set for a language or voice ("de", "en-us", "fr", ...): the
  /// German table for German, the English one for every other language, whose phonemes
  /// it does not list find their visemes by articulation.
  static VisemeMap Builtin(VisemeSet set, const std::string& language);
  /// Parses a table; InputError naming `origin` and the problem for a malformed one.
  static VisemeMap FromJson(const std::string& text, const std::string& origin = "viseme table");
  /// Reads a table file; InputError when it cannot be read or is malformed.
  static VisemeMap Load(const std::string& path);

  const std::string& GetSetName() const { return this->SetName; }
  const std::string& GetLanguage() const { return this->Language; }
  /// The viseme names in channel order.
  const std::vector<std::string>& GetVisemes() const { return this->Visemes; }
  /// The rest/pause viseme (also the target of every pause phoneme `_...`).
  const std::string& GetSilence() const { return this->Visemes[this->SilenceIndex]; }
  int GetSilenceIndex() const { return this->SilenceIndex; }
  /// Where an unknown phoneme goes.
  const std::string& GetFallback() const { return this->Visemes[this->FallbackIndex]; }
  int GetFallbackIndex() const { return this->FallbackIndex; }
  /// -1 when the set has no such viseme.
  int FindViseme(const std::string& name) const;

  /// The viseme index of a SAMPA (or X-SAMPA) phoneme: the table's entry, else the viseme of
  /// the table phoneme nearest in articulation (a diphthong: of its first vowel). Pauses
  /// give the silence viseme; a name that is no phone gives the fallback and a warning
  /// naming it and the voice.
  int MapPhoneme(const std::string& sampa, const WarningHandler& warn = {}) const;
  /// The visemes a phoneme shows in turn: one for most, two or three for diphthongs and
  /// triphthongs (0.6 + 0.4 or 0.4 + 0.3 + 0.3 of the duration, the nucleus first) and the
  /// German affricate pf (closure 0.4, then FF). Warns as MapPhoneme.
  std::vector<VisemePart> MapPhonemeParts(
    const std::string& sampa, const WarningHandler& warn = {}) const;
  /// True when `sampa` is a table phoneme or a phone whose articulation is known.
  bool IsKnownPhoneme(const std::string& sampa) const;
  /// The language or voice the table was chosen for (Builtin), named in warnings.
  const std::string& GetVoice() const { return this->Voice; }
  const std::string& MapPhonemeName(const std::string& sampa, const WarningHandler& warn = {}) const
  {
    return this->Visemes[this->MapPhoneme(sampa, warn)];
  }
  /// True when the phoneme's lips must close fully (the table's p b m, or any bilabial stop
  /// or nasal it does not list): its viseme reaches 1.
  bool IsClosurePhoneme(const std::string& sampa) const;
  /// Coarticulation strength a_s of a viseme (1 unless the table says otherwise).
  double GetDominance(int viseme) const { return this->Dominance[viseme]; }

  /// Rhubarb mouth shape ('A'..'H', 'X') of a viseme, and the viseme of a shape (-1 when
  /// the table has no entry).
  char GetRhubarbShape(int viseme) const { return this->ToShape[viseme]; }
  int GetVisemeOfShape(char shape) const;

  const std::map<std::string, int>& GetPhonemeTable() const { return this->Phonemes; }

private:
  VisemeMap() = default; // only the loaders make tables, so a table is never empty

  /// The viseme of the table phoneme nearest in articulation to one segment; -1 if none.
  int MapByArticulation(const std::string& segment) const;
  std::string WarnUnknown(const std::string& sampa) const;

  std::string SetName;
  std::string Language;
  std::string Voice;
  /// Table phonemes that are single phones, with their articulation (for MapByArticulation).
  std::vector<std::pair<Articulation, int>> Described;
  std::vector<std::string> Visemes;
  int SilenceIndex = 0;
  int FallbackIndex = 0;
  std::map<std::string, int> Phonemes;
  std::vector<std::string> ClosurePhonemes;
  std::vector<double> Dominance;
  std::vector<char> ToShape;
  std::map<char, int> FromShape;
};
} // namespace morphnode
