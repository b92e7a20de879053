// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SkinInfluences.h
/// @brief Which joints move each point of a skinned mesh, and how much (glTF 2.0's
/// JOINTS_n / WEIGHTS_n, every set): plain arrays, no math library in this header, so that
/// the glTF loader's scene can hold them.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
/// Per point, `PerPoint` influences (4 per glTF set: JOINTS_0/WEIGHTS_0, then _1, ...):
/// joint indices into the skin's joint list and weights, point-major
/// (Joints[i * PerPoint + k]). After Normalize() the weights of a point sum to 1.
struct SkinInfluences
{
  size_t PerPoint = 0;
  std::vector<uint16_t> Joints;
  std::vector<float> Weights;

  size_t GetNumberOfPoints() const
  {
    return this->PerPoint ? this->Weights.size() / this->PerPoint : 0;
  }
  bool Empty() const { return this->PerPoint == 0; }

  /// Appends one set of 4 influences per point (joints and weights, 4 values per point for
  /// `points` points), e.g. JOINTS_1/WEIGHTS_1 after JOINTS_0/WEIGHTS_0.
  void AddSet(const std::vector<float>& joints, const std::vector<float>& weights, size_t points);

  /// Checks and renormalizes: every joint index below `numJoints` where its weight is not 0,
  /// every weight finite and >= 0, and every point with a positive sum; then each point's
  /// weights are divided by their sum (glTF asks for a sum of 1; exporters round). Throws
  /// InputError naming `what`, the point and the fault.
  void Normalize(size_t numJoints, const std::string& what);

  /// The influences of the points `ids`, in that order (a subset or a permutation, e.g. a
  /// level-of-detail ladder's renumbering). Throws InputError for an id out of range.
  SkinInfluences Gather(const std::vector<uint32_t>& ids) const;
};
} // namespace morphnode
