// SPDX-License-Identifier: BSD-3-Clause
#include "skin/SkinInfluences.h"

#include "base/Error.h"

#include <cmath>
#include <cstddef>
#include <string>

namespace morphnode
{
void SkinInfluences::AddSet(
  const std::vector<float>& joints, const std::vector<float>& weights, size_t points)
{
  if (joints.size() != 4 * points || weights.size() != 4 * points)
  {
    throw InputError("skin: a set of joints and weights needs 4 of each per point");
  }
  if (this->PerPoint != 0 && this->GetNumberOfPoints() != points)
  {
    throw InputError("skin: the sets of joints and weights differ in point count");
  }
  const size_t old = this->PerPoint;
  const size_t per = old + 4;
  std::vector<uint16_t> j(per * points);
  std::vector<float> w(per * points);
  for (size_t i = 0; i < points; ++i)
  {
    for (size_t k = 0; k < old; ++k)
    {
      j[i * per + k] = this->Joints[i * old + k];
      w[i * per + k] = this->Weights[i * old + k];
    }
    for (size_t k = 0; k < 4; ++k)
    {
      const float v = joints[4 * i + k];
      // Joint indices are unsigned bytes or shorts in glTF: a value outside [0, 65535] or
      // not whole cannot come from a valid accessor.
      if (!(v >= 0.0f && v <= 65535.0f) || v != std::floor(v))
      {
        throw InputError("skin: point " + std::to_string(i) + " has joint index " +
          std::to_string(v) + ", which is not an unsigned 16-bit integer");
      }
      j[i * per + old + k] = static_cast<uint16_t>(v);
      w[i * per + old + k] = weights[4 * i + k];
    }
  }
  this->PerPoint = per;
  this->Joints = std::move(j);
  this->Weights = std::move(w);
}

void SkinInfluences::Normalize(size_t numJoints, const std::string& what)
{
  const size_t n = this->GetNumberOfPoints();
  for (size_t i = 0; i < n; ++i)
  {
    double sum = 0.0;
    for (size_t k = 0; k < this->PerPoint; ++k)
    {
      const float w = this->Weights[i * this->PerPoint + k];
      if (!std::isfinite(w) || w < 0.0f)
      {
        throw InputError(what + ": point " + std::to_string(i) + " has weight " +
          std::to_string(w) + " (weights must be finite and not negative)");
      }
      if (w > 0.0f && this->Joints[i * this->PerPoint + k] >= numJoints)
      {
        throw InputError(what + ": point " + std::to_string(i) + " is bound to joint " +
          std::to_string(this->Joints[i * this->PerPoint + k]) + ", but the skin has only " +
          std::to_string(numJoints) + " joints");
      }
      sum += w;
    }
    if (!(sum > 0.0))
    {
      throw InputError(
        what + ": point " + std::to_string(i) + " has no weight (all its weights are 0)");
    }
    for (size_t k = 0; k < this->PerPoint; ++k)
    {
      float& w = this->Weights[i * this->PerPoint + k];
      w = static_cast<float>(w / sum);
      if (w == 0.0f)
      {
        this->Joints[i * this->PerPoint + k] = 0; // unused slots point at a valid joint
      }
    }
  }
}
SkinInfluences SkinInfluences::Gather(const std::vector<uint32_t>& ids) const
{
  SkinInfluences out;
  out.PerPoint = this->PerPoint;
  out.Joints.reserve(ids.size() * this->PerPoint);
  out.Weights.reserve(ids.size() * this->PerPoint);
  const size_t n = this->GetNumberOfPoints();
  for (uint32_t id : ids)
  {
    if (id >= n)
    {
      throw InputError("skin: point " + std::to_string(id) + " gathered from influences of " +
        std::to_string(n) + " points");
    }
    const auto begin = static_cast<std::ptrdiff_t>(id * this->PerPoint);
    const auto end = begin + static_cast<std::ptrdiff_t>(this->PerPoint);
    out.Joints.insert(out.Joints.end(), this->Joints.begin() + begin, this->Joints.begin() + end);
    out.Weights.insert(
      out.Weights.end(), this->Weights.begin() + begin, this->Weights.begin() + end);
  }
  return out;
}
} // namespace morphnode
