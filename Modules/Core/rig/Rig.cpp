// SPDX-License-Identifier: BSD-3-Clause
#include "rig/Rig.h"

#include "base/Error.h"
#include "base/LibraryMessage.h"
#include "base/Text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <unordered_map>
#include <variant>

namespace morphnode
{
namespace
{
// ordered_json keeps shapes in file order (the order tables and sets are written in).
using Json = nlohmann::ordered_json;

[[noreturn]] void Fail(const std::string& source, const std::string& what)
{
  throw InputError("rig " + source + ": " + what);
}

std::string Quote(const std::string& s)
{
  return "'" + s + "'";
}

// nlohmann silently keeps one of two equal keys; a rig defining "E" twice (once as a
// paper viseme, once as a Meta viseme) must be an error instead, so keys are tracked per
// object while parsing.
Json ParseRejectingDuplicateKeys(const std::string& text, const std::string& source)
{
  std::vector<std::set<std::string>> keysPerObject;
  std::vector<std::string> path;
  std::string duplicate;
  auto callback = [&](int /*depth*/, Json::parse_event_t event, Json& parsed)
  {
    switch (event)
    {
      case Json::parse_event_t::object_start:
        keysPerObject.emplace_back();
        break;
      case Json::parse_event_t::object_end:
        if (!keysPerObject.empty())
        {
          keysPerObject.pop_back();
        }
        break;
      case Json::parse_event_t::key:
      {
        const std::string key = parsed.get<std::string>();
        if (!keysPerObject.empty() && !keysPerObject.back().insert(key).second && duplicate.empty())
        {
          duplicate = key;
        }
        break;
      }
      default:
        break;
    }
    return true;
  };
  Json json;
  try
  {
    json = Json::parse(text, callback);
  }
  catch (const Json::exception& e)
  {
    // parse_error, but also out_of_range for a number beyond double ("1e999").
    Fail(source, std::string("is not valid JSON: ") + text::LibraryMessage(e.what()));
  }
  if (!duplicate.empty())
  {
    Fail(source,
      "key " + Quote(duplicate) +
        " appears twice in one object (each shape, target "
        "and field must be defined once)");
  }
  return json;
}

/// A direction [x, y, z] of the eyes section.
std::array<double, 3> ParseDirection(
  const Json& value, const std::string& source, const std::string& where)
{
  if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
    !value[2].is_number())
  {
    Fail(source, where + " must be an array of 3 numbers");
  }
  return { value[0].get<double>(), value[1].get<double>(), value[2].get<double>() };
}

/// The "eyes" section: {"parts": [name | {"name", "side", "forward", "up"}], "forward",
/// "up", "limits": {"yaw", "up", "down"}}, every field optional (docs/rigs.md).
EyeRig ParseEyes(const Json& eyes, const std::string& src)
{
  if (!eyes.is_object())
  {
    Fail(src, "field 'eyes' must be an object (parts, forward, up, limits)");
  }
  for (const auto& item : eyes.items())
  {
    if (item.key() != "parts" && item.key() != "forward" && item.key() != "up" &&
      item.key() != "limits")
    {
      Fail(
        src, "eyes: unknown field " + Quote(item.key()) + " (known: parts, forward, up, limits)");
    }
  }
  EyeRig rig;
  try
  {
    std::array<double, 3> forward = rig.GetDefaultForward(), up = rig.GetDefaultUp();
    if (eyes.contains("forward"))
    {
      forward = ParseDirection(eyes["forward"], src, "eyes: 'forward'");
    }
    if (eyes.contains("up"))
    {
      up = ParseDirection(eyes["up"], src, "eyes: 'up'");
    }
    rig.SetDefaultDirections(forward, up);
    if (eyes.contains("limits"))
    {
      const Json& limits = eyes["limits"];
      if (!limits.is_object())
      {
        Fail(src, "eyes: 'limits' must be an object {\"yaw\", \"up\", \"down\"} (degrees)");
      }
      EyeLimits l;
      for (const auto& item : limits.items())
      {
        if (!item.value().is_number())
        {
          Fail(src, "eyes: limit " + Quote(item.key()) + " must be a number (degrees)");
        }
        const double v = item.value().get<double>();
        if (item.key() == "yaw")
        {
          l.MaxYaw = v;
        }
        else if (item.key() == "up")
        {
          l.MaxUp = v;
        }
        else if (item.key() == "down")
        {
          l.MaxDown = v;
        }
        else
        {
          Fail(src, "eyes: unknown limit " + Quote(item.key()) + " (known: yaw, up, down)");
        }
      }
      rig.SetLimits(l);
    }
    if (eyes.contains("parts"))
    {
      const Json& parts = eyes["parts"];
      if (!parts.is_array() || parts.empty())
      {
        Fail(src, "eyes: 'parts' must be a non-empty array of node or part names");
      }
      for (size_t i = 0; i < parts.size(); ++i)
      {
        const std::string where = "eyes: parts entry " + std::to_string(i);
        EyeSpec eye;
        eye.Forward = forward;
        eye.Up = up;
        if (parts[i].is_string())
        {
          eye.Name = parts[i].get<std::string>();
          eye.Side = EyeRig::SideFromName(eye.Name);
        }
        else if (parts[i].is_object())
        {
          const Json& entry = parts[i];
          for (const auto& item : entry.items())
          {
            if (item.key() != "name" && item.key() != "side" && item.key() != "forward" &&
              item.key() != "up")
            {
              Fail(src,
                where + ": unknown field " + Quote(item.key()) +
                  " (known: name, side, forward, up)");
            }
          }
          if (!entry.contains("name") || !entry["name"].is_string())
          {
            Fail(src, where + ": 'name' must be a string");
          }
          eye.Name = entry["name"].get<std::string>();
          eye.Side = EyeRig::SideFromName(eye.Name);
          if (entry.contains("side"))
          {
            const std::string side =
              entry["side"].is_string() ? entry["side"].get<std::string>() : "";
            if (side == "left")
            {
              eye.Side = EyeSide::Left;
            }
            else if (side == "right")
            {
              eye.Side = EyeSide::Right;
            }
            else
            {
              Fail(src, where + ": 'side' must be \"left\" or \"right\" (the character's)");
            }
          }
          if (entry.contains("forward"))
          {
            eye.Forward = ParseDirection(entry["forward"], src, where + ": 'forward'");
          }
          if (entry.contains("up"))
          {
            eye.Up = ParseDirection(entry["up"], src, where + ": 'up'");
          }
        }
        else
        {
          Fail(src, where + ": must be a name or an object {name, side, forward, up}");
        }
        rig.AddEye(eye);
      }
    }
  }
  catch (const InputError& e)
  {
    const std::string message = e.what();
    if (message.rfind("rig ", 0) == 0)
    {
      throw;
    }
    Fail(src, "eyes: " + message);
  }
  return rig;
}
} // namespace

