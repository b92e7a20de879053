// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ReductionStudy.h
/// @brief ReductionStudy's parts (docs/reduction.md): the face in flat arrays, a synthetic
/// speech track, the three reductions and their errors over the track, the plots, and the
/// frame-budget controller over a chain of reduced levels.

#include "budget/FrameBudgetController.h"
#include "morph/MorphAttribute.h"
#include "morph/MorphMesh.h"
#include "reduction/AnimationAwareReduction.h"
#include "track/WeightTrack.h"

#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <iomanip>
#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace reductionstudy
{
struct Options
{
  std::string FacePath;  ///< default: the ICT face
  std::string TrackPath; ///< relative weights (CSV); empty: a synthetic speech track
  std::string OutDir = "reduction-study";
  std::vector<double> Budgets = { 0.5, 0.25, 0.1 }; ///< fractions of the triangles
  double Weight = morphnode::ReductionSettings().AnimationWeight;
  size_t Stride = 2;     ///< every Stride-th frame is measured
  double Seconds = 20.0; ///< of the synthetic track
  /// MotionWeight, BoundaryWeight and PoseQuadrics of the compared reductions.
  morphnode::ReductionSettings Base;
  /// gltfpack (npm 1.3) as a fourth method; empty: left out.
  std::string Gltfpack;
  /// Run the frame-budget controller part (ReductionController) too.
  bool Controller = true;
};

// --- the face ------------------------------------------------------------------------------

/// The face in flat arrays, as the study measures it.
struct ReductionMesh
{
  std::vector<float> Positions;    ///< neutral, NumberOfPoints * 3
  std::vector<uint32_t> Triangles; ///< NumberOfTriangles * 3 point ids
  /// Position deltas, one array of NumberOfPoints * 3 per target (neutral excluded).
  std::vector<std::vector<float>> PositionDeltas;

  size_t GetNumberOfPoints() const { return this->Positions.size() / 3; }
  size_t GetNumberOfTriangles() const { return this->Triangles.size() / 3; }
  size_t GetNumberOfTargets() const { return this->PositionDeltas.size(); }
};

morphnode::MorphMesh ToMorphMesh(const ReductionMesh& flat);
ReductionMesh FromMorphMesh(const morphnode::MorphMesh& mesh);

struct Face
{
  ReductionMesh Mesh;
  std::vector<std::string> Names; // neutral first
};

Face LoadFace(const std::string& path);

vtkSmartPointer<vtkPolyData> ToPolyData(
  const float* positions, size_t np, const std::vector<uint32_t>& tris);

// --- the weight track ----------------------------------------------------------------------

/// A plausible 30 fps speech track over ARKit-named targets (relative weights), made
/// without any recorded data: visemes (Meta/Oculus set, as ARKit blends) every 70-170 ms
/// with pauses, blended by Cohen-Massaro-style dominance functions (coarticulation);
/// blinks (Poisson, ~17/min, 100 ms closing, 150 ms opening); brow raises every few
/// seconds; small gaze shifts; a slow smile. Deterministic (seed).
morphnode::WeightTrack MakeSyntheticSpeechTrack(
  const std::vector<std::string>& names, double seconds, unsigned seed);

// --- reductions and their errors -------------------------------------------------------------

struct Reduced
{
  ReductionMesh Mesh;
  /// Reduced point -> nearest original point (exact origin for the halfedge collapses).
  std::vector<uint32_t> Source;
  bool ExactPoints = true;
};

/// The animation-aware reduction (weight > 0) or plain quadric decimation (weight 0) of
/// OpenMesh, with `base`'s motion and boundary weights and pose quadrics.
Reduced ReduceOpenMesh(const ReductionMesh& mesh, size_t triangles, double weight,
  const morphnode::ReductionSettings& base);
/// VTK's quadric decimation of the neutral; targets by the nearest original vertex.
Reduced ReduceVTK(const ReductionMesh& mesh, size_t triangles);

/// The mesh at relative weights `relative` (one per target).
void Animate(const ReductionMesh& mesh, const double* relative, std::vector<float>& out);

/// Where every full-resolution point sits on a reduced mesh in the neutral: a triangle and
/// barycentric weights (the closest point). Animating the reduced mesh carries that point
/// along; its distance from the full-resolution point is the correspondence error, which,
/// unlike the surface distance, also sees motion along the surface.
struct Correspondence
{
  std::vector<std::array<uint32_t, 3>> Corners;
  std::vector<std::array<float, 3>> Weights;
};

Correspondence Correspond(const ReductionMesh& full, const ReductionMesh& reduced);
/// RMS distance of the full-resolution points carried by `corr` on `shown` from `full`.
double CorrespondenceRms(
  const Correspondence& corr, const std::vector<float>& shown, const std::vector<float>& full);

struct Errors
{
  std::string Method;
  double Budget = 0.0;
  size_t Triangles = 0, Points = 0;
  double StaticRms = 0, StaticMax = 0;
  double AnimRms = 0, AnimMax = 0, AnimRegionRms = 0;
  double CorrRms = 0, CorrMax = 0, CorrRegionRms = 0;
  double KeptRms = 0;
  double MotionRms = 0, MotionMax = 0, MotionRegionRms = 0, MotionP95 = 0, MotionP99 = 0;
  /// The motion error's percentiles over the lips' and the lids' points (LipsAndLids).
  double LipsP95 = 0, LipsP99 = 0, LidsP95 = 0, LidsP99 = 0;
  std::vector<double> PerFrameMotionRms; // 95th percentile over points, per frame
  std::vector<double> PerFrameAnimRms;
  std::vector<double> PerFrameCorrRms;
};

/// The lips' and the lids' points: those that the lip targets (mouthRoll*, mouthFunnel,
/// mouthPucker) or the blinks (eyeBlink*) move by more than a quarter of the target's reach.
struct LipsAndLids
{
  std::vector<bool> Lips, Lids;
};
LipsAndLids FindLipsAndLids(const Face& face);

/// The errors of one reduction over the track (every `stride`-th frame).
Errors Measure(const std::string& method, double budget, const ReductionMesh& full,
  const Reduced& r, const morphnode::WeightTrack& track, size_t stride,
  const std::vector<bool>& animatedRegion, const LipsAndLids* regions = nullptr);

/// gltfpack's simplification (`-si ratio -noq`) of the face, written to and read from
/// workDir; points matched to the face's by position. Throws InputError when gltfpack fails.
Reduced ReduceGltfpack(
  const Face& face, double ratio, const std::string& gltfpack, const std::string& workDir);

// --- plots ---------------------------------------------------------------------------------

void PlotVersusBudget(const std::vector<Errors>& all, const std::vector<std::string>& methods,
  const std::vector<double>& budgets, const std::string& file);
void PlotOverTime(const std::vector<Errors>& all, const std::vector<std::string>& methods,
  double budget, const morphnode::WeightTrack& track, size_t stride, const std::string& file);

// --- the two parts of the study ------------------------------------------------------------

/// The three reductions at every budget over the track: the first table of reduction.md
/// (to `md`), reduction_errors.csv and the two plots.
void CompareReductions(
  const Options& o, const Face& face, const morphnode::WeightTrack& track, std::ostream& md);

/// The frame-budget controller over a chain of animation-aware levels at three frame
/// budgets: its tables (to `md`), controller.csv and controller_calibration.csv.
void RunController(
  const Options& o, const Face& face, const morphnode::WeightTrack& track, std::ostream& md);

// --- formatting ------------------------------------------------------------------------------

inline double Seconds(std::chrono::steady_clock::duration d)
{
  return std::chrono::duration<double>(d).count();
}

inline std::string Mm(double metres, int precision = 3)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << 1000.0 * metres;
  return s.str();
}

inline std::string Us(double seconds)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << 1e6 * seconds;
  return s.str();
}
} // namespace reductionstudy
