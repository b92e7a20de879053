// SPDX-License-Identifier: BSD-3-Clause
// glTF alpha modes as MorphNode draws them (vtkMorphTargetReader's material fields,
// AppKit/HeadActors), on a small file written here, read back and rendered from the front:
//   - MASK: a 4 x 1 texture whose texels have alpha 0.2, 0.45, 0.55 and 0.9 under a cutoff
//     of 0.5: the first two are dropped (the background shows), the last two kept (blue);
//     with the cutoff at 0.7 only the last is kept.
//   - BLEND: a green half-transparent quad in front of an opaque red one, listed FIRST in
//     the file: it is drawn after the opaque part (depth peeling), so the overlap mixes
//     green and red; where it does not overlap the red, it mixes with the background.
//   - unlit: a quad with KHR_materials_unlit shows its base colour texture unshaded.
//   - normal map: a grey quad lit from the front, with and without a normal texture whose
//     one texel tilts the normal by about 75 degrees: with it the quad is much darker (so
//     the normal texture is drawn, which VTK does only with tangents) and its drawn part
//     carries Tangents; a separate occlusion texture lands in the R channel of VTK's ORM
//     texture beside the metallic-roughness texture's G and B.
// Run under `xvfb-run -a`.
#include "HeadActors.h"

#include "Core/gltf/GltfTestFiles.h"
#include "vtkMorphTargetReader.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkMapper.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <string>
#include <zlib.h>

using gltftest::Builder;
using gltftest::json;

