// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfExtensions.h
/// @brief Internal to the gltf concept: the glTF extensions the loader implements, and the
/// decoding of compressed buffer views (EXT_meshopt_compression, GltfMeshopt.cpp) that
/// runs between tinygltf's parse and the reading of accessors.
///
/// The loader's order (GltfScene.cpp): the checks (GltfCheck.cpp) accept a required
/// extension only when IsImplemented says so; a GLB or glTF whose meshopt fallback buffers
/// hold no data is handed to tinygltf with those buffers stubbed (PatchForTinygltf: tinygltf
/// 2.7 would copy the BIN chunk into them or fail); then DecodeMeshopt fills every
/// compressed view, and the accessor reader takes a view's bytes from there before the
/// buffer.

#include "TinyGltfConfig.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace morphnode
{
namespace gltfext
{
/// True for the extensions MorphNode reads (a file may list them in extensionsRequired):
/// KHR_mesh_quantization, EXT_meshopt_compression, EXT_texture_webp, KHR_texture_transform,
/// KHR_materials_unlit, KHR_materials_emissive_strength.
bool IsImplemented(const std::string& name);

/// Why a known extension is not implemented (empty when MorphNode knows nothing of it).
std::string WhyNotImplemented(const std::string& name);

/// True when `buffer` is an EXT_meshopt_compression fallback buffer without data (no uri):
/// only the compressed views' decoded bytes are ever read from it.
bool IsMeshoptFallback(const nlohmann::json& buffer);

/// True when the document has fallback buffers without data that tinygltf cannot parse.
bool NeedsPatch(const nlohmann::json& root);

/// The document as tinygltf can parse it: each fallback buffer without data gets a 3-byte
/// data URI instead. For a GLB the result is a whole GLB (the patched JSON chunk and the
/// original BIN chunk), for a .gltf the JSON text. `bin` / `binSize`: the GLB's BIN chunk
/// (null for a .gltf).
std::string PatchForTinygltf(
  const nlohmann::json& root, bool binary, const unsigned char* bin, size_t binSize);

/// Decoded bytes of compressed buffer views, by bufferView index; each holds the view's
/// byteLength bytes.
using DecodedViews = std::map<int, std::vector<unsigned char>>;

/// Decodes every bufferView with EXT_meshopt_compression (modes ATTRIBUTES, TRIANGLES and
/// INDICES; filters NONE, OCTAHEDRAL, QUATERNION and EXPONENTIAL) through Debian's
/// libmeshoptimizer. A stream version or filter the library cannot decode, a source range
/// outside its buffer, or more than `maxBytes` decoded in all: InputError naming the view.
DecodedViews DecodeMeshopt(const tinygltf::Model& model, const nlohmann::json& root,
  uint64_t maxBytes, const std::string& source);
} // namespace gltfext
} // namespace morphnode

namespace morphnode
{
struct GltfScene;
namespace gltfext
{
/// Reads `materials`, `textures`, `samplers` and `images` into the scene (Materials,
/// Images, Notes). `imageBytes[i]`: the encoded bytes of image i as tinygltf handed them to
/// its image loader (a bufferView or a data URI), empty for an image in a file;
/// `readFile(uri, bytes, error)` reads such a file (null: not allowed). An image that does
/// not decode keeps its index with an Error, and the textures using it draw without it;
/// so does one that would take the decoded images past `maxBytes` in all.
/// Malformed material JSON: InputError naming the pointer.
void ReadMaterials(const nlohmann::json& root,
  const std::vector<std::vector<unsigned char>>& imageBytes,
  bool (*readFile)(
    const std::string& uri, std::vector<unsigned char>& bytes, std::string& error, void* user),
  void* user, uint64_t maxBytes, GltfScene& scene, const std::string& source);
} // namespace gltfext
} // namespace morphnode
