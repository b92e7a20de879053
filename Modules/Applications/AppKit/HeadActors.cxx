// SPDX-License-Identifier: BSD-3-Clause
#include "HeadActors.h"

#include "vtkMorphPartData.h"
#include "vtkMorphSkinMapper.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkLightKit.h"
#include "vtkLinearTransform.h"
#include "vtkMath.h"
#include "vtkOpenGLRenderer.h"
#include "vtkPBRIrradianceTexture.h"
#include "vtkPBRLUTTexture.h"
#include "vtkPBRPrefilterTexture.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataTangents.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

namespace morphnode
{
namespace appkit
{
namespace
{
namespace partdata = vtkMorphPartData;

const char* const DisplayColors = "DisplayColors";

/// The part's linear RGBA from field data BaseColor (4 values); skin without a material.
std::array<double, 4> PartColor(vtkPolyData* part)
{
  vtkFieldData* fd = part->GetFieldData();
  const std::vector<double> base = partdata::GetNumbers(fd, partdata::BaseColorArray);
  if (base.size() < 3 || partdata::GetString(fd, partdata::MaterialNameArray).empty())
  {
    return { SkinColor[0], SkinColor[1], SkinColor[2], 1.0 };
  }
  std::array<double, 4> rgba{ 1, 1, 1, 1 };
  for (size_t k = 0; k < std::min<size_t>(4, base.size()); ++k)
  {
    const double v = base[k];
    rgba[k] = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0;
  }
  return rgba;
}

/// COLOR_0 times the base colour, as RGB bytes; null when the part has no COLOR_0.
vtkSmartPointer<vtkUnsignedCharArray> PointColors(
  vtkPolyData* part, const std::array<double, 4>& base)
{
  vtkDataArray* color = part->GetPointData()->GetArray("COLOR_0");
  if (!color || color->GetNumberOfComponents() < 3 ||
    color->GetNumberOfTuples() != part->GetNumberOfPoints())
  {
    return nullptr;
  }
  // Unsigned char (0-255) as the reader gives it, or normalized floats.
  const double scale = vtkUnsignedCharArray::SafeDownCast(color) ? 1.0 / 255.0 : 1.0;
  auto rgb = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgb->SetName(DisplayColors);
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(color->GetNumberOfTuples());
  for (vtkIdType i = 0; i < color->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      const double v = color->GetComponent(i, k) * scale * base[k];
      rgb->SetValue(
        3 * i + k, static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)));
    }
  }
  return rgb;
}
/// Value `component` of a numeric part field, `fallback` when absent, too short or not
/// finite (drawing is lenient: another pipeline may have set these).
double FieldNumber(vtkPolyData* part, const std::string& name, size_t component, double fallback)
{
  const std::vector<double> values = partdata::GetNumbers(part->GetFieldData(), name.c_str());
  return component < values.size() && std::isfinite(values[component]) ? values[component]
                                                                       : fallback;
}

std::string FieldString(vtkPolyData* part, const char* name)
{
  return partdata::GetString(part->GetFieldData(), name);
}

