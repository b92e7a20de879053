// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the glTF/GLB scene loader (LoadGltfSceneFromMemory), with checks of what
// an accepted scene promises. A structure-aware mutator (LLVMFuzzerCustomMutator) edits
// the JSON with nlohmann/json, keeps it valid JSON, and rebuilds a consistent GLB around
// it, so that most inputs reach the checks behind the JSON parser; one mutation in four is
// libFuzzer's own byte-level one (container damage, binary data).
#include "base/Error.h"
#include "gltf/GltfAnimation.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfVrm.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t maxSize)
  __attribute__((weak));

namespace
{
void Check(bool ok)
{
  if (!ok)
  {
    std::abort();
  }
}

bool Finite(const std::vector<float>& v)
{
  for (float x : v)
  {
    if (!std::isfinite(x))
    {
      return false;
    }
  }
  return true;
}

void CheckScene(const morphnode::GltfScene& scene)
{
  for (const auto& part : scene.Parts)
  {
    const size_t n = part.GetNumberOfPoints();
    Check(n > 0 && part.Positions.size() == 3 * n && Finite(part.Positions));
    Check(part.Normals.empty() || (part.Normals.size() == 3 * n && Finite(part.Normals)));
    Check(part.Colors.empty() || (part.Colors.size() == 4 * n && Finite(part.Colors)));
    Check(part.Triangles.size() % 3 == 0);
    for (uint32_t i : part.Triangles)
    {
      Check(i < n);
    }
    Check(part.DefaultWeights.size() == part.Targets.size());
    for (const auto& target : part.Targets)
    {
      Check(target.PositionDeltas.size() == 3 * n && Finite(target.PositionDeltas));
      Check(target.NormalDeltas.empty() ||
        (target.NormalDeltas.size() == 3 * n && Finite(target.NormalDeltas)));
    }
    Check(part.Node >= 0 && static_cast<size_t>(part.Node) < scene.Nodes.size());
    Check(scene.Nodes[static_cast<size_t>(part.Node)].Mesh == part.Mesh);
    for (double v : part.World)
    {
      Check(std::isfinite(v));
    }
    Check(scene.FindPart(part.Name) == static_cast<int>(&part - scene.Parts.data()));
  }
  for (size_t i = 0; i < scene.Nodes.size(); ++i)
  {
    const auto& node = scene.Nodes[i];
    for (int c : node.Children)
    {
      Check(c >= 0 && static_cast<size_t>(c) < scene.Nodes.size() &&
        scene.Nodes[static_cast<size_t>(c)].Parent == static_cast<int>(i));
    }
    Check(node.Mesh < static_cast<int>(scene.Meshes.size()));
  }
  for (const auto& animation : scene.Animations)
  {
    for (const auto& sampler : animation.Samplers)
    {
      Check(sampler.Components > 0 &&
        sampler.Values.size() % static_cast<size_t>(sampler.Components) == 0);
      for (size_t k = 1; k < sampler.Times.size(); ++k)
      {
        Check(sampler.Times[k] >= sampler.Times[k - 1]);
      }
    }
    for (const auto& channel : animation.Channels)
    {
      Check(
        channel.Sampler >= 0 && static_cast<size_t>(channel.Sampler) < animation.Samplers.size());
      Check(channel.Node >= 0 && static_cast<size_t>(channel.Node) < scene.Nodes.size());
      const auto& sampler = animation.Samplers[static_cast<size_t>(channel.Sampler)];
      const size_t keys = sampler.Times.size();
      const size_t cubic =
        sampler.Interpolation == morphnode::GltfInterpolation::CubicSpline ? 3 : 1;
      Check(channel.ValuesPerElement > 0 &&
        sampler.Values.size() == keys * cubic * static_cast<size_t>(channel.ValuesPerElement));
    }
  }
}

/// Plays every animation at its ends, between and outside its keys: rotations stay unit
/// quaternions, every node keeps its weights' count (GltfAnimation.h).
void SampleAnimations(const morphnode::GltfScene& scene)
{
  for (size_t a = 0; a < scene.Animations.size(); ++a)
  {
    try
    {
      const morphnode::GltfAnimationPlayer player(scene, static_cast<int>(a), "fuzz");
      const double start = player.GetStartTime(), end = player.GetEndTime();
      for (double t :
        { start - 1, start, 0.5 * (start + end), 0.3 * start + 0.7 * end, end, end + 1 })
      {
        const morphnode::GltfSceneSample sample = player.Sample(t);
        Check(sample.Nodes.size() == scene.Nodes.size());
        for (size_t n = 0; n < sample.Nodes.size(); ++n)
        {
          const auto& q = sample.Nodes[n].Rotation;
          Check(std::abs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1) < 1e-6);
          const int mesh = scene.Nodes[n].Mesh;
          Check(sample.Nodes[n].Weights.size() ==
            (mesh >= 0 ? scene.Meshes[static_cast<size_t>(mesh)].TargetNames.size() : 0));
        }
      }
      morphnode::GltfWeightsByTargetName(scene, player.Sample(start));
    }
    catch (const morphnode::InputError&)
    {
      // an animated node given by a matrix
    }
  }
}

