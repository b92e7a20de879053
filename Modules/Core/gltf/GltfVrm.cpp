// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfVrm.h"

#include "GltfCheck.h"

#include "base/Error.h"
#include "base/Text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace morphnode
{
using json = nlohmann::json;

double GltfVrmRangeMap::Map(double degrees) const
{
  if (!(this->InputMax > 0.0) || !std::isfinite(degrees))
  {
    return 0.0;
  }
  return std::min(std::abs(degrees), this->InputMax) / this->InputMax * this->OutputScale;
}

std::string GltfVrm::Describe() const
{
  if (!this->IsVrm())
  {
    return "not a VRM file";
  }
  std::ostringstream out;
  out << (this->Version == 2 ? "VRM 1.0" : "VRM 0.x") << ": " << this->Expressions.size()
      << " expressions, " << this->HumanBones.size() << " humanoid bones";
  if (!this->LookAtType.empty())
  {
    out << ", look-at by " << this->LookAtType;
  }
  return out.str();
}

namespace
{
/// The target names of mesh `m`: extras.targetNames, else target<k>.
std::vector<std::string> TargetNames(const json& root, int m, const std::string& what)
{
  const json* meshes =
    root.contains("meshes") && root["meshes"].is_array() ? &root["meshes"] : nullptr;
  if (!meshes || m < 0 || static_cast<size_t>(m) >= meshes->size())
  {
    throw InputError(what + ": mesh " + std::to_string(m) + " does not exist");
  }
  const json& mesh = (*meshes)[static_cast<size_t>(m)];
  std::vector<std::string> names;
  if (mesh.contains("extras") && mesh["extras"].is_object() &&
    mesh["extras"].contains("targetNames") && mesh["extras"]["targetNames"].is_array())
  {
    for (const auto& n : mesh["extras"]["targetNames"])
    {
      names.push_back(n.is_string() ? n.get<std::string>() : std::string());
    }
  }
  size_t count = 0;
  if (mesh.contains("primitives") && mesh["primitives"].is_array() && !mesh["primitives"].empty() &&
    mesh["primitives"][0].is_object() && mesh["primitives"][0].contains("targets") &&
    mesh["primitives"][0]["targets"].is_array())
  {
    count = mesh["primitives"][0]["targets"].size();
  }
  if (names.size() != count)
  {
    names.clear();
    for (size_t k = 0; k < count; ++k)
    {
      names.push_back("target" + std::to_string(k));
    }
  }
  return names;
}

int Int(const json& o, const char* key, int fallback = -1)
{
  return o.is_object() && o.contains(key) && o[key].is_number_integer() ? o[key].get<int>()
                                                                        : fallback;
}

double Number(const json& o, const char* key, double fallback)
{
  return o.is_object() && o.contains(key) && o[key].is_number() &&
      std::isfinite(o[key].get<double>())
    ? o[key].get<double>()
    : fallback;
}

std::string NodeName(const json& root, int node, const std::string& what)
{
  if (!root.contains("nodes") || !root["nodes"].is_array() || node < 0 ||
    static_cast<size_t>(node) >= root["nodes"].size())
  {
    throw InputError(what + ": node " + std::to_string(node) + " does not exist");
  }
  const json& n = root["nodes"][static_cast<size_t>(node)];
  return n.is_object() && n.contains("name") && n["name"].is_string()
    ? n["name"].get<std::string>()
    : "node" + std::to_string(node);
}

/// One bind: the target name at `index` of mesh `mesh`.
std::string BindTarget(const json& root, int mesh, int index, const std::string& what)
{
  const std::vector<std::string> names = TargetNames(root, mesh, what);
  if (index < 0 || static_cast<size_t>(index) >= names.size())
  {
    throw InputError(what + ": target " + std::to_string(index) + " of mesh " +
      std::to_string(mesh) + " does not exist (the mesh has " + std::to_string(names.size()) + ")");
  }
  return names[static_cast<size_t>(index)];
}

/// VRM 0.x preset names as VRM 1.0's.
std::string PresetName(const std::string& preset)
{
  static const std::map<std::string, std::string> names = { { "a", "aa" }, { "i", "ih" },
    { "u", "ou" }, { "e", "ee" }, { "o", "oh" }, { "joy", "happy" }, { "sorrow", "sad" },
    { "fun", "relaxed" }, { "angry", "angry" }, { "blink", "blink" }, { "blink_l", "blinkLeft" },
    { "blink_r", "blinkRight" }, { "lookup", "lookUp" }, { "lookdown", "lookDown" },
    { "lookleft", "lookLeft" }, { "lookright", "lookRight" }, { "neutral", "neutral" },
    { "surprised", "surprised" } };
  const auto it = names.find(text::ToLower(preset));
  return it == names.end() ? std::string() : it->second;
}

void AddBind(GltfVrmExpression& e, const std::string& target, double weight)
{
  for (auto& b : e.Binds)
  {
    if (b.first == target)
    {
      b.second = std::max(b.second, weight);
      return;
    }
  }
  e.Binds.emplace_back(target, weight);
}

void ReadVrm1(const json& root, const json& vrm, GltfVrm& out)
{
  out.Version = 2;
  const json& expressions = vrm.value("expressions", json::object());
  for (const char* group : { "preset", "custom" })
  {
    if (!expressions.is_object() || !expressions.contains(group) || !expressions[group].is_object())
    {
      continue;
    }
    for (const auto& [name, ex] : expressions[group].items())
    {
      GltfVrmExpression e;
      e.Name = name;
      e.Preset = std::string(group) == "preset";
      e.Binary = ex.is_object() && ex.value("isBinary", false);
      const std::string what = "VRMC_vrm expression '" + name + "'";
      if (ex.is_object() && ex.contains("morphTargetBinds") && ex["morphTargetBinds"].is_array())
      {
        for (const auto& bind : ex["morphTargetBinds"])
        {
          const int node = Int(bind, "node");
          if (!root.contains("nodes") || !root["nodes"].is_array() || node < 0 ||
            static_cast<size_t>(node) >= root["nodes"].size())
          {
            throw InputError(what + ": node " + std::to_string(node) + " does not exist");
          }
          const int mesh = Int(root["nodes"][static_cast<size_t>(node)], "mesh");
          const double weight = std::clamp(Number(bind, "weight", 1.0), 0.0, 1.0);
          AddBind(e, BindTarget(root, mesh, Int(bind, "index"), what), weight);
        }
      }
      out.Expressions.push_back(std::move(e));
    }
  }
  const json& humanoid = vrm.value("humanoid", json::object());
  if (humanoid.is_object() && humanoid.contains("humanBones") && humanoid["humanBones"].is_object())
  {
    for (const auto& [bone, value] : humanoid["humanBones"].items())
    {
      const int node = Int(value, "node");
      out.HumanBoneNodeNames[bone] = NodeName(root, node, "VRMC_vrm humanoid bone '" + bone + "'");
      out.HumanBones[bone] = node;
    }
  }
  const json& lookAt = vrm.value("lookAt", json::object());
  if (lookAt.is_object() && lookAt.contains("type") && lookAt["type"].is_string())
  {
    out.LookAtType = lookAt["type"].get<std::string>() == "expression" ? "expression" : "bone";
    const double scale = out.LookAtType == "bone" ? 10.0 : 1.0;
    auto range = [&](const char* key, GltfVrmRangeMap& map)
    {
      const json& r = lookAt.value(key, json::object());
      map.InputMax = Number(r, "inputMaxValue", 90.0);
      map.OutputScale = Number(r, "outputScale", scale);
    };
    range("rangeMapHorizontalInner", out.HorizontalInner);
    range("rangeMapHorizontalOuter", out.HorizontalOuter);
    range("rangeMapVerticalDown", out.VerticalDown);
    range("rangeMapVerticalUp", out.VerticalUp);
    const json& offset = lookAt.value("offsetFromHeadBone", json::array());
    for (size_t k = 0; k < 3 && offset.is_array() && k < offset.size(); ++k)
    {
      out.LookAtOffset[k] = offset[k].is_number() ? offset[k].get<double>() : 0.0;
    }
  }
}

void ReadVrm0(const json& root, const json& vrm, GltfVrm& out)
{
  out.Version = 1;
  const json& master = vrm.value("blendShapeMaster", json::object());
  if (master.is_object() && master.contains("blendShapeGroups") &&
    master["blendShapeGroups"].is_array())
  {
    for (const auto& group : master["blendShapeGroups"])
    {
      if (!group.is_object())
      {
        continue;
      }
      GltfVrmExpression e;
      const std::string preset = PresetName(group.value("presetName", std::string()));
      e.Preset = !preset.empty();
      e.Name = e.Preset ? preset : group.value("name", std::string("unnamed"));
      e.Binary = group.value("isBinary", false);
      const std::string what = "VRM blend shape group '" + e.Name + "'";
      if (group.contains("binds") && group["binds"].is_array())
      {
        for (const auto& bind : group["binds"])
        {
          const double weight = std::clamp(Number(bind, "weight", 100.0) / 100.0, 0.0, 1.0);
          AddBind(e, BindTarget(root, Int(bind, "mesh"), Int(bind, "index"), what), weight);
        }
      }
      out.Expressions.push_back(std::move(e));
    }
  }
  const json& humanoid = vrm.value("humanoid", json::object());
  if (humanoid.is_object() && humanoid.contains("humanBones") && humanoid["humanBones"].is_array())
  {
    for (const auto& b : humanoid["humanBones"])
    {
      if (!b.is_object() || !b.contains("bone") || !b["bone"].is_string())
      {
        continue;
      }
      const std::string bone = b["bone"].get<std::string>();
      const int node = Int(b, "node");
      out.HumanBoneNodeNames[bone] = NodeName(root, node, "VRM humanoid bone '" + bone + "'");
      out.HumanBones[bone] = node;
    }
  }
  const json& first = vrm.value("firstPerson", json::object());
  if (first.is_object() && first.contains("lookAtTypeName") && first["lookAtTypeName"].is_string())
  {
    out.LookAtType =
      first["lookAtTypeName"].get<std::string>() == "BlendShape" ? "expression" : "bone";
    const double scale = out.LookAtType == "bone" ? 10.0 : 1.0;
    auto curve = [&](const char* key, GltfVrmRangeMap& map)
    {
      const json& r = first.value(key, json::object());
      map.InputMax = Number(r, "xRange", 90.0);
      map.OutputScale = Number(r, "yRange", scale);
    };
    curve("lookAtHorizontalInner", out.HorizontalInner);
    curve("lookAtHorizontalOuter", out.HorizontalOuter);
    curve("lookAtVerticalDown", out.VerticalDown);
    curve("lookAtVerticalUp", out.VerticalUp);
    const json& offset = first.value("firstPersonBoneOffset", json::object());
    out.LookAtOffset = { { Number(offset, "x", 0.0), Number(offset, "y", 0.0),
      Number(offset, "z", 0.0) } };
  }
}

GltfVrm FromRoot(const json& root)
{
  GltfVrm out;
  if (!root.is_object() || !root.contains("extensions") || !root["extensions"].is_object())
  {
    return out;
  }
  const json& ext = root["extensions"];
  if (ext.contains("VRMC_vrm") && ext["VRMC_vrm"].is_object())
  {
    ReadVrm1(root, ext["VRMC_vrm"], out);
  }
  else if (ext.contains("VRM") && ext["VRM"].is_object())
  {
    ReadVrm0(root, ext["VRM"], out);
  }
  return out;
}
} // namespace

GltfVrm ReadGltfVrmFromJson(const std::string& text, const std::string& what)
{
  const json root = json::parse(text, nullptr, false);
  if (root.is_discarded())
  {
    throw InputError(what + ": not JSON");
  }
  try
  {
    return FromRoot(root);
  }
  catch (const json::exception& e)
  {
    throw InputError(what + ": " + e.what());
  }
}

GltfVrm ReadGltfVrmFromMemory(const void* data, size_t size, const std::string& what)
{
  const gltfcheck::Container container =
    gltfcheck::SplitContainer(static_cast<const unsigned char*>(data), size, what);
  const json root = gltfcheck::ParseJson(container, what);
  try
  {
    return FromRoot(root);
  }
  catch (const json::exception& e)
  {
    throw InputError(what + ": " + e.what());
  }
}

GltfVrm ReadGltfVrm(const std::string& fileName)
{
  const std::string bytes = text::ReadFile(fileName, "glTF file");
  return ReadGltfVrmFromMemory(bytes.data(), bytes.size(), fileName);
}
} // namespace morphnode