/// The texture of field data `<name>Image` (see vtkMorphTargetReader: RGBA rows top first,
/// which VTK's t = 0 samples as glTF's v = 0), with its sampler's filters and wraps; null
/// when the part has none. `mode`: "OPAQUE" drops alpha (so that the part stays in the
/// opaque pass), "MASK" makes alpha 0 or 1 at the cutoff (glTF's alpha test, drawn by the
/// translucent pass without blending artefacts), "BLEND" keeps it; `factor` multiplies
/// the alpha first (baseColorFactor's alpha).
vtkSmartPointer<vtkTexture> PartTexture(vtkPolyData* part, const std::string& name, bool srgb,
  const std::string& mode = "BLEND", double cutoff = 0.5, double factor = 1.0)
{
  auto* pixels = vtkUnsignedCharArray::SafeDownCast(
    part->GetFieldData()->GetArray(partdata::ImageArray(name).c_str()));
  // Sizes from field data another pipeline may have set: within int before the cast.
  auto size = [&](size_t k)
  {
    const double v = FieldNumber(part, partdata::ImageSizeArray(name), k, 0);
    return v >= 1 && v <= 65536 ? static_cast<int>(v) : 0;
  };
  const int width = size(0), height = size(1);
  if (!pixels || pixels->GetNumberOfComponents() != 4 || width <= 0 || height <= 0 ||
    pixels->GetNumberOfTuples() != vtkIdType(width) * height)
  {
    return nullptr;
  }
  vtkNew<vtkImageData> image;
  image->SetDimensions(width, height, 1);
  const int components = mode == "OPAQUE" ? 3 : 4;
  image->AllocateScalars(VTK_UNSIGNED_CHAR, components);
  const unsigned char* in = pixels->GetPointer(0);
  auto* out = static_cast<unsigned char*>(image->GetScalarPointer());
  for (vtkIdType i = 0; i < pixels->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      out[components * i + c] = in[4 * i + c];
    }
    if (components == 4)
    {
      const double alpha = in[4 * i + 3] / 255.0 * factor;
      out[4 * i + 3] = mode == "MASK"
        ? (alpha >= cutoff ? 255 : 0)
        : static_cast<unsigned char>(std::lround(std::clamp(alpha, 0.0, 1.0) * 255));
    }
  }
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(image);
  texture->SetUseSRGBColorSpace(srgb);
  auto sampler = [&](size_t k, double fallback)
  {
    const double v = FieldNumber(part, partdata::SamplerArray(name), k, fallback);
    return v >= 0 && v <= 65535 ? static_cast<int>(v) : static_cast<int>(fallback);
  };
  const int mag = sampler(0, 0), min = sampler(1, 0), wrap = sampler(2, 10497);
  texture->SetInterpolate(mag != 9728); // NEAREST only when the file asks for it
  texture->SetMipmap(min == 0 || min >= 9984);
  texture->SetRepeat(wrap != 33071);
  texture->SetEdgeClamp(wrap == 33071);
  return texture;
}

/// VTK's ORM texture (R occlusion, G roughness, B metallic) from glTF's separate occlusion
/// texture (its R) and metallic-roughness texture (its G and B), which VTK 9.1 cannot take
/// apart: one image when both have the same size, else the metallic-roughness one alone
/// (R is then set to 255, no occlusion). Null when the part has neither.
vtkSmartPointer<vtkTexture> OrmTexture(vtkPolyData* part)
{
  auto mr = PartTexture(part, partdata::MetallicRoughnessSlot, false, "OPAQUE");
  auto occlusion = PartTexture(part, partdata::OcclusionSlot, false, "OPAQUE");
  if (!occlusion && !mr)
  {
    return nullptr;
  }
  vtkSmartPointer<vtkTexture> orm = mr ? mr : occlusion;
  auto* image = vtkImageData::SafeDownCast(orm->GetInputDataObject(0, 0));
  auto* other =
    occlusion && mr ? vtkImageData::SafeDownCast(occlusion->GetInputDataObject(0, 0)) : nullptr;
  int dims[3], otherDims[3] = { 0, 0, 0 };
  image->GetDimensions(dims);
  if (other)
  {
    other->GetDimensions(otherDims);
  }
  const bool combine = other && dims[0] == otherDims[0] && dims[1] == otherDims[1];
  auto* rgb = static_cast<unsigned char*>(image->GetScalarPointer());
  const auto* ao = combine ? static_cast<const unsigned char*>(other->GetScalarPointer()) : nullptr;
  for (vtkIdType i = 0; i < vtkIdType(dims[0]) * dims[1]; ++i)
  {
    if (!occlusion)
    {
      rgb[3 * i] = 255; // R is not occlusion in a metallic-roughness image
    }
    else if (!mr)
    {
      rgb[3 * i + 1] = rgb[3 * i + 2] = 255; // the factors alone
    }
    else
    {
      rgb[3 * i] = combine ? ao[3 * i] : 255;
    }
  }
  return orm;
}

/// Tangents (vtkPolyDataTangents: per triangle from positions and texture coordinates,
/// averaged at the points) for a part whose material has a normal texture; null when it has no
/// normal texture, no normals, no texture coordinates, or cells other than triangles (the
/// filter takes triangles only; glTF parts are). Computed once on the
/// part as Build sees it and kept for later frames: morph targets move the points a little
/// and the shader orthogonalizes the tangent against the current normal.
vtkSmartPointer<vtkDataArray> PartTangents(vtkPolyData* part)
{
  if (!part->GetFieldData()->GetArray(partdata::ImageArray(partdata::NormalSlot).c_str()) ||
    !part->GetPointData()->GetTCoords() || !part->GetPointData()->GetNormals() ||
    part->GetNumberOfPolys() == 0 || part->GetPolys()->GetMaxCellSize() != 3 ||
    part->GetNumberOfStrips() > 0)
  {
    return nullptr;
  }
  vtkNew<vtkPolyData> copy;
  copy->ShallowCopy(part);
  vtkNew<vtkPolyDataTangents> tangents;
  tangents->SetInputData(copy);
  tangents->ComputePointTangentsOn();
  tangents->ComputeCellTangentsOff();
  tangents->Update();
  vtkDataArray* result = tangents->GetOutput()->GetPointData()->GetTangents();
  if (!result || result->GetNumberOfTuples() != part->GetNumberOfPoints())
  {
    return nullptr;
  }
  return result;
}

