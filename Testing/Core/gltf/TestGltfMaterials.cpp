// SPDX-License-Identifier: BSD-3-Clause
// Materials and images of glTF files (GltfMaterial.h): the avatar's materials as its README
// lists them, its WebP variant's images equal their PNG twins, an image that cannot be
// decoded leaves the other textures on their parts, KHR_texture_transform, unlit,
// emissive strength, and bad material JSON as an error naming the pointer.
#include "gltf/GltfScene.h"

#include "GltfTestFiles.h"
#include "MorphNodeTestErrors.h"
#include "base/Error.h"

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

using gltftest::Builder;
using gltftest::json;
using morphnode::GltfAlphaMode;
using morphnode::GltfScene;
using morphnode::InputError;
using morphnode::LoadGltfScene;

namespace
{
#define SKIP_WITHOUT_AVATAR() MORPHNODE_SKIP_WITHOUT_AVATAR(morphnode_test::AvatarFile())

GltfScene Load(const std::string& bytes)
{
  return morphnode::LoadGltfSceneFromMemory(bytes.data(), bytes.size(), "", {}, "test.glb");
}

/// The message of the InputError that loading `bytes` gives (Testing/MorphNodeTestErrors.h).
std::string ErrorOf(const std::string& bytes)
{
  return morphnode_test::ErrorOf([&] { Load(bytes); });
}

// A 1x1 RGBA PNG (red, alpha 128), made with Python's zlib.
const std::vector<unsigned char> RedPng = { 0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00,
  0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08,
  0x06, 0x00, 0x00, 0x00, 0x1f, 0x15, 0xc4, 0x89, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54,
  0x78, 0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0xd0, 0x00, 0x00, 0x04, 0x81, 0x01, 0x80, 0x2c, 0x55, 0xce,
  0xb0, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82 };

/// A triangle with UVs and three textured materials' worth of images: image 0 broken,
/// images 1 and 2 the red PNG; textures 0, 1, 2 on them.
Builder TexturedTriangle()
{
  Builder b;
  const int p = b.Vec3({ 0, 0, 0, 1, 0, 0, 0, 1, 0 });
  const int uv = b.Floats({ 0, 0, 1, 0, 0, 1 }, "VEC2", 2);
  const int i = b.Indices({ 0, 1, 2 });
  b.Mesh({ { "primitives",
    { { { "attributes", { { "POSITION", p }, { "TEXCOORD_0", uv } } }, { "indices", i },
      { "material", 0 } } } } });
  b.Node({ { "mesh", 0 } });
  b.Doc["scenes"] = { { { "nodes", { 0 } } } };
  const int broken = b.View(std::vector<unsigned char>{ 0x89, 'P', 'N', 'G', 0, 1, 2, 3 });
  const int red1 = b.View(RedPng);
  const int red2 = b.View(RedPng);
  b.Doc["images"] = { { { "bufferView", broken }, { "mimeType", "image/png" },
                        { "name", "broken" } },
    { { "bufferView", red1 }, { "mimeType", "image/png" } },
    { { "bufferView", red2 }, { "mimeType", "image/png" } } };
  b.Doc["samplers"] = { { { "magFilter", 9728 }, { "wrapS", 33071 } } };
  b.Doc["textures"] = { { { "source", 0 } }, { { "source", 1 }, { "sampler", 0 } },
    { { "source", 2 } } };
  b.Doc["materials"] = { { { "name", "M" },
    { "pbrMetallicRoughness",
      { { "baseColorTexture", { { "index", 0 } } },
        { "metallicRoughnessTexture", { { "index", 1 } } }, { "metallicFactor", 0.25 } } },
    { "emissiveTexture",
      { { "index", 2 },
        { "extensions",
          { { "KHR_texture_transform",
            { { "offset", { 0.5, 0 } }, { "scale", { 2, 2 } } } } } } } },
    { "emissiveFactor", { 1, 0.5, 0 } }, { "alphaMode", "BLEND" }, { "doubleSided", true },
    { "extensions",
      { { "KHR_materials_emissive_strength", { { "emissiveStrength", 4 } } },
        { "KHR_materials_clearcoat", json::object() } } } } };
  return b;
}
} // namespace