Rig Rig::LoadFile(const std::string& path)
{
  return LoadString(text::ReadFile(path, "rig file"), Quote(path));
}

Rig Rig::LoadString(const std::string& text, const std::string& sourceName)
{
  const std::string& src = sourceName;
  const Json json = ParseRejectingDuplicateKeys(text, src);
  if (!json.is_object())
  {
    Fail(src, "the top level must be a JSON object with \"name\" and \"shapes\"");
  }
  static const std::set<std::string> knownFields = { "name", "description", "targets", "shapes",
    "sets", "notes", "eyes" };
  for (const auto& item : json.items())
  {
    if (!knownFields.count(item.key()))
    {
      Fail(src,
        "unknown field " + Quote(item.key()) +
          " (known: name, description, targets, shapes, sets, notes, eyes)");
    }
  }

  Rig rig;
  if (!json.contains("name") || !json["name"].is_string() ||
    json["name"].get<std::string>().empty())
  {
    Fail(src, "field 'name' must be a non-empty string");
  }
  rig.Name = json["name"].get<std::string>();
  if (json.contains("description"))
  {
    if (!json["description"].is_string())
    {
      Fail(src, "field 'description' must be a string");
    }
    rig.Description = json["description"].get<std::string>();
  }

  std::set<std::string> declared;
  if (json.contains("targets"))
  {
    const Json& targets = json["targets"];
    if (!targets.is_array())
    {
      Fail(src, "field 'targets' must be an array of target names");
    }
    for (size_t i = 0; i < targets.size(); ++i)
    {
      if (!targets[i].is_string() || targets[i].get<std::string>().empty())
      {
        Fail(src, "field 'targets', entry " + std::to_string(i) + ": not a non-empty string");
      }
      const std::string name = targets[i].get<std::string>();
      if (!declared.insert(name).second)
      {
        Fail(src, "field 'targets': target " + Quote(name) + " is listed twice");
      }
      rig.DeclaredTargets.push_back(name);
    }
  }

  if (!json.contains("shapes") || !json["shapes"].is_object())
  {
    Fail(src, "field 'shapes' must be an object of shape name -> {target: coefficient}");
  }
  for (const auto& shape : json["shapes"].items())
  {
    const std::string& shapeName = shape.key();
    if (shapeName.empty())
    {
      Fail(src, "a shape has an empty name");
    }
    if (shape.value().is_string())
    {
      // An alias ("FF": "F"): one definition shared by two viseme sets; resolved below.
      rig.ShapeNames.push_back(shapeName);
      rig.Terms.emplace_back();
      rig.Aliases.push_back(shape.value().get<std::string>());
      continue;
    }
    if (!shape.value().is_object())
    {
      Fail(src,
        "shape " + Quote(shapeName) +
          " must be an object of target -> coefficient, or the name of another shape");
    }
    std::vector<RigTerm> terms;
    for (const auto& term : shape.value().items())
    {
      const std::string& target = term.key();
      if (target.empty())
      {
        Fail(src, "shape " + Quote(shapeName) + " has a target with an empty name");
      }
      if (!term.value().is_number())
      {
        Fail(src,
          "shape " + Quote(shapeName) + ", target " + Quote(target) +
            ": the coefficient must be a number");
      }
      const double coefficient = term.value().get<double>();
      if (!std::isfinite(coefficient))
      {
        Fail(src,
          "shape " + Quote(shapeName) + ", target " + Quote(target) +
            ": the coefficient is not finite");
      }
      if (!declared.empty() && !declared.count(target))
      {
        Fail(src,
          "shape " + Quote(shapeName) + " uses target " + Quote(target) +
            ", which is not in the rig's 'targets' list");
      }
      terms.push_back({ target, coefficient });
    }
    rig.ShapeNames.push_back(shapeName);
    rig.Terms.push_back(std::move(terms));
    rig.Aliases.emplace_back();
  }
  for (size_t s = 0; s < rig.ShapeNames.size(); ++s)
  {
    const std::string& alias = rig.Aliases[s];
    if (alias.empty())
    {
      continue;
    }
    const int original = rig.FindShape(alias);
    if (original < 0)
    {
      Fail(src,
        "shape " + Quote(rig.ShapeNames[s]) + " is an alias of " + Quote(alias) +
          ", which the rig does not define");
    }
    if (!rig.Aliases[static_cast<size_t>(original)].empty())
    {
      Fail(src,
        "shape " + Quote(rig.ShapeNames[s]) + " is an alias of " + Quote(alias) +
          ", which is itself an alias (name the original shape instead)");
    }
    rig.Terms[s] = rig.Terms[static_cast<size_t>(original)];
  }

  if (json.contains("sets"))
  {
    const Json& sets = json["sets"];
    if (!sets.is_object())
    {
      Fail(src, "field 'sets' must be an object of set name -> [shape names]");
    }
    for (const auto& set : sets.items())
    {
      if (!set.value().is_array())
      {
        Fail(src, "set " + Quote(set.key()) + " must be an array of shape names");
      }
      std::vector<std::string> members;
      std::set<std::string> seen;
      for (const auto& member : set.value())
      {
        if (!member.is_string())
        {
          Fail(src, "set " + Quote(set.key()) + " has an entry that is not a string");
        }
        const std::string name = member.get<std::string>();
        if (rig.FindShape(name) < 0)
        {
          Fail(src,
            "set " + Quote(set.key()) + " names shape " + Quote(name) +
              ", which the rig does not define");
        }
        if (!seen.insert(name).second)
        {
          Fail(src, "set " + Quote(set.key()) + " lists shape " + Quote(name) + " twice");
        }
        members.push_back(name);
      }
      rig.Sets[set.key()] = std::move(members);
    }
  }

  if (json.contains("notes"))
  {
    const Json& notes = json["notes"];
    if (!notes.is_object())
    {
      Fail(src, "field 'notes' must be an object of shape name -> text");
    }
    for (const auto& note : notes.items())
    {
      if (!note.value().is_string())
      {
        Fail(src, "note for " + Quote(note.key()) + " must be a string");
      }
      if (rig.FindShape(note.key()) < 0)
      {
        Fail(src, "note for shape " + Quote(note.key()) + ", which the rig does not define");
      }
    }
  }
  if (json.contains("eyes"))
  {
    rig.Eyes = ParseEyes(json["eyes"], src);
    rig.HasEyeSection = true;
  }
  return rig;
}

