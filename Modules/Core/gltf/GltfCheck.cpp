// SPDX-License-Identifier: BSD-3-Clause
#include "GltfCheck.h"
#include "GltfExtensions.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace morphnode
{
namespace gltfcheck
{
namespace
{
using json = nlohmann::json;

// tinygltf keeps indices, sparse counts and offsets in `int`: every index and count that
// reaches it must fit.
constexpr uint64_t MaxIndex = 0x7fffffff;
// Byte lengths and offsets: a GLB cannot exceed 4 GiB, and no buffer here may either.
constexpr uint64_t MaxBytes = 0xffffffffull;

constexpr int Byte = 5120, UnsignedByte = 5121, Short = 5122, UnsignedShort = 5123,
              UnsignedInt = 5125, Float = 5126;

uint32_t ReadLe32(const unsigned char* p)
{
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

/// RFC 6901: "~" -> "~0", "/" -> "~1".
std::string Escape(const std::string& key)
{
  std::string out;
  for (char c : key)
  {
    if (c == '~')
    {
      out += "~0";
    }
    else if (c == '/')
    {
      out += "~1";
    }
    else
    {
      out += c;
    }
  }
  return out;
}

std::string At(const std::string& pointer, const std::string& key)
{
  return pointer + "/" + Escape(key);
}

std::string At(const std::string& pointer, size_t index)
{
  return pointer + "/" + std::to_string(index);
}

const char* ComponentName(int componentType)
{
  switch (componentType)
  {
    case Byte:
      return "BYTE";
    case UnsignedByte:
      return "UNSIGNED_BYTE";
    case Short:
      return "SHORT";
    case UnsignedShort:
      return "UNSIGNED_SHORT";
    case UnsignedInt:
      return "UNSIGNED_INT";
    case Float:
      return "FLOAT";
    default:
      return "?";
  }
}

/// What the checks of meshes and animations need to know of an accessor.
struct AccessorInfo
{
  int ComponentType = 0;
  std::string Type;
  int Components = 0;
  uint64_t Count = 0;
  bool Normalized = false;
  bool HasBufferView = false;
  bool Sparse = false;

  std::string Describe() const
  {
    return this->Type + " of " + ComponentName(this->ComponentType) +
      (this->Normalized ? " (normalized)" : "");
  }
};

class Checker
{
public:
  Checker(const json& root, const Container& container, bool external, uint64_t maxBytes,
    const std::string& source)
    : Root(root)
    , Input(container)
    , External(external)
    , MaxDecoded(maxBytes)
    , Source(source)
  {
  }

  Document Run();

private:
  [[noreturn]] void Fail(const std::string& pointer, const std::string& what) const
  {
    throw InputError(
      this->Source + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " + what);
  }

  static std::string Describe(const json& v)
  {
    switch (v.type())
    {
      case json::value_t::null:
        return "null";
      case json::value_t::boolean:
        return v.get<bool>() ? "true" : "false";
      case json::value_t::string:
        return "the string " + text::Quote(v.get_ref<const std::string&>());
      case json::value_t::number_integer:
        return std::to_string(v.get<int64_t>());
      case json::value_t::number_unsigned:
        return std::to_string(v.get<uint64_t>());
      case json::value_t::number_float:
        return text::FormatNumber(v.get<double>());
      case json::value_t::array:
        return "an array";
      case json::value_t::object:
        return "an object";
      default:
        return "a " + std::string(v.type_name());
    }
  }

  const json* Member(const json& object, const char* key) const
  {
    auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  void ExpectObject(const json& v, const std::string& pointer) const
  {
    if (!v.is_object())
    {
      this->Fail(pointer, "must be an object, got " + Describe(v));
    }
  }

  /// The array `key` of `object` (empty when absent and not required).
  const json& Array(const json& object, const char* key, const std::string& pointer, bool required,
    size_t minSize = 0) const
  {
    static const json empty = json::array();
    const json* v = this->Member(object, key);
    if (!v)
    {
      if (required)
      {
        this->Fail(pointer, std::string("'") + key + "' is missing");
      }
      return empty;
    }
    if (!v->is_array())
    {
      this->Fail(At(pointer, key), "must be an array, got " + Describe(*v));
    }
    if (v->size() < minSize)
    {
      this->Fail(At(pointer, key),
        "must have at least " + std::to_string(minSize) + " element" + (minSize == 1 ? "" : "s"));
    }
    return *v;
  }

  /// An array of objects (each checked to be an object).
  const json& Objects(const json& object, const char* key, const std::string& pointer,
    bool required, size_t minSize = 0) const
  {
    const json& a = this->Array(object, key, pointer, required, minSize);
    for (size_t i = 0; i < a.size(); ++i)
    {
      this->ExpectObject(a[i], At(At(pointer, key), i));
    }
    return a;
  }

  uint64_t UnsignedValue(const json& v, const std::string& pointer, uint64_t max) const
  {
    if (!v.is_number_integer())
    {
      this->Fail(pointer, "must be an integer, got " + Describe(v));
    }
    if (!v.is_number_unsigned() && v.get<int64_t>() < 0)
    {
      this->Fail(pointer, "must not be negative, got " + Describe(v));
    }
    const uint64_t u = v.get<uint64_t>();
    if (u > max)
    {
      this->Fail(pointer, Describe(v) + " is too large (at most " + std::to_string(max) + ")");
    }
    return u;
  }

  uint64_t Unsigned(const json& object, const char* key, const std::string& pointer, bool required,
    uint64_t fallback, uint64_t min, uint64_t max) const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      if (required)
      {
        this->Fail(pointer, std::string("'") + key + "' is missing");
      }
      return fallback;
    }
    const uint64_t u = this->UnsignedValue(*v, At(pointer, key), max);
    if (u < min)
    {
      this->Fail(
        At(pointer, key), "must be at least " + std::to_string(min) + ", got " + Describe(*v));
    }
    return u;
  }

  int IndexValue(const json& v, const std::string& pointer, size_t size, const char* array,
    const char* owner = "the file") const
  {
    const uint64_t u = this->UnsignedValue(v, pointer, MaxIndex);
    if (u >= size)
    {
      this->Fail(pointer,
        "there is no " + std::string(array) + " " + std::to_string(u) + " (" + owner + " has " +
          std::to_string(size) + ")");
    }
    return static_cast<int>(u);
  }

  /// Index into the top-level array `array` (of `size` elements); -1 when absent.
  int Index(const json& object, const char* key, const std::string& pointer, bool required,
    size_t size, const char* array, const char* owner = "the file") const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      if (required)
      {
        this->Fail(pointer, std::string("'") + key + "' is missing");
      }
      return -1;
    }
    return this->IndexValue(*v, At(pointer, key), size, array, owner);
  }

  std::string String(
    const json& object, const char* key, const std::string& pointer, bool required) const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      if (required)
      {
        this->Fail(pointer, std::string("'") + key + "' is missing");
      }
      return std::string();
    }
    if (!v->is_string())
    {
      this->Fail(At(pointer, key), "must be a string, got " + Describe(*v));
    }
    return v->get<std::string>();
  }

  bool Boolean(const json& object, const char* key, const std::string& pointer) const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      return false;
    }
    if (!v->is_boolean())
    {
      this->Fail(At(pointer, key), "must be true or false, got " + Describe(*v));
    }
    return v->get<bool>();
  }

  /// An array of numbers (`size` of them unless 0); absent: empty.
  std::vector<double> Numbers(
    const json& object, const char* key, const std::string& pointer, size_t size) const
  {
    const json& a = this->Array(object, key, pointer, false);
    if (this->Member(object, key) && size != 0 && a.size() != size)
    {
      this->Fail(At(pointer, key),
        "must have " + std::to_string(size) + " numbers, got " + std::to_string(a.size()));
    }
    std::vector<double> out;
    out.reserve(a.size());
    for (size_t i = 0; i < a.size(); ++i)
    {
      if (!a[i].is_number())
      {
        this->Fail(At(At(pointer, key), i), "must be a number, got " + Describe(a[i]));
      }
      out.push_back(a[i].get<double>());
      // JSON has no NaN or infinity, and nlohmann rejects overflowing numbers, but check;
      // glTF's numbers are float: beyond its range is an error too (1e39 became infinity).
      if (!std::isfinite(out.back()))
      {
        this->Fail(At(At(pointer, key), i), "must be finite");
      }
      if (std::fabs(out.back()) > static_cast<double>(std::numeric_limits<float>::max()))
      {
        this->Fail(At(At(pointer, key), i),
          text::FormatNumber(out.back()) + " is beyond the range of float");
      }
    }
    return out;
  }

  void CheckNames(const json& object, const std::string& pointer) const
  {
    this->String(object, "name", pointer, false);
  }

  void CheckAsset();
  void CheckBuffers();
  void CheckBufferViews();
  void CheckAccessors();
  void CheckMaterials();
  void CheckMeshes();
  void CheckNodes();
  void CheckScenes(Document& doc);
  void CheckAnimations();
  void CheckImages();
  void CheckOthers();
  void Estimate(Document& doc);

  /// The accessor of a primitive's attribute, checked to be one of the allowed kinds.
  const AccessorInfo& Attribute(int accessor, const std::string& pointer, const char* semantic,
    const char* expected, bool (*allowed)(const AccessorInfo&)) const
  {
    const AccessorInfo& info = this->Accessors[static_cast<size_t>(accessor)];
    if (!allowed(info))
    {
      this->Fail(pointer,
        std::string("accessor ") + std::to_string(accessor) + " is " + info.Describe() + "; " +
          semantic + " must be " + expected);
    }
    return info;
  }

  const json& Root;
  const Container& Input;
  const bool External;
  const uint64_t MaxDecoded;
  const std::string& Source;

  std::vector<uint64_t> BufferLengths;
  struct ViewInfo
  {
    uint64_t Offset = 0, Length = 0, Stride = 0;
    int Buffer = -1;
  };
  std::vector<ViewInfo> Views;
  std::vector<AccessorInfo> Accessors;
  size_t NumMaterials = 0;
  bool Quantized = false; ///< KHR_mesh_quantization is used
  struct MeshInfo
  {
    size_t Targets = 0;
    struct Primitive
    {
      uint64_t Points = 0, Triangles = 0;
      bool Normals = false, Colors = false;
      std::vector<bool> TargetNormals;
    };
    std::vector<Primitive> Primitives;
  };
  std::vector<MeshInfo> Meshes;
  std::vector<int> Parent;
  size_t NumNodes = 0;
};

