// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file LipMeasures.h
/// @brief Where a face's lips are and how far apart, measured on its geometry: the lip
/// contact pair (the midline vertices of the upper and the lower lip that touch at rest and
/// part when the mouth opens) and the mouth corners. What the optimizer studies and the
/// tests of closures (p, b, m) and roundings (o, u) measure, on any face without naming its
/// vertices.
///
/// A face here is one part's points (3 floats each) and the dense deltas of its targets
/// (3 floats per point, glTF's relative form); +Y is up, +X the face's left, +Z forward.

#include <array>
#include <cstddef>
#include <vector>

namespace morphnode
{
struct LipPair
{
  size_t Upper = 0;
  size_t Lower = 0;
  double RestGap = 0.0; ///< y(upper) - y(lower) at rest
  double Opening = 0.0; ///< how much the gap grows with the opening deltas
};

/// The lip pair of a part: among the points within `midline` of the part's x centre, the
/// pair (upper above lower, at most `touch` apart at rest and at most `midline` apart in x)
/// whose vertical gap the deltas `opening` (3 per point, e.g. an open vowel's) widen most.
/// Returns false when the part has no such pair (no midline points, nothing opens).
bool FindLipPair(const std::vector<float>& points, const std::vector<double>& opening,
  double midline, double touch, LipPair& pair);

/// The mouth corners: the points that `spread` (3 per point, e.g. a smile's or a stretch's
/// deltas) moves most sideways, one on each side (+X first). False when nothing moves sideways.
bool FindMouthCorners(const std::vector<float>& points, const std::vector<double>& spread,
  std::array<size_t, 2>& corners);

/// A point of the part blended with relative weights: points[p] + sum_t w[t] deltas[t][p]
/// (deltas[t] may be nullptr for a target that does not move the part).
std::array<double, 3> BlendPoint(const std::vector<float>& points,
  const std::vector<const float*>& deltas, const double* weights, size_t p);
} // namespace morphnode
