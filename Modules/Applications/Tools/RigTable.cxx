// SPDX-License-Identifier: BSD-3-Clause
// The paper's Table 1 (normalized distances dist_norm of the 13 morph targets) on
// MorphNode's default face and on the ICT face with the paper's shapes baked through the
// ARKit rig, side by side with Berner's values. Prints a markdown table (docs/rigs.md).
//
//   RigTable [default_head.glb [ict_face.glb [rig.json]]]
//
// Without arguments: the project's default face, ICT-FaceKit from MORPHNODE_FACEKIT_DIR,
// Data/rigs/arkit.json; a missing ICT face gives an "n/a" column.
#include "CommandLine.h"
#include "DataPaths.h"

#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigBaker.h"
#include "vtkMorphTargetReader.h"

#include "vtkDoubleArray.h"
#include "vtkNew.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace
{
const char* const PaperNames[13] = { "Neutral", "EyesClosed", "BrowsUp", "S", "F", "BrowsFright",
  "BrowsAngry", "L", "E", "A", "MouthSmile", "MouthSad", "O" };
const double PaperValues[13] = { 0, 0.11, 0.12, 0.16, 0.20, 0.31, 0.39, 0.51, 0.62, 0.66, 0.67,
  0.90, 1.0 };

/// dist_norm by target name of the face in `file`, optionally baked through `rig` first.
/// Empty on failure.
std::map<std::string, double> DistNorm(const std::string& file, const std::string& rig)
{
  std::map<std::string, double> result;
  if (!std::ifstream(file))
  {
    return result;
  }
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetMeshIndex(0); // the face mesh as one vtkPolyData
  vtkNew<vtkMorphRigBaker> baker;
  vtkNew<vtkMorphNodeFilter> morph;
  if (rig.empty())
  {
    morph->SetInputConnection(reader->GetOutputPort());
  }
  else
  {
    baker->SetInputConnection(reader->GetOutputPort());
    baker->SetRigFileName(rig.c_str());
    baker->SetShapeSet("paper");
    morph->SetInputConnection(baker->GetOutputPort());
  }
  morph->GenerateDistanceArraysOn();
  morph->Update();
  vtkDoubleArray* dist = morph->GetDistNorm();
  for (int i = 0; dist && i < morph->GetNumberOfTargets() && i < dist->GetNumberOfTuples(); ++i)
  {
    result[morph->GetTargetName(i)] = dist->GetValue(i);
  }
  return result;
}

/// Rank (1 = smallest) of each of the 12 non-neutral shapes; ties share the lower rank.
std::vector<int> Ranks(const std::vector<double>& values)
{
  std::vector<int> ranks(values.size(), 0);
  for (size_t i = 0; i < values.size(); ++i)
  {
    int r = 1;
    for (size_t j = 0; j < values.size(); ++j)
    {
      r += values[j] < values[i];
    }
    ranks[i] = r;
  }
  return ranks;
}

/// Spearman's rank correlation (no tie correction).
double Spearman(const std::vector<int>& a, const std::vector<int>& b)
{
  const double n = static_cast<double>(a.size());
  double d2 = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
  {
    d2 += (a[i] - b[i]) * (a[i] - b[i]);
  }
  return 1.0 - 6.0 * d2 / (n * (n * n - 1.0));
}
} // namespace

int main(int argc, char* argv[])
{
  namespace appkit = morphnode::appkit;
  std::string defaultFace = appkit::DefaultFace();
  std::string ictFace = appkit::FaceKitPath("ict_face11248_sparse53.glb");
  std::string rig = appkit::DataPath("rigs/arkit.json");
  CLI::App app("RigTable: the paper's Table 1 (dist_norm of the 13 targets) on the default face "
               "and on the ICT face through the ARKit rig, as markdown (docs/rigs.md).",
    "RigTable");
  // Defaults shown as the project's paths, not this machine's.
  app.add_option("default-face", defaultFace, "the default face")
    ->default_str("Data/DefaultFace/default_head.glb");
  app.add_option("ict-face", ictFace, "the ICT face (n/a when missing)")
    ->default_str("../shared/data/ict-facekit/ict_face11248_sparse53.glb");
  app.add_option("rig", rig, "the ARKit rig")->default_str("Data/rigs/arkit.json");
  appkit::ParseCommandLine(app, argc, argv);

  const auto ours = DistNorm(defaultFace, "");
  const auto ict = DistNorm(ictFace, rig);
  if (ours.size() != 13)
  {
    std::fprintf(stderr, "RigTable: could not read the 13 targets of %s\n", defaultFace.c_str());
    return 1;
  }
  const bool haveIct = ict.size() == 13;
  if (!haveIct)
  {
    std::fprintf(
      stderr, "RigTable: ICT face not available (%s); its column is n/a\n", ictFace.c_str());
  }

  std::vector<double> paper, face, scan;
  for (int i = 1; i < 13; ++i)
  {
    paper.push_back(PaperValues[i]);
    face.push_back(ours.at(PaperNames[i]));
    scan.push_back(haveIct ? ict.at(PaperNames[i]) : 0.0);
  }
  const auto rPaper = Ranks(paper), rFace = Ranks(face), rScan = Ranks(scan);

  std::printf("| shape | paper | rank | default face | rank | ICT face, ARKit rig | rank |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  std::printf("| Neutral | 0 | | 0 | | %s | |\n", haveIct ? "0" : "n/a");
  for (size_t i = 0; i < paper.size(); ++i)
  {
    std::printf(
      "| %s | %.2f | %d | %.2f | %d |", PaperNames[i + 1], paper[i], rPaper[i], face[i], rFace[i]);
    if (haveIct)
    {
      std::printf(" %.2f | %d |\n", scan[i], rScan[i]);
    }
    else
    {
      std::printf(" n/a | |\n");
    }
  }
  std::printf(
    "\nSpearman rank correlation with the paper: default face %.2f", Spearman(rPaper, rFace));
  if (haveIct)
  {
    std::printf(", ICT face %.2f; between the two faces %.2f", Spearman(rPaper, rScan),
      Spearman(rFace, rScan));
  }
  std::printf(".\n");
  return 0;
}
