// SPDX-License-Identifier: BSD-3-Clause
// PlayScript: play a behaviour script (docs/behavior.md) on a face with morph targets,
// offscreen, and write PNG frames, the weight track as CSV and (when the script speaks)
// the speech as WAV into an output folder; a progress bar goes to stderr.
//
//   PlayScript [script] [--face face.glb] [--out DIR] [--fps F] [--duration S]
//              [--frames N] [--size WxH] [--voice VOICE] [--visemes paper6|oculus15|german16]
//
// Default: Data/scripts/greeting.txt on Data/DefaultFace/default_head.glb into
// ./PlayScript-out. --duration overrides the script's length, --frames renders only the
// first N frames (the CSV and the WAV still cover the whole track). Make a video with
//   ffmpeg -framerate 30 -i DIR/frame_%05d.png -i DIR/speech.wav -shortest out.mp4
//
// The pipeline: vtkBehaviorTimeSource (port 0: the weights at the requested time) drives
// vtkMorphAvatarPipeline, the avatar's chain in one class: vtkMorphNodeFilter in Relative
// mode (targets add on the neutral) on the whole head (every part of the glTF scene, one
// actor per part in its own colour: AppKit/HeadActors), vtkEyeGazeFilter turning the eye
// parts by the behaviour's EyeYaw/EyePitch (saccades, looks), and the head pose: the head
// pose channels turn all parts about the neck by one transform (behavior/HeadPose.h), since
// the face has no head-pose targets. Command line, frames, progress and the head's actors
// come from AppKit.
#include "CommandLine.h"
#include "DataPaths.h"
#include "FrameRecorder.h"
#include "HeadActors.h"
#include "ImageOutput.h"
#include "Progress.h"

#include "vtkBehaviorTimeSource.h"
#include "vtkMorphAvatarPipeline.h"

#include "vtkDelimitedTextWriter.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTransform.h" // the head pose, for the actors

#include <cmath>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  namespace appkit = morphnode::appkit;
  std::string script = appkit::DataPath("scripts/greeting.txt"), face = appkit::DefaultFace();
  std::string out = "PlayScript-out", voice, visemes;
  double fps = 0.0, duration = -1.0;
  int maxFrames = -1, width = 480, height = 480;
  CLI::App app(
    "PlayScript: a behaviour script played on a face, to PNG frames, CSV and WAV.", "PlayScript");
  app.add_option("script", script, "a behaviour script")
    ->check(CLI::ExistingFile)
    ->capture_default_str();
  app.add_option("--face", face, "a face with morph targets")
    ->check(CLI::ExistingFile)
    ->capture_default_str();
  app.add_option("--out", out, "output folder")->capture_default_str();
  appkit::AddNumberOption(app, "--fps", fps, 1.0, 240.0, "frame rate (default: the script's)")
    ->default_str("");
  appkit::AddNumberOption(
    app, "--duration", duration, 0.0, 86400.0, "seconds (default: the script's)")
    ->default_str("");
  app.add_option("--frames", maxFrames, "render only the first N frames")
    ->check(CLI::NonNegativeNumber);
  appkit::AddSizeOption(app, "--size", width, height, "frame size");
  app.add_option("--voice", voice, "eSpeak NG voice, e.g. en, de");
  app.add_option("--visemes", visemes, "paper6, oculus15 or german16");
  appkit::ParseCommandLine(app, argc, argv);

  // The behaviour: speech settings first (Say synthesizes while the script loads).
  vtkNew<vtkBehaviorTimeSource> behavior;
  if (!voice.empty())
  {
    behavior->SetVoice(voice.c_str());
  }
  if (!visemes.empty() && !behavior->SetVisemeSetFromString(visemes.c_str()))
  {
    return 2;
  }
  if (!behavior->LoadScript(script.c_str()))
  {
    return 1; // the error (with the line number) is printed already
  }
  if (fps > 0.0)
  {
    behavior->SetFrameRate(fps);
  }
  if (duration >= 0.0)
  {
    behavior->SetDuration(duration);
  }
  try
  {
    appkit::MakeFolder(out);

    // The track as CSV (port 1), and the speech lined up with it.
    vtkNew<vtkDelimitedTextWriter> csv;
    const std::string csvPath = out + "/track.csv";
    csv->SetFileName(csvPath.c_str());
    csv->SetInputConnection(behavior->GetOutputPort(1));
    if (!csv->Write())
    {
      std::cerr << "cannot write " << csvPath << "\n";
      return 1;
    }
    if (behavior->HasAudio() && !behavior->WriteAudio((out + "/speech.wav").c_str()))
    {
      return 1;
    }

    // The face, animated through time: the whole scene (every part of the head) morphed by
    // the behaviour, the eyes looking where it looks, the head turned by its pose.
    vtkNew<vtkMorphAvatarPipeline> avatar;
    avatar->SetFileName(face.c_str());
    avatar->SetWeightsConnection(behavior->GetOutputPort(0));
    avatar->UpdateTimeStep(0.0);
    double bounds[6];
    if (!appkit::HeadBounds(avatar->GetOutputDataObject(), bounds))
    {
      std::cerr << "nothing to show (see the errors above)\n";
      return 1;
    }
    vtkNew<vtkRenderer> renderer;
    appkit::HeadActors head;
    head.Build(avatar->GetOutputDataObject(), renderer, avatar->GetHeadPose());
    vtkNew<vtkRenderWindow> window;
    window->SetSize(width, height);
    window->SetMultiSamples(0);
    window->OffScreenRenderingOn();
    window->AddRenderer(renderer);
    appkit::HeadActors::SetUpView(renderer, bounds);

    const double rate = behavior->GetFrameRate();
    int count = static_cast<int>(std::floor(behavior->GetEffectiveDuration() * rate + 1e-9)) + 1;
    if (maxFrames >= 0 && maxFrames < count)
    {
      count = maxFrames;
    }
    std::cerr << script << ": " << behavior->GetEffectiveDuration() << " s at " << rate << " fps, "
              << behavior->GetNumberOfChannels() << " channels -> " << out << "\n";
    appkit::FrameRecorder recorder(window, rate);
    recorder.SetFramesFolder(out);
    appkit::ProgressBar progress(count);
    for (int f = 0; f < count; ++f)
    {
      if (!avatar->UpdateTimeStep(f / rate) || !head.Update(avatar->GetOutputDataObject()))
      {
        std::cerr << "\nthe face could not be morphed at t = " << f / rate << "\n";
        return 1;
      }
      window->Render();
      recorder.Capture(f);
      progress.Show(f + 1);
    }
    std::cout << "wrote " << count << " frames, " << csvPath
              << (behavior->HasAudio() ? " and " + out + "/speech.wav" : std::string()) << "\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "PlayScript: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
