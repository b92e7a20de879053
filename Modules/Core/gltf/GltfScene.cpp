// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfScene.h"

#include "GltfCheck.h"
#include "GltfExtensions.h"
#include "GltfSkinRead.h"
#include "TinyGltfConfig.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <utility>

namespace morphnode
{
GltfMatrix GltfIdentity()
{
  return GltfMatrix{ { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 } };
}

GltfMatrix GltfComposeTrs(
  const std::array<double, 3>& t, const std::array<double, 4>& q, const std::array<double, 3>& s)
{
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  const double r[3][3] = {
    { 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w) },
    { 2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w) },
    { 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y) },
  };
  GltfMatrix m = GltfIdentity();
  for (int c = 0; c < 3; ++c)
  {
    for (int row = 0; row < 3; ++row)
    {
      m[c * 4 + row] = r[row][c] * s[c];
    }
    m[12 + c] = t[c];
  }
  return m;
}

GltfMatrix GltfMultiply(const GltfMatrix& a, const GltfMatrix& b)
{
  GltfMatrix out{};
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 4; ++r)
    {
      double sum = 0;
      for (int k = 0; k < 4; ++k)
      {
        sum += a[k * 4 + r] * b[c * 4 + k];
      }
      out[c * 4 + r] = sum;
    }
  }
  return out;
}

size_t GltfScene::GetNumberOfPoints() const
{
  size_t n = 0;
  for (const auto& part : this->Parts)
  {
    n += part.GetNumberOfPoints();
  }
  return n;
}