// --- the structure-aware mutator --------------------------------------------------------

using json = nlohmann::json;

uint32_t ReadLe32(const uint8_t* p)
{
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

void AppendLe32(std::string& out, uint32_t v)
{
  for (int i = 0; i < 4; ++i)
  {
    out += static_cast<char>((v >> (8 * i)) & 0xff);
  }
}

/// Every value of the document with its parent (for erasing), in no particular order.
struct Slot
{
  json* Value;
  json* Parent;
  std::string Key; ///< in an object parent
  size_t Index;    ///< in an array parent
};

std::vector<Slot> Slots(json& root)
{
  std::vector<Slot> slots;
  std::vector<Slot> stack{ { &root, nullptr, std::string(), 0 } };
  while (!stack.empty())
  {
    Slot s = stack.back();
    stack.pop_back();
    slots.push_back(s);
    if (s.Value->is_object())
    {
      for (auto it = s.Value->begin(); it != s.Value->end(); ++it)
      {
        stack.push_back({ &it.value(), s.Value, it.key(), 0 });
      }
    }
    else if (s.Value->is_array())
    {
      for (size_t i = 0; i < s.Value->size(); ++i)
      {
        stack.push_back({ &(*s.Value)[i], s.Value, std::string(), i });
      }
    }
  }
  return slots;
}

json Interesting(std::minstd_rand& rng, const json& current)
{
  static const int64_t integers[] = { -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 24, 252, 255, 256,
    65535, 65536, 2147483647LL, 2147483648LL, 4294967295LL, 4294967296LL, -2147483648LL,
    9007199254740993LL, 5120, 5121, 5122, 5123, 5124, 5125, 5126, 5127, 34962, 34963 };
  static const char* const strings[] = { "SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4",
    "POSITION", "NORMAL", "COLOR_0", "LINEAR", "STEP", "CUBICSPLINE", "translation", "rotation",
    "scale", "weights", "", "2.0", "1.0", "data:application/octet-stream;base64,AAAA", "x.bin",
    "../x.bin", "KHR_draco_mesh_compression", "KHR_materials_unlit", "data:image/png;base64,AAAA",
    "a~b/c", "KHR_mesh_quantization", "EXT_meshopt_compression", "EXT_texture_webp",
    "KHR_texture_transform", "KHR_texture_basisu", "ATTRIBUTES", "TRIANGLES", "INDICES",
    "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL", "OPAQUE", "MASK", "BLEND", "TEXCOORD_0",
    "TEXCOORD_1", "image/webp", "image/jpeg" };
  switch (rng() % 8)
  {
    case 0:
    case 1:
      return integers[rng() % (sizeof(integers) / sizeof(integers[0]))];
    case 2:
      if (current.is_number_integer())
      {
        const int64_t deltas[] = { -4, -1, 1, 4, 12 };
        return current.get<int64_t>() + deltas[rng() % 5];
      }
      return static_cast<double>(static_cast<int>(rng() % 2001) - 1000) / 8.0;
    case 3:
      return strings[rng() % (sizeof(strings) / sizeof(strings[0]))];
    case 4:
      return json::array({ 0, 1, 2 });
    case 5:
      return rng() % 2 ? json::object() : json(nullptr);
    case 6:
      return rng() % 2 == 0;
    default:
      return 1e300 * (rng() % 2 ? 1 : -1);
  }
}

void MutateJson(json& root, std::minstd_rand& rng)
{
  std::vector<Slot> slots = Slots(root);
  const Slot s = slots[rng() % slots.size()];
  switch (rng() % 6)
  {
    case 0:
    case 1:
      *s.Value = Interesting(rng, *s.Value);
      break;
    case 2: // erase
      if (s.Parent && s.Parent->is_object())
      {
        s.Parent->erase(s.Key);
      }
      else if (s.Parent && s.Parent->is_array())
      {
        s.Parent->erase(s.Index);
      }
      break;
    case 3: // duplicate an element of an array
      if (s.Value->is_array() && !s.Value->empty())
      {
        s.Value->push_back((*s.Value)[rng() % s.Value->size()]);
      }
      else if (s.Parent && s.Parent->is_array())
      {
        s.Parent->push_back(*s.Value);
      }
      break;
    case 4: // copy another subtree here
    {
      const Slot from = slots[rng() % slots.size()];
      if (from.Value != s.Value)
      {
        json copy = *from.Value;
        *s.Value = std::move(copy);
      }
      break;
    }
    default: // add a known glTF key to an object
      if (s.Value->is_object())
      {
        static const char* const keys[] = { "bufferView", "byteOffset", "byteStride", "count",
          "sparse", "indices", "targets", "weights", "matrix", "children", "mesh", "scene", "mode",
          "material", "normalized", "extras", "rotation", "scale", "translation", "node", "sampler",
          "images", "uri", "extensionsRequired", "path", "interpolation", "type", "componentType",
          "byteLength", "input", "output", "attributes", "POSITION", "NORMAL", "COLOR_0",
          "targetNames", "baseColorFactor", "baseColorTexture", "index", "texCoord", "alphaMode",
          "alphaCutoff", "doubleSided", "source", "extensions", "filter", "fallback", "TEXCOORD_0",
          "emissiveFactor", "normalTexture", "offset" };
        (*s.Value)[keys[rng() % (sizeof(keys) / sizeof(keys[0]))]] = Interesting(rng, json());
      }
      break;
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  morphnode::GltfLoadOptions options;
  options.MaxDecodedBytes = 64u << 20; // stay well inside libFuzzer's memory limit
  try
  {
    const morphnode::GltfScene scene =
      morphnode::LoadGltfSceneFromMemory(data, size, "", options, "fuzz");
    CheckScene(scene);
    SampleAnimations(scene);
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  try
  {
    // A VRM's description (gltf/GltfVrm.h) from the same bytes: binds name existing targets.
    const morphnode::GltfVrm vrm = morphnode::ReadGltfVrmFromMemory(data, size, "fuzz");
    for (const auto& e : vrm.Expressions)
    {
      for (const auto& bind : e.Binds)
      {
        Check(bind.second >= 0.0 && bind.second <= 1.0);
      }
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}

extern "C" size_t LLVMFuzzerCustomMutator(
  uint8_t* data, size_t size, size_t maxSize, unsigned int seed)
{
  std::minstd_rand rng(seed);
  if (rng() % 4 == 0)
  {
    return LLVMFuzzerMutate(data, size, maxSize);
  }
  const bool glb = size >= 20 && std::memcmp(data, "glTF", 4) == 0;
  std::string text;
  std::string bin;
  if (glb)
  {
    const uint32_t jsonLength = ReadLe32(data + 12);
    if (jsonLength > size - 20)
    {
      return LLVMFuzzerMutate(data, size, maxSize);
    }
    text.assign(reinterpret_cast<const char*>(data + 20), jsonLength);
    const size_t at = 20 + size_t(jsonLength);
    if (size - at >= 8)
    {
      const uint32_t binLength = ReadLe32(data + at);
      if (binLength <= size - at - 8)
      {
        bin.assign(reinterpret_cast<const char*>(data + at + 8), binLength);
      }
    }
  }
  else
  {
    text.assign(reinterpret_cast<const char*>(data), size);
  }
  json root = json::parse(text, nullptr, false);
  if (root.is_discarded())
  {
    return LLVMFuzzerMutate(data, size, maxSize);
  }
  if (!bin.empty() && rng() % 5 == 0)
  {
    // Mutate the binary data (in place, or resized and byteLength following it).
    const size_t binSize = bin.size();
    bin.resize(std::max<size_t>(binSize, 4) * 2);
    size_t n = LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(&bin[0]), binSize, bin.size());
    n = (n + 3) / 4 * 4;
    bin.resize(n);
    if (rng() % 2 && root.is_object() && root.contains("buffers") && root["buffers"].is_array() &&
      !root["buffers"].empty() && root["buffers"][0].is_object())
    {
      root["buffers"][0]["byteLength"] = n;
    }
  }
  else
  {
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int i = 0; i < edits; ++i)
    {
      MutateJson(root, rng);
    }
  }
  std::string out;
  std::string dumped = root.dump();
  if (glb)
  {
    while (dumped.size() % 4 != 0)
    {
      dumped += ' ';
    }
    AppendLe32(out, 0x46546C67);
    AppendLe32(out, 2);
    AppendLe32(out, static_cast<uint32_t>(20 + dumped.size() + (bin.empty() ? 0 : 8 + bin.size())));
    AppendLe32(out, static_cast<uint32_t>(dumped.size()));
    AppendLe32(out, 0x4E4F534A);
    out += dumped;
    if (!bin.empty())
    {
      AppendLe32(out, static_cast<uint32_t>(bin.size()));
      AppendLe32(out, 0x004E4942);
      out += bin;
    }
  }
  else
  {
    out = std::move(dumped);
  }
  if (out.size() > maxSize)
  {
    return LLVMFuzzerMutate(data, size, maxSize);
  }
  std::memcpy(data, out.data(), out.size());
  return out.size();
}