/// Draws the part's glTF material (field data from vtkMorphTargetReader, docs/materials.md)
/// with VTK 9.1's PBR: base colour (sRGB texture times factor), metallic and roughness
/// (factors, and the ORM texture), normal and emissive textures, alpha modes, back faces
/// culled unless double-sided, unlit as flat ambient colour. False when the part has no
/// material fields (the classic look stays).
bool ApplyMaterial(
  vtkPolyData* part, vtkActor* actor, const std::array<double, 4>& color, bool tangents)
{
  vtkProperty* property = actor->GetProperty();
  if (!part->GetFieldData()->GetArray(partdata::MetallicFactorArray))
  {
    return false;
  }
  const std::string mode = FieldString(part, partdata::AlphaModeArray);
  const double cutoff = FieldNumber(part, partdata::AlphaCutoffArray, 0, 0.5);
  const bool textured = part->GetPointData()->GetTCoords() != nullptr;
  property->SetInterpolationToPBR();
  property->SetColor(color[0], color[1], color[2]);
  property->SetMetallic(FieldNumber(part, partdata::MetallicFactorArray, 0, 1.0));
  property->SetRoughness(FieldNumber(part, partdata::RoughnessFactorArray, 0, 1.0));
  property->SetEmissiveFactor(FieldNumber(part, partdata::EmissiveFactorArray, 0, 0),
    FieldNumber(part, partdata::EmissiveFactorArray, 1, 0),
    FieldNumber(part, partdata::EmissiveFactorArray, 2, 0));
  property->SetBackfaceCulling(FieldNumber(part, partdata::DoubleSidedArray, 0, 0) == 0);

  // Opacity: BLEND takes the factor's alpha; MASK and OPAQUE draw whole where they draw.
  property->SetOpacity(mode == "BLEND" ? color[3] : 1.0);
  if (textured)
  {
    if (auto base = PartTexture(part, partdata::BaseColorSlot, true, mode.empty() ? "OPAQUE" : mode,
          cutoff, mode == "BLEND" ? 1.0 : color[3]))
    {
      property->SetBaseColorTexture(base);
    }
    if (auto orm = OrmTexture(part))
    {
      property->SetORMTexture(orm);
      property->SetOcclusionStrength(FieldNumber(part, partdata::OcclusionStrengthArray, 0, 0.0));
    }
    // A normal map needs tangents: PartTangents gives the drawn copy of the part its own.
    auto normal = tangents ? PartTexture(part, partdata::NormalSlot, false, "OPAQUE") : nullptr;
    if (normal)
    {
      property->SetNormalTexture(normal);
      property->SetNormalScale(FieldNumber(part, partdata::NormalScaleArray, 0, 1.0));
    }
    if (auto emissive = PartTexture(part, partdata::EmissiveSlot, true, "OPAQUE"))
    {
      property->SetEmissiveTexture(emissive);
    }
  }
  else if (mode == "MASK" && color[3] < cutoff)
  {
    property->SetOpacity(0.0); // the whole part falls below the cutoff
  }
  if (FieldNumber(part, partdata::UnlitArray, 0, 0) != 0)
  {
    // KHR_materials_unlit: the base colour as it is. VTK's PBR has no unlit mode and its
    // base colour texture works only with PBR, so the classic path draws it, the texture
    // as the actor's.
    property->SetInterpolationToFlat();
    property->LightingOff();
    const auto& textures = property->GetAllTextures();
    const auto albedo = textures.find("albedoTex");
    if (albedo != textures.end())
    {
      actor->SetTexture(albedo->second);
    }
    property->RemoveAllTextures();
  }
  return true;
}
} // namespace