int Rig::FindShape(const std::string& name) const
{
  const auto it = std::find(this->ShapeNames.begin(), this->ShapeNames.end(), name);
  return it == this->ShapeNames.end() ? -1 : static_cast<int>(it - this->ShapeNames.begin());
}

const std::vector<std::string>& Rig::GetSet(const std::string& setName) const
{
  const auto it = this->Sets.find(setName);
  if (it == this->Sets.end())
  {
    throw InputError("rig '" + this->Name + "' has no shape set '" + setName + "'");
  }
  return it->second;
}

std::vector<std::string> Rig::GetSetNames() const
{
  std::vector<std::string> names;
  for (const auto& set : this->Sets)
  {
    names.push_back(set.first);
  }
  return names;
}

void Rig::Validate(const std::vector<std::string>& faceTargetNames) const
{
  const std::set<std::string> face(faceTargetNames.begin(), faceTargetNames.end());
  for (size_t s = 0; s < this->ShapeNames.size(); ++s)
  {
    for (const RigTerm& term : this->Terms[s])
    {
      if (!face.count(term.Target))
      {
        throw InputError("rig '" + this->Name + "', shape '" + this->ShapeNames[s] +
          "': the face has no target '" + term.Target + "' (it has " +
          std::to_string(faceTargetNames.size()) + " targets)");
      }
    }
  }
}

