// SPDX-License-Identifier: BSD-3-Clause
#include "skin/Skinning.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace
{
bool Finite(const glm::dmat4& m)
{
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 4; ++r)
    {
      if (!std::isfinite(m[c][r]))
      {
        return false;
      }
    }
  }
  return true;
}

/// Relative size below which a 3x3 determinant counts as singular (against the product of
/// the column lengths: a degenerate frame, not a small scale).
constexpr double SingularTolerance = 1e-9;

bool Singular(const glm::dmat3& m)
{
  const double scale = glm::length(m[0]) * glm::length(m[1]) * glm::length(m[2]);
  return !(scale > 0.0) || std::abs(glm::determinant(m)) <= SingularTolerance * scale;
}

/// The inverse transpose of a 3x3, up to a positive factor (the cofactor matrix, its sign
/// that of the determinant): what normals need before they are renormalized.
glm::dmat3 NormalMatrix(const glm::dmat3& m)
{
  const glm::dmat3 cof(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
  return glm::determinant(m) < 0.0 ? -cof : cof;
}

/// Equal within 1e-9 of the matrices' size: rest matrices that are one up to rounding (a
/// rest pose that is the bind pose gives World * InverseBind = I in float rounding) blend as
/// one, with an error far below the float points' own.
bool NearlyEqual(const glm::dmat4& a, const glm::dmat4& b)
{
  double size = 1.0, diff = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 3; ++r)
    {
      size = std::max(size, std::max(std::abs(a[c][r]), std::abs(b[c][r])));
      diff = std::max(diff, std::abs(a[c][r] - b[c][r]));
    }
  }
  // Rest matrices J(rest) IBM of a bind pose are the identity up to the float rounding of the
  // file's inverse bind matrices (about 1e-7): joints whose rest matrices agree that closely
  // re-skin by per-joint products (the float path), an error far below a float point's.
  return diff <= 1e-6 * size;
}

template <typename T>
void StoreNormal(const glm::dvec3& n, T* out)
{
  const double len = glm::length(n);
  const glm::dvec3 u = len > 0.0 ? n / len : n;
  out[0] = static_cast<T>(u.x);
  out[1] = static_cast<T>(u.y);
  out[2] = static_cast<T>(u.z);
}
} // namespace

void SkinJoints::Validate(const Skeleton& skeleton, const std::string& what) const
{
  if (this->Joints.empty())
  {
    throw InputError(what + ": the skin has no joints");
  }
  if (this->InverseBind.size() != this->Joints.size())
  {
    throw InputError(what + ": " + std::to_string(this->InverseBind.size()) +
      " inverse bind matrices for " + std::to_string(this->Joints.size()) + " joints");
  }
  for (size_t k = 0; k < this->Joints.size(); ++k)
  {
    if (this->Joints[k] < 0 || static_cast<size_t>(this->Joints[k]) >= skeleton.GetNumberOfJoints())
    {
      throw InputError(what + ": joint " + std::to_string(k) + " is node " +
        std::to_string(this->Joints[k]) + ", which does not exist");
    }
    const glm::dmat4& m = this->InverseBind[k];
    const std::string jk = what + ": the inverse bind matrix of joint " + std::to_string(k) + " (" +
      skeleton.GetJoint(static_cast<size_t>(this->Joints[k])).Name + ")";
    if (!Finite(m))
    {
      throw InputError(jk + " is not finite");
    }
    if (std::abs(m[0][3]) > 1e-6 || std::abs(m[1][3]) > 1e-6 || std::abs(m[2][3]) > 1e-6 ||
      std::abs(m[3][3] - 1.0) > 1e-6)
    {
      throw InputError(jk + " is not affine (its last row must be 0 0 0 1)");
    }
    if (Singular(glm::dmat3(m)))
    {
      throw InputError(jk + " is singular");
    }
  }
}

