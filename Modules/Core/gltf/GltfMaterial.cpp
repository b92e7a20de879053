// SPDX-License-Identifier: BSD-3-Clause
// Materials, textures, samplers and images of a glTF file (GltfMaterial.h). Every field is
// checked for its JSON type and range here (the document check, GltfCheck.cpp, checks only
// what the geometry needs); a fault is an InputError naming the JSON pointer.
#include "GltfExtensions.h"

#include "gltf/GltfScene.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace gltfext
{
namespace
{
using json = nlohmann::json;

class MaterialReader
{
public:
  MaterialReader(const json& root, GltfScene& scene, const std::string& source)
    : Root(root)
    , Scene(scene)
    , Source(source)
  {
  }

  [[noreturn]] void Fail(const std::string& pointer, const std::string& what) const
  {
    throw InputError(this->Source + ": " + pointer + ": " + what);
  }

  const json* Member(const json& object, const char* key) const
  {
    if (!object.is_object())
    {
      return nullptr;
    }
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  const json& Array(const char* key) const
  {
    static const json empty = json::array();
    const json* a = this->Member(this->Root, key);
    if (!a)
    {
      return empty;
    }
    if (!a->is_array())
    {
      this->Fail(std::string("/") + key, std::string("must be an array, got ") + a->type_name());
    }
    for (size_t i = 0; i < a->size(); ++i)
    {
      if (!(*a)[i].is_object())
      {
        this->Fail(std::string("/") + key + "/" + std::to_string(i), "must be an object");
      }
    }
    return *a;
  }

  double Number(const json& object, const char* key, const std::string& p, double fallback,
    double lo, double hi) const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      return fallback;
    }
    if (!v->is_number() || !std::isfinite(v->get<double>()) || v->get<double>() < lo ||
      v->get<double>() > hi)
    {
      this->Fail(p + "/" + key,
        "must be a number from " + text::FormatNumber(lo) + " to " + text::FormatNumber(hi) +
          ", got " + v->dump());
    }
    return v->get<double>();
  }

  int Index(
    const json& object, const char* key, const std::string& p, size_t size, const char* what) const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      return -1;
    }
    if (!v->is_number_unsigned() || v->get<uint64_t>() >= size)
    {
      this->Fail(p + "/" + key,
        v->dump() + " is not the index of one of the file's " + std::to_string(size) + " " + what);
    }
    return static_cast<int>(v->get<uint64_t>());
  }

  template <size_t N>
  void Numbers(const json& object, const char* key, const std::string& p,
    std::array<double, N>& out, double lo, double hi) const
  {
    const json* v = this->Member(object, key);
    if (!v)
    {
      return;
    }
    if (!v->is_array() || v->size() != N)
    {
      this->Fail(p + "/" + key, "must be an array of " + std::to_string(N) + " numbers");
    }
    for (size_t i = 0; i < N; ++i)
    {
      const json& x = (*v)[i];
      if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo ||
        x.get<double>() > hi)
      {
        this->Fail(p + "/" + key + "/" + std::to_string(i),
          "must be a number from " + text::FormatNumber(lo) + " to " + text::FormatNumber(hi) +
            ", got " + x.dump());
      }
      out[i] = x.get<double>();
    }
  }

  const json* Extensions(const json& object, const std::string& p) const
  {
    const json* e = this->Member(object, "extensions");
    if (e && !e->is_object())
    {
      this->Fail(p + "/extensions", "must be an object");
    }
    return e;
  }

  void Note(const std::string& line)
  {
    for (const auto& n : this->Scene.Notes)
    {
      if (n == line)
      {
        return;
      }
    }
    this->Scene.Notes.push_back(line);
  }

  void ReadImages(const std::vector<std::vector<unsigned char>>& bytes,
    bool (*readFile)(const std::string&, std::vector<unsigned char>&, std::string&, void*),
    void* user, uint64_t maxBytes)
  {
    uint64_t total = 0;
    const json& images = this->Array("images");
    for (size_t i = 0; i < images.size(); ++i)
    {
      const std::string p = "/images/" + std::to_string(i);
      GltfImage image;
      if (const json* name = this->Member(images[i], "name"); name && name->is_string())
      {
        image.Name = name->get<std::string>();
      }
      std::vector<unsigned char> fileBytes;
      const std::vector<unsigned char>* data = i < bytes.size() ? &bytes[i] : nullptr;
      const json* uri = this->Member(images[i], "uri");
      if ((!data || data->empty()) && uri && uri->is_string() &&
        uri->get<std::string>().rfind("data:", 0) != 0)
      {
        std::string error;
        if (readFile && readFile(uri->get<std::string>(), fileBytes, error, user))
        {
          data = &fileBytes;
        }
        else
        {
          image.Error = "the image file " + text::Quote(uri->get<std::string>()) +
            " cannot be read" + (error.empty() ? std::string() : ": " + error);
        }
      }
      if (image.Error.empty())
      {
        if (!data || data->empty())
        {
          image.Error = "no image data";
        }
        else
        {
          // What is left of the decoded-size budget bounds this image (a small PNG can
          // declare a huge canvas of one colour).
          const uint64_t left = maxBytes > total ? (maxBytes - total) / 4 : 0;
          GltfDecodeImage(
            data->data(), data->size(), image, std::min<uint64_t>(left, uint64_t(1) << 26));
          image.Encoded.assign(data->begin(), data->end());
          total += image.Pixels.size();
        }
      }
      if (!image.Error.empty())
      {
        this->Note(p + " (" + (image.Name.empty() ? "unnamed" : image.Name) + "): not decoded (" +
          image.Error + "); textures using it are drawn without it");
      }
      this->Scene.Images.push_back(std::move(image));
    }
  }

  struct Texture
  {
    int Image = -1;
    GltfSampler Sampler;
  };

  void ReadTextures()
  {
    const json& samplers = this->Array("samplers");
    std::vector<GltfSampler> ss;
    for (size_t s = 0; s < samplers.size(); ++s)
    {
      const std::string p = "/samplers/" + std::to_string(s);
      GltfSampler sampler;
      auto value = [&](const char* key, int fallback, std::initializer_list<int> allowed)
      {
        const json* v = this->Member(samplers[s], key);
        if (!v)
        {
          return fallback;
        }
        for (int a : allowed)
        {
          if (v->is_number_integer() && v->get<int64_t>() == a)
          {
            return a;
          }
        }
        this->Fail(p + "/" + key, v->dump() + " is not a glTF sampler value for " + key);
      };
      sampler.MagFilter = value("magFilter", 0, { 9728, 9729 });
      sampler.MinFilter = value("minFilter", 0, { 9728, 9729, 9984, 9985, 9986, 9987 });
      sampler.WrapS = value("wrapS", 10497, { 33071, 33648, 10497 });
      sampler.WrapT = value("wrapT", 10497, { 33071, 33648, 10497 });
      ss.push_back(sampler);
    }
    const json& textures = this->Array("textures");
    const size_t images = this->Scene.Images.size();
    for (size_t t = 0; t < textures.size(); ++t)
    {
      const std::string p = "/textures/" + std::to_string(t);
      Texture texture;
      const int sampler = this->Index(textures[t], "sampler", p, ss.size(), "samplers");
      if (sampler >= 0)
      {
        texture.Sampler = ss[static_cast<size_t>(sampler)];
      }
      const int source = this->Index(textures[t], "source", p, images, "images");
      int webp = -1, basisu = -1;
      if (const json* ext = this->Extensions(textures[t], p))
      {
        for (auto it = ext->begin(); it != ext->end(); ++it)
        {
          const std::string ep = p + "/extensions/" + it.key();
          if (it.key() == "EXT_texture_webp")
          {
            webp = this->Index(it.value(), "source", ep, images, "images");
          }
          else if (it.key() == "KHR_texture_basisu")
          {
            basisu = this->Index(it.value(), "source", ep, images, "images");
          }
          else
          {
            this->Note(ep + ": texture extension not read (ignored)");
          }
        }
      }
      auto decoded = [&](int i)
      { return i >= 0 && this->Scene.Images[static_cast<size_t>(i)].IsDecoded(); };
      // EXT_texture_webp first, `source` its fallback (the extension's rule); a KTX2 image
      // has no decoder here, so only the fallback can draw.
      texture.Image = decoded(webp) ? webp : decoded(source) ? source : -1;
      if (basisu >= 0)
      {
        this->Note(p + ": KHR_texture_basisu has no decoder on Debian 12; " +
          (texture.Image >= 0 ? std::string("its fallback image is drawn")
                              : std::string("drawn with the material's factors only")));
      }
      if (texture.Image < 0 && (source >= 0 || webp >= 0))
      {
        this->Note(p + ": none of its images decoded; drawn with the material's factors only");
      }
      this->Textures.push_back(texture);
    }
  }

  GltfTextureRef TextureInfo(
    const json& material, const char* key, const std::string& mp, const char* scaleKey)
  {
    GltfTextureRef ref;
    const json* info = this->Member(material, key);
    if (!info)
    {
      return ref;
    }
    const std::string p = mp + "/" + key;
    if (!info->is_object())
    {
      this->Fail(p, "must be an object");
    }
    ref.Texture = this->Index(*info, "index", p, this->Textures.size(), "textures");
    if (ref.Texture < 0)
    {
      this->Fail(p, "'index' is missing");
    }
    ref.TexCoord = static_cast<int>(this->Number(*info, "texCoord", p, 0, 0, 65535));
    if (scaleKey)
    {
      ref.Scale =
        this->Number(*info, scaleKey, p, 1.0, std::string(scaleKey) == "strength" ? 0.0 : -1e6,
          std::string(scaleKey) == "strength" ? 1.0 : 1e6);
    }
    if (const json* ext = this->Extensions(*info, p))
    {
      for (auto it = ext->begin(); it != ext->end(); ++it)
      {
        const std::string ep = p + "/extensions/" + it.key();
        if (it.key() == "KHR_texture_transform")
        {
          const json& t = it.value();
          if (!t.is_object())
          {
            this->Fail(ep, "must be an object");
          }
          ref.HasTransform = true;
          this->Numbers(t, "offset", ep, ref.Offset, -1e6, 1e6);
          this->Numbers(t, "scale", ep, ref.UvScale, -1e6, 1e6);
          ref.Rotation = this->Number(t, "rotation", ep, 0.0, -1e6, 1e6);
          if (this->Member(t, "texCoord"))
          {
            ref.TexCoord = static_cast<int>(this->Number(t, "texCoord", ep, 0, 0, 65535));
          }
        }
        else
        {
          this->Note(ep + ": texture extension not read (ignored)");
        }
      }
    }
    const Texture& texture = this->Textures[static_cast<size_t>(ref.Texture)];
    ref.Image = texture.Image;
    ref.Sampler = texture.Sampler;
    if (ref.TexCoord > 1)
    {
      this->Note(p + ": TEXCOORD_" + std::to_string(ref.TexCoord) +
        " is not read (only _0 and _1); the texture is left out");
      ref.Image = -1;
    }
    return ref;
  }

  void ReadMaterials()
  {
    const json& materials = this->Array("materials");
    for (size_t m = 0; m < materials.size(); ++m)
    {
      const json& jm = materials[m];
      const std::string p = "/materials/" + std::to_string(m);
      GltfMaterial out;
      if (const json* name = this->Member(jm, "name"); name && name->is_string())
      {
        out.Name = name->get<std::string>();
      }
      if (const json* pbr = this->Member(jm, "pbrMetallicRoughness"))
      {
        const std::string pp = p + "/pbrMetallicRoughness";
        this->Numbers(*pbr, "baseColorFactor", pp, out.BaseColorFactor, 0, 1);
        out.MetallicFactor = this->Number(*pbr, "metallicFactor", pp, 1.0, 0, 1);
        out.RoughnessFactor = this->Number(*pbr, "roughnessFactor", pp, 1.0, 0, 1);
        out.BaseColorTexture = this->TextureInfo(*pbr, "baseColorTexture", pp, nullptr);
        out.MetallicRoughnessTexture =
          this->TextureInfo(*pbr, "metallicRoughnessTexture", pp, nullptr);
      }
      out.NormalTexture = this->TextureInfo(jm, "normalTexture", p, "scale");
      out.OcclusionTexture = this->TextureInfo(jm, "occlusionTexture", p, "strength");
      out.EmissiveTexture = this->TextureInfo(jm, "emissiveTexture", p, nullptr);
      this->Numbers(jm, "emissiveFactor", p, out.EmissiveFactor, 0, 1);
      if (const json* mode = this->Member(jm, "alphaMode"))
      {
        const std::string s = mode->is_string() ? mode->get<std::string>() : std::string();
        if (s == "OPAQUE")
        {
          out.AlphaMode = GltfAlphaMode::Opaque;
        }
        else if (s == "MASK")
        {
          out.AlphaMode = GltfAlphaMode::Mask;
        }
        else if (s == "BLEND")
        {
          out.AlphaMode = GltfAlphaMode::Blend;
        }
        else
        {
          this->Fail(p + "/alphaMode", mode->dump() + " is not OPAQUE, MASK or BLEND");
        }
      }
      out.AlphaCutoff = this->Number(jm, "alphaCutoff", p, 0.5, 0, 1e6);
      if (const json* ds = this->Member(jm, "doubleSided"))
      {
        if (!ds->is_boolean())
        {
          this->Fail(p + "/doubleSided", "must be true or false, got " + ds->dump());
        }
        out.DoubleSided = ds->get<bool>();
      }
      if (const json* ext = this->Extensions(jm, p))
      {
        for (auto it = ext->begin(); it != ext->end(); ++it)
        {
          const std::string ep = p + "/extensions/" + it.key();
          if (it.key() == "KHR_materials_unlit")
          {
            out.Unlit = true;
          }
          else if (it.key() == "KHR_materials_emissive_strength")
          {
            if (!it.value().is_object())
            {
              this->Fail(ep, "must be an object");
            }
            out.EmissiveStrength = this->Number(it.value(), "emissiveStrength", ep, 1.0, 0, 1e6);
          }
          else
          {
            out.IgnoredExtensions.push_back(it.key());
            this->Note(ep + ": material extension not drawn (ignored)");
          }
        }
      }
      this->Scene.Materials.push_back(std::move(out));
    }
  }

  const json& Root;
  GltfScene& Scene;
  const std::string& Source;
  std::vector<Texture> Textures;
};
} // namespace

void ReadMaterials(const json& root, const std::vector<std::vector<unsigned char>>& imageBytes,
  bool (*readFile)(const std::string&, std::vector<unsigned char>&, std::string&, void*),
  void* user, uint64_t maxBytes, GltfScene& scene, const std::string& source)
{
  MaterialReader reader(root, scene, source);
  reader.ReadImages(imageBytes, readFile, user, maxBytes);
  reader.ReadTextures();
  reader.ReadMaterials();
  // Optional extensions the loader does not implement.
  if (const auto used = root.find("extensionsUsed"); used != root.end() && used->is_array())
  {
    for (const auto& name : *used)
    {
      if (name.is_string() && !IsImplemented(name.get<std::string>()) &&
        name.get<std::string>().rfind("KHR_materials_", 0) != 0)
      {
        const std::string why = WhyNotImplemented(name.get<std::string>());
        reader.Note("/extensionsUsed: " + name.get<std::string>() +
          " is optional and not read (ignored" + (why.empty() ? std::string() : ": " + why) + ")");
      }
    }
  }
}
} // namespace gltfext
} // namespace morphnode