TEST(GltfMaterials, AvatarMaterials)
{
  SKIP_WITHOUT_AVATAR();
  const GltfScene scene = LoadGltfScene(morphnode_test::AvatarFile());
  ASSERT_EQ(scene.Materials.size(), 6u);
  ASSERT_EQ(scene.Images.size(), 3u);
  for (const auto& image : scene.Images)
  {
    EXPECT_TRUE(image.IsDecoded()) << image.Error;
    EXPECT_EQ(image.MimeType, "image/png");
  }
  EXPECT_EQ(scene.Images[0].Width, 1024);
  const auto& eye = scene.Materials[1];
  EXPECT_EQ(eye.Name, "Eye");
  EXPECT_EQ(eye.AlphaMode, GltfAlphaMode::Mask);
  EXPECT_DOUBLE_EQ(eye.AlphaCutoff, 0.5);
  EXPECT_EQ(eye.BaseColorTexture.Image, 0);
  EXPECT_DOUBLE_EQ(eye.RoughnessFactor, 0.15);
  EXPECT_DOUBLE_EQ(eye.MetallicFactor, 0.0);
  EXPECT_EQ(eye.BaseColorTexture.Sampler.MinFilter, 9987);
  EXPECT_TRUE(scene.Materials[4].DoubleSided);
  EXPECT_EQ(scene.Materials[4].BaseColorTexture.Image, 1);
  EXPECT_EQ(scene.Materials[5].BaseColorTexture.Image, 2);
  EXPECT_FALSE(scene.Materials[0].BaseColorTexture.IsSet());
  EXPECT_NEAR(scene.Materials[0].BaseColorFactor[0], 0.7293, 1e-9);
  // The eye part carries its UVs.
  const int eyeLeft = scene.FindPart("EyeLeft");
  ASSERT_GE(eyeLeft, 0);
  EXPECT_EQ(scene.Parts[static_cast<size_t>(eyeLeft)].TexCoords0.size(),
    2 * scene.Parts[static_cast<size_t>(eyeLeft)].GetNumberOfPoints());
}

TEST(GltfMaterials, WebpImagesEqualTheirPngTwins)
{
  SKIP_WITHOUT_AVATAR();
  const GltfScene png = LoadGltfScene(morphnode_test::AvatarFile());
  const GltfScene webp = LoadGltfScene(morphnode_test::AvatarFile("makehuman_avatar_webp.glb"));
  ASSERT_EQ(webp.Images.size(), png.Images.size());
  for (size_t i = 0; i < png.Images.size(); ++i)
  {
    const auto& a = png.Images[i];
    const auto& b = webp.Images[i];
    ASSERT_TRUE(b.IsDecoded()) << b.Error;
    EXPECT_EQ(b.MimeType, "image/webp");
    ASSERT_EQ(b.Width, a.Width);
    ASSERT_EQ(b.Height, a.Height);
    // cwebp -q 90 (lossy colour, lossless alpha): mean colour error below 2 levels of 255,
    // alpha exact.
    double colour = 0;
    size_t alphaDiffs = 0;
    for (size_t k = 0; k < a.Pixels.size(); k += 4)
    {
      for (size_t c = 0; c < 3; ++c)
      {
        colour += std::abs(int(a.Pixels[k + c]) - int(b.Pixels[k + c]));
      }
      alphaDiffs += a.Pixels[k + 3] != b.Pixels[k + 3];
    }
    colour /= 3.0 * a.Pixels.size() / 4;
    EXPECT_LT(colour, 2.0) << "image " << i;
    EXPECT_EQ(alphaDiffs, 0u) << "image " << i;
    // Negative control: the images are not all alike (image 0 against image 1 differs).
  }
  EXPECT_NE(png.Images[1].Pixels, png.Images[2].Pixels);
  // The textures use the WebP images through EXT_texture_webp, same indices.
  for (size_t m = 0; m < png.Materials.size(); ++m)
  {
    EXPECT_EQ(webp.Materials[m].BaseColorTexture.Image, png.Materials[m].BaseColorTexture.Image);
  }
}

