// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTargetReader.h"

#include "vtkMorphSkinArrays.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gltf/GltfAnimation.h"
#include "gltf/GltfSkin.h"
#include "gltf/GltfScene.h"
#include "morph/MorphMesh.h"
#include "morph/Normals.h"
#include "rig/ObjSet.h"

#include "vtkCellArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataAssembly.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <unordered_set>

vtkStandardNewMacro(vtkMorphTargetReader);

namespace
{
using morphnode::InputError;
namespace arrays = vtkMorphTargetArrays;
using arrays::Kind;

bool EndsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool IsGltf(const std::string& fileName)
{
  const std::string lower = morphnode::text::ToLower(fileName);
  return EndsWith(lower, ".glb") || EndsWith(lower, ".gltf");
}

vtkSmartPointer<vtkDataArray> MakeVectors(const std::string& name, const std::vector<float>& values)
{
  return arrays::NewArray(
    VTK_FLOAT, name.c_str(), 3, static_cast<vtkIdType>(values.size() / 3), values.data());
}

void AddString(vtkFieldData* fd, const char* name, const std::string& value)
{
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

void AddDoubles(vtkFieldData* fd, const char* name, const double* values, int count)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfValues(count);
  std::copy_n(values, count, array->GetPointer(0));
  fd->AddArray(array);
}

std::string MeshNameOf(const morphnode::GltfScene& scene, size_t m)
{
  return scene.Meshes[m].Name.empty() ? "mesh" + std::to_string(m) : scene.Meshes[m].Name;
}

std::string NodeNameOf(const morphnode::GltfScene& scene, int n)
{
  return scene.Nodes[static_cast<size_t>(n)].Name.empty() ? "node" + std::to_string(n)
                                                          : scene.Nodes[static_cast<size_t>(n)].Name;
}

/// A part as the convention's vtkPolyData: float points, triangles, normals `Normals` (when
/// the file has them), COLOR_0 as unsigned char RGBA, `target<k>_position` for every target
/// and `target<k>_normal` for the targets that have normal deltas.
vtkSmartPointer<vtkPolyData> PartToPolyData(const morphnode::GltfPart& part)
{
  const vtkIdType n = static_cast<vtkIdType>(part.GetNumberOfPoints());
  auto output = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetData(MakeVectors("Points", part.Positions));
  output->SetPoints(points);

  vtkNew<vtkCellArray> polys;
  const size_t numTriangles = part.GetNumberOfTriangles();
  polys->AllocateExact(static_cast<vtkIdType>(numTriangles), 3 * static_cast<vtkIdType>(numTriangles));
  for (size_t t = 0; t < numTriangles; ++t)
  {
    const vtkIdType ids[3] = { part.Triangles[3 * t], part.Triangles[3 * t + 1], part.Triangles[3 * t + 2] };
    polys->InsertNextCell(3, ids);
  }
  output->SetPolys(polys);

  vtkPointData* pd = output->GetPointData();
  if (!part.Normals.empty())
  {
    pd->SetNormals(MakeVectors("Normals", part.Normals));
  }
  if (!part.Colors.empty())
  {
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("COLOR_0");
    colors->SetNumberOfComponents(4);
    colors->SetNumberOfTuples(n);
    unsigned char* out = colors->GetPointer(0);
    for (size_t i = 0; i < part.Colors.size(); ++i)
    {
      const double c = std::min(1.0, std::max(0.0, double(part.Colors[i])));
      out[i] = static_cast<unsigned char>(std::lround(255.0 * c));
    }
    pd->AddArray(colors);
  }
  for (size_t k = 0; k < part.Targets.size(); ++k)
  {
    pd->AddArray(MakeVectors(arrays::ArrayName(k, Kind::Position), part.Targets[k].PositionDeltas));
    if (!part.Targets[k].NormalDeltas.empty())
    {
      pd->AddArray(MakeVectors(arrays::ArrayName(k, Kind::Normal), part.Targets[k].NormalDeltas));
    }
  }
  return output;
}

/// Scale, normals (computed by the policy), and field data `TargetNames`.
void FinishMesh(vtkPolyData* output, const std::vector<std::string>& targetNames, double scale,
  int normalsMode)
{
  const size_t numPoints = static_cast<size_t>(output->GetNumberOfPoints());
  const size_t numTargets = targetNames.size() - 1;
  vtkPointData* pd = output->GetPointData();

  if (scale != 1.0)
  {
    // New arrays: the geometry's may be shared.
    auto scaled = [&](vtkDataArray* array) {
      std::vector<double> values = arrays::ToVector<double>(array);
      for (double& v : values)
      {
        v *= scale;
      }
      return arrays::NewArray(array->GetDataType(), array->GetName(),
        array->GetNumberOfComponents(), array->GetNumberOfTuples(), values.data());
    };
    vtkNew<vtkPoints> points;
    points->SetData(scaled(output->GetPoints()->GetData()));
    output->SetPoints(points);
    for (size_t k = 0; k < numTargets; ++k)
    {
      pd->AddArray(scaled(arrays::GetDeltas(pd, k, Kind::Position, output->GetNumberOfPoints())));
    }
  }

  // Normals: the morph node renormalizes blended normals, but only blends them when the
  // base and every target have them; otherwise shading would not follow the face.
  vtkDataArray* baseNormals = pd->GetNormals() ? pd->GetNormals() : pd->GetArray("Normal");
  bool complete = baseNormals != nullptr;
  for (size_t k = 0; k < numTargets && complete; ++k)
  {
    complete = arrays::GetDeltas(pd, k, Kind::Normal, output->GetNumberOfPoints()) != nullptr;
  }
  const bool compute = normalsMode == vtkMorphTargetReader::NORMALS_ALWAYS ||
    (normalsMode == vtkMorphTargetReader::NORMALS_WHEN_MISSING && !complete);
  if (compute && numPoints > 0)
  {
    const std::vector<uint32_t> triangles = arrays::GetTriangles(output, true);
    const std::vector<float> base = arrays::ToVector<float>(output->GetPoints()->GetData());
    const std::vector<float> normals =
      morphnode::ComputeVertexNormals(base.data(), numPoints, triangles.data(), triangles.size() / 3);
    if (baseNormals && baseNormals->GetName())
    {
      pd->RemoveArray(baseNormals->GetName());
    }
    pd->SetNormals(MakeVectors("Normals", normals));
    for (size_t k = 0; k < numTargets; ++k)
    {
      const std::string name = arrays::ArrayName(k, Kind::Normal);
      const std::vector<float> delta = arrays::ToVector<float>(
        arrays::GetDeltas(pd, k, Kind::Position, output->GetNumberOfPoints()));
      pd->RemoveArray(name.c_str());
      pd->AddArray(MakeVectors(name,
        morphnode::ComputeNormalDeltas(base.data(), delta.data(), normals, numPoints,
          triangles.data(), triangles.size() / 3)));
    }
  }
  else if (baseNormals && !pd->GetNormals())
  {
    pd->SetNormals(baseNormals);
  }

  arrays::SetTargetNames(output->GetFieldData(), targetNames);
}

/// "Neutral" and the part's target names.
std::vector<std::string> TargetNamesOf(const morphnode::GltfPart& part)
{
  std::vector<std::string> names{ morphnode::DefaultTargetNames(1)[0] };
  for (const auto& target : part.Targets)
  {
    names.push_back(target.Name);
  }
  return names;
}

/// PartName, NodeName, MaterialName, BaseColor; with `world`, NodeOrigin and NodeAxes too.
void AddPartFieldData(vtkFieldData* fd, const morphnode::GltfScene& scene,
  const morphnode::GltfPart& part, bool world, double scale)
{
  AddString(fd, "PartName", part.Name);
  AddString(fd, "NodeName", NodeNameOf(scene, part.Node));
  AddString(fd, "MaterialName", part.MaterialName);
  AddDoubles(fd, "BaseColor", part.BaseColor.data(), 4);
  if (world)
  {
    const morphnode::GltfMatrix& m = part.World; // column-major
    const double origin[3] = { scale * m[12], scale * m[13], scale * m[14] };
    AddDoubles(fd, "NodeOrigin", origin, 3);
    double axes[9];
    for (int c = 0; c < 3; ++c)
    {
      const double length = std::sqrt(m[4 * c] * m[4 * c] + m[4 * c + 1] * m[4 * c + 1] + m[4 * c + 2] * m[4 * c + 2]);
      for (int r = 0; r < 3; ++r)
      {
        axes[3 * c + r] = length > 0.0 ? m[4 * c + r] / length : (r == c ? 1.0 : 0.0);
      }
    }
    AddDoubles(fd, "NodeAxes", axes, 9);
  }
}

/// An image of the scene as a field-data array `<name>Image` (unsigned char RGBA, one tuple per
/// pixel, rows as in the file: top first, which is where glTF's v = 0 is and where VTK's
/// texture coordinate t = 0 samples) with `<name>ImageSize` (width, height) and
/// `<name>Sampler` (magFilter, minFilter, wrapS, wrapT as glTF's enums).
void AddImage(vtkFieldData* fd, const std::string& name, const morphnode::GltfImage& image,
  const morphnode::GltfSampler& sampler)
{
  vtkNew<vtkUnsignedCharArray> pixels;
  pixels->SetName((name + "Image").c_str());
  pixels->SetNumberOfComponents(4);
  pixels->SetNumberOfTuples(static_cast<vtkIdType>(image.Width) * image.Height);
  std::copy(image.Pixels.begin(), image.Pixels.end(), pixels->GetPointer(0));
  fd->AddArray(pixels);
  const double size[2] = { double(image.Width), double(image.Height) };
  AddDoubles(fd, (name + "ImageSize").c_str(), size, 2);
  const double s[4] = { double(sampler.MagFilter), double(sampler.MinFilter), double(sampler.WrapS),
    double(sampler.WrapT) };
  AddDoubles(fd, (name + "Sampler").c_str(), s, 4);
}

/// The part's material as field data (docs/materials.md): MetallicFactor, RoughnessFactor,
/// EmissiveFactor (times KHR_materials_emissive_strength), AlphaMode, AlphaCutoff,
/// DoubleSided, Unlit; the textures' images (BaseColor, MetallicRoughness, Normal,
/// Occlusion, Emissive) where they decoded and use the base colour's texture coordinates;
/// point data TCoords: the base colour texture's TEXCOORD_n with its KHR_texture_transform
/// applied (VTK draws all of a part's textures with one set of coordinates).
void AddMaterial(vtkPolyData* poly, const morphnode::GltfScene& scene, const morphnode::GltfPart& part,
  const std::string& fileName)
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
  AddDoubles(fd, "MaterialIndex", &index, 1);
  AddString(fd, "MaterialSource", fileName);
  AddDoubles(fd, "MetallicFactor", &m.MetallicFactor, 1);
  AddDoubles(fd, "RoughnessFactor", &m.RoughnessFactor, 1);
  const double emissive[3] = { m.EmissiveFactor[0] * m.EmissiveStrength, m.EmissiveFactor[1] * m.EmissiveStrength,
    m.EmissiveFactor[2] * m.EmissiveStrength };
  AddDoubles(fd, "EmissiveFactor", emissive, 3);
  AddString(fd, "AlphaMode", morphnode::GltfAlphaModeName(m.AlphaMode));
  AddDoubles(fd, "AlphaCutoff", &m.AlphaCutoff, 1);
  const double doubleSided = m.DoubleSided ? 1 : 0, unlit = m.Unlit ? 1 : 0;
  AddDoubles(fd, "DoubleSided", &doubleSided, 1);
  AddDoubles(fd, "Unlit", &unlit, 1);
  // The texture coordinates: those of the base colour texture, else of the first texture.
  const morphnode::GltfTextureRef* refs[5] = { &m.BaseColorTexture, &m.MetallicRoughnessTexture, &m.NormalTexture,
    &m.OcclusionTexture, &m.EmissiveTexture };
  const char* names[5] = { "BaseColor", "MetallicRoughness", "Normal", "Occlusion", "Emissive" };
  const morphnode::GltfTextureRef* uv = nullptr;
  for (const auto* ref : refs)
  {
    if (ref->IsSet() && !uv)
    {
      uv = ref;
    }
  }
  if (!uv)
  {
    return;
  }
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
    tcoords->SetTypedComponent(static_cast<vtkIdType>(i), 0, static_cast<float>(t[0] * u + t[1] * v + t[2]));
    tcoords->SetTypedComponent(static_cast<vtkIdType>(i), 1, static_cast<float>(t[3] * u + t[4] * v + t[5]));
  }
  poly->GetPointData()->SetTCoords(tcoords);
  for (int k = 0; k < 5; ++k)
  {
    const auto* ref = refs[k];
    const bool sameUv = ref->TexCoord == uv->TexCoord && ref->UvMatrix() == uv->UvMatrix();
    if (ref->IsSet() && sameUv && static_cast<size_t>(ref->Image) < scene.Images.size())
    {
      AddImage(fd, names[k], scene.Images[static_cast<size_t>(ref->Image)], ref->Sampler);
      if (k == 2)
      {
        AddDoubles(fd, "NormalScale", &ref->Scale, 1);
      }
      if (k == 3)
      {
        AddDoubles(fd, "OcclusionStrength", &ref->Scale, 1);
      }
    }
  }
}