void Checker::CheckAsset()
{
  const json* asset = this->Member(this->Root, "asset");
  if (!asset)
  {
    this->Fail("", "'asset' is missing (is this a glTF 2.0 file?)");
  }
  this->ExpectObject(*asset, "/asset");
  const std::string version = this->String(*asset, "version", "/asset", true);
  if (version.size() < 2 || version.compare(0, 2, "2.") != 0)
  {
    this->Fail("/asset/version", "glTF " + text::Quote(version) + " is not supported (only 2.x)");
  }
  const std::string minVersion = this->String(*asset, "minVersion", "/asset", false);
  if (!minVersion.empty() && minVersion != "2.0")
  {
    // The file needs a newer reader than glTF 2.0 (the spec: refuse, do not guess).
    this->Fail("/asset/minVersion",
      "glTF " + text::Quote(minVersion) + " is required; this reader reads 2.0");
  }
  this->String(*asset, "generator", "/asset", false);

  const json& used = this->Array(this->Root, "extensionsUsed", "", false);
  for (size_t i = 0; i < used.size(); ++i)
  {
    if (!used[i].is_string())
    {
      this->Fail(At("/extensionsUsed", i), "must be a string, got " + Describe(used[i]));
    }
    this->Quantized = this->Quantized || used[i].get<std::string>() == "KHR_mesh_quantization";
  }
  const json& required = this->Array(this->Root, "extensionsRequired", "", false);
  for (size_t i = 0; i < required.size(); ++i)
  {
    if (!required[i].is_string())
    {
      this->Fail(At("/extensionsRequired", i), "must be a string, got " + Describe(required[i]));
    }
    const std::string name = required[i].get<std::string>();
    // A required extension MorphNode does not implement is refused, never read as garbage
    // (GltfExtensions.h lists those it implements).
    if (!gltfext::IsImplemented(name))
    {
      const std::string why = gltfext::WhyNotImplemented(name);
      this->Fail(At("/extensionsRequired", i),
        "the file requires the extension " + text::Quote(name) +
          ", which MorphNode does not support" + (why.empty() ? std::string() : " (" + why + ")"));
    }
  }
}

