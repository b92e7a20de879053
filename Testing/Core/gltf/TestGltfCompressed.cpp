// SPDX-License-Identifier: BSD-3-Clause
// Compressed glTF geometry: KHR_mesh_quantization and EXT_meshopt_compression decoded equal
// the uncompressed original within the quantization step (positions, normals, UVs, morph
// deltas), on the shared MakeHuman avatar's variants, on variants gltfpack makes here at
// test time (other bit depths, normalized positions, meshopt filters), and on small files
// written by the test; required extensions MorphNode does not implement, and streams or
// filters the meshoptimizer library cannot decode, give an error naming them.
//
// The space of the comparison: gltfpack folds the dequantization of positions into the
// mesh nodes' transforms (and the skin's inverse bind matrices). The loader applies node
// transforms (GltfLoadOptions::ApplyTransforms, the default), so both files are compared in
// the scene's space at rest; skins are not applied (at rest they leave the avatar where
// it is, README of the data), so the inverse bind matrices do not enter.
#include "gltf/GltfScene.h"

#include "GltfTestFiles.h"
#include "MorphNodeTestErrors.h"
#include "base/Error.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <tuple>

using gltftest::Builder;
using gltftest::json;
using morphnode::GltfPart;
using morphnode::GltfScene;
using morphnode::InputError;
using morphnode::LoadGltfScene;