/// The node tree of the scene as a data assembly, each part's index on its node.
vtkSmartPointer<vtkDataAssembly> MakeAssembly(const morphnode::GltfScene& scene, const std::string& fileName)
{
  auto assembly = vtkSmartPointer<vtkDataAssembly>::New();
  std::string root = scene.SceneName;
  if (root.empty())
  {
    root = std::filesystem::path(fileName).stem().string();
  }
  assembly->SetRootNodeName(vtkDataAssembly::MakeValidNodeName(root.empty() ? "Scene" : root.c_str()).c_str());
  std::vector<std::vector<unsigned int>> partsOfNode(scene.Nodes.size());
  for (size_t p = 0; p < scene.Parts.size(); ++p)
  {
    partsOfNode[static_cast<size_t>(scene.Parts[p].Node)].push_back(static_cast<unsigned int>(p));
  }
  // Depth-first, children in the file's order; the loader checked the tree (no cycles).
  std::vector<std::pair<int, int>> stack; // node, parent assembly id
  for (size_t n = scene.Nodes.size(); n-- > 0;)
  {
    if (scene.Nodes[n].Parent < 0 && scene.Nodes[n].InScene)
    {
      stack.emplace_back(static_cast<int>(n), vtkDataAssembly::GetRootNode());
    }
  }
  while (!stack.empty())
  {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    const morphnode::GltfNode& gltfNode = scene.Nodes[static_cast<size_t>(node)];
    const int id = assembly->AddNode(
      vtkDataAssembly::MakeValidNodeName(NodeNameOf(scene, node).c_str()).c_str(), parent);
    for (unsigned int p : partsOfNode[static_cast<size_t>(node)])
    {
      assembly->AddDataSetIndex(id, p);
    }
    for (auto child = gltfNode.Children.rbegin(); child != gltfNode.Children.rend(); ++child)
    {
      stack.emplace_back(*child, id);
    }
  }
  return assembly;
}