void Checker::CheckBuffers()
{
  const json& buffers = this->Objects(this->Root, "buffers", "", false);
  for (size_t b = 0; b < buffers.size(); ++b)
  {
    const std::string p = At("/buffers", b);
    const json& buffer = buffers[b];
    const uint64_t length = this->Unsigned(buffer, "byteLength", p, true, 0, 1, MaxBytes);
    this->CheckNames(buffer, p);
    if (gltfext::IsMeshoptFallback(buffer))
    {
      // EXT_meshopt_compression: no data; only its compressed views are read, decoded.
      this->BufferLengths.push_back(length);
      continue;
    }
    if (!this->Member(buffer, "uri"))
    {
      if (!this->Input.Binary)
      {
        this->Fail(p, "has no 'uri' (only a GLB's first buffer may be its BIN chunk)");
      }
      if (b != 0)
      {
        this->Fail(p, "has no 'uri', but only the first buffer of a GLB can be its BIN chunk");
      }
      if (!this->Input.Bin)
      {
        this->Fail(p, "refers to the GLB's BIN chunk, but the file has none");
      }
      if (length > this->Input.BinSize)
      {
        this->Fail(At(p, "byteLength"),
          std::to_string(length) + " exceeds the BIN chunk (" +
            std::to_string(this->Input.BinSize) + " bytes)");
      }
    }
    else
    {
      const std::string uri = this->String(buffer, "uri", p, true);
      const std::string up = At(p, "uri");
      if (uri.rfind("data:", 0) == 0)
      {
        // tinygltf decodes these two media types for buffers (the spec's
        // application/gltf-buffer and the older application/octet-stream).
        std::string payload;
        for (const char* prefix :
          { "data:application/octet-stream;base64,", "data:application/gltf-buffer;base64," })
        {
          if (uri.rfind(prefix, 0) == 0)
          {
            payload = uri.substr(std::strlen(prefix));
            break;
          }
        }
        if (payload.empty())
        {
          this->Fail(
            up, "a data URI must be base64 of application/octet-stream or application/gltf-buffer");
        }
        size_t n = 0;
        while (n < payload.size() &&
          (std::isalnum(static_cast<unsigned char>(payload[n])) || payload[n] == '+' ||
            payload[n] == '/'))
        {
          if (static_cast<unsigned char>(payload[n]) >= 128)
          {
            break;
          }
          ++n;
        }
        size_t pad = 0;
        while (n + pad < payload.size() && payload[n + pad] == '=' && pad < 2)
        {
          ++pad;
        }
        if (n + pad != payload.size() || n % 4 == 1)
        {
          this->Fail(
            up, "the data URI is not valid base64 (at character " + std::to_string(n + pad) + ")");
        }
        const uint64_t bytes = uint64_t(n) * 3 / 4;
        if (bytes != length)
        {
          this->Fail(up,
            "the data URI holds " + std::to_string(bytes) + " bytes, but byteLength is " +
              std::to_string(length));
        }
      }
      else
      {
        if (!this->External)
        {
          this->Fail(up,
            "the buffer is in a separate file " + text::Quote(uri) +
              ", which cannot be found when reading from memory");
        }
        // tinygltf URL-decodes the path ('+' too); what it will open must be a plain
        // file name in the input's folder.
        std::string decoded;
        for (size_t i = 0; i < uri.size(); ++i)
        {
          if (uri[i] == '%' && i + 2 < uri.size())
          {
            auto hex = [](char c) -> int
            {
              return c >= '0' && c <= '9' ? c - '0'
                : c >= 'a' && c <= 'f'    ? c - 'a' + 10
                : c >= 'A' && c <= 'F'    ? c - 'A' + 10
                                          : 0;
            };
            decoded += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
          }
          else
          {
            decoded += uri[i] == '+' ? ' ' : uri[i];
          }
        }
        bool plain = !decoded.empty() && decoded != "." && decoded != "..";
        for (char c : decoded)
        {
          if (c == '/' || c == '\\' || c == ':' || static_cast<unsigned char>(c) < 32)
          {
            plain = false;
          }
        }
        if (!plain)
        {
          this->Fail(up,
            text::Quote(uri) +
              " is not a file name in the glTF file's own folder (paths, "
              "'..' and URL schemes are not followed)");
        }
      }
    }
    this->BufferLengths.push_back(length);
  }
}

void Checker::CheckBufferViews()
{
  const json& views = this->Objects(this->Root, "bufferViews", "", false);
  for (size_t v = 0; v < views.size(); ++v)
  {
    const std::string p = At("/bufferViews", v);
    const json& view = views[v];
    ViewInfo info;
    info.Buffer = this->Index(view, "buffer", p, true, this->BufferLengths.size(), "buffer");
    info.Offset = this->Unsigned(view, "byteOffset", p, false, 0, 0, MaxBytes);
    info.Length = this->Unsigned(view, "byteLength", p, true, 0, 1, MaxBytes);
    info.Stride = this->Unsigned(view, "byteStride", p, false, 0, 4, 252);
    if (info.Stride % 4 != 0)
    {
      this->Fail(
        At(p, "byteStride"), "must be a multiple of 4, got " + std::to_string(info.Stride));
    }
    if (const json* target = this->Member(view, "target"))
    {
      const uint64_t t = this->UnsignedValue(*target, At(p, "target"), MaxIndex);
      if (t != 34962 && t != 34963)
      {
        this->Fail(At(p, "target"),
          "must be 34962 (ARRAY_BUFFER) or 34963 (ELEMENT_ARRAY_BUFFER), got " + std::to_string(t));
      }
    }
    this->CheckNames(view, p);
    const uint64_t bufferLength = this->BufferLengths[static_cast<size_t>(info.Buffer)];
    if (info.Offset > bufferLength || info.Length > bufferLength - info.Offset)
    {
      this->Fail(p,
        "bytes " + std::to_string(info.Offset) + " to " +
          std::to_string(info.Offset + info.Length) + " lie outside buffer " +
          std::to_string(info.Buffer) + " (" + std::to_string(bufferLength) + " bytes)");
    }
    this->Views.push_back(info);
  }
}

