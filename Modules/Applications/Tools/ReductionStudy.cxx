// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: scalable avatars. Reduces a face with morph targets to several triangle
// budgets three ways (animation-aware, plain OpenMesh quadric decimation, VTK's
// vtkQuadricDecimation with targets transferred by nearest original vertex), animates every
// result over a weight track and measures its error against the full-resolution animated
// face. Then runs the frame-budget controller over a chain of reduced levels at three
// budgets.
//
//   ReductionStudy [--face face.glb] [--track relative_weights.csv] [--out DIR]
//                  [--budgets 0.5,0.25,0.1] [--weight 1] [--stride 2] [--seconds 20]
//                  [--motion 1] [--boundary 1] [--no-poses]
//
// Without --track, a speech-like track is generated (SyntheticSpeechTrack.cxx) and written
// to DIR/speech_track.csv. Writes DIR/reduction.md (tables), DIR/reduction_errors.csv,
// DIR/reduction_error_vs_budget.png, DIR/reduction_error_over_time.png,
// DIR/controller.csv and DIR/controller_calibration.csv.
//
// The parts: ReductionStudy.h declares them; ReductionFace (the face), SyntheticSpeechTrack,
// ReductionErrors (the reductions and their errors), ReductionPlots, ReductionController.
#include "ReductionStudy.h"

#include "CommandLine.h"
#include "DataPaths.h"