/// The part of one mesh and primitive, chosen by name or index (single-mesh mode).
const morphnode::GltfPart& SelectPart(const morphnode::GltfScene& scene,
  const std::vector<std::string>& meshNames, const std::string& fileName, const std::string& meshName,
  int meshIndexWanted, int primitiveWanted)
{
  size_t meshIndex = static_cast<size_t>(std::max(meshIndexWanted, 0));
  if (!meshName.empty())
  {
    auto it = std::find(meshNames.begin(), meshNames.end(), meshName);
    if (it == meshNames.end())
    {
      std::ostringstream msg;
      msg << "'" << fileName << "' has no mesh named '" << meshName << "'; meshes:";
      for (const auto& n : meshNames)
      {
        msg << " " << n;
      }
      throw InputError(msg.str());
    }
    meshIndex = static_cast<size_t>(it - meshNames.begin());
  }
  if (meshIndex >= meshNames.size())
  {
    std::ostringstream msg;
    msg << "mesh index " << meshIndex << " out of range: '" << fileName << "' has "
        << meshNames.size() << " meshes";
    throw InputError(msg.str());
  }
  const int primitive = std::max(primitiveWanted, 0);
  if (static_cast<size_t>(primitive) >= scene.Meshes[meshIndex].NumberOfPrimitives)
  {
    std::ostringstream msg;
    msg << "primitive " << primitive << " out of range: mesh '" << meshNames[meshIndex]
        << "' has " << scene.Meshes[meshIndex].NumberOfPrimitives;
    throw InputError(msg.str());
  }
  for (const morphnode::GltfPart& part : scene.Parts)
  {
    if (part.Mesh == static_cast<int>(meshIndex) && part.Primitive == primitive)
    {
      return part;
    }
  }
  throw InputError("mesh '" + meshNames[meshIndex] + "' of '" + fileName +
    "' is on no node of the scene");
}