void Checker::CheckAccessors()
{
  const json& accessors = this->Objects(this->Root, "accessors", "", false);
  for (size_t a = 0; a < accessors.size(); ++a)
  {
    const std::string p = At("/accessors", a);
    const json& accessor = accessors[a];
    AccessorInfo info;
    const int view =
      this->Index(accessor, "bufferView", p, false, this->Views.size(), "bufferView");
    info.HasBufferView = view >= 0;
    const uint64_t offset = this->Unsigned(accessor, "byteOffset", p, false, 0, 0, MaxBytes);
    if (!info.HasBufferView && this->Member(accessor, "byteOffset"))
    {
      this->Fail(At(p, "byteOffset"), "is given, but the accessor has no bufferView");
    }
    info.ComponentType =
      static_cast<int>(this->Unsigned(accessor, "componentType", p, true, 0, 0, MaxIndex));
    const size_t componentSize = ComponentSize(info.ComponentType);
    if (componentSize == 0)
    {
      this->Fail(At(p, "componentType"),
        std::to_string(info.ComponentType) +
          " is not a glTF component type (5120, 5121, 5122, 5123, 5125 or 5126)");
    }
    info.Normalized = this->Boolean(accessor, "normalized", p);
    if (info.Normalized && (info.ComponentType == Float || info.ComponentType == UnsignedInt))
    {
      this->Fail(At(p, "normalized"),
        std::string("cannot be true for ") + ComponentName(info.ComponentType));
    }
    info.Count = this->Unsigned(accessor, "count", p, true, 0, 1, MaxIndex);
    info.Type = this->String(accessor, "type", p, true);
    info.Components = ComponentCount(info.Type);
    if (info.Components == 0)
    {
      this->Fail(At(p, "type"),
        text::Quote(info.Type) + " is not SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4");
    }
    this->Numbers(accessor, "min", p, static_cast<size_t>(info.Components));
    this->Numbers(accessor, "max", p, static_cast<size_t>(info.Components));
    this->CheckNames(accessor, p);

    // Bytes per element, with the column padding of byte and short matrices.
    uint64_t elementSize = componentSize * static_cast<uint64_t>(info.Components);
    if (info.Type == "MAT2" && componentSize == 1)
    {
      elementSize = 8;
    }
    else if (info.Type == "MAT3" && componentSize <= 2)
    {
      elementSize = componentSize == 1 ? 12 : 24;
    }

    if (info.HasBufferView)
    {
      const ViewInfo& v = this->Views[static_cast<size_t>(view)];
      if (offset % componentSize != 0 || (v.Offset + offset) % componentSize != 0)
      {
        this->Fail(At(p, "byteOffset"),
          "the accessor's data do not start on a multiple of " + std::to_string(componentSize) +
            " bytes");
      }
      const uint64_t stride = v.Stride ? v.Stride : elementSize;
      if (stride < elementSize)
      {
        this->Fail(p,
          "bufferView " + std::to_string(view) + "'s byteStride " + std::to_string(stride) +
            " is less than an element (" + std::to_string(elementSize) + " bytes)");
      }
      // Count < 2^31 and stride <= 252: no overflow in 64 bits.
      const uint64_t end = offset + stride * (info.Count - 1) + elementSize;
      if (end > v.Length)
      {
        this->Fail(At(p, "count"),
          std::to_string(info.Count) + " elements from byte " + std::to_string(offset) + " need " +
            std::to_string(end) + " bytes, but bufferView " + std::to_string(view) + " has " +
            std::to_string(v.Length));
      }
    }

    if (const json* sparse = this->Member(accessor, "sparse"))
    {
      const std::string sp = At(p, "sparse");
      this->ExpectObject(*sparse, sp);
      info.Sparse = true;
      const uint64_t count = this->Unsigned(*sparse, "count", sp, true, 0, 1, MaxIndex);
      if (count > info.Count)
      {
        this->Fail(At(sp, "count"),
          std::to_string(count) + " exceeds the accessor's count " + std::to_string(info.Count));
      }
      const json* indices = this->Member(*sparse, "indices");
      const json* values = this->Member(*sparse, "values");
      if (!indices)
      {
        this->Fail(sp, "'indices' is missing");
      }
      if (!values)
      {
        this->Fail(sp, "'values' is missing");
      }
      const std::string ip = At(sp, "indices"), vp = At(sp, "values");
      this->ExpectObject(*indices, ip);
      this->ExpectObject(*values, vp);

      const int iview =
        this->Index(*indices, "bufferView", ip, true, this->Views.size(), "bufferView");
      const uint64_t ioffset = this->Unsigned(*indices, "byteOffset", ip, false, 0, 0, MaxIndex);
      const int itype =
        static_cast<int>(this->Unsigned(*indices, "componentType", ip, true, 0, 0, MaxIndex));
      if (itype != UnsignedByte && itype != UnsignedShort && itype != UnsignedInt)
      {
        this->Fail(At(ip, "componentType"),
          std::to_string(itype) + " is not an unsigned integer type (5121, 5123 or 5125)");
      }
      const ViewInfo& iv = this->Views[static_cast<size_t>(iview)];
      if (iv.Stride != 0)
      {
        this->Fail(At(ip, "bufferView"),
          "sparse indices must be tightly packed, but bufferView " + std::to_string(iview) +
            " has a byteStride");
      }
      const uint64_t isize = ComponentSize(itype);
      if ((iv.Offset + ioffset) % isize != 0)
      {
        this->Fail(At(ip, "byteOffset"),
          "the indices do not start on a multiple of " + std::to_string(isize) + " bytes");
      }
      if (ioffset + count * isize > iv.Length)
      {
        this->Fail(At(sp, "count"),
          std::to_string(count) + " indices from byte " + std::to_string(ioffset) + " need " +
            std::to_string(ioffset + count * isize) + " bytes, but bufferView " +
            std::to_string(iview) + " has " + std::to_string(iv.Length));
      }

      const int vview =
        this->Index(*values, "bufferView", vp, true, this->Views.size(), "bufferView");
      const uint64_t voffset = this->Unsigned(*values, "byteOffset", vp, false, 0, 0, MaxIndex);
      const ViewInfo& vv = this->Views[static_cast<size_t>(vview)];
      if (vv.Stride != 0)
      {
        this->Fail(At(vp, "bufferView"),
          "sparse values must be tightly packed, but bufferView " + std::to_string(vview) +
            " has a byteStride");
      }
      if ((vv.Offset + voffset) % componentSize != 0)
      {
        this->Fail(At(vp, "byteOffset"),
          "the values do not start on a multiple of " + std::to_string(componentSize) + " bytes");
      }
      if (voffset + count * elementSize > vv.Length)
      {
        this->Fail(At(sp, "count"),
          std::to_string(count) + " values from byte " + std::to_string(voffset) + " need " +
            std::to_string(voffset + count * elementSize) + " bytes, but bufferView " +
            std::to_string(vview) + " has " + std::to_string(vv.Length));
      }
    }
    this->Accessors.push_back(info);
  }
}

void Checker::CheckMaterials()
{
  const json& materials = this->Objects(this->Root, "materials", "", false);
  for (size_t m = 0; m < materials.size(); ++m)
  {
    const std::string p = At("/materials", m);
    this->CheckNames(materials[m], p);
    if (const json* pbr = this->Member(materials[m], "pbrMetallicRoughness"))
    {
      const std::string pp = At(p, "pbrMetallicRoughness");
      this->ExpectObject(*pbr, pp);
      const std::vector<double> color = this->Numbers(*pbr, "baseColorFactor", pp, 4);
      for (size_t i = 0; i < color.size(); ++i)
      {
        if (color[i] < 0 || color[i] > 1)
        {
          this->Fail(At(At(pp, "baseColorFactor"), i),
            "must lie in [0, 1], got " + text::FormatNumber(color[i]));
        }
      }
    }
  }
  this->NumMaterials = materials.size();
}

bool IsVec3Float(const AccessorInfo& a)
{
  return a.Type == "VEC3" && a.ComponentType == Float;
}

bool IsColor(const AccessorInfo& a)
{
  return (a.Type == "VEC3" || a.Type == "VEC4") &&
    (a.ComponentType == Float ||
      (a.Normalized && (a.ComponentType == UnsignedByte || a.ComponentType == UnsignedShort)));
}

// KHR_mesh_quantization widens the attribute types (its table of types).
bool IsQuantizedPosition(const AccessorInfo& a)
{
  return a.Type == "VEC3" &&
    (a.ComponentType == Float || a.ComponentType == Byte || a.ComponentType == UnsignedByte ||
      a.ComponentType == Short || a.ComponentType == UnsignedShort);
}

bool IsQuantizedNormal(const AccessorInfo& a)
{
  return a.Type == "VEC3" &&
    (a.ComponentType == Float ||
      (a.Normalized && (a.ComponentType == Byte || a.ComponentType == Short)));
}

bool IsQuantizedTargetPosition(const AccessorInfo& a)
{
  return a.Type == "VEC3" &&
    (a.ComponentType == Float || a.ComponentType == Byte || a.ComponentType == Short);
}

bool IsTexCoord(const AccessorInfo& a)
{
  return a.Type == "VEC2" &&
    (a.ComponentType == Float ||
      (a.Normalized && (a.ComponentType == UnsignedByte || a.ComponentType == UnsignedShort)));
}

bool IsQuantizedTexCoord(const AccessorInfo& a)
{
  return a.Type == "VEC2" &&
    (a.ComponentType == Float || a.ComponentType == Byte || a.ComponentType == UnsignedByte ||
      a.ComponentType == Short || a.ComponentType == UnsignedShort);
}

bool IsIndex(const AccessorInfo& a)
{
  return a.Type == "SCALAR" && !a.Normalized &&
    (a.ComponentType == UnsignedByte || a.ComponentType == UnsignedShort ||
      a.ComponentType == UnsignedInt);
}

