// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfScene.h
/// @brief A glTF 2.0 scene (.glb or .gltf) read into plain arrays, every input validated
/// first: the parts (one per primitive of each node that holds a mesh, in scene order),
/// their morph targets and names, node transforms, materials' base colours, the node
/// hierarchy and the animations.
///
/// How it reads (docs/gltf.md has the whole list of checks):
/// 1. The container: a GLB's header and chunks are checked by MorphNode (lengths, types,
///    alignment); a .gltf is UTF-8 JSON.
/// 2. The JSON is parsed with nlohmann/json (nesting depth limited) and checked by MorphNode
///    against the parts of the glTF 2.0 schema the scene uses: every field's JSON type and
///    range, every index against the array it points into, every accessor and buffer view
///    against the bytes its buffer declares, sparse accessors, primitive modes, attribute
///    types and counts, morph target counts per primitive and mesh, target names, weights,
///    the node hierarchy (one parent per node, no cycles), materials and animations.
///    A failure is an InputError naming the JSON pointer, e.g.
///    "face.glb: /accessors/12/sparse/count: 400 exceeds the accessor's count 300".
/// 3. Only then does tinygltf (Debian's libtinygltf-dev, compiled into this library without
///    image decoding) turn the same document into its model and load the buffers: the GLB's
///    BIN chunk, base64 data URIs, or a .bin file beside a .gltf (only there: absolute paths,
///    "..", other folders and URL schemes are refused). tinygltf is not trusted for safety:
///    it misses some bounds (sparse accessors, index values, overflowing offsets) and casts
///    64-bit integers to int without a check; step 2 runs before it, and every byte read
///    afterwards goes through a bounds-checked view of the buffer.
/// 4. The data are decoded, and what only the bytes can tell is checked on the way: index
///    values below the vertex count, sparse indices increasing and in range, finite floats,
///    animation times finite, not negative and non-decreasing.
///
/// Nothing here depends on VTK.

#include "gltf/GltfMaterial.h"
#include "skin/SkinInfluences.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
/// A 4x4 matrix in glTF's order: column-major, element (row r, column c) at [c * 4 + r].
using GltfMatrix = std::array<double, 16>;

/// The identity.
GltfMatrix GltfIdentity();
/// T * R * S as glTF composes a node's translation, rotation (unit quaternion x, y, z, w)
/// and scale.
GltfMatrix GltfComposeTrs(const std::array<double, 3>& translation,
  const std::array<double, 4>& rotation, const std::array<double, 3>& scale);
/// a * b.
GltfMatrix GltfMultiply(const GltfMatrix& a, const GltfMatrix& b);

struct GltfNode
{
  std::string Name; ///< as in the file (may be empty)
  int Parent = -1;
  std::vector<int> Children;
  int Mesh = -1;
  /// True when the node gives `matrix`; Translation/Rotation/Scale are then the defaults.
  bool HasMatrix = false;
  std::array<double, 3> Translation{ { 0, 0, 0 } };
  std::array<double, 4> Rotation{ { 0, 0, 0, 1 } }; ///< x, y, z, w, normalized
  std::array<double, 3> Scale{ { 1, 1, 1 } };
  GltfMatrix Local = GltfIdentity(); ///< the node's own transform
  GltfMatrix World = GltfIdentity(); ///< parents' transforms applied (root first)
  /// The node's own default morph weights (`node.weights`), empty when it has none.
  std::vector<double> Weights;
  bool InScene = false; ///< reached from the scene that was read
};

struct GltfMesh
{
  std::string Name;
  size_t NumberOfPrimitives = 0;
  /// One per morph target (the same for every primitive): `extras.targetNames`, or
  /// "target0", "target1", ... when the file has none.
  std::vector<std::string> TargetNames;
  /// `mesh.weights`, or zeros (one per target) when absent.
  std::vector<double> Weights;
};

struct GltfTarget
{
  std::string Name;
  /// 3 per point; zeros where the target does not move the point. Always present.
  std::vector<float> PositionDeltas;
  /// 3 per point when the target has NORMAL deltas, else empty.
  std::vector<float> NormalDeltas;
};

/// One primitive of one node of the scene: a triangle mesh with its morph targets.
struct GltfPart
{
  /// Unique in the scene: the node's name (or "node<i>"), plus "/<material name>" (or
  /// "/primitive<j>") when its mesh has several primitives.
  std::string Name;
  int Node = -1;
  int Mesh = -1;
  int Primitive = -1;
  int Material = -1; ///< -1: glTF's default material
  std::string MaterialName;
  /// The material's `pbrMetallicRoughness.baseColorFactor` (linear RGBA; white by default).
  std::array<double, 4> BaseColor{ { 1, 1, 1, 1 } };

  /// The node's world transform. When TransformApplied, Positions, Normals and the deltas
  /// are in world space (and triangles turned when the transform mirrors); otherwise they
  /// are as in the file, in the node's frame.
  GltfMatrix World = GltfIdentity();
  bool TransformApplied = false;