/// Blends a part's weights into its points and normals (glTF: base + sum w_k delta_k;
/// normals renormalized), as a glTF viewer shows the morphed mesh.
void BlendWeights(morphnode::GltfPart& part, const std::vector<double>& weights)
{
  const size_t n = part.GetNumberOfPoints();
  std::vector<double> p(part.Positions.begin(), part.Positions.end());
  std::vector<double> normals(part.Normals.begin(), part.Normals.end());
  for (size_t k = 0; k < part.Targets.size() && k < weights.size(); ++k)
  {
    const double w = weights[k];
    if (w == 0.0)
    {
      continue;
    }
    const auto& target = part.Targets[k];
    for (size_t i = 0; i < 3 * n; ++i)
    {
      p[i] += w * double(target.PositionDeltas[i]);
    }
    if (!normals.empty() && !target.NormalDeltas.empty())
    {
      for (size_t i = 0; i < 3 * n; ++i)
      {
        normals[i] += w * double(target.NormalDeltas[i]);
      }
    }
  }
  std::copy(p.begin(), p.end(), part.Positions.begin());
  for (size_t i = 0; i < n && !normals.empty(); ++i)
  {
    double* v = &normals[3 * i];
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (size_t c = 0; c < 3; ++c)
    {
      part.Normals[3 * i + c] = static_cast<float>(length > 0 ? v[c] / length : v[c]);
    }
  }
}

void AddColumn(vtkTable* table, const std::string& name, const double* values, int components)
{
  vtkNew<vtkDoubleArray> column;
  column->SetName(name.c_str());
  column->SetNumberOfComponents(components);
  column->SetNumberOfTuples(1);
  std::copy_n(values, components, column->GetPointer(0));
  table->AddColumn(column);
}

/// The time steps advertised: key times, or a regular grid at `rate` over the keys' range.
std::vector<double> TimeSteps(const morphnode::GltfAnimationPlayer& player, double rate)
{
  if (rate <= 0.0)
  {
    return player.GetKeyTimes();
  }
  std::vector<double> steps;
  const double start = player.GetStartTime(), end = player.GetEndTime();
  const double count = std::floor((end - start) * rate + 1e-9);
  for (double i = 0; i <= count && steps.size() < 1000000; ++i)
  {
    steps.push_back(start + i / rate);
  }
  if (steps.empty() || steps.back() < end - 1e-12)
  {
    steps.push_back(end);
  }
  return steps;
}
} // namespace

