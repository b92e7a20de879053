// SPDX-License-Identifier: BSD-3-Clause
// PlayScript: play a behaviour script (docs/behavior.md) on a face with morph targets,
// offscreen, and write PNG frames, the weight track as CSV and (when the script speaks)
// the speech as WAV into an output folder; a progress bar goes to stderr.
//
//   PlayScript [script] [--face face.glb] [--out DIR] [--fps F] [--duration S]
//              [--frames N] [--size W H] [--voice VOICE] [--visemes paper6|oculus15|german16]
//
// Default: Data/scripts/greeting.txt on Data/DefaultFace/default_face.glb into
// ./PlayScript-out. --duration overrides the script's length, --frames renders only the
// first N frames (the CSV and the WAV still cover the whole track). Make a video with
//   ffmpeg -framerate 30 -i DIR/frame_%05d.png -i DIR/speech.wav -shortest out.mp4
//
// The face's targets come from the morph filter in Relative mode (targets add on the
// neutral); the head pose channels (HeadYaw/Pitch/Roll, degrees) turn the actor about a
// pivot in the neck, since the face has no head-pose targets.
#include "vtkBehaviorTimeSource.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDelimitedTextWriter.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointSet.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkWindowToImageFilter.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

namespace
{
double Channel(vtkTable* table, const char* name)
{
  auto* column = vtkDoubleArray::SafeDownCast(table->GetColumnByName(name));
  return column ? column->GetValue(0) : 0.0;
}

void Progress(int done, int total)
{
  const int width = 40;
  const int filled = total > 0 ? done * width / total : width;
  std::cerr << "\r[" << std::string(static_cast<size_t>(filled), '#')
            << std::string(static_cast<size_t>(width - filled), '.') << "] " << done << "/" << total
            << " frames" << std::flush;
  if (done == total)
  {
    std::cerr << "\n";
  }
}
} // namespace

int main(int argc, char* argv[])
{
  std::string script = std::string(MORPHNODE_DATA_DIR) + "/scripts/greeting.txt";
  std::string face = std::string(MORPHNODE_DATA_DIR) + "/DefaultFace/default_face.glb";
  std::string out = "PlayScript-out";
  std::string voice, visemes;
  double fps = 0.0, duration = -1.0;
  int maxFrames = -1, width = 480, height = 480;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        std::cerr << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--face")
    {
      face = next();
    }
    else if (arg == "--out")
    {
      out = next();
    }
    else if (arg == "--fps")
    {
      fps = std::atof(next().c_str());
    }
    else if (arg == "--duration")
    {
      duration = std::atof(next().c_str());
    }
    else if (arg == "--frames")
    {
      maxFrames = std::atoi(next().c_str());
    }
    else if (arg == "--size")
    {
      width = std::atoi(next().c_str());
      height = std::atoi(next().c_str());
    }
    else if (arg == "--voice")
    {
      voice = next();
    }
    else if (arg == "--visemes")
    {
      visemes = next();
    }
    else if (arg == "-h" || arg == "--help")
    {
      std::cout << "PlayScript [script] [--face face.glb] [--out DIR] [--fps F] [--duration S]\n"
                   "           [--frames N] [--size W H] [--voice VOICE] [--visemes SET]\n";
      return 0;
    }
    else if (arg.rfind("--", 0) == 0)
    {
      std::cerr << "unknown option " << arg << "\n";
      return 2;
    }
    else
    {
      script = arg;
    }
  }

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

  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec)
  {
    std::cerr << "cannot create " << out << ": " << ec.message() << "\n";
    return 1;
  }

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

  // The face, animated through time.
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(face.c_str());
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightsConnection(behavior->GetOutputPort(0));
  morph->SetWeightModeToRelative();
  morph->UpdateTimeStep(0.0);
  auto* output = vtkPointSet::SafeDownCast(morph->GetOutputDataObject(0));
  if (!output || output->GetNumberOfPoints() == 0)
  {
    std::cerr << "nothing to show (see the errors above)\n";
    return 1;
  }

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(morph->GetOutputPort());
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.86, 0.72, 0.62);
  actor->GetProperty()->SetSpecular(0.2);
  double bounds[6];
  output->GetBounds(bounds);
  // Pivot of the head pose: in the neck (+Y up, the face looks along +Z).
  actor->SetOrigin(0.5 * (bounds[0] + bounds[1]), bounds[2] + 0.25 * (bounds[3] - bounds[2]),
    0.5 * (bounds[4] + bounds[5]));

  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0.15, 0.16, 0.2);
  renderer->AddActor(actor);
  vtkNew<vtkRenderWindow> window;
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  window->AddRenderer(renderer);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Zoom(1.3);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> png;
  png->SetInputConnection(grab->GetOutputPort());

  const double rate = behavior->GetFrameRate();
  int frames = static_cast<int>(std::floor(behavior->GetEffectiveDuration() * rate + 1e-9)) + 1;
  if (maxFrames >= 0 && maxFrames < frames)
  {
    frames = maxFrames;
  }
  std::cerr << script << ": " << behavior->GetEffectiveDuration() << " s at " << rate << " fps, "
            << behavior->GetNumberOfChannels() << " channels -> " << out << "\n";
  for (int f = 0; f < frames; ++f)
  {
    const double t = f / rate;
    morph->UpdateTimeStep(t);
    auto* weights = vtkTable::SafeDownCast(behavior->GetOutputDataObject(0));
    // Angles as seen from the character: yaw > 0 to its left (about +Y), pitch > 0 up
    // (about -X), roll > 0 tilts the top to its left (about -Z).
    actor->SetOrientation(0.0, 0.0, 0.0);
    actor->RotateY(Channel(weights, "HeadYaw"));
    actor->RotateX(-Channel(weights, "HeadPitch"));
    actor->RotateZ(-Channel(weights, "HeadRoll"));
    renderer->ResetCameraClippingRange();
    window->Render();
    grab->Modified();
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", f);
    png->SetFileName((out + name).c_str());
    png->Write();
    Progress(f + 1, frames);
  }
  std::cout << "wrote " << frames << " frames, " << csvPath
            << (behavior->HasAudio() ? " and " + out + "/speech.wav" : std::string()) << "\n";
  return 0;
}