void Checker::CheckMeshes()
{
  const json& meshes = this->Objects(this->Root, "meshes", "", false);
  for (size_t m = 0; m < meshes.size(); ++m)
  {
    const std::string p = At("/meshes", m);
    const json& mesh = meshes[m];
    this->CheckNames(mesh, p);
    MeshInfo info;
    const json& primitives = this->Objects(mesh, "primitives", p, true, 1);
    for (size_t k = 0; k < primitives.size(); ++k)
    {
      const std::string pp = At(At(p, "primitives"), k);
      const json& primitive = primitives[k];
      MeshInfo::Primitive prim;
      const json* attributes = this->Member(primitive, "attributes");
      if (!attributes)
      {
        this->Fail(pp, "'attributes' is missing");
      }
      const std::string ap = At(pp, "attributes");
      this->ExpectObject(*attributes, ap);
      if (!this->Member(*attributes, "POSITION"))
      {
        this->Fail(ap, "has no POSITION (MorphNode reads meshes with points)");
      }
      const AccessorInfo& position =
        this->Attribute(this->IndexValue((*attributes)["POSITION"], At(ap, "POSITION"),
                          this->Accessors.size(), "accessor"),
          At(ap, "POSITION"), "POSITION",
          this->Quantized ? "VEC3 of FLOAT or (normalized) BYTE/SHORT, unsigned too"
                          : "VEC3 of FLOAT (integers need KHR_mesh_quantization)",
          this->Quantized ? IsQuantizedPosition : IsVec3Float);
      prim.Points = position.Count;
      for (auto it = attributes->begin(); it != attributes->end(); ++it)
      {
        const std::string at = At(ap, it.key());
        const int a = this->IndexValue(it.value(), at, this->Accessors.size(), "accessor");
        const AccessorInfo& info = this->Accessors[static_cast<size_t>(a)];
        if (info.Count != prim.Points)
        {
          this->Fail(at,
            "accessor " + std::to_string(a) + " has " + std::to_string(info.Count) +
              " elements, but POSITION has " + std::to_string(prim.Points));
        }
        if (it.key() == "NORMAL")
        {
          this->Attribute(a, at, "NORMAL",
            this->Quantized ? "VEC3 of FLOAT or normalized BYTE/SHORT" : "VEC3 of FLOAT",
            this->Quantized ? IsQuantizedNormal : IsVec3Float);
          prim.Normals = true;
        }
        else if (it.key() == "TEXCOORD_0" || it.key() == "TEXCOORD_1")
        {
          this->Attribute(a, at, it.key().c_str(),
            this->Quantized ? "VEC2 of FLOAT or (normalized) BYTE/SHORT, unsigned too"
                            : "VEC2 of FLOAT or normalized UNSIGNED_BYTE/SHORT",
            this->Quantized ? IsQuantizedTexCoord : IsTexCoord);
        }
        else if (it.key() == "COLOR_0")
        {
          this->Attribute(
            a, at, "COLOR_0", "VEC3 or VEC4 of FLOAT or normalized UNSIGNED_BYTE/SHORT", IsColor);
          prim.Colors = true;
        }
      }

      uint64_t mode = this->Unsigned(primitive, "mode", pp, false, 4, 0, MaxIndex);
      if (mode > 6)
      {
        this->Fail(At(pp, "mode"), std::to_string(mode) + " is not a glTF primitive mode (0 to 6)");
      }
      if (mode < 4)
      {
        static const char* const names[] = { "POINTS", "LINES", "LINE_LOOP", "LINE_STRIP" };
        this->Fail(At(pp, "mode"),
          std::string(names[mode]) +
            " is not supported: MorphNode reads triangles (modes 4, 5 and 6)");
      }
      uint64_t corners = prim.Points;
      if (this->Member(primitive, "indices"))
      {
        const std::string ip = At(pp, "indices");
        const int a =
          this->Index(primitive, "indices", pp, true, this->Accessors.size(), "accessor");
        const AccessorInfo& info =
          this->Attribute(a, ip, "indices", "SCALAR of UNSIGNED_BYTE, _SHORT or _INT", IsIndex);
        if (!info.HasBufferView)
        {
          this->Fail(
            ip, "accessor " + std::to_string(a) + " has no bufferView, which indices need");
        }
        corners = info.Count;
      }
      if (mode == 4 && corners % 3 != 0)
      {
        this->Fail(this->Member(primitive, "indices") ? At(pp, "indices") : At(ap, "POSITION"),
          std::to_string(corners) + " corners do not make whole triangles (not a multiple of 3)");
      }
      if (corners < 3)
      {
        this->Fail(this->Member(primitive, "indices") ? At(pp, "indices") : At(ap, "POSITION"),
          std::to_string(corners) + " corners make no triangle");
      }
      prim.Triangles = mode == 4 ? corners / 3 : corners - 2;
      this->Index(primitive, "material", pp, false, this->NumMaterials, "material");

      const json& targets = this->Objects(primitive, "targets", pp, false);
      for (size_t t = 0; t < targets.size(); ++t)
      {
        const std::string tp = At(At(pp, "targets"), t);
        bool normals = false;
        for (auto it = targets[t].begin(); it != targets[t].end(); ++it)
        {
          const std::string at = At(tp, it.key());
          const int a = this->IndexValue(it.value(), at, this->Accessors.size(), "accessor");
          const AccessorInfo& info = this->Accessors[static_cast<size_t>(a)];
          if (info.Count != prim.Points)
          {
            this->Fail(at,
              "accessor " + std::to_string(a) + " has " + std::to_string(info.Count) +
                " elements, but the primitive has " + std::to_string(prim.Points) + " points");
          }
          if (it.key() == "POSITION" || it.key() == "NORMAL")
          {
            const bool position = it.key() == "POSITION";
            this->Attribute(a, at, position ? "a POSITION target" : "a NORMAL target",
              !this->Quantized ? "VEC3 of FLOAT"
                : position     ? "VEC3 of FLOAT or (normalized) BYTE/SHORT"
                               : "VEC3 of FLOAT or normalized BYTE/SHORT",
              !this->Quantized ? IsVec3Float
                : position     ? IsQuantizedTargetPosition
                               : IsQuantizedNormal);
            normals = normals || it.key() == "NORMAL";
          }
        }
        prim.TargetNormals.push_back(normals);
      }
      if (k == 0)
      {
        info.Targets = targets.size();
      }
      else if (targets.size() != info.Targets)
      {
        this->Fail(At(pp, "targets"),
          "the primitive has " + std::to_string(targets.size()) +
            " morph targets, but primitive 0 of the mesh has " + std::to_string(info.Targets));
      }
      info.Primitives.push_back(std::move(prim));
    }

    const std::vector<double> weights = this->Numbers(mesh, "weights", p, 0);
    if (this->Member(mesh, "weights") && weights.size() != info.Targets)
    {
      this->Fail(At(p, "weights"),
        std::to_string(weights.size()) + " weights for " + std::to_string(info.Targets) +
          " morph targets");
    }
    if (const json* extras = this->Member(mesh, "extras"))
    {
      if (extras->is_object() && this->Member(*extras, "targetNames"))
      {
        const std::string np = At(At(p, "extras"), "targetNames");
        const json& names = (*extras)["targetNames"];
        if (!names.is_array())
        {
          this->Fail(np, "must be an array of strings, got " + Describe(names));
        }
        if (names.size() != info.Targets)
        {
          this->Fail(np,
            std::to_string(names.size()) + " names for " + std::to_string(info.Targets) +
              " morph targets");
        }
        std::map<std::string, size_t> seen;
        for (size_t i = 0; i < names.size(); ++i)
        {
          if (!names[i].is_string())
          {
            this->Fail(At(np, i), "must be a string, got " + Describe(names[i]));
          }
          const std::string& name = names[i].get_ref<const std::string&>();
          auto inserted = seen.emplace(name, i);
          if (!inserted.second)
          {
            this->Fail(At(np, i),
              text::Quote(name) + " names target " + std::to_string(inserted.first->second) +
                " already");
          }
        }
      }
    }
    this->Meshes.push_back(std::move(info));
  }
}

