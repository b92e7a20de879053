// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphPartData.h"

#include "base/Error.h"
#include "gltf/GltfScene.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>

namespace vtkMorphPartData
{
namespace
{
/// An image as `<slot>Image`, `<slot>ImageSize` and `<slot>Sampler` (see the header).
void SetImage(vtkFieldData* fd, const std::string& slot, const morphnode::GltfImage& image,
  const morphnode::GltfSampler& sampler)
{
  vtkNew<vtkUnsignedCharArray> pixels;
  pixels->SetName(ImageArray(slot).c_str());
  pixels->SetNumberOfComponents(4);
  pixels->SetNumberOfTuples(static_cast<vtkIdType>(image.Width) * image.Height);
  std::copy(image.Pixels.begin(), image.Pixels.end(), pixels->GetPointer(0));
  fd->AddArray(pixels);
  const double size[2] = { double(image.Width), double(image.Height) };
  SetNumbers(fd, ImageSizeArray(slot).c_str(), size, 2);
  const double s[4] = { double(sampler.MagFilter), double(sampler.MinFilter), double(sampler.WrapS),
    double(sampler.WrapT) };
  SetNumbers(fd, SamplerArray(slot).c_str(), s, 4);
}

template <size_t N>
std::optional<std::array<double, N>> Optional(vtkFieldData* fd, const char* name)
{
  std::array<double, N> values{};
  if (GetNumbers(fd, name, values.data(), static_cast<int>(N)))
  {
    return values;
  }
  return std::nullopt;
}
} // namespace

//------------------------------------------------------------------------------
std::string GetString(vtkFieldData* fd, const char* name)
{
  auto* array = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  return array && array->GetNumberOfValues() > 0 ? array->GetValue(0) : std::string();
}

//------------------------------------------------------------------------------
std::vector<double> GetNumbers(vtkFieldData* fd, const char* name)
{
  vtkDataArray* array = fd ? fd->GetArray(name) : nullptr;
  std::vector<double> values;
  if (array)
  {
    const int nc = array->GetNumberOfComponents();
    values.resize(static_cast<size_t>(array->GetNumberOfValues()));
    for (size_t i = 0; i < values.size(); ++i)
    {
      values[i] = array->GetComponent(static_cast<vtkIdType>(i) / nc, static_cast<int>(i % nc));
    }
  }
  return values;
}

//------------------------------------------------------------------------------
bool GetNumbers(vtkFieldData* fd, const char* name, double* values, int count)
{
  const std::vector<double> all = GetNumbers(fd, name);
  if (!fd || !fd->GetArray(name))
  {
    return false;
  }
  if (all.size() != static_cast<size_t>(count))
  {
    throw morphnode::InputError(std::string("field data ") + name + " has " +
      std::to_string(all.size()) + " values, not " + std::to_string(count));
  }
  if (!std::all_of(all.begin(), all.end(), [](double v) { return std::isfinite(v); }))
  {
    throw morphnode::InputError(std::string("field data ") + name + " is not finite");
  }
  std::copy(all.begin(), all.end(), values);
  return true;
}

//------------------------------------------------------------------------------
void SetString(vtkFieldData* fd, const char* name, const std::string& value)
{
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

//------------------------------------------------------------------------------
void SetNumbers(vtkFieldData* fd, const char* name, const double* values, int count)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfValues(count);
  std::copy_n(values, count, array->GetPointer(0));
  fd->AddArray(array);
}

//------------------------------------------------------------------------------
std::string GetPartName(vtkFieldData* fd, const std::string& fallback)
{
  const std::string name = GetString(fd, PartNameArray);
  return name.empty() ? fallback : name;
}

//------------------------------------------------------------------------------
std::string GetNodeName(vtkFieldData* fd, const std::string& fallback)
{
  const std::string name = GetString(fd, NodeNameArray);
  return name.empty() ? fallback : name;
}

//------------------------------------------------------------------------------
bool GetNodeFrame(vtkFieldData* fd, std::array<double, 3>& origin, std::array<double, 9>& axes)
{
  const bool hasOrigin = GetNumbers(fd, NodeOriginArray, origin.data(), 3);
  const bool hasAxes = GetNumbers(fd, NodeAxesArray, axes.data(), 9);
  return hasOrigin || hasAxes;
}

//------------------------------------------------------------------------------
PartFields GetPartFields(vtkFieldData* fd)
{
  PartFields fields;
  fields.PartName = GetString(fd, PartNameArray);
  fields.NodeName = GetString(fd, NodeNameArray);
  fields.MaterialName = GetString(fd, MaterialNameArray);
  fields.BaseColor = Optional<4>(fd, BaseColorArray);
  fields.NodeOrigin = Optional<3>(fd, NodeOriginArray);
  fields.NodeAxes = Optional<9>(fd, NodeAxesArray);
  fields.MaterialSource = GetString(fd, MaterialSourceArray);
  if (const auto index = Optional<1>(fd, MaterialIndexArray))
  {
    if ((*index)[0] < 0 || (*index)[0] != std::floor((*index)[0]) || (*index)[0] > 1e9)
    {
      throw morphnode::InputError(std::string("field data ") + MaterialIndexArray +
        " is not an index: " + std::to_string((*index)[0]));
    }
    fields.MaterialIndex = static_cast<int>((*index)[0]);
  }
  return fields;
}

//------------------------------------------------------------------------------
void SetPartFields(vtkFieldData* fd, const PartFields& fields)
{
  SetString(fd, PartNameArray, fields.PartName);
  SetString(fd, NodeNameArray, fields.NodeName);
  SetString(fd, MaterialNameArray, fields.MaterialName);
  if (fields.BaseColor)
  {
    SetNumbers(fd, BaseColorArray, fields.BaseColor->data(), 4);
  }
  if (fields.NodeOrigin)
  {
    SetNumbers(fd, NodeOriginArray, fields.NodeOrigin->data(), 3);
  }
  if (fields.NodeAxes)
  {
    SetNumbers(fd, NodeAxesArray, fields.NodeAxes->data(), 9);
  }
  if (fields.MaterialIndex >= 0)
  {
    const double index = fields.MaterialIndex;
    SetNumbers(fd, MaterialIndexArray, &index, 1);
    SetString(fd, MaterialSourceArray, fields.MaterialSource);
  }
}

//------------------------------------------------------------------------------
PartFields FromGltfPart(
  const morphnode::GltfScene& scene, const morphnode::GltfPart& part, bool world, double scale)
{
  PartFields fields;
  fields.PartName = part.Name;
  fields.NodeName = morphnode::GltfNodeName(scene, part.Node);
  fields.MaterialName = part.MaterialName;
  fields.BaseColor = part.BaseColor;
  if (world)
  {
    const morphnode::GltfMatrix& m = part.World; // column-major
    fields.NodeOrigin = std::array<double, 3>{ { scale * m[12], scale * m[13], scale * m[14] } };
    std::array<double, 9> axes{};
    for (int c = 0; c < 3; ++c)
    {
      const double length =
        std::sqrt(m[4 * c] * m[4 * c] + m[4 * c + 1] * m[4 * c + 1] + m[4 * c + 2] * m[4 * c + 2]);
      for (int r = 0; r < 3; ++r)
      {
        axes[3 * c + r] = length > 0.0 ? m[4 * c + r] / length : (r == c ? 1.0 : 0.0);
      }
    }
    fields.NodeAxes = axes;
  }
  return fields;
}

//------------------------------------------------------------------------------
void SetMaterial(vtkPolyData* poly, const morphnode::GltfScene& scene,
  const morphnode::GltfPart& part, const std::string& sourceFile)
{
  if (part.Material < 0 || static_cast<size_t>(part.Material) >= scene.Materials.size())
  {
    return;
  }
  const morphnode::GltfMaterial& m = scene.Materials[static_cast<size_t>(part.Material)];
  vtkFieldData* fd = poly->GetFieldData();
  // Where the material came from: vtkMorphGltfWriter writes the file's material (and its
  // images) back from these.
  const double index = part.Material;
  SetNumbers(fd, MaterialIndexArray, &index, 1);
  SetString(fd, MaterialSourceArray, sourceFile);
  SetNumbers(fd, MetallicFactorArray, &m.MetallicFactor, 1);
  SetNumbers(fd, RoughnessFactorArray, &m.RoughnessFactor, 1);
  const double emissive[3] = { m.EmissiveFactor[0] * m.EmissiveStrength,
    m.EmissiveFactor[1] * m.EmissiveStrength, m.EmissiveFactor[2] * m.EmissiveStrength };
  SetNumbers(fd, EmissiveFactorArray, emissive, 3);
  SetString(fd, AlphaModeArray, morphnode::GltfAlphaModeName(m.AlphaMode));
  SetNumbers(fd, AlphaCutoffArray, &m.AlphaCutoff, 1);
  const double doubleSided = m.DoubleSided ? 1 : 0, unlit = m.Unlit ? 1 : 0;
  SetNumbers(fd, DoubleSidedArray, &doubleSided, 1);
  SetNumbers(fd, UnlitArray, &unlit, 1);
  // The texture coordinates: those of the base colour texture, else of the first texture.
  const std::array<const morphnode::GltfTextureRef*, 5> refs{ { &m.BaseColorTexture,
    &m.MetallicRoughnessTexture, &m.NormalTexture, &m.OcclusionTexture, &m.EmissiveTexture } };
  const auto first = std::find_if(refs.begin(), refs.end(), [](auto* ref) { return ref->IsSet(); });
  if (first == refs.end())
  {
    return;
  }
  const morphnode::GltfTextureRef* uv = *first;
  const std::vector<float>& tc = uv->TexCoord == 0 ? part.TexCoords0 : part.TexCoords1;
  if (tc.size() != 2 * part.GetNumberOfPoints())
  {
    return; // the primitive lacks the set: drawn without textures
  }
  const std::array<double, 9> t = uv->UvMatrix();
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(static_cast<vtkIdType>(part.GetNumberOfPoints()));
  for (size_t i = 0; i < part.GetNumberOfPoints(); ++i)
  {
    const double u = tc[2 * i], v = tc[2 * i + 1];
    tcoords->SetTypedComponent(
      static_cast<vtkIdType>(i), 0, static_cast<float>(t[0] * u + t[1] * v + t[2]));
    tcoords->SetTypedComponent(
      static_cast<vtkIdType>(i), 1, static_cast<float>(t[3] * u + t[4] * v + t[5]));
  }
  poly->GetPointData()->SetTCoords(tcoords);
  for (size_t k = 0; k < refs.size(); ++k)
  {
    const auto* ref = refs[k];
    const bool sameUv = ref->TexCoord == uv->TexCoord && ref->UvMatrix() == uv->UvMatrix();
    if (ref->IsSet() && sameUv && static_cast<size_t>(ref->Image) < scene.Images.size())
    {
      SetImage(fd, TextureSlots[k], scene.Images[static_cast<size_t>(ref->Image)], ref->Sampler);
      if (k == 2)
      {
        SetNumbers(fd, NormalScaleArray, &ref->Scale, 1);
      }
      if (k == 3)
      {
        SetNumbers(fd, OcclusionStrengthArray, &ref->Scale, 1);
      }
    }
  }
}
} // namespace vtkMorphPartData