TEST(GltfMaterials, UndecodableImageLeavesTheOthersOnTheirParts)
{
  const GltfScene scene = Load(TexturedTriangle().Glb());
  ASSERT_EQ(scene.Images.size(), 3u);
  EXPECT_FALSE(scene.Images[0].IsDecoded());
  EXPECT_NE(scene.Images[0].Error.find("PNG"), std::string::npos) << scene.Images[0].Error;
  ASSERT_TRUE(scene.Images[1].IsDecoded());
  EXPECT_EQ(scene.Images[1].Width, 1);
  EXPECT_EQ(scene.Images[1].Pixels, (std::vector<uint8_t>{ 255, 0, 0, 128 }));
  const auto& m = scene.Materials[0];
  EXPECT_EQ(m.BaseColorTexture.Texture, 0);
  EXPECT_EQ(m.BaseColorTexture.Image, -1);        // drawn without it
  EXPECT_EQ(m.MetallicRoughnessTexture.Image, 1); // not shifted onto image 0
  EXPECT_EQ(m.EmissiveTexture.Image, 2);
  EXPECT_EQ(m.MetallicRoughnessTexture.Sampler.MagFilter, 9728);
  EXPECT_EQ(m.MetallicRoughnessTexture.Sampler.WrapS, 33071);
  EXPECT_TRUE(m.EmissiveTexture.HasTransform);
  const auto uv = m.EmissiveTexture.UvMatrix();
  EXPECT_DOUBLE_EQ(uv[0] * 1 + uv[2], 2.5); // u = 1 -> 0.5 + 2 * 1
  EXPECT_DOUBLE_EQ(m.EmissiveStrength, 4);
  EXPECT_EQ(m.AlphaMode, GltfAlphaMode::Blend);
  EXPECT_TRUE(m.DoubleSided);
  EXPECT_DOUBLE_EQ(m.MetallicFactor, 0.25);
  ASSERT_EQ(m.IgnoredExtensions.size(), 1u);
  EXPECT_EQ(m.IgnoredExtensions[0], "KHR_materials_clearcoat");
  bool notedImage = false, notedClearcoat = false;
  for (const auto& note : scene.Notes)
  {
    notedImage = notedImage || note.find("/images/0 (broken): not decoded") != std::string::npos;
    notedClearcoat = notedClearcoat || note.find("KHR_materials_clearcoat") != std::string::npos;
  }
  EXPECT_TRUE(notedImage);
  EXPECT_TRUE(notedClearcoat);
}

TEST(GltfMaterials, WebpFallbackAndBasisu)
{
  Builder b = TexturedTriangle();
  // Texture 1: a WebP source that does not decode, its fallback `source` the red PNG.
  b.Doc["textures"][1]["extensions"] = { { "EXT_texture_webp", { { "source", 0 } } } };
  // Texture 2: KTX2 only (no decoder): drawn without it, with a note.
  b.Doc["textures"][2] = { { "extensions", { { "KHR_texture_basisu", { { "source", 0 } } } } } };
  const GltfScene scene = Load(b.Glb());
  EXPECT_EQ(scene.Materials[0].MetallicRoughnessTexture.Image, 1);
  EXPECT_EQ(scene.Materials[0].EmissiveTexture.Image, -1);
  bool noted = false;
  for (const auto& note : scene.Notes)
  {
    noted = noted || note.find("KHR_texture_basisu has no decoder") != std::string::npos;
  }
  EXPECT_TRUE(noted);
}

TEST(GltfMaterials, BadMaterialJsonNamesThePointer)
{
  struct Case
  {
    std::function<void(json&)> Change;
    std::string Expected;
  };
  const std::vector<Case> cases = {
    { [](json& d) { d["materials"][0]["alphaMode"] = "GLASS"; },
      "/materials/0/alphaMode: \"GLASS\" is not OPAQUE" },
    { [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 7; },
      "/materials/0/pbrMetallicRoughness/baseColorTexture/index: 7 is not the index" },
    { [](json& d) { d["textures"][0]["source"] = -1; }, "/textures/0/source: -1 is not the index" },
    { [](json& d) { d["samplers"][0]["wrapS"] = 1; },
      "/samplers/0/wrapS: 1 is not a glTF sampler value" },
    { [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = 2; },
      "/materials/0/pbrMetallicRoughness/metallicFactor: must be a number from 0 to 1" },
    { [](json& d) {
       d["materials"][0]["emissiveTexture"]["extensions"]["KHR_texture_transform"]["scale"] = { 1 };
     },
      "/materials/0/emissiveTexture/extensions/KHR_texture_transform/scale: must be an array of 2 "
      "numbers" },
  };
  for (const Case& c : cases)
  {
    Builder b = TexturedTriangle();
    c.Change(b.Doc);
    const std::string error = ErrorOf(b.Glb());
    EXPECT_NE(error.find(c.Expected), std::string::npos) << error;
  }
}

