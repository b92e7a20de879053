// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfSkinnedTestFiles.h
/// @brief A small skinned glTF made in memory (GltfTestFiles.h's builder) with hand-computed
/// results, for the core tests, the VTK cross-check and the fuzz seeds.
///
/// Nodes: 0 `Root` (translation (0, 1, 0)) with children 1 and 3; 1 `J1` (translation
/// (1, 0, 0), 90 degrees about +Z) with child 2 `J2` (translation (0, 1, 0)); 3 `Mesh`
/// (translation (100, 0, 0), which glTF says to ignore: the mesh is skinned). Skin 0: joints
/// J1, J2 with inverse bind matrices translate(-1, -1, 0) and translate(-1, -3, 0): a bind
/// pose unlike the node pose (J2 was bound at (1, 3, 0), it stands at (0, 1, 0) + ...).
/// Joint matrices: M1 = T(1, 1, 0) Rz(90) T(-1, -1, 0), M2 = T(1, 1, 0) Rz(90) T(-1, -2, 0).
///
/// Four points, z = 0, normals +Z; JOINTS_0 unsigned byte with float WEIGHTS_0, JOINTS_1
/// unsigned short with normalized unsigned byte WEIGHTS_1:
///   p0 (1, 1, 0): J1 only                    -> (1, 1, 0)
///   p1 (2, 1, 0): J1 only                    -> (1, 2, 0)
///   p2 (1, 2, 0): J2 only, from set 1        -> (1, 1, 0)
///   p3 (3, 1, 0): J1 0.25 (set 0) + J2 1.0 (set 1), renormalized 0.2 / 0.8
///                 -> 0.2 (1, 3, 0) + 0.8 (2, 3, 0) = (1.8, 3, 0)
/// Targets: `Up` moves p3 by (0, 1, 0), `Right` moves p0 by (1, 0, 0) (bind space). Morph
/// first, then skin: `Up` at 1 puts p3 at 0.2 (0, 3, 0) + 0.8 (1, 3, 0) = (0.8, 3, 0), a rest
/// delta of (-1, 0, 0); skinning first and adding the delta would give (1.8, 4, 0).

#include "GltfTestFiles.h"

#include <cmath>

namespace gltftest
{
inline Builder SkinnedQuad()
{
  Builder b;
  const int position = b.Vec3({ 1, 1, 0, 2, 1, 0, 1, 2, 0, 3, 1, 0 });
  const int normal = b.Vec3({ 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 });
  const int joints0 =
    b.Accessor({ { "bufferView",
                   b.View(std::vector<uint8_t>{ 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 }) },
      { "componentType", UnsignedByte }, { "count", 4 }, { "type", "VEC4" } });
  const int weights0 = b.Floats({ 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0.25f, 0, 0, 0 }, "VEC4", 4);
  const int joints1 = b.Accessor(
    { { "bufferView",
        b.View(std::vector<uint16_t>{ 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0 }) },
      { "componentType", UnsignedShort }, { "count", 4 }, { "type", "VEC4" } });
  const int weights1 = b.Accessor(
    { { "bufferView",
        b.View(std::vector<uint8_t>{ 0, 0, 0, 0, 0, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0 }) },
      { "componentType", UnsignedByte }, { "normalized", true }, { "count", 4 },
      { "type", "VEC4" } });
  const int indices = b.Indices({ 0, 1, 2, 1, 3, 2 });
  const int up = b.Vec3({ 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0 });
  const int right = b.Vec3({ 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 });
  b.Mesh({ { "name", "SkinnedQuad" },
    { "primitives",
      { { { "attributes",
            { { "POSITION", position }, { "NORMAL", normal }, { "JOINTS_0", joints0 },
              { "WEIGHTS_0", weights0 }, { "JOINTS_1", joints1 }, { "WEIGHTS_1", weights1 } } },
        { "indices", indices },
        { "targets", { { { "POSITION", up } }, { { "POSITION", right } } } } } } },
    { "weights", { 0, 0 } }, { "extras", { { "targetNames", { "Up", "Right" } } } } });
  // Inverse bind matrices, column-major.
  const std::vector<float> ibm = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, -1, 0, 1, //
    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, -3, 0, 1 };
  const int ibmAccessor = b.Accessor({ { "bufferView", b.View(ibm) }, { "componentType", Float },
    { "count", 2 }, { "type", "MAT4" } });
  const double s = std::sqrt(0.5);
  b.Node({ { "name", "Root" }, { "translation", { 0, 1, 0 } }, { "children", { 1, 3 } } });
  b.Node({ { "name", "J1" }, { "translation", { 1, 0, 0 } }, { "rotation", { 0, 0, s, s } },
    { "children", { 2 } } });
  b.Node({ { "name", "J2" }, { "translation", { 0, 1, 0 } } });
  b.Node({ { "name", "Mesh" }, { "mesh", 0 }, { "skin", 0 }, { "translation", { 100, 0, 0 } } });
  b.Doc["skins"] = json::array({ { { "name", "Rig" }, { "joints", { 1, 2 } }, { "skeleton", 1 },
    { "inverseBindMatrices", ibmAccessor } } });
  b.Doc["scenes"] = json::array({ { { "nodes", { 0 } } } });
  b.Doc["scene"] = 0;
  return b;
}

/// The rest points of SkinnedQuad (x, y, z per point).
inline std::vector<double> SkinnedQuadRest()
{
  return { 1, 1, 0, 1, 2, 0, 1, 1, 0, 1.8, 3, 0 };
}
} // namespace gltftest