struct HeadActors::Part
{
  vtkNew<vtkPolyData> Display;
  vtkSmartPointer<vtkPolyDataMapper> Mapper; ///< plain, or vtkMorphSkinMapper (SkinOnGpu)
  vtkNew<vtkActor> Actor;
  vtkSmartPointer<vtkUnsignedCharArray> Colors; // COLOR_0 x BaseColor, or null
  vtkSmartPointer<vtkDataArray> Tangents;       // for a normal texture (PartTangents), or null
  vtkIdType Points = 0;
  std::string Name;
  std::array<double, 4> Color = { 1, 1, 1, 1 };
  /// A morph filter's mesh levels (point data OriginalPointId, docs/lod.md): the part's
  /// point count changes with its level; its colours and tangents per level, made at the
  /// level's first frame.
  std::map<vtkIdType,
    std::pair<vtkSmartPointer<vtkUnsignedCharArray>, vtkSmartPointer<vtkDataArray>>>
    ByLevel;

  void Take(vtkPolyData* part)
  {
    if (part->GetNumberOfPoints() != this->Points)
    {
      // Another level of the part: its own colours and tangents.
      this->ByLevel[this->Points] = { this->Colors, this->Tangents };
      this->Points = part->GetNumberOfPoints();
      auto found = this->ByLevel.find(this->Points);
      if (found != this->ByLevel.end())
      {
        std::tie(this->Colors, this->Tangents) = found->second;
      }
      else
      {
        this->Colors = this->Colors ? PointColors(part, this->Color) : nullptr;
        this->Tangents = this->Tangents ? PartTangents(part) : nullptr;
      }
    }
    // Our own copy of the arrays' list: the colours added here never reach the filter's output.
    this->Display->ShallowCopy(part);
    if (this->Colors)
    {
      this->Display->GetPointData()->AddArray(this->Colors);
    }
    if (this->Tangents)
    {
      this->Display->GetPointData()->SetTangents(this->Tangents);
    }
  }

  void ShowOwnColors()
  {
    this->Mapper->SetLookupTable(nullptr);
    if (this->Colors)
    {
      this->Mapper->SetScalarModeToUsePointFieldData();
      this->Mapper->SelectColorArray(DisplayColors);
      this->Mapper->SetColorModeToDirectScalars();
      this->Mapper->ScalarVisibilityOn();
    }
    else
    {
      this->Mapper->ScalarVisibilityOff();
    }
  }
};

std::vector<vtkPolyData*> HeadParts(vtkDataObject* head)
{
  std::vector<vtkPolyData*> parts;
  if (auto* poly = vtkPolyData::SafeDownCast(head))
  {
    parts.push_back(poly);
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(head))
  {
    for (vtkDataObject* node : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      if (auto* leaf = vtkPolyData::SafeDownCast(node))
      {
        parts.push_back(leaf);
      }
    }
  }
  return parts;
}

bool HeadBounds(vtkDataObject* head, double bounds[6])
{
  bool any = false;
  for (int k = 0; k < 3; ++k)
  {
    bounds[2 * k] = std::numeric_limits<double>::max();
    bounds[2 * k + 1] = std::numeric_limits<double>::lowest();
  }
  for (vtkPolyData* part : HeadParts(head))
  {
    if (part->GetNumberOfPoints() == 0)
    {
      continue;
    }
    double b[6];
    part->GetBounds(b);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
    }
    any = true;
  }
  if (!any)
  {
    for (int k = 0; k < 6; ++k)
    {
      bounds[k] = k % 2 ? 1.0 : 0.0;
    }
  }
  return any;
}

HeadActors::HeadActors() = default;
HeadActors::~HeadActors() = default;

bool HeadActors::Build(vtkDataObject* head, vtkRenderer* renderer, vtkLinearTransform* pose)
{
  const std::vector<vtkPolyData*> parts = HeadParts(head);
  vtkIdType points = 0;
  for (vtkPolyData* part : parts)
  {
    points += part->GetNumberOfPoints();
  }
  if (points == 0)
  {
    return false;
  }
  for (vtkPolyData* input : parts)
  {
    auto part = std::make_unique<Part>();
    part->Mapper = this->SkinOnGpu
      ? vtkSmartPointer<vtkPolyDataMapper>(vtkSmartPointer<vtkMorphSkinMapper>::New())
      : vtkSmartPointer<vtkPolyDataMapper>::New();
    const std::array<double, 4> color = PartColor(input);
    part->Colors = PointColors(input, color);
    part->Color = color;
    part->Points = input->GetNumberOfPoints();
    part->Name = partdata::GetPartName(input->GetFieldData());
    part->Tangents = PartTangents(input);
    part->Take(input);
    part->Mapper->SetInputData(part->Display);
    part->ShowOwnColors();
    part->Actor->SetMapper(part->Mapper);
    if (pose)
    {
      part->Actor->SetUserTransform(pose);
    }
    vtkProperty* property = part->Actor->GetProperty();
    if (!ApplyMaterial(input, part->Actor, color, part->Tangents != nullptr))
    {
      property->SetColor(color[0], color[1], color[2]);
      property->SetOpacity(color[3]);
      property->SetAmbient(0.08);
      property->SetDiffuse(0.92);
      property->SetSpecular(0.15);
      property->SetSpecularPower(20.0);
    }
    renderer->AddActor(part->Actor);
    this->Parts.push_back(std::move(part));
  }
  return true;
}

