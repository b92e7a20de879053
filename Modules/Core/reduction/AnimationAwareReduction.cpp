// SPDX-License-Identifier: BSD-3-Clause
#include "reduction/AnimationAwareReduction.h"

#include "base/Error.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
// QuadricT needs vector_traits from the mesh headers.
#include <OpenMesh/Core/Geometry/QuadricT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModBaseT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>
#include <variant>

namespace morphnode
{
namespace
{
struct Traits : public OpenMesh::DefaultTraits
{
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
using Quadric = OpenMesh::Geometry::QuadricT<double>;

/// Silences OpenMesh's error stream (omerr) for its lifetime and restores it after.
class OpenMeshErrorsQuiet
{
public:
  OpenMeshErrorsQuiet()
    : WasEnabled(omerr().is_enabled())
  {
    omerr().disable();
  }
  ~OpenMeshErrorsQuiet()
  {
    if (this->WasEnabled)
    {
      omerr().enable();
    }
  }
  OpenMeshErrorsQuiet(const OpenMeshErrorsQuiet&) = delete;
  OpenMeshErrorsQuiet& operator=(const OpenMeshErrorsQuiet&) = delete;

private:
  bool WasEnabled;
};

/// The area-weighted plane quadric of a triangle, as ModQuadricT builds it.
Quadric FaceQuadric(
  const OpenMesh::Vec3d& a, const OpenMesh::Vec3d& b, const OpenMesh::Vec3d& c, double* areaOut)
{
  OpenMesh::Vec3d n = (b - a) % (c - a);
  double area = n.norm();
  if (area > FLT_MIN)
  {
    n /= area;
    area *= 0.5;
  }
  Quadric q(n[0], n[1], n[2], -(a | n));
  q *= area;
  if (areaOut)
  {
    *areaOut = area;
  }
  return q;
}

/// Binary module recording every collapse, for the representative map. Never refuses.
template <class MeshT>
class ModCollapseRecorderT : public OpenMesh::Decimater::ModBaseT<MeshT>
{
public:
  DECIMATING_MODULE(ModCollapseRecorderT, MeshT, CollapseRecorder);

  explicit ModCollapseRecorderT(MeshT& mesh)
    : Base(mesh, true)
  {
  }

  float collapse_priority(const CollapseInfo&) override { return Base::LEGAL_COLLAPSE; }
  void postprocess_collapse(const CollapseInfo& ci) override
  {
    this->CollapsedInto[ci.v0.idx()] = static_cast<uint32_t>(ci.v1.idx());
  }

  std::vector<uint32_t> CollapsedInto;
};

/// What the collapse costs read of the mesh: the neutral positions and every target's dense
/// position deltas, flat (3 per point), in the Position attribute's own type.
template <typename T>
struct FlatPositions
{
  const std::vector<T>& Positions;
  std::vector<std::vector<T>> PositionDeltas; // one per target, neutral excluded

  FlatPositions(const MorphAttribute<T>& attribute)
    : Positions(attribute.GetNeutral())
  {
    for (size_t k = 1; k < attribute.GetNumberOfTargets(); ++k)
    {
      this->PositionDeltas.emplace_back(this->Positions.size());
      attribute.GetTarget(k).ToDense(this->PositionDeltas.back().data());
    }
  }
  size_t GetNumberOfPoints() const { return this->Positions.size() / 3; }
  size_t GetNumberOfTargets() const { return this->PositionDeltas.size(); }
};

/// The priority module of the animation-aware reduction (see the header for the cost), for
/// positions of type T.
template <class MeshT, typename T>
class ModAnimationQuadricT : public OpenMesh::Decimater::ModBaseT<MeshT>
{
public:
  // DECIMATING_MODULE(ModAnimationQuadricT, MeshT, AnimationQuadric), which allows only the
  // mesh as template parameter.
  using Self = ModAnimationQuadricT<MeshT, T>;
  using Handle = OpenMesh::Decimater::ModHandleT<Self>;
  using Base = OpenMesh::Decimater::ModBaseT<MeshT>;
  using Mesh = typename Base::Mesh;
  using CollapseInfo = typename Base::CollapseInfo;
  DECIMATER_MODNAME(AnimationQuadric)

  explicit ModAnimationQuadricT(MeshT& mesh)
    : Base(mesh, false)
  {
  }

  void Configure(
    const FlatPositions<T>* morph, double weight, bool poseQuadrics, double motionWeight)
  {
    this->Morph = morph;
    this->Weight = weight;
    this->MotionWeight = motionWeight;
    this->UsePoses = poseQuadrics && !morph->PositionDeltas.empty();
  }