int GltfScene::FindPart(const std::string& name) const
{
  for (size_t i = 0; i < this->Parts.size(); ++i)
  {
    if (this->Parts[i].Name == name)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::string GltfNodeName(const GltfScene& scene, int node)
{
  const std::string& name = scene.Nodes.at(static_cast<size_t>(node)).Name;
  return name.empty() ? "node" + std::to_string(node) : name;
}

std::string GltfMeshName(const GltfScene& scene, size_t mesh)
{
  const std::string& name = scene.Meshes.at(mesh).Name;
  return name.empty() ? "mesh" + std::to_string(mesh) : name;
}

std::string GltfAnimationName(const GltfScene& scene, size_t animation)
{
  const std::string& name = scene.Animations.at(animation).Name;
  return name.empty() ? "animation" + std::to_string(animation) : name;
}

namespace
{
using json = nlohmann::json;

// --- tinygltf: buffers from the input, from data URIs, or from files in one folder ----

struct Folder
{
  std::string Base;  ///< with a trailing '/'
  uint64_t MaxBytes; ///< the largest byteLength of any buffer
};

bool InFolder(const std::string& path, const Folder& folder)
{
  if (path.size() <= folder.Base.size() || path.compare(0, folder.Base.size(), folder.Base) != 0 ||
    path.find_first_of("/\\", folder.Base.size()) != std::string::npos)
  {
    return false;
  }
  // Confined after resolving links: a link in the folder must not lead outside it.
  std::error_code ec;
  const std::filesystem::path real = std::filesystem::canonical(path, ec);
  if (ec || !std::filesystem::is_regular_file(real, ec))
  {
    return false;
  }
  const std::filesystem::path base =
    std::filesystem::canonical(folder.Base.empty() ? "." : folder.Base, ec);
  return !ec && real.parent_path() == base;
}

bool FileExists(const std::string& path, void* user)
{
  return InFolder(path, *static_cast<Folder*>(user));
}

std::string ExpandFilePath(const std::string& path, void*)
{
  return path; // no shell expansion
}

bool ReadWholeFile(
  std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user)
{
  const Folder& folder = *static_cast<Folder*>(user);
  std::error_code ec;
  if (!InFolder(path, folder))
  {
    *err = "not a file in the glTF file's folder";
    return false;
  }
  uintmax_t size = 0;
  try
  {
    size = file::CheckInputFile(path, "buffer", folder.MaxBytes); // kind and size first
  }
  catch (const InputError& e)
  {
    *err = e.what();
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(static_cast<size_t>(size));
  if (size > 0 &&
    !in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size)))
  {
    *err = "cannot be read";
    return false;
  }
  return true;
}

/// Issue 29: finite values whose blend is not (a position of 3.4e38, a delta of 3e38, a
/// default weight of 1e39) loaded and drew NaN or nothing. The largest coordinate any blend
/// at the default weights (or at weight 1) can reach must stay below MaxBlendCoordinate, so
/// that bounds, distances and squared lengths stay finite even in float.
constexpr double MaxBlendCoordinate = 1e18;

void CheckBlendRange(const GltfPart& part, const std::string& where)
{
  const auto largest = [](const std::vector<float>& v)
  {
    double m = 0.0;
    for (float x : v)
    {
      m = std::max(m, std::fabs(static_cast<double>(x)));
    }
    return m;
  };
  double reach = largest(part.Positions);
  for (size_t t = 0; t < part.Targets.size(); ++t)
  {
    const double w = t < part.DefaultWeights.size() ? std::fabs(part.DefaultWeights[t]) : 1.0;
    reach += std::max(1.0, w) * largest(part.Targets[t].PositionDeltas);
  }
  if (!(reach < MaxBlendCoordinate))
  {
    throw InputError(where + ": its positions, deltas and default weights reach a coordinate of " +
      text::FormatNumber(reach) + "; at most " + text::FormatNumber(MaxBlendCoordinate) +
      " keeps every blend finite (docs/limits.md)");
  }
}

/// Keeps each image's encoded bytes (gltf/GltfMaterial.cpp decodes them after the checks).
bool KeepImage(tinygltf::Image*, const int index, std::string*, std::string*, int, int,
  const unsigned char* bytes, int size, void* user)
{
  auto& images = *static_cast<std::vector<std::vector<unsigned char>>*>(user);
  if (index >= 0 && static_cast<size_t>(index) < images.size() && bytes && size > 0)
  {
    images[static_cast<size_t>(index)].assign(bytes, bytes + size);
  }
  return true;
}

/// An image file named by a .gltf: a plain file name in the input's folder only.
bool ReadImageFile(
  const std::string& uri, std::vector<unsigned char>& bytes, std::string& error, void* user)
{
  if (uri.empty() || uri == "." || uri == ".." || uri.find_first_of("/\\:%") != std::string::npos)
  {
    error = "not a plain file name in the glTF file's folder";
    return false;
  }
  const Folder& folder = *static_cast<const Folder*>(user);
  return !folder.Base.empty() &&
    ReadWholeFile(&bytes, &error, folder.Base + uri, const_cast<Folder*>(&folder));
}

tinygltf::Model LoadModel(const unsigned char* data, size_t size,
  const gltfcheck::Container& container, const std::string& baseDirectory, const json& root,
  const std::string& source, std::vector<std::vector<unsigned char>>& images)
{
  Folder folder;
  folder.Base = baseDirectory.empty() ? std::string() : baseDirectory + "/";
  folder.MaxBytes = 0;
  for (const auto& buffer : root.value("buffers", json::array()))
  {
    folder.MaxBytes = std::max<uint64_t>(folder.MaxBytes, buffer["byteLength"].get<uint64_t>());
  }
  tinygltf::TinyGLTF loader;
  tinygltf::FsCallbacks fs{ &FileExists, &ExpandFilePath, &ReadWholeFile, nullptr, &folder };
  loader.SetFsCallbacks(fs);
  images.assign(root.value("images", json::array()).size(), {});
  loader.SetImageLoader(&KeepImage, &images);
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  // EXT_meshopt_compression's fallback buffers hold no data, which tinygltf cannot parse:
  // it gets a copy of the document with those stubbed (GltfExtensions.h).
  std::string patched;
  if (gltfext::NeedsPatch(root))
  {
    patched = gltfext::PatchForTinygltf(root, container.Binary, container.Bin, container.BinSize);
    data = reinterpret_cast<const unsigned char*>(patched.data());
    size = patched.size();
  }
  try
  {
    // CheckDocument ran before: every index and count fits tinygltf's int, every buffer
    // view lies in its buffer, an image's buffer view exists.
    if (container.Binary)
    {
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, data, static_cast<unsigned int>(size),
        baseDirectory.empty() ? std::string(".") : baseDirectory);
    }
    else
    {
      ok = loader.LoadASCIIFromString(&model, &err, &warn,
        patched.empty() ? container.Json : patched.data(),
        static_cast<unsigned int>(patched.empty() ? container.JsonSize : patched.size()),
        baseDirectory.empty() ? std::string(".") : baseDirectory);
    }
  }
  catch (const std::exception& e)
  {
    ok = false;
    err = e.what();
  }
  if (!ok)
  {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' '))
    {
      err.pop_back();
    }
    // The library's words translated into what and where: a buffer file it could not
    // find or read is named by its pointer.
    const auto buffers = root.value("buffers", json::array());
    for (size_t b = 0; b < buffers.size(); ++b)
    {
      const std::string uri =
        buffers[b].is_object() ? buffers[b].value("uri", std::string()) : std::string();
      if (!uri.empty() && uri.rfind("data:", 0) != 0 && err.find(uri) != std::string::npos &&
        (err.find("File not found") != std::string::npos || err.find("read") != std::string::npos))
      {
        throw InputError(source + ": /buffers/" + std::to_string(b) + "/uri: " + text::Quote(uri) +
          " is not a readable regular file in the glTF file's folder (links leading out of the "
          "folder are refused)");
      }
    }
    throw InputError(source + ": the file cannot be read as glTF (" +
      (err.empty() ? std::string("no reason given") : text::Quote(err).substr(0, 200)) + ")");
  }
  return model;
}

// --- reading accessors ---------------------------------------------------------------

std::string Pointer(const char* array, size_t index)
{
  return std::string("/") + array + "/" + std::to_string(index);
}

class Reader
{
public:
  Reader(
    const tinygltf::Model& model, const gltfext::DecodedViews& decoded, const std::string& source)
    : Model(model)
    , Decoded(decoded)
    , Source(source)
  {
  }

  [[noreturn]] void Fail(const std::string& pointer, const std::string& what) const
  {
    throw InputError(this->Source + ": " + pointer + ": " + what);
  }

  int Components(int accessor) const
  {
    return tinygltf::GetNumComponentsInType(
      static_cast<uint32_t>(this->Model.accessors.at(accessor).type));
  }