void Checker::CheckNodes()
{
  const json& nodes = this->Objects(this->Root, "nodes", "", false);
  this->NumNodes = nodes.size();
  this->Parent.assign(nodes.size(), -1);
  for (size_t n = 0; n < nodes.size(); ++n)
  {
    const std::string p = At("/nodes", n);
    const json& node = nodes[n];
    this->CheckNames(node, p);
    const int mesh = this->Index(node, "mesh", p, false, this->Meshes.size(), "mesh");
    // Cameras and skins are not read, but tinygltf keeps their indices in int.
    this->Unsigned(node, "camera", p, false, 0, 0, MaxIndex);
    this->Unsigned(node, "skin", p, false, 0, 0, MaxIndex);

    const std::vector<double> matrix = this->Numbers(node, "matrix", p, 16);
    const std::vector<double> translation = this->Numbers(node, "translation", p, 3);
    const std::vector<double> rotation = this->Numbers(node, "rotation", p, 4);
    this->Numbers(node, "scale", p, 3);
    if (this->Member(node, "matrix"))
    {
      for (const char* trs : { "translation", "rotation", "scale" })
      {
        if (this->Member(node, trs))
        {
          this->Fail(
            At(p, trs), "a node with a 'matrix' cannot also have a translation, rotation or scale");
        }
      }
      if (matrix[3] != 0 || matrix[7] != 0 || matrix[11] != 0 || matrix[15] != 1)
      {
        this->Fail(At(p, "matrix"), "is not an affine transform (its last row must be 0, 0, 0, 1)");
      }
    }
    if (!rotation.empty())
    {
      const double norm = std::sqrt(rotation[0] * rotation[0] + rotation[1] * rotation[1] +
        rotation[2] * rotation[2] + rotation[3] * rotation[3]);
      if (!(norm > 1e-6) || !std::isfinite(norm))
      {
        this->Fail(At(p, "rotation"), "is not a rotation quaternion (its length is 0)");
      }
    }
    const std::vector<double> weights = this->Numbers(node, "weights", p, 0);
    if (this->Member(node, "weights"))
    {
      if (mesh < 0)
      {
        this->Fail(At(p, "weights"), "the node has morph weights but no mesh");
      }
      if (weights.size() != this->Meshes[static_cast<size_t>(mesh)].Targets)
      {
        this->Fail(At(p, "weights"),
          std::to_string(weights.size()) + " weights for " +
            std::to_string(this->Meshes[static_cast<size_t>(mesh)].Targets) +
            " morph targets of mesh " + std::to_string(mesh));
      }
    }
  }

  for (size_t n = 0; n < nodes.size(); ++n)
  {
    const std::string p = At("/nodes", n);
    const json& children = this->Array(nodes[n], "children", p, false);
    for (size_t c = 0; c < children.size(); ++c)
    {
      const std::string cp = At(At(p, "children"), c);
      const int child = this->IndexValue(children[c], cp, nodes.size(), "node");
      if (static_cast<size_t>(child) == n)
      {
        this->Fail(cp, "node " + std::to_string(n) + " cannot be its own child");
      }
      if (this->Parent[static_cast<size_t>(child)] >= 0)
      {
        this->Fail(cp,
          "node " + std::to_string(child) + " is already a child of node " +
            std::to_string(this->Parent[static_cast<size_t>(child)]) + " (a node has one parent)");
      }
      this->Parent[static_cast<size_t>(child)] = static_cast<int>(n);
    }
  }
  // With one parent per node, a node no root reaches lies on or below a cycle.
  std::vector<char> reached(nodes.size(), 0);
  std::vector<size_t> stack;
  for (size_t n = 0; n < nodes.size(); ++n)
  {
    if (this->Parent[n] < 0)
    {
      stack.push_back(n);
    }
  }
  while (!stack.empty())
  {
    const size_t n = stack.back();
    stack.pop_back();
    reached[n] = 1;
    for (const auto& c : this->Array(nodes[n], "children", "", false))
    {
      stack.push_back(c.get<size_t>());
    }
  }
  for (size_t n = 0; n < nodes.size(); ++n)
  {
    if (!reached[n])
    {
      // Walk up to a node of the cycle.
      size_t on = n;
      for (size_t i = 0; i < nodes.size(); ++i)
      {
        on = static_cast<size_t>(this->Parent[on]);
      }
      this->Fail(At(At("/nodes", static_cast<size_t>(this->Parent[on])), "children"),
        "node " + std::to_string(on) + " is its own ancestor (the node hierarchy has a cycle)");
    }
  }
}

void Checker::CheckScenes(Document& doc)
{
  const json& scenes = this->Objects(this->Root, "scenes", "", false);
  for (size_t s = 0; s < scenes.size(); ++s)
  {
    const std::string p = At("/scenes", s);
    this->CheckNames(scenes[s], p);
    const json& roots = this->Array(scenes[s], "nodes", p, false);
    std::set<int> seen;
    for (size_t i = 0; i < roots.size(); ++i)
    {
      const std::string rp = At(At(p, "nodes"), i);
      const int n = this->IndexValue(roots[i], rp, this->NumNodes, "node");
      if (this->Parent[static_cast<size_t>(n)] >= 0)
      {
        this->Fail(rp,
          "node " + std::to_string(n) + " is a child of node " +
            std::to_string(this->Parent[static_cast<size_t>(n)]) + ", not a root");
      }
      if (!seen.insert(n).second)
      {
        this->Fail(rp, "node " + std::to_string(n) + " is listed twice");
      }
    }
  }
  doc.Scene = this->Index(this->Root, "scene", "", false, scenes.size(), "scene");
  if (doc.Scene < 0 && !scenes.empty())
  {
    doc.Scene = 0;
  }
  if (doc.Scene >= 0)
  {
    for (const auto& n : this->Array(scenes[static_cast<size_t>(doc.Scene)], "nodes", "", false))
    {
      doc.Roots.push_back(n.get<int>());
    }
  }
  else
  {
    // No scene: every root node, as most viewers show such files.
    for (size_t n = 0; n < this->NumNodes; ++n)
    {
      if (this->Parent[n] < 0)
      {
        doc.Roots.push_back(static_cast<int>(n));
      }
    }
  }
  doc.Parent = this->Parent;
}