  void initialize() override
  {
    const size_t nv = this->Morph->GetNumberOfPoints();
    const size_t nk = this->UsePoses ? this->Morph->GetNumberOfTargets() : 0;
    this->Neutral.assign(nv, Quadric());
    this->Poses.assign(nv * nk, Quadric());
    this->Area.assign(nv, 0.0);
    this->MotionBound.assign(nv, 0.0);
    const auto& P = this->Morph->Positions;
    auto point = [&](uint32_t v, const T* delta)
    {
      OpenMesh::Vec3d p(P[3 * v], P[3 * v + 1], P[3 * v + 2]);
      if (delta)
      {
        p += OpenMesh::Vec3d(delta[3 * v], delta[3 * v + 1], delta[3 * v + 2]);
      }
      return p;
    };
    // Faces of the OpenMesh mesh: degenerate input triangles are not among them.
    for (const auto fh : Base::mesh().faces())
    {
      uint32_t ids[3];
      int i = 0;
      for (const auto vh : Base::mesh().fv_range(fh))
      {
        ids[i++] = static_cast<uint32_t>(vh.idx());
      }
      double area = 0.0;
      const Quadric q =
        FaceQuadric(point(ids[0], nullptr), point(ids[1], nullptr), point(ids[2], nullptr), &area);
      for (uint32_t id : ids)
      {
        this->Neutral[id] += q;
        this->Area[id] += area;
      }
      for (size_t k = 0; k < nk; ++k)
      {
        const T* d = this->Morph->PositionDeltas[k].data();
        const Quadric qk =
          FaceQuadric(point(ids[0], d), point(ids[1], d), point(ids[2], d), nullptr);
        for (uint32_t id : ids)
        {
          this->Poses[id * nk + k] += qk;
        }
      }
    }
    // Boundary contours (lips, eyelids) in every pose: a plane through each boundary edge,
    // perpendicular to its face, weighted by the squared edge length (Garland & Heckbert),
    // so that contours the animation opens and closes do not erode.
    for (size_t k = 0; k<nk&& this->BoundaryWeight> 0.0; ++k)
    {
      const T* d = this->Morph->PositionDeltas[k].data();
      for (const auto heh : Base::mesh().halfedges())
      {
        if (!Base::mesh().is_boundary(heh))
        {
          continue;
        }
        const auto opposite = Base::mesh().opposite_halfedge_handle(heh);
        const auto fh = Base::mesh().face_handle(opposite);
        const uint32_t a = static_cast<uint32_t>(Base::mesh().from_vertex_handle(heh).idx());
        const uint32_t b = static_cast<uint32_t>(Base::mesh().to_vertex_handle(heh).idx());
        uint32_t ids[3];
        int i = 0;
        for (const auto vh : Base::mesh().fv_range(fh))
        {
          ids[i++] = static_cast<uint32_t>(vh.idx());
        }
        OpenMesh::Vec3d faceNormal =
          (point(ids[1], d) - point(ids[0], d)) % (point(ids[2], d) - point(ids[0], d));
        const OpenMesh::Vec3d pa = point(a, d), pb = point(b, d);
        const OpenMesh::Vec3d edge = pb - pa;
        OpenMesh::Vec3d n = edge % faceNormal;
        const double len = n.norm();
        if (len <= DBL_MIN)
        {
          continue;
        }
        n /= len;
        Quadric q(n[0], n[1], n[2], -(pa | n));
        q *= this->BoundaryWeight * edge.sqrnorm();
        this->Poses[a * nk + k] += q;
        this->Poses[b * nk + k] += q;
      }
    }
  }

  float collapse_priority(const CollapseInfo& ci) override
  {
    const int v0 = ci.v0.idx();
    const int v1 = ci.v1.idx();
    Quadric q = this->Neutral[v0];
    q += this->Neutral[v1];
    double cost = q(ci.p1);
    if (this->Weight > 0.0)
    {
      cost += this->Weight * this->AnimationCost(v0, v1, ci.p1);
    }
    return static_cast<float>(cost);
  }

