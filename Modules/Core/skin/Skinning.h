// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Skinning.h
/// @brief Linear blend skinning as glTF 2.0 defines it, and re-skinning of rest-posed
/// geometry when joints move.
///
/// glTF: a skinned point p (in the mesh's bind space) goes to
///   p' = sum_k w_k J_k p,  J_k = World(joint_k) * InverseBind_k,
/// in world space; the transform of the node that holds the mesh is ignored. Morph targets
/// act first, in bind space: p = base + sum_i w_i delta_i. Normals go by the inverse
/// transpose of the blended linear part and are renormalized.
///
/// Because the blended transform B_v = sum_k w_k J_k of a point is affine, skinning a
/// morphed point equals adding the deltas turned by B_v's linear part to the skinned base.
/// So a mesh can be kept in its rest pose (B_v at rest applied to the base AND to every
/// delta, as the glTF loader gives it) and morphed there, and when joints move it is
/// re-skinned exactly by A_v = B_v(new) * B_v(rest)^-1 (RestSkin).

#include "skin/Skeleton.h"
#include "skin/SkinInfluences.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
/// The joints of one skin (indices into a skeleton) and their inverse bind matrices
/// (identity when the file has none).
struct SkinJoints
{
  std::string Name;
  std::vector<int> Joints;
  std::vector<glm::dmat4> InverseBind;

  /// Checks joint indices against the skeleton, one inverse bind matrix per joint, finite,
  /// affine (last row 0 0 0 1) and not singular. Throws InputError naming `what`.
  void Validate(const Skeleton& skeleton, const std::string& what) const;

  /// J_k = world[Joints[k]] * InverseBind[k], one per joint of the skin.
  std::vector<glm::dmat4> Matrices(const std::vector<glm::dmat4>& world) const;
};

/// B_v = sum_k w_k J_k of one point.
glm::dmat4 BlendedMatrix(
  const SkinInfluences& influences, const std::vector<glm::dmat4>& matrices, size_t point);

/// Skins `n` points (and normals, when both normal pointers are given) from bind space:
/// out = B_v p, normals by B_v's inverse transpose, renormalized. Points [begin, end).
/// `matrices` come from SkinJoints::Matrices; influences must be normalized (checked by
/// SkinInfluences::Normalize).
template <typename T>
void SkinPoints(const SkinInfluences& influences, const std::vector<glm::dmat4>& matrices,
  const T* points, const T* normals, T* outPoints, T* outNormals, size_t begin, size_t end);

/// Re-skins geometry that is in its rest pose: for each point A_v = B_v(pose) B_v(rest)^-1
/// (B_v(rest)^-1 computed once), applied to its (morphed) point and, by the inverse
/// transpose, to its normal, renormalized. Points whose joints all keep their rest
/// matrices are copied as they are. Where the joints of a point share one rest matrix (the
/// usual case: a rest pose that is the bind pose, or one dequantization folded into every
/// inverse bind matrix), A_v = sum_k w_k J_k(pose) J_k(rest)^-1 exactly, and the per-joint
/// products are formed once per pose: plain linear blend skinning, in float.
class RestSkin
{
public:
  RestSkin() = default;
  /// Throws InputError when a point's rest transform is singular (it could not have been
  /// shown) or not finite.
  RestSkin(SkinInfluences influences, const std::vector<glm::dmat4>& restMatrices,
    const std::string& what);

  size_t GetNumberOfPoints() const { return this->Influences.GetNumberOfPoints(); }
  size_t GetNumberOfJoints() const { return this->Rest.size(); }
  const SkinInfluences& GetInfluences() const { return this->Influences; }

  /// Prepares a pose: `matrices` (one per joint of the skin, as SkinJoints::Matrices gives
  /// them). Returns false when no joint that moves a point of this mesh left its rest
  /// (Apply would copy).
  bool SetPose(const std::vector<glm::dmat4>& matrices);
  /// True when a point of the last SetPose moves.
  bool Moves(size_t point) const;
  /// True when a joint of the point has another matrix (compared exactly) in the last
  /// SetPose than in the one before it.
  bool Changed(size_t point) const;

  /// Re-skins only what may have changed since the previous call, for points [begin, end):
  /// every point with a joint whose matrix changed (exactly) between the last two SetPose
  /// calls, and the points in `changedInput` (sorted, disjoint [first, last) pairs: the
  /// points whose input, point or normal, may differ from the previous call's; {0, n} for a
  /// first frame or new output arrays). Other points keep what `outPoints`/`outNormals`
  /// hold (the previous frame's output: nothing is read or copied there). The result equals
  /// Apply bit for bit: a point's output depends only on its input and its joints'
  /// matrices. The points are re-skinned by runs and groups set up once (SkinRun,
  /// BlendGroup): a run of points bound rigidly to one joint is one 3x4 transform over
  /// consecutive points, its normals turned by the same rotation; a group's points, blended
  /// over the same joints, are re-skinned together in vectorized blocks. In and out must be
  /// different arrays. Returns the number of points re-skinned.
  template <typename T>
  size_t ApplyChanged(const T* points, const T* normals, T* outPoints, T* outNormals,
    const std::vector<size_t>& changedInput, size_t begin, size_t end) const;

