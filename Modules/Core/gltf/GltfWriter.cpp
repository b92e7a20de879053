// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfWriter.h"

#include "TinyGltfConfig.h"

#include "base/Error.h"
#include "base/File.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace morphnode
{
namespace
{
[[noreturn]] void Fail(const std::string& message)
{
  throw InputError("glTF export: " + message);
}

bool AllFinite(const std::vector<float>& v)
{
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

/// Builds the tinygltf model: one buffer, one buffer view per accessor (or sparse part).
struct ModelBuilder
{
  tinygltf::Model Model;
  bool Quantized = false; ///< some accessor uses KHR_mesh_quantization

  ModelBuilder() { this->Model.buffers.emplace_back(); }

  std::vector<unsigned char>& Bin() { return this->Model.buffers[0].data; }

  int AddView(const void* data, size_t bytes, int target)
  {
    auto& bin = this->Bin();
    while (bin.size() % 4 != 0)
    {
      bin.push_back(0);
    }
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bin.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + bytes);
    this->Model.bufferViews.push_back(view);
    return static_cast<int>(this->Model.bufferViews.size() - 1);
  }

  static int TypeOf(int components)
  {
    switch (components)
    {
      case 1:
        return TINYGLTF_TYPE_SCALAR;
      case 2:
        return TINYGLTF_TYPE_VEC2;
      case 3:
        return TINYGLTF_TYPE_VEC3;
      case 16:
        return TINYGLTF_TYPE_MAT4;
      default:
        return TINYGLTF_TYPE_VEC4;
    }
  }

  /// min and max per component of `values` (count elements of `components`).
  static void MinMax(const std::vector<float>& values, int components, tinygltf::Accessor& a)
  {
    a.minValues.assign(static_cast<size_t>(components), std::numeric_limits<double>::infinity());
    a.maxValues.assign(static_cast<size_t>(components), -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < values.size(); ++i)
    {
      const size_t c = i % static_cast<size_t>(components);
      a.minValues[c] = std::min(a.minValues[c], static_cast<double>(values[i]));
      a.maxValues[c] = std::max(a.maxValues[c], static_cast<double>(values[i]));
    }
    if (values.empty())
    {
      a.minValues.clear();
      a.maxValues.clear();
    }
  }

  int AddAccessor(tinygltf::Accessor a)
  {
    this->Model.accessors.push_back(std::move(a));
    return static_cast<int>(this->Model.accessors.size() - 1);
  }

  /// Dense floats.
  int AddFloats(const std::vector<float>& values, int components, bool minMax, int target)
  {
    tinygltf::Accessor a;
    a.bufferView = this->AddView(values.data(), values.size() * sizeof(float), target);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = TypeOf(components);
    a.count = values.size() / static_cast<size_t>(components);
    if (minMax)
    {
      MinMax(values, components, a);
    }
    return this->AddAccessor(std::move(a));
  }

  /// Target deltas (3 per point): sparse when that is smaller, no data when all zero;
  /// sparse values as normalized shorts when `quantize` and they fit (Quantized is set).
  int AddDeltas(const std::vector<float>& deltas, bool quantize = false)
  {
    const size_t n = deltas.size() / 3;
    std::vector<uint32_t> moved;
    for (size_t i = 0; i < n; ++i)
    {
      if (deltas[3 * i] != 0.0f || deltas[3 * i + 1] != 0.0f || deltas[3 * i + 2] != 0.0f)
      {
        moved.push_back(static_cast<uint32_t>(i));
      }
    }
    const bool shortIndices = n <= 65536;
    const size_t sparseBytes = moved.size() * (12 + (shortIndices ? 2 : 4));
    if (!moved.empty() && sparseBytes >= 12 * n)
    {
      return this->AddFloats(deltas, 3, true, TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    tinygltf::Accessor a;
    a.bufferView = -1;
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = TINYGLTF_TYPE_VEC3;
    a.count = n;
    std::vector<float> values;
    values.reserve(3 * moved.size());
    for (uint32_t i : moved)
    {
      values.insert(values.end(), deltas.begin() + 3 * i, deltas.begin() + 3 * i + 3);
    }
    // min/max over the whole accessor: the points it does not move are zeros.
    MinMax(values, 3, a);
    if (moved.size() < n || values.empty())
    {
      a.minValues.resize(3, 0.0);
      a.maxValues.resize(3, 0.0);
      for (int c = 0; c < 3; ++c)
      {
        a.minValues[c] = std::min(a.minValues[c], 0.0);
        a.maxValues[c] = std::max(a.maxValues[c], 0.0);
      }
    }
    if (!moved.empty())
    {
      a.sparse.isSparse = true;
      a.sparse.count = static_cast<int>(moved.size());
      if (shortIndices)
      {
        std::vector<uint16_t> small(moved.begin(), moved.end());
        a.sparse.indices.bufferView = this->AddView(small.data(), small.size() * 2, 0);
        a.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
      }
      else
      {
        a.sparse.indices.bufferView = this->AddView(moved.data(), moved.size() * 4, 0);
        a.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      }
      a.sparse.indices.byteOffset = 0;
      const bool fits =
        std::all_of(values.begin(), values.end(), [](float v) { return v >= -1.0f && v <= 1.0f; });
      if (quantize && fits)
      {
        // KHR_mesh_quantization: normalized SHORT, value = max(q / 32767, -1); min and max
        // in the integer domain (with the zeros of the points not moved).
        std::vector<int16_t> q(values.size());
        for (size_t i = 0; i < values.size(); ++i)
        {
          q[i] = static_cast<int16_t>(std::lround(static_cast<double>(values[i]) * 32767.0));
        }
        a.componentType = TINYGLTF_COMPONENT_TYPE_SHORT;
        a.normalized = true;
        for (int c = 0; c < 3; ++c)
        {
          double lo = moved.size() < n ? 0.0 : 32767.0, hi = moved.size() < n ? 0.0 : -32767.0;
          for (size_t i = static_cast<size_t>(c); i < q.size(); i += 3)
          {
            lo = std::min(lo, static_cast<double>(q[i]));
            hi = std::max(hi, static_cast<double>(q[i]));
          }
          a.minValues[static_cast<size_t>(c)] = lo;
          a.maxValues[static_cast<size_t>(c)] = hi;
        }
        a.sparse.values.bufferView = this->AddView(q.data(), q.size() * sizeof(int16_t), 0);
        this->Quantized = true;
      }
      else
      {
        a.sparse.values.bufferView = this->AddView(values.data(), values.size() * sizeof(float), 0);
      }
      a.sparse.values.byteOffset = 0;
    }
    return this->AddAccessor(std::move(a));
  }

  int AddIndices(const std::vector<uint32_t>& triangles, size_t points)
  {
    tinygltf::Accessor a;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = triangles.size();
    if (points < 65535)
    {
      std::vector<uint16_t> small(triangles.begin(), triangles.end());
      a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
      a.bufferView =
        this->AddView(small.data(), small.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    }
    else
    {
      a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      a.bufferView =
        this->AddView(triangles.data(), triangles.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    }
    return this->AddAccessor(std::move(a));
  }
};

std::string NodeLabel(const GltfScene& scene, int node)
{
  const std::string& name = scene.Nodes[static_cast<size_t>(node)].Name;
  return name.empty() ? "node" + std::to_string(node) : name;
}

void CheckPart(const GltfPart& part, size_t index, const GltfScene& scene)
{
  const std::string where = "part " + std::to_string(index) + " (" + part.Name + ")";
  const size_t n = part.GetNumberOfPoints();
  if (part.Positions.size() != 3 * n || n == 0)
  {
    Fail(where + ": positions must be 3 per point, at least one point (got " +
      std::to_string(part.Positions.size()) + " values)");
  }
  if (!part.Normals.empty() && part.Normals.size() != 3 * n)
  {
    Fail(where + ": " + std::to_string(part.Normals.size()) + " normal values for " +
      std::to_string(n) + " points");
  }
  if (!part.Colors.empty() && part.Colors.size() != 4 * n)
  {
    Fail(where + ": " + std::to_string(part.Colors.size()) + " colour values for " +
      std::to_string(n) + " points (RGBA: 4 per point)");
  }
  for (const auto* uv : { &part.TexCoords0, &part.TexCoords1 })
  {
    if (!uv->empty() && (uv->size() != 2 * n || !AllFinite(*uv)))
    {
      Fail(where + ": texture coordinates must be 2 finite values per point (got " +
        std::to_string(uv->size()) + " values for " + std::to_string(n) + " points)");
    }
  }
  if (part.Triangles.empty() || part.Triangles.size() % 3 != 0)
  {
    Fail(where + ": triangles must be 3 indices each, at least one");
  }
  for (uint32_t i : part.Triangles)
  {
    if (i >= n)
    {
      Fail(where + ": triangle index " + std::to_string(i) + " beyond its " + std::to_string(n) +
        " points");
    }
  }
  if (!AllFinite(part.Positions) || !AllFinite(part.Normals) || !AllFinite(part.Colors))
  {
    Fail(where + ": positions, normals and colours must be finite");
  }
  if (part.Node < 0 || static_cast<size_t>(part.Node) >= scene.Nodes.size())
  {
    Fail(where + ": node " + std::to_string(part.Node) + " is not a node of the scene");
  }
  for (const auto& target : part.Targets)
  {
    if (target.Name.empty())
    {
      Fail(where + ": a target without a name");
    }
    if (target.PositionDeltas.size() != 3 * n)
    {
      Fail(where + ": target '" + target.Name + "' has " +
        std::to_string(target.PositionDeltas.size()) + " position delta values for " +
        std::to_string(n) + " points");
    }
    if (!target.NormalDeltas.empty() &&
      (target.NormalDeltas.size() != 3 * n || part.Normals.empty()))
    {
      Fail(where + ": target '" + target.Name +
        "': normal deltas need normals and 3 values per point");
    }
    if (!AllFinite(target.PositionDeltas) || !AllFinite(target.NormalDeltas))
    {
      Fail(where + ": target '" + target.Name + "' has non-finite deltas");
    }
  }
  for (double c : part.BaseColor)
  {
    if (!std::isfinite(c) || c < 0.0 || c > 1.0)
    {
      Fail(where + ": base colour components must be in [0, 1]");
    }
  }
}

std::vector<std::string> TargetNamesOf(const GltfPart& part)
{
  std::vector<std::string> names;
  for (const auto& t : part.Targets)
  {
    names.push_back(t.Name);
  }
  return names;
}

tinygltf::Value StringArray(const std::vector<std::string>& names)
{
  tinygltf::Value::Array values;
  for (const auto& n : names)
  {
    values.emplace_back(n);
  }
  return tinygltf::Value(values);
}

void CheckPerformance(const GltfPerformance& p)
{
  if (p.Interpolation == GltfInterpolation::CubicSpline)
  {
    Fail("the performance's interpolation must be LINEAR or STEP");
  }
  if (p.Times.empty())
  {
    Fail("the performance has no times");
  }
  for (size_t i = 0; i < p.Times.size(); ++i)
  {
    const double t = p.Times[i];
    if (!std::isfinite(t) || t < 0.0)
    {
      Fail("time " + std::to_string(i) + " is " + std::to_string(t) +
        ": times must be finite and >= 0");
    }
    if (i > 0 && !(static_cast<float>(t) > static_cast<float>(p.Times[i - 1])))
    {
      Fail("times must increase: time " + std::to_string(i) + " (" + std::to_string(t) +
        " s) does not come after time " + std::to_string(i - 1) + " (" +
        std::to_string(p.Times[i - 1]) + " s) (as 32-bit floats, as glTF stores them)");
    }
  }
  if (p.Weights.size() != p.Times.size() * p.TargetNames.size())
  {
    Fail(std::to_string(p.Weights.size()) + " weights for " + std::to_string(p.Times.size()) +
      " times x " + std::to_string(p.TargetNames.size()) + " targets");
  }
  for (size_t i = 0; i < p.Weights.size(); ++i)
  {
    if (!std::isfinite(p.Weights[i]))
    {
      const size_t k = p.TargetNames.empty() ? 0 : i / p.TargetNames.size();
      Fail("the weight of '" + p.TargetNames[i % p.TargetNames.size()] + "' at time " +
        std::to_string(k) + " is not finite");
    }
  }
  std::map<std::string, int> seen;
  for (const auto& name : p.TargetNames)
  {
    if (++seen[name] > 1)
    {
      Fail("the target '" + name + "' appears twice in the performance");
    }
  }
  for (const auto& r : p.Rotations)
  {
    const std::string what =
      r.Node.empty() ? std::string("the scene's rotation") : "the rotation of '" + r.Node + "'";
    if (r.Rotations.size() != 4 * p.Times.size())
    {
      Fail(what + " has " + std::to_string(r.Rotations.size()) + " values for " +
        std::to_string(p.Times.size()) + " times (4 per time: x, y, z, w)");
    }
    for (double v : r.Pivot)
    {
      if (!std::isfinite(v))
      {
        Fail(what + ": the pivot must be finite");
      }
    }
    for (size_t k = 0; k < p.Times.size(); ++k)
    {
      const double* q = r.Rotations.data() + 4 * k;
      const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!std::isfinite(len) || len < 1e-6)
      {
        Fail(what + " at time " + std::to_string(k) +
          " is not a rotation (a non-finite or zero quaternion)");
      }
    }
  }
}

/// Unit, sign-continuous quaternions as floats.
std::vector<float> Quaternions(const std::vector<double>& q)
{
  std::vector<float> out(q.size());
  double prev[4] = { 0, 0, 0, 1 };
  for (size_t k = 0; k < q.size() / 4; ++k)
  {
    double v[4];
    const double* s = q.data() + 4 * k;
    const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + s[3] * s[3]);
    for (int c = 0; c < 4; ++c)
    {
      v[c] = s[c] / len;
    }
    if (k > 0 && v[0] * prev[0] + v[1] * prev[1] + v[2] * prev[2] + v[3] * prev[3] < 0.0)
    {
      for (double& c : v)
      {
        c = -c;
      }
    }
    for (int c = 0; c < 4; ++c)
    {
      prev[c] = v[c];
      out[4 * k + c] = static_cast<float>(v[c]);
    }
  }
  return out;
}
} // namespace

std::array<double, 4> GltfQuaternionFromRowMajor(const std::array<double, 16>& m)
{
  auto at = [&m](int r, int c) { return m[static_cast<size_t>(4 * r + c)]; };
  const double trace = at(0, 0) + at(1, 1) + at(2, 2);
  std::array<double, 4> q{};
  if (trace > 0.0)
  {
    const double s = 0.5 / std::sqrt(trace + 1.0);
    q = { (at(2, 1) - at(1, 2)) * s, (at(0, 2) - at(2, 0)) * s, (at(1, 0) - at(0, 1)) * s,
      0.25 / s };
  }
  else if (at(0, 0) > at(1, 1) && at(0, 0) > at(2, 2))
  {
    const double s = 2.0 * std::sqrt(1.0 + at(0, 0) - at(1, 1) - at(2, 2));
    q = { 0.25 * s, (at(0, 1) + at(1, 0)) / s, (at(0, 2) + at(2, 0)) / s,
      (at(2, 1) - at(1, 2)) / s };
  }
  else if (at(1, 1) > at(2, 2))
  {
    const double s = 2.0 * std::sqrt(1.0 + at(1, 1) - at(0, 0) - at(2, 2));
    q = { (at(0, 1) + at(1, 0)) / s, 0.25 * s, (at(1, 2) + at(2, 1)) / s,
      (at(0, 2) - at(2, 0)) / s };
  }
  else
  {
    const double s = 2.0 * std::sqrt(1.0 + at(2, 2) - at(0, 0) - at(1, 1));
    q = { (at(0, 2) + at(2, 0)) / s, (at(1, 2) + at(2, 1)) / s, 0.25 * s,
      (at(1, 0) - at(0, 1)) / s };
  }
  const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(len) || len == 0.0)
  {
    throw InputError("glTF export: not a rotation matrix");
  }
  for (double& c : q)
  {
    c /= len;
  }
  return q;
}

std::vector<unsigned char> WriteGltfSceneToMemory(
  const GltfScene& scene, const GltfPerformance* performance, const GltfWriteOptions& options)
{
  if (scene.Parts.empty())
  {
    Fail("the scene has no parts");
  }
  for (size_t i = 0; i < scene.Parts.size(); ++i)
  {
    CheckPart(scene.Parts[i], i, scene);
  }
  const bool applied = scene.Parts[0].TransformApplied;
  for (const auto& part : scene.Parts)
  {
    if (part.TransformApplied != applied)
    {
      Fail("some parts are in world space and others in their nodes' frames");
    }
  }
  const size_t numNodes = scene.Nodes.size();
  for (size_t n = 0; n < numNodes; ++n)
  {
    const GltfNode& node = scene.Nodes[n];
    if (node.Parent < -1 || node.Parent >= static_cast<int>(numNodes))
    {
      Fail(
        "node " + std::to_string(n) + ": parent " + std::to_string(node.Parent) + " is not a node");
    }
    for (int c : node.Children)
    {
      if (c < 0 || c >= static_cast<int>(numNodes) ||
        scene.Nodes[static_cast<size_t>(c)].Parent != static_cast<int>(n))
      {
        Fail("node " + std::to_string(n) + ": child " + std::to_string(c) +
          " is not a node whose parent it is");
      }
    }
  }
  // Cycles: every node must reach a root within numNodes steps.
  for (size_t n = 0; n < numNodes; ++n)
  {
    int p = static_cast<int>(n);
    size_t steps = 0;
    while (p >= 0 && steps++ <= numNodes)
    {
      p = scene.Nodes[static_cast<size_t>(p)].Parent;
    }
    if (p >= 0)
    {
      Fail("the node hierarchy has a cycle through node " + std::to_string(n));
    }
  }
  if (performance)
  {
    CheckPerformance(*performance);
  }

  ModelBuilder b;
  tinygltf::Model& m = b.Model;
  m.asset.version = "2.0";
  m.asset.generator = options.Generator;

  // Nodes: the scene's, in its order.
  std::vector<int> partsOfNode; // node -> mesh index
  m.nodes.resize(numNodes);
  for (size_t n = 0; n < numNodes; ++n)
  {
    const GltfNode& src = scene.Nodes[n];
    tinygltf::Node& dst = m.nodes[n];
    dst.name = src.Name;
    dst.children = src.Children;
    if (!applied)
    {
      if (src.HasMatrix)
      {
        dst.matrix.assign(src.Local.begin(), src.Local.end());
      }
      else
      {
        if (src.Translation != std::array<double, 3>{ { 0, 0, 0 } })
        {
          dst.translation.assign(src.Translation.begin(), src.Translation.end());
        }
        if (src.Rotation != std::array<double, 4>{ { 0, 0, 0, 1 } })
        {
          dst.rotation.assign(src.Rotation.begin(), src.Rotation.end());
        }
        if (src.Scale != std::array<double, 3>{ { 1, 1, 1 } })
        {
          dst.scale.assign(src.Scale.begin(), src.Scale.end());
        }
      }
    }
  }

  // The scene's own materials (GltfScene::Materials, what the loader read) are written
  // back whole, with their textures, samplers and images; parts without one get a
  // material from their name and base colour, shared by equal name and colour.
  std::map<int, int> sceneMaterials; // scene material -> written material
  std::map<int, int> sceneImages;    // scene image -> written image
  std::map<std::array<int, 4>, int> samplers;
  std::map<std::pair<int, int>, int> textures; // (written image, sampler) -> texture
  bool textureTransform = false, unlit = false, emissiveStrength = false;
  auto imageOf = [&](int index)
  {
    const auto it = sceneImages.find(index);
    if (it != sceneImages.end())
    {
      return it->second;
    }
    const GltfImage& src = scene.Images[static_cast<size_t>(index)];
    tinygltf::Image image;
    image.name = src.Name;
    // PNG and JPEG go back as the file held them (no loss, the original size); WebP and
    // images without their bytes are re-encoded as PNG from the decoded pixels, so that
    // the file needs no extension.
    const bool original =
      !src.Encoded.empty() && (src.MimeType == "image/png" || src.MimeType == "image/jpeg");
    const std::vector<uint8_t> bytes = original ? src.Encoded : GltfEncodePng(src);
    image.mimeType = original ? src.MimeType : "image/png";
    image.bufferView = b.AddView(bytes.data(), bytes.size(), 0);
    m.images.push_back(image);
    const int written = static_cast<int>(m.images.size() - 1);
    sceneImages[index] = written;
    return written;
  };
  // A texture reference as textureInfo: index, texCoord and KHR_texture_transform; -1 when
  // the reference has no decoded image.
  auto textureOf = [&](const GltfTextureRef& ref, tinygltf::ExtensionMap& extensions, int& texCoord)
  {
    if (!ref.IsSet() || static_cast<size_t>(ref.Image) >= scene.Images.size() ||
      !scene.Images[static_cast<size_t>(ref.Image)].IsDecoded())
    {
      return -1;
    }
    const int image = imageOf(ref.Image);
    const std::array<int, 4> key{ { ref.Sampler.MagFilter, ref.Sampler.MinFilter, ref.Sampler.WrapS,
      ref.Sampler.WrapT } };
    auto sit = samplers.find(key);
    if (sit == samplers.end())
    {
      tinygltf::Sampler sampler;
      sampler.magFilter = ref.Sampler.MagFilter > 0 ? ref.Sampler.MagFilter : -1;
      sampler.minFilter = ref.Sampler.MinFilter > 0 ? ref.Sampler.MinFilter : -1;
      sampler.wrapS = ref.Sampler.WrapS;
      sampler.wrapT = ref.Sampler.WrapT;
      m.samplers.push_back(sampler);
      sit = samplers.emplace(key, static_cast<int>(m.samplers.size() - 1)).first;
    }
    auto tit = textures.find({ image, sit->second });
    if (tit == textures.end())
    {
      tinygltf::Texture texture;
      texture.source = image;
      texture.sampler = sit->second;
      m.textures.push_back(texture);
      tit = textures
              .emplace(std::make_pair(image, sit->second), static_cast<int>(m.textures.size() - 1))
              .first;
    }
    texCoord = ref.TexCoord;
    if (ref.HasTransform)
    {
      tinygltf::Value::Object t;
      t["offset"] = tinygltf::Value(
        tinygltf::Value::Array{ tinygltf::Value(ref.Offset[0]), tinygltf::Value(ref.Offset[1]) });
      t["rotation"] = tinygltf::Value(ref.Rotation);
      t["scale"] = tinygltf::Value(
        tinygltf::Value::Array{ tinygltf::Value(ref.UvScale[0]), tinygltf::Value(ref.UvScale[1]) });
      extensions["KHR_texture_transform"] = tinygltf::Value(t);
      textureTransform = true;
    }
    return tit->second;
  };
  auto writeMaterial = [&](const GltfMaterial& src)
  {
    tinygltf::Material mat;
    mat.name = src.Name;
    auto& pbr = mat.pbrMetallicRoughness;
    pbr.baseColorFactor.assign(src.BaseColorFactor.begin(), src.BaseColorFactor.end());
    pbr.metallicFactor = src.MetallicFactor;
    pbr.roughnessFactor = src.RoughnessFactor;
    pbr.baseColorTexture.index = textureOf(
      src.BaseColorTexture, pbr.baseColorTexture.extensions, pbr.baseColorTexture.texCoord);
    pbr.metallicRoughnessTexture.index = textureOf(src.MetallicRoughnessTexture,
      pbr.metallicRoughnessTexture.extensions, pbr.metallicRoughnessTexture.texCoord);
    mat.normalTexture.index =
      textureOf(src.NormalTexture, mat.normalTexture.extensions, mat.normalTexture.texCoord);
    mat.normalTexture.scale = src.NormalTexture.Scale;
    mat.occlusionTexture.index = textureOf(
      src.OcclusionTexture, mat.occlusionTexture.extensions, mat.occlusionTexture.texCoord);
    mat.occlusionTexture.strength = src.OcclusionTexture.Scale;
    mat.emissiveTexture.index =
      textureOf(src.EmissiveTexture, mat.emissiveTexture.extensions, mat.emissiveTexture.texCoord);
    mat.emissiveFactor.assign(src.EmissiveFactor.begin(), src.EmissiveFactor.end());
    mat.alphaMode = GltfAlphaModeName(src.AlphaMode);
    if (src.AlphaMode == GltfAlphaMode::Mask)
    {
      mat.alphaCutoff = src.AlphaCutoff;
    }
    mat.doubleSided = src.DoubleSided;
    if (src.Unlit)
    {
      mat.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
      unlit = true;
    }
    if (src.EmissiveStrength != 1.0)
    {
      tinygltf::Value::Object e;
      e["emissiveStrength"] = tinygltf::Value(src.EmissiveStrength);
      mat.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(e);
      emissiveStrength = true;
    }
    m.materials.push_back(mat);
    return static_cast<int>(m.materials.size() - 1);
  };
  std::map<std::pair<std::string, std::array<double, 4>>, int> materials;
  auto materialOf = [&](const GltfPart& part)
  {
    if (part.Material >= 0 && static_cast<size_t>(part.Material) < scene.Materials.size())
    {
      const auto it = sceneMaterials.find(part.Material);
      if (it != sceneMaterials.end())
      {
        return it->second;
      }
      const int index = writeMaterial(scene.Materials[static_cast<size_t>(part.Material)]);
      sceneMaterials[part.Material] = index;
      return index;
    }
    const bool none = part.Material < 0 && part.MaterialName.empty() &&
      part.BaseColor == std::array<double, 4>{ { 1, 1, 1, 1 } };
    if (none)
    {
      return -1;
    }
    const auto key = std::make_pair(part.MaterialName, part.BaseColor);
    auto it = materials.find(key);
    if (it != materials.end())
    {
      return it->second;
    }
    tinygltf::Material mat;
    mat.name = part.MaterialName;
    mat.pbrMetallicRoughness.baseColorFactor.assign(part.BaseColor.begin(), part.BaseColor.end());
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 0.5;
    if (part.BaseColor[3] < 1.0)
    {
      mat.alphaMode = "BLEND";
    }
    m.materials.push_back(mat);
    const int index = static_cast<int>(m.materials.size() - 1);
    materials[key] = index;
    return index;
  };

  // Skins: written when the parts are in their nodes' frames (bind space as in the file,
  // GltfLoadOptions::ApplyTransforms off), the nodes then keeping their transforms. With the
  // transforms applied the parts are the skinned rest pose in world space and the nodes
  // are written without transforms, so the skins are left out (the rest pose stays).
  const bool skinned = !applied && !scene.Skins.empty();
  if (skinned)
  {
    for (size_t k = 0; k < scene.Skins.size(); ++k)
    {
      const GltfSkin& src = scene.Skins[k];
      const std::string where = "skin " + std::to_string(k) + " (" + src.Name + ")";
      if (src.Joints.empty() || src.InverseBind.size() != src.Joints.size())
      {
        Fail(where + ": " + std::to_string(src.Joints.size()) + " joints and " +
          std::to_string(src.InverseBind.size()) + " inverse bind matrices");
      }
      tinygltf::Skin skin;
      skin.name = src.Name;
      for (int j : src.Joints)
      {
        if (j < 0 || static_cast<size_t>(j) >= numNodes)
        {
          Fail(where + ": joint " + std::to_string(j) + " is not a node");
        }
      }
      skin.joints = src.Joints;
      skin.skeleton =
        src.Skeleton >= 0 && static_cast<size_t>(src.Skeleton) < numNodes ? src.Skeleton : -1;
      std::vector<float> matrices;
      for (const auto& ibm : src.InverseBind)
      {
        for (double v : ibm)
        {
          if (!std::isfinite(v))
          {
            Fail(where + ": an inverse bind matrix is not finite");
          }
          matrices.push_back(static_cast<float>(v));
        }
      }
      skin.inverseBindMatrices = b.AddFloats(matrices, 16, false, 0);
      m.skins.push_back(skin);
    }
    for (const auto& part : scene.Parts)
    {
      if (part.Skin < 0)
      {
        continue;
      }
      if (static_cast<size_t>(part.Skin) >= scene.Skins.size() ||
        part.Influences.PerPoint % 4 != 0 || part.Influences.PerPoint == 0 ||
        part.Influences.GetNumberOfPoints() != part.GetNumberOfPoints() ||
        part.Influences.Joints.size() != part.Influences.Weights.size())
      {
        Fail("part '" + part.Name + "': its skin " + std::to_string(part.Skin) +
          " or influences do not fit");
      }
      const size_t jointCount = scene.Skins[static_cast<size_t>(part.Skin)].Joints.size();
      for (size_t i = 0; i < part.Influences.Joints.size(); ++i)
      {
        if (part.Influences.Weights[i] > 0.0f && part.Influences.Joints[i] >= jointCount)
        {
          Fail("part '" + part.Name + "': joint index " +
            std::to_string(part.Influences.Joints[i]) + " beyond its skin's " +
            std::to_string(jointCount) + " joints");
        }
      }
      tinygltf::Node& node = m.nodes[static_cast<size_t>(part.Node)];
      if (node.skin >= 0 && node.skin != part.Skin)
      {
        Fail("the parts of node '" + NodeLabel(scene, part.Node) + "' have different skins");
      }
      node.skin = part.Skin;
    }
  }

  // Meshes: the parts of each node, in part order.
  std::vector<std::vector<std::string>> meshTargets; // per written mesh
  std::vector<int> meshNode;
  for (size_t n = 0; n < numNodes; ++n)
  {
    std::vector<const GltfPart*> parts;
    for (const auto& part : scene.Parts)
    {
      if (part.Node == static_cast<int>(n))
      {
        parts.push_back(&part);
      }
    }
    if (parts.empty())
    {
      continue;
    }
    const std::vector<std::string> names = TargetNamesOf(*parts[0]);
    for (const GltfPart* part : parts)
    {
      if (TargetNamesOf(*part) != names)
      {
        Fail("the parts of node '" + NodeLabel(scene, static_cast<int>(n)) +
          "' have different targets (glTF gives every primitive of a mesh the same targets): '" +
          parts[0]->Name + "' and '" + part->Name + "'");
      }
    }
    tinygltf::Mesh mesh;
    mesh.name = NodeLabel(scene, static_cast<int>(n));
    for (const GltfPart* part : parts)
    {
      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.attributes["POSITION"] =
        b.AddFloats(part->Positions, 3, true, TINYGLTF_TARGET_ARRAY_BUFFER);
      if (!part->Normals.empty())
      {
        std::vector<float> normals(part->Normals);
        for (size_t i = 0; i < normals.size(); i += 3)
        {
          const double len = std::sqrt(double(normals[i]) * normals[i] +
            double(normals[i + 1]) * normals[i + 1] + double(normals[i + 2]) * normals[i + 2]);
          if (len > 1e-12)
          {
            for (int c = 0; c < 3; ++c)
            {
              normals[i + c] = static_cast<float>(normals[i + c] / len);
            }
          }
          else
          {
            normals[i] = 0.0f;
            normals[i + 1] = 0.0f;
            normals[i + 2] = 1.0f;
          }
        }
        prim.attributes["NORMAL"] = b.AddFloats(normals, 3, false, TINYGLTF_TARGET_ARRAY_BUFFER);
      }
      if (!part->Colors.empty())
      {
        std::vector<float> colors(part->Colors);
        for (float& c : colors)
        {
          c = std::min(1.0f, std::max(0.0f, c));
        }
        prim.attributes["COLOR_0"] = b.AddFloats(colors, 4, false, TINYGLTF_TARGET_ARRAY_BUFFER);
      }
      const size_t points = part->GetNumberOfPoints();
      if (part->TexCoords0.size() == 2 * points && points > 0)
      {
        prim.attributes["TEXCOORD_0"] =
          b.AddFloats(part->TexCoords0, 2, false, TINYGLTF_TARGET_ARRAY_BUFFER);
      }
      if (part->TexCoords1.size() == 2 * points && points > 0)
      {
        prim.attributes["TEXCOORD_1"] =
          b.AddFloats(part->TexCoords1, 2, false, TINYGLTF_TARGET_ARRAY_BUFFER);
      }
      if (skinned && part->Skin >= 0)
      {
        // JOINTS_n / WEIGHTS_n, 4 influences per set, joints as unsigned byte when the skin
        // has at most 256 joints, else unsigned short; weights as float (renormalized by
        // the loader, so each point's sum is 1 within float rounding).
        const SkinInfluences& inf = part->Influences;
        const size_t jointCount = scene.Skins[static_cast<size_t>(part->Skin)].Joints.size();
        for (size_t set = 0; set < inf.PerPoint / 4; ++set)
        {
          std::vector<float> weights(4 * points);
          std::vector<uint16_t> joints(4 * points);
          for (size_t i = 0; i < points; ++i)
          {
            for (size_t k = 0; k < 4; ++k)
            {
              const size_t at = i * inf.PerPoint + 4 * set + k;
              weights[4 * i + k] = inf.Weights[at];
              joints[4 * i + k] = weights[4 * i + k] > 0.0f ? inf.Joints[at] : 0;
            }
          }
          tinygltf::Accessor a;
          a.type = TINYGLTF_TYPE_VEC4;
          a.count = points;
          if (jointCount <= 256)
          {
            std::vector<uint8_t> small(joints.begin(), joints.end());
            a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
            a.bufferView = b.AddView(small.data(), small.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
          }
          else
          {
            a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
            a.bufferView =
              b.AddView(joints.data(), joints.size() * 2, TINYGLTF_TARGET_ARRAY_BUFFER);
          }
          prim.attributes["JOINTS_" + std::to_string(set)] = b.AddAccessor(std::move(a));
          prim.attributes["WEIGHTS_" + std::to_string(set)] =
            b.AddFloats(weights, 4, false, TINYGLTF_TARGET_ARRAY_BUFFER);
        }
      }
      prim.indices = b.AddIndices(part->Triangles, part->GetNumberOfPoints());
      prim.material = materialOf(*part);
      for (const auto& target : part->Targets)
      {
        std::map<std::string, int> attributes;
        attributes["POSITION"] = b.AddDeltas(target.PositionDeltas, options.QuantizeTargets);
        if (!target.NormalDeltas.empty())
        {
          attributes["NORMAL"] = b.AddDeltas(target.NormalDeltas, options.QuantizeTargets);
        }
        prim.targets.push_back(attributes);
      }
      mesh.primitives.push_back(prim);
    }
    if (!names.empty())
    {
      tinygltf::Value::Object extras;
      extras["targetNames"] = StringArray(names);
      mesh.extras = tinygltf::Value(extras);
      mesh.weights = parts[0]->DefaultWeights;
      if (mesh.weights.size() != names.size())
      {
        mesh.weights.assign(names.size(), 0.0);
      }
    }
    m.meshes.push_back(mesh);
    m.nodes[n].mesh = static_cast<int>(m.meshes.size() - 1);
    meshTargets.push_back(names);
    meshNode.push_back(static_cast<int>(n));
  }

  // Roots of the scene: nodes without parent that are in the scene (all of them when no
  // node is marked).
  const bool anyInScene = std::any_of(
    scene.Nodes.begin(), scene.Nodes.end(), [](const GltfNode& node) { return node.InScene; });
  std::vector<int> roots;
  for (size_t n = 0; n < numNodes; ++n)
  {
    if (scene.Nodes[n].Parent < 0 && (scene.Nodes[n].InScene || !anyInScene))
    {
      roots.push_back(static_cast<int>(n));
    }
  }
  for (const auto& part : scene.Parts)
  {
    int root = part.Node;
    while (scene.Nodes[static_cast<size_t>(root)].Parent >= 0)
    {
      root = scene.Nodes[static_cast<size_t>(root)].Parent;
    }
    if (std::find(roots.begin(), roots.end(), root) == roots.end())
    {
      Fail("part '" + part.Name + "' is on a node outside the scene");
    }
  }

  if (performance)
  {
    const GltfPerformance& p = *performance;
    const size_t frames = p.Times.size();
    // Every named target must be some mesh's.
    for (const auto& name : p.TargetNames)
    {
      const bool found = std::any_of(meshTargets.begin(), meshTargets.end(),
        [&name](const std::vector<std::string>& t)
        { return std::find(t.begin(), t.end(), name) != t.end(); });
      if (!found)
      {
        Fail("the performance names the target '" + name + "', which no part of the scene has");
      }
    }
    tinygltf::Animation anim;
    anim.name = p.Name;
    const std::string interpolation =
      p.Interpolation == GltfInterpolation::Step ? "STEP" : "LINEAR";
    std::vector<float> times(p.Times.begin(), p.Times.end());
    const int input = b.AddFloats(times, 1, true, 0);
    auto addSampler = [&](int output)
    {
      tinygltf::AnimationSampler s;
      s.input = input;
      s.output = output;
      s.interpolation = interpolation;
      anim.samplers.push_back(s);
      return static_cast<int>(anim.samplers.size() - 1);
    };
    auto addChannel = [&](int sampler, int node, const std::string& path)
    {
      tinygltf::AnimationChannel c;
      c.sampler = sampler;
      c.target_node = node;
      c.target_path = path;
      anim.channels.push_back(c);
    };
    for (size_t k = 0; k < meshTargets.size(); ++k)
    {
      const auto& names = meshTargets[k];
      if (names.empty())
      {
        continue;
      }
      std::vector<int> column(names.size(), -1);
      const auto offAt = p.TargetsOffAtNode.find(meshNode[k]);
      for (size_t t = 0; t < names.size(); ++t)
      {
        const auto it = std::find(p.TargetNames.begin(), p.TargetNames.end(), names[t]);
        const bool off = offAt != p.TargetsOffAtNode.end() &&
          std::find(offAt->second.begin(), offAt->second.end(), names[t]) != offAt->second.end();
        column[t] =
          it == p.TargetNames.end() || off ? -1 : static_cast<int>(it - p.TargetNames.begin());
      }
      std::vector<float> values(frames * names.size(), 0.0f);
      for (size_t f = 0; f < frames; ++f)
      {
        for (size_t t = 0; t < names.size(); ++t)
        {
          if (column[t] >= 0)
          {
            values[f * names.size() + t] = static_cast<float>(
              p.Weights[f * p.TargetNames.size() + static_cast<size_t>(column[t])]);
          }
        }
      }
      const int node = meshNode[k];
      addChannel(addSampler(b.AddFloats(values, 1, false, 0)), node, "weights");
    }
    for (const auto& r : p.Rotations)
    {
      const std::vector<float> q = Quaternions(r.Rotations);
      int turned = -1; // -1: the whole scene
      if (!r.Node.empty())
      {
        for (size_t n = 0; n < numNodes; ++n)
        {
          if (scene.Nodes[n].Name == r.Node)
          {
            if (turned >= 0)
            {
              Fail("several nodes are named '" + r.Node + "': the rotation's node must be unique");
            }
            turned = static_cast<int>(n);
          }
        }
        if (turned < 0)
        {
          Fail("the performance turns the node '" + r.Node + "', which the scene does not have");
        }
      }
      // A skin's joint turned about its own origin (the pivot is its translation) gets the
      // channel itself: T(t) R T(-t) T(t) R0 S = T(t) (R R0) S, so the channel holds R R0
      // and the skeleton stays as the avatar's maker made it (no inserted nodes).
      if (turned >= 0 && skinned)
      {
        const GltfNode& joint = scene.Nodes[static_cast<size_t>(turned)];
        const bool isJoint = std::any_of(scene.Skins.begin(), scene.Skins.end(),
          [turned](const GltfSkin& skin) {
            return std::find(skin.Joints.begin(), skin.Joints.end(), turned) != skin.Joints.end();
          });
        const bool atOrigin = std::abs(r.Pivot[0] - joint.Translation[0]) < 1e-9 &&
          std::abs(r.Pivot[1] - joint.Translation[1]) < 1e-9 &&
          std::abs(r.Pivot[2] - joint.Translation[2]) < 1e-9;
        if (isJoint && !joint.HasMatrix && atOrigin)
        {
          const auto& q0 = joint.Rotation;
          std::vector<double> turnedRest(r.Rotations.size());
          for (size_t k = 0; k < r.Rotations.size() / 4; ++k)
          {
            const double* a = r.Rotations.data() + 4 * k;
            double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]);
            const double x = a[0] / len, y = a[1] / len, z = a[2] / len, w = a[3] / len;
            // (x, y, z, w) * q0, Hamilton product.
            double* o = turnedRest.data() + 4 * k;
            o[0] = w * q0[0] + x * q0[3] + y * q0[2] - z * q0[1];
            o[1] = w * q0[1] - x * q0[2] + y * q0[3] + z * q0[0];
            o[2] = w * q0[2] + x * q0[1] - y * q0[0] + z * q0[3];
            o[3] = w * q0[3] - x * q0[0] - y * q0[1] - z * q0[2];
          }
          std::vector<float> values = Quaternions(turnedRest);
          addChannel(addSampler(b.AddFloats(values, 4, false, 0)), turned, "rotation");
          continue;
        }
      }
      const std::string base = r.Node.empty() ? std::string("Head") : r.Node;
      tinygltf::Node rotation;
      rotation.name = base + "Rotation";
      rotation.translation.assign(r.Pivot.begin(), r.Pivot.end());
      tinygltf::Node pivot;
      pivot.name = base + "Pivot";
      pivot.translation = { -r.Pivot[0], -r.Pivot[1], -r.Pivot[2] };
      const int rotationIndex = static_cast<int>(m.nodes.size());
      const int pivotIndex = rotationIndex + 1;
      rotation.children = { pivotIndex };
      if (turned < 0)
      {
        pivot.children = roots;
        roots = { rotationIndex };
      }
      else
      {
        pivot.children = { turned };
        // Put the rotation node where the turned node was.
        bool placed = false;
        for (auto& node : m.nodes)
        {
          for (int& c : node.children)
          {
            if (c == turned)
            {
              c = rotationIndex;
              placed = true;
            }
          }
        }
        for (int& root : roots)
        {
          if (root == turned)
          {
            root = rotationIndex;
            placed = true;
          }
        }
        if (!placed)
        {
          Fail("the node '" + r.Node + "' is not in the scene");
        }
      }
      m.nodes.push_back(rotation);
      m.nodes.push_back(pivot);
      std::vector<float> values(q);
      addChannel(addSampler(b.AddFloats(values, 4, false, 0)), rotationIndex, "rotation");
    }
    if (!anim.channels.empty())
    {
      m.animations.push_back(anim);
    }
  }

  tinygltf::Scene s;
  s.name = scene.SceneName;
  s.nodes = roots;
  m.scenes.push_back(s);
  m.defaultScene = 0;
  const std::pair<bool, const char*> used[] = { { textureTransform, "KHR_texture_transform" },
    { unlit, "KHR_materials_unlit" }, { emissiveStrength, "KHR_materials_emissive_strength" } };
  for (const auto& [on, name] : used)
  {
    if (on)
    {
      m.extensionsUsed.emplace_back(name);
    }
  }
  if (b.Quantized)
  {
    m.extensionsUsed.push_back("KHR_mesh_quantization");
    m.extensionsRequired.push_back("KHR_mesh_quantization");
  }
  while (b.Bin().size() % 4 != 0)
  {
    b.Bin().push_back(0);
  }
  if (b.Bin().empty())
  {
    m.buffers.clear();
  }

  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(&m, out, false, options.Binary))
  {
    Fail("tinygltf could not serialize the scene");
  }
  const std::string bytes = out.str();
  return std::vector<unsigned char>(bytes.begin(), bytes.end());
}

void WriteGltfScene(const std::string& fileName, const GltfScene& scene,
  const GltfPerformance* performance, GltfWriteOptions options)
{
  options.Binary = !text::HasExtension(fileName, ".gltf");
  const std::vector<unsigned char> bytes = WriteGltfSceneToMemory(scene, performance, options);
  // Beside the target, renamed onto it when complete; never through a link or onto a device.
  file::WriteFileSafely(fileName,
    std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "glTF export");
}
} // namespace morphnode