std::vector<glm::dmat4> SkinJoints::Matrices(const std::vector<glm::dmat4>& world) const
{
  std::vector<glm::dmat4> out(this->Joints.size());
  for (size_t k = 0; k < this->Joints.size(); ++k)
  {
    out[k] = world.at(static_cast<size_t>(this->Joints[k])) * this->InverseBind[k];
  }
  return out;
}

glm::dmat4 BlendedMatrix(
  const SkinInfluences& influences, const std::vector<glm::dmat4>& matrices, size_t point)
{
  glm::dmat4 b(0.0);
  const size_t per = influences.PerPoint;
  for (size_t k = 0; k < per; ++k)
  {
    const float w = influences.Weights[point * per + k];
    if (w != 0.0f)
    {
      b += static_cast<double>(w) * matrices[influences.Joints[point * per + k]];
    }
  }
  return b;
}

template <typename T>
void SkinPoints(const SkinInfluences& influences, const std::vector<glm::dmat4>& matrices,
  const T* points, const T* normals, T* outPoints, T* outNormals, size_t begin, size_t end)
{
  for (size_t i = begin; i < end; ++i)
  {
    const glm::dmat4 b = BlendedMatrix(influences, matrices, i);
    const glm::dvec3 p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
    const glm::dvec3 q = glm::dvec3(b * glm::dvec4(p, 1.0));
    outPoints[3 * i] = static_cast<T>(q.x);
    outPoints[3 * i + 1] = static_cast<T>(q.y);
    outPoints[3 * i + 2] = static_cast<T>(q.z);
    if (normals && outNormals)
    {
      const glm::dvec3 n(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
      StoreNormal(NormalMatrix(glm::dmat3(b)) * n, outNormals + 3 * i);
    }
  }
}

template void SkinPoints<float>(const SkinInfluences&, const std::vector<glm::dmat4>&, const float*,
  const float*, float*, float*, size_t, size_t);
template void SkinPoints<double>(const SkinInfluences&, const std::vector<glm::dmat4>&,
  const double*, const double*, double*, double*, size_t, size_t);

RestSkin::RestSkin(
  SkinInfluences influences, const std::vector<glm::dmat4>& restMatrices, const std::string& what)
  : Influences(std::move(influences))
  , Rest(restMatrices)
  , Pose(restMatrices)
  , Moved(restMatrices.size(), 0)
  , JointChanged(restMatrices.size(), 0)
  , Rigid(restMatrices.size(), 1)
  , Used(restMatrices.size(), 0)
{
  const size_t n = this->Influences.GetNumberOfPoints();
  for (size_t i = 0; i < n * this->Influences.PerPoint; ++i)
  {
    if (this->Influences.Weights[i] != 0.0f && this->Influences.Joints[i] < restMatrices.size())
    {
      this->Used[this->Influences.Joints[i]] = 1;
    }
    if (this->Influences.Weights[i] != 0.0f && this->Influences.Joints[i] >= restMatrices.size())
    {
      throw InputError(what + ": point " + std::to_string(i / this->Influences.PerPoint) +
        " is bound to joint " + std::to_string(this->Influences.Joints[i]) +
        ", but the skin has only " + std::to_string(restMatrices.size()) + " joints");
    }
  }
  for (const auto& m : this->Rest)
  {
    this->RestJointInverse.push_back(glm::inverse(m));
  }
  this->RestInverse.resize(12 * n);
  this->SharedRest.assign(n, 1);
  this->Delta.assign(12 * restMatrices.size(), 0.0f);
  for (size_t k = 0; k < this->Rest.size(); ++k)
  {
    this->SetDelta(k, this->Rest[k]); // the products at rest: SetPose forms only changed ones
  }
  const size_t per = this->Influences.PerPoint;
  for (size_t i = 0; i < n; ++i)
  {
    int first = -1;
    for (size_t k = 0; k < per; ++k)
    {
      if (this->Influences.Weights[i * per + k] == 0.0f)
      {
        continue;
      }
      const int j = this->Influences.Joints[i * per + k];
      if (first < 0)
      {
        first = j;
      }
      else if (!NearlyEqual(
                 this->Rest[static_cast<size_t>(j)], this->Rest[static_cast<size_t>(first)]))
      {
        this->SharedRest[i] = 0;
      }
    }
    const glm::dmat4 b = BlendedMatrix(this->Influences, this->Rest, i);
    if (!Finite(b) || Singular(glm::dmat3(b)))
    {
      throw InputError(what + ": point " + std::to_string(i) + ": its rest skin transform is " +
        (Finite(b) ? "singular" : "not finite"));
    }
    const glm::dmat4 inv = glm::inverse(b);
    for (int c = 0; c < 4; ++c)
    {
      for (int r = 0; r < 3; ++r)
      {
        this->RestInverse[12 * i + static_cast<size_t>(3 * c + r)] = inv[c][r];
      }
    }
  }
}

void RestSkin::SetDelta(size_t k, const glm::dmat4& m)
{
  const glm::dmat4 d = m * this->RestJointInverse[k];
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 3; ++r)
    {
      this->Delta[12 * k + static_cast<size_t>(3 * c + r)] = static_cast<float>(d[c][r]);
    }
  }
  const glm::dmat3 l(d);
  const glm::dmat3 e = glm::transpose(l) * l - glm::dmat3(1.0);
  double off = 0.0;
  for (int c = 0; c < 3; ++c)
  {
    for (int r = 0; r < 3; ++r)
    {
      off = std::max(off, std::abs(e[c][r]));
    }
  }
  this->Rigid[k] = off < 1e-6 && glm::determinant(l) > 0.0;
}