#include "morph/OptimizerQuality.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace reductionstudy
{
void CompareReductions(
  const Options& o, const Face& face, const morphnode::WeightTrack& track, std::ostream& md)
{
  const ReductionMesh& full = face.Mesh;
  const std::string& outDir = o.OutDir;
  const std::vector<double>& budgets = o.Budgets;
  const double weight = o.Weight;
  const size_t stride = o.Stride;
  // Animated region: points some target moves by more than 10 % of the largest motion.
  std::vector<double> region(full.GetNumberOfPoints(), 0.0);
  for (const auto& d : full.PositionDeltas)
  {
    for (size_t p = 0; p < region.size(); ++p)
    {
      region[p] = std::max(region[p],
        std::sqrt(double(d[3 * p]) * d[3 * p] + double(d[3 * p + 1]) * d[3 * p + 1] +
          double(d[3 * p + 2]) * d[3 * p + 2]));
    }
  }
  const double regionCut = 0.1 * *std::max_element(region.begin(), region.end());
  std::vector<bool> animated(region.size());
  size_t animatedCount = 0;
  for (size_t p = 0; p < region.size(); ++p)
  {
    animated[p] = region[p] > regionCut;
    animatedCount += animated[p] ? 1 : 0;
  }

  std::vector<std::string> methods = { "animation-aware (ours)", "OpenMesh quadric",
    "vtkQuadricDecimation + nearest" };
  if (!o.Gltfpack.empty())
  {
    methods.push_back("gltfpack 1.3 -si -noq");
  }
  const LipsAndLids regions = FindLipsAndLids(face);
  std::vector<Errors> all;
  std::map<double, size_t> keptAnimated[4];
  for (double b : budgets)
  {
    const size_t triangles = static_cast<size_t>(std::round(b * full.GetNumberOfTriangles()));
    std::vector<Reduced> reduced = { ReduceOpenMesh(full, triangles, weight, o.Base),
      ReduceOpenMesh(full, triangles, 0.0, o.Base), ReduceVTK(full, triangles) };
    if (!o.Gltfpack.empty())
    {
      reduced.push_back(ReduceGltfpack(face, b, o.Gltfpack, outDir + "/gltfpack"));
    }
    for (size_t m = 0; m < reduced.size(); ++m)
    {
      const auto t0 = std::chrono::steady_clock::now();
      all.push_back(Measure(methods[m], b, full, reduced[m], track, stride, animated, &regions));
      size_t kept = 0;
      for (uint32_t s : reduced[m].Source)
      {
        kept += animated[s] ? 1 : 0;
      }
      keptAnimated[m][b] = kept;
      std::cerr << methods[m] << " at " << b << ": corr " << Mm(all.back().CorrRms) << " mm, anim "
                << Mm(all.back().AnimRms) << " mm, motion " << Mm(all.back().MotionRms)
                << " / region " << Mm(all.back().MotionRegionRms) << " / max "
                << Mm(all.back().MotionMax) << " / p95 " << Mm(all.back().MotionP95) << " / p99 "
                << Mm(all.back().MotionP99) << " mm, lips p95 " << Mm(all.back().LipsP95)
                << ", lids p95 " << Mm(all.back().LidsP95) << " mm, static "
                << Mm(all.back().StaticRms) << " mm ("
                << Seconds(std::chrono::steady_clock::now() - t0) << " s)\n";
    }
  }

  // Tables.
  md << "Face: " << full.GetNumberOfPoints() << " points, " << full.GetNumberOfTriangles()
     << " triangles, " << full.GetNumberOfTargets()
     << " targets. Track: " << track.GetNumberOfFrames() << " frames at " << track.GetFrameRate()
     << " fps, every " << stride << ". frame measured. AnimationWeight " << weight
     << ". Animated region: " << animatedCount << " points (some target moves them > "
     << Mm(regionCut, 2) << " mm). Distances in mm.\n\n";
  md << "| triangles kept | method | triangles | points | points kept in animated region "
        "| static RMS | static max | motion error p95 | motion error p99 | motion error RMS "
        "| motion error RMS, animated region | animated surface distance RMS | animated surface "
        "distance max "
        "| correspondence RMS | kept-vertex RMS |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::ostringstream lipsTable;
  lipsTable << "\nThe lips (" << std::count(regions.Lips.begin(), regions.Lips.end(), true)
            << " points) and lids (" << std::count(regions.Lids.begin(), regions.Lids.end(), true)
            << " points) alone, motion error in mm:\n\n| triangles kept | method | lips p95 | lips "
               "p99 | lids p95 | lids p99 |\n"
               "|---|---|---|---|---|---|\n";
  std::ofstream csv(outDir + "/reduction_errors.csv");
  csv << "budget,method,triangles,points,kept_animated,static_rms_mm,static_max_mm,anim_rms_mm,"
         "anim_max_mm,"
         "anim_region_rms_mm,corr_rms_mm,corr_max_mm,corr_region_rms_mm,kept_rms_mm,motion_p95_mm,"
         "motion_p99_mm,"
         "motion_rms_mm,motion_region_rms_mm,motion_max_mm,lips_p95_mm,lips_p99_mm,lids_p95_mm,"
         "lids_p99_mm\n";
  for (const auto& e : all)
  {
    const int m =
      static_cast<int>(std::find(methods.begin(), methods.end(), e.Method) - methods.begin());
    md << "| " << 100.0 * e.Budget << " % | " << e.Method << " | " << e.Triangles << " | "
       << e.Points << " | " << keptAnimated[m][e.Budget] << " | " << Mm(e.StaticRms) << " | "
       << Mm(e.StaticMax) << " | " << Mm(e.MotionP95) << " | " << Mm(e.MotionP99) << " | "
       << Mm(e.MotionRms) << " | " << Mm(e.MotionRegionRms) << " | " << Mm(e.AnimRms) << " | "
       << Mm(e.AnimMax) << " | " << Mm(e.CorrRms) << " | " << Mm(e.KeptRms) << " |\n";
    lipsTable << "| " << 100.0 * e.Budget << " % | " << e.Method << " | " << Mm(e.LipsP95) << " | "
              << Mm(e.LipsP99) << " | " << Mm(e.LidsP95) << " | " << Mm(e.LidsP99) << " |\n";
    csv << e.Budget << "," << e.Method << "," << e.Triangles << "," << e.Points << ","
        << keptAnimated[m][e.Budget] << "," << Mm(e.StaticRms, 5) << "," << Mm(e.StaticMax, 5)
        << "," << Mm(e.AnimRms, 5) << "," << Mm(e.AnimMax, 5) << "," << Mm(e.AnimRegionRms, 5)
        << "," << Mm(e.CorrRms, 5) << "," << Mm(e.CorrMax, 5) << "," << Mm(e.CorrRegionRms, 5)
        << "," << Mm(e.KeptRms, 5) << "," << Mm(e.MotionP95, 5) << "," << Mm(e.MotionP99, 5) << ","
        << Mm(e.MotionRms, 5) << "," << Mm(e.MotionRegionRms, 5) << "," << Mm(e.MotionMax, 5) << ","
        << Mm(e.LipsP95, 5) << "," << Mm(e.LipsP99, 5) << "," << Mm(e.LidsP95, 5) << ","
        << Mm(e.LidsP99, 5) << "\n";
  }
  md << lipsTable.str() << "\n";
  PlotVersusBudget(all, methods, budgets, outDir + "/reduction_error_vs_budget.png");
  PlotOverTime(all, methods, *std::min_element(budgets.begin(), budgets.end()), track, stride,
    outDir + "/reduction_error_over_time.png");
}
} // namespace reductionstudy

