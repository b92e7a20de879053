// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Articulation.h
/// @brief How a phone is articulated, read from its X-SAMPA name (SAMPA is a subset): for
/// vowels height, backness and lip rounding, for consonants place and manner. The viseme
/// of a phone that no table lists is the table's phone nearest in articulation
/// (VisemeMap), so every language eSpeak NG speaks gets visemes without a table written
/// by hand: French /u/ and /y/ round the lips, Spanish /b/ closes them, /f/ gives FF.

#include <string>
#include <vector>

namespace morphnode
{
enum class ArticulationPlace
{
  None,
  Bilabial,
  Labiodental,
  Dental,
  Alveolar,
  Postalveolar,
  Retroflex,
  AlveoloPalatal,
  Palatal,
  Velar,
  Uvular,
  Pharyngeal,
  Glottal,
  LabialVelar,  ///< w, ʍ
  LabialPalatal ///< ɥ
};

enum class ArticulationManner
{
  None,
  Stop,
  Nasal,
  Trill,
  Flap,
  Fricative,
  Affricate,
  Approximant,
  Lateral,
  Click
};

struct Articulation
{
  enum class Kind
  {
    Unknown,
    Pause,
    Vowel,
    Consonant
  };
  Kind Type = Kind::Unknown;
  double Height = 0.0;   ///< vowels: 0 close (i, u) .. 1 open (a)
  double Backness = 0.0; ///< vowels: 0 front .. 1 back
  bool Rounded = false;  ///< vowels: rounded lips; consonants: labialized (w, ʷ)
  bool Nasalized = false;
  ArticulationPlace Place = ArticulationPlace::None;
  ArticulationManner Manner = ArticulationManner::None;

  bool IsKnown() const { return this->Type != Kind::Unknown; }
  /// Lips fully closed: bilabial stops and nasals.
  bool ClosesLips() const;
};

/// The segments of a phone name: one for a plain phone ("u:", "tS", "p_h", "O~"), two or
/// three for a diphthong or triphthong ("aI" -> "a", "I"; "aU@" -> "a", "U", "@"), and the
/// German affricate "pf" -> "p", "f" (its closure and its friction show differently). Empty
/// when the name is not a phone: any symbol X-SAMPA lacks, or consonants joined otherwise.
std::vector<std::string> SplitPhone(const std::string& xsampa);

/// The articulation of one segment (length, aspiration, palatalization, syllabicity,
/// stress and tone marks are ignored; `~` nasalizes, `_w` labializes). Pauses (`_...`)
/// give Kind::Pause; an unknown symbol Kind::Unknown.
Articulation DescribePhone(const std::string& segment);

/// A distance between two articulations for finding the nearest: rounding and the lips'
/// places weigh most, then height, place and manner.
double ArticulationDistance(const Articulation& a, const Articulation& b);
} // namespace morphnode
