// SPDX-License-Identifier: BSD-3-Clause
#include "skin/Skinning.h"

#include "base/Error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

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
        this->AllShared = false;
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
  // The runs: consecutive points with the same joints and the same path; and the groups:
  // points blended over the same (up to four) joints.
  std::vector<uint16_t> joints;
  std::map<std::pair<size_t, std::array<uint16_t, MaxGroupJoints>>, size_t> groupOf;
  std::vector<std::vector<uint32_t>> groupPoints;
  for (size_t i = 0; i < n; ++i)
  {
    joints.clear();
    for (size_t k = 0; k < per; ++k)
    {
      if (this->Influences.Weights[i * per + k] != 0.0f)
      {
        joints.push_back(this->Influences.Joints[i * per + k]);
      }
    }
    std::sort(joints.begin(), joints.end());
    joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
    const int kind = !this->SharedRest[i] ? SkinRun::Exact
      : joints.size() == 1                ? static_cast<int>(joints[0])
                                          : SkinRun::Blend;
    if (kind == SkinRun::Blend && joints.size() <= MaxGroupJoints)
    {
      // Blended over up to four joints: into the group of its joints.
      std::array<uint16_t, MaxGroupJoints> key{};
      std::copy(joints.begin(), joints.end(), key.begin());
      auto [it, added] = groupOf.emplace(std::make_pair(joints.size(), key), this->Groups.size());
      if (added)
      {
        BlendGroup g;
        g.M = joints.size();
        g.Joints = key;
        this->Groups.push_back(g);
        groupPoints.emplace_back();
      }
      groupPoints[it->second].push_back(static_cast<uint32_t>(i));
      continue;
    }
    if (!this->Runs.empty())
    {
      SkinRun& last = this->Runs.back();
      if (last.Joint == kind && last.JointsEnd - last.JointsBegin == joints.size() &&
        std::equal(joints.begin(), joints.end(),
          this->RunJoints.begin() + static_cast<long>(last.JointsBegin)))
      {
        last.End = i + 1;
        continue;
      }
    }
    SkinRun run;
    run.Begin = i;
    run.End = i + 1;
    run.Joint = kind;
    run.JointsBegin = this->RunJoints.size();
    this->RunJoints.insert(this->RunJoints.end(), joints.begin(), joints.end());
    run.JointsEnd = this->RunJoints.size();
    this->Runs.push_back(run);
  }
  for (size_t g = 0; g < this->Groups.size(); ++g)
  {
    BlendGroup& group = this->Groups[g];
    group.Begin = this->GroupPoints.size();
    group.Weights = this->GroupWeights.size();
    for (uint32_t i : groupPoints[g])
    {
      this->GroupPoints.push_back(i);
      for (size_t m = 0; m < group.M; ++m)
      {
        float w = 0.0f; // the point's weights on the group's joint m, summed
        for (size_t k = 0; k < per; ++k)
        {
          if (this->Influences.Joints[i * per + k] == group.Joints[m])
          {
            w += this->Influences.Weights[i * per + k];
          }
        }
        this->GroupWeights.push_back(w);
      }
    }
    group.End = this->GroupPoints.size();
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
    this->JointChanged[k] = matrices[k] != this->Pose[k];
    if (this->JointChanged[k])
    {
      // (An unchanged matrix was checked when it came.)
      if (!Finite(matrices[k]))
      {
        throw InputError("skin: the pose of joint " + std::to_string(k) + " is not finite");
      }
      this->Moved[k] = matrices[k] != this->Rest[k];
      this->Pose[k] = matrices[k];
    }
    any = any || (this->Moved[k] && this->Used[k]);
    if (!this->Used[k] || !this->JointChanged[k])
    {
      continue; // no point of this mesh follows it, or its product is formed already
    }
    this->SetDelta(k, matrices[k]);
  }
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

namespace
{
/// One joint's 3x4 (column-major, float) over consecutive points: out = A p. The loop
/// has no branch and no dependence between points, so that it vectorizes. In and out may
/// be the same array (each point is read before it is written).
template <typename T>
void TransformPoints(const float* a, const T* in, T* out, size_t n)
{
  const float a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6],
              a7 = a[7], a8 = a[8], a9 = a[9], a10 = a[10], a11 = a[11];
  for (size_t i = 0; i < n; ++i)
  {
    const float x = static_cast<float>(in[3 * i]), y = static_cast<float>(in[3 * i + 1]),
                z = static_cast<float>(in[3 * i + 2]);
    out[3 * i] = static_cast<T>(a0 * x + a3 * y + a6 * z + a9);
    out[3 * i + 1] = static_cast<T>(a1 * x + a4 * y + a7 * z + a10);
    out[3 * i + 2] = static_cast<T>(a2 * x + a5 * y + a8 * z + a11);
  }
}

