// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTargetReader.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/Text.h"
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
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
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
  polys->AllocateExact(static_cast<vtkIdType>(numTriangles), static_cast<vtkIdType>(3 * numTriangles));
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

} // namespace

//------------------------------------------------------------------------------
vtkMorphTargetReader::vtkMorphTargetReader()
{
  this->SetNumberOfInputPorts(0);
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
int vtkMorphTargetReader::FillOutputPortInformation(int, vtkInformation* info)
{
  // A vtkPolyData or, for a whole scene, a vtkPartitionedDataSetCollection.
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkDataObject");
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
  this->TargetNames.clear();
  this->PartNames.clear();
  this->MeshNames.clear();
  try
  {
    if (this->FileName.empty())
    {
      throw InputError("no file name set");
    }
    this->UpdateProgress(0.0);
    if (IsGltf(this->FileName))
    {
      const bool whole = this->GetReadsWholeScene();
      morphnode::GltfLoadOptions options;
      options.ApplyTransforms = whole;
      const morphnode::GltfScene scene = morphnode::LoadGltfScene(this->FileName, options);
      this->UpdateProgress(0.5);
      for (size_t m = 0; m < scene.Meshes.size(); ++m)
      {
        this->MeshNames.push_back(MeshNameOf(scene, m));
      }
      if (scene.Parts.empty())
      {
        throw InputError("'" + this->FileName + "' has no mesh on a node of its scene");
      }
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
          const morphnode::GltfPart& part = scene.Parts[p];
          const std::vector<std::string> names = TargetNamesOf(part);
          auto poly = PartToPolyData(part);
          FinishMesh(poly, names, this->Scale, this->NormalsMode);
          AddPartFieldData(poly->GetFieldData(), scene, part, true, this->Scale);
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
      }
      else
      {
        auto* poly = vtkPolyData::SafeDownCast(output);
        if (!poly)
        {
          throw InputError("internal: the output is not a vtkPolyData");
        }
        const morphnode::GltfPart& part = SelectPart(
          scene, this->MeshNames, this->FileName, this->MeshName, this->MeshIndex, this->PrimitiveIndex);
        const std::vector<std::string> names = TargetNamesOf(part);
        poly->ShallowCopy(PartToPolyData(part));
        FinishMesh(poly, names, this->Scale, this->NormalsMode);
        AddPartFieldData(poly->GetFieldData(), scene, part, false, this->Scale);
        this->TargetNames = names;
        this->PartNames.push_back(part.Name);
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
  os << indent << "NumberOfTargets: " << this->GetNumberOfTargets() << "\n";
  os << indent << "NumberOfParts: " << this->GetNumberOfParts() << "\n";
}
