// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfCheck.h
/// @brief Internal to the gltf concept: the checks that run before any buffer is touched,
/// on the container (GLB header and chunks) and on the JSON document.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
namespace gltfcheck
{
/// The pieces of a glTF input: the JSON text and, for a GLB, its BIN chunk.
struct Container
{
  bool Binary = false;
  const char* Json = nullptr;
  size_t JsonSize = 0;
  const unsigned char* Bin = nullptr; ///< null when the GLB has no BIN chunk
  size_t BinSize = 0;
};

/// Splits a GLB into its chunks (checking the header, every chunk length and type, and
/// the 4-byte alignment) or takes the whole input as glTF JSON.
/// Throws InputError "<source>: GLB: ...".
Container SplitContainer(const unsigned char* data, size_t size, const std::string& source);

/// Parses the JSON (no more than MaxDepth levels of nesting).
nlohmann::json ParseJson(const Container& container, const std::string& source);

constexpr int MaxDepth = 64;

/// What the check learnt and the decoder uses.
struct Document
{
  int Scene = -1;                  ///< the scene to read, -1 when there is none
  std::vector<int> Roots;          ///< its root nodes, in order
  std::vector<int> Parent;         ///< per node, -1 for a root
  std::vector<size_t> MeshTargets; ///< morph targets per mesh
  uint64_t DecodedBytes = 0;       ///< estimate of the decoded scene
};

/// Checks the document against the parts of the glTF 2.0 schema MorphNode uses, every
/// index against its array, every accessor and buffer view against the byte lengths the
/// buffers declare, and the scene's structure. `external` tells whether buffers may live
/// in files beside the input. Throws InputError "<source>: <JSON pointer>: <what>".
Document CheckDocument(const nlohmann::json& root, const Container& container, bool external,
  uint64_t maxDecodedBytes, const std::string& source);

/// Bytes per component of a glTF componentType (0 when it is not one).
size_t ComponentSize(int componentType);
/// Components per element of a glTF accessor type ("SCALAR" 1 ... "MAT4" 16; 0 if none).
int ComponentCount(const std::string& type);
} // namespace gltfcheck
} // namespace morphnode