/// The last glTF scene read, and what it was read from.
struct vtkMorphTargetReader::SceneCache
{
  std::string FileName;
  bool ApplyTransforms = true;
  std::filesystem::file_time_type WriteTime;
  std::uintmax_t Size = 0;
  vtkMTimeType ReaderTime = 0; ///< the reader's MTime: any property set reads again
  std::shared_ptr<const morphnode::GltfScene> Scene;
};

//------------------------------------------------------------------------------
vtkMorphTargetReader::vtkMorphTargetReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
vtkMorphTargetReader::~vtkMorphTargetReader() = default;

//------------------------------------------------------------------------------
bool vtkMorphTargetReader::GetReadsWholeScene()
{
  return IsGltf(this->FileName) && this->MeshName.empty() && this->MeshIndex < 0 &&
    this->PrimitiveIndex < 0;
}

//------------------------------------------------------------------------------
const char* vtkMorphTargetReader::GetAnimationNameByIndex(int index)
{
  return index >= 0 && index < this->GetNumberOfAnimations()
    ? this->AnimationNames[static_cast<size_t>(index)].c_str()
    : nullptr;
}

//------------------------------------------------------------------------------
vtkTable* vtkMorphTargetReader::GetWeightsOutput()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

//------------------------------------------------------------------------------
std::shared_ptr<const morphnode::GltfScene> vtkMorphTargetReader::LoadScene(bool applyTransforms)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_time_type writeTime = fs::last_write_time(this->FileName, ec);
  const std::uintmax_t size = ec ? 0 : fs::file_size(this->FileName, ec);
  SceneCache* cache = this->Cache.get();
  if (!ec && cache && cache->Scene && cache->FileName == this->FileName &&
    cache->ApplyTransforms == applyTransforms && cache->WriteTime == writeTime && cache->Size == size &&
    cache->ReaderTime == this->GetMTime())
  {
    return cache->Scene;
  }
  this->Cache.reset();
  morphnode::GltfLoadOptions options;
  options.ApplyTransforms = applyTransforms;
  // The decoded limit counts what the VTK side derives too: the reader's output arrays,
  // the morph filter's blended copy and the renderer's buffers hold about four copies of
  // the scene (a GLB of 1,000 instances took 9 GB for one frame against a 2 GiB core
  // limit, issue 29), so the core scene gets a quarter of the budget (docs/limits.md).
  options.MaxDecodedBytes = morphnode::GltfLoadOptions().MaxDecodedBytes / 4;
  auto scene = std::make_shared<const morphnode::GltfScene>(morphnode::LoadGltfScene(this->FileName, options));
  if (!ec)
  {
    this->Cache = std::make_unique<SceneCache>();
    this->Cache->FileName = this->FileName;
    this->Cache->ApplyTransforms = applyTransforms;
    this->Cache->WriteTime = writeTime;
    this->Cache->Size = size;
    this->Cache->ReaderTime = this->GetMTime();
    this->Cache->Scene = scene;
  }
  return scene;
}

//------------------------------------------------------------------------------
int vtkMorphTargetReader::ResolveAnimation(const morphnode::GltfScene& scene) const
{
  if (!this->AnimationName.empty())
  {
    for (size_t a = 0; a < scene.Animations.size(); ++a)
    {
      const std::string name = scene.Animations[a].Name.empty() ? "animation" + std::to_string(a)
                                                                 : scene.Animations[a].Name;
      if (name == this->AnimationName)
      {
        return static_cast<int>(a);
      }
    }
    std::ostringstream msg;
    msg << "'" << this->FileName << "' has no animation named '" << this->AnimationName << "'; animations:";
    for (size_t a = 0; a < scene.Animations.size(); ++a)
    {
      msg << " " << (scene.Animations[a].Name.empty() ? "animation" + std::to_string(a) : scene.Animations[a].Name);
    }
    if (scene.Animations.empty())
    {
      msg << " none";
    }
    throw InputError(msg.str());
  }
  if (this->AnimationIndex >= 0 && static_cast<size_t>(this->AnimationIndex) >= scene.Animations.size())
  {
    throw InputError("animation index " + std::to_string(this->AnimationIndex) + " out of range: '" +
      this->FileName + "' has " + std::to_string(scene.Animations.size()) + " animations");
  }
  return this->AnimationIndex;
}

//------------------------------------------------------------------------------
const char* vtkMorphTargetReader::GetTargetName(int index)
{
  return index >= 0 && index < this->GetNumberOfTargets()
    ? this->TargetNames[static_cast<size_t>(index)].c_str()
    : nullptr;
}

//------------------------------------------------------------------------------
const char* vtkMorphTargetReader::GetMeshNameByIndex(int index)
{
  return index >= 0 && index < this->GetNumberOfMeshes()
    ? this->MeshNames[static_cast<size_t>(index)].c_str()
    : nullptr;
}

//------------------------------------------------------------------------------
const char* vtkMorphTargetReader::GetPartName(int index)
{
  return index >= 0 && index < this->GetNumberOfParts()
    ? this->PartNames[static_cast<size_t>(index)].c_str()
    : nullptr;
}

