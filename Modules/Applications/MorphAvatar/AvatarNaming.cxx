// SPDX-License-Identifier: BSD-3-Clause
#include "AvatarNaming.h"

#include "Avatar.h"
#include "DataPaths.h"

#include "base/Text.h"
#include "capture/ArkitNames.h"
#include "capture/FaceRig.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfVrm.h"
#include "rig/Rig.h"

#include "vtkMorphSkinFilter.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace morphavatar
{
namespace appkit = morphnode::appkit;

namespace
{
/// True for an eyeLook* target in any ARKit spelling.
bool IsEyeLook(const std::string& name)
{
  const int a = morphnode::FindArkitShape(name);
  return a >= 0 && morphnode::ArkitShapeNames()[static_cast<size_t>(a)].rfind("eyeLook", 0) == 0;
}
} // namespace

bool ChooseFaceSetup(Avatar& a)
{
  Options& o = a.Opt;
  const std::string face = o.Face.empty() ? appkit::DefaultFace() : o.Face;
  a.Reader->SetFileName(face.c_str());
  a.Reader->Update();
  std::vector<std::string> targets;
  for (int t = 1; t < a.Reader->GetNumberOfTargets(); ++t)
  {
    targets.emplace_back(a.Reader->GetTargetName(t));
  }
  if (targets.empty())
  {
    if (o.Visemes.empty())
    {
      o.Visemes = "paper6";
    }
    return true; // SetUpFace reports what is wrong with the face
  }
  // The skeleton, if any: eye bones?
  vtkNew<vtkMorphSkinFilter> skin;
  skin->SetInputConnection(a.Reader->GetOutputPort());
  skin->Update();
  const bool eyeBones = skin->GetHasEyeBones();
  std::ostream& out = o.CommandsStdin ? std::cerr : std::cout;
  // Every line a program line ("MorphAvatar: ..."), as the content errors are.
  std::ostringstream log;
  const auto flush = [&]()
  {
    std::istringstream lines(log.str());
    for (std::string line; std::getline(lines, line);)
    {
      out << "MorphAvatar: " << line << "\n";
    }
    log.str("");
  };

  // A VRM avatar's own expressions and look-at (gltf/GltfVrm.h); nothing for other files.
  std::vector<morphnode::FaceExpression> expressions;
  std::string lookAt;
  try
  {
    const std::string ext =
      morphnode::text::ToLower(std::filesystem::path(face).extension().string());
    if (ext == ".glb" || ext == ".gltf" || ext == ".vrm")
    {
      const morphnode::GltfVrm vrm = morphnode::ReadGltfVrm(face);
      for (const auto& e : vrm.Expressions)
      {
        expressions.push_back({ e.Name, e.Binds });
      }
      lookAt = vrm.LookAtType;
      if (vrm.IsVrm() && !o.Quiet)
      {
        log << face << ": " << vrm.Describe() << "\n";
      }
    }
  }
  catch (const std::exception& e)
  {
    log << "the VRM description is not used: " << e.what() << "\n";
  }
  std::string rigJson;
  bool ownVisemes = false;
  try
  {
    if (o.Rig.empty())
    {
      const morphnode::Rig arkit = morphnode::Rig::LoadFile(appkit::DataPath("rigs/arkit.json"));
      const morphnode::FaceRigChoice choice = morphnode::ChooseFaceRig(targets, arkit, expressions);
      ownVisemes = choice.HasOwnVisemes;
      if (!o.Quiet)
      {
        log << face << ": " << choice.Report()
            << (choice.NeedsRig ? "rig: chosen from the face's names (--rig FILE overrides)\n"
                                : "");
      }
      if (choice.NeedsRig)
      {
        rigJson = choice.RigJson;
      }
    }
    else
    {
      rigJson = morphnode::text::ReadFile(o.Rig, "rig");
      for (const auto& t : targets)
      {
        ownVisemes = ownVisemes || morphnode::text::ToLower(t).rfind("viseme_", 0) == 0;
      }
    }
  }
  catch (const std::exception& e)
  {
    flush();
    std::cerr << "MorphAvatar: " << e.what() << "\n";
    return false;
  }
  if (o.Visemes.empty())
  {
    o.Visemes = ownVisemes ? "oculus15" : "paper6";
    if (!o.Quiet && ownVisemes)
    {
      log << "visemes: oculus15 (the face has its own viseme_* targets; --visemes overrides)\n";
    }
  }

  // The eyes one way: bones or targets.
  if (o.Gaze == "auto")
  {
    // A VRM says how it looks at things (lookAt type: bone or expression).
    o.Gaze = lookAt == "expression" ? "targets" : eyeBones ? "bones" : "targets";
  }
  // With eye bones the eyeballs turn by their joints; their eyeLook* targets are turned off
  // on the parts those joints turn (the eyeballs), so that the rig's eyeLook* weights move
  // only the rest (the lids of the head) and the eyeballs never turn twice.
  size_t offParts = 0;
  a.Morph->RemoveAllTargetsOffInParts();
  if (o.Gaze == "bones")
  {
    for (int p = 0; p < skin->GetNumberOfEyeParts(); ++p)
    {
      bool any = false;
      for (const auto& t : targets)
      {
        if (IsEyeLook(t))
        {
          a.Morph->SetTargetOffInPart(skin->GetEyePart(p), t.c_str());
          any = true;
        }
      }
      offParts += any ? 1 : 0;
    }
  }
  if (!o.Quiet)
  {
    if (o.Gaze == "bones")
    {
      log << "eyes: turned by the eye joints (" << (eyeBones ? skin->GetBones() : "none found")
          << ")"
          << (offParts ? "; eyeLook* targets move the lids, not the eyeballs (" +
                   std::to_string(offParts) + " eye parts)"
                       : std::string())
          << " (--gaze targets overrides)\n";
    }
    else if (eyeBones)
    {
      log << "eyes: turned by eyeLook* targets; the eye joints stay (--gaze bones overrides)\n";
    }
    if (skin->GetJawByBone())
    {
      log << "jaw: opened by the jaw joint (the face has no jawOpen target)\n";
    }
  }
  if (!rigJson.empty() && o.Rig.empty())
  {
    const std::filesystem::path file = std::filesystem::temp_directory_path() /
      ("morphavatar-rig-" + std::to_string(::getpid()) + ".json");
    std::ofstream(file) << rigJson;
    a.ChosenRig.Path = file.string();
    o.Rig = file.string();
  }
  flush();
  return true;
}

std::string ChooseServeNaming(
  const morphnode::GltfScene& face, const std::string& faceFile, Options& o)
{
  std::vector<std::string> targets;
  for (const auto& part : face.Parts)
  {
    for (const auto& t : part.Targets)
    {
      if (std::find(targets.begin(), targets.end(), t.Name) == targets.end())
      {
        targets.push_back(t.Name);
      }
    }
  }
  std::vector<morphnode::FaceExpression> expressions;
  const std::string ext =
    morphnode::text::ToLower(std::filesystem::path(faceFile).extension().string());
  if (ext == ".glb" || ext == ".gltf" || ext == ".vrm")
  {
    for (const auto& e : morphnode::ReadGltfVrm(faceFile).Expressions)
    {
      expressions.push_back({ e.Name, e.Binds });
    }
  }
  std::string rigJson;
  bool ownVisemes = false;
  std::ostream& out = std::cout;
  if (o.Rig.empty() && !targets.empty())
  {
    const morphnode::Rig arkit = morphnode::Rig::LoadFile(appkit::DataPath("rigs/arkit.json"));
    const morphnode::FaceRigChoice choice = morphnode::ChooseFaceRig(targets, arkit, expressions);
    ownVisemes = choice.HasOwnVisemes;
    if (!o.Quiet)
    {
      std::istringstream lines(faceFile + ": " + choice.Report() +
        (choice.NeedsRig ? "rig: chosen from the face's names (--rig FILE overrides)\n" : ""));
      for (std::string line; std::getline(lines, line);)
      {
        out << "MorphAvatar: " << line << "\n";
      }
    }
    rigJson = choice.NeedsRig ? choice.RigJson : std::string();
  }
  else if (!o.Rig.empty())
  {
    rigJson = morphnode::text::ReadFile(o.Rig, "rig");
    for (const auto& t : targets)
    {
      ownVisemes = ownVisemes || morphnode::text::ToLower(t).rfind("viseme_", 0) == 0;
    }
  }
  if (o.Visemes.empty())
  {
    o.Visemes = ownVisemes ? "oculus15" : "paper6";
    if (!o.Quiet && ownVisemes)
    {
      out << "MorphAvatar: visemes: oculus15 (the face has its own viseme_* targets; --visemes "
             "overrides)\n";
    }
  }
  return rigJson;
}
} // namespace morphavatar