bool RestSkin::SetPose(const std::vector<glm::dmat4>& matrices)
{
  if (matrices.size() != this->Rest.size())
  {
    throw InputError("skin: " + std::to_string(matrices.size()) + " joint matrices for a skin of " +
      std::to_string(this->Rest.size()) + " joints");
  }
  bool any = false;
  for (size_t k = 0; k < matrices.size(); ++k)
  {
    if (!Finite(matrices[k]))
    {
      throw InputError("skin: the pose of joint " + std::to_string(k) + " is not finite");
    }
    this->Moved[k] = matrices[k] != this->Rest[k];
    any = any || (this->Moved[k] && this->Used[k]);
    this->JointChanged[k] = matrices[k] != this->Pose[k];
    if (!this->Used[k] || !this->JointChanged[k])
    {
      continue; // no point of this mesh follows it, or its product is formed already
    }
    this->SetDelta(k, matrices[k]);
  }
  this->Pose = matrices;
  return any;
}

bool RestSkin::Moves(size_t point) const
{
  const size_t per = this->Influences.PerPoint;
  for (size_t k = 0; k < per; ++k)
  {
    if (this->Influences.Weights[point * per + k] != 0.0f &&
      this->Moved[this->Influences.Joints[point * per + k]])
    {
      return true;
    }
  }
  return false;
}

bool RestSkin::Changed(size_t point) const
{
  const size_t per = this->Influences.PerPoint;
  for (size_t k = 0; k < per; ++k)
  {
    if (this->Influences.Weights[point * per + k] != 0.0f &&
      this->JointChanged[this->Influences.Joints[point * per + k]])
    {
      return true;
    }
  }
  return false;
}