namespace
{
const std::string Output = MORPHNODE_TEST_OUTPUT_DIR;
constexpr int Size = 200;

/// An RGBA PNG of `width` x 1 pixels (zlib from the system; PNG's chunks are simple).
std::vector<unsigned char> Png(const std::vector<std::array<unsigned char, 4>>& pixels)
{
  auto be32 = [](std::vector<unsigned char>& out, uint32_t v)
  {
    for (int i = 3; i >= 0; --i)
    {
      out.push_back(static_cast<unsigned char>(v >> (8 * i)));
    }
  };
  auto chunk =
    [&](std::vector<unsigned char>& out, const char* type, const std::vector<unsigned char>& data)
  {
    be32(out, static_cast<uint32_t>(data.size()));
    std::vector<unsigned char> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    out.insert(out.end(), body.begin(), body.end());
    be32(out, static_cast<uint32_t>(crc32(0, body.data(), static_cast<uInt>(body.size()))));
  };
  std::vector<unsigned char> png = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
  std::vector<unsigned char> header;
  be32(header, static_cast<uint32_t>(pixels.size()));
  be32(header, 1);
  header.insert(header.end(), { 8, 6, 0, 0, 0 });
  chunk(png, "IHDR", header);
  std::vector<unsigned char> raw = { 0 };
  for (const auto& p : pixels)
  {
    raw.insert(raw.end(), p.begin(), p.end());
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<unsigned char> packed(size);
  compress(packed.data(), &size, raw.data(), static_cast<uLong>(raw.size()));
  packed.resize(size);
  chunk(png, "IDAT", packed);
  chunk(png, "IEND", {});
  return png;
}

/// A quad from (x0, y0) to (x1, y1) at depth z, with UVs 0..1 left to right.
json Quad(Builder& b, float x0, float y0, float x1, float y1, float z, int material)
{
  const int p = b.Vec3({ x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z });
  const int n = b.Vec3({ 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 });
  const int uv = b.Floats({ 0, 1, 1, 1, 1, 0, 0, 0 }, "VEC2", 2);
  const int i = b.Indices({ 0, 1, 2, 0, 2, 3 });
  return { { "attributes", { { "POSITION", p }, { "NORMAL", n }, { "TEXCOORD_0", uv } } },
    { "indices", i }, { "material", material } };
}

/// The scene: node "Glass" (BLEND, listed first), "Wall" (opaque red), "Cutout" (MASK),
/// "Sign" (unlit, textured).
std::string WriteScene(double cutoff)
{
  Builder b;
  const int texture =
    b.View(Png({ { 0, 0, 255, 51 }, { 0, 0, 255, 115 }, { 0, 0, 255, 140 }, { 0, 0, 255, 230 } }));
  const int sign = b.View(Png({ { 255, 255, 0, 255 } }));
  b.Doc["images"] = { { { "bufferView", texture }, { "mimeType", "image/png" } },
    { { "bufferView", sign }, { "mimeType", "image/png" } } };
  b.Doc["samplers"] = { { { "magFilter", 9728 }, { "minFilter", 9728 } } };
  b.Doc["textures"] = { { { "source", 0 }, { "sampler", 0 } },
    { { "source", 1 }, { "sampler", 0 } } };
  b.Doc["materials"] = { { { "name", "Glass" },
                           { "pbrMetallicRoughness",
                             { { "baseColorFactor", { 0, 1, 0, 0.5 } }, { "metallicFactor", 0 } } },
                           { "alphaMode", "BLEND" } },
    { { "name", "Wall" },
      { "pbrMetallicRoughness",
        { { "baseColorFactor", { 1, 0, 0, 1 } }, { "metallicFactor", 0 } } } },
    { { "name", "Cutout" },
      { "pbrMetallicRoughness",
        { { "baseColorTexture", { { "index", 0 } } }, { "metallicFactor", 0 } } },
      { "alphaMode", "MASK" }, { "alphaCutoff", cutoff } },
    { { "name", "Sign" },
      { "pbrMetallicRoughness", { { "baseColorTexture", { { "index", 1 } } } } },
      { "extensions", { { "KHR_materials_unlit", json::object() } } } } };
  b.Doc["extensionsUsed"] = { "KHR_materials_unlit" };
  // Glass covers x -0.9..-0.1, y 0.1..0.9, in front; the wall x -0.9..-0.5 behind it.
  b.Mesh({ { "primitives", { Quad(b, -0.9f, 0.1f, -0.1f, 0.9f, 0.2f, 0) } } });
  b.Mesh({ { "primitives", { Quad(b, -0.9f, 0.1f, -0.5f, 0.9f, 0.0f, 1) } } });
  b.Mesh({ { "primitives", { Quad(b, 0.1f, 0.1f, 0.9f, 0.9f, 0.0f, 2) } } });
  b.Mesh({ { "primitives", { Quad(b, 0.1f, -0.9f, 0.9f, -0.1f, 0.0f, 3) } } });
  b.Doc["nodes"] = { { { "name", "Glass" }, { "mesh", 0 } }, { { "name", "Wall" }, { "mesh", 1 } },
    { { "name", "Cutout" }, { "mesh", 2 } }, { { "name", "Sign" }, { "mesh", 3 } } };
  b.Doc["scenes"] = { { { "nodes", { 0, 1, 2, 3 } } } };
  const std::string file = Output + "/TestMaterialAlpha.glb";
  const std::string bytes = b.Glb();
  std::ofstream(file, std::ios::binary)
    .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return file;
}

struct Frame
{
  vtkNew<vtkImageData> Image;
  std::array<int, 3> At(double x, double y) const // scene coordinates in [-1, 1]
  {
    const int i = static_cast<int>((x + 1) / 2 * Size), j = static_cast<int>((y + 1) / 2 * Size);
    auto* rgb = vtkUnsignedCharArray::SafeDownCast(this->Image->GetPointData()->GetScalars());
    const vtkIdType k = static_cast<vtkIdType>(j) * Size + i;
    return { rgb->GetValue(3 * k), rgb->GetValue(3 * k + 1), rgb->GetValue(3 * k + 2) };
  }
};

/// One grey quad over the whole view with an occlusion texture (R 40) and a
/// metallic-roughness texture (G 200, B 10); with `normalMap` also a normal texture (one
/// texel (230, 128, 150): the tangent-space normal (0.8, 0, 0.18), tilted towards +u).
std::string WriteBumpyScene(bool normalMap)
{
  Builder b;
  json material = { { "name", "Bumpy" },
    { "pbrMetallicRoughness",
      { { "baseColorFactor", { 0.5, 0.5, 0.5, 1 } }, { "metallicFactor", 0 } } } };
  const int normal = b.View(Png({ { 230, 128, 150, 255 } }));
  const int occlusion = b.View(Png({ { 40, 0, 0, 255 } }));
  const int mr = b.View(Png({ { 0, 200, 10, 255 } }));
  b.Doc["images"] = { { { "bufferView", normal }, { "mimeType", "image/png" } },
    { { "bufferView", occlusion }, { "mimeType", "image/png" } },
    { { "bufferView", mr }, { "mimeType", "image/png" } } };
  b.Doc["samplers"] = { { { "magFilter", 9728 }, { "minFilter", 9728 } } };
  b.Doc["textures"] = { { { "source", 0 }, { "sampler", 0 } },
    { { "source", 1 }, { "sampler", 0 } }, { { "source", 2 }, { "sampler", 0 } } };
  if (normalMap)
  {
    material["normalTexture"] = { { "index", 0 } };
  }
  material["occlusionTexture"] = { { "index", 1 }, { "strength", 0.75 } };
  material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = { { "index", 2 } };
  b.Doc["materials"] = { material };
  b.Mesh({ { "primitives", { Quad(b, -1.0f, -1.0f, 1.0f, 1.0f, 0.0f, 0) } } });
  b.Doc["nodes"] = { { { "name", "Bumpy" }, { "mesh", 0 } } };
  b.Doc["scenes"] = { { { "nodes", { 0 } } } };
  const std::string file =
    Output + (normalMap ? "/TestMaterialNormalMap.glb" : "/TestMaterialNoNormalMap.glb");
  const std::string bytes = b.Glb();
  std::ofstream(file, std::ios::binary)
    .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return file;
}

/// What the test looks at in the drawn parts besides the frame.
struct Drawn
{
  bool Tangents = false;                       // the first part's drawn copy has point Tangents
  std::array<int, 4> Orm = { -1, -1, -1, -1 }; // first texel of its ORM texture, channels
};

std::unique_ptr<Frame> Render(const std::string& file, int parts, Drawn* drawn = nullptr)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  window->SetSize(Size, Size);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  window->AddRenderer(renderer);
  morphnode::appkit::HeadActors head;
  EXPECT_TRUE(head.Build(reader->GetOutputDataObject(0), renderer, nullptr));
  EXPECT_EQ(head.GetNumberOfParts(), parts);
  if (drawn && head.GetNumberOfParts() > 0)
  {
    vtkActor* actor = head.GetActor(0);
    drawn->Tangents = actor->GetMapper()->GetInput()->GetPointData()->GetTangents() != nullptr;
    const auto& textures = actor->GetProperty()->GetAllTextures();
    const auto orm = textures.find("materialTex");
    if (orm != textures.end())
    {
      auto* image = vtkImageData::SafeDownCast(orm->second->GetInputDataObject(0, 0));
      const int n = image ? image->GetNumberOfScalarComponents() : 0;
      for (int c = 0; c < n && c < 4; ++c)
      {
        drawn->Orm[c] = static_cast<int>(image->GetScalarComponentAsDouble(0, 0, 0, c));
      }
    }
  }
  renderer->SetBackground(0, 0, 0);
  renderer->SetUseDepthPeeling(true);
  renderer->RemoveAllLights();
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPositional(false);
  light->SetPosition(0, 0, 5);
  light->SetFocalPoint(0, 0, 0);
  light->SetIntensity(3.14159);
  renderer->AddLight(light);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetParallelScale(1.0);
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 1, 0);
  renderer->ResetCameraClippingRange();
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  auto frame = std::make_unique<Frame>();
  frame->Image->DeepCopy(grab->GetOutput());
  return frame;
}