  /// The accessor's values as floats (normalized integers converted as glTF says),
  /// components interleaved. `use` says what reads it, for messages.
  std::vector<float> Floats(int index, const std::string& use) const
  {
    const tinygltf::Accessor& a = this->Model.accessors.at(static_cast<size_t>(index));
    const std::string p = Pointer("accessors", static_cast<size_t>(index));
    const int components = this->Components(index);
    const size_t csize = gltfcheck::ComponentSize(a.componentType);
    // The check lets only SCALAR and VEC accessors be read (matrices would pad columns).
    if (components <= 0 || components > 4 || csize == 0)
    {
      this->Fail(p, "unexpected type (internal check)");
    }
    std::vector<float> out(a.count * static_cast<size_t>(components), 0.0f);
    if (a.bufferView >= 0)
    {
      size_t size = 0;
      const unsigned char* bytes = this->ViewBytes(a.bufferView, size);
      const tinygltf::BufferView& view = this->Model.bufferViews[static_cast<size_t>(a.bufferView)];
      const uint64_t elementSize = csize * static_cast<uint64_t>(components);
      const uint64_t stride = view.byteStride ? view.byteStride : elementSize;
      const uint64_t end = uint64_t(a.byteOffset) + stride * (a.count - 1) + elementSize;
      if (a.count == 0 || end > size)
      {
        this->Fail(
          p, "the data run past bufferView " + std::to_string(a.bufferView) + " (internal check)");
      }
      for (size_t i = 0; i < a.count; ++i)
      {
        const unsigned char* e = bytes + a.byteOffset + i * stride;
        for (int c = 0; c < components; ++c)
        {
          out[i * static_cast<size_t>(components) + static_cast<size_t>(c)] = static_cast<float>(
            Component(e + static_cast<size_t>(c) * csize, a.componentType, a.normalized));
        }
      }
    }
    if (a.sparse.isSparse)
    {
      const std::vector<uint32_t> indices = this->SparseIndices(a, p);
      size_t size = 0;
      const unsigned char* bytes = this->ViewBytes(a.sparse.values.bufferView, size);
      const uint64_t elementSize = csize * static_cast<uint64_t>(components);
      const uint64_t begin = static_cast<uint64_t>(a.sparse.values.byteOffset);
      if (begin + elementSize * indices.size() > size)
      {
        this->Fail(p + "/sparse/values", "the values run past their bufferView (internal check)");
      }
      for (size_t k = 0; k < indices.size(); ++k)
      {
        const unsigned char* e = bytes + begin + k * elementSize;
        for (int c = 0; c < components; ++c)
        {
          out[indices[k] * static_cast<size_t>(components) + static_cast<size_t>(c)] =
            static_cast<float>(
              Component(e + static_cast<size_t>(c) * csize, a.componentType, a.normalized));
        }
      }
    }
    for (size_t i = 0; i < out.size(); ++i)
    {
      if (!std::isfinite(out[i]))
      {
        this->Fail(p,
          "element " + std::to_string(i / static_cast<size_t>(components)) + " (" + use + ") is " +
            (std::isnan(out[i]) ? "NaN" : "infinite"));
      }
    }
    return out;
  }