// The fuzz seeds of these paths (Testing/Fuzz/tools/MakeGltfSeeds.cpp) load as meant, so that
// the fuzzer starts inside the decoders, not at their first check.
TEST(GltfMaterials, FuzzSeedsReachTheDecoders)
{
  const std::string corpus = std::string(MORPHNODE_SOURCE_DIR) + "/Testing/Fuzz/corpus/gltf/";
  const GltfScene meshopt = LoadGltfScene(corpus + "meshopt.glb");
  ASSERT_EQ(meshopt.Parts.size(), 1u);
  EXPECT_EQ(meshopt.Parts[0].Positions, (std::vector<float>{ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 }));
  EXPECT_EQ(meshopt.Parts[0].GetNumberOfTriangles(), 2u);
  EXPECT_NEAR(meshopt.Parts[0].Normals[2], 1.0, 0.01); // OCTAHEDRAL filter decoded
  const GltfScene quantized = LoadGltfScene(corpus + "quantized.glb");
  EXPECT_NEAR(quantized.Parts[0].Positions[3], 1.0, 1e-6);
  const GltfScene materials = LoadGltfScene(corpus + "materials.glb");
  ASSERT_EQ(materials.Images.size(), 5u);
  EXPECT_EQ(materials.Images[0].MimeType, "image/png");
  EXPECT_EQ(materials.Images[1].MimeType, "image/webp");
  EXPECT_EQ(materials.Images[2].MimeType, "image/jpeg");
  EXPECT_FALSE(materials.Images[3].IsDecoded());
  EXPECT_EQ(materials.Materials[0].BaseColorTexture.Image, 1); // the WebP
  EXPECT_EQ(materials.Materials[0].AlphaMode, GltfAlphaMode::Mask);
  EXPECT_TRUE(materials.Materials[1].Unlit);
  EXPECT_FALSE(materials.Parts[0].TexCoords1.empty());
}

// Decoded images count against GltfLoadOptions::MaxDecodedBytes with the geometry: an image
// past the budget is left out (with its reason), the file still loads.
TEST(GltfMaterials, ImagesPastTheDecodedSizeLimitAreLeftOut)
{
  const std::string bytes = TexturedTriangle().Glb();
  auto loads = [&](uint64_t limit)
  {
    morphnode::GltfLoadOptions options;
    options.MaxDecodedBytes = limit;
    try
    {
      morphnode::LoadGltfSceneFromMemory(bytes.data(), bytes.size(), "", options, "test.glb");
      return true;
    }
    catch (const InputError&)
    {
      return false;
    }
  };
  // The smallest limit the geometry needs (the check's estimate).
  uint64_t lo = 0, hi = 1 << 20;
  while (lo + 1 < hi)
  {
    const uint64_t mid = (lo + hi) / 2;
    (loads(mid) ? hi : lo) = mid;
  }
  morphnode::GltfLoadOptions options;
  options.MaxDecodedBytes = hi + 4; // room for one 1 x 1 RGBA image
  const GltfScene scene =
    morphnode::LoadGltfSceneFromMemory(bytes.data(), bytes.size(), "", options, "test.glb");
  ASSERT_EQ(scene.Images.size(), 3u);
  EXPECT_TRUE(scene.Images[1].IsDecoded());
  EXPECT_FALSE(scene.Images[2].IsDecoded());
  EXPECT_NE(scene.Images[2].Error.find("more than the limit"), std::string::npos)
    << scene.Images[2].Error;
  EXPECT_EQ(scene.Materials[0].MetallicRoughnessTexture.Image, 1);
  EXPECT_EQ(scene.Materials[0].EmissiveTexture.Image, -1);
}