/// Normals turned by a rotation (its own inverse transpose, lengths kept).
template <typename T>
void RotateNormals(const float* a, const T* in, T* out, size_t n)
{
  const float a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6],
              a7 = a[7], a8 = a[8];
  for (size_t i = 0; i < n; ++i)
  {
    const float x = static_cast<float>(in[3 * i]), y = static_cast<float>(in[3 * i + 1]),
                z = static_cast<float>(in[3 * i + 2]);
    out[3 * i] = static_cast<T>(a0 * x + a3 * y + a6 * z);
    out[3 * i + 1] = static_cast<T>(a1 * x + a4 * y + a7 * z);
    out[3 * i + 2] = static_cast<T>(a2 * x + a5 * y + a8 * z);
  }
}
/// Points blended over M joints (their 3x4 products `d`, per point M weights), in SoA
/// blocks: B = sum_m w_m D_m, out = B p, normals by B's cofactor matrix (the inverse
/// transpose up to det, whose sign is kept), renormalized. No branch and no dependence
/// between points, so that it vectorizes across points.
constexpr size_t GroupBlock = 64; ///< points per SoA block

template <int M, bool Normals>
void BlendBlock(const float* dIn, const float (*__restrict w)[GroupBlock], size_t c,
  const float (*__restrict in)[GroupBlock], float (*__restrict out)[GroupBlock])
{
  float d[12 * M];
  for (int e = 0; e < 12 * M; ++e)
  {
    d[e] = dIn[e];
  }
  const float* x = in[0];
  const float* y = in[1];
  const float* z = in[2];
  const float* nx = in[3];
  const float* ny = in[4];
  const float* nz = in[5];
  float* ox = out[0];
  float* oy = out[1];
  float* oz = out[2];
  float* onx = out[3];
  float* ony = out[4];
  float* onz = out[5];
  for (size_t t = 0; t < c; ++t)
  {
    float a[12];
    for (int e = 0; e < 12; ++e)
    {
      float v = w[0][t] * d[e];
      for (int m = 1; m < M; ++m)
      {
        v += w[m][t] * d[12 * m + e];
      }
      a[e] = v;
    }
    ox[t] = a[0] * x[t] + a[3] * y[t] + a[6] * z[t] + a[9];
    oy[t] = a[1] * x[t] + a[4] * y[t] + a[7] * z[t] + a[10];
    oz[t] = a[2] * x[t] + a[5] * y[t] + a[8] * z[t] + a[11];
    if (Normals)
    {
      const float c00 = a[4] * a[8] - a[5] * a[7], c01 = a[5] * a[6] - a[3] * a[8],
                  c02 = a[3] * a[7] - a[4] * a[6];
      const float c10 = a[7] * a[2] - a[8] * a[1], c11 = a[8] * a[0] - a[6] * a[2],
                  c12 = a[6] * a[1] - a[7] * a[0];
      const float c20 = a[1] * a[5] - a[2] * a[4], c21 = a[2] * a[3] - a[0] * a[5],
                  c22 = a[0] * a[4] - a[1] * a[3];
      const float det = a[0] * c00 + a[1] * c01 + a[2] * c02;
      const float mx = c00 * nx[t] + c10 * ny[t] + c20 * nz[t];
      const float my = c01 * nx[t] + c11 * ny[t] + c21 * nz[t];
      const float mz = c02 * nx[t] + c12 * ny[t] + c22 * nz[t];
      const float len = std::sqrt(mx * mx + my * my + mz * mz);
      const float scale = len > 0.0f ? (det < 0.0f ? -1.0f : 1.0f) / len : 1.0f;
      onx[t] = mx * scale;
      ony[t] = my * scale;
      onz[t] = mz * scale;
    }
  }
}
} // namespace