namespace
{
using morphnode_test::AvatarFile;

#define SKIP_WITHOUT_AVATAR() MORPHNODE_SKIP_WITHOUT_AVATAR(AvatarFile())

/// The largest differences of a decoded part from the original's: per vertex of the
/// original, the decoded vertex nearest in position (welded duplicates share it; among
/// those at the same place the one with the nearest UV, after the material's texture
/// transform).
struct Differences
{
  double Position = 0, Normal = 0, Uv = 0, PositionDelta = 0, NormalDelta = 0;
  size_t Compared = 0;
};

Differences Compare(
  const GltfPart& original, const GltfPart& decoded, const std::array<double, 9>* uvMatrix)
{
  // A hash grid of the decoded points, 1 mm cells.
  const double cell = 1e-3;
  std::map<std::tuple<long, long, long>, std::vector<size_t>> grid;
  auto key = [&](const float* p, int dx, int dy, int dz)
  {
    return std::make_tuple(static_cast<long>(std::floor(p[0] / cell)) + dx,
      static_cast<long>(std::floor(p[1] / cell)) + dy,
      static_cast<long>(std::floor(p[2] / cell)) + dz);
  };
  for (size_t i = 0; i < decoded.GetNumberOfPoints(); ++i)
  {
    grid[key(&decoded.Positions[3 * i], 0, 0, 0)].push_back(i);
  }
  auto uvOf = [&](size_t i)
  {
    double u = decoded.TexCoords0[2 * i], v = decoded.TexCoords0[2 * i + 1];
    if (uvMatrix)
    {
      const auto& m = *uvMatrix;
      const double x = m[0] * u + m[1] * v + m[2], y = m[3] * u + m[4] * v + m[5];
      u = x;
      v = y;
    }
    return std::array<double, 2>{ { u, v } };
  };
  const bool uvs = !original.TexCoords0.empty() && !decoded.TexCoords0.empty();
  Differences d;
  for (size_t i = 0; i < original.GetNumberOfPoints(); ++i)
  {
    const float* p = &original.Positions[3 * i];
    size_t best = SIZE_MAX;
    double bestDistance = 1e9, bestUv = 1e9;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
        {
          auto it = grid.find(key(p, dx, dy, dz));
          if (it == grid.end())
          {
            continue;
          }
          for (size_t j : it->second)
          {
            const float* q = &decoded.Positions[3 * j];
            const double dist = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) +
              (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
            double uvd = 0;
            if (uvs)
            {
              const auto uv = uvOf(j);
              uvd = std::max(std::abs(uv[0] - original.TexCoords0[2 * i]),
                std::abs(uv[1] - original.TexCoords0[2 * i + 1]));
            }
            // Points within 0.3 mm are candidates for the same vertex; among them the UV
            // and the normal decide (the teeth have points back to back).
            if (!original.Normals.empty() && !decoded.Normals.empty())
            {
              for (int k = 0; k < 3; ++k)
              {
                uvd += std::abs(double(original.Normals[3 * i + k]) - decoded.Normals[3 * j + k]);
              }
            }
            if (dist > 3e-4 && dist > bestDistance)
            {
              continue;
            }
            if ((dist <= 3e-4 && bestDistance > 3e-4) || (dist <= 3e-4 && uvd < bestUv) ||
              (dist > 3e-4 && dist < bestDistance))
            {
              best = j;
              bestDistance = dist;
              bestUv = uvd;
            }
          }
        }
    if (best == SIZE_MAX)
    {
      d.Position = 1e9;
      return d;
    }
    ++d.Compared;
    d.Position = std::max(d.Position, bestDistance);
    if (uvs)
    {
      const auto uv = uvOf(best);
      d.Uv = std::max(d.Uv,
        std::max(std::abs(uv[0] - original.TexCoords0[2 * i]),
          std::abs(uv[1] - original.TexCoords0[2 * i + 1])));
    }
    for (int k = 0; k < 3; ++k)
    {
      if (!original.Normals.empty())
      {
        d.Normal = std::max(
          d.Normal, std::abs(double(original.Normals[3 * i + k]) - decoded.Normals[3 * best + k]));
      }
      for (size_t t = 0; t < original.Targets.size(); ++t)
      {
        const auto& a = original.Targets[t];
        const auto& b = decoded.Targets[t];
        d.PositionDelta = std::max(d.PositionDelta,
          std::abs(double(a.PositionDeltas[3 * i + k]) - b.PositionDeltas[3 * best + k]));
        if (!a.NormalDeltas.empty() && !b.NormalDeltas.empty())
        {
          // Normal deltas are stored as normalized bytes or shorts, which hold [-1, 1]:
          // larger deltas (a normal turning past 60 degrees) are clamped by the writer.
          const double clamped = std::max(-1.0, std::min(1.0, double(a.NormalDeltas[3 * i + k])));
          d.NormalDelta = std::max(d.NormalDelta,
            std::min(std::abs(clamped - b.NormalDeltas[3 * best + k]),
              std::abs(double(a.NormalDeltas[3 * i + k]) - b.NormalDeltas[3 * best + k])));
        }
      }
    }
  }
  return d;
}

struct Steps
{
  double Position, Normal, Uv, PositionDelta, NormalDelta;
};

/// Every part of `variant` against the original avatar's, within the given tolerances.
void ExpectLikeOriginal(const std::string& variantPath, const Steps& tolerance)
{
  const GltfScene original = LoadGltfScene(AvatarFile("makehuman_avatar.glb"));
  const GltfScene variant = LoadGltfScene(variantPath);
  ASSERT_EQ(variant.Parts.size(), original.Parts.size()) << variantPath;
  for (size_t p = 0; p < original.Parts.size(); ++p)
  {
    const GltfPart& a = original.Parts[p];
    const GltfPart& b = variant.Parts[p];
    SCOPED_TRACE(variantPath + ": part " + a.Name);
    EXPECT_EQ(b.MaterialName, a.MaterialName);
    EXPECT_EQ(b.GetNumberOfTriangles(), a.GetNumberOfTriangles());
    ASSERT_EQ(b.Targets.size(), a.Targets.size());
    EXPECT_EQ(b.Targets[49].Name, "jawOpen");
    const auto& material = variant.Materials[static_cast<size_t>(b.Material)];
    const bool textured = material.BaseColorTexture.Texture >= 0;
    const std::array<double, 9> m = material.BaseColorTexture.UvMatrix();
    if (textured)
    {
      EXPECT_FALSE(b.TexCoords0.empty());
    }
    const Differences d = Compare(a, b, textured ? &m : nullptr);
    EXPECT_GT(d.Compared, a.GetNumberOfPoints() - 1);
    EXPECT_LT(d.Position, tolerance.Position);
    EXPECT_LT(d.Normal, tolerance.Normal);
    if (textured)
    {
      EXPECT_LT(d.Uv, tolerance.Uv);
    }
    EXPECT_LT(d.PositionDelta, tolerance.PositionDelta);
    EXPECT_LT(d.NormalDelta, tolerance.NormalDelta);
  }
}

// gltfpack's defaults: 14-bit positions over the avatar's 1.9 m box (0.116 mm steps),
// 8-bit normals (1/127), 12-bit UVs; deltas on the position grid. A position rounds by
// half a step per axis (0.1 mm in 3-D), a delta by up to one step (it is the difference of
// two rounded values, or rounded on a normalized grid with -vpn); a UV by half of
// (range / 4095).
const Steps DefaultSteps{ 1.1e-4, 0.02, 2e-3, 1.17e-4, 0.03 };
} // namespace

TEST(GltfCompressed, QuantizedAvatarEqualsOriginal)
{
  SKIP_WITHOUT_AVATAR();
  ExpectLikeOriginal(AvatarFile("makehuman_avatar_quantized.glb"), DefaultSteps);
}

