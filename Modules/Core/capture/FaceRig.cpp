// SPDX-License-Identifier: BSD-3-Clause
#include "capture/FaceRig.h"

#include "capture/ArkitNames.h"

#include "base/Error.h"
#include "base/Text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <sstream>

namespace morphnode
{
namespace
{
/// Per behaviour shape, the target names that are that shape in a naming family, in order
/// of preference (compared without case). A table, not code: extend it for a new family.
const std::map<std::string, std::vector<std::string>>& OwnNames()
{
  static const std::map<std::string, std::vector<std::string>> table = {
    // Meta / Oculus visemes (the rig's "meta" set) and the German set's aliases.
    { "sil", { "viseme_sil" } },
    { "PP", { "viseme_PP" } },
    { "P", { "viseme_PP" } },
    { "FF", { "viseme_FF" } },
    { "TH", { "viseme_TH" } },
    { "DD", { "viseme_DD" } },
    { "T", { "viseme_DD" } },
    { "kk", { "viseme_kk" } },
    { "K", { "viseme_kk" } },
    { "CH", { "viseme_CH" } },
    { "Z", { "viseme_CH" } },
    { "SS", { "viseme_SS" } },
    { "nn", { "viseme_nn" } },
    { "RR", { "viseme_RR" } },
    { "aa", { "viseme_aa", "Fcl_MTH_A", "aa" } },
    { "ih", { "viseme_I", "Fcl_MTH_I", "ih" } },
    { "oh", { "viseme_O", "Fcl_MTH_O", "oh" } },
    { "ou", { "viseme_U", "Fcl_MTH_U", "ou" } },
    { "U", { "viseme_U", "Fcl_MTH_U", "ou" } },
    // The paper's shapes, where a family has a close peer.
    { "A", { "viseme_aa", "Fcl_MTH_A", "aa" } },
    { "E", { "viseme_E", "Fcl_MTH_E", "ee" } },
    { "O", { "viseme_O", "Fcl_MTH_O", "oh" } },
    { "S", { "viseme_SS" } },
    { "F", { "viseme_FF" } },
    { "EyesClosed", { "Fcl_EYE_Close", "blink" } },
    { "MouthSmile", { "Fcl_MTH_Joy", "Fcl_ALL_Joy", "happy", "joy" } },
    { "MouthSad", { "Fcl_MTH_Sorrow", "Fcl_ALL_Sorrow", "sad", "sorrow" } },
    { "BrowsAngry", { "Fcl_BRW_Angry", "angry" } },
    { "BrowsUp", { "Fcl_BRW_Surprised", "surprised" } },
    { "BrowsFright", { "Fcl_BRW_Sorrow" } },
    // The behaviour's looks: VRM's look expressions.
    { "LookUp", { "lookUp" } },
    { "LookDown", { "lookDown" } },
    { "LookLeft", { "lookLeft" } },
    { "LookRight", { "lookRight" } },
  };
  return table;
}

bool IsPaperName(const std::string& name)
{
  static const char* const paper[] = { "EyesClosed", "BrowsUp", "S", "F", "BrowsFright",
    "BrowsAngry", "L", "E", "A", "MouthSmile", "MouthSad", "O" };
  return std::find(std::begin(paper), std::end(paper), name) != std::end(paper);
}
} // namespace

std::string FaceRigChoice::Report() const
{
  std::ostringstream out;
  out << "face naming: " << (this->Families.empty() ? "none recognised" : this->Families) << "\n";
  if (!this->NeedsRig)
  {
    out << "rig: none needed (the face's targets are the behaviour's shapes)\n";
    return out.str();
  }
  auto list = [&](const char* what, const std::vector<std::string>& shapes)
  {
    out << what << " (" << shapes.size() << "): ";
    for (size_t i = 0; i < shapes.size(); ++i)
    {
      out << (i ? " " : "") << shapes[i];
    }
    out << (shapes.empty() ? "none" : "") << "\n";
  };
  list("shapes on the face's own targets", this->Own);
  list("shapes synthesized from ARKit shapes", this->Synthesized);
  list("shapes missing (nothing drives them)", this->Missing);
  return out.str();
}

FaceRigChoice ChooseFaceRig(const std::vector<std::string>& faceTargets, const Rig& arkitRig)
{
  return ChooseFaceRig(faceTargets, arkitRig, {});
}

FaceRigChoice ChooseFaceRig(const std::vector<std::string>& faceTargets, const Rig& arkitRig,
  const std::vector<FaceExpression>& expressions)
{
  std::map<std::string, const FaceExpression*> expressionByLower;
  for (const auto& e : expressions)
  {
    if (!e.Binds.empty())
    {
      expressionByLower.emplace(text::ToLower(e.Name), &e);
    }
  }
  FaceRigChoice choice;
  std::map<std::string, std::string> byLower; // lower-case name -> the face's spelling
  for (const auto& t : faceTargets)
  {
    byLower.emplace(text::ToLower(t), t);
  }
  // Families, with counts.
  size_t paper = 0, oculus = 0, vroid = 0, vrm = 0;
  for (const auto& t : faceTargets)
  {
    paper += IsPaperName(t) ? 1 : 0;
    const std::string lower = text::ToLower(t);
    oculus += lower.rfind("viseme_", 0) == 0 ? 1 : 0;
    vroid += lower.rfind("fcl_", 0) == 0 ? 1 : 0;
    static const char* const vrmNames[] = { "aa", "ih", "ou", "ee", "oh", "blink", "blinkleft",
      "blinkright", "happy", "angry", "sad", "relaxed", "surprised", "joy", "sorrow", "fun" };
    vrm += std::find(std::begin(vrmNames), std::end(vrmNames), lower) != std::end(vrmNames) ? 1 : 0;
  }
  const ArkitFaceMapping arkit = MapArkitShapes(faceTargets);
  const size_t arkitShapes = ArkitShapeCount - arkit.UnmappedShapes.size();
  std::vector<std::string> families;
  if (paper)
  {
    families.push_back("the paper's shapes (" + std::to_string(paper) + " of 12)");
  }
  if (arkitShapes)
  {
    families.push_back("ARKit (" + std::to_string(arkitShapes) + " of 52 shapes)");
  }
  if (oculus)
  {
    families.push_back("Oculus visemes (" + std::to_string(oculus) + ")");
  }
  if (vroid)
  {
    families.push_back("VRoid Fcl_* (" + std::to_string(vroid) + ")");
  }
  if (vrm)
  {
    families.push_back("VRM expressions (" + std::to_string(vrm) + ")");
  }
  if (!expressionByLower.empty())
  {
    families.push_back(
      "VRM expressions (" + std::to_string(expressionByLower.size()) + ", from the file)");
  }
  for (size_t i = 0; i < families.size(); ++i)
  {
    choice.Families += (i ? ", " : "") + families[i];
  }
  if (paper >= 8 && arkitShapes < 10)
  {
    choice.NeedsRig = false;
    return choice;
  }
  if (families.empty() ||
    (arkitShapes == 0 && oculus == 0 && vroid == 0 && vrm == 0 && expressionByLower.empty()))
  {
    throw InputError(
      "no target name of the face belongs to a known naming family (the paper's shapes, ARKit, "
      "Oculus visemes viseme_*, VRoid Fcl_*, VRM expressions): give a rig with --rig");
  }
  choice.HasOwnVisemes = oculus >= 10;

  nlohmann::ordered_json doc;
  doc["name"] = "Chosen for the face";
  doc["description"] =
    "Made by MorphNode from the face's target names (capture/FaceRig.h): " + choice.Families;
  nlohmann::ordered_json shapes = nlohmann::ordered_json::object();
  for (const std::string& shape : arkitRig.GetShapeNames())
  {
    nlohmann::ordered_json terms = nlohmann::ordered_json::object();
    // 1. The face's own target of this shape.
    const auto own = OwnNames().find(shape);
    if (own != OwnNames().end())
    {
      for (const auto& candidate : own->second)
      {
        const auto ex = expressionByLower.find(text::ToLower(candidate));
        if (ex != expressionByLower.end())
        {
          for (const auto& [target, weight] : ex->second->Binds)
          {
            terms[target] = weight;
          }
          break;
        }
        const auto it = byLower.find(text::ToLower(candidate));
        if (it != byLower.end())
        {
          terms[it->second] = 1.0;
          break;
        }
      }
    }
    if (!terms.empty())
    {
      choice.Own.push_back(shape);
    }
    else if (arkitShapes > 0)
    {
      // 2. Synthesized: the ARKit rig's terms in the face's spelling. Split halves
      // (browInnerUp_L/_R) that land on one whole target keep the larger coefficient.
      const size_t s = static_cast<size_t>(arkitRig.FindShape(shape));
      for (const RigTerm& term : arkitRig.GetShapeTerms(s))
      {
        const int a = FindArkitShape(term.Target);
        if (a < 0)
        {
          continue;
        }
        for (size_t t : arkit.Targets[static_cast<size_t>(a)])
        {
          const std::string& name = faceTargets[t];
          terms[name] = std::max(terms.value(name, 0.0), term.Coefficient);
        }
      }
      const bool empty = arkitRig.GetShapeTerms(s).empty(); // sil: the neutral face on purpose
      (terms.empty() && !empty ? choice.Missing : choice.Synthesized).push_back(shape);
    }
    else
    {
      choice.Missing.push_back(shape);
    }
    shapes[shape] = terms;
  }
  doc["shapes"] = shapes;
  nlohmann::ordered_json sets = nlohmann::ordered_json::object();
  for (const std::string& set : arkitRig.GetSetNames())
  {
    sets[set] = arkitRig.GetSet(set);
  }
  doc["sets"] = sets;
  choice.RigJson = doc.dump(2);
  Rig::LoadString(choice.RigJson, "the chosen rig").Validate(faceTargets); // a check of this code
  return choice;
}
} // namespace morphnode
