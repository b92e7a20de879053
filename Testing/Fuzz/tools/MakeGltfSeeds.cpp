// SPDX-License-Identifier: BSD-3-Clause
// Writes the seed corpus of FuzzGltf (Testing/Fuzz/corpus/gltf): small glTF and GLB files
// that reach every part of the loader, and a few damaged ones kept as regression inputs.
// Not built by CMake; run once when the seeds change:
//   g++ -std=c++17 -ITesting/Core/gltf Testing/Fuzz/tools/MakeGltfSeeds.cpp -lmeshoptimizer -o
//   /tmp/seeds && /tmp/seeds Testing/Fuzz/corpus/gltf
#include "GltfAnimatedTestFiles.h"
#include "GltfSkinnedTestFiles.h"
#include "GltfTestFiles.h"

#include <meshoptimizer.h>

#include <cstdio>
#include <fstream>
#include <string>

using gltftest::Builder;
using gltftest::json;

namespace
{
std::string Folder;

// 2 x 2 RGBA images (red at alpha 128, green), as PNG, lossless WebP (cwebp) and JPEG.
const std::vector<unsigned char> Png = { 0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00,
  0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x06,
  0x00, 0x00, 0x00, 0x72, 0xb6, 0x0d, 0x24, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78,
  0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0xd0, 0xc0, 0xf0, 0x1f, 0x0c, 0x21, 0x0c, 0x00, 0x3c, 0x5f, 0x06,
  0xfb, 0x43, 0x98, 0x42, 0x3e, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60,
  0x82 };
const std::vector<unsigned char> Webp = { 0x52, 0x49, 0x46, 0x46, 0x1e, 0x00, 0x00, 0x00, 0x57,
  0x45, 0x42, 0x50, 0x56, 0x50, 0x38, 0x4c, 0x12, 0x00, 0x00, 0x00, 0x2f, 0x01, 0x40, 0x00, 0x10,
  0x0f, 0xb0, 0xff, 0xf3, 0x1f, 0x0f, 0xfc, 0x8f, 0x0a, 0x19, 0xd1, 0xff, 0x00 };
const std::vector<unsigned char> Jpeg = { 0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0x49,
  0x46, 0x00, 0x01, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0xff, 0xdb, 0x00, 0x43, 0x00,
  0x02, 0x01, 0x01, 0x01, 0x01, 0x01, 0x02, 0x01, 0x01, 0x01, 0x02, 0x02, 0x02, 0x02, 0x02, 0x04,
  0x03, 0x02, 0x02, 0x02, 0x02, 0x05, 0x04, 0x04, 0x03, 0x04, 0x06, 0x05, 0x06, 0x06, 0x06, 0x05,
  0x06, 0x06, 0x06, 0x07, 0x09, 0x08, 0x06, 0x07, 0x09, 0x07, 0x06, 0x06, 0x08, 0x0b, 0x08, 0x09,
  0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x06, 0x08, 0x0b, 0x0c, 0x0b, 0x0a, 0x0c, 0x09, 0x0a, 0x0a, 0x0a,
  0xff, 0xdb, 0x00, 0x43, 0x01, 0x02, 0x02, 0x02, 0x02, 0x02, 0x02, 0x05, 0x03, 0x03, 0x05, 0x0a,
  0x07, 0x06, 0x07, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a,
  0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a,
  0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0x0a,
  0x0a, 0x0a, 0x0a, 0x0a, 0x0a, 0xff, 0xc2, 0x00, 0x11, 0x08, 0x00, 0x02, 0x00, 0x02, 0x03, 0x01,
  0x22, 0x00, 0x02, 0x11, 0x01, 0x03, 0x11, 0x01, 0xff, 0xc4, 0x00, 0x15, 0x00, 0x01, 0x01, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x05, 0xff,
  0xc4, 0x00, 0x14, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x08, 0xff, 0xda, 0x00, 0x0c, 0x03, 0x01, 0x00, 0x02, 0x10, 0x03, 0x10,
  0x00, 0x00, 0x01, 0xb2, 0x0b, 0x84, 0x6f, 0xff, 0xc4, 0x00, 0x15, 0x10, 0x01, 0x01, 0x00, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x05, 0x35, 0xff, 0xda,
  0x00, 0x08, 0x01, 0x01, 0x00, 0x01, 0x05, 0x02, 0x1a, 0x3f, 0xff, 0xc4, 0x00, 0x1b, 0x11, 0x00,
  0x00, 0x07, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x01, 0x03, 0x04, 0x06, 0x36, 0x73, 0xb2, 0xff, 0xda, 0x00, 0x08, 0x01, 0x03, 0x01, 0x01, 0x3f,
  0x01, 0x94, 0x59, 0x9f, 0x6c, 0xa7, 0x66, 0x3f, 0xff, 0xc4, 0x00, 0x19, 0x11, 0x00, 0x01, 0x05,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x02,
  0x03, 0x33, 0x71, 0xff, 0xda, 0x00, 0x08, 0x01, 0x02, 0x01, 0x01, 0x3f, 0x01, 0x9e, 0xe7, 0x6a,
  0x9f, 0xff, 0xc4, 0x00, 0x18, 0x10, 0x00, 0x02, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x04, 0x74, 0xb2, 0xff, 0xda, 0x00, 0x08, 0x01,
  0x01, 0x00, 0x06, 0x3f, 0x02, 0x89, 0x59, 0x32, 0x7f, 0xff, 0xc4, 0x00, 0x16, 0x10, 0x00, 0x03,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x51,
  0xf0, 0xff, 0xda, 0x00, 0x08, 0x01, 0x01, 0x00, 0x01, 0x3f, 0x21, 0xa2, 0x87, 0xff, 0xda, 0x00,
  0x0c, 0x03, 0x01, 0x00, 0x02, 0x00, 0x03, 0x00, 0x00, 0x00, 0x10, 0xf3, 0xff, 0xc4, 0x00, 0x14,
  0x11, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00, 0xff, 0xda, 0x00, 0x08, 0x01, 0x03, 0x01, 0x01, 0x3f, 0x10, 0x45, 0xff, 0xc4, 0x00,
  0x17, 0x11, 0x00, 0x03, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00, 0x00, 0x01, 0x51, 0xf0, 0xff, 0xda, 0x00, 0x08, 0x01, 0x02, 0x01, 0x01, 0x3f, 0x10,
  0xcc, 0xac, 0xff, 0xc4, 0x00, 0x14, 0x10, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xda, 0x00, 0x08, 0x01, 0x01, 0x00, 0x01,
  0x3f, 0x10, 0x6d, 0xff, 0xd9 };

/// A triangle with TEXCOORD_0 and TEXCOORD_1 and materials using every texture slot: images
/// PNG, WebP (through EXT_texture_webp, its fallback the PNG), JPEG, a broken one, and a
/// KTX2-only texture; samplers; KHR_texture_transform; MASK, BLEND, unlit, emissive
/// strength and an ignored extension.
Builder TexturedTriangle()
{
  Builder b;
  const int p = b.Vec3({ 0, 0, 0, 1, 0, 0, 0, 1, 0 });
  const int uv = b.Floats({ 0, 0, 1, 0, 0, 1 }, "VEC2", 2);
  const int uv1 = b.View(std::vector<uint16_t>{ 0, 0, 65535, 0, 0, 65535 });
  const int uv1a = b.Accessor({ { "bufferView", uv1 }, { "componentType", gltftest::UnsignedShort },
    { "normalized", true }, { "count", 3 }, { "type", "VEC2" } });
  const int i = b.Indices({ 0, 1, 2 });
  b.Mesh({ { "primitives",
    { { { "attributes", { { "POSITION", p }, { "TEXCOORD_0", uv }, { "TEXCOORD_1", uv1a } } },
        { "indices", i }, { "material", 0 } },
      { { "attributes", { { "POSITION", p }, { "TEXCOORD_0", uv } } }, { "indices", i },
        { "material", 1 } } } } });
  b.Node({ { "mesh", 0 } });
  b.Doc["scenes"] = { { { "nodes", { 0 } } } };
  const int png = b.View(Png), webp = b.View(Webp), jpeg = b.View(Jpeg);
  const int broken = b.View(std::vector<unsigned char>{ 0xff, 0xd8, 0xff, 0, 1, 2, 3, 4 });
  b.Doc["images"] = { { { "bufferView", png }, { "mimeType", "image/png" } },
    { { "bufferView", webp }, { "mimeType", "image/webp" } },
    { { "bufferView", jpeg }, { "mimeType", "image/jpeg" } },
    { { "bufferView", broken }, { "mimeType", "image/jpeg" } },
    { { "uri", "data:image/png;base64,AAAA" } } };
  b.Doc["samplers"] = { { { "magFilter", 9728 }, { "minFilter", 9984 }, { "wrapS", 33071 },
    { "wrapT", 33648 } } };
  b.Doc["textures"] = { { { "source", 0 }, { "sampler", 0 },
                          { "extensions", { { "EXT_texture_webp", { { "source", 1 } } } } } },
    { { "source", 2 } }, { { "source", 3 } },
    { { "extensions", { { "KHR_texture_basisu", { { "source", 4 } } } } } } };
  json transform = { { "KHR_texture_transform",
    { { "offset", { 0.5, 0 } }, { "rotation", 0.3 }, { "scale", { 2, 2 } }, { "texCoord", 1 } } } };
  b.Doc["materials"] = {
    { { "name", "Everything" },
      { "pbrMetallicRoughness",
        { { "baseColorFactor", { 1, 0.5, 0.5, 0.8 } }, { "baseColorTexture", { { "index", 0 } } },
          { "metallicRoughnessTexture", { { "index", 1 }, { "extensions", transform } } },
          { "metallicFactor", 0.2 }, { "roughnessFactor", 0.7 } } },
      { "normalTexture", { { "index", 2 }, { "scale", 0.5 } } },
      { "occlusionTexture", { { "index", 1 }, { "strength", 0.5 } } },
      { "emissiveTexture", { { "index", 3 }, { "texCoord", 1 } } },
      { "emissiveFactor", { 1, 1, 0 } }, { "alphaMode", "MASK" }, { "alphaCutoff", 0.6 },
      { "doubleSided", true },
      { "extensions",
        { { "KHR_materials_emissive_strength", { { "emissiveStrength", 3 } } },
          { "KHR_materials_clearcoat", { { "clearcoatFactor", 1 } } } } } },
    { { "name", "Glass" }, { "alphaMode", "BLEND" },
      { "extensions", { { "KHR_materials_unlit", json::object() } } } }
  };
  b.Doc["extensionsUsed"] = { "EXT_texture_webp", "KHR_texture_transform", "KHR_texture_basisu",
    "KHR_materials_unlit", "KHR_materials_emissive_strength", "KHR_materials_clearcoat" };
  b.Doc["extensionsRequired"] = { "EXT_texture_webp" };
  return b;
}

/// A quad whose positions, normals (OCTAHEDRAL filter) and indices are
/// EXT_meshopt_compression streams, with the fallback buffer the extension defines.
std::string MeshoptQuad()
{
  const std::vector<float> positions = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
  const std::vector<int8_t> normals = { 0, 0, 127, 127, 0, 0, 127, 127, 0, 0, 127, 127, 0, 0, 127,
    127 };
  const std::vector<uint16_t> indices = { 0, 1, 2, 0, 2, 3 };
  std::vector<unsigned char> bin;
  auto append = [&bin](const std::vector<unsigned char>& bytes)
  {
    const size_t offset = bin.size();
    bin.insert(bin.end(), bytes.begin(), bytes.end());
    while (bin.size() % 4)
    {
      bin.push_back(0);
    }
    return offset;
  };
  std::vector<unsigned char> p(meshopt_encodeVertexBufferBound(4, 12));
  p.resize(meshopt_encodeVertexBuffer(p.data(), p.size(), positions.data(), 4, 12));
  std::vector<unsigned char> n(meshopt_encodeVertexBufferBound(4, 4));
  n.resize(meshopt_encodeVertexBuffer(n.data(), n.size(), normals.data(), 4, 4));
  std::vector<unsigned char> t(meshopt_encodeIndexBufferBound(6, 4));
  t.resize(meshopt_encodeIndexBuffer(t.data(), t.size(), indices.data(), 6));
  const size_t po = append(p), no = append(n), to = append(t);
  auto ext =
    [](size_t offset, size_t length, int stride, int count, const char* mode, const char* filter)
  {
    json e = { { "buffer", 0 }, { "byteOffset", offset }, { "byteLength", length },
      { "byteStride", stride }, { "count", count }, { "mode", mode } };
    if (filter)
    {
      e["filter"] = filter;
    }
    return json{ { "EXT_meshopt_compression", e } };
  };
  json doc = { { "asset", { { "version", "2.0" } } },
    { "extensionsUsed", { "EXT_meshopt_compression", "KHR_mesh_quantization" } },
    { "extensionsRequired", { "EXT_meshopt_compression", "KHR_mesh_quantization" } },
    { "buffers",
      { { { "byteLength", bin.size() } },
        { { "byteLength", 80 },
          { "extensions", { { "EXT_meshopt_compression", { { "fallback", true } } } } } } } },
    { "bufferViews",
      { { { "buffer", 1 }, { "byteOffset", 0 }, { "byteLength", 48 }, { "byteStride", 12 },
          { "extensions", ext(po, p.size(), 12, 4, "ATTRIBUTES", nullptr) } },
        { { "buffer", 1 }, { "byteOffset", 48 }, { "byteLength", 16 }, { "byteStride", 4 },
          { "extensions", ext(no, n.size(), 4, 4, "ATTRIBUTES", "OCTAHEDRAL") } },
        { { "buffer", 1 }, { "byteOffset", 64 }, { "byteLength", 12 },
          { "extensions", ext(to, t.size(), 2, 6, "TRIANGLES", nullptr) } } } },
    { "accessors",
      { { { "bufferView", 0 }, { "componentType", gltftest::Float }, { "count", 4 },
          { "type", "VEC3" } },
        { { "bufferView", 1 }, { "componentType", gltftest::Byte }, { "normalized", true },
          { "count", 4 }, { "type", "VEC3" } },
        { { "bufferView", 2 }, { "componentType", gltftest::UnsignedShort }, { "count", 6 },
          { "type", "SCALAR" } } } },
    { "meshes",
      { { { "primitives",
        { { { "attributes", { { "POSITION", 0 }, { "NORMAL", 1 } } }, { "indices", 2 } } } } } } },
    { "nodes", { { { "mesh", 0 } } } }, { "scenes", { { { "nodes", { 0 } } } } } };
  return Builder::MakeGlb(doc.dump(), bin);
}

void Write(const std::string& name, const std::string& bytes)
{
  std::ofstream(Folder + "/" + name, std::ios::binary)
    .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
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
    b.Doc["nodes"][0] = { { "matrix", { 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, -0.5, 0, 1, 2, 3, 1 } },
      { "children", { 1 } } };
    b.Doc["nodes"][1].erase("translation");
    b.Doc["nodes"][1].erase("rotation");
    b.Doc["nodes"][1]["matrix"] = { 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 };
    b.Doc["nodes"][1]["children"] = { 2 };
    b.Node(
      { { "name", "Leaf" }, { "mesh", 0 }, { "scale", { 1, 2, 3 } }, { "weights", { 1, 0.5 } } });
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
    const int scales =
      b.Floats({ 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 2, 2, 2, 0, 0, 0 }, "VEC3", 3);
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
    const int position = b.Accessor({ { "bufferView", view }, { "componentType", gltftest::Float },
      { "count", 3 }, { "type", "VEC3" } });
    const int normal = b.Accessor({ { "bufferView", view }, { "byteOffset", 12 },
      { "componentType", gltftest::Float }, { "count", 3 }, { "type", "VEC3" } });
    const int indices = b.Accessor({ { "bufferView", b.View(std::vector<uint8_t>{ 0, 1, 2, 0 }) },
      { "componentType", gltftest::UnsignedByte }, { "count", 3 }, { "type", "SCALAR" } });
    const int color = b.Accessor({ { "bufferView", b.View(std::vector<uint16_t>(12, 40000)) },
      { "componentType", gltftest::UnsignedShort }, { "normalized", true }, { "count", 3 },
      { "type", "VEC4" } });
    b.Mesh({ { "primitives",
      { { { "attributes",
            { { "POSITION", position }, { "NORMAL", normal }, { "COLOR_0", color } } },
          { "indices", indices } },
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
    b.Doc["cameras"] = { { { "type", "perspective" },
      { "perspective", { { "yfov", 0.8 }, { "znear", 0.01 } } } } };
    b.Doc["nodes"][0]["camera"] = 0;
    b.Doc["extensionsUsed"] = { "KHR_materials_emissive_strength" };
    b.Doc["extensionsRequired"] = { "KHR_materials_emissive_strength" };
    b.Doc["meshes"][0]["primitives"][0]["attributes"]["_MY/ATTR~1"] = 1;
    b.Doc["animations"][0]["channels"].push_back(
      { { "sampler", 0 }, { "target", { { "path", "rotation" } } } });
    Write("unread-parts.glb", b.Glb());
  }
  {
    // Normalized integer outputs (rotation as SHORT, weights as UNSIGNED_BYTE), byte
    // sparse indices over three points, a sparse index accessor.
    Builder b = gltftest::Quad();
    const int rotations = b.Accessor(
      { { "bufferView",
          b.View(std::vector<int16_t>{ 0, 0, 0, 32767, 0, 0, 12540, 30273, 0, 0, 23170, 23170 }) },
        { "componentType", gltftest::Short }, { "normalized", true }, { "count", 3 },
        { "type", "VEC4" } });
    const int weights =
      b.Accessor({ { "bufferView", b.View(std::vector<uint8_t>{ 0, 0, 255, 0, 0, 255, 0, 0 }) },
        { "componentType", gltftest::UnsignedByte }, { "normalized", true }, { "count", 6 },
        { "type", "SCALAR" } });
    b.Doc["animations"][0]["samplers"][0]["output"] = rotations;
    b.Doc["animations"][0]["samplers"][1]["output"] = weights;
    const int iv = b.View(std::vector<uint8_t>{ 0, 2, 3, 0 });
    const int vv = b.View(std::vector<float>{ 1, 0, 0, 0, 1, 0, 0, 0, 1 });
    b.Doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] =
      b.Accessor({ { "componentType", gltftest::Float }, { "count", 4 }, { "type", "VEC3" },
        { "sparse",
          { { "count", 3 },
            { "indices", { { "bufferView", iv }, { "componentType", gltftest::UnsignedByte } } },
            { "values", { { "bufferView", vv } } } } } });
    const int base = b.View(std::vector<uint16_t>{ 0, 1, 2, 0, 2, 3 });
    const int si = b.View(std::vector<uint16_t>{ 5, 0 });
    const int sv = b.View(std::vector<uint16_t>{ 1, 0 });
    b.Doc["meshes"][0]["primitives"][0]["indices"] = b.Accessor({ { "bufferView", base },
      { "componentType", gltftest::UnsignedShort }, { "count", 6 }, { "type", "SCALAR" },
      { "sparse",
        { { "count", 1 },
          { "indices", { { "bufferView", si }, { "componentType", gltftest::UnsignedShort } } },
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
  // Compressed geometry and materials (docs/materials.md).
  {
    Builder b;
    const int pv = b.View(std::vector<int16_t>{ 0, 0, 0, 0, 100, 0, 0, 0, 0, 100, 0, 0 }, 8);
    const int pa = b.Accessor({ { "bufferView", pv }, { "componentType", gltftest::Short },
      { "count", 3 }, { "type", "VEC3" } });
    const int nv = b.View(std::vector<int8_t>{ 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0 }, 4);
    const int na = b.Accessor({ { "bufferView", nv }, { "componentType", gltftest::Byte },
      { "normalized", true }, { "count", 3 }, { "type", "VEC3" } });
    const int dv = b.View(std::vector<int8_t>{ 0, 0, 0, 0, 10, -10, 0, 0, 0, 0, 5, 0 }, 4);
    const int da = b.Accessor({ { "bufferView", dv }, { "componentType", gltftest::Byte },
      { "count", 3 }, { "type", "VEC3" } });
    const int ia = b.Indices({ 0, 1, 2 });
    b.Mesh({ { "primitives",
      { { { "attributes", { { "POSITION", pa }, { "NORMAL", na } } }, { "indices", ia },
        { "targets", { { { "POSITION", da } } } } } } } });
    b.Node({ { "mesh", 0 }, { "scale", { 0.01, 0.01, 0.01 } } });
    b.Doc["scenes"] = { { { "nodes", { 0 } } } };
    b.Doc["extensionsUsed"] = { "KHR_mesh_quantization" };
    b.Doc["extensionsRequired"] = { "KHR_mesh_quantization" };
    Write("quantized.glb", b.Glb());
  }
  Write("materials.glb", TexturedTriangle().Glb());
  Write("meshopt.glb", MeshoptQuad());
  return 0;
}