TEST(GltfCompressed, MeshoptAvatarEqualsQuantized)
{
  SKIP_WITHOUT_AVATAR();
  // meshopt is lossless on the quantized data: every decoded number equals the quantized
  // file's.
  const GltfScene q = LoadGltfScene(AvatarFile("makehuman_avatar_quantized.glb"));
  const GltfScene m = LoadGltfScene(AvatarFile("makehuman_avatar_meshopt.glb"));
  ASSERT_EQ(m.Parts.size(), q.Parts.size());
  for (size_t p = 0; p < q.Parts.size(); ++p)
  {
    EXPECT_EQ(m.Parts[p].Positions, q.Parts[p].Positions);
    EXPECT_EQ(m.Parts[p].Normals, q.Parts[p].Normals);
    EXPECT_EQ(m.Parts[p].TexCoords0, q.Parts[p].TexCoords0);
    // The index codec may start a triangle at another corner (same winding).
    auto rotated = [](std::vector<uint32_t> t)
    {
      for (size_t i = 0; i + 2 < t.size(); i += 3)
      {
        while (t[i] > t[i + 1] || t[i] > t[i + 2])
        {
          std::rotate(t.begin() + static_cast<long>(i), t.begin() + static_cast<long>(i) + 1,
            t.begin() + static_cast<long>(i) + 3);
        }
      }
      return t;
    };
    EXPECT_EQ(rotated(m.Parts[p].Triangles), rotated(q.Parts[p].Triangles));
    ASSERT_EQ(m.Parts[p].Targets.size(), q.Parts[p].Targets.size());
    for (size_t t = 0; t < q.Parts[p].Targets.size(); ++t)
    {
      EXPECT_EQ(m.Parts[p].Targets[t].PositionDeltas, q.Parts[p].Targets[t].PositionDeltas);
      EXPECT_EQ(m.Parts[p].Targets[t].NormalDeltas, q.Parts[p].Targets[t].NormalDeltas);
    }
  }
  ExpectLikeOriginal(AvatarFile("makehuman_avatar_meshopt.glb"), DefaultSteps);
}

namespace
{
/// Runs gltfpack on the original avatar with `options` into a temporary file; empty path
/// when gltfpack is missing.
std::string Gltfpack(const std::string& options, const std::string& name)
{
  if (std::system("command -v gltfpack > /dev/null 2>&1") != 0)
  {
    return std::string();
  }
  const std::string out =
    (std::filesystem::temp_directory_path() / ("morphnode_gltfpack_" + name + ".glb")).string();
  const std::string command = "gltfpack -kn -km -ke " + options + " -i '" +
    AvatarFile("makehuman_avatar.glb") + "' -o '" + out + "' > /dev/null 2>&1";
  return std::system(command.c_str()) == 0 ? out : std::string();
}
} // namespace

TEST(GltfCompressed, GltfpackVariantsEqualOriginal)
{
  SKIP_WITHOUT_AVATAR();
  if (std::system("command -v gltfpack > /dev/null 2>&1") != 0)
  {
    if (std::getenv("CI"))
    {
      FAIL() << "gltfpack (Debian package gltfpack) is required under CI";
    }
    GTEST_SKIP() << "gltfpack not installed (Debian package gltfpack)";
  }
  // 16-bit positions and 12-bit normals (SHORT normals); normalized positions (-vpn); the
  // higher compression -cc (OCTAHEDRAL filter on normals and meshopt index sequences);
  // float attributes (-noq) compressed.
  struct Case
  {
    const char* Options;
    const char* Name;
    Steps Tolerance;
  };
  const Case cases[] = {
    { "-vp 16 -vn 12 -vt 14", "fine", { 3e-5, 2e-3, 5e-4, 3e-5, 3e-3 } },
    { "-vpn -c", "normalized", DefaultSteps },
    { "-cc", "cc", DefaultSteps },
    { "-noq -c", "float", { 1e-6, 1e-6, 1e-6, 1e-6, 1e-6 } },
  };
  for (const Case& c : cases)
  {
    SCOPED_TRACE(c.Options);
    const std::string path = Gltfpack(c.Options, c.Name);
    ASSERT_FALSE(path.empty()) << "gltfpack " << c.Options << " failed";
    ExpectLikeOriginal(path, c.Tolerance);
    std::filesystem::remove(path);
  }
}

