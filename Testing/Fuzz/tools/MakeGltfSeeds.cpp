// SPDX-License-Identifier: BSD-3-Clause
// Writes the seed corpus of FuzzGltf (Testing/Fuzz/corpus/gltf): small glTF and GLB files
// that reach every part of the loader, and a few damaged ones kept as regression inputs.
// Not built by CMake; run once when the seeds change:
//   g++ -std=c++17 -ITesting/Core/gltf Testing/Fuzz/tools/MakeGltfSeeds.cpp -o /tmp/seeds &&
//   /tmp/seeds Testing/Fuzz/corpus/gltf
#include "GltfAnimatedTestFiles.h"
#include "GltfSkinnedTestFiles.h"
#include "GltfTestFiles.h"

#include <cstdio>
#include <fstream>
#include <string>

using gltftest::Builder;
using gltftest::json;

namespace
{
std::string Folder;

void Write(const std::string& name, const std::string& bytes)
{
  std::ofstream(Folder + "/" + name, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  std::printf("%s: %zu bytes\n", name.c_str(), bytes.size());
}
} // namespace

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: %s <corpus folder>\n", argv[0]);
    return 2;
  }
  Folder = argv[1];

  const Builder quad = gltftest::Quad();
  Write("quad.glb", quad.Glb());
  Write("quad-data-uri.gltf", quad.GltfWithDataUri());

  {
    Builder b = gltftest::Quad();
    b.Doc["meshes"][0]["primitives"][0]["indices"] = b.Indices({ 0, 1, 3, 2 });
    b.Doc["meshes"][0]["primitives"][0]["mode"] = 5;
    Write("quad-strip.glb", b.Glb());
    b.Doc["meshes"][0]["primitives"][0]["indices"] = b.Indices({ 0, 1, 2, 3 });
    b.Doc["meshes"][0]["primitives"][0]["mode"] = 6;
    Write("quad-fan.glb", b.Glb());
  }
  {
    // Matrices three deep, one mirroring.
    Builder b = gltftest::Quad();
    b.Doc["nodes"][0] = { { "matrix", { 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, -0.5, 0, 1, 2, 3, 1 } }, { "children", { 1 } } };
    b.Doc["nodes"][1].erase("translation");
    b.Doc["nodes"][1].erase("rotation");
    b.Doc["nodes"][1]["matrix"] = { 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 };
    b.Doc["nodes"][1]["children"] = { 2 };
    b.Node({ { "name", "Leaf" }, { "mesh", 0 }, { "scale", { 1, 2, 3 } }, { "weights", { 1, 0.5 } } });
    Write("nested-matrix.glb", b.Glb());
  }
  {
    Builder b = gltftest::Quad();
    b.Doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] =
      b.SparseVec3(4, { 1, 3 }, { 0, 0, 7, 0, 0, 9 }, { 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4 });
    Write("sparse-on-base.glb", b.Glb());
  }
  {
    // CUBICSPLINE translation and scale (in-tangent, value, out-tangent per key), STEP weights.
    Builder b = gltftest::Quad();
    const int times = b.Floats({ 0, 1 }, "SCALAR", 1);
    const int moves = b.Floats({ 0, 0, 0, 1, 2, 3, 0, 0, 0, 0, 0, 0, 4, 5, 6, 0, 0, 0 }, "VEC3", 3);
    const int scales = b.Floats({ 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 2, 2, 2, 0, 0, 0 }, "VEC3", 3);
    b.Doc["animations"].push_back({ { "name", "Cubic" },
      { "samplers",
        { { { "input", times }, { "output", moves }, { "interpolation", "CUBICSPLINE" } },
          { { "input", times }, { "output", scales }, { "interpolation", "CUBICSPLINE" } } } },
      { "channels",
        { { { "sampler", 0 }, { "target", { { "node", 1 }, { "path", "translation" } } } },
          { { "sampler", 1 }, { "target", { { "node", 0 }, { "path", "scale" } } } } } } });
    Write("animations.glb", b.Glb());
  }
  {
    // Interleaved points and normals (byteStride 24), byte indices, 16-bit RGBA colours,
    // two primitives, no scene (every root is read).
    Builder b;
    const std::vector<float> interleaved = { 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1 };
    const int view = b.View(interleaved, 24);
    const int position = b.Accessor({ { "bufferView", view }, { "componentType", gltftest::Float }, { "count", 3 }, { "type", "VEC3" } });
    const int normal = b.Accessor(
      { { "bufferView", view }, { "byteOffset", 12 }, { "componentType", gltftest::Float }, { "count", 3 }, { "type", "VEC3" } });
    const int indices = b.Accessor({ { "bufferView", b.View(std::vector<uint8_t>{ 0, 1, 2, 0 }) },
      { "componentType", gltftest::UnsignedByte }, { "count", 3 }, { "type", "SCALAR" } });
    const int color = b.Accessor({ { "bufferView", b.View(std::vector<uint16_t>(12, 40000)) },
      { "componentType", gltftest::UnsignedShort }, { "normalized", true }, { "count", 3 }, { "type", "VEC4" } });
    b.Mesh({ { "primitives",
      { { { "attributes", { { "POSITION", position }, { "NORMAL", normal }, { "COLOR_0", color } } }, { "indices", indices } },
        { { "attributes", { { "POSITION", position } } } } } } });
    b.Node({ { "mesh", 0 } });
    b.Node({ { "mesh", 0 }, { "translation", { 0, 0, 1 } } });
    Write("interleaved-no-scene.glb", b.Glb());
  }
  {
    Builder b;
    const int position = b.Vec3({ 0, 0, 0, 1, 0, 0, 0, 1, 0 });
    b.Mesh({ { "primitives", { { { "attributes", { { "POSITION", position } } } } } } });
    b.Node({ { "mesh", 0 } });
    b.Doc["scenes"] = { { { "nodes", { 0 } } } };
    Write("triangle.gltf", b.GltfWithDataUri());
  }

  {
    // What is validated but not read: images (in a buffer view and as a data URI),
    // textures, samplers, cameras, skins, appearance extensions, a custom attribute whose
    // name needs escaping in a JSON pointer, a channel without a node.
    Builder b = gltftest::Quad();
    const int image = b.View(std::vector<uint8_t>{ 0x89, 'P', 'N', 'G' });
    b.Doc["images"] = { { { "bufferView", image }, { "mimeType", "image/png" } },
      { { "uri", "data:image/png;base64,iVBORw0K" } } };
    b.Doc["samplers"] = { json::object() };
    b.Doc["textures"] = { { { "source", 0 }, { "sampler", 0 } } };
    b.Doc["cameras"] = { { { "type", "perspective" }, { "perspective", { { "yfov", 0.8 }, { "znear", 0.01 } } } } };
    b.Doc["nodes"][0]["camera"] = 0;
    b.Doc["extensionsUsed"] = { "KHR_materials_emissive_strength" };
    b.Doc["extensionsRequired"] = { "KHR_materials_emissive_strength" };
    b.Doc["meshes"][0]["primitives"][0]["attributes"]["_MY/ATTR~1"] = 1;
    b.Doc["animations"][0]["channels"].push_back({ { "sampler", 0 }, { "target", { { "path", "rotation" } } } });
    Write("unread-parts.glb", b.Glb());
  }
  {
    // Normalized integer outputs (rotation as SHORT, weights as UNSIGNED_BYTE), byte
    // sparse indices over three points, a sparse index accessor.
    Builder b = gltftest::Quad();
    const int rotations = b.Accessor({ { "bufferView", b.View(std::vector<int16_t>{ 0, 0, 0, 32767, 0, 0, 12540, 30273, 0, 0, 23170, 23170 }) },
      { "componentType", gltftest::Short }, { "normalized", true }, { "count", 3 }, { "type", "VEC4" } });
    const int weights = b.Accessor({ { "bufferView", b.View(std::vector<uint8_t>{ 0, 0, 255, 0, 0, 255, 0, 0 }) },
      { "componentType", gltftest::UnsignedByte }, { "normalized", true }, { "count", 6 }, { "type", "SCALAR" } });
    b.Doc["animations"][0]["samplers"][0]["output"] = rotations;
    b.Doc["animations"][0]["samplers"][1]["output"] = weights;
    const int iv = b.View(std::vector<uint8_t>{ 0, 2, 3, 0 });
    const int vv = b.View(std::vector<float>{ 1, 0, 0, 0, 1, 0, 0, 0, 1 });
    b.Doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = b.Accessor({ { "componentType", gltftest::Float },
      { "count", 4 }, { "type", "VEC3" },
      { "sparse", { { "count", 3 }, { "indices", { { "bufferView", iv }, { "componentType", gltftest::UnsignedByte } } },
                    { "values", { { "bufferView", vv } } } } } });
    const int base = b.View(std::vector<uint16_t>{ 0, 1, 2, 0, 2, 3 });
    const int si = b.View(std::vector<uint16_t>{ 5, 0 });
    const int sv = b.View(std::vector<uint16_t>{ 1, 0 });
    b.Doc["meshes"][0]["primitives"][0]["indices"] = b.Accessor({ { "bufferView", base },
      { "componentType", gltftest::UnsignedShort }, { "count", 6 }, { "type", "SCALAR" },
      { "sparse", { { "count", 1 }, { "indices", { { "bufferView", si }, { "componentType", gltftest::UnsignedShort } } },
                    { "values", { { "bufferView", sv } } } } } });
    Write("normalized-and-sparse.glb", b.Glb());
  }

  // Damaged inputs kept as regression tests (each must be rejected without a crash).
  {
    // A BIN chunk that claims the 8 bytes of its own header more than the file holds, and
    // a buffer as long: tinygltf 2.7 accepts the length and copies past the end of the
    // input (ASan: heap-buffer-overflow in ParseBuffer).
    json doc = quad.Finished();
    doc["buffers"][0]["byteLength"] = doc["buffers"][0]["byteLength"].get<uint32_t>() + 8;
    std::string g = Builder::MakeGlb(doc.dump(), quad.PaddedBin());
    uint32_t jsonLength, binLength;
    std::memcpy(&jsonLength, &g[12], 4);
    std::memcpy(&binLength, &g[20 + jsonLength], 4);
    binLength += 8;
    std::memcpy(&g[20 + jsonLength], &binLength, 4);
    Write("damaged-bin-chunk-past-end.glb", g);
  }
  {
    json doc = quad.Finished();
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 4294967296ull; // tinygltf: 0
    Write("damaged-index-2pow32.glb", Builder::MakeGlb(doc.dump(), quad.PaddedBin()));
  }
  {
    json doc = quad.Finished();
    doc["nodes"][1]["children"] = { 0 };
    Write("damaged-node-cycle.glb", Builder::MakeGlb(doc.dump(), quad.PaddedBin()));
  }
  {
    json doc = quad.Finished();
    doc["accessors"][6]["sparse"]["count"] = 3; // more indices than its buffer view holds
    Write("damaged-sparse-count.glb", Builder::MakeGlb(doc.dump(), quad.PaddedBin()));
  }
  {
    json doc = quad.Finished();
    doc["accessors"][0]["count"] = 400;
    Write("damaged-accessor-count.glb", Builder::MakeGlb(doc.dump(), quad.PaddedBin()));
  }
  {
    // The animated head of the animation tests (GltfAnimatedTestFiles.h): weights LINEAR,
    // STEP and CUBICSPLINE on two meshes, node TRS; and its eye given by a matrix, which
    // the loader accepts and GltfAnimationPlayer refuses (glTF animates only TRS nodes).
    const Builder head = gltftest::AnimatedHead();
    Write("animated-head.glb", head.Glb());
    json doc = head.Finished();
    doc["nodes"][2].erase("translation");
    doc["nodes"][2]["matrix"] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.3, 0.2, 0.1, 1 };
    Write("animated-matrix-node.glb", Builder::MakeGlb(doc.dump(), head.PaddedBin()));
  }
  {
    // A skin: nested joints, inverse bind matrices, two weight sets (unsigned byte joints with
    // float weights, unsigned short joints with normalized byte weights), and the same with a
    // joint index beyond the skin's joints.
    const Builder skinned = gltftest::SkinnedQuad();
    Write("skinned-quad.glb", skinned.Glb());
    json doc = skinned.Finished();
    doc["skins"][0]["joints"] = { 1 };
    Write("damaged-skin-joint-index.glb", Builder::MakeGlb(doc.dump(), skinned.PaddedBin()));
  }
  return 0;
}
