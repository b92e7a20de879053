// SPDX-License-Identifier: BSD-3-Clause
// Images of a glTF file decoded to RGBA8 by Debian's libraries: libpng (its simplified
// API), libjpeg-turbo (TurboJPEG API) and libwebp. See GltfMaterial.h.
#include "gltf/GltfMaterial.h"

#include "base/Error.h"

#include <png.h>
#include <turbojpeg.h>
#include <webp/decode.h>

#include <cmath>
#include <cstring>

namespace morphnode
{
const char* GltfAlphaModeName(GltfAlphaMode mode)
{
  switch (mode)
  {
    case GltfAlphaMode::Mask:
      return "MASK";
    case GltfAlphaMode::Blend:
      return "BLEND";
    default:
      return "OPAQUE";
  }
}

std::array<double, 9> GltfTextureRef::UvMatrix() const
{
  const double c = std::cos(this->Rotation), s = std::sin(this->Rotation);
  const double sx = this->UvScale[0], sy = this->UvScale[1];
  // T * R * S with R = [[c, s], [-s, c]] as KHR_texture_transform defines it.
  return { { c * sx, s * sy, this->Offset[0], -s * sx, c * sy, this->Offset[1], 0, 0, 1 } };
}

namespace
{
bool TooLarge(uint64_t width, uint64_t height, uint64_t maxPixels, GltfImage& image)
{
  if (width == 0 || height == 0 || width * height > maxPixels)
  {
    image.Error = width == 0 || height == 0 ? "the image has no pixels"
                                            : "the image has " + std::to_string(width) + " x " +
        std::to_string(height) + " pixels, more than the limit of " + std::to_string(maxPixels);
    return true;
  }
  return false;
}

bool DecodePng(const unsigned char* bytes, size_t size, GltfImage& image, uint64_t maxPixels)
{
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes, size))
  {
    image.Error = std::string("PNG: ") + png.message;
    return false;
  }
  if (TooLarge(png.width, png.height, maxPixels, image))
  {
    png_image_free(&png);
    return false;
  }
  png.format = PNG_FORMAT_RGBA;
  image.Pixels.assign(PNG_IMAGE_SIZE(png), 0);
  if (!png_image_finish_read(&png, nullptr, image.Pixels.data(), 0, nullptr))
  {
    image.Error = std::string("PNG: ") + png.message;
    image.Pixels.clear();
    png_image_free(&png);
    return false;
  }
  image.Width = static_cast<int>(png.width);
  image.Height = static_cast<int>(png.height);
  image.MimeType = "image/png";
  return true;
}

bool DecodeJpeg(const unsigned char* bytes, size_t size, GltfImage& image, uint64_t maxPixels)
{
  tjhandle handle = tjInitDecompress();
  if (!handle)
  {
    image.Error = "JPEG: cannot start the decoder";
    return false;
  }
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  bool ok = tjDecompressHeader3(handle, bytes, static_cast<unsigned long>(size), &width, &height,
              &subsampling, &colorspace) == 0;
  if (!ok)
  {
    image.Error = std::string("JPEG: ") + tjGetErrorStr2(handle);
  }
  else if (TooLarge(static_cast<uint64_t>(width), static_cast<uint64_t>(height), maxPixels, image))
  {
    ok = false;
  }
  else
  {
    image.Pixels.assign(size_t(4) * static_cast<size_t>(width) * static_cast<size_t>(height), 0);
    ok = tjDecompress2(handle, bytes, static_cast<unsigned long>(size), image.Pixels.data(), width,
           0, height, TJPF_RGBA, 0) == 0;
    if (!ok)
    {
      image.Error = std::string("JPEG: ") + tjGetErrorStr2(handle);
      image.Pixels.clear();
    }
  }
  tjDestroy(handle);
  if (ok)
  {
    image.Width = width;
    image.Height = height;
    image.MimeType = "image/jpeg";
  }
  return ok;
}

bool DecodeWebp(const unsigned char* bytes, size_t size, GltfImage& image, uint64_t maxPixels)
{
  int width = 0, height = 0;
  if (!WebPGetInfo(bytes, size, &width, &height))
  {
    image.Error = "WebP: not a WebP image libwebp can read";
    return false;
  }
  if (TooLarge(static_cast<uint64_t>(width), static_cast<uint64_t>(height), maxPixels, image))
  {
    return false;
  }
  image.Pixels.assign(size_t(4) * static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  if (!WebPDecodeRGBAInto(bytes, size, image.Pixels.data(), image.Pixels.size(), 4 * width))
  {
    image.Error = "WebP: the image data cannot be decoded";
    image.Pixels.clear();
    return false;
  }
  image.Width = width;
  image.Height = height;
  image.MimeType = "image/webp";
  return true;
}
} // namespace

bool GltfDecodeImage(const unsigned char* bytes, size_t size, GltfImage& image, uint64_t maxPixels)
{
  image.Pixels.clear();
  image.Error.clear();
  image.Width = image.Height = 0;
  static const unsigned char png[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
  if (size >= 8 && std::memcmp(bytes, png, 8) == 0)
  {
    return DecodePng(bytes, size, image, maxPixels);
  }
  if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff)
  {
    return DecodeJpeg(bytes, size, image, maxPixels);
  }
  if (size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0)
  {
    return DecodeWebp(bytes, size, image, maxPixels);
  }
  if (size >= 12 && std::memcmp(bytes, "\xabKTX 20\xbb", 8) == 0)
  {
    image.Error = "KTX2 (KHR_texture_basisu): Debian 12 has no KTX2 / Basis Universal decoder";
    return false;
  }
  image.Error = "neither PNG, JPEG nor WebP";
  return false;
}

std::vector<uint8_t> GltfEncodePng(const GltfImage& image)
{
  if (image.Width <= 0 || image.Height <= 0 ||
    image.Pixels.size() != 4 * static_cast<size_t>(image.Width) * static_cast<size_t>(image.Height))
  {
    throw InputError("PNG encoding: the image '" + image.Name + "' has no decoded pixels");
  }
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.Width);
  png.height = static_cast<png_uint_32>(image.Height);
  png.format = PNG_FORMAT_RGBA;
  // First call: the size; second: the bytes (libpng's simplified API).
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.Pixels.data(), 0, nullptr))
  {
    throw InputError(std::string("PNG encoding: ") + png.message);
  }
  std::vector<uint8_t> bytes(size);
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.Pixels.data(), 0, nullptr))
  {
    throw InputError(std::string("PNG encoding: ") + png.message);
  }
  bytes.resize(size);
  return bytes;
}
} // namespace morphnode
