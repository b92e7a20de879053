// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file MorphLadder.h
/// @brief The scalable avatar's ladder: levels of detail of a morphable mesh made by the
/// animation-aware reduction, sharing ONE vertex buffer and ONE set of targets, with an
/// index buffer per level (as Unity's mesh LODs do), so that no target is stored twice.
///
/// Why one buffer works: the reduction is a sequence of halfedge collapses, which keep a
/// subset of the original points unchanged (position and every delta). The levels are
/// chained (level l+1 reduced from level l), so each level's points are a subset of the
/// finer level's. The ladder renumbers the points once, coarsest level's points first, then
/// the points the next finer level adds, and so on: level l uses the prefix
/// [0, Levels[l].NumberOfPoints) of the shared buffer, and blending a level is blending that
/// point range (MorphAttribute::Blend(begin = 0, end = n_l)); its cost falls with the level.
/// OriginalPointIds maps the shared numbering back to the input's (a permutation: nothing
/// is resampled, nothing duplicated).
///
/// Geomorph (Hoppe 1997): every point not in the coarsest level has a Parent, the point of
/// the next coarser level it was collapsed into. Between level l and l+1 only the points
/// [n_{l+1}, n_l) move: p -> (1 - alpha) p + alpha parent(p); the parents lie in the prefix
/// [0, n_{l+1}) and do not move, so the geomorph runs in place on the blended buffer. At
/// alpha = 1, level l's triangles show exactly level l+1's surface (the collapsed ones are
/// degenerate), so the index buffer switches without a pop.