bool HeadActors::Update(vtkDataObject* head)
{
  const std::vector<vtkPolyData*> parts = HeadParts(head);
  if (parts.size() != this->Parts.size())
  {
    return false;
  }
  for (size_t i = 0; i < parts.size(); ++i)
  {
    // A part at another mesh level (OriginalPointId) is the same part.
    if (parts[i]->GetNumberOfPoints() != this->Parts[i]->Points &&
      !parts[i]->GetPointData()->GetArray("OriginalPointId"))
    {
      return false;
    }
  }
  for (size_t i = 0; i < parts.size(); ++i)
  {
    this->Parts[i]->Take(parts[i]);
  }
  return true;
}

bool HeadActors::ColorBy(const std::string& array, vtkScalarsToColors* lut, double range[2])
{
  range[0] = std::numeric_limits<double>::max();
  range[1] = std::numeric_limits<double>::lowest();
  for (const auto& part : this->Parts)
  {
    if (vtkDataArray* scalars = part->Display->GetPointData()->GetArray(array.c_str()))
    {
      double r[2];
      scalars->GetRange(r);
      range[0] = std::min(range[0], r[0]);
      range[1] = std::max(range[1], r[1]);
    }
  }
  if (range[0] > range[1])
  {
    range[0] = 0.0;
    range[1] = 1.0;
    return false;
  }
  for (const auto& part : this->Parts)
  {
    if (!part->Display->GetPointData()->GetArray(array.c_str()))
    {
      part->ShowOwnColors();
      continue;
    }
    part->Mapper->SetScalarModeToUsePointFieldData();
    part->Mapper->SelectColorArray(array.c_str());
    part->Mapper->SetColorModeToMapScalars();
    part->Mapper->SetLookupTable(lut);
    part->Mapper->UseLookupTableScalarRangeOff();
    part->Mapper->SetScalarRange(range);
    part->Mapper->ScalarVisibilityOn();
  }
  return true;
}

vtkActor* HeadActors::GetActor(int part) const
{
  return part >= 0 && part < this->GetNumberOfParts() ? this->Parts[part]->Actor.Get() : nullptr;
}

std::string HeadActors::GetPartName(int part) const
{
  if (part < 0 || part >= this->GetNumberOfParts())
  {
    return std::string();
  }
  return this->Parts[part]->Name.empty() ? "part " + std::to_string(part) : this->Parts[part]->Name;
}

namespace
{
/// How bright the environment is next to the light kit: chosen by looking at the default
/// face, the ICT head and the avatar (docs/materials.md), so that skin keeps its colour.
double EnvironmentScale = 0.3;
}

vtkSmartPointer<vtkTexture> HeadActors::MakeEnvironment()
{
  if (const char* s = std::getenv("MORPHNODE_ENVIRONMENT_SCALE"))
  {
    EnvironmentScale = std::atof(s);
  }
  // An equirectangular studio made here (no download): a bright neutral sky, a horizon
  // and a darker floor, linear values. What PBR skin reflects and is lit by from all round,
  // so that it does not look like plastic in the dark between the light kit's lights.
  const int width = 64, height = 32;
  vtkNew<vtkImageData> image;
  image->SetDimensions(width, height, 1);
  image->AllocateScalars(VTK_FLOAT, 3);
  auto* p = static_cast<float*>(image->GetScalarPointer());
  for (int y = 0; y < height; ++y)
  {
    const double up = (y + 0.5) / height * 2.0 - 1.0; // -1 floor .. +1 zenith (rows bottom first)
    double rgb[3];
    if (up >= 0)
    {
      const double t = std::pow(up, 0.5);
      const double sky[3] = { 0.9, 0.9, 0.92 }, horizon[3] = { 0.95, 0.92, 0.88 };
      for (int c = 0; c < 3; ++c)
      {
        rgb[c] = horizon[c] + (sky[c] - horizon[c]) * t;
      }
    }
    else
    {
      const double t = std::pow(-up, 0.5);
      const double floor[3] = { 0.3, 0.28, 0.26 }, horizon[3] = { 0.7, 0.67, 0.63 };
      for (int c = 0; c < 3; ++c)
      {
        rgb[c] = horizon[c] + (floor[c] - horizon[c]) * t;
      }
    }
    for (int x = 0; x < width; ++x)
    {
      for (int c = 0; c < 3; ++c)
      {
        p[3 * (y * width + x) + c] = static_cast<float>(EnvironmentScale * rgb[c]);
      }
    }
  }
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(image);
  texture->InterpolateOn();
  texture->MipmapOn();
  return texture;
}

