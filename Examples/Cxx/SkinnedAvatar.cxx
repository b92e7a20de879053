// SPDX-License-Identifier: BSD-3-Clause
// SkinnedAvatar: a skinned avatar (a glTF with a skin, e.g. the shared MakeHuman avatar)
// saying a vowel with its head turned on its neck and its eyes looking aside in their
// sockets, framed on the face (docs/avatars.md): vtkMorphTargetReader (the skinned parts
// at rest) -> vtkMorphNodeFilter (the weights) -> vtkMorphSkinFilter (the bones posed,
// the morphed parts re-skinned). The C++ twin of Examples/Python/skinned_avatar.py.
//
// Usage: SkinnedAvatar avatar.glb [--head-yaw DEG] [--eye-yaw DEG] [--weight NAME=VALUE ...]
//                      [--png out.png] [--size WxH]
#include "CommandLine.h"
#include "HeadActors.h"
#include "ImageOutput.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

#include <iostream>
#include <map>
#include <string>

int main(int argc, char* argv[])
{
  namespace appkit = morphnode::appkit;
  std::string avatar, png;
  std::map<std::string, double> weights{ { "viseme_O", 1.0 }, { "jawOpen", 0.45 } }; // "O"
  double headYaw = 20.0, eyeYaw = 25.0;
  int width = 400, height = 400;
  CLI::App app("SkinnedAvatar: a skinned avatar posed by its bones and morphed.", "SkinnedAvatar");
  app.add_option("avatar", avatar, "a skinned glTF/GLB avatar")->required();
  appkit::AddNumberOption(
    app, "--head-yaw", headYaw, -90.0, 90.0, "head turn, degrees to its left");
  appkit::AddNumberOption(
    app, "--eye-yaw", eyeYaw, -90.0, 90.0, "gaze relative to the head, degrees");
  app
    .add_option(
      "--weight", weights, "a target's weight, NAME=VALUE (default viseme_O=1 jawOpen=0.45)")
    ->delimiter('=')
    ->take_all();
  app.add_option("--png", png, "render offscreen to this file instead of a window");
  appkit::AddSizeOption(app, "--size", width, height, "window / image size");
  appkit::ParseCommandLine(app, argc, argv);

  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(avatar.c_str());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative(); // glTF-style weights
  for (const auto& [name, weight] : weights)
  {
    morph->SetWeightByName(name.c_str(), weight);
  }
  vtkNew<vtkMorphSkinFilter> skin;
  // Downstream of the morph node: a second pass. The same filter can pose in the morph
  // node's own pass instead (morph->SetPoseFilter(skin), its output then the posed
  // avatar; MorphAvatar does, docs/avatars.md): the same points, one pass fewer.
  skin->SetInputConnection(morph->GetOutputPort());
  skin->SetHeadYaw(headYaw);
  skin->SetEyeYaw(eyeYaw);
  skin->RelaxArmsOn();
  skin->Update();
  double bounds[6];
  if (skin->GetNumberOfSkinnedParts() == 0 || !skin->GetHeadBounds(bounds))
  {
    std::cerr << "SkinnedAvatar: " << avatar << " has no skinned head (see the errors above)\n";
    return 1;
  }
  std::cout << avatar << ": " << skin->GetNumberOfSkinnedParts()
            << " skinned parts; bones: " << skin->GetBones() << "\n";

  vtkNew<vtkRenderer> renderer;
  appkit::HeadActors head;
  head.Build(skin->GetOutputDataObject(0), renderer, nullptr);
  vtkNew<vtkRenderWindow> window;
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  window->AddRenderer(renderer);
  appkit::HeadActors::SetUpView(renderer, bounds, 0.75); // framed on the face, down to the chin
  if (!png.empty())
  {
    window->OffScreenRenderingOn();
    window->Render();
    try
    {
      appkit::WritePng(window, png);
    }
    catch (const std::exception& e)
    {
      std::cerr << "SkinnedAvatar: " << e.what() << "\n";
      return 1;
    }
    std::cout << "wrote " << png << "\n";
    return 0;
  }
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(window);
  window->Render();
  interactor->Start();
  return 0;
}
