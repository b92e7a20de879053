// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTargetReader.h"

#include "vtkMorphPartData.h"
#include "vtkMorphSkinArrays.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gltf/GltfAnimation.h"
#include "gltf/GltfPose.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfVrm.h"
#include "morph/MorphMesh.h"
#include "morph/Normals.h"
#include "rig/ObjSet.h"

#include "vtkCellArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataAssembly.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <system_error>

vtkStandardNewMacro(vtkMorphTargetReader);

namespace
{
using morphnode::InputError;
namespace arrays = vtkMorphTargetArrays;
namespace partdata = vtkMorphPartData;
using arrays::Kind;

bool IsGltf(const std::string& fileName)
{
  return morphnode::text::HasExtension(fileName, ".glb") ||
    morphnode::text::HasExtension(fileName, ".gltf");
}

vtkSmartPointer<vtkDataArray> MakeVectors(const std::string& name, const std::vector<float>& values)
{
  return arrays::NewArray(
    VTK_FLOAT, name.c_str(), 3, static_cast<vtkIdType>(values.size() / 3), values.data());
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
  polys->AllocateExact(
    static_cast<vtkIdType>(numTriangles), 3 * static_cast<vtkIdType>(numTriangles));
  for (size_t t = 0; t < numTriangles; ++t)
  {
    const vtkIdType ids[3] = { part.Triangles[3 * t], part.Triangles[3 * t + 1],
      part.Triangles[3 * t + 2] };
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
void FinishMesh(
  vtkPolyData* output, const std::vector<std::string>& targetNames, double scale, int normalsMode)
{
  const size_t numPoints = static_cast<size_t>(output->GetNumberOfPoints());
  const size_t numTargets = targetNames.size() - 1;
  vtkPointData* pd = output->GetPointData();

  if (scale != 1.0)
  {
    // New arrays: the geometry's may be shared.
    auto scaled = [&](vtkDataArray* array)
    {
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
    const std::vector<float> normals = morphnode::ComputeVertexNormals(
      base.data(), numPoints, triangles.data(), triangles.size() / 3);
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
        morphnode::ComputeNormalDeltas(
          base.data(), delta.data(), normals, numPoints, triangles.data(), triangles.size() / 3)));
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

/// The node tree of the scene as a data assembly, each part's index on its node.
vtkSmartPointer<vtkDataAssembly> MakeAssembly(
  const morphnode::GltfScene& scene, const std::string& fileName)
{
  auto assembly = vtkSmartPointer<vtkDataAssembly>::New();
  std::string root = scene.SceneName;
  if (root.empty())
  {
    root = std::filesystem::path(fileName).stem().string();
  }
  assembly->SetRootNodeName(
    vtkDataAssembly::MakeValidNodeName(root.empty() ? "Scene" : root.c_str()).c_str());
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
      vtkDataAssembly::MakeValidNodeName(morphnode::GltfNodeName(scene, node).c_str()).c_str(),
      parent);
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

void AddColumn(vtkTable* table, const std::string& name, const double* values, int components)
{
  vtkNew<vtkDoubleArray> column;
  column->SetName(name.c_str());
  column->SetNumberOfComponents(components);
  column->SetNumberOfTuples(1);
  std::copy_n(values, components, column->GetPointer(0));
  table->AddColumn(column);
}

/// A posed part in the convention with the part's field data (vtkMorphPartData.h): its
/// weights, and for a part of a whole scene its world frame and skin.
vtkSmartPointer<vtkPolyData> PartOutput(const morphnode::GltfScene& scene,
  const morphnode::GltfPose& pose, const morphnode::GltfPart& part, bool whole, double scale,
  int normalsMode, const morphnode::GltfVrm& vrm)
{
  auto poly = PartToPolyData(part);
  FinishMesh(poly, TargetNamesOf(part), scale, normalsMode);
  vtkFieldData* fd = poly->GetFieldData();
  partdata::SetPartFields(fd, partdata::FromGltfPart(scene, part, whole, scale));
  partdata::SetMaterial(poly, scene, part, pose.Options.Source);
  partdata::SetNumbers(fd, partdata::DefaultWeightsArray, part.DefaultWeights.data(),
    static_cast<int>(part.DefaultWeights.size()));
  if (pose.Options.ApplyWeights)
  {
    const std::vector<double>& w = pose.Sample.Nodes[static_cast<size_t>(part.Node)].Weights;
    partdata::SetNumbers(fd, partdata::AppliedWeightsArray, w.data(),
      static_cast<int>(std::min(w.size(), part.Targets.size())));
  }
  if (whole && part.Skin >= 0)
  {
    vtkMorphSkinArrays::AddSkin(poly, scene, part, pose.Locals, scale);
    vtkMorphSkinArrays::AddVrm(poly, vrm);
  }
  return poly;
}

/// Port 1: one row of weights by target name, the animated nodes' TRS (`<node>.translation`
/// scaled, `.rotation`, `.scale`), field data Time and AnimationName.
void FillWeights(vtkTable* table, const morphnode::GltfScene& scene,
  const morphnode::GltfPose& pose, const std::vector<std::string>& names,
  const std::vector<double>& values, double scale)
{
  for (size_t k = 0; k < names.size(); ++k)
  {
    AddColumn(table, names[k], &values[k], 1);
  }
  for (int n : pose.AnimatedNodes)
  {
    const morphnode::GltfNodeSample& node = pose.Sample.Nodes[static_cast<size_t>(n)];
    const std::string name = morphnode::GltfNodeName(scene, n);
    if (node.TranslationAnimated)
    {
      const double t[3] = { scale * node.Translation[0], scale * node.Translation[1],
        scale * node.Translation[2] };
      AddColumn(table, name + ".translation", t, 3);
    }
    if (node.RotationAnimated)
    {
      AddColumn(table, name + ".rotation", node.Rotation.data(), 4);
    }
    if (node.ScaleAnimated)
    {
      AddColumn(table, name + ".scale", node.Scale.data(), 3);
    }
  }
  partdata::SetNumbers(table->GetFieldData(), "Time", &pose.Time, 1);
  const int animation = pose.Options.Animation;
  partdata::SetString(table->GetFieldData(), "AnimationName",
    animation >= 0 ? morphnode::GltfAnimationName(scene, static_cast<size_t>(animation))
                   : std::string());
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
    cache->ApplyTransforms == applyTransforms && cache->WriteTime == writeTime &&
    cache->Size == size && cache->ReaderTime == this->GetMTime())
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
  auto scene =
    std::make_shared<const morphnode::GltfScene>(morphnode::LoadGltfScene(this->FileName, options));
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
      if (morphnode::GltfAnimationName(scene, a) == this->AnimationName)
      {
        return static_cast<int>(a);
      }
    }
    std::ostringstream msg;
    msg << "'" << this->FileName << "' has no animation named '" << this->AnimationName
        << "'; animations:";
    for (size_t a = 0; a < scene.Animations.size(); ++a)
    {
      msg << " " << morphnode::GltfAnimationName(scene, a);
    }
    if (scene.Animations.empty())
    {
      msg << " none";
    }
    throw InputError(msg.str());
  }
  if (this->AnimationIndex >= 0 &&
    static_cast<size_t>(this->AnimationIndex) >= scene.Animations.size())
  {
    throw InputError("animation index " + std::to_string(this->AnimationIndex) +
      " out of range: '" + this->FileName + "' has " + std::to_string(scene.Animations.size()) +
      " animations");
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
        this->AnimationNames.push_back(morphnode::GltfAnimationName(*scene, a));
      }
      const int chosen = this->ResolveAnimation(*scene);
      if (chosen >= 0)
      {
        const morphnode::GltfAnimationPlayer player(*scene, chosen, this->FileName);
        steps = morphnode::GltfTimeSteps(player, this->FrameRate);
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
      outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps.data(),
        static_cast<int>(steps.size()));
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
      this->ReadGltf(output, weightsOutput, outputVector);
    }
    else if (morphnode::text::HasExtension(this->FileName, ".obj") ||
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
      throw InputError("'" + this->FileName +
        "': expected a .glb or .gltf file, an OBJ set's "
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
void vtkMorphTargetReader::ReadGltf(
  vtkDataObject* output, vtkTable* weightsOutput, vtkInformationVector* outputVector)
{
  const bool whole = this->GetReadsWholeScene();
  morphnode::GltfPoseOptions options;
  options.Source = this->FileName;
  const bool chosen = this->AnimationIndex >= 0 || !this->AnimationName.empty();
  // Animated transforms are applied to parts read in their nodes' frames.
  options.ApplyTransforms = chosen && whole && this->ApplyAnimation != ANIMATION_NOT_APPLIED;
  options.ApplyWeights = chosen && this->ApplyAnimation == ANIMATION_TRANSFORMS_AND_WEIGHTS;
  const auto scenePointer = this->LoadScene(whole && !options.ApplyTransforms);
  const morphnode::GltfScene& scene = *scenePointer;
  this->UpdateProgress(0.5);
  for (size_t m = 0; m < scene.Meshes.size(); ++m)
  {
    this->MeshNames.push_back(morphnode::GltfMeshName(scene, m));
  }
  if (scene.Parts.empty())
  {
    throw InputError("'" + this->FileName + "' has no mesh on a node of its scene");
  }
  options.Animation = this->ResolveAnimation(scene);
  for (int port = 0; port < 2 && !options.Time; ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      options.Time = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    }
  }
  const morphnode::GltfPose pose = morphnode::PoseGltfScene(scene, options);

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
    // A VRM avatar's humanoid bones and look-at (its extension JSON; none for others).
    morphnode::GltfVrm vrm;
    try
    {
      if (std::any_of(scene.Parts.begin(), scene.Parts.end(),
            [](const morphnode::GltfPart& q) { return q.Skin >= 0; }))
      {
        vrm = morphnode::ReadGltfVrm(this->FileName);
      }
    }
    catch (const std::exception& e)
    {
      vtkWarningMacro(<< "the VRM description of " << this->FileName
                      << " is not used: " << e.what());
    }
    for (size_t p = 0; p < scene.Parts.size(); ++p)
    {
      const morphnode::GltfPart part = morphnode::PoseGltfPart(scene, pose, scene.Parts[p]);
      collection->SetPartition(static_cast<unsigned int>(p), 0,
        PartOutput(scene, pose, part, true, this->Scale, this->NormalsMode, vrm));
      collection->GetMetaData(static_cast<unsigned int>(p))
        ->Set(vtkCompositeDataSet::NAME(), part.Name.c_str());
      this->PartNames.push_back(part.Name);
      this->UpdateProgress(0.5 + 0.5 * double(p + 1) / double(scene.Parts.size()));
    }
    // The neutral, then the parts' targets (a target named like the neutral is the neutral).
    const std::string neutral = morphnode::DefaultTargetNames(1)[0];
    this->TargetNames = { neutral };
    for (const std::string& name : morphnode::GltfTargetNames(scene))
    {
      if (name != neutral)
      {
        this->TargetNames.push_back(name);
      }
    }
    collection->SetDataAssembly(MakeAssembly(scene, this->FileName));
    arrays::SetTargetNames(collection->GetFieldData(), this->TargetNames);
    const morphnode::GltfNamedWeights named =
      morphnode::GltfWeightsByTargetName(scene, pose.Sample);
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
    const morphnode::GltfPart part = morphnode::PoseGltfPart(scene, pose,
      morphnode::FindGltfPart(
        scene, this->MeshName, this->MeshIndex, this->PrimitiveIndex, this->FileName));
    poly->ShallowCopy(
      PartOutput(scene, pose, part, false, this->Scale, this->NormalsMode, morphnode::GltfVrm{}));
    this->TargetNames = TargetNamesOf(part);
    this->PartNames.push_back(part.Name);
    const std::vector<double>& w = pose.Sample.Nodes[static_cast<size_t>(part.Node)].Weights;
    for (size_t k = 0; k < part.Targets.size() && k < w.size(); ++k)
    {
      weightNames.push_back(part.Targets[k].Name);
      weightValues.push_back(w[k]);
    }
  }
  FillWeights(weightsOutput, scene, pose, weightNames, weightValues, this->Scale);
  if (options.Animation >= 0)
  {
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), pose.Time);
    weightsOutput->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), pose.Time);
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
    neutral =
      fs::exists(folder / "generic_neutral_mesh.obj") ? "generic_neutral_mesh.obj" : "neutral.obj";
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