void HeadActors::SetUpLights(vtkRenderer* renderer, bool imageBasedLighting)
{
  // Image-based lighting for the PBR materials (the classic parts ignore it), and depth
  // peeling so that translucent parts (BLEND, MASK cards) are drawn after the opaque ones
  // in depth order.
  if (imageBasedLighting)
  {
    renderer->UseImageBasedLightingOn();
    renderer->SetEnvironmentTexture(MakeEnvironment());
    if (auto* gl = vtkOpenGLRenderer::SafeDownCast(renderer))
    {
      // The environment is a smooth gradient: small prefiltered maps with few samples look
      // the same and take a fraction of the time VTK's defaults (128 pixels, 1024 samples,
      // a LUT of 128) take on a software GL, where the first frame waited seconds.
      gl->GetEnvMapPrefiltered()->SetPrefilterLevels(4);
      gl->GetEnvMapPrefiltered()->SetPrefilterMaxSamples(64);
      gl->GetEnvMapLookupTable()->SetLUTSize(64);
      gl->GetEnvMapLookupTable()->SetLUTSamples(128);
      gl->GetEnvMapIrradiance()->SetIrradianceSize(16);
    }
  }
  renderer->SetUseDepthPeeling(true);
  renderer->SetMaximumNumberOfPeels(6);
  renderer->SetOcclusionRatio(0.0);
  renderer->RemoveAllLights();
  vtkNew<vtkLightKit> lights;
  lights->SetKeyLightIntensity(0.85);
  // White lights: glTF materials are drawn gamma-correct, where the kit's warm key and cool
  // fill would tint the skin grey-green.
  lights->SetKeyLightWarmth(0.5);
  lights->SetFillLightWarmth(0.5);
  lights->SetBackLightWarmth(0.5);
  lights->SetHeadLightWarmth(0.5);
  lights->AddLightsToRenderer(renderer);
}

void HeadActors::SetUpView(vtkRenderer* renderer, const double bounds[6], double zoom)
{
  SetUpLights(renderer);
  renderer->SetBackground(0.15, 0.16, 0.2);
  renderer->SetBackground2(0.32, 0.34, 0.42);
  renderer->GradientBackgroundOn();

  // A portrait: the head from the top down to the neck (the lowest 15 % of the bounds, the
  // neck or shoulders, may leave the frame), the face a little below the middle, clear of
  // text at the top; seen from the front at a 30 degree view angle.
  const double* b = bounds;
  const double bottom = b[2] + 0.15 * (b[3] - b[2]);
  const double height = 1.12 * (b[3] - bottom);
  const double center[3] = { 0.5 * (b[0] + b[1]), 0.5 * (bottom + b[3]) + 0.04 * height,
    0.5 * (b[4] + b[5]) };
  const double distance =
    0.5 * height / std::tan(vtkMath::RadiansFromDegrees(15.0)) / (zoom > 0.0 ? zoom : 1.0);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(center);
  camera->SetPosition(center[0], center[1], b[5] + distance); // the height fits at the front
  camera->SetViewUp(0.0, 1.0, 0.0);
  camera->SetViewAngle(30.0);
  // Far enough for a head turned by the pose (the diagonal all round).
  const double d = std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  renderer->ResetCameraClippingRange(b[0] - d, b[1] + d, b[2] - d, b[3] + d, b[4] - d, b[5] + d);
  // Smooth edges without multisampling (offscreen under Xvfb too); FXAA on a multisampled
  // window renders black there, so only on a window without it.
  vtkRenderWindow* window = renderer->GetRenderWindow();
  renderer->SetUseFXAA(window && window->GetMultiSamples() == 0);
}
} // namespace appkit
} // namespace morphnode
