// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfTestFiles.h
/// @brief Small glTF files made in memory for the tests and the fuzz seeds: a builder that
/// keeps the JSON (nlohmann) and the binary chunk apart, so that a test can damage either
/// before writing the GLB.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace gltftest
{
using json = nlohmann::json;

constexpr int Byte = 5120, UnsignedByte = 5121, Short = 5122, UnsignedShort = 5123,
              UnsignedInt = 5125, Float = 5126;

class Builder
{
public:
  json Doc = { { "asset", { { "version", "2.0" }, { "generator", "MorphNode tests" } } } };
  std::vector<unsigned char> Bin;

  /// Appends bytes (padded to 4) as a new buffer view of buffer 0; returns its index.
  template <typename T>
  int View(const std::vector<T>& values, int stride = 0)
  {
    while (this->Bin.size() % 4 != 0)
    {
      this->Bin.push_back(0);
    }
    const size_t offset = this->Bin.size();
    const size_t bytes = values.size() * sizeof(T);
    this->Bin.resize(offset + bytes);
    if (bytes)
    {
      std::memcpy(this->Bin.data() + offset, values.data(), bytes);
    }
    json view = { { "buffer", 0 }, { "byteOffset", offset }, { "byteLength", bytes } };
    if (stride)
    {
      view["byteStride"] = stride;
    }
    this->Doc["bufferViews"].push_back(view);
    return static_cast<int>(this->Doc["bufferViews"].size() - 1);
  }

  int Accessor(json accessor)
  {
    this->Doc["accessors"].push_back(std::move(accessor));
    return static_cast<int>(this->Doc["accessors"].size() - 1);
  }

  /// A tightly packed FLOAT accessor of `type` (VEC3, SCALAR, ...).
  int Floats(const std::vector<float>& values, const char* type, int components)
  {
    const int view = this->View(values);
    return this->Accessor({ { "bufferView", view }, { "componentType", Float },
      { "count", values.size() / static_cast<size_t>(components) }, { "type", type } });
  }

  int Vec3(const std::vector<float>& values) { return this->Floats(values, "VEC3", 3); }

  int Indices(const std::vector<uint16_t>& values)
  {
    const int view = this->View(values);
    return this->Accessor({ { "bufferView", view }, { "componentType", UnsignedShort },
      { "count", values.size() }, { "type", "SCALAR" } });
  }

  /// A sparse VEC3 FLOAT accessor of `count` elements: values at `indices`; on a zero base
  /// (no bufferView) or on `base` (dense values, when given).
  int SparseVec3(size_t count, const std::vector<uint32_t>& indices,
    const std::vector<float>& values, const std::vector<float>& base = {})
  {
    json accessor = { { "componentType", Float }, { "count", count }, { "type", "VEC3" } };
    if (!base.empty())
    {
      accessor["bufferView"] = this->View(base);
    }
    const int iv = this->View(indices);
    const int vv = this->View(values);
    accessor["sparse"] = { { "count", indices.size() },
      { "indices", { { "bufferView", iv }, { "componentType", UnsignedInt } } },
      { "values", { { "bufferView", vv } } } };
    return this->Accessor(accessor);
  }

  int Node(json node)
  {
    this->Doc["nodes"].push_back(std::move(node));
    return static_cast<int>(this->Doc["nodes"].size() - 1);
  }

  int Mesh(json mesh)
  {
    this->Doc["meshes"].push_back(std::move(mesh));
    return static_cast<int>(this->Doc["meshes"].size() - 1);
  }

  /// The document with buffers[0] describing Bin (unless the test replaced it).
  json Finished() const
  {
    json doc = this->Doc;
    if (!doc.contains("buffers"))
    {
      doc["buffers"] = json::array({ { { "byteLength", this->PaddedBin().size() } } });
    }
    return doc;
  }

  std::vector<unsigned char> PaddedBin() const
  {
    std::vector<unsigned char> bin = this->Bin;
    while (bin.size() % 4 != 0)
    {
      bin.push_back(0);
    }
    return bin;
  }

  /// GLB with the JSON given (default: Finished()) and the BIN chunk.
  std::string Glb() const { return MakeGlb(this->Finished().dump(), this->PaddedBin()); }

  static std::string MakeGlb(std::string text, const std::vector<unsigned char>& bin)
  {
    while (text.size() % 4 != 0)
    {
      text += ' ';
    }
    std::string out;
    auto u32 = [&out](uint32_t v)
    {
      for (int i = 0; i < 4; ++i)
      {
        out += static_cast<char>((v >> (8 * i)) & 0xff);
      }
    };
    const size_t length = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
    u32(0x46546C67);
    u32(2);
    u32(static_cast<uint32_t>(length));
    u32(static_cast<uint32_t>(text.size()));
    u32(0x4E4F534A);
    out += text;
    if (!bin.empty())
    {
      u32(static_cast<uint32_t>(bin.size()));
      u32(0x004E4942);
      out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
    }
    return out;
  }

  /// .gltf JSON with the buffer as a base64 data URI.
  std::string GltfWithDataUri() const
  {
    static const char* const alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const std::vector<unsigned char> bin = this->PaddedBin();
    std::string b64;
    for (size_t i = 0; i < bin.size(); i += 3)
    {
      const uint32_t n = (uint32_t(bin[i]) << 16) |
        (i + 1 < bin.size() ? uint32_t(bin[i + 1]) << 8 : 0) |
        (i + 2 < bin.size() ? uint32_t(bin[i + 2]) : 0);
      b64 += alphabet[(n >> 18) & 63];
      b64 += alphabet[(n >> 12) & 63];
      b64 += i + 1 < bin.size() ? alphabet[(n >> 6) & 63] : '=';
      b64 += i + 2 < bin.size() ? alphabet[n & 63] : '=';
    }
    json doc = this->Finished();
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + b64;
    return doc.dump();
  }
};

/// A small scene with everything the loader reads: a root node (scale 0.5) with a child
/// (translation, rotation) holding a quad of two triangles with normals, a material,
/// COLOR_0, two morph targets (one dense with NORMAL deltas, one sparse without a
/// bufferView) named in extras.targetNames, default weights, and an animation of the
/// child's rotation and the mesh's weights.
inline Builder Quad()
{
  Builder b;
  const int position = b.Vec3({ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 });
  const int normal = b.Vec3({ 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 });
  const int color =
    b.Accessor({ { "bufferView",
                   b.View(std::vector<uint8_t>{ 255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255 }) },
      { "componentType", UnsignedByte }, { "normalized", true }, { "count", 4 },
      { "type", "VEC3" } });
  const int indices = b.Indices({ 0, 1, 2, 0, 2, 3 });
  const int dense = b.Vec3({ 0, 0, 0.1f, 0, 0, 0.2f, 0, 0, 0.3f, 0, 0, 0.4f });
  const int denseNormal = b.Vec3({ 0.1f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 });
  const int sparse = b.SparseVec3(4, { 2 }, { 0, 0.5f, 0 });
  b.Mesh({ { "name", "QuadMesh" },
    { "primitives",
      { { { "attributes",
            { { "POSITION", position }, { "NORMAL", normal }, { "COLOR_0", color } } },
        { "indices", indices }, { "material", 0 },
        { "targets",
          { { { "POSITION", dense }, { "NORMAL", denseNormal } },
            { { "POSITION", sparse } } } } } } },
    { "weights", { 0.25, 0 } }, { "extras", { { "targetNames", { "Lift", "Raise" } } } } });
  b.Doc["materials"] = { { { "name", "Skin" },
    { "pbrMetallicRoughness", { { "baseColorFactor", { 0.8, 0.6, 0.5, 1 } } } } } };
  b.Node({ { "name", "Root" }, { "scale", { 0.5, 0.5, 0.5 } }, { "children", { 1 } } });
  // 90 degrees about z: (x, y, z, w) = (0, 0, sin 45, cos 45)
  b.Node({ { "name", "Quad" }, { "mesh", 0 }, { "translation", { 1, 2, 3 } },
    { "rotation", { 0, 0, 0.70710678118654752, 0.70710678118654752 } } });
  b.Doc["scenes"] = { { { "name", "Scene" }, { "nodes", { 0 } } } };
  b.Doc["scene"] = 0;
  const int times = b.Floats({ 0, 0.5f, 1 }, "SCALAR", 1);
  const int rotations =
    b.Floats({ 0, 0, 0, 1, 0, 0, 0.3826834f, 0.9238795f, 0, 0, 0.7071068f, 0.7071068f }, "VEC4", 4);
  const int weights = b.Floats({ 0, 0, 1, 0, 0, 1 }, "SCALAR", 1);
  b.Doc["animations"] = { { { "name", "Nod" },
    { "samplers",
      { { { "input", times }, { "output", rotations }, { "interpolation", "LINEAR" } },
        { { "input", times }, { "output", weights }, { "interpolation", "STEP" } } } },
    { "channels",
      { { { "sampler", 0 }, { "target", { { "node", 1 }, { "path", "rotation" } } } },
        { { "sampler", 1 }, { "target", { { "node", 1 }, { "path", "weights" } } } } } } } };
  return b;
}
} // namespace gltftest
