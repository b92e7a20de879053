// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Transfer.h
/// @brief Bring your own head: a source face's named morph targets transferred onto a bare
/// target mesh of any topology, scale and pose (docs/transfer.md).
///
/// The steps, as the literature does them:
/// 1. **Similarity alignment** (rotation, uniform scale, translation; Umeyama 1991 through
///    Eigen::umeyama): from landmarks when the target has a landmark file (the source's
///    landmarks are found on it automatically from its own targets: the lids' centres from
///    eyeBlink_L/R, the mouth corners and lip centres from jawOpen's mouth opening, the chin,
///    the nose tip), else from the principal axes (the four proper sign choices, the one ICP
///    fits best); then refined by a trimmed similarity ICP over the source's face region.
/// 2. **Non-rigid registration** of the source onto the target: non-rigid ICP with annealed
///    stiffness after Amberg, Romdhani and Vetter (CVPR 2007), with the per-vertex affine
///    transform reduced to a per-vertex translation (stiffness on the edges' differences).
///    Why: after step 1 what is left is small and smooth, and the translation form needs one
///    n x n matrix shared by x, y and z (Amberg's needs 4n x 4n); correspondences on the
///    target's border, facing away or far off are dropped, as Amberg does.
/// 3. **Deformation transfer** (Sumner and Popovic, SIGGRAPH 2004) in its Poisson form (Botsch
///    et al. 2006): each target's deformation gradients on the aligned source, applied to the
///    registered source's triangles, solved for the points; the matrix (the registered
///    source's cotangent Laplacian) is factored once (Eigen's SimplicialLDLT), each target is
///    three back-substitutions.
/// 4. **Seam-aware resampling** onto the target's own vertices: each target point takes the
///    deltas at its closest point on the registered source. Around the mouth and the lids
///    the upper and lower side never swap: the source's sides come from its own targets
///    (jawOpen moves the lower lip, eyeBlink the upper lid), the target's from its own mouth
///    and eye openings, and a target point only lands on its own side. A target whose mouth
///    is closed (no opening near the source's) is refused: cut the lips apart first.
/// Parts of the source that move rigidly in every target (eyes, teeth) move rigidly on the
/// target too (the best rigid fit, Kabsch through Eigen::umeyama).
///
/// Nothing here depends on VTK.

#include "morph/MorphMesh.h"
#include "transfer/TransferGeometry.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace morphnode
{
/// A named point on the target (in the target's units and frame).
struct TransferLandmark
{
  std::string Name;
  glm::dvec3 Position{ 0.0 };
};

/// The names of the landmarks found on the source (and accepted in a landmark file).
const std::vector<std::string>& TransferLandmarkNames();

/// Parses a landmark file: one "name x y z" per line, '#' starts a comment. Throws
/// InputError naming `sourceName` and the line for anything else (unknown names, duplicates,
/// numbers that are not finite).
std::vector<TransferLandmark> ParseTransferLandmarks(
  const std::string& text, const std::string& sourceName = "landmarks");

/// The source face: points, triangles and dense deltas per non-neutral target.
struct TransferSource
{
  TransferSurface Surface;
  std::vector<std::string> TargetNames; ///< without the neutral
  std::vector<std::vector<glm::dvec3>> Deltas;
};

/// The source from a morph mesh (its Position attribute and triangles). Throws InputError.
TransferSource MakeTransferSource(const MorphMesh& mesh);

enum class TransferMethod
{
  NearestVertex,      ///< the delta of the nearest registered-source vertex
  Barycentric,        ///< the source's deltas interpolated at the closest point
  DeformationTransfer ///< deformation transfer on the registered source, interpolated
};

struct TransferOptions
{
  /// Landmarks on the target (a subset of TransferLandmarkNames(), at least 3); empty:
  /// automatic alignment.
  std::vector<TransferLandmark> TargetLandmarks;
  TransferMethod Method = TransferMethod::DeformationTransfer;
  /// Also fill NearestDeltas and BarycentricDeltas (the study's yardsticks).
  bool ComputeAllMethods = false;
  /// Non-rigid ICP: stiffness per stage (annealed, high to low) and iterations per stage.
  /// Empty: no registration (the aligned source is used as is).
  std::vector<double> Stiffness{ 50.0, 20.0, 8.0, 3.0, 1.0, 0.5 };
  int IterationsPerStage = 4;
  /// The largest accepted registration residual: the 95th percentile of the distances of
  /// the source's face region to the target, as a fraction of the eye distance. Above it
  /// the target is refused as "not a face like the source".
  double MaxResidual = 0.1;
  /// Refuse a target without a mouth opening near the source's mouth.
  bool RequireMouthOpening = true;
  /// The targets that find the mouth (moves the lower lip) and the lids (move the upper lid).
  std::string MouthTarget = "jawOpen";
  std::vector<std::string> LidTargets{ "eyeBlink_L", "eyeBlink_R" };
};

/// Seam labels of points: 0 none; +1/-1 upper/lower lip; +2/-2 upper/lower lid of the first
/// lid target, +3/-3 of the second.
using TransferSide = int8_t;

struct TransferResult
{
  std::vector<std::string> TargetNames; ///< the source's, without the neutral
  /// Per target: 3 floats per target point (relative, glTF-style), by Method.
  std::vector<std::vector<float>> Deltas;
  std::vector<std::vector<float>> NearestDeltas;     ///< when ComputeAllMethods
  std::vector<std::vector<float>> BarycentricDeltas; ///< when ComputeAllMethods
  /// Per target point in [0, 1]: how close and alike (normal) the registered source is.
  std::vector<float> Confidence;

  /// The similarity from the source onto the target: q = Scale * Rotation * p + Translation.
  double Scale = 1.0;
  glm::dmat3 Rotation{ 1.0 };
  glm::dvec3 Translation{ 0.0 };
  /// The source's landmarks after alignment and after registration (target frame).
  std::vector<TransferLandmark> SourceLandmarks;
  /// The registered source (source topology, target frame).
  std::vector<glm::dvec3> Registered;
  /// Distances of the source's animated region (points a target moves by at least 20 % of
  /// its largest motion) to the target, before and after registration.
  double AlignedResidualP95 = 0.0;
  double ResidualMean = 0.0;
  double ResidualP95 = 0.0;
  double EyeDistance = 0.0; ///< of the aligned source, target units
  /// Seam side per target point and per source point.
  std::vector<TransferSide> TargetSide;
  std::vector<TransferSide> SourceSide;
  /// The correspondence: per target point, the registered source's triangle (-1: none)
  /// and barycentric coordinates of its closest point.
  std::vector<int> HitTriangle;
  std::vector<glm::dvec3> HitBarycentric;
  /// Target points that moved rigidly (a part fitted to a rigid source part).
  std::vector<bool> Rigid;
  std::vector<std::string> Warnings;
  double AlignSeconds = 0, RegisterSeconds = 0, TransferSeconds = 0, ResampleSeconds = 0;
};

/// Transfers every target of `source` onto `target`. Throws InputError for bad input (no
/// triangles, non-manifold, a source that is not a face with the mouth and lid targets, a
/// closed mouth, a residual above the limit).
TransferResult TransferTargets(
  const TransferSource& source, const TransferSurface& target, const TransferOptions& options = {});
} // namespace morphnode