template <typename T>
void RestSkin::ApplyPoint(const T* points, const T* normals, T* outPoints, T* outNormals, size_t i,
  bool moves, int single, int count) const
{
  const size_t per = this->Influences.PerPoint;
  const uint16_t* joints = this->Influences.Joints.data();
  const float* weights = this->Influences.Weights.data();
  if (!moves)
  {
    if (outPoints != points)
    {
      for (int k = 0; k < 3; ++k)
      {
        outPoints[3 * i + k] = points[3 * i + k];
      }
    }
    if (normals && outNormals && outNormals != normals)
    {
      for (int k = 0; k < 3; ++k)
      {
        outNormals[3 * i + k] = normals[3 * i + k];
      }
    }
    return;
  }
  if (this->SharedRest[i])
  {
    // Linear blend skinning with the per-joint products, in float; a point bound to one
    // joint takes its product as it is.
    float blended[12];
    const float* a = blended;
    if (count == 1)
    {
      a = &this->Delta[12 * static_cast<size_t>(single)];
    }
    else
    {
      for (float& v : blended)
      {
        v = 0.0f;
      }
      for (size_t k = 0; k < per; ++k)
      {
        const float w = weights[i * per + k];
        if (w != 0.0f)
        {
          const float* d = &this->Delta[12 * joints[i * per + k]];
          for (int e = 0; e < 12; ++e)
          {
            blended[e] += w * d[e];
          }
        }
      }
    }
    const float x = static_cast<float>(points[3 * i]), y = static_cast<float>(points[3 * i + 1]),
                z = static_cast<float>(points[3 * i + 2]);
    outPoints[3 * i] = static_cast<T>(a[0] * x + a[3] * y + a[6] * z + a[9]);
    outPoints[3 * i + 1] = static_cast<T>(a[1] * x + a[4] * y + a[7] * z + a[10]);
    outPoints[3 * i + 2] = static_cast<T>(a[2] * x + a[5] * y + a[8] * z + a[11]);
    if (normals && outNormals)
    {
      const float nx = static_cast<float>(normals[3 * i]),
                  ny = static_cast<float>(normals[3 * i + 1]),
                  nz = static_cast<float>(normals[3 * i + 2]);
      if (count == 1 && this->Rigid[static_cast<size_t>(single)])
      {
        // A rotation: it is its own inverse transpose and keeps lengths.
        outNormals[3 * i] = static_cast<T>(a[0] * nx + a[3] * ny + a[6] * nz);
        outNormals[3 * i + 1] = static_cast<T>(a[1] * nx + a[4] * ny + a[7] * nz);
        outNormals[3 * i + 2] = static_cast<T>(a[2] * nx + a[5] * ny + a[8] * nz);
        return;
      }
      // The cofactor matrix of the linear part: the inverse transpose up to det, whose sign
      // is kept; renormalized.
      // Columns of the cofactor matrix: cross(col1, col2), cross(col2, col0), cross(col0, col1).
      const float c0[3] = { a[4] * a[8] - a[5] * a[7], a[5] * a[6] - a[3] * a[8],
        a[3] * a[7] - a[4] * a[6] };
      const float c1[3] = { a[7] * a[2] - a[8] * a[1], a[8] * a[0] - a[6] * a[2],
        a[6] * a[1] - a[7] * a[0] };
      const float c2[3] = { a[1] * a[5] - a[2] * a[4], a[2] * a[3] - a[0] * a[5],
        a[0] * a[4] - a[1] * a[3] };
      const float det = a[0] * c0[0] + a[1] * c0[1] + a[2] * c0[2];
      float m[3] = { c0[0] * nx + c1[0] * ny + c2[0] * nz, c0[1] * nx + c1[1] * ny + c2[1] * nz,
        c0[2] * nx + c1[2] * ny + c2[2] * nz };
      float len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      len = len > 0.0f ? (det < 0.0f ? -1.0f : 1.0f) / len : 1.0f;
      for (int k = 0; k < 3; ++k)
      {
        outNormals[3 * i + k] = static_cast<T>(m[k] * len);
      }
    }
    return;
  }
  const double* r = &this->RestInverse[12 * i];
  const glm::dmat4 inv(
    r[0], r[1], r[2], 0.0, r[3], r[4], r[5], 0.0, r[6], r[7], r[8], 0.0, r[9], r[10], r[11], 1.0);
  const glm::dmat4 a = BlendedMatrix(this->Influences, this->Pose, i) * inv;
  const glm::dvec3 p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
  const glm::dvec3 q = glm::dvec3(a * glm::dvec4(p, 1.0));
  outPoints[3 * i] = static_cast<T>(q.x);
  outPoints[3 * i + 1] = static_cast<T>(q.y);
  outPoints[3 * i + 2] = static_cast<T>(q.z);
  if (normals && outNormals)
  {
    const glm::dvec3 n(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
    StoreNormal(NormalMatrix(glm::dmat3(a)) * n, outNormals + 3 * i);
  }
}

template <typename T>
void RestSkin::Apply(
  const T* points, const T* normals, T* outPoints, T* outNormals, size_t begin, size_t end) const
{
  const size_t per = this->Influences.PerPoint;
  const uint16_t* joints = this->Influences.Joints.data();
  const float* weights = this->Influences.Weights.data();
  const char* moved = this->Moved.data();
  for (size_t i = begin; i < end; ++i)
  {
    // One pass over the point's influences: does it move, and is it bound to one joint?
    bool moves = false;
    int single = -1;
    int count = 0;
    for (size_t k = 0; k < per; ++k)
    {
      if (weights[i * per + k] != 0.0f)
      {
        const uint16_t j = joints[i * per + k];
        moves = moves || moved[j];
        single = j;
        ++count;
      }
    }
    this->ApplyPoint(points, normals, outPoints, outNormals, i, moves, single, count);
  }
}

template void RestSkin::Apply<float>(
  const float*, const float*, float*, float*, size_t, size_t) const;
template void RestSkin::Apply<double>(
  const double*, const double*, double*, double*, size_t, size_t) const;

template <typename T>
size_t RestSkin::ApplyChanged(const T* points, const T* normals, T* lastPoints, T* lastNormals,
  T* outPoints, T* outNormals, size_t begin, size_t end, bool all) const
{
  const bool withNormals = normals && outNormals && lastNormals;
  const size_t per = this->Influences.PerPoint;
  const uint16_t* joints = this->Influences.Joints.data();
  const float* weights = this->Influences.Weights.data();
  const char* moved = this->Moved.data();
  const char* changed = this->JointChanged.data();
  size_t count = 0;
  for (size_t i = begin; i < end; ++i)
  {
    // Exact comparison of the input with the previous frame's (a changed point is stored).
    bool dirty = all || points[3 * i] != lastPoints[3 * i] ||
      points[3 * i + 1] != lastPoints[3 * i + 1] || points[3 * i + 2] != lastPoints[3 * i + 2] ||
      (withNormals &&
        (normals[3 * i] != lastNormals[3 * i] || normals[3 * i + 1] != lastNormals[3 * i + 1] ||
          normals[3 * i + 2] != lastNormals[3 * i + 2]));
    if (dirty)
    {
      for (int k = 0; k < 3; ++k)
      {
        lastPoints[3 * i + k] = points[3 * i + k];
      }
      for (int k = 0; k < 3 && withNormals; ++k)
      {
        lastNormals[3 * i + k] = normals[3 * i + k];
      }
    }
    // One pass over the point's influences: does it move, did a joint change, one joint?
    bool moves = false;
    int single = -1;
    int n = 0;
    for (size_t k = 0; k < per; ++k)
    {
      if (weights[i * per + k] != 0.0f)
      {
        const uint16_t j = joints[i * per + k];
        moves = moves || moved[j];
        dirty = dirty || changed[j];
        single = j;
        ++n;
      }
    }
    if (dirty)
    {
      this->ApplyPoint(points, withNormals ? normals : nullptr, outPoints,
        withNormals ? outNormals : nullptr, i, moves, single, n);
      ++count;
    }
  }
  return count;
}

template size_t RestSkin::ApplyChanged<float>(
  const float*, const float*, float*, float*, float*, float*, size_t, size_t, bool) const;
template size_t RestSkin::ApplyChanged<double>(
  const double*, const double*, double*, double*, double*, double*, size_t, size_t, bool) const;

} // namespace morphnode