void Rig::Bind(const std::vector<std::string>& faceTargetNames)
{
  this->Validate(faceTargetNames);
  std::unordered_map<std::string, size_t> index;
  for (size_t t = 0; t < faceTargetNames.size(); ++t)
  {
    // First occurrence wins, as in MorphMesh::FindTarget.
    index.emplace(faceTargetNames[t], t);
  }
  this->RowStart.assign(1, 0);
  this->Columns.clear();
  this->Values.clear();
  for (const auto& terms : this->Terms)
  {
    for (const RigTerm& term : terms)
    {
      this->Columns.push_back(index.at(term.Target));
      this->Values.push_back(term.Coefficient);
    }
    this->RowStart.push_back(this->Columns.size());
  }
  this->BoundTargetNames = faceTargetNames;
  this->Bound = true;
}

void Rig::Bind(const MorphMesh& model)
{
  const auto& names = model.GetTargetNames();
  if (names.empty())
  {
    throw InputError(
      "rig '" + this->Name + "': the morph model has no targets, not even a neutral");
  }
  this->Bind(std::vector<std::string>(names.begin() + 1, names.end()));
}

void Rig::RequireBound(const char* what) const
{
  if (!this->Bound)
  {
    throw InputError(
      std::string("rig '") + this->Name + "': " + what + " needs Bind() to a face's targets first");
  }
}

void Rig::Expand(const double* shapeWeights, double* targetWeights) const
{
  this->RequireBound("Expand");
  const size_t numTargets = this->BoundTargetNames.size();
  std::fill(targetWeights, targetWeights + numTargets, 0.0);
  const size_t numShapes = this->ShapeNames.size();
  for (size_t s = 0; s < numShapes; ++s)
  {
    const double w = shapeWeights[s];
    if (!std::isfinite(w))
    {
      throw InputError("rig '" + this->Name + "': the weight of shape '" + this->ShapeNames[s] +
        "' is not finite");
    }
    if (w == 0.0)
    {
      continue;
    }
    for (size_t k = this->RowStart[s]; k < this->RowStart[s + 1]; ++k)
    {
      targetWeights[this->Columns[k]] += w * this->Values[k];
    }
  }
  // Action-unit targets are sculpted for [0, 1]: beyond 1 they overshoot (lips through
  // teeth), below 0 they invert. Summing e.g. A (jawOpen 0.7) and O (jawOpen 0.45) must
  // not open the jaw past its sculpted maximum.
  for (size_t t = 0; t < numTargets; ++t)
  {
    targetWeights[t] = std::clamp(targetWeights[t], 0.0, 1.0);
  }
}

std::vector<double> Rig::Expand(const std::vector<double>& shapeWeights) const
{
  if (shapeWeights.size() != this->ShapeNames.size())
  {
    throw InputError("rig '" + this->Name + "': " + std::to_string(shapeWeights.size()) +
      " shape weights given, the rig has " + std::to_string(this->ShapeNames.size()) + " shapes");
  }
  this->RequireBound("Expand");
  std::vector<double> out(this->BoundTargetNames.size());
  this->Expand(shapeWeights.data(), out.data());
  return out;
}

std::vector<double> Rig::Expand(const std::map<std::string, double>& namedWeights) const
{
  std::vector<double> weights(this->ShapeNames.size(), 0.0);
  for (const auto& named : namedWeights)
  {
    const int s = this->FindShape(named.first);
    if (s < 0)
    {
      throw InputError("rig '" + this->Name + "' has no shape '" + named.first + "'");
    }
    weights[static_cast<size_t>(s)] = named.second;
  }
  return this->Expand(weights);
}