  std::vector<float> Positions; ///< 3 per point
  std::vector<float> Normals;   ///< 3 per point, or empty when the file has none
  std::vector<float> Colors;    ///< COLOR_0 as RGBA, 4 per point, or empty
  /// TEXCOORD_0 and TEXCOORD_1, 2 per point (u, v as in the file: v down), or empty.
  std::vector<float> TexCoords0;
  std::vector<float> TexCoords1;
  /// 3 point indices per triangle (strips and fans converted; a primitive without indices
  /// uses its points in order).
  std::vector<uint32_t> Triangles;

  std::vector<GltfTarget> Targets;
  /// The default morph weights: the node's `weights`, else the mesh's, else zeros.
  std::vector<double> DefaultWeights;

  /// A skinned part (gltf/GltfSkin.h): its node's skin (into GltfScene::Skins), -1 when the
  /// part is not skinned, and every JOINTS_n/WEIGHTS_n set, weights renormalized. With
  /// ApplyTransforms the part is skinned at rest (the joints as stored; the node's own
  /// transform ignored as glTF requires), its deltas and normals with it; otherwise it is in
  /// its bind space as in the file.
  int Skin = -1;
  SkinInfluences Influences;

  size_t GetNumberOfPoints() const { return this->Positions.size() / 3; }
  size_t GetNumberOfTriangles() const { return this->Triangles.size() / 3; }
};

enum class GltfInterpolation
{
  Linear,
  Step,
  CubicSpline
};

enum class GltfAnimationPath
{
  Translation,
  Rotation,
  Scale,
  Weights
};

struct GltfAnimationSampler
{
  GltfInterpolation Interpolation = GltfInterpolation::Linear;
  std::vector<float> Times; ///< seconds, finite, >= 0, non-decreasing
  /// Output values, Components per element (normalized integers converted to float). For
  /// CUBICSPLINE each key has three elements: in-tangent, value, out-tangent.
  std::vector<float> Values;
  int Components = 0;
};

struct GltfAnimationChannel
{
  int Sampler = -1; ///< into the animation's samplers
  int Node = -1;
  GltfAnimationPath Path = GltfAnimationPath::Translation;
  /// Values per key and element: 3 (translation, scale), 4 (rotation), or the number of
  /// morph targets of the node's mesh (weights).
  int ValuesPerElement = 0;
};

/// Validated animation data; gltf/GltfAnimation.h plays them (GltfAnimationPlayer).
struct GltfAnimation
{
  std::string Name;
  std::vector<GltfAnimationSampler> Samplers;
  std::vector<GltfAnimationChannel> Channels;
};

/// A skin: its joints (node indices) and inverse bind matrices (identity when absent).
struct GltfSkin
{
  std::string Name;
  std::vector<int> Joints;
  std::vector<GltfMatrix> InverseBind;
  int Skeleton = -1; ///< the `skeleton` node, -1 when absent
};

struct GltfScene
{
  int Scene = -1; ///< the scene read (`scene`, else 0); -1: the file has no scenes
  std::string SceneName;
  std::vector<GltfNode> Nodes;
  std::vector<GltfMesh> Meshes;
  std::vector<GltfPart> Parts;
  std::vector<GltfAnimation> Animations;
  std::vector<GltfSkin> Skins;
  /// The file's materials (GltfPart::Material indexes them) and images (decoded RGBA8).
  std::vector<GltfMaterial> Materials;
  std::vector<GltfImage> Images;
  /// What was read but is not drawn or was left out, one line each (optional extensions
  /// ignored, images that did not decode, ...).
  std::vector<std::string> Notes;

  size_t GetNumberOfPoints() const;
  /// Index of the part with this name, -1 if none.
  int FindPart(const std::string& name) const;
};

/// The name MorphNode gives a node: its own, else "node<n>".
std::string GltfNodeName(const GltfScene& scene, int node);
/// A mesh's name, else "mesh<m>".
std::string GltfMeshName(const GltfScene& scene, size_t mesh);
/// An animation's name, else "animation<a>".
std::string GltfAnimationName(const GltfScene& scene, size_t animation);

struct GltfLoadOptions
{
  /// Apply each node's world transform to its parts' points, normals and deltas.
  bool ApplyTransforms = true;
  /// Upper bound on the decoded scene in bytes, checked before anything is decoded: a
  /// small file can declare huge zero-filled accessors (sparse without bufferView) or
  /// instance one mesh on many nodes.
  uint64_t MaxDecodedBytes = uint64_t(2) << 30;
};

/// Transforms a part's points, normals and deltas by `m` as the loader's ApplyTransforms
/// does (normals by the inverse transpose, kept unit with their deltas scaled alike;
/// triangles turned when `m` mirrors) and sets TransformApplied. Points a transform takes
/// beyond float range are not checked here.
void GltfTransformPart(GltfPart& part, const GltfMatrix& m);

/// Reads a .glb or .gltf file (a .gltf may use data URIs or .bin files in its own folder).
/// Throws InputError, naming the file and the JSON pointer of the fault.
GltfScene LoadGltfScene(const std::string& fileName, const GltfLoadOptions& options = {});

/// Reads a GLB or glTF JSON held in memory. External buffers resolve in baseDirectory; with
/// an empty baseDirectory a buffer that is not embedded is an error. `sourceName` prefixes
/// error messages.
GltfScene LoadGltfSceneFromMemory(const void* data, size_t size,
  const std::string& baseDirectory = std::string(), const GltfLoadOptions& options = {},
  const std::string& sourceName = "glTF");
} // namespace morphnode
