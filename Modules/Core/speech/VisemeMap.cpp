// SPDX-License-Identifier: BSD-3-Clause
#include "speech/VisemeMap.h"

#include "base/Error.h"
#include "base/LibraryMessage.h"
#include "base/Text.h"
#include "speech/BuiltinVisemeTables.h"
#include "speech/Rhubarb.h"
#include "speech/Sampa.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace morphnode
{
using nlohmann::json;

const char* VisemeSetName(VisemeSet set)
{
  switch (set)
  {
    case VisemeSet::Oculus15:
      return "oculus15";
    case VisemeSet::German16:
      return "german16";
    case VisemeSet::Paper6:
      return "paper6";
  }
  return "oculus15";
}

VisemeSet ParseVisemeSet(const std::string& name)
{
  const std::string lower = text::ToLower(name);
  for (VisemeSet set : { VisemeSet::Oculus15, VisemeSet::German16, VisemeSet::Paper6 })
  {
    if (lower == VisemeSetName(set))
    {
      return set;
    }
  }
  throw InputError("unknown viseme set '" + name + "' (known: oculus15, german16, paper6)");
}

VisemeMap VisemeMap::Builtin(VisemeSet set, const std::string& language)
{
  const std::string key = std::string(VisemeSetName(set)) + "_" + SpeechLanguageOf(language);
  const char* text = speech_detail::BuiltinVisemeTableJson(key.c_str());
  if (!text)
  {
    throw InputError("no built-in viseme table '" + key + "'");
  }
  VisemeMap map = FromJson(text, "built-in viseme table " + key);
  map.Voice = language;
  if (!HasSampaTables(language) && language != "en" && language != "de" && !language.empty())
  {
    // Other languages: the English table, whose phonemes the German table's complete for
    // the articulatory search (front rounded vowels y 2 9, uvular R, ...).
    const std::string germanKey = std::string(VisemeSetName(set)) + "_de";
    if (const char* german = speech_detail::BuiltinVisemeTableJson(germanKey.c_str()))
    {
      const VisemeMap de = FromJson(german, "built-in viseme table " + germanKey);
      for (const auto& described : de.Described)
      {
        const auto& [a, v] = described;
        const Articulation& articulation = a; // clang 14 cannot capture a structured binding
        const int viseme = map.FindViseme(de.Visemes[static_cast<size_t>(v)]);
        const bool known = std::any_of(map.Described.begin(), map.Described.end(),
          [&articulation](const std::pair<Articulation, int>& d)
          { return ArticulationDistance(d.first, articulation) == 0.0; });
        if (viseme >= 0 && !known)
        {
          map.Described.emplace_back(a, viseme);
        }
      }
    }
  }
  return map;
}

VisemeMap VisemeMap::Load(const std::string& path)
{
  return FromJson(text::ReadFile(path, "viseme table"), path);
}

namespace
{
const std::string& GetString(const json& object, const char* key, const std::string& origin)
{
  auto it = object.find(key);
  if (it == object.end() || !it->is_string() || it->get_ref<const std::string&>().empty())
  {
    throw InputError(origin + ": '" + key + "' must be a non-empty string");
  }
  return it->get_ref<const std::string&>();
}

// json::value() throws json::type_error (not InputError) when the key holds a non-string.
std::string GetOptionalString(
  const json& object, const char* key, const std::string& fallback, const std::string& origin)
{
  auto it = object.find(key);
  if (it == object.end())
  {
    return fallback;
  }
  if (!it->is_string())
  {
    throw InputError(origin + ": '" + key + "' must be a string");
  }
  return it->get<std::string>();
}

char ParseShape(const json& value, const std::string& origin, const std::string& what)
{
  if (!value.is_string() || value.get_ref<const std::string&>().size() != 1 ||
    !IsRhubarbShape(value.get_ref<const std::string&>()[0]))
  {
    throw InputError(origin + ": " + what + " must be a Rhubarb shape A-H or X");
  }
  return value.get_ref<const std::string&>()[0];
}
} // namespace

VisemeMap VisemeMap::FromJson(const std::string& text, const std::string& origin)
{
  json root;
  try
  {
    root = json::parse(text);
  }
  catch (const json::exception& e)
  {
    throw InputError(origin + ": not valid JSON (" + text::LibraryMessage(e.what()) + ")");
  }
  if (!root.is_object())
  {
    throw InputError(origin + ": the top level must be an object");
  }
  VisemeMap map;
  map.SetName = GetOptionalString(root, "set", "custom", origin);
  map.Language = GetOptionalString(root, "language", std::string(), origin);

  const auto visemes = root.find("visemes");
  if (visemes == root.end() || !visemes->is_array() || visemes->empty())
  {
    throw InputError(origin + ": 'visemes' must be a non-empty array of names");
  }
  for (const json& v : *visemes)
  {
    if (!v.is_string() || v.get_ref<const std::string&>().empty())
    {
      throw InputError(origin + ": viseme names must be non-empty strings");
    }
    if (map.FindViseme(v.get<std::string>()) >= 0)
    {
      throw InputError(origin + ": viseme '" + v.get<std::string>() + "' appears twice");
    }
    map.Visemes.push_back(v.get<std::string>());
  }
  auto indexOf = [&](const std::string& name, const std::string& what)
  {
    const int index = map.FindViseme(name);
    if (index < 0)
    {
      throw InputError(
        origin + ": " + what + " names viseme '" + name + "', which is not in 'visemes'");
    }
    return index;
  };
  map.SilenceIndex = indexOf(GetString(root, "silence", origin), "'silence'");
  map.FallbackIndex = indexOf(GetString(root, "fallback", origin), "'fallback'");

  const auto phonemes = root.find("phonemes");
  if (phonemes == root.end() || !phonemes->is_object())
  {
    throw InputError(origin + ": 'phonemes' must be an object {\"sampa\": \"viseme\"}");
  }
  for (auto it = phonemes->begin(); it != phonemes->end(); ++it)
  {
    if (!it.value().is_string())
    {
      throw InputError(origin + ": phoneme '" + it.key() + "' must map to a viseme name");
    }
    map.Phonemes[it.key()] = indexOf(it.value().get<std::string>(), "phoneme '" + it.key() + "'");
  }
  for (const auto& [name, viseme] : map.Phonemes)
  {
    const std::vector<std::string> parts = SplitPhone(name);
    if (parts.size() == 1)
    {
      const Articulation a = DescribePhone(parts[0]);
      if (a.Type == Articulation::Kind::Vowel || a.Type == Articulation::Kind::Consonant)
      {
        map.Described.emplace_back(a, viseme);
      }
    }
  }

  map.ClosurePhonemes = { "p", "b", "m" };
  if (auto closure = root.find("closurePhonemes"); closure != root.end())
  {
    if (!closure->is_array())
    {
      throw InputError(origin + ": 'closurePhonemes' must be an array of SAMPA names");
    }
    map.ClosurePhonemes.clear();
    for (const json& p : *closure)
    {
      if (!p.is_string())
      {
        throw InputError(origin + ": 'closurePhonemes' must be an array of SAMPA names");
      }
      map.ClosurePhonemes.push_back(p.get<std::string>());
    }
  }

  map.Dominance.assign(map.Visemes.size(), 1.0);
  if (auto dominance = root.find("dominance"); dominance != root.end())
  {
    if (!dominance->is_object())
    {
      throw InputError(origin + ": 'dominance' must be an object {\"viseme\": number}");
    }
    for (auto it = dominance->begin(); it != dominance->end(); ++it)
    {
      const int index = indexOf(it.key(), "'dominance'");
      if (!it.value().is_number() || !(it.value().get<double>() > 0.0) ||
        !std::isfinite(it.value().get<double>()))
      {
        throw InputError(origin + ": dominance of '" + it.key() + "' must be a number > 0");
      }
      map.Dominance[index] = it.value().get<double>();
    }
  }

  map.ToShape.assign(map.Visemes.size(), '\0');
  if (auto rhubarb = root.find("rhubarb"); rhubarb != root.end())
  {
    const auto toShape = rhubarb->find("toShape");
    const auto fromShape = rhubarb->find("fromShape");
    if (!rhubarb->is_object() || toShape == rhubarb->end() || !toShape->is_object() ||
      fromShape == rhubarb->end() || !fromShape->is_object())
    {
      throw InputError(origin + ": 'rhubarb' must hold objects 'toShape' and 'fromShape'");
    }
    for (auto it = toShape->begin(); it != toShape->end(); ++it)
    {
      map.ToShape[indexOf(it.key(), "'rhubarb.toShape'")] =
        ParseShape(it.value(), origin, "rhubarb.toShape of '" + it.key() + "'");
    }
    for (size_t v = 0; v < map.Visemes.size(); ++v)
    {
      if (!map.ToShape[v])
      {
        throw InputError(origin + ": 'rhubarb.toShape' lacks viseme '" + map.Visemes[v] + "'");
      }
    }
    for (auto it = fromShape->begin(); it != fromShape->end(); ++it)
    {
      const char shape =
        ParseShape(json(it.key()), origin, "rhubarb.fromShape key '" + it.key() + "'");
      if (!it.value().is_string())
      {
        throw InputError(
          origin + ": rhubarb.fromShape of '" + it.key() + "' must be a viseme name");
      }
      map.FromShape[shape] = indexOf(it.value().get<std::string>(), "'rhubarb.fromShape'");
    }
  }
  return map;
}

int VisemeMap::FindViseme(const std::string& name) const
{
  auto it = std::find(this->Visemes.begin(), this->Visemes.end(), name);
  return it == this->Visemes.end() ? -1 : static_cast<int>(it - this->Visemes.begin());
}

int VisemeMap::MapByArticulation(const std::string& segment) const
{
  const auto it = this->Phonemes.find(segment);
  if (it != this->Phonemes.end())
  {
    return it->second;
  }
  const Articulation a = DescribePhone(segment);
  if (!a.IsKnown())
  {
    return -1;
  }
  if (a.Type == Articulation::Kind::Pause)
  {
    return this->SilenceIndex;
  }
  double best = 50.0; // farther than this (a vowel for a consonant): no match
  int viseme = -1;
  for (const auto& [b, v] : this->Described)
  {
    const double d = ArticulationDistance(a, b);
    if (d < best)
    {
      best = d;
      viseme = v;
    }
  }
  return viseme;
}

std::string VisemeMap::WarnUnknown(const std::string& sampa) const
{
  return "unknown phoneme '" + sampa + "'" +
    (this->Voice.empty() ? "" : " (voice " + this->Voice + ")") + " in viseme table " +
    this->SetName + (this->Language.empty() ? "" : "/" + this->Language) +
    ": shown as fallback viseme '" + this->GetFallback() + "'";
}

int VisemeMap::MapPhoneme(const std::string& sampa, const WarningHandler& warn) const
{
  auto it = this->Phonemes.find(sampa);
  if (it != this->Phonemes.end())
  {
    return it->second;
  }
  if (IsPausePhoneme(sampa))
  {
    return this->SilenceIndex;
  }
  const std::vector<std::string> parts = SplitPhone(sampa);
  if (!parts.empty())
  {
    const int viseme = this->MapByArticulation(parts.front());
    if (viseme >= 0)
    {
      return viseme;
    }
  }
  if (warn)
  {
    warn(this->WarnUnknown(sampa));
  }
  return this->FallbackIndex;
}

std::vector<VisemePart> VisemeMap::MapPhonemeParts(
  const std::string& sampa, const WarningHandler& warn) const
{
  if (IsPausePhoneme(sampa))
  {
    return { { this->SilenceIndex, 1.0, false } };
  }
  const std::vector<std::string> parts = SplitPhone(sampa);
  if (parts.size() >= 2)
  {
    std::vector<VisemePart> out;
    const double fractions2[2] = { 0.6, 0.4 };
    const double fractions3[3] = { 0.4, 0.3, 0.3 };
    const bool pf = parts.size() == 2 && parts[0] == "p" && parts[1] == "f";
    for (size_t k = 0; k < parts.size(); ++k)
    {
      const int viseme = this->MapByArticulation(parts[k]);
      if (viseme < 0)
      {
        out.clear();
        break;
      }
      VisemePart part;
      part.Viseme = viseme;
      part.Fraction =
        pf ? (k == 0 ? 0.4 : 0.6) : (parts.size() == 2 ? fractions2[k] : fractions3[k]);
      part.Closure = this->IsClosurePhoneme(parts[k]);
      // Equal neighbours are one part (a diphthong whose vowels share a viseme).
      if (!out.empty() && out.back().Viseme == part.Viseme && out.back().Closure == part.Closure)
      {
        out.back().Fraction += part.Fraction;
        continue;
      }
      out.push_back(part);
    }
    if (!out.empty())
    {
      return out;
    }
  }
  return { { this->MapPhoneme(sampa, warn), 1.0, this->IsClosurePhoneme(sampa) } };
}

bool VisemeMap::IsKnownPhoneme(const std::string& sampa) const
{
  if (this->Phonemes.count(sampa) || IsPausePhoneme(sampa))
  {
    return true;
  }
  const std::vector<std::string> parts = SplitPhone(sampa);
  return !parts.empty() &&
    std::all_of(parts.begin(), parts.end(),
      [this](const std::string& p) { return this->MapByArticulation(p) >= 0; });
}

bool VisemeMap::IsClosurePhoneme(const std::string& sampa) const
{
  if (std::find(this->ClosurePhonemes.begin(), this->ClosurePhonemes.end(), sampa) !=
    this->ClosurePhonemes.end())
  {
    return true;
  }
  // A phoneme the table lists is a closure only if the table says so.
  return this->Phonemes.count(sampa) == 0 && DescribePhone(sampa).ClosesLips();
}

int VisemeMap::GetVisemeOfShape(char shape) const
{
  auto it = this->FromShape.find(shape);
  return it == this->FromShape.end() ? -1 : it->second;
}
} // namespace morphnode