namespace
{
/// A one-triangle mesh with quantized attributes written by the test: positions as `type`
/// (normalized or not), BYTE normals, UNSIGNED_SHORT UVs and a BYTE morph target.
Builder QuantizedTriangle(int type, bool normalized)
{
  Builder b;
  std::vector<int16_t> p16 = { 0, 0, 0, 0, 100, 0, 0, 0, 0, 100, 0, 0 };
  std::vector<int8_t> p8 = { 0, 0, 0, 0, 100, 0, 0, 0, 0, 100, 0, 0 };
  const bool shorts = type == gltftest::Short || type == gltftest::UnsignedShort;
  const int pv = shorts ? b.View(p16, 8) : b.View(p8, 4);
  json position = { { "bufferView", pv }, { "componentType", type }, { "count", 3 },
    { "type", "VEC3" } };
  if (normalized)
  {
    position["normalized"] = true;
  }
  const int pa = b.Accessor(position);
  const int nv = b.View(std::vector<int8_t>{ 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -127, 0 }, 4);
  const int na = b.Accessor({ { "bufferView", nv }, { "componentType", gltftest::Byte },
    { "normalized", true }, { "count", 3 }, { "type", "VEC3" } });
  const int uv = b.View(std::vector<uint16_t>{ 0, 0, 65535, 0, 0, 32768 });
  const int ua = b.Accessor({ { "bufferView", uv }, { "componentType", gltftest::UnsignedShort },
    { "normalized", true }, { "count", 3 }, { "type", "VEC2" } });
  const int dv = b.View(std::vector<int8_t>{ 0, 0, 0, 0, 10, -10, 0, 0, 0, 0, 5, 0 }, 4);
  const int da = b.Accessor({ { "bufferView", dv }, { "componentType", gltftest::Byte },
    { "count", 3 }, { "type", "VEC3" } });
  const int ia = b.Indices({ 0, 1, 2 });
  b.Mesh({ { "primitives",
    { { { "attributes", { { "POSITION", pa }, { "NORMAL", na }, { "TEXCOORD_0", ua } } },
      { "indices", ia }, { "targets", { { { "POSITION", da } } } } } } } });
  b.Node({ { "mesh", 0 } });
  b.Doc["scenes"] = { { { "nodes", { 0 } } } };
  b.Doc["extensionsUsed"] = { "KHR_mesh_quantization" };
  b.Doc["extensionsRequired"] = { "KHR_mesh_quantization" };
  return b;
}

GltfScene Load(const std::string& bytes)
{
  return morphnode::LoadGltfSceneFromMemory(bytes.data(), bytes.size(), "", {}, "test.glb");
}

/// The message of the InputError that loading `bytes` gives (Testing/MorphNodeTestErrors.h).
std::string ErrorOf(const std::string& bytes)
{
  return morphnode_test::ErrorOf([&] { Load(bytes); });
}
} // namespace

TEST(GltfCompressed, QuantizationTypesWrittenByTheTest)
{
  struct Case
  {
    int Type;
    bool Normalized;
    double Scale; // what 100 reads as
  };
  const Case cases[] = { { gltftest::Byte, false, 100 }, { gltftest::Byte, true, 100 / 127.0 },
    { gltftest::UnsignedByte, false, 100 }, { gltftest::UnsignedByte, true, 100 / 255.0 },
    { gltftest::Short, false, 100 }, { gltftest::Short, true, 100 / 32767.0 },
    { gltftest::UnsignedShort, false, 100 }, { gltftest::UnsignedShort, true, 100 / 65535.0 } };
  for (const Case& c : cases)
  {
    SCOPED_TRACE(std::to_string(c.Type) + (c.Normalized ? " normalized" : ""));
    const GltfScene scene = Load(QuantizedTriangle(c.Type, c.Normalized).Glb());
    ASSERT_EQ(scene.Parts.size(), 1u);
    const GltfPart& part = scene.Parts[0];
    EXPECT_NEAR(part.Positions[3], c.Scale, 1e-6);
    EXPECT_NEAR(part.Positions[7], c.Scale, 1e-6);
    EXPECT_NEAR(part.Normals[2], 1.0, 1e-6);
    EXPECT_NEAR(part.Normals[8], -1.0, 1e-6);
    EXPECT_NEAR(part.TexCoords0[2], 1.0, 1e-6);
    EXPECT_NEAR(part.TexCoords0[5], 32768 / 65535.0, 1e-6);
    EXPECT_NEAR(part.Targets[0].PositionDeltas[3], 10, 1e-6);
    EXPECT_NEAR(part.Targets[0].PositionDeltas[4], -10, 1e-6);
  }
  // Without the extension, integer positions are refused (the base spec allows only FLOAT).
  Builder b = QuantizedTriangle(gltftest::Short, false);
  b.Doc.erase("extensionsUsed");
  b.Doc.erase("extensionsRequired");
  EXPECT_NE(ErrorOf(b.Glb()).find("integers need KHR_mesh_quantization"), std::string::npos)
    << ErrorOf(b.Glb());
}