//------------------------------------------------------------------------------
int vtkMorphTargetReader::FillOutputPortInformation(int port, vtkInformation* info)
{
  // Port 0: a vtkPolyData or, for a whole scene, a vtkPartitionedDataSetCollection;
  // port 1: the weights (and animated node transforms) at the time requested.
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 1 ? "vtkTable" : "vtkDataObject");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphTargetReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  this->AnimationNames.clear();
  this->ChosenAnimation = -1;
  this->AnimationRange[0] = this->AnimationRange[1] = 0.0;
  std::vector<double> steps;
  if (IsGltf(this->FileName))
  {
    // Errors are reported by RequestData (with an empty output); here they only leave the
    // time unadvertised.
    try
    {
      const bool whole = this->GetReadsWholeScene();
      const bool transformsApplied = !(this->ApplyAnimation != ANIMATION_NOT_APPLIED &&
        (this->AnimationIndex >= 0 || !this->AnimationName.empty()));
      const auto scene = this->LoadScene(whole && transformsApplied);
      for (size_t a = 0; a < scene->Animations.size(); ++a)
      {
        this->AnimationNames.push_back(
          scene->Animations[a].Name.empty() ? "animation" + std::to_string(a) : scene->Animations[a].Name);
      }
      const int chosen = this->ResolveAnimation(*scene);
      if (chosen >= 0)
      {
        const morphnode::GltfAnimationPlayer player(*scene, chosen, this->FileName);
        steps = TimeSteps(player, this->FrameRate);
        this->ChosenAnimation = chosen;
        this->AnimationRange[0] = player.GetStartTime();
        this->AnimationRange[1] = player.GetEndTime();
      }
    }
    catch (const std::exception&)
    {
      steps.clear();
      this->ChosenAnimation = -1;
    }
  }
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    if (steps.empty())
    {
      outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
      outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
    }
    else
    {
      outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps.data(), static_cast<int>(steps.size()));
      outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), this->AnimationRange, 2);
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkMorphTargetReader::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_OBJECT()))
  {
    return this->RequestDataObject(request, inputVector, outputVector);
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkMorphTargetReader::RequestDataObject(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataObject* output = vtkDataObject::GetData(outInfo);
  const bool scene = this->GetReadsWholeScene();
  if (!vtkTable::SafeDownCast(vtkDataObject::GetData(outputVector, 1)))
  {
    vtkNew<vtkTable> table;
    outputVector->GetInformationObject(1)->Set(vtkDataObject::DATA_OBJECT(), table);
  }
  if (scene && !vtkPartitionedDataSetCollection::SafeDownCast(output))
  {
    vtkNew<vtkPartitionedDataSetCollection> collection;
    outInfo->Set(vtkDataObject::DATA_OBJECT(), collection);
  }
  else if (!scene && !vtkPolyData::SafeDownCast(output))
  {
    vtkNew<vtkPolyData> poly;
    outInfo->Set(vtkDataObject::DATA_OBJECT(), poly);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphTargetReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  vtkTable* weightsOutput = vtkTable::GetData(outputVector, 1);
  this->TargetNames.clear();
  this->PartNames.clear();
  this->MeshNames.clear();
  if (weightsOutput)
  {
    weightsOutput->Initialize();
  }
  try
  {
    if (this->FileName.empty())
    {
      throw InputError("no file name set");
    }
    if (!weightsOutput)
    {
      throw InputError("internal: output port 1 is not a vtkTable");
    }
    this->UpdateProgress(0.0);
    if (IsGltf(this->FileName))
    {
      const bool whole = this->GetReadsWholeScene();
      const bool chosen = this->AnimationIndex >= 0 || !this->AnimationName.empty();
      // Animated transforms are applied here, to parts read in their nodes' frames.
      const bool applyTransforms = chosen && whole && this->ApplyAnimation != ANIMATION_NOT_APPLIED;
      const bool applyWeights = chosen && this->ApplyAnimation == ANIMATION_TRANSFORMS_AND_WEIGHTS;
      const std::shared_ptr<const morphnode::GltfScene> scenePointer = this->LoadScene(whole && !applyTransforms);
      const morphnode::GltfScene& scene = *scenePointer;
      this->UpdateProgress(0.5);
      for (size_t m = 0; m < scene.Meshes.size(); ++m)
      {
        this->MeshNames.push_back(MeshNameOf(scene, m));
      }
      if (scene.Parts.empty())
      {
        throw InputError("'" + this->FileName + "' has no mesh on a node of its scene");
      }

      // The scene at the time requested (the rest pose without animation).
      const int animation = this->ResolveAnimation(scene);
      morphnode::GltfSceneSample sample;
      std::vector<int> animatedNodes;
      double time = 0.0;
      if (animation >= 0)
      {
        const morphnode::GltfAnimationPlayer player(scene, animation, this->FileName);
        time = player.GetStartTime();
        for (int port = 0; port < 2; ++port)
        {
          vtkInformation* outInfo = outputVector->GetInformationObject(port);
          if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
          {
            time = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
            break;
          }
        }
        if (!std::isfinite(time))
        {
          throw InputError("the time requested is not a finite number");
        }
        sample = player.Sample(time);
        animatedNodes = player.GetAnimatedNodes();
      }
      else
      {
        sample = morphnode::GltfRestPose(scene);
      }
      // Node transforms at the time sampled: skins pose their parts with them, and skinned
      // parts carry them as the rest of their skeleton (vtkMorphSkinArrays.h).
      std::vector<morphnode::GltfMatrix> worlds, locals;
      for (size_t n = 0; n < scene.Nodes.size(); ++n)
      {
        const bool sampled = applyTransforms && n < sample.Nodes.size();
        worlds.push_back(sampled ? sample.Nodes[n].World : scene.Nodes[n].World);
        locals.push_back(sampled ? sample.Nodes[n].Local : scene.Nodes[n].Local);
      }
      auto prepare = [&](const morphnode::GltfPart& part) {
        const morphnode::GltfNodeSample& node = sample.Nodes[static_cast<size_t>(part.Node)];
        morphnode::GltfPart posed = part;
        if (applyWeights)
        {
          BlendWeights(posed, node.Weights);
        }
        if (applyTransforms && posed.Skin >= 0)
        {
          morphnode::GltfSkinPart(posed, scene, worlds, this->FileName); // gltf/GltfSkin.h
        }
        else if (applyTransforms)
        {
          morphnode::GltfTransformPart(posed, node.World);
          posed.World = node.World;
        }
        return posed;
      };
      auto addWeightFields = [&](vtkFieldData* fd, const morphnode::GltfPart& part) {
        AddDoubles(fd, "DefaultWeights", part.DefaultWeights.data(), static_cast<int>(part.DefaultWeights.size()));
        if (applyWeights)
        {
          const std::vector<double>& w = sample.Nodes[static_cast<size_t>(part.Node)].Weights;
          AddDoubles(fd, "AppliedWeights", w.data(), static_cast<int>(std::min(w.size(), part.Targets.size())));
        }
      };

      // Port 1: weights by target name, and the animated nodes' TRS.
      std::vector<std::string> weightNames;
      std::vector<double> weightValues;

      if (whole)
      {
        auto* collection = vtkPartitionedDataSetCollection::SafeDownCast(output);
        if (!collection)
        {
          throw InputError("internal: the output is not a vtkPartitionedDataSetCollection");
        }
        collection->Initialize();
        collection->SetNumberOfPartitionedDataSets(static_cast<unsigned int>(scene.Parts.size()));
        std::unordered_set<std::string> seen;
        for (size_t p = 0; p < scene.Parts.size(); ++p)
        {
          const morphnode::GltfPart part = prepare(scene.Parts[p]);
          const std::vector<std::string> names = TargetNamesOf(part);
          auto poly = PartToPolyData(part);
          FinishMesh(poly, names, this->Scale, this->NormalsMode);
          AddPartFieldData(poly->GetFieldData(), scene, part, true, this->Scale);
          AddMaterial(poly, scene, part, this->FileName);
          addWeightFields(poly->GetFieldData(), part);
          if (part.Skin >= 0)
          {
            vtkMorphSkinArrays::AddSkin(poly, scene, part, locals, this->Scale);
          }
          collection->SetPartition(static_cast<unsigned int>(p), 0, poly);
          collection->GetMetaData(static_cast<unsigned int>(p))->Set(vtkCompositeDataSet::NAME(), part.Name.c_str());
          this->PartNames.push_back(part.Name);
          if (this->TargetNames.empty())
          {
            this->TargetNames.push_back(names[0]);
            seen.insert(names[0]);
          }
          for (size_t k = 1; k < names.size(); ++k)
          {
            if (seen.insert(names[k]).second)
            {
              this->TargetNames.push_back(names[k]);
            }
          }
          this->UpdateProgress(0.5 + 0.5 * double(p + 1) / double(scene.Parts.size()));
        }
        collection->SetDataAssembly(MakeAssembly(scene, this->FileName));
        arrays::SetTargetNames(collection->GetFieldData(), this->TargetNames);
        const morphnode::GltfNamedWeights named = morphnode::GltfWeightsByTargetName(scene, sample);
        weightNames = named.Names;
        weightValues = named.Values;
      }
      else
      {
        auto* poly = vtkPolyData::SafeDownCast(output);
        if (!poly)
        {
          throw InputError("internal: the output is not a vtkPolyData");
        }
        const morphnode::GltfPart& selected = SelectPart(
          scene, this->MeshNames, this->FileName, this->MeshName, this->MeshIndex, this->PrimitiveIndex);
        const morphnode::GltfPart part = prepare(selected);
        const std::vector<std::string> names = TargetNamesOf(part);
        poly->ShallowCopy(PartToPolyData(part));
        FinishMesh(poly, names, this->Scale, this->NormalsMode);
        AddPartFieldData(poly->GetFieldData(), scene, part, false, this->Scale);
        AddMaterial(poly, scene, part, this->FileName);
        addWeightFields(poly->GetFieldData(), part);
        this->TargetNames = names;
        this->PartNames.push_back(part.Name);
        const std::vector<double>& w = sample.Nodes[static_cast<size_t>(part.Node)].Weights;
        for (size_t k = 0; k < part.Targets.size() && k < w.size(); ++k)
        {
          weightNames.push_back(part.Targets[k].Name);
          weightValues.push_back(w[k]);
        }
      }

      for (size_t k = 0; k < weightNames.size(); ++k)
      {
        AddColumn(weightsOutput, weightNames[k], &weightValues[k], 1);
      }
      for (int n : animatedNodes)
      {
        const morphnode::GltfNodeSample& node = sample.Nodes[static_cast<size_t>(n)];
        const std::string name = NodeNameOf(scene, n);
        if (node.TranslationAnimated)
        {
          const double t[3] = { this->Scale * node.Translation[0], this->Scale * node.Translation[1],
            this->Scale * node.Translation[2] };
          AddColumn(weightsOutput, name + ".translation", t, 3);
        }
        if (node.RotationAnimated)
        {
          AddColumn(weightsOutput, name + ".rotation", node.Rotation.data(), 4);
        }
        if (node.ScaleAnimated)
        {
          AddColumn(weightsOutput, name + ".scale", node.Scale.data(), 3);
        }
      }
      AddDoubles(weightsOutput->GetFieldData(), "Time", &time, 1);
      std::string animationName;
      if (animation >= 0)
      {
        animationName = scene.Animations[static_cast<size_t>(animation)].Name;
        if (animationName.empty())
        {
          animationName = "animation" + std::to_string(animation);
        }
      }
      AddString(weightsOutput->GetFieldData(), "AnimationName", animationName);
      if (animation >= 0)
      {
        output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), time);
        weightsOutput->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), time);
      }
    }
    else if (EndsWith(morphnode::text::ToLower(this->FileName), ".obj") ||
      std::filesystem::is_directory(this->FileName))
    {
      auto* poly = vtkPolyData::SafeDownCast(output);
      if (!poly)
      {
        throw InputError("internal: the output is not a vtkPolyData");
      }
      this->ReadObjSet(poly);
      FinishMesh(poly, this->TargetNames, this->Scale, this->NormalsMode);
      this->PartNames.push_back(std::filesystem::path(this->FileName).stem().string());
    }
    else
    {
      throw InputError("'" + this->FileName + "': expected a .glb or .gltf file, an OBJ set's "
                                              "folder or its neutral .obj");
    }
    this->UpdateProgress(1.0);
    return 1;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    if (weightsOutput)
    {
      weightsOutput->Initialize();
    }
    this->TargetNames.clear();
    this->PartNames.clear();
    return 0;
  }
}

