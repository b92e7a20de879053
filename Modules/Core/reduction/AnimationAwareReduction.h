// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AnimationAwareReduction.h
/// @brief Mesh reduction of a morphable face that reduces highly animated regions less than
/// the others (the paper's future work, section 6), with every morph target carried along.
///
/// The reduction is a sequence of halfedge collapses (OpenMesh's Decimater): a collapse
/// v0 -> v1 removes v0 and keeps v1 where it is. The reduced mesh's vertices are therefore
/// a subset of the original ones, and a kept vertex keeps its neutral position and its
/// deltas for every target and every attribute unchanged: carrying the targets over is an
/// exact gather through OriginalPointIds, with no resampling.
///
/// Cost of a collapse v0 -> v1 (p1 the position of v1, d_k(v) the delta of target k):
///
///     cost = Q_n(p1) + AnimationWeight * (max_k Q_k(p1 + d_k(v1)) + MotionWeight * A * e^2)
///
/// - Q_n: the Garland-Heckbert quadric of the neutral, area weighted, as OpenMesh's
///   ModQuadricT computes it (with AnimationWeight 0, ModQuadricT itself is used).
/// - Q_k: the same quadric built on the faces of target pose k (neutral + delta k), plus
///   boundary-contour planes (lips, eyelids) in that pose weighted by BoundaryWeight, so
///   that the reduced mesh approximates every target's shape, not only the neutral's
///   (PoseQuadrics). The worst pose counts: a target that folds the eyelid must not be
///   averaged away by the 50 targets that leave the eyelid alone.
/// - e: a bound on how far the motion of any vertex merged into v1 differs from the motion
///   of v1, over all targets: e(v1) <- max(e(v1), e(v0) + max_k |d_k(v0) - d_k(v1)|)
///   (triangle inequality). It is 0 where the face does not move and grows with the
///   per-vertex motion differences, so collapses in animated regions (mouth, eyes, brows)
///   become expensive. It also covers motion along the surface, which no quadric sees.
///   A is the face area the two vertices stand for, so that the term has the quadric's
///   units (area times squared distance).
///
/// Scale: on a face in metres, the motion term of an animated vertex is about 100 times its
/// neutral quadric error (motions of millimetres against deviations of tenths of a
/// millimetre), hence the default AnimationWeight of 0.01; measured on the ICT face in
/// docs/reduction.md (larger weights starve the static head and raise the static error).
///
/// A binary module refuses collapses that flip a neutral face normal by more than
/// MaxNormalDeviation degrees, in both the plain and the animation-aware reduction.

#include "morph/MorphMesh.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
struct ReductionSettings
{
  /// Stop at this many triangles (0: use TargetPoints).
  size_t TargetTriangles = 0;
  /// Stop at this many points (used when TargetTriangles is 0).
  size_t TargetPoints = 0;
  /// Weight of the animation terms; 0 = plain quadric decimation (OpenMesh's ModQuadricT).
  /// The default is the one measured best on the ICT face (docs/reduction.md).
  double AnimationWeight = 0.01;
  /// Add the quadrics of every target pose (see the file comment).
  bool PoseQuadrics = true;
  /// Factor of the motion-bound term A * e^2 inside the animation cost.
  double MotionWeight = 1.0;
  /// Weight of the boundary-contour planes in the pose quadrics (times squared edge length).
  double BoundaryWeight = 1.0;
  /// Largest change of a neutral face normal a collapse may cause, degrees (0 = no check).
  double MaxNormalDeviation = 60.0;
  /// Leave out the triangles OpenMesh cannot add (they would make the mesh non-manifold)
  /// instead of refusing the mesh; counted in ReductionResult::SkippedNonManifoldTriangles.
  bool SkipNonManifold = false;
  /// Storage of the reduced mesh's deltas (MorphAttribute::AddRelativeTarget); no effect on
  /// any value.
  double SparseCoverage = MorphMesh::DefaultSparseCoverage;
};

struct ReductionResult
{
  /// The reduced mesh: its triangles, the input's target names and every attribute of the
  /// input (neutral and deltas) gathered through OriginalPointIds, in its own type. Colour
  /// clamp ranges are not carried over.
  MorphMesh Mesh;
  /// Reduced point -> original point (the reduced point has its position and deltas).
  std::vector<uint32_t> OriginalPointIds;
  /// Original point -> reduced point it was collapsed into (itself when kept): Hoppe's
  /// geomorph target, and a nearest-kept-vertex map for any per-point data.
  std::vector<uint32_t> Representatives;
  /// Reduced triangle -> the input triangle it is (index into the input's triangles / 3): a
  /// halfedge collapse removes the two triangles of the collapsed edge and moves a corner of
  /// the others, so every kept triangle is one of the input's. For carrying per-triangle
  /// data (cell data) onto the reduced mesh.
  std::vector<uint32_t> OriginalTriangleIds;
  /// Degenerate input triangles (a repeated point id) that were dropped.
  size_t DroppedDegenerateTriangles = 0;
  /// Non-manifold triangles left out (ReductionSettings::SkipNonManifold).
  size_t SkippedNonManifoldTriangles = 0;
};

/// Reduces `mesh` to the settings' budget. The collapses are chosen on the mesh's triangles
/// and its (first) Position attribute, 3 components of float or double, with its targets'
/// deltas; every attribute is carried over.
/// Throws InputError for: no points, no Position attribute of 3 components, no triangles,
/// an invalid mesh (MorphMesh::Validate: point ids out of range, an attribute with the wrong
/// number of targets), non-finite neutral positions, a budget of 0 or not below the mesh's
/// size, a negative or non-finite weight, and non-manifold input OpenMesh cannot represent.
ReductionResult ReduceAnimationAware(const MorphMesh& mesh, const ReductionSettings& settings);

/// Per-point values of any attribute (`components` per point) gathered through
/// OriginalPointIds: the reduced mesh's copy of an attribute or of a target's deltas.
/// Throws InputError when `values` does not hold numPoints * components values or an id is
/// out of range.
template <typename T>
std::vector<T> GatherPoints(const std::vector<T>& values, int components, size_t numPoints,
  const std::vector<uint32_t>& originalPointIds);

/// The mesh of the points `ids` of `input` (in that order; a subset or a permutation): every
/// attribute's neutral and deltas gathered, the target names kept, `triangles` (in the new
/// ids) as its topology. Deltas stored by `sparseCoverage` (MorphAttribute::AddRelativeTarget).
/// Throws InputError for an id out of range.
MorphMesh GatherMorphMesh(const MorphMesh& input, const std::vector<uint32_t>& ids,
  std::vector<uint32_t> triangles, double sparseCoverage = MorphMesh::DefaultSparseCoverage);

/// Hoppe-style geomorph of a fine level towards a coarser one nested in it:
/// out[v] = (1 - alpha) * fine[v] + alpha * fine[representative[v]], where
/// `representative` maps every fine point to the fine id of the point it collapses into.
/// At alpha = 1 the fine mesh has exactly the coarse mesh's shape (collapsed triangles are
/// degenerate), so switching topology there does not pop.
void Geomorph(const float* fine, size_t numPoints, const std::vector<uint32_t>& representative,
  double alpha, float* out);

extern template std::vector<float> GatherPoints(
  const std::vector<float>&, int, size_t, const std::vector<uint32_t>&);
extern template std::vector<double> GatherPoints(
  const std::vector<double>&, int, size_t, const std::vector<uint32_t>&);
} // namespace morphnode