void Checker::CheckAnimations()
{
  const json& animations = this->Objects(this->Root, "animations", "", false);
  const json& nodes = this->Array(this->Root, "nodes", "", false);
  for (size_t a = 0; a < animations.size(); ++a)
  {
    const std::string p = At("/animations", a);
    const json& animation = animations[a];
    this->CheckNames(animation, p);
    const json& samplers = this->Objects(animation, "samplers", p, true, 1);
    struct SamplerInfo
    {
      uint64_t Keys = 0, Outputs = 0;
      bool Cubic = false;
      const AccessorInfo* Output = nullptr;
    };
    std::vector<SamplerInfo> infos;
    for (size_t s = 0; s < samplers.size(); ++s)
    {
      const std::string sp = At(At(p, "samplers"), s);
      const json& sampler = samplers[s];
      SamplerInfo info;
      const int input = this->Index(sampler, "input", sp, true, this->Accessors.size(), "accessor");
      const int output =
        this->Index(sampler, "output", sp, true, this->Accessors.size(), "accessor");
      const AccessorInfo& in = this->Accessors[static_cast<size_t>(input)];
      if (in.Type != "SCALAR" || in.ComponentType != Float)
      {
        this->Fail(At(sp, "input"),
          "accessor " + std::to_string(input) + " is " + in.Describe() +
            "; key times must be SCALAR of FLOAT");
      }
      const std::string interpolation = this->Member(sampler, "interpolation")
        ? this->String(sampler, "interpolation", sp, true)
        : "LINEAR";
      if (interpolation != "LINEAR" && interpolation != "STEP" && interpolation != "CUBICSPLINE")
      {
        this->Fail(At(sp, "interpolation"),
          text::Quote(interpolation) + " is not LINEAR, STEP or CUBICSPLINE");
      }
      info.Cubic = interpolation == "CUBICSPLINE";
      info.Keys = in.Count;
      info.Output = &this->Accessors[static_cast<size_t>(output)];
      info.Outputs = info.Output->Count;
      const uint64_t per = info.Cubic ? 3 * info.Keys : info.Keys;
      if (info.Cubic && info.Keys < 2)
      {
        this->Fail(At(sp, "input"),
          "CUBICSPLINE needs at least 2 keys, the input has " + std::to_string(info.Keys));
      }
      if (info.Outputs % per != 0)
      {
        this->Fail(At(sp, "output"),
          "accessor " + std::to_string(output) + " has " + std::to_string(info.Outputs) +
            " elements, not a multiple of " + std::to_string(per) + " (" +
            std::to_string(info.Keys) + " keys" + (info.Cubic ? " times 3 for CUBICSPLINE)" : ")"));
      }
      infos.push_back(info);
    }

    const json& channels = this->Objects(animation, "channels", p, true, 1);
    std::set<std::pair<int, std::string>> targeted;
    for (size_t c = 0; c < channels.size(); ++c)
    {
      const std::string cp = At(At(p, "channels"), c);
      const json& channel = channels[c];
      const int s =
        this->Index(channel, "sampler", cp, true, samplers.size(), "sampler", "the animation");
      const json* target = this->Member(channel, "target");
      if (!target)
      {
        this->Fail(cp, "'target' is missing");
      }
      const std::string tp = At(cp, "target");
      this->ExpectObject(*target, tp);
      const int node = this->Index(*target, "node", tp, false, nodes.size(), "node");
      const std::string path = this->String(*target, "path", tp, true);
      if (path != "translation" && path != "rotation" && path != "scale" && path != "weights")
      {
        this->Fail(
          At(tp, "path"), text::Quote(path) + " is not translation, rotation, scale or weights");
      }
      if (node < 0)
      {
        continue; // the spec lets extensions name the target; such channels are ignored
      }
      if (!targeted.emplace(node, path).second)
      {
        this->Fail(tp,
          "node " + std::to_string(node) + "'s " + path + " is animated by an earlier channel too");
      }
      const SamplerInfo& info = infos[static_cast<size_t>(s)];
      const AccessorInfo& out = *info.Output;
      const std::string op = At(At(At(p, "samplers"), static_cast<size_t>(s)), "output");
      uint64_t perKey = 1;
      if (path == "translation" || path == "scale")
      {
        if (out.Type != "VEC3" || out.ComponentType != Float)
        {
          this->Fail(op,
            "is " + out.Describe() + ", but channel " + std::to_string(c) + " animates " + path +
              ", which needs VEC3 of FLOAT");
        }
      }
      else
      {
        const bool isRotation = path == "rotation";
        const bool typeOk = out.Type == (isRotation ? "VEC4" : "SCALAR");
        const bool componentOk =
          out.ComponentType == Float || (out.Normalized && out.ComponentType != UnsignedInt);
        if (!typeOk || !componentOk)
        {
          this->Fail(op,
            "is " + out.Describe() + ", but channel " + std::to_string(c) + " animates " + path +
              ", which needs " + (isRotation ? "VEC4" : "SCALAR") +
              " of FLOAT or a normalized integer");
        }
        if (!isRotation)
        {
          const json& n = nodes[static_cast<size_t>(node)];
          const json* mesh = this->Member(n, "mesh");
          perKey = mesh ? this->Meshes[mesh->get<size_t>()].Targets : 0;
          if (perKey == 0)
          {
            this->Fail(At(tp, "node"),
              "node " + std::to_string(node) + " has no mesh with morph targets to weigh");
          }
        }
      }
      const uint64_t expected = info.Keys * perKey * (info.Cubic ? 3 : 1);
      if (info.Outputs != expected)
      {
        this->Fail(op,
          std::to_string(info.Outputs) + " output elements, but " + std::to_string(info.Keys) +
            " keys of " + path +
            (perKey > 1 ? " (" + std::to_string(perKey) + " morph targets)" : std::string()) +
            (info.Cubic ? " with CUBICSPLINE tangents" : "") + " need " + std::to_string(expected));
      }
    }
  }
}

void Checker::CheckImages()
{
  // Images are not decoded, but tinygltf hands an image's buffer view to the (no-op)
  // image loader while it parses, so its index must be good.
  const json& images = this->Objects(this->Root, "images", "", false);
  for (size_t i = 0; i < images.size(); ++i)
  {
    const std::string p = At("/images", i);
    this->CheckNames(images[i], p);
    this->Index(images[i], "bufferView", p, false, this->Views.size(), "bufferView");
    this->String(images[i], "uri", p, false);
    this->String(images[i], "mimeType", p, false);
    if (this->Member(images[i], "bufferView") == nullptr &&
      this->Member(images[i], "uri") == nullptr)
    {
      this->Fail(p, "has neither 'uri' nor 'bufferView'");
    }
    if (this->Member(images[i], "bufferView") && this->Member(images[i], "uri"))
    {
      this->Fail(p, "has both 'uri' and 'bufferView'");
    }
  }
}

void Checker::CheckOthers()
{
  // Not read here, but tinygltf parses them: each must at least be an array of objects.
  for (const char* key : { "textures", "samplers", "skins", "cameras" })
  {
    this->Objects(this->Root, key, "", false);
  }
  const json& cameras = this->Array(this->Root, "cameras", "", false);
  for (size_t c = 0; c < cameras.size(); ++c)
  {
    this->String(cameras[c], "type", At("/cameras", c), true);
  }
}

