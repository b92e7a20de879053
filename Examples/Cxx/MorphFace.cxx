// SPDX-License-Identifier: BSD-3-Clause
// MorphFace: read a face with morph targets, set weights, optionally optimize them, and
// render it (to a window, or offscreen to a PNG), optionally coloured by distance. A glTF
// file is read as a whole scene (every part: skin, mouth, teeth, tongue, eyes, ...; a
// vtkPartitionedDataSetCollection), morphed as one head, and drawn one actor per part in
// the part's own colour (AppKit/HeadActors); an OBJ set is one vtkPolyData.
//
//   MorphFace [face.glb] [--weight NAME=VALUE]... [--mode strict|normalize|relative]
//             [--method none|fixed-maximum|fixed-remaining|adjusted|error-bounded]
//             [--threshold T] [--max-error E] [--color AnimatedRegion|Distance_<target>]
//             [--png out.png] [--size WxH]
//
// Example: MorphFace Data/DefaultFace/default_head.glb --weight O=0.8 --weight BrowsUp=0.5 --png
// o.png
#include "CommandLine.h"
#include "DataPaths.h"
#include "HeadActors.h"
#include "ImageOutput.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"

#include <iostream>
#include <map>
#include <string>

int main(int argc, char* argv[])
{
  namespace appkit = morphnode::appkit;
  std::string face = appkit::DefaultFace(), png, color, mode = "normalize";
  std::map<std::string, double> weights;
  auto method = morphnode::OptimizerPreset::None;
  double threshold = 0.0, maxError = 0.0;
  int width = 600, height = 600;
  CLI::App app("MorphFace: a face with morph targets at the given weights, optionally optimized.",
    "MorphFace");
  app.add_option("face", face, "a face with morph targets (glTF/GLB, OBJ set)")
    ->capture_default_str();
  app.add_option("--weight", weights, "a target's weight, NAME=VALUE (repeatable)")
    ->delimiter('=')
    ->take_all();
  app.add_option("--mode", mode, "weight mode")
    ->check(CLI::IsMember({ "strict", "normalize", "relative" }))
    ->capture_default_str();
  appkit::AddOptimizerPresetOption(app, "--method", method, appkit::OptimizerPresetChoices());
  appkit::AddNumberOption(
    app, "--threshold", threshold, 0.0, 1.0, "th_fix of the threshold methods");
  appkit::AddNumberOption(
    app, "--max-error", maxError, 0.0, 1e30, "error bound of error-bounded, model units");
  app.add_option("--color", color, "colour by AnimatedRegion or Distance_<target>");
  app.add_option("--png", png, "render offscreen to this file instead of a window");
  appkit::AddSizeOption(app, "--size", width, height, "window / image size");
  appkit::ParseCommandLine(app, argc, argv);

  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(face.c_str()); // the whole scene (SetMeshIndex(i): one mesh)
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  for (const auto& [name, weight] : weights)
  {
    morph->SetWeightByName(name.c_str(), weight);
  }
  morph->SetWeightMode(mode == "strict" ? vtkMorphNodeFilter::STRICT
      : mode == "relative"              ? vtkMorphNodeFilter::RELATIVE
                                        : vtkMorphNodeFilter::NORMALIZE);
  morph->SetThreshold(threshold);
  morph->SetMaxVertexError(maxError);
  morph->SetOptimizerPreset(static_cast<int>(method));
  morph->SetGenerateDistanceArrays(!color.empty());
  morph->Update();
  // The input's structure: a composite of parts (weights by name reach every part that has
  // the target), or a vtkPolyData.
  vtkDataObject* output = morph->GetOutputDataObject(0);
  double bounds[6];
  if (!appkit::HeadBounds(output, bounds))
  {
    std::cerr << "nothing to show (see the errors above)\n";
    return 1;
  }
  std::cout << face << ": " << morph->GetNumberOfTargets() << " targets, "
            << morph->GetActiveTargetCount() << " active, error bound " << morph->GetErrorBound()
            << "\n";

  vtkNew<vtkRenderer> renderer;
  appkit::HeadActors head; // one actor per part, in its own colour
  head.Build(output, renderer, nullptr);
  if (!color.empty())
  {
    vtkNew<vtkLookupTable> still2moving; // blue where the face stays still, red where it moves
    still2moving->SetHueRange(0.667, 0.0);
    double range[2];
    if (!head.ColorBy(color, still2moving, range))
    {
      std::cerr << "no point array '" << color << "' (try AnimatedRegion or Distance_<target>)\n";
      return 1;
    }
    vtkNew<vtkScalarBarActor> bar;
    bar->SetLookupTable(still2moving);
    bar->SetTitle(color.c_str());
    bar->SetNumberOfLabels(4);
    bar->SetMaximumWidthInPixels(90);
    renderer->AddActor2D(bar);
  }
  vtkNew<vtkRenderWindow> window;
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  window->AddRenderer(renderer);
  appkit::HeadActors::SetUpView(renderer, bounds);
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
      std::cerr << "MorphFace: " << e.what() << "\n";
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
