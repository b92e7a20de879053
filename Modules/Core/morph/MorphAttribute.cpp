// SPDX-License-Identifier: BSD-3-Clause
#include "morph/MorphAttribute.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace morphnode
{
namespace
{
// The dense kernels are built twice, for AVX2 and for the baseline ISA, and the loader
// picks one per machine: with 8-wide vectors two threads stream 20-25 % more bandwidth
// (docs/benchmarks.md). Without FMA on purpose: both clones round the same way, so a blend
// does not depend on the machine, and the dense and sparse paths stay bit-identical.
// GCC only: clang 14 rejects target_clones on templates and together with noinline (the
// fuzz and clang builds get the baseline kernels; docs/fuzzing.md).
#if defined(__x86_64__) && defined(__has_attribute) && !defined(__clang__)
#if __has_attribute(target_clones)
#define MORPHNODE_KERNEL_CLONES __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef MORPHNODE_KERNEL_CLONES
#define MORPHNODE_KERNEL_CLONES
#endif
// The renormalization of normals is bound by double-precision square roots and divides,
// which AVX-512 does eight at a time: 2.5x faster than AVX2 on 11,248 normals (one
// thread, this machine). Square roots and divides round correctly at any vector width, and
// this file is built without FMA contraction, so every clone gives the same bits.
#if defined(__x86_64__) && defined(__has_attribute) && !defined(__clang__)
#if __has_attribute(target_clones)
#define MORPHNODE_NORMALIZE_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#endif
#endif
#ifndef MORPHNODE_NORMALIZE_CLONES
#define MORPHNODE_NORMALIZE_CLONES
#endif

// The kernels below add weighted deltas to y. The first pass over a block reads the neutral
// instead of y (Start = true), so the neutral is not copied into y in a pass of its own:
// y = neutral + w d rounds as y = neutral; y += w d does, so the result is the same bits.
// Kept out of line on purpose: inlined into the loop over targets, GCC 12 -O3 interchanges
// the two loops and vectorizes over targets with gathers, 6-7x slower.
template <bool Start, typename T>
__attribute__((noinline)) MORPHNODE_KERNEL_CLONES void Axpy(
  T weight, const T* __restrict x, const T* __restrict neutral, T* __restrict y, size_t n)
{
  for (size_t i = 0; i < n; ++i)
  {
    y[i] = (Start ? neutral[i] : y[i]) + weight * x[i];
  }
}

// Up to four targets in one pass over a block: the output is loaded and stored once per
// pass instead of once per delta, and the delta streams are in flight together. Each element
// still receives w0 d0, w1 d1, ... in that order, rounded after each add, as Count Axpy calls
// would (the kernels are built without FMA), so the result is the same bits. Fewer than four
// pending targets (a speech frame of Java3D's ICT shapes has three) take one pass too, not
// one each: 1.6x faster for three dense targets. Eight a pass were no faster than four.
constexpr int MaxTargetsPerPass = 4;

template <bool Start, int Count, typename T>
__attribute__((noinline)) MORPHNODE_KERNEL_CLONES void AxpyN(const T* w, const T* __restrict x0,
  const T* __restrict x1, const T* __restrict x2, const T* __restrict x3,
  const T* __restrict neutral, T* __restrict y, size_t n)
{
  static_assert(Count >= 1 && Count <= MaxTargetsPerPass, "one to four targets a pass");
  const T w0 = w[0];
  const T w1 = Count > 1 ? w[1] : T(0);
  const T w2 = Count > 2 ? w[2] : T(0);
  const T w3 = Count > 3 ? w[3] : T(0);
  for (size_t i = 0; i < n; ++i)
  {
    T v = Start ? neutral[i] : y[i];
    v += w0 * x0[i];
    if constexpr (Count > 1)
    {
      v += w1 * x1[i];
    }
    if constexpr (Count > 2)
    {
      v += w2 * x2[i];
    }
    if constexpr (Count > 3)
    {
      v += w3 * x3[i];
    }
    y[i] = v;
  }
}

// The pending dense targets (1 to MaxTargetsPerPass) in one pass.
template <bool Start, typename T>
void AxpyPending(int count, const T* w, const T* const* x, const T* neutral, T* y, size_t n)
{
  switch (count)
  {
    case 1:
      AxpyN<Start, 1, T>(w, x[0], nullptr, nullptr, nullptr, neutral, y, n);
      break;
    case 2:
      AxpyN<Start, 2, T>(w, x[0], x[1], nullptr, nullptr, neutral, y, n);
      break;
    case 3:
      AxpyN<Start, 3, T>(w, x[0], x[1], x[2], nullptr, neutral, y, n);
      break;
    default:
      AxpyN<Start, 4, T>(w, x[0], x[1], x[2], x[3], neutral, y, n);
      break;
  }
}

// Blended normals back to unit length, for xyz triples. The same arithmetic as the general
// loop in BlendBlock (length in double, its inverse rounded to T, one multiply per
// component; a zero or NaN length leaves the normal as it is), written without a branch so
// that it vectorizes: as a scalar loop of sqrt and divide it took more time than blending
// the normals (MorphAvatar's default face). GCC vectorizes it only with -fno-math-errno
// and -fno-trapping-math (Modules/Core/CMakeLists.txt); neither changes a value.
template <typename T>
__attribute__((noinline)) MORPHNODE_NORMALIZE_CLONES void NormalizeTriples(
  T* __restrict v, size_t count)
{
  for (size_t p = 0; p < count; ++p)
  {
    const double x = static_cast<double>(v[3 * p]);
    const double y = static_cast<double>(v[3 * p + 1]);
    const double z = static_cast<double>(v[3 * p + 2]);
    const double len = std::sqrt(x * x + y * y + z * z);
    const double divisor = len > 0.0 ? len : 1.0; // a select, not a branch
    const T inv = static_cast<T>(1.0 / divisor);
    v[3 * p] *= inv;
    v[3 * p + 1] *= inv;
    v[3 * p + 2] *= inv;
  }
}

template <typename T>
double Norm(const T* v, int components)
{
  double s = 0.0;
  for (int c = 0; c < components; ++c)
  {
    s += static_cast<double>(v[c]) * static_cast<double>(v[c]);
  }
  return std::sqrt(s);
}
} // namespace

template <typename T>
TargetDeltas<T> TargetDeltas<T>::FromDense(
  const T* deltas, size_t numPoints, int components, double sparseCoverage)
{
  if (numPoints > std::numeric_limits<uint32_t>::max())
  {
    throw InputError("meshes of more than 2^32 points are not supported");
  }
  TargetDeltas<T> t;
  t.Components = components;
  t.NumPoints = numPoints;
  const size_t c = static_cast<size_t>(components);
  std::vector<Span> runs; // every run of moved points; First unused here
  for (size_t p = 0; p < numPoints; ++p)
  {
    const double n = Norm(deltas + p * c, components);
    if (n == 0.0)
    {
      continue;
    }
    if (!runs.empty() && size_t(runs.back().Begin) + runs.back().Count == p)
    {
      ++runs.back().Count;
    }
    else
    {
      runs.push_back({ static_cast<uint32_t>(p), 1, 0 });
    }
    ++t.MovedPoints;
    t.SumNorm += n;
    t.MaxNorm = std::max(t.MaxNorm, n);
  }
  t.Sparse = numPoints > 0 &&
    static_cast<double>(t.MovedPoints) <= sparseCoverage * static_cast<double>(numPoints);
  if (!t.Sparse)
  {
    t.Dense.assign(deltas, deltas + numPoints * c);
    return t;
  }
  for (const Span& run : runs)
  {
    const T* first = deltas + size_t(run.Begin) * c;
    if (run.Count >= MinSpanPoints)
    {
      t.Spans.push_back({ run.Begin, run.Count, static_cast<uint32_t>(t.SpanValues.size() / c) });
      t.SpanValues.insert(t.SpanValues.end(), first, first + size_t(run.Count) * c);
      continue;
    }
    for (uint32_t k = 0; k < run.Count; ++k)
    {
      t.Points.push_back(run.Begin + k);
    }
    t.PointValues.insert(t.PointValues.end(), first, first + size_t(run.Count) * c);
  }
  return t;
}

template <typename T>
void TargetDeltas<T>::AddScaled(T weight, T* out, size_t begin, size_t end) const
{
  const size_t c = static_cast<size_t>(this->Components);
  if (!this->Sparse)
  {
    Axpy<false, T>(
      weight, this->Dense.data() + begin * c, nullptr, out + begin * c, (end - begin) * c);
    return;
  }
  // Each moved point is in a span or among the single points, never both, so the order in
  // which the two are added does not change a bit. Spans may straddle the range's ends.
  auto span = std::upper_bound(this->Spans.begin(), this->Spans.end(), begin,
    [](size_t point, const Span& s) { return point < size_t(s.Begin) + s.Count; });
  for (; span != this->Spans.end() && span->Begin < end; ++span)
  {
    const size_t lo = std::max<size_t>(span->Begin, begin);
    const size_t hi = std::min<size_t>(size_t(span->Begin) + span->Count, end);
    Axpy<false, T>(weight, this->SpanValues.data() + (span->First + (lo - span->Begin)) * c,
      nullptr, out + lo * c, (hi - lo) * c);
  }
  const uint32_t* idx = this->Points.data();
  const size_t count = this->Points.size();
  size_t k = static_cast<size_t>(
    std::lower_bound(this->Points.begin(), this->Points.end(), begin) - this->Points.begin());
  if (c == 3)
  {
    // The common case (positions, normals) with the component loop unrolled.
    const T* __restrict d = this->PointValues.data();
    for (; k < count && idx[k] < end; ++k)
    {
      T* o = out + size_t(idx[k]) * 3;
      o[0] += weight * d[3 * k];
      o[1] += weight * d[3 * k + 1];
      o[2] += weight * d[3 * k + 2];
    }
    return;
  }
  for (; k < count && idx[k] < end; ++k)
  {
    const T* d = this->PointValues.data() + k * c;
    T* o = out + size_t(idx[k]) * c;
    for (size_t j = 0; j < c; ++j)
    {
      o[j] += weight * d[j];
    }
  }
}

template <typename T>
void TargetDeltas<T>::PointNorms(std::vector<double>& perPoint) const
{
  const size_t c = static_cast<size_t>(this->Components);
  std::vector<T> expanded;
  if (this->Sparse)
  {
    expanded.resize(this->NumPoints * c);
    this->ToDense(expanded.data());
  }
  const T* deltas = this->Sparse ? expanded.data() : this->Dense.data();
  perPoint.resize(this->NumPoints);
  for (size_t p = 0; p < this->NumPoints; ++p)
  {
    perPoint[p] = Norm(deltas + p * c, this->Components);
  }
}

template <typename T>
void TargetDeltas<T>::ToDense(T* deltas) const
{
  const size_t c = static_cast<size_t>(this->Components);
  if (!this->Sparse)
  {
    std::copy(this->Dense.begin(), this->Dense.end(), deltas);
    return;
  }
  std::fill_n(deltas, this->NumPoints * c, T(0));
  for (const Span& span : this->Spans)
  {
    std::copy_n(this->SpanValues.data() + size_t(span.First) * c, size_t(span.Count) * c,
      deltas + size_t(span.Begin) * c);
  }
  for (size_t k = 0; k < this->Points.size(); ++k)
  {
    std::copy_n(this->PointValues.data() + k * c, c, deltas + size_t(this->Points[k]) * c);
  }
}

template <typename T>
size_t TargetDeltas<T>::GetMemorySize() const
{
  return (this->Dense.size() + this->SpanValues.size() + this->PointValues.size()) * sizeof(T) +
    this->Spans.size() * sizeof(Span) + this->Points.size() * sizeof(uint32_t);
}

template <typename T>
MorphAttribute<T>::MorphAttribute(
  std::string name, AttributeRole role, int components, size_t numPoints)
  : Name(std::move(name))
  , Role(role)
  , Components(components)
  , NumPoints(numPoints)
  , ClampLo(-std::numeric_limits<double>::infinity())
  , ClampHi(std::numeric_limits<double>::infinity())
  , Neutral(numPoints * static_cast<size_t>(std::max(components, 0)), T(0))
{
  if (components < 1)
  {
    std::ostringstream msg;
    msg << "attribute '" << this->Name << "' has " << components << " components";
    throw InputError(msg.str());
  }
}

template <typename T>
void MorphAttribute<T>::SetClampRange(double lo, double hi)
{
  this->ClampLo = lo;
  this->ClampHi = hi;
}

template <typename T>
void MorphAttribute<T>::SetNeutral(const T* values)
{
  std::copy_n(values, this->Neutral.size(), this->Neutral.begin());
}

template <typename T>
void MorphAttribute<T>::AddAbsoluteTarget(const T* values, double sparseCoverage)
{
  std::vector<T> deltas(this->Neutral.size());
  for (size_t i = 0; i < deltas.size(); ++i)
  {
    deltas[i] = values[i] - this->Neutral[i];
  }
  this->AddRelativeTarget(deltas.data(), sparseCoverage);
}

template <typename T>
void MorphAttribute<T>::AddRelativeTarget(const T* deltas, double sparseCoverage)
{
  for (size_t i = 0; i < this->Neutral.size(); ++i)
  {
    if (!std::isfinite(static_cast<double>(deltas[i])))
    {
      std::ostringstream msg;
      msg << "attribute '" << this->Name << "' of target " << this->Targets.size() + 1
          << " has a non-finite value at point " << i / this->Components;
      throw InputError(msg.str());
    }
  }
  this->Targets.push_back(
    TargetDeltas<T>::FromDense(deltas, this->NumPoints, this->Components, sparseCoverage));
}

template <typename T>
void MorphAttribute<T>::Blend(
  const double* weights, size_t numWeights, T* out, size_t begin, size_t end) const
{
  end = std::min(end, this->NumPoints);
  // Blocks small enough that the output stays in cache while every active target is
  // added to it: the deltas stream from memory once, the output is written once.
  for (size_t block = begin; block < end; block += BlockPoints)
  {
    this->BlendBlock(weights, numWeights, out, block, std::min(block + BlockPoints, end));
  }
}

template <typename T>
void MorphAttribute<T>::BlendBlock(
  const double* weights, size_t numWeights, T* out, size_t begin, size_t end) const
{
  const size_t c = static_cast<size_t>(this->Components);
  const size_t n = std::min(numWeights, this->GetNumberOfTargets());
  // Dense targets are gathered up to four at a time (AxpyN); sparse ones scatter. Every element
  // receives its targets' contributions in target order whatever their storage (pending
  // dense targets are added before a sparse one), so the result does not depend on which
  // targets a piece stores sparsely: a point shared by two pieces blends to the same bits.
  const T* dense[MaxTargetsPerPass] = {};
  T denseWeights[MaxTargetsPerPass] = {};
  int pending = 0;
  T* const y = out + begin * c;
  const T* const neutral = this->Neutral.data() + begin * c;
  const size_t count = (end - begin) * c;
  bool started = false; // y holds the neutral plus what was added so far
  const auto startFromNeutral = [&]
  {
    if (!started)
    {
      std::copy_n(neutral, count, y);
      started = true;
    }
  };
  const auto flushPending = [&]
  {
    if (pending == 0)
    {
      return;
    }
    if (started)
    {
      AxpyPending<false>(pending, denseWeights, dense, neutral, y, count);
    }
    else
    {
      AxpyPending<true>(pending, denseWeights, dense, neutral, y, count);
      started = true;
    }
    pending = 0;
  };
  for (size_t i = 1; i < n; ++i)
  {
    if (weights[i] == 0.0)
    {
      continue;
    }
    const TargetDeltas<T>& target = this->Targets[i - 1];
    if (target.IsSparse())
    {
      flushPending();
      startFromNeutral();
      target.AddScaled(static_cast<T>(weights[i]), out, begin, end);
      continue;
    }
    dense[pending] = target.DenseData() + begin * c;
    denseWeights[pending] = static_cast<T>(weights[i]);
    if (++pending == MaxTargetsPerPass)
    {
      flushPending();
    }
  }
  flushPending();
  startFromNeutral(); // no target was active: the neutral itself
  if (this->Role == AttributeRole::Normal && c == 3)
  {
    NormalizeTriples(y, end - begin);
  }
  else if (this->Role == AttributeRole::Normal)
  {
    for (size_t p = begin; p < end; ++p)
    {
      T* v = out + p * c;
      const double len = Norm(v, this->Components);
      if (len > 0.0)
      {
        const T inv = static_cast<T>(1.0 / len);
        for (size_t j = 0; j < c; ++j)
        {
          v[j] *= inv;
        }
      }
    }
  }
  else if (this->Role == AttributeRole::Color)
  {
    const T lo = static_cast<T>(this->ClampLo);
    const T hi = static_cast<T>(this->ClampHi);
    for (size_t i = begin * c; i < end * c; ++i)
    {
      out[i] = std::min(std::max(out[i], lo), hi);
    }
  }
}

template <typename T>
size_t MorphAttribute<T>::GetMemorySize() const
{
  size_t bytes = this->Neutral.size() * sizeof(T);
  for (const auto& t : this->Targets)
  {
    bytes += t.GetMemorySize();
  }
  return bytes;
}

template class TargetDeltas<float>;
template class TargetDeltas<double>;
template class MorphAttribute<float>;
template class MorphAttribute<double>;
} // namespace morphnode