void Checker::Estimate(Document& doc)
{
  // The decoded scene's size: points, normals, colours and deltas as floats, triangles as
  // 3 x uint32, per part; sampler times and values. Each node of the scene that holds a
  // mesh copies it.
  uint64_t bytes = 0;
  const json& nodes = this->Array(this->Root, "nodes", "", false);
  std::vector<int> stack(doc.Roots.rbegin(), doc.Roots.rend());
  while (!stack.empty())
  {
    const size_t n = static_cast<size_t>(stack.back());
    stack.pop_back();
    bytes += 512;
    if (const json* mesh = this->Member(nodes[n], "mesh"))
    {
      const MeshInfo& info = this->Meshes[mesh->get<size_t>()];
      for (const auto& prim : info.Primitives)
      {
        uint64_t floats = 3 + (prim.Normals ? 3 : 0) + (prim.Colors ? 4 : 0);
        for (bool normals : prim.TargetNormals)
        {
          floats += normals ? 6 : 3;
        }
        bytes += 512 + prim.Points * floats * 4 + prim.Triangles * 12;
      }
    }
    const json& children = this->Array(nodes[n], "children", "", false);
    for (size_t c = children.size(); c-- > 0;)
    {
      stack.push_back(children[c].get<int>());
    }
  }
  const json& animations = this->Array(this->Root, "animations", "", false);
  for (const auto& animation : animations)
  {
    for (const auto& sampler : animation["samplers"])
    {
      const AccessorInfo& in = this->Accessors[sampler["input"].get<size_t>()];
      const AccessorInfo& out = this->Accessors[sampler["output"].get<size_t>()];
      bytes += 256 + in.Count * 4 + out.Count * static_cast<uint64_t>(out.Components) * 4;
    }
  }
  doc.DecodedBytes = bytes;
  if (bytes > this->MaxDecoded)
  {
    this->Fail("",
      "the scene would take " + std::to_string(bytes) + " bytes decoded, more than the limit of " +
        std::to_string(this->MaxDecoded) + " (GltfLoadOptions::MaxDecodedBytes)");
  }
}

Document Checker::Run()
{
  if (!this->Root.is_object())
  {
    this->Fail("", "the glTF document must be a JSON object, got " + Describe(this->Root));
  }
  Document doc;
  this->CheckAsset();
  this->CheckBuffers();
  this->CheckBufferViews();
  this->CheckAccessors();
  this->CheckMaterials();
  this->CheckMeshes();
  this->CheckNodes();
  this->CheckScenes(doc);
  this->CheckAnimations();
  this->CheckImages();
  this->CheckOthers();
  for (const auto& mesh : this->Meshes)
  {
    doc.MeshTargets.push_back(mesh.Targets);
  }
  this->Estimate(doc);
  return doc;
}
} // namespace

size_t ComponentSize(int componentType)
{
  switch (componentType)
  {
    case Byte:
    case UnsignedByte:
      return 1;
    case Short:
    case UnsignedShort:
      return 2;
    case UnsignedInt:
    case Float:
      return 4;
    default:
      return 0;
  }
}

int ComponentCount(const std::string& type)
{
  static const std::map<std::string, int> counts = { { "SCALAR", 1 }, { "VEC2", 2 }, { "VEC3", 3 },
    { "VEC4", 4 }, { "MAT2", 4 }, { "MAT3", 9 }, { "MAT4", 16 } };
  auto it = counts.find(type);
  return it == counts.end() ? 0 : it->second;
}

Container SplitContainer(const unsigned char* data, size_t size, const std::string& source)
{
  Container c;
  auto fail = [&](const std::string& what) { throw InputError(source + ": GLB: " + what); };
  if (size >= 4 && std::memcmp(data, "glTF", 4) == 0)
  {
    c.Binary = true;
    if (size < 12)
    {
      fail("the file ends inside its 12-byte header (" + std::to_string(size) + " bytes)");
    }
    const uint32_t version = ReadLe32(data + 4);
    const uint32_t length = ReadLe32(data + 8);
    if (version != 2)
    {
      fail("version " + std::to_string(version) + " is not supported (only 2)");
    }
    if (length != size)
    {
      fail("the header gives a length of " + std::to_string(length) + " bytes, but the file has " +
        std::to_string(size) + (length > size ? " (truncated?)" : ""));
    }
    size_t at = 12;
    int chunk = 0;
    while (at < size)
    {
      if (size - at < 8)
      {
        fail("chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) +
          ": the file ends inside its header");
      }
      const uint32_t chunkLength = ReadLe32(data + at);
      const uint32_t chunkType = ReadLe32(data + at + 4);
      if (chunkLength > size - at - 8)
      {
        fail("chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) + ": its length " +
          std::to_string(chunkLength) + " runs past the end of the file (" +
          std::to_string(size - at - 8) + " bytes left)");
      }
      if (chunk == 0)
      {
        if (chunkType != 0x4E4F534Au)
        {
          fail("the first chunk must be JSON");
        }
        if (chunkLength == 0)
        {
          fail("the JSON chunk is empty");
        }
        c.Json = reinterpret_cast<const char*>(data + at + 8);
        c.JsonSize = chunkLength;
      }
      else if (chunk == 1)
      {
        // tinygltf reads the BIN chunk only right after the JSON chunk, and only whole
        // 4-byte words of it; an unknown chunk there is an error for it too.
        if (chunkType != 0x004E4942u)
        {
          fail("the second chunk must be BIN");
        }
        if (chunkLength == 0 || chunkLength % 4 != 0)
        {
          fail("the BIN chunk's length " + std::to_string(chunkLength) +
            " is not a positive multiple of 4");
        }
        c.Bin = data + at + 8;
        c.BinSize = chunkLength;
      }
      else if (chunkType == 0x004E4942u)
      {
        fail("chunk " + std::to_string(chunk) + " is a second BIN chunk");
      }
      else if (chunkType == 0x4E4F534Au)
      {
        fail("chunk " + std::to_string(chunk) + " is a second JSON chunk");
      }
      at += 8 + size_t(chunkLength);
      ++chunk;
    }
    if (chunk == 0)
    {
      fail("the file has no JSON chunk");
    }
    return c;
  }
  c.Json = reinterpret_cast<const char*>(data);
  c.JsonSize = size;
  return c;
}

nlohmann::json ParseJson(const Container& container, const std::string& source)
{
  // tinygltf wants at least 4 bytes and an unsigned int length.
  if (container.JsonSize < 4)
  {
    throw InputError(source + ": is neither a GLB nor glTF JSON (" +
      std::to_string(container.JsonSize) + " bytes)");
  }
  if (container.JsonSize > 0xffffffffull)
  {
    throw InputError(source + ": the JSON is larger than 4 GiB");
  }
  try
  {
    return nlohmann::json::parse(container.Json, container.Json + container.JsonSize,
      [](int depth, nlohmann::json::parse_event_t, nlohmann::json&)
      {
        if (depth > MaxDepth)
        {
          throw InputError("the JSON nests deeper than " + std::to_string(MaxDepth) + " levels");
        }
        return true;
      });
  }
  catch (const InputError& e)
  {
    throw InputError(source + ": " + e.what());
  }
  catch (const nlohmann::json::exception& e)
  {
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ..."
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos)
    {
      what = what.substr(bracket + 2);
    }
    throw InputError(source + ": " + (container.Binary ? "the JSON chunk" : "the file") +
      " is not valid glTF JSON: " + what);
  }
}

Document CheckDocument(const nlohmann::json& root, const Container& container, bool external,
  uint64_t maxDecodedBytes, const std::string& source)
{
  return Checker(root, container, external, maxDecodedBytes, source).Run();
}
} // namespace gltfcheck
} // namespace morphnode
