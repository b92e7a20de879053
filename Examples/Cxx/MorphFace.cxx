// SPDX-License-Identifier: BSD-3-Clause
// MorphFace: read a face with morph targets, set weights, optionally optimize them, and
// render it (to a window, or offscreen to a PNG), optionally coloured by distance.
//
//   MorphFace [face.glb] [--weight NAME=VALUE]... [--mode strict|normalize|relative]
//             [--threshold T] [--adjust] [--color AnimatedRegion|Distance_<target>]
//             [--png out.png] [--size W H]
//
// Example: MorphFace Data/DefaultFace/default_face.glb --weight O=0.8 --weight BrowsUp=0.5 --png o.png
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkWindowToImageFilter.h"

#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  std::string face = std::string(MORPHNODE_DATA_DIR) + "/DefaultFace/default_face.glb";
  std::string png, color, mode = "normalize";
  int width = 600, height = 600;
  vtkNew<vtkMorphNodeFilter> morph;
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
    if (arg == "--weight")
    {
      const std::string w = next();
      const auto eq = w.find('=');
      if (eq == std::string::npos)
      {
        std::cerr << "--weight expects NAME=VALUE, got " << w << "\n";
        return 2;
      }
      morph->SetWeightByName(w.substr(0, eq).c_str(), std::atof(w.c_str() + eq + 1));
    }
    else if (arg == "--mode")
    {
      mode = next();
    }
    else if (arg == "--threshold")
    {
      morph->SetThreshold(std::atof(next().c_str()));
    }
    else if (arg == "--adjust")
    {
      morph->AdjustThresholdOn();
    }
    else if (arg == "--color")
    {
      color = next();
    }
    else if (arg == "--png")
    {
      png = next();
    }
    else if (arg == "--size")
    {
      width = std::atoi(next().c_str());
      height = std::atoi(next().c_str());
    }
    else if (arg.rfind("--", 0) == 0)
    {
      std::cerr << "unknown option " << arg << "\n";
      return 2;
    }
    else
    {
      face = arg;
    }
  }
  if (mode == "strict")
  {
    morph->SetWeightModeToStrict();
  }
  else if (mode == "relative")
  {
    morph->SetWeightModeToRelative();
  }
  else if (mode != "normalize")
  {
    std::cerr << "unknown mode " << mode << "\n";
    return 2;
  }

  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(face.c_str());
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetGenerateDistanceArrays(!color.empty());
  morph->Update();
  auto* output = vtkPolyData::SafeDownCast(morph->GetOutput());
  if (!output || output->GetNumberOfPoints() == 0)
  {
    std::cerr << "nothing to show (see the errors above)\n";
    return 1;
  }
  std::cout << face << ": " << morph->GetNumberOfTargets() << " targets, "
            << morph->GetActiveTargetCount() << " active, error bound " << morph->GetErrorBound() << "\n";

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(output);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0.15, 0.16, 0.2);
  renderer->AddActor(actor);
  if (!color.empty())
  {
    vtkDataArray* scalars = output->GetPointData()->GetArray(color.c_str());
    if (!scalars)
    {
      std::cerr << "no point array '" << color << "' (try AnimatedRegion or Distance_<target>)\n";
      return 1;
    }
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray(color.c_str());
    mapper->SetScalarRange(scalars->GetRange());
    mapper->ScalarVisibilityOn();
    vtkNew<vtkLookupTable> still2moving; // blue where the face stays still, red where it moves
    still2moving->SetHueRange(0.667, 0.0);
    mapper->SetLookupTable(still2moving);
    vtkNew<vtkScalarBarActor> bar;
    bar->SetLookupTable(mapper->GetLookupTable());
    bar->SetTitle(color.c_str());
    bar->SetNumberOfLabels(4);
    bar->SetMaximumWidthInPixels(90);
    renderer->AddActor2D(bar);
  }
  else
  {
    actor->GetProperty()->SetColor(0.86, 0.72, 0.62);
    actor->GetProperty()->SetSpecular(0.2);
  }
  vtkNew<vtkRenderWindow> window;
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  window->AddRenderer(renderer);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Zoom(1.4);
  renderer->ResetCameraClippingRange();
  if (!png.empty())
  {
    window->OffScreenRenderingOn();
    window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(png.c_str());
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    std::cout << "wrote " << png << "\n";
    return 0;
  }
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(window);
  window->Render();
  interactor->Start();
  return 0;
}