namespace
{
namespace appkit = morphnode::appkit;
using namespace reductionstudy;

Options ParseOptions(int argc, char* argv[])
{
  Options o;
  o.FacePath = appkit::FaceKitPath("ict_face11248_sparse53.glb");
  CLI::App app("ReductionStudy: animation-aware reduction against plain quadric decimation over a "
               "weight track, and the frame-budget controller (docs/reduction.md).",
    "ReductionStudy");
  app.add_option("--face", o.FacePath, "a face with morph targets (glTF/GLB)")
    ->check(CLI::ExistingFile)
    ->capture_default_str();
  app
    .add_option(
      "--track", o.TrackPath, "relative target weights, CSV (default: a synthetic speech track)")
    ->check(CLI::ExistingFile);
  app.add_option("--out", o.OutDir, "output folder")->capture_default_str();
  appkit::AddNumberListOption(
    app, "--budgets", o.Budgets, 1e-6, 1.0, "fractions of the triangles kept");
  appkit::AddNumberOption(
    app, "--weight", o.Weight, 0.0, 1e6, "AnimationWeight of the animation-aware reduction");
  app.add_option("--stride", o.Stride, "measure every N-th frame")
    ->check(CLI::Range(1, 1000000))
    ->capture_default_str();
  appkit::AddNumberOption(
    app, "--seconds", o.Seconds, 1.0, 3600.0, "length of the synthetic track");
  appkit::AddNumberOption(
    app, "--motion", o.Base.MotionWeight, 0.0, 1e6, "MotionWeight of the reductions");
  appkit::AddNumberOption(
    app, "--boundary", o.Base.BoundaryWeight, 0.0, 1e6, "BoundaryWeight of the reductions");
  app
    .add_option("--gltfpack", o.Gltfpack,
      "gltfpack executable (npm 1.3, .ci/install-npm-tools.sh) as a "
      "fourth method; empty: left out")
    ->capture_default_str();
  app.add_flag_callback(
    "--no-controller", [&o]() { o.Controller = false; }, "skip the frame-budget part");
  app.add_flag_callback(
    "--no-poses", [&o]() { o.Base.PoseQuadrics = false; }, "no pose quadrics");
  appkit::ParseCommandLine(app, argc, argv);
  return o;
}

/// Relative weights, one channel per target in the face's order: the given track or a
/// synthetic one (written to DIR/speech_track.csv).
morphnode::WeightTrack LoadTrack(const Options& o, const Face& face)
{
  morphnode::WeightTrack track;
  if (!o.TrackPath.empty())
  {
    std::ifstream in(o.TrackPath);
    const morphnode::WeightTrack given = morphnode::WeightTrack::ReadCsv(in);
    const morphnode::WeightTrack absolute = morphnode::ToAbsoluteWeights(given, face.Names);
    track = morphnode::WeightTrack(
      std::vector<std::string>(face.Names.begin() + 1, face.Names.end()), absolute.GetFrameRate());
    for (size_t f = 0; f < absolute.GetNumberOfFrames(); ++f)
    {
      track.AppendFrame(absolute.GetFrame(f) + 1);
    }
  }
  else
  {
    track = MakeSyntheticSpeechTrack(face.Names, o.Seconds, 7);
    std::ofstream out(o.OutDir + "/speech_track.csv");
    track.WriteCsv(out);
  }
  return track;
}
} // namespace

int main(int argc, char* argv[])
{
  const Options o = ParseOptions(argc, argv);
  try
  {
    std::filesystem::create_directories(o.OutDir);
    const Face face = LoadFace(o.FacePath);
    const ReductionMesh& full = face.Mesh;
    std::cerr << "face: " << full.GetNumberOfPoints() << " points, " << full.GetNumberOfTriangles()
              << " triangles, " << full.GetNumberOfTargets() << " targets\n";
    const morphnode::WeightTrack track = LoadTrack(o, face);
    std::cerr << "track: " << track.GetNumberOfFrames() << " frames at " << track.GetFrameRate()
              << " fps\n";
    std::ofstream md(o.OutDir + "/reduction.md");
    CompareReductions(o, face, track, md);
    if (o.Controller)
    {
      RunController(o, face, track, md);
    }
    std::cerr << "wrote " << o.OutDir << "/reduction.md\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "ReductionStudy: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
