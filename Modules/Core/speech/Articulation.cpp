// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Articulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>

namespace morphnode
{
namespace
{
using Place = ArticulationPlace;
using Manner = ArticulationManner;

struct Vowel
{
  double Height, Backness;
  bool Rounded;
};

/// The X-SAMPA vowel chart (IPA's trapezoid: height 0 close .. 1 open).
const std::unordered_map<std::string, Vowel>& Vowels()
{
  static const std::unordered_map<std::string, Vowel> vowels = {
    { "i", { 0.0, 0.0, false } },
    { "y", { 0.0, 0.0, true } },
    { "1", { 0.0, 0.5, false } },
    { "}", { 0.0, 0.5, true } },
    { "M", { 0.0, 1.0, false } },
    { "u", { 0.0, 1.0, true } },
    { "I", { 0.15, 0.15, false } },
    { "Y", { 0.15, 0.15, true } },
    { "I\\", { 0.15, 0.5, false } },
    { "U\\", { 0.15, 0.5, true } },
    { "U", { 0.15, 0.85, true } },
    { "e", { 0.33, 0.0, false } },
    { "2", { 0.33, 0.0, true } },
    { "@\\", { 0.33, 0.5, false } },
    { "8", { 0.33, 0.5, true } },
    { "7", { 0.33, 1.0, false } },
    { "o", { 0.33, 1.0, true } },
    { "@", { 0.5, 0.5, false } },
    { "E", { 0.66, 0.0, false } },
    { "9", { 0.66, 0.0, true } },
    { "3", { 0.66, 0.5, false } },
    { "3\\", { 0.66, 0.5, true } },
    { "V", { 0.66, 1.0, false } },
    { "O", { 0.66, 1.0, true } },
    { "{", { 0.85, 0.0, false } },
    { "6", { 0.85, 0.5, false } },
    { "a", { 1.0, 0.0, false } },
    { "&", { 1.0, 0.0, true } },
    { "A", { 1.0, 1.0, false } },
    { "Q", { 1.0, 1.0, true } },
    // r-coloured vowels
    { "@`", { 0.5, 0.5, false } },
    { "3`", { 0.66, 0.5, false } },
  };
  return vowels;
}

struct Consonant
{
  Place Where;
  Manner How;
  bool Rounded;
};

const std::unordered_map<std::string, Consonant>& Consonants()
{
  static const std::unordered_map<std::string, Consonant> consonants = {
    { "p", { Place::Bilabial, Manner::Stop, false } },
    { "b", { Place::Bilabial, Manner::Stop, false } },
    { "m", { Place::Bilabial, Manner::Nasal, false } },
    { "p\\", { Place::Bilabial, Manner::Fricative, false } },
    { "B", { Place::Bilabial, Manner::Fricative, false } },
    { "B\\", { Place::Bilabial, Manner::Trill, false } },
    { "f", { Place::Labiodental, Manner::Fricative, false } },
    { "v", { Place::Labiodental, Manner::Fricative, false } },
    { "F", { Place::Labiodental, Manner::Nasal, false } },
    { "v\\", { Place::Labiodental, Manner::Approximant, false } },
    { "pf", { Place::Labiodental, Manner::Affricate, false } },
    { "T", { Place::Dental, Manner::Fricative, false } },
    { "D", { Place::Dental, Manner::Fricative, false } },
    { "t", { Place::Alveolar, Manner::Stop, false } },
    { "d", { Place::Alveolar, Manner::Stop, false } },
    { "n", { Place::Alveolar, Manner::Nasal, false } },
    { "r", { Place::Alveolar, Manner::Trill, false } },
    { "4", { Place::Alveolar, Manner::Flap, false } },
    { "s", { Place::Alveolar, Manner::Fricative, false } },
    { "z", { Place::Alveolar, Manner::Fricative, false } },
    { "K", { Place::Alveolar, Manner::Fricative, false } },
    { "K\\", { Place::Alveolar, Manner::Fricative, false } },
    { "r\\", { Place::Alveolar, Manner::Approximant, false } },
    { "l", { Place::Alveolar, Manner::Lateral, false } },
    { "5", { Place::Alveolar, Manner::Lateral, false } },
    { "l\\", { Place::Alveolar, Manner::Flap, false } },
    { "ts", { Place::Alveolar, Manner::Affricate, false } },
    { "dz", { Place::Alveolar, Manner::Affricate, false } },
    { "S", { Place::Postalveolar, Manner::Fricative, false } },
    { "Z", { Place::Postalveolar, Manner::Fricative, false } },
    { "tS", { Place::Postalveolar, Manner::Affricate, false } },
    { "dZ", { Place::Postalveolar, Manner::Affricate, false } },
    { "t`", { Place::Retroflex, Manner::Stop, false } },
    { "d`", { Place::Retroflex, Manner::Stop, false } },
    { "n`", { Place::Retroflex, Manner::Nasal, false } },
    { "r`", { Place::Retroflex, Manner::Flap, false } },
    { "s`", { Place::Retroflex, Manner::Fricative, false } },
    { "z`", { Place::Retroflex, Manner::Fricative, false } },
    { "r\\`", { Place::Retroflex, Manner::Approximant, false } },
    { "l`", { Place::Retroflex, Manner::Lateral, false } },
    { "ts`", { Place::Retroflex, Manner::Affricate, false } },
    { "dz`", { Place::Retroflex, Manner::Affricate, false } },
    { "s\\", { Place::AlveoloPalatal, Manner::Fricative, false } },
    { "z\\", { Place::AlveoloPalatal, Manner::Fricative, false } },
    { "ts\\", { Place::AlveoloPalatal, Manner::Affricate, false } },
    { "dz\\", { Place::AlveoloPalatal, Manner::Affricate, false } },
    { "c", { Place::Palatal, Manner::Stop, false } },
    { "J\\", { Place::Palatal, Manner::Stop, false } },
    { "J", { Place::Palatal, Manner::Nasal, false } },
    { "C", { Place::Palatal, Manner::Fricative, false } },
    { "j\\", { Place::Palatal, Manner::Fricative, false } },
    { "j", { Place::Palatal, Manner::Approximant, false } },
    { "L", { Place::Palatal, Manner::Lateral, false } },
    { "k", { Place::Velar, Manner::Stop, false } },
    { "g", { Place::Velar, Manner::Stop, false } },
    { "N", { Place::Velar, Manner::Nasal, false } },
    { "x", { Place::Velar, Manner::Fricative, false } },
    { "G", { Place::Velar, Manner::Fricative, false } },
    { "M\\", { Place::Velar, Manner::Approximant, false } },
    { "L\\", { Place::Velar, Manner::Lateral, false } },
    { "x\\", { Place::Velar, Manner::Fricative, true } },
    { "q", { Place::Uvular, Manner::Stop, false } },
    { "G\\", { Place::Uvular, Manner::Stop, false } },
    { "N\\", { Place::Uvular, Manner::Nasal, false } },
    { "R\\", { Place::Uvular, Manner::Trill, false } },
    { "X", { Place::Uvular, Manner::Fricative, false } },
    { "R", { Place::Uvular, Manner::Fricative, false } },
    { "X\\", { Place::Pharyngeal, Manner::Fricative, false } },
    { "?\\", { Place::Pharyngeal, Manner::Fricative, false } },
    { "h", { Place::Glottal, Manner::Fricative, false } },
    { "h\\", { Place::Glottal, Manner::Fricative, false } },
    { "?", { Place::Glottal, Manner::Stop, false } },
    { "w", { Place::LabialVelar, Manner::Approximant, true } },
    { "W", { Place::LabialVelar, Manner::Fricative, true } },
    { "H", { Place::LabialPalatal, Manner::Approximant, true } },
    // clicks (Zulu, Xhosa): tongue clicks, lips at rest
    { "O\\", { Place::Bilabial, Manner::Click, false } },
    { "|\\", { Place::Dental, Manner::Click, false } },
    { "!\\", { Place::Alveolar, Manner::Click, false } },
    { "|\\|\\", { Place::Alveolar, Manner::Click, false } },
    { "=\\", { Place::Palatal, Manner::Click, false } },
    // implosives
    { "b_<", { Place::Bilabial, Manner::Stop, false } },
    { "d_<", { Place::Alveolar, Manner::Stop, false } },
    { "g_<", { Place::Velar, Manner::Stop, false } },
    { "J\\_<", { Place::Palatal, Manner::Stop, false } },
  };
  return consonants;
}

/// Reads one base symbol at `at` (the longest known one) and the modifiers after it.
/// Returns false when no known symbol starts there.
bool ReadSegment(const std::string& s, size_t& at, std::string& base, bool& nasal, bool& labialized)
{
  base.clear();
  for (size_t length = std::min<size_t>(4, s.size() - at); length > 0; --length)
  {
    const std::string candidate = s.substr(at, length);
    if (Vowels().count(candidate) || Consonants().count(candidate))
    {
      base = candidate;
      break;
    }
  }
  if (base.empty())
  {
    return false;
  }
  at += base.size();
  nasal = false;
  labialized = false;
  // Modifiers: length, nasal, syllabic, stress, diacritics "_x", palatalization "'".
  while (at < s.size())
  {
    const char c = s[at];
    if (c == ':' || c == '\'' || c == '=' || c == '"' || c == '%' || c == '`' || c == '.' ||
      c == '[' || c == ';')
    {
      ++at;
    }
    else if (c == '~')
    {
      nasal = true;
      ++at;
    }
    else if (c == '_' && at + 1 < s.size())
    {
      if (s[at + 1] == 'w')
      {
        labialized = true;
      }
      at += 2;
      if (at < s.size() && s[at] == '\\')
      {
        ++at;
      }
    }
    else
    {
      break;
    }
  }
  return true;
}
} // namespace

bool Articulation::ClosesLips() const
{
  return this->Type == Kind::Consonant && this->Place == ArticulationPlace::Bilabial &&
    (this->Manner == ArticulationManner::Stop || this->Manner == ArticulationManner::Nasal);
}

namespace
{
bool IsGlide(const std::string& base)
{
  return base == "j" || base == "w" || base == "H";
}

/// The segments of `s`, or empty when it is not one phone, a diphthong or a glide + vowel.
std::vector<std::string> Segments(const std::string& s)
{
  std::vector<std::string> segments;
  size_t at = 0;
  size_t vowels = 0, others = 0;
  while (at < s.size())
  {
    const size_t from = at;
    std::string base;
    bool nasal = false, labialized = false;
    if (!ReadSegment(s, at, base, nasal, labialized))
    {
      return {};
    }
    segments.push_back(s.substr(from, at - from));
    if (Vowels().count(base))
    {
      ++vowels;
    }
    else if (!IsGlide(base))
    {
      ++others;
    }
  }
  // Several segments: diphthongs and triphthongs, possibly with glides (ja, wa, uI).
  if (segments.size() > 1 && (others > 0 || vowels == 0 || segments.size() > 3))
  {
    return {};
  }
  if (segments.size() == 1 && segments[0].rfind("pf", 0) == 0)
  {
    return { "p", "f" };
  }
  return segments;
}
} // namespace

std::vector<std::string> SplitPhone(const std::string& name)
{
  if (name.empty() || name[0] == '_')
  {
    return {};
  }
  std::vector<std::string> segments = Segments(name);
  if (!segments.empty())
  {
    return segments;
  }
  // eSpeak's variant marks (digits, '#', '/', '-', '!') after a name carry no articulation.
  std::string s = name;
  while (s.size() > 1 &&
    (std::isdigit(static_cast<unsigned char>(s.back())) || s.back() == '#' || s.back() == '/' ||
      s.back() == '-' || s.back() == '!'))
  {
    s.pop_back();
  }
  return s == name ? segments : Segments(s);
}

Articulation DescribePhone(const std::string& segment)
{
  Articulation a;
  if (!segment.empty() && segment[0] == '_')
  {
    a.Type = Articulation::Kind::Pause;
    return a;
  }
  size_t at = 0;
  std::string base;
  bool nasal = false, labialized = false;
  if (!ReadSegment(segment, at, base, nasal, labialized) || at != segment.size())
  {
    return a;
  }
  a.Nasalized = nasal;
  if (const auto v = Vowels().find(base); v != Vowels().end())
  {
    a.Type = Articulation::Kind::Vowel;
    a.Height = v->second.Height;
    a.Backness = v->second.Backness;
    a.Rounded = v->second.Rounded || labialized;
    return a;
  }
  const Consonant& c = Consonants().at(base);
  a.Type = Articulation::Kind::Consonant;
  a.Place = c.Where;
  a.Manner = c.How;
  a.Rounded = c.Rounded || labialized;
  return a;
}

double ArticulationDistance(const Articulation& a, const Articulation& b)
{
  using Kind = Articulation::Kind;
  if (a.Type != b.Type)
  {
    // Glides sit next to their vowels (w ~ u, j ~ i, ɥ ~ y); everything else is far.
    const Articulation& c = a.Type == Kind::Consonant ? a : b;
    const Articulation& v = a.Type == Kind::Vowel ? a : b;
    if (c.Type == Kind::Consonant && v.Type == Kind::Vowel && c.Manner == Manner::Approximant &&
      (c.Place == Place::LabialVelar || c.Place == Place::Palatal ||
        c.Place == Place::LabialPalatal))
    {
      return 3.0 + 3.0 * v.Height + (c.Rounded != v.Rounded ? 6.0 : 0.0);
    }
    return 100.0;
  }
  if (a.Type == Kind::Vowel)
  {
    return 3.0 * std::abs(a.Height - b.Height) + 1.5 * std::abs(a.Backness - b.Backness) +
      (a.Rounded != b.Rounded ? 6.0 : 0.0);
  }
  if (a.Type != Kind::Consonant)
  {
    return a.Type == b.Type ? 0.0 : 100.0;
  }
  auto group = [](Place p)
  {
    switch (p)
    {
      case Place::Bilabial:
        return 0;
      case Place::Labiodental:
        return 1;
      case Place::Dental:
        return 2;
      case Place::Alveolar:
        return 3;
      case Place::Postalveolar:
      case Place::Retroflex:
      case Place::AlveoloPalatal:
        return 4;
      case Place::Palatal:
        return 5;
      case Place::Velar:
      case Place::Uvular:
        return 6;
      case Place::Pharyngeal:
      case Place::Glottal:
        return 7;
      case Place::LabialVelar:
      case Place::LabialPalatal:
        return 8;
      case Place::None:
        break;
    }
    return 9;
  };
  double d = 0.0;
  const int ga = group(a.Place), gb = group(b.Place);
  if (a.Place != b.Place)
  {
    const bool lips = ga <= 1 || gb <= 1 || ga == 8 || gb == 8;
    const bool bothLips = ga <= 1 && gb <= 1; // bilabial and labiodental: both use the lips
    d += ga == gb ? 1.0 : (bothLips ? 4.0 : (lips ? 12.0 : 3.0 + 0.3 * std::abs(ga - gb)));
  }
  if (a.Manner != b.Manner)
  {
    auto pair = [&](Manner x, Manner y)
    { return (a.Manner == x && b.Manner == y) || (a.Manner == y && b.Manner == x); };
    // A bilabial stop or nasal closes the lips; nothing else may take its place.
    if ((a.ClosesLips() != b.ClosesLips()))
    {
      // Nothing else may stand for a closure, but a bilabial fricative (β) is nearer to it
      // than to anything made elsewhere.
      d += a.Place == b.Place ? 3.0 : 12.0;
    }
    else if (pair(Manner::Stop, Manner::Affricate) || pair(Manner::Fricative, Manner::Affricate) ||
      pair(Manner::Trill, Manner::Flap) || pair(Manner::Approximant, Manner::Lateral) ||
      pair(Manner::Trill, Manner::Approximant) || pair(Manner::Flap, Manner::Approximant))
    {
      d += 1.0;
    }
    else if (pair(Manner::Stop, Manner::Flap) || pair(Manner::Flap, Manner::Lateral) ||
      pair(Manner::Trill, Manner::Fricative))
    {
      d += 1.5;
    }
    else
    {
      d += 2.5;
    }
  }
  if (a.Rounded != b.Rounded)
  {
    d += 4.0;
  }
  return d;
}
} // namespace morphnode
