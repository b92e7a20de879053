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

  /// Re-skins only what changed since the previous frame: points [begin, end) whose input
  /// (point or normal) differs from `lastPoints`/`lastNormals` (the inputs of the previous
  /// call, updated here) or that have a joint whose matrix changed between the last two
  /// SetPose calls. Other points keep what `outPoints`/`outNormals` hold (the previous
  /// frame's output: nothing is copied). `all` re-skins every point (a first frame, new
  /// output arrays). The result equals Apply bit for bit: a point's output depends only on
  /// its input and its joints' matrices. In and out must be different arrays. Returns the
  /// number of points re-skinned.
  template <typename T>
  size_t ApplyChanged(const T* points, const T* normals, T* lastPoints, T* lastNormals,
    T* outPoints, T* outNormals, size_t begin, size_t end, bool all) const;

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

  SkinInfluences Influences;
  std::vector<glm::dmat4> Rest;
  std::vector<glm::dmat4> RestJointInverse; ///< per joint: J(rest)^-1, formed once
  std::vector<double> RestInverse;          ///< 12 per point: the 3x4 of B_v(rest)^-1, column-major
  std::vector<char> SharedRest;             ///< per point: its joints share one rest matrix
  std::vector<float> Delta;                 ///< 12 per joint: J(pose) J(rest)^-1, column-major 3x4
  std::vector<glm::dmat4> Pose;
  std::vector<char> Moved;        ///< per joint
  std::vector<char> JointChanged; ///< per joint: its matrix differs from the previous SetPose's
  std::vector<char>
    Rigid; ///< per joint: its Delta is a rotation and translation (normals need no renormalizing)
  std::vector<char> Used; ///< per joint: some point has a weight on it
};
} // namespace morphnode