  /// Consecutive points that share how they are skinned, found once: bound to one joint
  /// (Joint >= 0), blended over the same joints with one rest matrix (Blend), or by the
  /// exact path (Exact), in point order. Runs cover every point but those of the blend
  /// groups (BlendGroup).
  struct SkinRun
  {
    static constexpr int Blend = -1;
    static constexpr int Exact = -2;
    size_t Begin = 0, End = 0;
    int Joint = Blend;
    size_t JointsBegin = 0, JointsEnd = 0; ///< its joints, in RunJoints
  };
  const std::vector<SkinRun>& GetRuns() const { return this->Runs; }

  /// The per-joint products of the last SetPose (of the rest before the first), 12 floats
  /// per joint of the skin: the 3x4 of J_k(pose) J_k(rest)^-1, column-major (column c, row r
  /// at 3 c + r). Joints no point follows keep their rest product (identity). Where every
  /// point's joints share one rest matrix (AllSharedRest), re-skinning a point is plain
  /// linear blend skinning with these: sum_k w_k Delta_k, applied to the point and, by its
  /// cofactor, to the normal, renormalized; what a renderer does per vertex.
  const std::vector<float>& GetDeltas() const { return this->Delta; }
  /// True when the joints of every point share one rest matrix (GetDeltas suffice).
  bool AllSharedRest() const { return this->AllShared; }

  /// Re-skins points [begin, end) for the pose of the last SetPose. `normals`/`outNormals`
  /// may be null. In and out may be the same arrays.
  template <typename T>
  void Apply(
    const T* points, const T* normals, T* outPoints, T* outNormals, size_t begin, size_t end) const;

private:
  void SetDelta(size_t joint, const glm::dmat4& matrix); ///< Delta and Rigid of a joint
  /// Re-skins point i (its influences scanned: moves, the last joint, their count).
  template <typename T>
  void ApplyPoint(const T* points, const T* normals, T* outPoints, T* outNormals, size_t i,
    bool moves, int single, int count) const;
  /// Re-skins points [begin, end) of `run` (all of its kind).
  template <typename T>
  void ApplyRun(const SkinRun& run, const T* points, const T* normals, T* outPoints, T* outNormals,
    size_t begin, size_t end) const;

  /// Points blended over the same joints (up to MaxGroupJoints), wherever they are in the
  /// mesh: re-skinned together, gathered into short SoA blocks so that the blend, the point
  /// and the normal (cofactor, renormalized) vectorize across points.
  static constexpr size_t MaxGroupJoints = 4;
  struct BlendGroup
  {
    size_t M = 0;
    std::array<uint16_t, MaxGroupJoints> Joints{};
    size_t Begin = 0, End = 0; ///< its points in GroupPoints
    size_t Weights = 0;        ///< its weights in GroupWeights, M per point
  };
  /// Re-skins the points `ids` (count of them, at `weights`: M per point) of group `g`.
  template <typename T>
  void ApplyGroup(const BlendGroup& g, const uint32_t* ids, const float* weights, size_t count,
    const T* points, const T* normals, T* outPoints, T* outNormals) const;
  /// Re-skins the points of the groups in [begin, end): all of a group whose joints changed
  /// (or every group's when `all`), else those `mask` (per point, non-zero: input changed)
  /// marks. Returns the count.
  template <typename T>
  size_t ApplyGroups(const T* points, const T* normals, T* outPoints, T* outNormals,
    const char* mask, bool all, size_t begin, size_t end) const;

  SkinInfluences Influences;
  std::vector<glm::dmat4> Rest;
  std::vector<glm::dmat4> RestJointInverse; ///< per joint: J(rest)^-1, formed once
  std::vector<double> RestInverse;          ///< 12 per point: the 3x4 of B_v(rest)^-1, column-major
  std::vector<char> SharedRest;             ///< per point: its joints share one rest matrix
  bool AllShared = true;                    ///< every point's SharedRest
  std::vector<float> Delta;                 ///< 12 per joint: J(pose) J(rest)^-1, column-major 3x4
  std::vector<glm::dmat4> Pose;
  std::vector<char> Moved;        ///< per joint
  std::vector<char> JointChanged; ///< per joint: its matrix differs from the previous SetPose's
  std::vector<char>
    Rigid; ///< per joint: its Delta is a rotation and translation (normals need no renormalizing)
  std::vector<char> Used; ///< per joint: some point has a weight on it
  std::vector<SkinRun> Runs;
  std::vector<uint16_t> RunJoints; ///< the joints of each run, sorted
  std::vector<BlendGroup> Groups;
  std::vector<uint32_t> GroupPoints; ///< each group's points, in point order
  std::vector<float> GroupWeights;
};
} // namespace morphnode
