// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file MorphAttribute.h
/// @brief One per-point attribute (positions, normals, colours, ...) of a morphable mesh:
/// the neutral values and, per target, the deltas target - neutral.
///
/// Deltas are stored per target either densely (all points) or sparsely (only the points
/// the target moves, as spans of consecutive point ids), chosen per target by coverage, so
/// that blending costs "active targets x points they move". Blending works on a point range
/// [begin, end), so that callers parallelize over points (vtkSMPTools in the VTK module)
/// and ranges never overlap in writes.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
/// How blended values are finished.
enum class AttributeRole
{
  Position, ///< plain blend
  Normal,   ///< blend, then renormalize to unit length (Java3D does not; glTF engines should)
  Color,    ///< blend, then clamp to the value range of the original type
  Generic   ///< texture coordinates and any other numeric array: plain blend
};

/// Deltas of one target for one attribute.
template <typename T>
class TargetDeltas
{
public:
  /// Keeps the points whose delta is not exactly zero. Stores them sparsely when they are
  /// at most `sparseCoverage` of all points (0 forces dense, 1 forces sparse).
  static TargetDeltas FromDense(
    const T* deltas, size_t numPoints, int components, double sparseCoverage);

  bool IsSparse() const { return this->Sparse; }
  /// Points with a non-zero delta.
  size_t GetNumberOfMovedPoints() const { return this->MovedPoints; }
  /// Largest Euclidean norm of a point's delta (the target's reach, M_i).
  double GetMaxNorm() const { return this->MaxNorm; }
  /// Sum over points of the Euclidean norm of the delta (the paper's dist_morph).
  double GetSumNorm() const { return this->SumNorm; }

  /// Dense storage: numPoints * components deltas; nullptr when sparse.
  const T* DenseData() const { return this->Sparse ? nullptr : this->Dense.data(); }
  /// Sparse storage keeps runs of at least this many consecutive moved points as spans.
  static constexpr size_t MinSpanPoints = 8;
  /// Sparse storage: runs of at least MinSpanPoints consecutive moved points (0 when dense).
  size_t GetNumberOfSpans() const { return this->Spans.size(); }
  /// Sparse storage: moved points outside those runs (0 when dense).
  size_t GetNumberOfSinglePoints() const { return this->Points.size(); }

  /// out[p] += weight * delta[p] for p in [begin, end).
  void AddScaled(T weight, T* out, size_t begin, size_t end) const;
  /// perPoint[p] = |delta[p]| for every point (size numPoints).
  void PointNorms(std::vector<double>& perPoint) const;
  /// Writes the dense deltas (numPoints * components values).
  void ToDense(T* deltas) const;

  size_t GetMemorySize() const;

private:
  int Components = 0;
  size_t NumPoints = 0;
  bool Sparse = false;
  size_t MovedPoints = 0;
  double MaxNorm = 0.0;
  double SumNorm = 0.0;
  /// Moved points [Begin, Begin + Count), their deltas at SpanValues[First * Components].
  /// Face targets move regions, and meshes number a region's points mostly in a row (runs
  /// of 9-34 points on average on the ICT and default faces), so a span blends as a dense
  /// run does, vectorized. Runs shorter than MinSpanPoints are kept as single points
  /// instead: a scatter costs less than starting a short vector loop at every run when a
  /// mesh's numbering scatters what a target moves.
  struct Span
  {
    uint32_t Begin;
    uint32_t Count;
    uint32_t First;
  };
  std::vector<T> Dense;         // NumPoints * Components
  std::vector<Span> Spans;      // sparse: long runs, sorted, disjoint
  std::vector<T> SpanValues;    // sparse: the spans' deltas, span after span
  std::vector<uint32_t> Points; // sparse: the moved points outside spans, sorted
  std::vector<T> PointValues;   // sparse: Points.size() * Components
};

/// The neutral values of an attribute and its per-target deltas.
/// Target 0 is the neutral (no deltas); targets 1..n carry deltas.
template <typename T>
class MorphAttribute
{
public:
  MorphAttribute(std::string name, AttributeRole role, int components, size_t numPoints);

  const std::string& GetName() const { return this->Name; }
  AttributeRole GetRole() const { return this->Role; }
  int GetNumberOfComponents() const { return this->Components; }
  size_t GetNumberOfPoints() const { return this->NumPoints; }
  /// Neutral included.
  size_t GetNumberOfTargets() const { return this->Targets.size() + 1; }

  /// Value range the blended values are clamped to (Color role).
  void SetClampRange(double lo, double hi);

  /// numPoints * components values.
  void SetNeutral(const T* values);
  const std::vector<T>& GetNeutral() const { return this->Neutral; }
  /// Appends the next target from its absolute values (target - neutral is stored).
  void AddAbsoluteTarget(const T* values, double sparseCoverage);
  /// Appends the next target from its deltas (glTF's relative form).
  void AddRelativeTarget(const T* deltas, double sparseCoverage);
  /// target >= 1.
  const TargetDeltas<T>& GetTarget(size_t target) const { return this->Targets.at(target - 1); }

  /// Blends points [begin, end) into `out` (numPoints * components values, written only in
  /// the range) with absolute weights (neutral first, summing to 1):
  /// out = neutral + sum_{i>0, w_i != 0} w_i * delta_i, then finished by role.
  /// Targets with weight 0 cost nothing.
  void Blend(const double* weights, size_t numWeights, T* out, size_t begin, size_t end) const;

  size_t GetMemorySize() const;

  /// Points blended together: the output block stays in cache (L2) across targets while
  /// each target's deltas stream in one long run. 32768 xyz floats = 384 KiB; measured on
  /// a 1M-point, 53-target dense blend (docs/benchmarks.md), 2048-point blocks streamed
  /// 25-40 % slower (each target's run too short for the hardware prefetchers).
  static constexpr size_t BlockPoints = 32768;

private:
  void BlendBlock(const double* weights, size_t numWeights, T* out, size_t begin, size_t end) const;

  std::string Name;
  AttributeRole Role;
  int Components;
  size_t NumPoints;
  double ClampLo;
  double ClampHi;
  std::vector<T> Neutral;
  std::vector<TargetDeltas<T>> Targets;
};

extern template class TargetDeltas<float>;
extern template class TargetDeltas<double>;
extern template class MorphAttribute<float>;
extern template class MorphAttribute<double>;
} // namespace morphnode