TEST(GltfCompressed, RequiredExtensionsNotImplementedAreErrors)
{
  for (const char* name : { "KHR_draco_mesh_compression", "KHR_texture_basisu",
         "EXT_mesh_gpu_instancing", "KHR_materials_volume", "VENDOR_made_up" })
  {
    Builder b = QuantizedTriangle(gltftest::Short, false);
    b.Doc["extensionsUsed"].push_back(name);
    b.Doc["extensionsRequired"].push_back(name);
    const std::string error = ErrorOf(b.Glb());
    EXPECT_NE(error.find("/extensionsRequired/1: the file requires the extension '" +
                std::string(name) + "'"),
      std::string::npos)
      << error;
  }
  // Draco says why.
  Builder b = QuantizedTriangle(gltftest::Short, false);
  b.Doc["extensionsRequired"] = { "KHR_draco_mesh_compression" };
  EXPECT_NE(ErrorOf(b.Glb()).find("Draco decoding is not implemented"), std::string::npos);
  // Optional ones are read past, with a note.
  b.Doc["extensionsRequired"] = { "KHR_mesh_quantization" };
  b.Doc["extensionsUsed"] = { "KHR_mesh_quantization", "KHR_draco_mesh_compression",
    "KHR_materials_sheen" };
  const GltfScene scene = Load(b.Glb());
  bool noted = false;
  for (const auto& note : scene.Notes)
  {
    noted = noted ||
      note.find("KHR_draco_mesh_compression is optional and not read") != std::string::npos;
  }
  EXPECT_TRUE(noted);
}

TEST(GltfCompressed, MeshoptStreamsTheLibraryCannotDecodeAreRefused)
{
  SKIP_WITHOUT_AVATAR();
  std::ifstream in(AvatarFile("makehuman_avatar_meshopt.glb"), std::ios::binary);
  const std::string original(
    (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Split the GLB, change the JSON, join again.
  const uint32_t jsonLength = *reinterpret_cast<const uint32_t*>(original.data() + 12);
  json doc = json::parse(original.substr(20, jsonLength));
  const std::string binChunk = original.substr(20 + jsonLength + 8);
  const std::vector<unsigned char> bin(binChunk.begin(), binChunk.end());
  auto errorWith = [&](const std::function<void(json&, std::vector<unsigned char>&)>& change)
  {
    json d = doc;
    std::vector<unsigned char> b = bin;
    change(d, b);
    return ErrorOf(Builder::MakeGlb(d.dump(), b));
  };
  auto& ext0 = doc["bufferViews"][3]["extensions"]["EXT_meshopt_compression"];
  const size_t offset = ext0["byteOffset"].get<size_t>();
  // A vertex stream of version 1 (a newer meshoptimizer's).
  std::string e = errorWith([&](json&, std::vector<unsigned char>& b) { b[offset] = 0xa1; });
  EXPECT_NE(
    e.find(
      "/bufferViews/3/extensions/EXT_meshopt_compression: meshopt vertex stream version 1, which "
      "Debian's meshoptimizer 0.18 cannot decode"),
    std::string::npos)
    << e;
  e = errorWith([&](json& d, std::vector<unsigned char>&)
    { d["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["filter"] = "COLOR"; });
  EXPECT_NE(
    e.find("/bufferViews/3/extensions/EXT_meshopt_compression/filter: 'COLOR' is a filter Debian's "
           "meshoptimizer 0.18 cannot decode"),
    std::string::npos)
    << e;
  e = errorWith([&](json& d, std::vector<unsigned char>&)
    { d["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 10; });
  EXPECT_NE(e.find("cannot be decoded (meshoptimizer error"), std::string::npos) << e;
  e = errorWith([&](json& d, std::vector<unsigned char>&)
    { d["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 1u << 30; });
  EXPECT_NE(
    e.find("/bufferViews/3/extensions/EXT_meshopt_compression/byteOffset: must be an integer"),
    std::string::npos)
    << e;
  // The extension not declared as used: the fallback buffer is then a GLB buffer without
  // data, which is an error too (never zeros read as the mesh).
  e = errorWith(
    [&](json& d, std::vector<unsigned char>&) {
      d["extensionsRequired"] = { "KHR_mesh_quantization", "VENDOR_meshopt" };
    });
  EXPECT_NE(e.find("VENDOR_meshopt"), std::string::npos) << e;
}