//------------------------------------------------------------------------------
void vtkMorphTargetReader::ReadObjSet(vtkPolyData* output)
{
  namespace fs = std::filesystem;
  fs::path folder = this->FileName;
  std::string neutral = this->NeutralFileName;
  if (!fs::is_directory(folder))
  {
    neutral = folder.filename().string();
    folder = folder.parent_path();
  }
  else if (neutral.empty())
  {
    neutral = fs::exists(folder / "generic_neutral_mesh.obj") ? "generic_neutral_mesh.obj" : "neutral.obj";
  }
  const morphnode::MorphMesh set = morphnode::ReadObjSetDirectory(folder.string(), neutral);
  output->ShallowCopy(arrays::ToPolyData(set));
  this->TargetNames = set.GetTargetNames();
}

//------------------------------------------------------------------------------
void vtkMorphTargetReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "MeshName: " << this->MeshName << "\n";
  os << indent << "MeshIndex: " << this->MeshIndex << "\n";
  os << indent << "PrimitiveIndex: " << this->PrimitiveIndex << "\n";
  os << indent << "ReadsWholeScene: " << (this->GetReadsWholeScene() ? "yes" : "no") << "\n";
  os << indent << "NeutralFileName: " << this->NeutralFileName << "\n";
  os << indent << "Scale: " << this->Scale << "\n";
  os << indent << "NormalsMode: " << this->NormalsMode << "\n";
  os << indent << "AnimationName: " << this->AnimationName << "\n";
  os << indent << "AnimationIndex: " << this->AnimationIndex << "\n";
  os << indent << "FrameRate: " << this->FrameRate << "\n";
  os << indent << "ApplyAnimation: " << this->ApplyAnimation << "\n";
  os << indent << "NumberOfAnimations: " << this->GetNumberOfAnimations() << "\n";
  os << indent << "ChosenAnimation: " << this->ChosenAnimation << "\n";
  os << indent << "NumberOfTargets: " << this->GetNumberOfTargets() << "\n";
  os << indent << "NumberOfParts: " << this->GetNumberOfParts() << "\n";
}