#include "budget/FrameBudgetController.h"
#include "morph/MorphMesh.h"
#include "reduction/AnimationAwareReduction.h"
#include "skin/SkinInfluences.h"

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace morphnode
{
struct LadderSettings
{
  /// Triangles of each reduced level as a fraction of the full mesh's, decreasing, each in
  /// (0, 1). Level 0 is always the full mesh; none: the full mesh alone.
  std::vector<double> TriangleFractions = { 0.5, 0.25, 0.1 };
  /// The reduction (its budget fields are ignored). AnimationWeight 0: plain quadric.
  /// SkipNonManifold is on: a few non-manifold triangles (the default head has two) stay in
  /// the full level and are left out of the reduced ones (MorphLadder::SkippedTriangles).
  ReductionSettings Reduction = []
  {
    ReductionSettings r;
    r.SkipNonManifold = true;
    return r;
  }();
  /// A skinned mesh's poses the level errors cover (its influences given to
  /// BuildMorphLadder): each the joint matrices J_k (skin/Skinning's SkinJoints::Matrices)
  /// of a pose the part takes, e.g. the jaw open, the head turned. The errors (MaxError,
  /// Error99, RmsError) then run over the neutral and every target pose, unskinned and
  /// skinned by each of these: a level whose coarse triangles cannot follow the bend of a
  /// skinned region shows it in its error and is chosen accordingly. Ignored without
  /// influences.
  std::vector<std::vector<glm::dmat4>> SkinPoses;
};

struct LadderLevel
{
  /// The level uses the points [0, NumberOfPoints) of the shared mesh.
  size_t NumberOfPoints = 0;
  /// Its index buffer: 3 shared point ids per triangle, all < NumberOfPoints.
  std::vector<uint32_t> Triangles;
  /// Per triangle of the index buffer, the input triangle it is (an index into the input
  /// mesh's triangles / 3; the identity for level 0): every reduced triangle is an input
  /// triangle with collapsed corners moved, so per-triangle data (cell data) carries over.
  std::vector<uint32_t> OriginalTriangleIds;
  /// Where every shared point sits on this level: the level triangle (3 shared ids) and
  /// barycentric weights of its closest point in the neutral, searched among the triangles
  /// around the point's representative (two rings), so that a lip point stays on its own
  /// lip. Carried through the animation, it is what the level shows of the full-resolution
  /// point. Empty for level 0 (every point is its own).
  std::vector<uint32_t> Corners;
  std::vector<float> Barycentrics;
  /// Largest distance between a full-resolution point and its carried point (Corners,
  /// Barycentrics) on this level, in the neutral and in every target's pose at weight 1,
  /// and those poses skinned by LadderSettings::SkinPoses (model units; 0 for level 0): surface
  /// error plus the motion the level gets wrong (sliding included). Times the pixels per unit: the
  /// level's error in pixels, by which it is chosen on screen.
  double MaxError = 0.0;
  /// The 99th percentile over the points of each point's largest distance over the poses:
  /// the error the level is chosen by on screen (ToLevelOfDetail). The largest (MaxError)
  /// belongs to a few points on a fold (a lid's or lip's margin) whose carried point crosses
  /// to the other side when it opens, and would keep a level off the screen until the face
  /// is a few pixels high (docs/lod.md has both).
  double Error99 = 0.0;
  /// The same distances' RMS over points and poses.
  double RmsError = 0.0;
  /// Towards the next coarser level (empty for the coarsest): over the points this level
  /// has and the next lacks, the largest distance to their parent in the neutral (entry 0)
  /// and the largest difference of their deltas from the parent's (entry k, target k). A
  /// point and its parent are at most GeomorphReach[0] + sum_k |w_k| GeomorphReach[k] apart
  /// under weights w: a whole geomorph's largest vertex jump.
  std::vector<double> GeomorphReach;
  /// Over the level's points: the targets' distances (M_i for the optimizer's bound) and
  /// the points each target moves (the blend's cost).
  TargetDistances Distances;
  std::vector<double> MovedPoints;
};

struct MorphLadder
{
  /// The one vertex buffer and set of targets (every attribute, renumbered); its triangles
  /// are level 0's.
  MorphMesh Mesh;
  /// Shared point -> the input's point id (a permutation).
  std::vector<uint32_t> OriginalPointIds;
  /// Shared point -> the point of the next coarser level it collapses into (itself for the
  /// coarsest level's points); always below the point's own id.
  std::vector<uint32_t> Parent;
  /// Finest (the full mesh) first.
  std::vector<LadderLevel> Levels;
  /// Non-manifold triangles of the input the reduced levels leave out.
  size_t SkippedTriangles = 0;
  /// A skinned part's joints and weights per shared point (the input's, gathered by
  /// OriginalPointIds; empty for a mesh without a skin). Every level's points are kept
  /// points of the input, so the prefix [0, n_l) skins exactly as the full mesh skins
  /// those points (skin/Skinning's SkinPoints or RestSkin over [0, n_l)): a reduced skinned
  /// part still skins, with one set of influences for every level.
  SkinInfluences Influences;

  /// The point `point` stands on at `level` (follows Parent until it is in the level).
  uint32_t Representative(size_t level, uint32_t point) const;
};

/// Builds the ladder. Throws InputError for what ReduceAnimationAware refuses and for
/// fractions that are not decreasing in (0, 1). No fractions: a one-level ladder (a part
/// too small to reduce, e.g. an eye, in a ScalableScene).
MorphLadder BuildMorphLadder(const MorphMesh& mesh, const LadderSettings& settings);
/// The same for a skinned mesh: `influences` (one entry per point of `mesh`, normalized) are
/// carried into MorphLadder::Influences, and the level errors cover settings.SkinPoses.
/// Throws InputError when their point count differs or a pose has too few joints.
MorphLadder BuildMorphLadder(
  const MorphMesh& mesh, const SkinInfluences& influences, const LadderSettings& settings);

/// Geomorph of level `level` towards level + 1, in place on `positions` (3 values per shared
/// point, at least Levels[level].NumberOfPoints points blended): the points of level
/// `level` that level + 1 does not have slide by alpha in [0, 1] towards their parents.
/// Throws InputError for the coarsest level or a level out of range.
template <typename T>
void GeomorphLadder(const MorphLadder& ladder, size_t level, double alpha, T* positions);
/// The same for any per-point attribute of the shared mesh (normals, texture coordinates,
/// colours): `components` values per point.
template <typename T>
void GeomorphLadder(
  const MorphLadder& ladder, size_t level, double alpha, T* values, int components);

/// A level for the FrameBudgetController, with the level's cost model; GeometricError is
/// the level's Error99.
LevelOfDetail ToLevelOfDetail(const MorphLadder& ladder, size_t level, const CostModel& cost);

extern template void GeomorphLadder(const MorphLadder&, size_t, double, float*);
extern template void GeomorphLadder(const MorphLadder&, size_t, double, double*);
extern template void GeomorphLadder(const MorphLadder&, size_t, double, float*, int);
extern template void GeomorphLadder(const MorphLadder&, size_t, double, double*, int);
} // namespace morphnode
