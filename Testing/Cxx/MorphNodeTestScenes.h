// SPDX-License-Identifier: BSD-3-Clause
// A small glTF head made in memory, shared by the tests of the reader and of the morph node
// on scenes: four parts on nested nodes (matrix, TRS, matrix), a target name on only some
// parts, a part without targets, vertex colours.
#ifndef MorphNodeTestScenes_h
#define MorphNodeTestScenes_h

#include "Core/gltf/GltfTestFiles.h"

#include <array>
#include <fstream>
#include <string>
#include <vector>

namespace morphnode_test
{
namespace scenes
{
/// Writes `bytes` into the test output folder; the path.
inline std::string WriteFile(const std::string& name, const std::string& bytes)
{
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/" + name;
  std::ofstream(path, std::ios::binary)
    .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

using Vec3 = std::array<double, 3>;

// The transforms of the test scene, each written out by hand (not through the loader's
// matrices): Head = matrix (scale 2, then translate (10, 0, 0)), its child Jaw = TRS
// (rotation 90 degrees about z, translation (0, 1, 0)), Jaw's child Tooth = matrix
// (translation (0, 0, 1)); EyeLeft, Head's second child, translation (1, 1, 1).
inline Vec3 HeadMap(Vec3 p)
{
  return { 2 * p[0] + 10, 2 * p[1], 2 * p[2] };
}
inline Vec3 JawMap(Vec3 p)
{
  return HeadMap({ -p[1], p[0] + 1, p[2] });
}
inline Vec3 ToothMap(Vec3 p)
{
  return JawMap({ p[0], p[1], p[2] + 1 });
}
inline Vec3 EyeMap(Vec3 p)
{
  return HeadMap({ p[0] + 1, p[1] + 1, p[2] + 1 });
}
/// A delta only turns and scales: Head's 2 and Jaw's rotation.
inline Vec3 JawDelta(Vec3 d)
{
  return { -2 * d[1], 2 * d[0], 2 * d[2] };
}

inline const std::vector<float> QuadPoints{ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
inline const std::vector<float> QuadNormals{ 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 };

/// A head of four parts on nested nodes: Jaw's mesh "Skin" has two primitives (materials
/// Skin and Lips) with the targets Lift and Raise; Tooth's mesh "Teeth" has Raise only;
/// EyeLeft's mesh "Eye" has none, and vertex colours.
inline gltftest::Builder TestHead()
{
  gltftest::Builder b;
  const int position = b.Vec3(QuadPoints);
  const int normal = b.Vec3(QuadNormals);
  const int indices = b.Indices({ 0, 1, 2, 0, 2, 3 });
  const int lift = b.Vec3({ 0, 0, 0.1f, 0, 0, 0.2f, 0, 0, 0.3f, 0, 0, 0.4f });
  const int liftNormal = b.Vec3({ 0.1f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 });
  const int raise = b.SparseVec3(4, { 2 }, { 0, 0.5f, 0 }); // sparse, no bufferView
  const int raiseNormal = b.Vec3(std::vector<float>(12, 0.f));
  const int raiseTooth = b.Vec3({ 0.3f, 0, 0, 0.3f, 0, 0, 0, 0, 0, 0, 0, 0 });
  const int color = b.Accessor(
    { { "bufferView",
        b.View(std::vector<float>{ 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 0.5f, 1, 1, 1, 1 }) },
      { "componentType", gltftest::Float }, { "count", 4 }, { "type", "VEC4" } });
  const gltftest::json targets = { { { "POSITION", lift }, { "NORMAL", liftNormal } },
    { { "POSITION", raise }, { "NORMAL", raiseNormal } } };
  b.Mesh({ { "name", "Skin" },
    { "primitives",
      { { { "attributes", { { "POSITION", position }, { "NORMAL", normal } } },
          { "indices", indices }, { "material", 0 }, { "targets", targets } },
        { { "attributes", { { "POSITION", position }, { "NORMAL", normal } } },
          { "indices", indices }, { "material", 1 }, { "targets", targets } } } },
    { "extras", { { "targetNames", { "Lift", "Raise" } } } } });
  b.Mesh({ { "name", "Teeth" },
    { "primitives",
      { { { "attributes", { { "POSITION", position }, { "NORMAL", normal } } },
        { "indices", indices }, { "material", 2 },
        { "targets", { { { "POSITION", raiseTooth } } } } } } },
    { "extras", { { "targetNames", { "Raise" } } } } });
  b.Mesh({ { "name", "Eye" },
    { "primitives",
      { { { "attributes",
            { { "POSITION", position }, { "NORMAL", normal }, { "COLOR_0", color } } },
        { "indices", indices } } } } });
  b.Doc["materials"] = {
    { { "name", "Skin" },
      { "pbrMetallicRoughness", { { "baseColorFactor", { 0.8, 0.6, 0.5, 1 } } } } },
    { { "name", "Lips" },
      { "pbrMetallicRoughness", { { "baseColorFactor", { 0.7, 0.3, 0.3, 1 } } } } },
    { { "name", "Enamel" },
      { "pbrMetallicRoughness", { { "baseColorFactor", { 0.9, 0.9, 0.85, 1 } } } } }
  };
  b.Node({ { "name", "Head" }, { "matrix", { 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 10, 0, 0, 1 } },
    { "children", { 1, 3 } } });
  b.Node({ { "name", "Jaw" }, { "mesh", 0 }, { "translation", { 0, 1, 0 } },
    { "rotation", { 0, 0, 0.70710678118654752, 0.70710678118654752 } }, { "children", { 2 } } });
  b.Node({ { "name", "Tooth" }, { "mesh", 1 },
    { "matrix", { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 } } });
  b.Node({ { "name", "EyeLeft" }, { "mesh", 2 }, { "translation", { 1, 1, 1 } } });
  b.Doc["scenes"] = { { { "name", "TestHead" }, { "nodes", { 0 } } } };
  b.Doc["scene"] = 0;
  return b;
}

} // namespace scenes
} // namespace morphnode_test

#endif