  /// Unsigned integer values (indices), each below `limit`.
  std::vector<uint32_t> Unsigned(int index, size_t limit, const std::string& use) const
  {
    const tinygltf::Accessor& a = this->Model.accessors.at(static_cast<size_t>(index));
    const std::string p = Pointer("accessors", static_cast<size_t>(index));
    const size_t csize = gltfcheck::ComponentSize(a.componentType);
    if (this->Components(index) != 1 || a.bufferView < 0 || a.count == 0 ||
      (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    {
      this->Fail(p, "unexpected index accessor (internal check)");
    }
    size_t size = 0;
    const unsigned char* bytes = this->ViewBytes(a.bufferView, size);
    const tinygltf::BufferView& view = this->Model.bufferViews[static_cast<size_t>(a.bufferView)];
    const uint64_t stride = view.byteStride ? view.byteStride : csize;
    if (uint64_t(a.byteOffset) + stride * (a.count - 1) + csize > size)
    {
      this->Fail(
        p, "the data run past bufferView " + std::to_string(a.bufferView) + " (internal check)");
    }
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i)
    {
      out[i] = ReadUnsigned(bytes + a.byteOffset + i * stride, a.componentType);
    }
    if (a.sparse.isSparse)
    {
      const std::vector<uint32_t> indices = this->SparseIndices(a, p);
      size_t vsize = 0;
      const unsigned char* values = this->ViewBytes(a.sparse.values.bufferView, vsize);
      const uint64_t begin = static_cast<uint64_t>(a.sparse.values.byteOffset);
      if (begin + csize * indices.size() > vsize)
      {
        this->Fail(p + "/sparse/values", "the values run past their bufferView (internal check)");
      }
      for (size_t k = 0; k < indices.size(); ++k)
      {
        out[indices[k]] = ReadUnsigned(values + begin + k * csize, a.componentType);
      }
    }
    for (size_t i = 0; i < out.size(); ++i)
    {
      if (out[i] >= limit)
      {
        this->Fail(p,
          "element " + std::to_string(i) + " (" + use + ") is " + std::to_string(out[i]) +
            ", but there are only " + std::to_string(limit) + " points");
      }
    }
    return out;
  }

private:
  const unsigned char* ViewBytes(int index, size_t& size) const
  {
    const std::string p = Pointer("bufferViews", static_cast<size_t>(std::max(index, 0)));
    if (index < 0 || static_cast<size_t>(index) >= this->Model.bufferViews.size())
    {
      this->Fail(p, "no such bufferView (internal check)");
    }
    const auto decoded = this->Decoded.find(index);
    if (decoded != this->Decoded.end())
    {
      size = decoded->second.size(); // EXT_meshopt_compression, decoded
      return decoded->second.data();
    }
    const tinygltf::BufferView& view = this->Model.bufferViews[static_cast<size_t>(index)];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= this->Model.buffers.size())
    {
      this->Fail(p, "no such buffer (internal check)");
    }
    const std::vector<unsigned char>& data =
      this->Model.buffers[static_cast<size_t>(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    {
      this->Fail(p, "lies outside its buffer's data (internal check)");
    }
    size = view.byteLength;
    return data.data() + view.byteOffset;
  }

  std::vector<uint32_t> SparseIndices(const tinygltf::Accessor& a, const std::string& p) const
  {
    const auto& s = a.sparse;
    const size_t csize = gltfcheck::ComponentSize(s.indices.componentType);
    if (s.count <= 0 || static_cast<size_t>(s.count) > a.count || csize == 0 ||
      s.indices.byteOffset < 0 || s.values.byteOffset < 0)
    {
      this->Fail(p + "/sparse", "unexpected sparse storage (internal check)");
    }
    size_t size = 0;
    const unsigned char* bytes = this->ViewBytes(s.indices.bufferView, size);
    const size_t count = static_cast<size_t>(s.count);
    if (uint64_t(s.indices.byteOffset) + uint64_t(count) * csize > size)
    {
      this->Fail(p + "/sparse/indices", "the indices run past their bufferView (internal check)");
    }
    std::vector<uint32_t> out(count);
    for (size_t k = 0; k < count; ++k)
    {
      out[k] = ReadUnsigned(bytes + s.indices.byteOffset + k * csize, s.indices.componentType);
      if (out[k] >= a.count)
      {
        this->Fail(p + "/sparse/indices",
          "index " + std::to_string(k) + " is " + std::to_string(out[k]) +
            ", outside the accessor's " + std::to_string(a.count) + " elements");
      }
      if (k > 0 && out[k] <= out[k - 1])
      {
        this->Fail(p + "/sparse/indices",
          "index " + std::to_string(k) + " (" + std::to_string(out[k]) +
            ") does not follow index " + std::to_string(k - 1) + " (" + std::to_string(out[k - 1]) +
            "): sparse indices must increase");
      }
    }
    return out;
  }

  static uint32_t ReadUnsigned(const unsigned char* p, int type)
  {
    switch (type)
    {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return p[0];
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      default:
      {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
  }

  static double Component(const unsigned char* p, int type, bool normalized)
  {
    switch (type)
    {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
      {
        int8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? p[0] / 255.0 : p[0];
      case TINYGLTF_COMPONENT_TYPE_SHORT:
      {
        int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      default:
      {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
  }

  const tinygltf::Model& Model;
  const gltfext::DecodedViews& Decoded;
  const std::string& Source;
};

// --- the scene -------------------------------------------------------------------------

/// Transforms a part's points, normals and deltas by `m`; mirrored transforms turn the
/// triangles so that they keep facing outwards.
void ApplyTransform(GltfPart& part, const GltfMatrix& m)
{
  const double l[3][3] = { { m[0], m[4], m[8] }, { m[1], m[5], m[9] }, { m[2], m[6], m[10] } };
  // Normals turn with the cofactor matrix (det(L) times the inverse transpose, defined for
  // a singular L too), its sign made that of the inverse transpose.
  double cof[3][3];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      cof[r][c] = l[r1][c1] * l[r2][c2] - l[r1][c2] * l[r2][c1];
    }
  }
  const double det = l[0][0] * cof[0][0] + l[0][1] * cof[0][1] + l[0][2] * cof[0][2];
  double nm[3][3];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      nm[r][c] = det < 0 ? -cof[r][c] : cof[r][c];
    }
  }
  auto linear = [](const double(*a)[3], const float* v, double* out)
  {
    for (int r = 0; r < 3; ++r)
    {
      out[r] = a[r][0] * v[0] + a[r][1] * v[1] + a[r][2] * v[2];
    }
  };
  const size_t n = part.GetNumberOfPoints();
  std::vector<double> normalScale(n, 1.0);
  for (size_t i = 0; i < n; ++i)
  {
    double p[3];
    linear(l, &part.Positions[3 * i], p);
    for (int k = 0; k < 3; ++k)
    {
      part.Positions[3 * i + static_cast<size_t>(k)] = static_cast<float>(p[k] + m[12 + k]);
    }
    if (!part.Normals.empty())
    {
      double q[3];
      linear(nm, &part.Normals[3 * i], q);
      const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
      // A normal keeps unit length, and its deltas are scaled like it, so that the blended
      // normal, once renormalized, is the transform of the file's blended normal.
      normalScale[i] = len > 0 ? 1.0 / len : 1.0;
      for (int k = 0; k < 3; ++k)
      {
        part.Normals[3 * i + static_cast<size_t>(k)] = static_cast<float>(q[k] * normalScale[i]);
      }
    }
  }
  for (auto& target : part.Targets)
  {
    for (size_t i = 0; i < n; ++i)
    {
      double d[3];
      linear(l, &target.PositionDeltas[3 * i], d);
      for (int k = 0; k < 3; ++k)
      {
        target.PositionDeltas[3 * i + static_cast<size_t>(k)] = static_cast<float>(d[k]);
      }
      if (!target.NormalDeltas.empty())
      {
        linear(nm, &target.NormalDeltas[3 * i], d);
        for (int k = 0; k < 3; ++k)
        {
          target.NormalDeltas[3 * i + static_cast<size_t>(k)] =
            static_cast<float>(d[k] * normalScale[i]);
        }
      }
    }
  }
  if (det < 0)
  {
    for (size_t t = 0; t + 2 < part.Triangles.size(); t += 3)
    {
      std::swap(part.Triangles[t + 1], part.Triangles[t + 2]);
    }
  }
  part.TransformApplied = true;
}

std::vector<uint32_t> Triangulate(const std::vector<uint32_t>& corners, int mode)
{
  std::vector<uint32_t> out;
  if (mode == TINYGLTF_MODE_TRIANGLES)
  {
    return corners;
  }
  out.reserve(corners.size() >= 3 ? 3 * (corners.size() - 2) : 0);
  for (size_t i = 0; i + 2 < corners.size(); ++i)
  {
    uint32_t a, b, c;
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
    {
      // glTF 2.0, 3.7.2.1: p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}
      a = corners[i];
      b = corners[i + 1 + i % 2];
      c = corners[i + 2 - i % 2];
    }
    else
    {
      // fan: p_i = {v_{i+1}, v_{i+2}, v_0}
      a = corners[i + 1];
      b = corners[i + 2];
      c = corners[0];
    }
    if (a != b && b != c && a != c) // strips join pieces with degenerate triangles
    {
      out.insert(out.end(), { a, b, c });
    }
  }
  return out;
}

class SceneBuilder
{
public:
  SceneBuilder(const tinygltf::Model& model, const json& root, const gltfcheck::Document& doc,
    const GltfLoadOptions& options, const gltfext::DecodedViews& decoded, const std::string& source)
    : Model(model)
    , Root(root)
    , Doc(doc)
    , Options(options)
    , Read(model, decoded, source)
    , Decoded(decoded)
    , Source(source)
  {
  }

  GltfScene Build()
  {
    this->CheckModel();
    GltfScene scene;
    scene.Scene = this->Doc.Scene;
    if (scene.Scene >= 0)
    {
      scene.SceneName = this->Model.scenes[static_cast<size_t>(scene.Scene)].name;
    }
    this->BuildMeshes(scene);
    this->BuildNodes(scene);
    scene.Skins = gltfskin::ReadSkins(this->Model, scene.Nodes, this->Source, &this->Decoded);
    this->BuildParts(scene);
    this->BuildAnimations(scene);
    return scene;
  }

private:
  /// tinygltf's model must mirror the checked document (it drops what it cannot parse,
  /// which the check has refused already); each buffer holds the bytes it declares.
  void CheckModel() const
  {
    auto size = [&](const char* key) { return this->Root.value(key, json::array()).size(); };
    if (this->Model.buffers.size() != size("buffers") ||
      this->Model.bufferViews.size() != size("bufferViews") ||
      this->Model.accessors.size() != size("accessors") ||
      this->Model.meshes.size() != size("meshes") || this->Model.nodes.size() != size("nodes") ||
      this->Model.materials.size() != size("materials") ||
      this->Model.animations.size() != size("animations") ||
      this->Model.scenes.size() != size("scenes"))
    {
      throw InputError(
        this->Source + ": tinygltf read a different document than was checked (internal check)");
    }
    for (size_t m = 0; m < this->Model.meshes.size(); ++m)
    {
      if (this->Model.meshes[m].primitives.size() != this->Root["meshes"][m]["primitives"].size())
      {
        throw InputError(this->Source + ": " + Pointer("meshes", m) +
          ": tinygltf dropped a primitive (internal check)");
      }
    }
    for (size_t b = 0; b < this->Model.buffers.size(); ++b)
    {
      if (gltfext::IsMeshoptFallback(this->Root["buffers"][b]))
      {
        continue; // stubbed for tinygltf; its views are decoded
      }
      const uint64_t length = this->Root["buffers"][b]["byteLength"].get<uint64_t>();
      if (this->Model.buffers[b].data.size() != length)
      {
        throw InputError(this->Source + ": " + Pointer("buffers", b) + ": holds " +
          std::to_string(this->Model.buffers[b].data.size()) + " bytes, but byteLength is " +
          std::to_string(length));
      }
    }
  }

  void BuildMeshes(GltfScene& scene) const
  {
    for (size_t m = 0; m < this->Model.meshes.size(); ++m)
    {
      const tinygltf::Mesh& mesh = this->Model.meshes[m];
      GltfMesh out;
      out.Name = mesh.name;
      out.NumberOfPrimitives = mesh.primitives.size();
      const size_t targets = this->Doc.MeshTargets[m];
      const json& jm = this->Root["meshes"][m];
      const auto extras = jm.find("extras");
      if (extras != jm.end() && extras->is_object() && extras->contains("targetNames"))
      {
        for (const auto& name : (*extras)["targetNames"])
        {
          out.TargetNames.push_back(name.get<std::string>());
        }
      }
      else
      {
        for (size_t t = 0; t < targets; ++t)
        {
          out.TargetNames.push_back("target" + std::to_string(t));
        }
      }
      out.Weights = mesh.weights.empty() ? std::vector<double>(targets, 0.0) : mesh.weights;
      scene.Meshes.push_back(std::move(out));
    }
  }

  void BuildNodes(GltfScene& scene) const
  {
    const size_t count = this->Model.nodes.size();
    scene.Nodes.resize(count);
    for (size_t n = 0; n < count; ++n)
    {
      const tinygltf::Node& node = this->Model.nodes[n];
      GltfNode& out = scene.Nodes[n];
      out.Name = node.name;
      out.Parent = this->Doc.Parent[n];
      out.Children = node.children;
      out.Mesh = node.mesh;
      out.Weights = node.weights;
      if (node.matrix.size() == 16)
      {
        out.HasMatrix = true;
        std::copy(node.matrix.begin(), node.matrix.end(), out.Local.begin());
      }
      else
      {
        if (node.translation.size() == 3)
        {
          std::copy(node.translation.begin(), node.translation.end(), out.Translation.begin());
        }
        if (node.rotation.size() == 4)
        {
          const double norm =
            std::sqrt(node.rotation[0] * node.rotation[0] + node.rotation[1] * node.rotation[1] +
              node.rotation[2] * node.rotation[2] + node.rotation[3] * node.rotation[3]);
          for (size_t k = 0; k < 4; ++k)
          {
            out.Rotation[k] = node.rotation[k] / norm;
          }
        }
        if (node.scale.size() == 3)
        {
          std::copy(node.scale.begin(), node.scale.end(), out.Scale.begin());
        }
        out.Local = GltfComposeTrs(out.Translation, out.Rotation, out.Scale);
      }
    }
    // World transforms, parents first (the check found no cycle).
    std::vector<size_t> stack;
    for (size_t n = 0; n < count; ++n)
    {
      if (scene.Nodes[n].Parent < 0)
      {
        scene.Nodes[n].World = scene.Nodes[n].Local;
        stack.push_back(n);
      }
    }
    while (!stack.empty())
    {
      const size_t n = stack.back();
      stack.pop_back();
      for (int c : scene.Nodes[n].Children)
      {
        GltfNode& child = scene.Nodes[static_cast<size_t>(c)];
        child.World = GltfMultiply(scene.Nodes[n].World, child.Local);
        stack.push_back(static_cast<size_t>(c));
      }
    }
    for (size_t n = 0; n < count; ++n)
    {
      for (double v : scene.Nodes[n].World)
      {
        if (!std::isfinite(v))
        {
          throw InputError(this->Source + ": " + Pointer("nodes", n) +
            ": the world transform overflows (its parents' scales multiply past the range of a "
            "double)");
        }
      }
    }
  }

  void BuildParts(GltfScene& scene) const
  {
    std::set<std::string> names;
    std::vector<int> stack(this->Doc.Roots.rbegin(), this->Doc.Roots.rend());
    while (!stack.empty())
    {
      const size_t n = static_cast<size_t>(stack.back());
      stack.pop_back();
      GltfNode& node = scene.Nodes[n];
      node.InScene = true;
      if (node.Mesh >= 0)
      {
        const tinygltf::Mesh& mesh = this->Model.meshes[static_cast<size_t>(node.Mesh)];
        for (size_t k = 0; k < mesh.primitives.size(); ++k)
        {
          GltfPart part = this->BuildPart(scene, n, k);
          std::string name = GltfNodeName(scene, static_cast<int>(n));
          if (mesh.primitives.size() > 1)
          {
            name += "/" +
              (part.MaterialName.empty() ? "primitive" + std::to_string(k) : part.MaterialName);
          }
          std::string unique = name;
          for (int i = 2; !names.insert(unique).second; ++i)
          {
            unique = name + "#" + std::to_string(i);
          }
          part.Name = unique;
          scene.Parts.push_back(std::move(part));
        }
      }
      for (size_t c = node.Children.size(); c-- > 0;)
      {
        stack.push_back(node.Children[c]);
      }
    }
  }

  GltfPart BuildPart(const GltfScene& scene, size_t n, size_t k) const
  {
    const GltfNode& node = scene.Nodes[n];
    const size_t m = static_cast<size_t>(node.Mesh);
    const tinygltf::Primitive& prim = this->Model.meshes[m].primitives[k];
    const std::string pp = Pointer("meshes", m) + "/primitives/" + std::to_string(k);
    GltfPart part;
    part.Node = static_cast<int>(n);
    part.Mesh = static_cast<int>(m);
    part.Primitive = static_cast<int>(k);
    part.Material = prim.material;
    if (prim.material >= 0)
    {
      const tinygltf::Material& material =
        this->Model.materials[static_cast<size_t>(prim.material)];
      part.MaterialName = material.name;
      const auto& color = material.pbrMetallicRoughness.baseColorFactor;
      if (color.size() == 4)
      {
        std::copy(color.begin(), color.end(), part.BaseColor.begin());
      }
    }
    part.World = node.World;

    auto attribute = [&](const std::map<std::string, int>& attributes, const char* name)
    {
      auto it = attributes.find(name);
      return it == attributes.end() ? -1 : it->second;
    };
    const int position = attribute(prim.attributes, "POSITION");
    part.Positions = this->Read.Floats(position, "POSITION of " + pp);
    const size_t points = part.GetNumberOfPoints();
    const int normal = attribute(prim.attributes, "NORMAL");
    if (normal >= 0)
    {
      part.Normals = this->Read.Floats(normal, "NORMAL of " + pp);
    }
    const int uv0 = attribute(prim.attributes, "TEXCOORD_0");
    if (uv0 >= 0)
    {
      part.TexCoords0 = this->Read.Floats(uv0, "TEXCOORD_0 of " + pp);
    }
    const int uv1 = attribute(prim.attributes, "TEXCOORD_1");
    if (uv1 >= 0)
    {
      part.TexCoords1 = this->Read.Floats(uv1, "TEXCOORD_1 of " + pp);
    }
    const int color = attribute(prim.attributes, "COLOR_0");
    if (color >= 0)
    {
      const std::vector<float> c = this->Read.Floats(color, "COLOR_0 of " + pp);
      const size_t components = static_cast<size_t>(this->Read.Components(color));
      part.Colors.resize(4 * points, 1.0f);
      for (size_t i = 0; i < points; ++i)
      {
        for (size_t j = 0; j < components; ++j)
        {
          part.Colors[4 * i + j] = c[components * i + j];
        }
      }
    }

    std::vector<uint32_t> corners;
    if (prim.indices >= 0)
    {
      corners = this->Read.Unsigned(prim.indices, points, "indices of " + pp);
    }
    else
    {
      corners.resize(points);
      for (size_t i = 0; i < points; ++i)
      {
        corners[i] = static_cast<uint32_t>(i);
      }
    }
    part.Triangles = Triangulate(corners, prim.mode);

    const std::vector<std::string>& names = scene.Meshes[m].TargetNames;
    for (size_t t = 0; t < prim.targets.size(); ++t)
    {
      GltfTarget target;
      target.Name = t < names.size() ? names[t] : "target" + std::to_string(t);
      const std::string tp = pp + "/targets/" + std::to_string(t);
      const int dp = attribute(prim.targets[t], "POSITION");
      if (dp >= 0)
      {
        target.PositionDeltas = this->Read.Floats(dp, "POSITION of " + tp);
      }
      else
      {
        target.PositionDeltas.assign(3 * points, 0.0f);
      }
      const int dn = attribute(prim.targets[t], "NORMAL");
      if (dn >= 0)
      {
        target.NormalDeltas = this->Read.Floats(dn, "NORMAL of " + tp);
      }
      if (target.PositionDeltas.size() != 3 * points ||
        (!target.NormalDeltas.empty() && target.NormalDeltas.size() != 3 * points))
      {
        throw InputError(
          this->Source + ": " + tp + ": the target's point count differs (internal check)");
      }
      part.Targets.push_back(std::move(target));
    }
    const std::vector<double>& nodeWeights = node.Weights;
    part.DefaultWeights = !nodeWeights.empty() ? nodeWeights : scene.Meshes[m].Weights;
    if (part.DefaultWeights.size() != part.Targets.size())
    {
      throw InputError(
        this->Source + ": " + pp + ": weights and targets differ in number (internal check)");
    }
    const int skin = this->Model.nodes[n].skin;
    if (skin >= 0) // gltf/GltfSkin.cpp
    {
      gltfskin::ReadInfluences(
        this->Model, prim, skin, scene.Skins, pp,
        [this](int a, const std::string& use) { return this->Read.Floats(a, use); }, this->Source,
        part);
    }
    if (this->Options.ApplyTransforms)
    {
      if (part.Skin >= 0)
      {
        gltfskin::SkinAtRest(part, scene, this->Source + ": " + pp); // the node's transform ignored
      }
      else
      {
        ApplyTransform(part, part.World);
      }
      // A finite but huge transform (1e300) can take points past the range of float.
      auto finite = [](const std::vector<float>& v)
      { return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); }); };
      bool ok = finite(part.Positions) && finite(part.Normals);
      for (const auto& target : part.Targets)
      {
        ok = ok && finite(target.PositionDeltas) && finite(target.NormalDeltas);
      }
      if (!ok)
      {
        throw InputError(this->Source + ": " + Pointer("nodes", n) +
          ": its world transform takes the points of " + pp + " beyond the range of float");
      }
    }
    CheckBlendRange(part, this->Source + ": " + pp);
    return part;
  }

  void BuildAnimations(GltfScene& scene) const
  {
    for (size_t a = 0; a < this->Model.animations.size(); ++a)
    {
      const tinygltf::Animation& animation = this->Model.animations[a];
      const std::string ap = Pointer("animations", a);
      GltfAnimation out;
      out.Name = animation.name;
      for (size_t s = 0; s < animation.samplers.size(); ++s)
      {
        const tinygltf::AnimationSampler& sampler = animation.samplers[s];
        const std::string sp = ap + "/samplers/" + std::to_string(s);
        GltfAnimationSampler so;
        so.Interpolation = sampler.interpolation == "STEP" ? GltfInterpolation::Step
          : sampler.interpolation == "CUBICSPLINE"         ? GltfInterpolation::CubicSpline
                                                           : GltfInterpolation::Linear;
        so.Times = this->Read.Floats(sampler.input, "input of " + sp);
        for (size_t i = 0; i < so.Times.size(); ++i)
        {
          if (so.Times[i] < 0 || (i > 0 && so.Times[i] < so.Times[i - 1]))
          {
            throw InputError(this->Source + ": " +
              Pointer("accessors", static_cast<size_t>(sampler.input)) + ": key time " +
              std::to_string(i) + " (" + text::FormatNumber(so.Times[i]) + " s, input of " + sp +
              ") is " + (so.Times[i] < 0 ? "negative" : "earlier than the key before it"));
          }
        }
        so.Values = this->Read.Floats(sampler.output, "output of " + sp);
        so.Components = this->Read.Components(sampler.output);
        out.Samplers.push_back(std::move(so));
      }
      for (const tinygltf::AnimationChannel& channel : animation.channels)
      {
        if (channel.target_node < 0)
        {
          continue; // targets named by extensions are not read
        }
        GltfAnimationChannel co;
        co.Sampler = channel.sampler;
        co.Node = channel.target_node;
        const std::string& path = channel.target_path;
        co.Path = path == "translation" ? GltfAnimationPath::Translation
          : path == "rotation"          ? GltfAnimationPath::Rotation
          : path == "scale"             ? GltfAnimationPath::Scale
                                        : GltfAnimationPath::Weights;
        co.ValuesPerElement = co.Path == GltfAnimationPath::Rotation ? 4
          : co.Path == GltfAnimationPath::Weights
          ? static_cast<int>(
              this->Doc
                .MeshTargets[static_cast<size_t>(scene.Nodes[static_cast<size_t>(co.Node)].Mesh)])
          : 3;
        out.Channels.push_back(co);
      }
      scene.Animations.push_back(std::move(out));
    }
  }

  const tinygltf::Model& Model;
  const json& Root;
  const gltfcheck::Document& Doc;
  const GltfLoadOptions& Options;
  Reader Read;
  const gltfext::DecodedViews& Decoded; // EXT_meshopt_compression's views (skins read them too)
  const std::string& Source;
};
} // namespace