  void postprocess_collapse(const CollapseInfo& ci) override
  {
    const int v0 = ci.v0.idx();
    const int v1 = ci.v1.idx();
    this->Neutral[v1] += this->Neutral[v0];
    const size_t nk = this->UsePoses ? this->Morph->GetNumberOfTargets() : 0;
    for (size_t k = 0; k < nk; ++k)
    {
      this->Poses[v1 * nk + k] += this->Poses[v0 * nk + k];
    }
    this->MotionBound[v1] = this->MergedMotionBound(v0, v1);
    this->Area[v1] += this->Area[v0];
  }

private:
  double MotionDifference(int v0, int v1) const
  {
    double worst = 0.0;
    for (const auto& d : this->Morph->PositionDeltas)
    {
      const double dx = double(d[3 * v0]) - d[3 * v1];
      const double dy = double(d[3 * v0 + 1]) - d[3 * v1 + 1];
      const double dz = double(d[3 * v0 + 2]) - d[3 * v1 + 2];
      worst = std::max(worst, dx * dx + dy * dy + dz * dz);
    }
    return std::sqrt(worst);
  }

  double MergedMotionBound(int v0, int v1) const
  {
    return std::max(this->MotionBound[v1], this->MotionBound[v0] + this->MotionDifference(v0, v1));
  }

  double AnimationCost(int v0, int v1, const OpenMesh::Vec3d& p1) const
  {
    double pose = 0.0;
    if (this->UsePoses)
    {
      const size_t nk = this->Morph->GetNumberOfTargets();
      for (size_t k = 0; k < nk; ++k)
      {
        Quadric q = this->Poses[v0 * nk + k];
        q += this->Poses[v1 * nk + k];
        const T* d = this->Morph->PositionDeltas[k].data();
        const OpenMesh::Vec3d pk = p1 + OpenMesh::Vec3d(d[3 * v1], d[3 * v1 + 1], d[3 * v1 + 2]);
        pose = std::max(pose, q(pk));
      }
    }
    const double e = this->MergedMotionBound(v0, v1);
    return pose + this->MotionWeight * (this->Area[v0] + this->Area[v1]) * e * e;
  }

  const FlatPositions<T>* Morph = nullptr;
  double Weight = 0.0;
  double MotionWeight = 1.0;

public:
  double BoundaryWeight = 0.0;

private:
  bool UsePoses = false;
  std::vector<Quadric> Neutral;
  std::vector<Quadric> Poses; // point-major: Poses[v * targets + k]
  std::vector<double> Area;
  std::vector<double> MotionBound;
};

/// The Position attribute the collapses are chosen on; throws InputError for a mesh the
/// reduction cannot work on.
const AnyMorphAttribute& Validate(const MorphMesh& mesh, const ReductionSettings& settings)
{
  const size_t np = mesh.GetNumberOfPoints();
  if (np == 0)
  {
    throw InputError("Reduction: the mesh has no points.");
  }
  const int position = mesh.GetPositionAttribute();
  const AnyMorphAttribute* positions =
    position < 0 ? nullptr : &mesh.GetAttribute(static_cast<size_t>(position));
  if (!positions ||
    std::visit([](const auto& a) { return a.GetNumberOfComponents(); }, *positions) != 3)
  {
    throw InputError("Reduction: the mesh has no Position attribute of 3 components.");
  }
  if (!mesh.HasTriangles())
  {
    throw InputError("Reduction: the mesh has no triangles.");
  }
  mesh.Validate();
  std::visit(
    [](const auto& a)
    {
      for (const auto x : a.GetNeutral())
      {
        if (!std::isfinite(x))
        {
          throw InputError("Reduction: the neutral positions contain NaN or infinity.");
        }
      }
    },
    *positions);
  if (!std::isfinite(settings.AnimationWeight) || settings.AnimationWeight < 0.0)
  {
    throw InputError("Reduction: the animation weight must be finite and >= 0, got " +
      std::to_string(settings.AnimationWeight) + ".");
  }
  if (settings.TargetTriangles > 0)
  {
    if (settings.TargetTriangles >= mesh.GetNumberOfTriangles())
    {
      throw InputError("Reduction: the triangle budget (" +
        std::to_string(settings.TargetTriangles) + ") must be below the mesh's " +
        std::to_string(mesh.GetNumberOfTriangles()) + " triangles.");
    }
  }
  else if (settings.TargetPoints > 0)
  {
    if (settings.TargetPoints >= np)
    {
      throw InputError("Reduction: the point budget (" + std::to_string(settings.TargetPoints) +
        ") must be below the mesh's " + std::to_string(np) + " points.");
    }
  }
  else
  {
    throw InputError("Reduction: no budget; set TargetTriangles or TargetPoints.");
  }
  return *positions;
}

/// The reduced mesh: every attribute of `input` gathered through `ids`.

template <typename T>
ReductionResult Reduce(
  const MorphMesh& morph, const MorphAttribute<T>& positions, const ReductionSettings& settings)
{
  const FlatPositions<T> input(positions);
  const std::vector<uint32_t>& triangles = morph.GetTriangles();
  const size_t np = input.GetNumberOfPoints();

  ReductionResult result;
  Mesh mesh;
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  mesh.request_face_normals();
  std::vector<Mesh::VertexHandle> handles(np);
  for (size_t v = 0; v < np; ++v)
  {
    handles[v] = mesh.add_vertex(
      Mesh::Point(input.Positions[3 * v], input.Positions[3 * v + 1], input.Positions[3 * v + 2]));
  }
  size_t rejected = 0;
  // OpenMesh prints "complex edge" / "complex vertex" on its error stream for every face it
  // refuses; the count is reported below (or through the result) instead, in one message.
  const OpenMeshErrorsQuiet quiet;
  std::vector<uint32_t> faceInput; // OpenMesh face id -> input triangle
  faceInput.reserve(morph.GetNumberOfTriangles());
  for (size_t t = 0; t < morph.GetNumberOfTriangles(); ++t)
  {
    const uint32_t* ids = &triangles[3 * t];
    if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2])
    {
      ++result.DroppedDegenerateTriangles;
      continue;
    }
    if (!mesh.add_face(handles[ids[0]], handles[ids[1]], handles[ids[2]]).is_valid())
    {
      ++rejected;
      continue;
    }
    faceInput.push_back(static_cast<uint32_t>(t));
  }
  if (rejected > 0 && settings.SkipNonManifold)
  {
    result.SkippedNonManifoldTriangles = rejected;
  }
  else if (rejected > 0)
  {
    throw InputError("Reduction: " + std::to_string(rejected) +
      " triangles make the mesh non-manifold (an edge shared by more than two triangles, or a "
      "vertex joining separate fans with inconsistent orientation); clean the mesh first.");
  }
  mesh.update_face_normals();
  const size_t faces = mesh.n_faces();
  if (settings.TargetTriangles >= faces && settings.TargetTriangles > 0)
  {
    throw InputError("Reduction: the triangle budget must be below the " + std::to_string(faces) +
      " non-degenerate triangles of the mesh.");
  }