std::unique_ptr<Frame> Render(double cutoff)
{
  return Render(WriteScene(cutoff), 4);
}

std::string Text(const std::array<int, 3>& c)
{
  return "(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) +
    ")";
}

bool Dark(const std::array<int, 3>& c)
{
  return c[0] < 20 && c[1] < 20 && c[2] < 20;
}

bool Blue(const std::array<int, 3>& c)
{
  return c[2] > 150 && c[0] < 60 && c[1] < 60; // blue, with a little white highlight
}
} // namespace

TEST(MaterialAlpha, MaskCutoffKeepsAndDropsTheRightTexels)
{
  auto frame = Render(0.5);
  // The cutout quad spans x 0.1..0.9: texel k covers x 0.1 + 0.2 k .. 0.3 + 0.2 k.
  const double texel[4] = { 0.2, 0.4, 0.6, 0.8 };
  EXPECT_TRUE(Dark(frame->At(texel[0], 0.5)))
    << "alpha 0.2 kept: " << Text(frame->At(texel[0], 0.5));
  EXPECT_TRUE(Dark(frame->At(texel[1], 0.5)))
    << "alpha 0.45 kept: " << Text(frame->At(texel[1], 0.5));
  EXPECT_TRUE(Blue(frame->At(texel[2], 0.5)))
    << "alpha 0.55 dropped: " << Text(frame->At(texel[2], 0.5));
  EXPECT_TRUE(Blue(frame->At(texel[3], 0.5)))
    << "alpha 0.9 dropped: " << Text(frame->At(texel[3], 0.5));
  // Another cutoff moves the edge: 0.7 keeps only the last texel.
  auto higher = Render(0.7);
  EXPECT_TRUE(Dark(higher->At(texel[2], 0.5)))
    << "alpha 0.55 kept at cutoff 0.7: " << Text(higher->At(texel[2], 0.5));
  EXPECT_TRUE(Blue(higher->At(texel[3], 0.5))) << Text(higher->At(texel[3], 0.5));
}