void GltfTransformPart(GltfPart& part, const GltfMatrix& m)
{
  ApplyTransform(part, m);
}

GltfScene LoadGltfSceneFromMemory(const void* data, size_t size, const std::string& baseDirectory,
  const GltfLoadOptions& options, const std::string& sourceName)
{
  const unsigned char* bytes = static_cast<const unsigned char*>(data);
  if (size > 0xffffffffull)
  {
    throw InputError(sourceName + ": larger than 4 GiB, which glTF does not allow");
  }
  const gltfcheck::Container container = gltfcheck::SplitContainer(bytes, size, sourceName);
  const json root = gltfcheck::ParseJson(container, sourceName);
  const gltfcheck::Document doc = gltfcheck::CheckDocument(
    root, container, !baseDirectory.empty(), options.MaxDecodedBytes, sourceName);
  std::vector<std::vector<unsigned char>> images;
  const tinygltf::Model model =
    LoadModel(bytes, size, container, baseDirectory, root, sourceName, images);
  const gltfext::DecodedViews decoded =
    gltfext::DecodeMeshopt(model, root, options.MaxDecodedBytes, sourceName);
  GltfScene scene = SceneBuilder(model, root, doc, options, decoded, sourceName).Build();
  Folder folder{ baseDirectory.empty() ? std::string() : baseDirectory + "/",
    options.MaxDecodedBytes };
  const uint64_t used = doc.DecodedBytes +
    [&decoded]
  {
    uint64_t n = 0;
    for (const auto& view : decoded)
    {
      n += view.second.size();
    }
    return n;
  }();
  gltfext::ReadMaterials(root, images, &ReadImageFile, &folder,
    options.MaxDecodedBytes > used ? options.MaxDecodedBytes - used : 0, scene, sourceName);
  return scene;
}

GltfScene LoadGltfScene(const std::string& fileName, const GltfLoadOptions& options)
{
  const std::string bytes =
    text::ReadFile(fileName, "glTF file", (uint64_t(4) << 30) - 1); // glTF's 4 GiB
  std::string folder = std::filesystem::path(fileName).parent_path().string();
  if (folder.empty())
  {
    folder = ".";
  }
  return LoadGltfSceneFromMemory(bytes.data(), bytes.size(), folder, options, fileName);
}
} // namespace morphnode
