// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file   vtkMorphPartData.h
 * @brief  The part convention in VTK field data (private to the module): what a part of a
 *         head (a leaf of vtkMorphTargetReader's collection) says about itself.
 *
 * The one place that spells the part field data; every VTK class reads and writes it
 * through these functions (the targets' own convention is vtkMorphTargetArrays.h, the
 * skin's vtkMorphSkinArrays.h):
 *
 * - `PartName`, `NodeName`, `MaterialName`: vtkStringArray, one value;
 * - `BaseColor`: 4 doubles (RGBA, linear, glTF's baseColorFactor);
 * - `NodeOrigin` (3 doubles) and `NodeAxes` (9 doubles, the node's unit x, y and z axes one
 *   after the other): the frame of the part's node in world space (whole scenes only);
 * - `MaterialIndex` (1 double, the material's index in `MaterialSource`) and
 *   `MaterialSource` (the file name): where the part's material came from, so that a writer
 *   can copy it back;
 * - the material's factors and textures (docs/materials.md): `MetallicFactor`,
 *   `RoughnessFactor`, `EmissiveFactor`, `AlphaMode`, `AlphaCutoff`, `DoubleSided`, `Unlit`,
 *   `NormalScale`, `OcclusionStrength`, and per texture slot `<Slot>Image` (unsigned char
 *   RGBA, rows top first), `<Slot>ImageSize` (width, height), `<Slot>Sampler` (glTF's
 *   magFilter, minFilter, wrapS, wrapT); point data TCoords;
 * - `DefaultWeights` (the mesh's weights) and `AppliedWeights` (those blended into the points
 *   when the reader applies an animation's weights).
 *
 * Numeric values are read with their count checked: functions throw morphnode::InputError
 * naming the array; callers turn that into vtkErrorMacro.
 */

#ifndef vtkMorphPartData_h
#define vtkMorphPartData_h

#include <array>
#include <optional>
#include <string>
#include <vector>

class vtkFieldData;
class vtkPolyData;

namespace morphnode
{
struct GltfPart;
struct GltfScene;
}

namespace vtkMorphPartData
{
constexpr const char* PartNameArray = "PartName";
constexpr const char* NodeNameArray = "NodeName";
constexpr const char* MaterialNameArray = "MaterialName";
constexpr const char* BaseColorArray = "BaseColor";
constexpr const char* NodeOriginArray = "NodeOrigin";
constexpr const char* NodeAxesArray = "NodeAxes";
constexpr const char* MaterialIndexArray = "MaterialIndex";
constexpr const char* MaterialSourceArray = "MaterialSource";
constexpr const char* DefaultWeightsArray = "DefaultWeights";
constexpr const char* AppliedWeightsArray = "AppliedWeights";
constexpr const char* MetallicFactorArray = "MetallicFactor";
constexpr const char* RoughnessFactorArray = "RoughnessFactor";
constexpr const char* EmissiveFactorArray = "EmissiveFactor";
constexpr const char* AlphaModeArray = "AlphaMode";
constexpr const char* AlphaCutoffArray = "AlphaCutoff";
constexpr const char* DoubleSidedArray = "DoubleSided";
constexpr const char* UnlitArray = "Unlit";
constexpr const char* NormalScaleArray = "NormalScale";
constexpr const char* OcclusionStrengthArray = "OcclusionStrength";
/// The texture slots, in glTF's order; `<Slot>Image`, `<Slot>ImageSize`, `<Slot>Sampler`.
constexpr const char* BaseColorSlot = "BaseColor";
constexpr const char* MetallicRoughnessSlot = "MetallicRoughness";
constexpr const char* NormalSlot = "Normal";
constexpr const char* OcclusionSlot = "Occlusion";
constexpr const char* EmissiveSlot = "Emissive";
constexpr std::array<const char*, 5> TextureSlots{ { BaseColorSlot, MetallicRoughnessSlot,
  NormalSlot, OcclusionSlot, EmissiveSlot } };
/// A slot's arrays: ImageArray(slot) = `<Slot>Image`, and the image's size and sampler.
inline std::string ImageArray(const std::string& slot)
{
  return slot + "Image";
}
inline std::string ImageSizeArray(const std::string& slot)
{
  return slot + "ImageSize";
}
inline std::string SamplerArray(const std::string& slot)
{
  return slot + "Sampler";
}

/// The first value of a string field-data array, empty when absent (or `fd` is null).
std::string GetString(vtkFieldData* fd, const char* name);
/// Every value of a numeric field-data array (tuples one after the other), empty when
/// absent or not numeric.
std::vector<double> GetNumbers(vtkFieldData* fd, const char* name);
/// Exactly `count` finite values of a numeric field-data array into `values`; false (and
/// `values` untouched) when absent. Throws InputError ("field data <name> has n values, not
/// <count>" or "... is not finite").
bool GetNumbers(vtkFieldData* fd, const char* name, double* values, int count);
/// Replaces a string field-data array with one holding `value`.
void SetString(vtkFieldData* fd, const char* name, const std::string& value);
/// Replaces a double field-data array with one holding `count` values.
void SetNumbers(vtkFieldData* fd, const char* name, const double* values, int count);

/// What a part says about itself (the arrays above but the material's and the weights').
struct PartFields
{
  std::string PartName;
  std::string NodeName;
  std::string MaterialName;
  std::optional<std::array<double, 4>> BaseColor;
  std::optional<std::array<double, 3>> NodeOrigin;
  std::optional<std::array<double, 9>> NodeAxes;
  /// The material's index in MaterialSource, -1 when none.
  int MaterialIndex = -1;
  std::string MaterialSource;
};

/// The part's name, else `fallback` (a block name, say).
std::string GetPartName(vtkFieldData* fd, const std::string& fallback = std::string());
/// The part's node name, else `fallback`.
std::string GetNodeName(vtkFieldData* fd, const std::string& fallback = std::string());
/// NodeOrigin and NodeAxes into `origin` and `axes` where present (each left untouched when
/// absent); true when either was. Throws InputError for a wrong count or a value that is
/// not finite.
bool GetNodeFrame(vtkFieldData* fd, std::array<double, 3>& origin, std::array<double, 9>& axes);
/// All of PartFields, numeric arrays checked as GetNumbers does.
PartFields GetPartFields(vtkFieldData* fd);
/// Writes every field of `fields` that is set (strings always, optional numbers when
/// present, the material's origin when MaterialIndex >= 0).
void SetPartFields(vtkFieldData* fd, const PartFields& fields);

/// A glTF part's fields: names (the node's, or `node<n>`), material name and base colour;
/// with `world`, NodeOrigin (times `scale`) and NodeAxes (unit columns) of part.World.
PartFields FromGltfPart(
  const morphnode::GltfScene& scene, const morphnode::GltfPart& part, bool world, double scale);
/// The part's material (when it has one) as field data and TCoords: index and source file,
/// factors, alpha, and the textures' images that use the base colour's texture coordinates
/// (see the file comment).
void SetMaterial(vtkPolyData* poly, const morphnode::GltfScene& scene,
  const morphnode::GltfPart& part, const std::string& sourceFile);
} // namespace vtkMorphPartData

#endif