TEST(MaterialAlpha, BlendIsDrawnAfterTheOpaqueParts)
{
  auto frame = Render(0.5);
  const auto overlap = frame->At(-0.7, 0.5);   // glass in front of the wall
  const auto glassOnly = frame->At(-0.3, 0.5); // glass in front of the background
  const auto wall = frame->At(-0.7, -0.5);     // nothing there: background
  std::cout << "glass over wall " << Text(overlap) << ", glass alone " << Text(glassOnly) << "\n";
  // Half green over red: both show. Had the glass been drawn first and written its depth,
  // the wall behind it would be missing (green only); drawn opaque, red would be hidden.
  EXPECT_GT(overlap[0], 60) << Text(overlap);
  EXPECT_GT(overlap[1], 60) << Text(overlap);
  EXPECT_LT(glassOnly[0], 20) << Text(glassOnly);
  EXPECT_GT(glassOnly[1], 60) << Text(glassOnly);
  EXPECT_LT(glassOnly[1], overlap[1] + 60); // half green over black
  EXPECT_TRUE(Dark(wall)) << Text(wall);
}

TEST(MaterialAlpha, UnlitShowsItsTexture)
{
  auto frame = Render(0.5);
  const auto sign = frame->At(0.5, -0.5);
  // The yellow texel as it is (no shading): red and green full, blue none.
  EXPECT_GT(sign[0], 240) << Text(sign);
  EXPECT_GT(sign[1], 240) << Text(sign);
  EXPECT_LT(sign[2], 20) << Text(sign);
}

TEST(MaterialNormalMap, NormalTextureTiltsTheShading)
{
  Drawn plain, bumpy;
  auto flat = Render(WriteBumpyScene(false), 1, &plain);
  auto tilted = Render(WriteBumpyScene(true), 1, &bumpy);
  const auto a = flat->At(0.0, 0.0), b = tilted->At(0.0, 0.0);
  std::cout << "without normal texture " << Text(a) << ", with " << Text(b) << "\n";
  EXPECT_FALSE(plain.Tangents) << "tangents for a part without a normal texture";
  EXPECT_TRUE(bumpy.Tangents) << "no Tangents on the part with a normal texture";
  // Lit head-on, the untilted quad is bright; the normal tilted by ~75 degrees turns it away
  // from the light (N.L about 0.2): without the normal texture drawn both frames are equal.
  EXPECT_GT(a[0], 60) << Text(a);
  EXPECT_GT(a[0] - b[0], 40) << "normal texture not drawn: " << Text(a) << " vs " << Text(b);
  // Occlusion R (40), roughness G (200), metallic B (10) in one ORM texture.
  EXPECT_EQ(plain.Orm[0], 40);
  EXPECT_EQ(bumpy.Orm[0], 40);
  EXPECT_EQ(bumpy.Orm[1], 200);
  EXPECT_EQ(bumpy.Orm[2], 10);
}
