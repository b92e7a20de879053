// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar: the running system of Berner (WSCG 2004, Figure 6). An avatar speaks a
// sentence or plays a behaviour script, with idle behaviour (blinks, saccades, head
// micro-motion); the weight optimizer can be switched while it runs, and an overlay shows
// the frame rate, the method, the threshold and the active targets.
//
// Interactive (a window, time runs in real time):
//   MorphAvatar --say "Hello, how are you?"
//   MorphAvatar --script Data/scripts/greeting.txt
// Offscreen (every frame at the frame rate, to PNG frames and/or a video with sound):
//   MorphAvatar --script Data/scripts/greeting.txt --offscreen --frames out/ --video
//   out/greeting.ogv
// One frame, compared with a baseline (the render regression test):
//   MorphAvatar --script ... --at 1.5 --png frame.png --compare
//   Testing/Baseline/TestMorphAvatar.png
//
// The files: AvatarOptions (the command line), Avatar (the pipeline and the scene),
// AvatarInteractive and AvatarOffscreen (the two modes). `MorphAvatar --help` lists every
// option; docs/avatar.md describes them.
#include "Avatar.h"
#include "AvatarFrameBudget.h"
#include "AvatarGltf.h"
#include "AvatarLive.h"
#include "AvatarNaming.h"
#include "AvatarServe.h"
#include "StopSignal.h"

#include <cstdlib>
#include <iostream>

namespace
{
int Run(int argc, char* argv[])
{
  using namespace morphavatar;
  Avatar a;
  a.Opt = ParseOptions(argc, argv);
  if (!a.Opt.Serve.empty())
  {
    return RunServe(a.Opt); // browsers are the faces (docs/streaming.md): no window, no display
  }
  // --gltf alone writes a file and renders nothing.
  const bool render = a.Opt.Gltf.empty() || a.Opt.Offscreen || IsLive(a.Opt);
  if (render && !std::getenv("DISPLAY"))
  {
    std::cerr << "MorphAvatar: no X display (DISPLAY is not set). VTK renders through X, "
                 "offscreen too: run under `xvfb-run -a MorphAvatar ...`.\n";
    return 2;
  }
  // The face's rig, visemes and gaze chosen from its names (unless given), printed.
  if (!ChooseFaceSetup(a) || !a.SetUpBehavior() || !a.SetUpFace())
  {
    return 1;
  }
  if (!a.Opt.Gltf.empty() && !ExportGltf(a))
  {
    return 1;
  }
  if (!render)
  {
    return 0;
  }
  // From here SIGTERM/SIGINT end the run as quit does (before: the default action, which
  // ends a setup or a --gltf export at once; its files are renamed into place whole).
  morphnode::appkit::InstallStopSignals();
  a.SetUpScene();
  if (!a.Opt.Profile.empty())
  {
    a.Morph->SetDeviceProfile(a.Opt.Profile.c_str()); // before --frame-budget, which overrides
  }
  else if (a.Opt.Lod)
  {
    a.Morph->SetTargetPixelBound(0.5);
  }
  if ((a.Opt.Lod || !a.Opt.Profile.empty()) && vtkMorphNodeFilter::HasMeshLevels())
  {
    // The mesh levels the screen and the budget ask for, every part at one level.
    a.Morph->MeshLevelsOn();
  }
  WatchFrameBudget(a.Morph, a.Opt);
  if (!a.Opt.Quiet)
  {
    // With commands on stdin, stdout carries only their events.
    (a.Opt.CommandsStdin ? std::cerr : std::cout)
      << a.FaceFile << ": " << a.Morph->GetNumberOfTargets() << " targets; behaviour " << a.Duration
      << " s at " << a.Fps << " fps, " << a.Behavior->GetNumberOfChannels() << " channels, "
      << a.Behavior->GetNumberOfUtterances() << " utterance(s)\n";
  }
  // Live: commands from a dialog system (docs/dialog.md).
  const int code =
    IsLive(a.Opt) ? RunLive(a) : (a.Opt.Offscreen ? RunOffscreen(a) : RunInteractive(a));
  const bool logged = FinishFrameBudget();
  if (morphnode::appkit::StopRequested() && !a.Opt.Quiet)
  {
    std::cerr << "MorphAvatar: stopped by signal " << morphnode::appkit::StopSignalNumber() << "\n";
  }
  return logged ? code : (code != 0 ? code : 1);
}
} // namespace

int main(int argc, char* argv[])
{
  // Library failures and exhausted memory end the program with a message, never an abort.
  try
  {
    return Run(argc, argv);
  }
  catch (const std::bad_alloc&)
  {
    std::cerr
      << "MorphAvatar: out of memory (an input too large for this machine; see docs/limits.md)\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "MorphAvatar: " << e.what() << "\n";
  }
  return 1;
}
