// SPDX-License-Identifier: BSD-3-Clause
// EXT_meshopt_compression through Debian's libmeshoptimizer (0.18), and the list of
// extensions the loader implements. See GltfExtensions.h.
#include "GltfExtensions.h"

#include "base/Error.h"
#include "base/Text.h"

#include <meshoptimizer.h>

#include <cstring>
#include <set>

namespace morphnode
{
namespace gltfext
{
using json = nlohmann::json;

bool IsImplemented(const std::string& name)
{
  static const std::set<std::string> implemented{ "KHR_mesh_quantization",
    "EXT_meshopt_compression", "EXT_texture_webp", "KHR_texture_transform", "KHR_materials_unlit",
    "KHR_materials_emissive_strength" };
  return implemented.count(name) > 0;
}

std::string WhyNotImplemented(const std::string& name)
{
  if (name == "KHR_draco_mesh_compression")
  {
    return "Draco decoding is not implemented (re-export without Draco, e.g. gltfpack -cc or "
           "gltf-transform meshopt, which MorphNode reads)";
  }
  if (name == "KHR_texture_basisu")
  {
    return "Debian 12 has no KTX2 / Basis Universal decoder";
  }
  if (name == "KHR_meshopt_compression")
  {
    return "Debian's meshoptimizer 0.18 predates it (EXT_meshopt_compression is read)";
  }
  return std::string();
}

bool IsMeshoptFallback(const json& buffer)
{
  if (!buffer.is_object() || buffer.contains("uri"))
  {
    return false;
  }
  const auto ext = buffer.find("extensions");
  if (ext == buffer.end() || !ext->is_object())
  {
    return false;
  }
  const auto meshopt = ext->find("EXT_meshopt_compression");
  if (meshopt == ext->end() || !meshopt->is_object())
  {
    return false;
  }
  const auto fallback = meshopt->find("fallback");
  return fallback != meshopt->end() && fallback->is_boolean() && fallback->get<bool>();
}

bool NeedsPatch(const json& root)
{
  const auto buffers = root.find("buffers");
  if (buffers == root.end() || !buffers->is_array())
  {
    return false;
  }
  for (const auto& buffer : *buffers)
  {
    if (IsMeshoptFallback(buffer))
    {
      return true;
    }
  }
  return false;
}

std::string PatchForTinygltf(
  const json& root, bool binary, const unsigned char* bin, size_t binSize)
{
  json patched = root;
  for (auto& buffer : patched["buffers"])
  {
    if (IsMeshoptFallback(buffer))
    {
      buffer["uri"] = "data:application/octet-stream;base64,AAAA";
      buffer["byteLength"] = 3;
    }
  }
  std::string text = patched.dump();
  if (!binary)
  {
    return text;
  }
  while (text.size() % 4 != 0)
  {
    text += ' ';
  }
  const size_t binPadded = bin ? (binSize + 3) / 4 * 4 : 0;
  const uint64_t total = 12 + 8 + text.size() + (bin ? 8 + binPadded : 0);
  std::string glb;
  glb.reserve(static_cast<size_t>(total));
  auto le32 = [&glb](uint64_t v)
  {
    for (int i = 0; i < 4; ++i)
    {
      glb += static_cast<char>((v >> (8 * i)) & 0xff);
    }
  };
  glb += "glTF";
  le32(2);
  le32(total);
  le32(text.size());
  glb += "JSON";
  glb += text;
  if (bin)
  {
    le32(binPadded);
    glb += std::string("BIN\0", 4);
    glb.append(reinterpret_cast<const char*>(bin), binSize);
    glb.append(binPadded - binSize, '\0');
  }
  return glb;
}

namespace
{
/// A member of the extension object, as an unsigned integer no larger than `max`.
uint64_t Unsigned(const json& object, const char* key, bool required, uint64_t fallback,
  uint64_t max, const std::string& pointer, const std::string& source)
{
  const auto it = object.find(key);
  if (it == object.end())
  {
    if (required)
    {
      throw InputError(source + ": " + pointer + ": '" + key + "' is missing");
    }
    return fallback;
  }
  if (!it->is_number_unsigned() || it->get<uint64_t>() > max)
  {
    throw InputError(source + ": " + pointer + "/" + key + ": must be an integer from 0 to " +
      std::to_string(max) + ", got " + it->dump());
  }
  return it->get<uint64_t>();
}

std::string String(const json& object, const char* key, const char* fallback,
  const std::string& pointer, const std::string& source)
{
  const auto it = object.find(key);
  if (it == object.end())
  {
    if (!fallback)
    {
      throw InputError(source + ": " + pointer + ": '" + key + "' is missing");
    }
    return fallback;
  }
  if (!it->is_string())
  {
    throw InputError(source + ": " + pointer + "/" + key + ": must be a string, got " + it->dump());
  }
  return it->get<std::string>();
}
} // namespace

DecodedViews DecodeMeshopt(
  const tinygltf::Model& model, const json& root, uint64_t maxBytes, const std::string& source)
{
  DecodedViews out;
  const auto views = root.find("bufferViews");
  if (views == root.end() || !views->is_array())
  {
    return out;
  }
  const auto buffers = root.find("buffers");
  uint64_t total = 0;
  for (size_t v = 0; v < views->size(); ++v)
  {
    const json& view = (*views)[v];
    const auto exts = view.find("extensions");
    if (exts == view.end() || !exts->is_object() || !exts->contains("EXT_meshopt_compression"))
    {
      continue;
    }
    const json& ext = (*exts)["EXT_meshopt_compression"];
    const std::string p =
      "/bufferViews/" + std::to_string(v) + "/extensions/EXT_meshopt_compression";
    if (!ext.is_object())
    {
      throw InputError(source + ": " + p + ": must be an object, got " + ext.dump());
    }
    if (model.buffers.empty())
    {
      throw InputError(source + ": " + p + ": the file has no buffers");
    }
    const size_t buffer =
      static_cast<size_t>(Unsigned(ext, "buffer", true, 0, model.buffers.size() - 1, p, source));
    if (buffers != root.end() && buffers->is_array() && buffer < buffers->size() &&
      IsMeshoptFallback((*buffers)[buffer]))
    {
      throw InputError(source + ": " + p + "/buffer: buffer " + std::to_string(buffer) +
        " holds no data (it is a fallback buffer)");
    }
    const std::vector<unsigned char>& data = model.buffers[buffer].data;
    const uint64_t offset = Unsigned(ext, "byteOffset", false, 0, data.size(), p, source);
    const uint64_t length = Unsigned(ext, "byteLength", true, 0, data.size() - offset, p, source);
    const uint64_t stride = Unsigned(ext, "byteStride", true, 0, 256, p, source);
    const uint64_t count = Unsigned(ext, "count", true, 0, 0xffffffffull, p, source);
    const std::string mode = String(ext, "mode", nullptr, p, source);
    const std::string filter = String(ext, "filter", "NONE", p, source);
    // The view's own byteLength was checked against its (fallback) buffer; the decoded data
    // fill it.
    const uint64_t viewLength = view.at("byteLength").get<uint64_t>();
    if (stride == 0 || count * stride > viewLength)
    {
      throw InputError(source + ": " + p + ": count " + std::to_string(count) + " x byteStride " +
        std::to_string(stride) + " does not fit the bufferView's byteLength " +
        std::to_string(viewLength));
    }
    total += viewLength;
    if (total > maxBytes)
    {
      throw InputError(source + ": " + p + ": the compressed views would take more than " +
        std::to_string(maxBytes) + " bytes decoded (GltfLoadOptions::MaxDecodedBytes)");
    }
    std::vector<unsigned char> decoded(static_cast<size_t>(viewLength), 0);
    const unsigned char* src = data.data() + offset;
    const size_t n = static_cast<size_t>(count);
    const size_t s = static_cast<size_t>(stride);
    if (length == 0)
    {
      throw InputError(source + ": " + p + "/byteLength: the compressed stream is empty");
    }
    // The library asserts its preconditions (removed in release builds): check them here.
    int rc = 0;
    if (mode == "ATTRIBUTES")
    {
      if (s % 4 != 0)
      {
        throw InputError(source + ": " + p + "/byteStride: " + std::to_string(s) +
          " is not a multiple of 4, which ATTRIBUTES need");
      }
      if ((src[0] & 0xf0) != 0xa0)
      {
        throw InputError(source + ": " + p + ": not a meshopt vertex stream (header byte " +
          std::to_string(src[0]) + ")");
      }
      if ((src[0] & 0x0f) > 0)
      {
        throw InputError(source + ": " + p + ": meshopt vertex stream version " +
          std::to_string(src[0] & 0x0f) + ", which Debian's meshoptimizer " +
          std::to_string(MESHOPTIMIZER_VERSION / 1000) + "." +
          std::to_string(MESHOPTIMIZER_VERSION / 10 % 100) + " cannot decode (it reads version 0)");
      }
      rc = meshopt_decodeVertexBuffer(decoded.data(), n, s, src, static_cast<size_t>(length));
    }
    else if (mode == "TRIANGLES" || mode == "INDICES")
    {
      if (s != 2 && s != 4)
      {
        throw InputError(
          source + ": " + p + "/byteStride: " + std::to_string(s) + " must be 2 or 4 for " + mode);
      }
      if (filter != "NONE")
      {
        throw InputError(source + ": " + p + "/filter: " + text::Quote(filter) +
          " is only allowed with ATTRIBUTES");
      }
      const bool triangles = mode == "TRIANGLES";
      if (triangles && n % 3 != 0)
      {
        throw InputError(source + ": " + p + "/count: " + std::to_string(n) +
          " is not a multiple of 3 (TRIANGLES)");
      }
      const unsigned header = triangles ? 0xe0u : 0xd0u;
      const unsigned maxVersion = triangles ? 1u : 0u;
      if ((src[0] & 0xf0u) != header)
      {
        throw InputError(source + ": " + p + ": not a meshopt " +
          (triangles ? "index" : "index sequence") + " stream (header byte " +
          std::to_string(src[0]) + ")");
      }
      if ((src[0] & 0x0fu) > maxVersion)
      {
        throw InputError(source + ": " + p + ": meshopt " + mode + " stream version " +
          std::to_string(src[0] & 0x0f) + ", which Debian's meshoptimizer 0.18 cannot decode");
      }
      rc = triangles
        ? meshopt_decodeIndexBuffer(decoded.data(), n, s, src, static_cast<size_t>(length))
        : meshopt_decodeIndexSequence(decoded.data(), n, s, src, static_cast<size_t>(length));
    }
    else
    {
      throw InputError(source + ": " + p + "/mode: " + text::Quote(mode) +
        " is not an EXT_meshopt_compression mode (ATTRIBUTES, TRIANGLES, INDICES)");
    }
    if (rc != 0)
    {
      throw InputError(source + ": " + p + ": the compressed " + mode +
        " stream cannot be decoded (meshoptimizer error " + std::to_string(rc) + ")");
    }
    if (filter == "OCTAHEDRAL")
    {
      if (s != 4 && s != 8)
      {
        throw InputError(source + ": " + p +
          "/byteStride: the OCTAHEDRAL filter needs 4 or 8, got " + std::to_string(s));
      }
      meshopt_decodeFilterOct(decoded.data(), n, s);
    }
    else if (filter == "QUATERNION")
    {
      if (s != 8)
      {
        throw InputError(source + ": " + p + "/byteStride: the QUATERNION filter needs 8, got " +
          std::to_string(s));
      }
      meshopt_decodeFilterQuat(decoded.data(), n, s);
    }
    else if (filter == "EXPONENTIAL")
    {
      meshopt_decodeFilterExp(decoded.data(), n, s); // s % 4 == 0 checked above
    }
    else if (filter != "NONE")
    {
      throw InputError(source + ": " + p + "/filter: " + text::Quote(filter) +
        " is a filter Debian's meshoptimizer 0.18 cannot decode (NONE, OCTAHEDRAL, QUATERNION, "
        "EXPONENTIAL)");
    }
    out.emplace(static_cast<int>(v), std::move(decoded));
  }
  return out;
}
} // namespace gltfext
} // namespace morphnode