template <typename T>
void RestSkin::ApplyGroup(const BlendGroup& g, const uint32_t* ids, const float* weights,
  size_t count, const T* points, const T* normals, T* outPoints, T* outNormals) const
{
  bool moves = false;
  for (size_t m = 0; m < g.M; ++m)
  {
    moves = moves || this->Moved[g.Joints[m]];
  }
  if (!moves)
  {
    for (size_t t = 0; t < count; ++t)
    {
      const size_t i = ids[t];
      for (int k = 0; k < 3; ++k)
      {
        outPoints[3 * i + k] = points[3 * i + k];
        if (normals)
        {
          outNormals[3 * i + k] = normals[3 * i + k];
        }
      }
    }
    return;
  }
  constexpr size_t Block = GroupBlock;
  alignas(32) float in[6][Block], out[6][Block], w[MaxGroupJoints][Block];
  float d[12 * MaxGroupJoints];
  for (size_t m = 0; m < g.M && m < MaxGroupJoints; ++m)
  {
    for (size_t e = 0; e < 12; ++e)
    {
      d[12 * m + e] = this->Delta[12 * g.Joints[m] + e];
    }
  }
  for (size_t first = 0; first < count; first += Block)
  {
    const size_t c = std::min(Block, count - first);
    for (size_t t = 0; t < c; ++t)
    {
      const size_t i = ids[first + t];
      for (int k = 0; k < 3; ++k)
      {
        in[k][t] = static_cast<float>(points[3 * i + k]);
        in[3 + k][t] = normals ? static_cast<float>(normals[3 * i + k]) : 0.0f;
      }
      for (size_t m = 0; m < g.M; ++m)
      {
        w[m][t] = weights[(first + t) * g.M + m];
      }
    }
    switch (g.M * 2 + (normals ? 1 : 0))
    {
      case 4:
        BlendBlock<2, false>(d, w, c, in, out);
        break;
      case 5:
        BlendBlock<2, true>(d, w, c, in, out);
        break;
      case 6:
        BlendBlock<3, false>(d, w, c, in, out);
        break;
      case 7:
        BlendBlock<3, true>(d, w, c, in, out);
        break;
      case 8:
        BlendBlock<4, false>(d, w, c, in, out);
        break;
      default:
        BlendBlock<4, true>(d, w, c, in, out);
        break;
    }
    for (size_t t = 0; t < c; ++t)
    {
      const size_t i = ids[first + t];
      for (int k = 0; k < 3; ++k)
      {
        outPoints[3 * i + k] = static_cast<T>(out[k][t]);
        if (normals)
        {
          outNormals[3 * i + k] = static_cast<T>(out[3 + k][t]);
        }
      }
    }
  }
}

template <typename T>
size_t RestSkin::ApplyGroups(const T* points, const T* normals, T* outPoints, T* outNormals,
  const char* mask, bool all, size_t begin, size_t end) const
{
  size_t count = 0;
  constexpr size_t Block = GroupBlock;
  uint32_t ids[Block];
  float weights[Block * MaxGroupJoints];
  for (const BlendGroup& g : this->Groups)
  {
    const uint32_t* gp = this->GroupPoints.data();
    const size_t lo = static_cast<size_t>(
      std::lower_bound(gp + g.Begin, gp + g.End, static_cast<uint32_t>(begin)) - gp);
    const size_t hi =
      static_cast<size_t>(std::lower_bound(gp + lo, gp + g.End,
                            static_cast<uint32_t>(std::min<size_t>(end, UINT32_MAX))) -
        gp);
    if (lo == hi)
    {
      continue;
    }
    bool dirty = all;
    for (size_t m = 0; m < g.M && !dirty; ++m)
    {
      dirty = this->JointChanged[g.Joints[m]];
    }
    if (dirty)
    {
      this->ApplyGroup(g, gp + lo, &this->GroupWeights[g.Weights + (lo - g.Begin) * g.M], hi - lo,
        points, normals, outPoints, outNormals);
      count += hi - lo;
      continue;
    }
    if (!mask)
    {
      continue;
    }
    size_t c = 0;
    for (size_t k = lo; k < hi; ++k)
    {
      if (!mask[gp[k] - begin])
      {
        continue;
      }
      ids[c] = gp[k];
      for (size_t m = 0; m < g.M && m < MaxGroupJoints; ++m)
      {
        weights[c * g.M + m] = this->GroupWeights[g.Weights + (k - g.Begin) * g.M + m];
      }
      if (++c == Block)
      {
        this->ApplyGroup(g, ids, weights, c, points, normals, outPoints, outNormals);
        count += c;
        c = 0;
      }
    }
    if (c)
    {
      this->ApplyGroup(g, ids, weights, c, points, normals, outPoints, outNormals);
      count += c;
    }
  }
  return count;
}

