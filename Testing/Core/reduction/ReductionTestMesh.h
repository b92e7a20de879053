// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A synthetic "face" for the reduction tests: a gently curved grid whose lower part (the
// "mouth") and two small spots (the "eyes") are animated by targets, the rest static.

#include "morph/MorphMesh.h"
#include "reduction/AnimationAwareReduction.h"

#include <cmath>
#include <variant>

namespace reductiontest
{
inline float Height(float x, float y)
{
  return 0.05f * std::sin(3.0f * x) * std::cos(2.0f * y) + 0.02f * std::sin(7.0f * x + 3.0f * y);
}

/// The face in flat arrays, to build variants of it (bad input) from.
struct FlatFace
{
  std::vector<float> Positions;                   ///< 3 per point
  std::vector<uint32_t> Triangles;                ///< 3 per triangle
  std::vector<std::vector<float>> PositionDeltas; ///< 3 per point, one array per target

  size_t GetNumberOfPoints() const { return this->Positions.size() / 3; }

  /// Targets "Neutral", "target0", ...; one float Position attribute.
  morphnode::MorphMesh ToMesh() const
  {
    morphnode::MorphMesh mesh(this->GetNumberOfPoints());
    mesh.SetTargetNames(morphnode::DefaultTargetNames(this->PositionDeltas.size() + 1));
    auto& positions = mesh.AddAttribute<float>("Position", morphnode::AttributeRole::Position, 3);
    positions.SetNeutral(this->Positions.data());
    for (const auto& d : this->PositionDeltas)
    {
      positions.AddRelativeTarget(d.data(), morphnode::MorphMesh::DefaultSparseCoverage);
    }
    mesh.SetTriangles(this->Triangles);
    return mesh;
  }
};

/// The float Position attribute of a mesh.
inline const morphnode::MorphAttribute<float>& PositionsOf(const morphnode::MorphMesh& mesh)
{
  return std::get<morphnode::MorphAttribute<float>>(
    mesh.GetAttribute(static_cast<size_t>(mesh.GetPositionAttribute())));
}

/// Dense position deltas of target `target` (1-based: 0 is the neutral).
inline std::vector<float> DeltasOf(const morphnode::MorphMesh& mesh, size_t target)
{
  std::vector<float> d(3 * mesh.GetNumberOfPoints());
  PositionsOf(mesh).GetTarget(target).ToDense(d.data());
  return d;
}

/// n x n points on [0, 1]^2.
inline FlatFace MakeFlatFace(int n = 41)
{
  FlatFace mesh;
  const float h = 1.0f / static_cast<float>(n - 1);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const float x = i * h, y = j * h;
      mesh.Positions.insert(mesh.Positions.end(), { x, y, Height(x, y) });
    }
  }
  for (int j = 0; j + 1 < n; ++j)
  {
    for (int i = 0; i + 1 < n; ++i)
    {
      const uint32_t a = static_cast<uint32_t>(j * n + i), b = a + 1, c = a + n, d = c + 1;
      mesh.Triangles.insert(mesh.Triangles.end(), { a, b, d, a, d, c });
    }
  }
  const size_t np = mesh.GetNumberOfPoints();
  std::vector<float> jaw(3 * np, 0.0f), smile(3 * np, 0.0f), blinkL(3 * np, 0.0f),
    blinkR(3 * np, 0.0f);
  for (size_t p = 0; p < np; ++p)
  {
    const float x = mesh.Positions[3 * p], y = mesh.Positions[3 * p + 1];
    if (y < 0.35f)
    {
      // the jaw opens: lower points drop and bulge, more towards the chin
      const float s = (0.35f - y) / 0.35f;
      jaw[3 * p + 1] = -0.08f * s * s;
      jaw[3 * p + 2] = 0.04f * std::sin(6.0f * x) * s;
      // the corners of the mouth pull up and out
      const float r2 = (x - 0.5f) * (x - 0.5f) + (y - 0.2f) * (y - 0.2f);
      smile[3 * p] = 0.05f * (x - 0.5f) * std::exp(-r2 / 0.02f);
      smile[3 * p + 1] = 0.03f * std::exp(-r2 / 0.02f);
    }
    auto spot = [&](std::vector<float>& d, float cx)
    {
      const float r2 = (x - cx) * (x - cx) + (y - 0.75f) * (y - 0.75f);
      if (r2 < 0.01f)
      {
        d[3 * p + 1] = -0.04f * std::exp(-r2 / 0.002f);
        d[3 * p + 2] = 0.01f * std::exp(-r2 / 0.002f);
      }
    };
    spot(blinkL, 0.3f);
    spot(blinkR, 0.7f);
  }
  mesh.PositionDeltas = { jaw, smile, blinkL, blinkR };
  return mesh;
}

inline morphnode::MorphMesh MakeFace(int n = 41)
{
  return MakeFlatFace(n).ToMesh();
}
} // namespace reductiontest