template <typename T>
std::vector<std::vector<T>> Rig::Bake(
  const std::vector<const T*>& targetDeltas, size_t numValues) const
{
  this->RequireBound("Bake");
  if (targetDeltas.size() != this->BoundTargetNames.size())
  {
    throw InputError("rig '" + this->Name + "': Bake got " + std::to_string(targetDeltas.size()) +
      " target delta sets, the bound face has " + std::to_string(this->BoundTargetNames.size()));
  }
  std::vector<std::vector<T>> shapes(this->ShapeNames.size());
  for (size_t s = 0; s < shapes.size(); ++s)
  {
    shapes[s].resize(numValues);
    this->BakeShape(s, targetDeltas.data(), numValues, shapes[s].data());
  }
  return shapes;
}

template <typename T>
void Rig::BakeShape(size_t shape, const T* const* targetDeltas, size_t numValues, T* out) const
{
  std::vector<double> sum(numValues, 0.0); // double: several terms, one rounding at the end
  for (size_t k = this->RowStart[shape]; k < this->RowStart[shape + 1]; ++k)
  {
    const T* delta = targetDeltas[this->Columns[k]];
    if (delta == nullptr)
    {
      throw InputError("rig '" + this->Name + "', shape '" + this->ShapeNames[shape] +
        "': no deltas given for target '" + this->BoundTargetNames[this->Columns[k]] + "'");
    }
    const double c = this->Values[k];
    for (size_t v = 0; v < numValues; ++v)
    {
      sum[v] += c * static_cast<double>(delta[v]);
    }
  }
  std::copy(sum.begin(), sum.end(), out);
}

template std::vector<std::vector<float>> Rig::Bake<float>(
  const std::vector<const float*>&, size_t) const;
template std::vector<std::vector<double>> Rig::Bake<double>(
  const std::vector<const double*>&, size_t) const;

std::vector<size_t> Rig::ResolveShapes(const std::vector<std::string>& shapeNames) const
{
  std::vector<size_t> shapes;
  if (shapeNames.empty())
  {
    for (size_t s = 0; s < this->ShapeNames.size(); ++s)
    {
      shapes.push_back(s);
    }
    return shapes;
  }
  for (const auto& name : shapeNames)
  {
    const int s = this->FindShape(name);
    if (s < 0)
    {
      throw InputError("rig '" + this->Name + "' has no shape '" + name + "'");
    }
    shapes.push_back(static_cast<size_t>(s));
  }
  return shapes;
}

MorphMesh Rig::BakeModel(const MorphMesh& model, const std::vector<std::string>& shapeNames)
{
  model.Validate();
  this->Bind(model);
  const std::vector<size_t> shapes = this->ResolveShapes(shapeNames);
  const size_t numTargets = this->BoundTargetNames.size();
  const size_t numPoints = model.GetNumberOfPoints();

  MorphMesh baked(numPoints);
  std::vector<std::string> names{ "Neutral" };
  for (size_t s : shapes)
  {
    names.push_back(this->ShapeNames[s]);
  }
  baked.SetTargetNames(names);

  for (size_t a = 0; a < model.GetNumberOfAttributes(); ++a)
  {
    std::visit(
      [&](const auto& attribute)
      {
        using T = typename std::decay_t<decltype(attribute.GetNeutral())>::value_type;
        const size_t numValues = numPoints * static_cast<size_t>(attribute.GetNumberOfComponents());
        // Dense copies of the targets a requested shape uses; each is read once per shape.
        std::vector<std::vector<T>> dense(numTargets);
        std::vector<const T*> pointers(numTargets, nullptr);
        for (size_t s : shapes)
        {
          for (size_t k = this->RowStart[s]; k < this->RowStart[s + 1]; ++k)
          {
            const size_t t = this->Columns[k];
            if (pointers[t] == nullptr)
            {
              dense[t].resize(numValues);
              attribute.GetTarget(t + 1).ToDense(dense[t].data());
              pointers[t] = dense[t].data();
            }
          }
        }
        auto& out = baked.AddAttribute<T>(
          attribute.GetName(), attribute.GetRole(), attribute.GetNumberOfComponents());
        out.SetNeutral(attribute.GetNeutral().data());
        std::vector<T> shapeDeltas(numValues);
        for (size_t s : shapes)
        {
          this->BakeShape(s, pointers.data(), numValues, shapeDeltas.data());
          out.AddRelativeTarget(shapeDeltas.data(), MorphMesh::DefaultSparseCoverage);
        }
      },
      model.GetAttribute(a));
  }
  baked.SetTriangles(model.GetTriangles());
  return baked;
}
} // namespace morphnode