  using Decimater = OpenMesh::Decimater::DecimaterT<Mesh>;
  Decimater decimater(mesh);
  // The plain reduction is OpenMesh's own ModQuadricT; ours replaces it as the priority
  // module (OpenMesh allows exactly one) with the same neutral quadric plus the animation
  // terms.
  OpenMesh::Decimater::ModQuadricT<Mesh>::Handle plain;
  typename ModAnimationQuadricT<Mesh, T>::Handle animated;
  if (settings.AnimationWeight > 0.0)
  {
    decimater.add(animated);
    decimater.module(animated).Configure(
      &input, settings.AnimationWeight, settings.PoseQuadrics, settings.MotionWeight);
    decimater.module(animated).BoundaryWeight = settings.BoundaryWeight;
  }
  else
  {
    decimater.add(plain);
  }
  OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle flipping;
  if (settings.MaxNormalDeviation > 0.0)
  {
    decimater.add(flipping);
    decimater.module(flipping).set_max_normal_deviation(settings.MaxNormalDeviation);
  }
  typename ModCollapseRecorderT<Mesh>::Handle recorder;
  decimater.add(recorder);
  decimater.module(recorder).CollapsedInto.resize(np);
  for (size_t v = 0; v < np; ++v)
  {
    decimater.module(recorder).CollapsedInto[v] = static_cast<uint32_t>(v);
  }
  if (!decimater.initialize())
  {
    throw InputError("Reduction: OpenMesh's decimater could not be initialized.");
  }
  if (settings.TargetTriangles > 0)
  {
    decimater.decimate_to_faces(0, settings.TargetTriangles);
  }
  else
  {
    decimater.decimate_to(settings.TargetPoints);
  }

