// SPDX-License-Identifier: BSD-3-Clause
#include "speech/VisemeMap.h"

#include "speech/BuiltinVisemeTables.h"
#include "base/Error.h"
#include "base/Text.h"
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
  return FromJson(text, "built-in viseme table " + key);
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
    throw InputError(origin + ": not valid JSON (" + e.what() + ")");
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
  auto indexOf = [&](const std::string& name, const std::string& what) {
    const int index = map.FindViseme(name);
    if (index < 0)
    {
      throw InputError(origin + ": " + what + " names viseme '" + name + "', which is not in 'visemes'");
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
      const char shape = ParseShape(json(it.key()), origin, "rhubarb.fromShape key '" + it.key() + "'");
      if (!it.value().is_string())
      {
        throw InputError(origin + ": rhubarb.fromShape of '" + it.key() + "' must be a viseme name");
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
  if (warn)
  {
    warn("unknown phoneme '" + sampa + "' in viseme table " + this->SetName +
      (this->Language.empty() ? "" : "/" + this->Language) + ": shown as fallback viseme '" +
      this->GetFallback() + "'");
  }
  return this->FallbackIndex;
}

bool VisemeMap::IsClosurePhoneme(const std::string& sampa) const
{
  return std::find(this->ClosurePhonemes.begin(), this->ClosurePhonemes.end(), sampa) !=
    this->ClosurePhonemes.end();
}

int VisemeMap::GetVisemeOfShape(char shape) const
{
  auto it = this->FromShape.find(shape);
  return it == this->FromShape.end() ? -1 : it->second;
}
} // namespace morphnode
