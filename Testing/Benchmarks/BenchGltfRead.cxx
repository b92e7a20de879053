// SPDX-License-Identifier: BSD-3-Clause
// Reading the MakeHuman avatar and its three variants (quantized, meshopt, WebP;
// ../shared/data/makehuman-avatar), time and peak memory, by
// - core: morphnode::LoadGltfScene (geometry, targets, materials, images decoded);
// - reader: vtkMorphTargetReader, the whole scene as VTK data (what MorphAvatar reads);
// - importer: VTK 9.1's vtkGLTFImporter into a renderer (the yardstick; it reads neither
//   the quantized nor the meshopt file, and skips WebP images),
// in one run, each (reader, file) in a child process of its own so that the peak resident
// memory (getrusage) is that read's alone; the median of 3 reads' wall time.
//   BenchGltfRead [--smoke] [--markdown FILE]
// (docs/benchmarks.md, docs/materials.md). Nothing timed is asserted.
#include "vtkMorphTargetReader.h"

#include "gltf/GltfScene.h"

#include "vtkGLTFImporter.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <sys/resource.h>
#include <vector>

namespace
{
double ReadOnce(const std::string& reader, const std::string& file)
{
  const auto start = std::chrono::steady_clock::now();
  if (reader == "core")
  {
    const morphnode::GltfScene scene = morphnode::LoadGltfScene(file);
    if (scene.Parts.empty())
    {
      return -1;
    }
  }
  else if (reader == "reader")
  {
    vtkNew<vtkMorphTargetReader> r;
    r->SetFileName(file.c_str());
    r->Update();
  }
  else
  {
    vtkNew<vtkRenderWindow> window;
    window->OffScreenRenderingOn();
    vtkNew<vtkRenderer> renderer;
    window->AddRenderer(renderer);
    vtkNew<vtkGLTFImporter> importer;
    importer->SetFileName(file.c_str());
    importer->SetRenderWindow(window);
    importer->Update();
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
} // namespace

int main(int argc, char** argv)
{
  bool smoke = false;
  std::string markdown;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--child" && i + 2 < argc)
    {
      const std::string reader = argv[i + 1], file = argv[i + 2];
      const int reps = i + 3 < argc ? std::atoi(argv[i + 3]) : 3;
      std::vector<double> times;
      for (int k = 0; k < reps; ++k)
      {
        try
        {
          times.push_back(ReadOnce(reader, file));
        }
        catch (const std::exception& e)
        {
          std::cerr << e.what() << "\n";
          times.push_back(-1);
        }
      }
      std::sort(times.begin(), times.end());
      struct rusage usage;
      getrusage(RUSAGE_SELF, &usage);
      std::printf("%.4f %ld\n", times[times.size() / 2], usage.ru_maxrss);
      return 0;
    }
    smoke = smoke || a == "--smoke";
    if (a == "--markdown" && i + 1 < argc)
    {
      markdown = argv[++i];
    }
  }
  const std::string dir = MORPHNODE_AVATAR_DIR;
  std::vector<std::string> files = { "makehuman_avatar.glb", "makehuman_avatar_quantized.glb",
    "makehuman_avatar_meshopt.glb", "makehuman_avatar_webp.glb" };
  if (!std::filesystem::exists(dir + "/" + files[0]))
  {
    std::cout << "BenchGltfRead: the avatar is missing (" << dir << "); nothing measured\n";
    return 0;
  }
  if (smoke)
  {
    files.resize(1);
  }
  std::string table =
    "| file | bytes | core: s, MB | vtkMorphTargetReader: s, MB | vtkGLTFImporter: s, MB |\n"
    "| --- | ---: | ---: | ---: | ---: |\n";
  for (const std::string& f : files)
  {
    const std::string path = dir + "/" + f;
    table += "| " + f + " | " + std::to_string(std::filesystem::file_size(path)) + " |";
    for (const char* reader : { "core", "reader", "importer" })
    {
      const std::string command = "'" + std::string(argv[0]) + "' --child " + reader + " '" + path +
        "' " + (smoke ? "1" : "3") + " 2>/dev/null";
      FILE* pipe = popen(command.c_str(), "r");
      double seconds = -1;
      long kb = 0;
      if (!pipe || std::fscanf(pipe, "%lf %ld", &seconds, &kb) != 2)
      {
        seconds = -1;
      }
      if (pipe)
      {
        pclose(pipe);
      }
      char cell[64];
      std::snprintf(cell, sizeof(cell), " %.3f, %.0f |", seconds, kb / 1024.0);
      table += seconds < 0 ? std::string(" fails |") : std::string(cell);
    }
    table += "\n";
  }
  std::cout << table;
  if (!markdown.empty())
  {
    std::ofstream(markdown) << table;
  }
  return 0;
}