  // Kept points in original order; no garbage collection, so handle ids are original ids.
  std::vector<uint32_t> reducedId(np, UINT32_MAX);
  for (size_t v = 0; v < np; ++v)
  {
    if (!mesh.status(handles[v]).deleted())
    {
      reducedId[v] = static_cast<uint32_t>(result.OriginalPointIds.size());
      result.OriginalPointIds.push_back(static_cast<uint32_t>(v));
    }
  }
  // Follow chains of collapses v -> ... -> kept point.
  const auto& into = decimater.module(recorder).CollapsedInto;
  result.Representatives.resize(np);
  for (size_t v = 0; v < np; ++v)
  {
    uint32_t r = static_cast<uint32_t>(v);
    while (reducedId[r] == UINT32_MAX)
    {
      r = into[r];
    }
    result.Representatives[v] = reducedId[r];
  }
  std::vector<uint32_t> reducedTriangles;
  reducedTriangles.reserve(3 * mesh.n_faces());
  for (const auto fh : mesh.faces())
  {
    if (mesh.status(fh).deleted())
    {
      continue;
    }
    result.OriginalTriangleIds.push_back(faceInput[static_cast<size_t>(fh.idx())]);
    for (const auto vh : mesh.fv_range(fh))
    {
      reducedTriangles.push_back(reducedId[vh.idx()]);
    }
  }
  result.Mesh = GatherMorphMesh(
    morph, result.OriginalPointIds, std::move(reducedTriangles), settings.SparseCoverage);
  return result;
}
} // namespace

MorphMesh GatherMorphMesh(const MorphMesh& input, const std::vector<uint32_t>& ids,
  std::vector<uint32_t> triangles, double sparseCoverage)
{
  const size_t np = input.GetNumberOfPoints();
  MorphMesh out(ids.size());
  out.SetTargetNames(input.GetTargetNames());
  for (size_t a = 0; a < input.GetNumberOfAttributes(); ++a)
  {
    std::visit(
      [&](const auto& attribute)
      {
        using T = typename std::decay_t<decltype(attribute.GetNeutral())>::value_type;
        const int nc = attribute.GetNumberOfComponents();
        auto& reduced = out.AddAttribute<T>(attribute.GetName(), attribute.GetRole(), nc);
        reduced.SetNeutral(GatherPoints(attribute.GetNeutral(), nc, np, ids).data());
        std::vector<T> dense(np * static_cast<size_t>(nc));
        for (size_t k = 1; k < attribute.GetNumberOfTargets(); ++k)
        {
          attribute.GetTarget(k).ToDense(dense.data());
          reduced.AddRelativeTarget(GatherPoints(dense, nc, np, ids).data(), sparseCoverage);
        }
      },
      input.GetAttribute(a));
  }
  out.SetTriangles(std::move(triangles));
  return out;
}

ReductionResult ReduceAnimationAware(const MorphMesh& mesh, const ReductionSettings& settings)
{
  return std::visit([&](const auto& positions) { return Reduce(mesh, positions, settings); },
    Validate(mesh, settings));
}

template <typename T>
std::vector<T> GatherPoints(const std::vector<T>& values, int components, size_t numPoints,
  const std::vector<uint32_t>& originalPointIds)
{
  const size_t nc = static_cast<size_t>(components);
  if (components <= 0 || values.size() != numPoints * nc)
  {
    throw InputError("GatherPoints: expected " + std::to_string(numPoints) + " points of " +
      std::to_string(components) + " components, got " + std::to_string(values.size()) +
      " values.");
  }
  std::vector<T> out(originalPointIds.size() * nc);
  for (size_t i = 0; i < originalPointIds.size(); ++i)
  {
    const size_t src = originalPointIds[i];
    if (src >= numPoints)
    {
      throw InputError("GatherPoints: point id " + std::to_string(src) + " is out of range (" +
        std::to_string(numPoints) + " points).");
    }
    std::copy_n(values.begin() + src * nc, nc, out.begin() + i * nc);
  }
  return out;
}

void Geomorph(const float* fine, size_t numPoints, const std::vector<uint32_t>& representative,
  double alpha, float* out)
{
  if (representative.size() != numPoints)
  {
    throw InputError("Geomorph: the representative map has " +
      std::to_string(representative.size()) + " entries for " + std::to_string(numPoints) +
      " points.");
  }
  const float a = static_cast<float>(std::clamp(alpha, 0.0, 1.0));
  for (size_t v = 0; v < numPoints; ++v)
  {
    const size_t r = representative[v];
    if (r >= numPoints)
    {
      throw InputError("Geomorph: representative " + std::to_string(r) + " is out of range.");
    }
    for (int c = 0; c < 3; ++c)
    {
      out[3 * v + c] = (1.0f - a) * fine[3 * v + c] + a * fine[3 * r + c];
    }
  }
}

template std::vector<float> GatherPoints(
  const std::vector<float>&, int, size_t, const std::vector<uint32_t>&);
template std::vector<double> GatherPoints(
  const std::vector<double>&, int, size_t, const std::vector<uint32_t>&);
} // namespace morphnode
