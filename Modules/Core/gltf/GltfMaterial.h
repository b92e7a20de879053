// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfMaterial.h
/// @brief glTF 2.0 materials as the file defines them (metallic-roughness PBR, their
/// textures and samplers, KHR_texture_transform, alpha modes, KHR_materials_unlit and
/// KHR_materials_emissive_strength) and the images decoded to RGBA8 (PNG and JPEG, WebP
/// through EXT_texture_webp with its fallback). docs/materials.md says what survives of a
/// material and why. Nothing here depends on VTK.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
/// An image of the file, decoded to 8-bit RGBA, rows top first (as glTF's UV origin).
struct GltfImage
{
  std::string Name;
  std::string MimeType; ///< image/png, image/jpeg or image/webp (from the bytes)
  int Width = 0;
  int Height = 0;
  std::vector<uint8_t> Pixels; ///< 4 * Width * Height; empty when not decoded
  /// The image's bytes as the file holds them (PNG, JPEG or WebP), kept so that an export
  /// writes them back unchanged; empty when the image had no data.
  std::vector<uint8_t> Encoded;
  /// Why the image could not be decoded (empty when it was). Such an image is left out of
  /// the textures that use it; the other images keep their indices.
  std::string Error;
  bool IsDecoded() const { return this->Error.empty() && !this->Pixels.empty(); }
};

/// glTF sampler values (WebGL enums): filters 9728 NEAREST, 9729 LINEAR, 9984..9987 the
/// mipmap variants (0: unset); wraps 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT, 10497 REPEAT.
struct GltfSampler
{
  int MagFilter = 0;
  int MinFilter = 0;
  int WrapS = 10497;
  int WrapT = 10497;
};

/// A material's reference to a texture (textureInfo), resolved to an image.
struct GltfTextureRef
{
  int Texture = -1; ///< index into the file's textures; -1: none
  /// The image drawn: the texture's EXT_texture_webp source, else its source; -1 when the
  /// texture has none that decoded (see the scene's Notes).
  int Image = -1;
  int TexCoord = 0; ///< TEXCOORD_n set (KHR_texture_transform's texCoord overrides)
  /// normalTexture.scale or occlusionTexture.strength; 1 otherwise.
  double Scale = 1.0;
  GltfSampler Sampler;
  /// KHR_texture_transform: uv' = T(offset) * R(rotation) * S(scale) * uv.
  bool HasTransform = false;
  std::array<double, 2> Offset{ { 0, 0 } };
  double Rotation = 0.0; ///< radians, counter-clockwise in UV space
  std::array<double, 2> UvScale{ { 1, 1 } };

  bool IsSet() const { return this->Image >= 0; }
  /// The 3x3 UV transform (row-major, last row 0 0 1) of KHR_texture_transform.
  std::array<double, 9> UvMatrix() const;
};

enum class GltfAlphaMode
{
  Opaque,
  Mask,
  Blend
};

struct GltfMaterial
{
  std::string Name;
  std::array<double, 4> BaseColorFactor{ { 1, 1, 1, 1 } }; ///< linear RGBA
  GltfTextureRef BaseColorTexture;                         ///< sRGB RGBA
  double MetallicFactor = 1.0;
  double RoughnessFactor = 1.0;
  GltfTextureRef MetallicRoughnessTexture; ///< linear: roughness in G, metallic in B
  GltfTextureRef NormalTexture;            ///< tangent space; Scale = normal scale
  GltfTextureRef OcclusionTexture;         ///< R; Scale = strength
  GltfTextureRef EmissiveTexture;          ///< sRGB
  std::array<double, 3> EmissiveFactor{ { 0, 0, 0 } };
  double EmissiveStrength = 1.0; ///< KHR_materials_emissive_strength
  GltfAlphaMode AlphaMode = GltfAlphaMode::Opaque;
  double AlphaCutoff = 0.5;
  bool DoubleSided = false;
  bool Unlit = false; ///< KHR_materials_unlit
  /// Material extensions present but not drawn (e.g. KHR_materials_clearcoat).
  std::vector<std::string> IgnoredExtensions;
};

const char* GltfAlphaModeName(GltfAlphaMode mode);

/// Decodes a PNG, JPEG or WebP held in memory (the format from its signature) to RGBA8
/// through libpng, libjpeg-turbo and libwebp. Returns false with `error` set when the bytes
/// are not an image these decode or it is larger than `maxPixels`.
bool GltfDecodeImage(const unsigned char* bytes, size_t size, GltfImage& image,
  uint64_t maxPixels = uint64_t(1) << 26);

/// Encodes a decoded image (RGBA8) as PNG through libpng. Throws InputError when the
/// image has no pixels or libpng fails.
std::vector<uint8_t> GltfEncodePng(const GltfImage& image);
} // namespace morphnode
