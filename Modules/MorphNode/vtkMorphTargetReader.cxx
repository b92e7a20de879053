// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTargetReader.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "morph/MorphMesh.h"
#include "morph/Normals.h"
#include "rig/ObjSet.h"

#include "vtkCellArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGLTFDocumentLoader.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

vtkStandardNewMacro(vtkMorphTargetReader);

namespace
{
using morphnode::InputError;

std::string Lower(std::string s)
{
  for (char& c : s)
  {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return s;
}

bool EndsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// The JSON document and, for a GLB, its binary chunk.
struct GLTFFile
{
  nlohmann::json Document;
  std::vector<char> Binary;
  bool IsBinary = false;
};

uint32_t ReadU32(const std::vector<char>& bytes, size_t at)
{
  uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, sizeof(v));
  return v;
}

GLTFFile ReadGLTFFile(const std::string& fileName)
{
  std::ifstream in(fileName, std::ios::binary);
  if (!in)
  {
    throw InputError("cannot open '" + fileName + "'");
  }
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  GLTFFile file;
  std::string json;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0)
  {
    // GLB: 12-byte header, then chunks of (length, type, data).
    file.IsBinary = true;
    if (bytes.size() < 20 || ReadU32(bytes, 16) != 0x4E4F534A)
    {
      throw InputError("'" + fileName + "' is a GLB file without a JSON chunk");
    }
    const size_t jsonLength = ReadU32(bytes, 12);
    if (20 + jsonLength > bytes.size())
    {
      throw InputError("'" + fileName + "': the GLB JSON chunk runs past the end of the file");
    }
    json.assign(bytes.data() + 20, jsonLength);
    const size_t binAt = 20 + jsonLength;
    if (binAt + 8 <= bytes.size())
    {
      const size_t binLength = ReadU32(bytes, binAt);
      if (ReadU32(bytes, binAt + 4) != 0x004E4942 || binAt + 8 + binLength > bytes.size())
      {
        throw InputError("'" + fileName + "': malformed GLB binary chunk");
      }
      file.Binary.assign(bytes.begin() + static_cast<long>(binAt + 8),
        bytes.begin() + static_cast<long>(binAt + 8 + binLength));
    }
  }
  else
  {
    json.assign(bytes.begin(), bytes.end());
  }
  try
  {
    file.Document = nlohmann::json::parse(json);
  }
  catch (const nlohmann::json::exception& e)
  {
    throw InputError("'" + fileName + "' is not valid glTF JSON: " + e.what());
  }
  return file;
}

namespace arrays = vtkMorphTargetArrays;
using arrays::Kind;