template <typename T>
void RestSkin::ApplyRun(const SkinRun& run, const T* points, const T* normals, T* outPoints,
  T* outNormals, size_t begin, size_t end) const
{
  if (run.Joint < 0)
  {
    const size_t per = this->Influences.PerPoint;
    const uint16_t* joints = this->Influences.Joints.data();
    const float* weights = this->Influences.Weights.data();
    const char* moved = this->Moved.data();
    for (size_t i = begin; i < end; ++i)
    {
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
    return;
  }
  const size_t j = static_cast<size_t>(run.Joint);
  const size_t n = end - begin;
  if (!this->Moved[j])
  {
    if (outPoints != points)
    {
      std::copy(points + 3 * begin, points + 3 * end, outPoints + 3 * begin);
    }
    if (normals && outNormals && outNormals != normals)
    {
      std::copy(normals + 3 * begin, normals + 3 * end, outNormals + 3 * begin);
    }
    return;
  }
  const float* a = &this->Delta[12 * j];
  TransformPoints(a, points + 3 * begin, outPoints + 3 * begin, n);
  if (!normals || !outNormals)
  {
    return;
  }
  if (this->Rigid[j])
  {
    RotateNormals(a, normals + 3 * begin, outNormals + 3 * begin, n);
    return;
  }
  for (size_t i = begin; i < end; ++i)
  {
    this->ApplyPoint(points, normals, outPoints, outNormals, i, true, run.Joint, 1);
  }
}

template <typename T>
void RestSkin::Apply(
  const T* points, const T* normals, T* outPoints, T* outNormals, size_t begin, size_t end) const
{
  if (!normals || !outNormals)
  {
    normals = outNormals = nullptr;
  }
  auto run = std::partition_point(
    this->Runs.begin(), this->Runs.end(), [begin](const SkinRun& r) { return r.End <= begin; });
  for (; run != this->Runs.end() && run->Begin < end; ++run)
  {
    this->ApplyRun(*run, points, normals, outPoints, outNormals, std::max(run->Begin, begin),
      std::min(run->End, end));
  }
  this->ApplyGroups(points, normals, outPoints, outNormals, nullptr, true, begin, end);
}

template void RestSkin::Apply<float>(
  const float*, const float*, float*, float*, size_t, size_t) const;
template void RestSkin::Apply<double>(
  const double*, const double*, double*, double*, size_t, size_t) const;

template <typename T>
size_t RestSkin::ApplyChanged(const T* points, const T* normals, T* outPoints, T* outNormals,
  const std::vector<size_t>& changedInput, size_t begin, size_t end) const
{
  if (!normals || !outNormals)
  {
    normals = outNormals = nullptr;
  }
  const char* changed = this->JointChanged.data();
  auto run = std::partition_point(
    this->Runs.begin(), this->Runs.end(), [begin](const SkinRun& r) { return r.End <= begin; });
  // The first [first, last) pair of changedInput that ends after `begin`.
  size_t c = 0;
  const size_t pairs = changedInput.size() / 2;
  {
    size_t lo = 0, hi = pairs;
    while (lo < hi)
    {
      const size_t mid = (lo + hi) / 2;
      if (changedInput[2 * mid + 1] <= begin)
      {
        lo = mid + 1;
      }
      else
      {
        hi = mid;
      }
    }
    c = lo;
  }
  size_t count = 0;
  for (; run != this->Runs.end() && run->Begin < end; ++run)
  {
    const size_t s = std::max(run->Begin, begin), e = std::min(run->End, end);
    bool dirty = false;
    for (size_t k = run->JointsBegin; k < run->JointsEnd && !dirty; ++k)
    {
      dirty = changed[this->RunJoints[k]];
    }
    if (dirty)
    {
      this->ApplyRun(*run, points, normals, outPoints, outNormals, s, e);
      count += e - s;
    }
    for (; c < pairs && changedInput[2 * c] < e; ++c)
    {
      const size_t ps = std::max(s, changedInput[2 * c]), pe = std::min(e, changedInput[2 * c + 1]);
      if (!dirty && ps < pe)
      {
        this->ApplyRun(*run, points, normals, outPoints, outNormals, ps, pe);
        count += pe - ps;
      }
      if (changedInput[2 * c + 1] > e)
      {
        break; // it goes on into the next run
      }
    }
  }
  // The groups: the points whose input may have changed, marked.
  std::vector<char> mask;
  for (size_t k = 0; k < pairs; ++k)
  {
    const size_t ps = std::max(begin, changedInput[2 * k]),
                 pe = std::min(end, changedInput[2 * k + 1]);
    if (ps < pe)
    {
      mask.resize(end - begin, 0);
      std::fill(mask.begin() + static_cast<long>(ps - begin),
        mask.begin() + static_cast<long>(pe - begin), 1);
    }
  }
  count += this->ApplyGroups(points, normals, outPoints, outNormals,
    mask.empty() ? nullptr : mask.data(), false, begin, end);
  return count;
}

template size_t RestSkin::ApplyChanged<float>(
  const float*, const float*, float*, float*, const std::vector<size_t>&, size_t, size_t) const;
template size_t RestSkin::ApplyChanged<double>(
  const double*, const double*, double*, double*, const std::vector<size_t>&, size_t, size_t) const;

} // namespace morphnode