vtkSmartPointer<vtkDataArray> MakeVectors(const std::string& name, const std::vector<float>& values)
{
  return arrays::NewArray(
    VTK_FLOAT, name.c_str(), 3, static_cast<vtkIdType>(values.size() / 3), values.data());
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
int vtkMorphTargetReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->TargetNames.clear();
  try
  {
    if (this->FileName.empty())
    {
      throw InputError("no file name set");
    }
    const std::string lower = Lower(this->FileName);
    if (EndsWith(lower, ".glb") || EndsWith(lower, ".gltf"))
    {
      this->ReadGLTF(output);
    }
    else if (EndsWith(lower, ".obj") || std::filesystem::is_directory(this->FileName))
    {
      this->ReadObjSet(output);
    }
    else
    {
      throw InputError("'" + this->FileName + "': expected a .glb or .gltf file, an OBJ set's "
                                              "folder or its neutral .obj");
    }
    this->FinishOutput(output);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    this->TargetNames.clear();
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphTargetReader::ReadGLTF(vtkPolyData* output)
{
  const GLTFFile file = ReadGLTFFile(this->FileName);
  const nlohmann::json& meshes = file.Document.value("meshes", nlohmann::json::array());
  this->MeshNames.clear();
  for (size_t m = 0; m < meshes.size(); ++m)
  {
    const auto& name = meshes[m].value("name", std::string());
    this->MeshNames.push_back(name.empty() ? "mesh" + std::to_string(m) : name);
  }
  if (this->MeshNames.empty())
  {
    throw InputError("'" + this->FileName + "' has no meshes");
  }
  size_t meshIndex = static_cast<size_t>(this->MeshIndex);
  if (!this->MeshName.empty())
  {
    auto it = std::find(this->MeshNames.begin(), this->MeshNames.end(), this->MeshName);
    if (it == this->MeshNames.end())
    {
      std::ostringstream msg;
      msg << "'" << this->FileName << "' has no mesh named '" << this->MeshName << "'; meshes:";
      for (const auto& n : this->MeshNames)
      {
        msg << " " << n;
      }
      throw InputError(msg.str());
    }
    meshIndex = static_cast<size_t>(it - this->MeshNames.begin());
  }
  if (meshIndex >= this->MeshNames.size())
  {
    std::ostringstream msg;
    msg << "mesh index " << meshIndex << " out of range: '" << this->FileName << "' has "
        << this->MeshNames.size() << " meshes";
    throw InputError(msg.str());
  }

  vtkNew<vtkGLTFDocumentLoader> loader;
  if (!loader->LoadModelMetaDataFromFile(this->FileName) || !loader->LoadModelData(file.Binary) ||
    !loader->BuildModelVTKGeometry())
  {
    throw InputError("VTK's glTF loader could not read '" + this->FileName + "'");
  }
  auto model = loader->GetInternalModel();
  const auto& mesh = model->Meshes.at(meshIndex);
  if (static_cast<size_t>(this->PrimitiveIndex) >= mesh.Primitives.size())
  {
    std::ostringstream msg;
    msg << "primitive " << this->PrimitiveIndex << " out of range: mesh '" << this->MeshNames[meshIndex]
        << "' has " << mesh.Primitives.size();
    throw InputError(msg.str());
  }
  vtkPolyData* geometry = mesh.Primitives[static_cast<size_t>(this->PrimitiveIndex)].Geometry;
  if (!geometry || geometry->GetNumberOfPoints() == 0)
  {
    throw InputError("mesh '" + this->MeshNames[meshIndex] + "' has no points");
  }
  output->ShallowCopy(geometry);

  const size_t numTargets = arrays::CountTargets(output->GetPointData(), output->GetNumberOfPoints());
  std::vector<std::string> names = morphnode::DefaultTargetNames(numTargets + 1);
  const auto& extras = meshes[meshIndex].value("extras", nlohmann::json::object());
  if (extras.contains("targetNames"))
  {
    const auto& given = extras["targetNames"];
    if (!given.is_array() || given.size() != numTargets)
    {
      std::ostringstream msg;
      msg << "mesh '" << this->MeshNames[meshIndex] << "': extras.targetNames has "
          << (given.is_array() ? given.size() : 0) << " names for " << numTargets
          << " targets; using target<k> names";
      vtkWarningMacro(<< msg.str());
    }
    else
    {
      for (size_t k = 0; k < numTargets; ++k)
      {
        if (!given[k].is_string())
        {
          throw InputError("extras.targetNames[" + std::to_string(k) + "] is not a string");
        }
        names[k + 1] = given[k].get<std::string>();
      }
    }
  }
  this->TargetNames = names;
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
void vtkMorphTargetReader::FinishOutput(vtkPolyData* output)
{
  const size_t numPoints = static_cast<size_t>(output->GetNumberOfPoints());
  const size_t numTargets = this->TargetNames.size() - 1;
  vtkPointData* pd = output->GetPointData();

  if (this->Scale != 1.0)
  {
    // New arrays: the geometry's may be shared with the glTF loader.
    auto scaled = [&](vtkDataArray* array) {
      std::vector<double> values = arrays::ToVector<double>(array);
      for (double& v : values)
      {
        v *= this->Scale;
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
  const bool compute = this->NormalsMode == NORMALS_ALWAYS ||
    (this->NormalsMode == NORMALS_WHEN_MISSING && !complete);
  if (compute)
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

  arrays::SetTargetNames(output->GetFieldData(), this->TargetNames);
}

//------------------------------------------------------------------------------
void vtkMorphTargetReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "MeshName: " << this->MeshName << "\n";
  os << indent << "NeutralFileName: " << this->NeutralFileName << "\n";
  os << indent << "MeshIndex: " << this->MeshIndex << "\n";
  os << indent << "PrimitiveIndex: " << this->PrimitiveIndex << "\n";
  os << indent << "Scale: " << this->Scale << "\n";
  os << indent << "NormalsMode: " << this->NormalsMode << "\n";
  os << indent << "NumberOfTargets: " << this->GetNumberOfTargets() << "\n";
}
