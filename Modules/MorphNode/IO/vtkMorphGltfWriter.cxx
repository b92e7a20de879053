// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphGltfWriter.h"

#include "vtkMorphPartData.h"
#include "vtkMorphSkinArrays.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/File.h"
#include "base/Text.h"
#include "behavior/HeadPose.h"
#include "gltf/GltfPerformanceExport.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfSkin.h"

#include "vtkAbstractArray.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMorphGltfWriter);

namespace
{
namespace arrays = vtkMorphTargetArrays;
namespace partdata = vtkMorphPartData;

std::vector<float> ToFloats(vtkDataArray* a)
{
  return arrays::ToVector<float>(a);
}

/// One leaf as a glTF part (world space) and its node name.
morphnode::GltfPart ToPart(
  vtkPolyData* poly, const std::string& fallbackName, std::string& nodeName)
{
  morphnode::GltfPart part;
  vtkFieldData* fd = poly->GetFieldData();
  const partdata::PartFields fields = partdata::GetPartFields(fd);
  part.Name = fields.PartName.empty() ? fallbackName : fields.PartName;
  nodeName = fields.NodeName.empty() ? part.Name : fields.NodeName;
  part.MaterialName = fields.MaterialName;
  if (fields.BaseColor)
  {
    std::copy(fields.BaseColor->begin(), fields.BaseColor->end(), part.BaseColor.begin());
    part.Material = 0; // a material of its own (its index is the writer's business)
  }
  part.TransformApplied = true;
  const vtkIdType n = poly->GetNumberOfPoints();
  if (n == 0 || !poly->GetPoints())
  {
    throw morphnode::InputError("part '" + part.Name + "' has no points");
  }
  part.Positions = ToFloats(poly->GetPoints()->GetData());
  vtkPointData* pd = poly->GetPointData();
  if (vtkDataArray* normals = pd->GetNormals())
  {
    if (normals->GetNumberOfComponents() != 3 || normals->GetNumberOfTuples() != n)
    {
      throw morphnode::InputError("part '" + part.Name + "': its normals are not 3 per point");
    }
    part.Normals = ToFloats(normals);
  }
  if (vtkDataArray* colors = pd->GetArray("COLOR_0"))
  {
    const int nc = colors->GetNumberOfComponents();
    if ((nc != 3 && nc != 4) || colors->GetNumberOfTuples() != n)
    {
      throw morphnode::InputError(
        "part '" + part.Name + "': COLOR_0 must be RGB or RGBA per point");
    }
    const double scale = colors->GetDataType() == VTK_UNSIGNED_CHAR ? 1.0 / 255.0
      : colors->GetDataType() == VTK_UNSIGNED_SHORT                 ? 1.0 / 65535.0
                                                                    : 1.0;
    part.Colors.resize(4 * static_cast<size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int c = 0; c < 4; ++c)
      {
        part.Colors[4 * i + c] =
          c < nc ? static_cast<float>(colors->GetComponent(i, c) * scale) : 1.0f;
      }
    }
  }
  // The texture coordinates the reader gave the part (its base colour texture's set), written
  // as TEXCOORD_0 for the source file's material (see RequestData).
  if (vtkDataArray* tc = pd->GetTCoords())
  {
    if (tc->GetNumberOfComponents() == 2 && tc->GetNumberOfTuples() == n)
    {
      part.TexCoords0 = ToFloats(tc);
    }
  }
  part.Triangles = arrays::GetTriangles(poly, true);
  if (arrays::HasTargets(pd))
  {
    const size_t count = arrays::CountTargets(pd, n);
    const std::vector<std::string> names = arrays::GetTargetNames(fd, count + 1);
    arrays::CheckUniqueNames(names);
    const bool normalDeltas = !part.Normals.empty();
    for (size_t k = 0; k < count; ++k)
    {
      morphnode::GltfTarget target;
      target.Name = names[k + 1];
      target.PositionDeltas = ToFloats(arrays::GetDeltas(pd, k, arrays::Kind::Position, n));
      if (normalDeltas)
      {
        if (vtkDataArray* d = arrays::GetDeltas(pd, k, arrays::Kind::Normal, n))
        {
          target.NormalDeltas = ToFloats(d);
        }
      }
      part.Targets.push_back(std::move(target));
    }
    // glTF needs the same attributes in every target of a primitive.
    const bool all = std::all_of(part.Targets.begin(), part.Targets.end(),
      [](const morphnode::GltfTarget& t) { return !t.NormalDeltas.empty(); });
    if (!all)
    {
      for (auto& t : part.Targets)
      {
        t.NormalDeltas.clear();
      }
    }
  }
  part.DefaultWeights.assign(part.Targets.size(), 0.0);
  return part;
}

/// A column of the table as doubles, or empty when absent or not numeric.
std::vector<double> Column(vtkTable* table, const char* name)
{
  auto* a = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
  std::vector<double> values;
  if (a && a->GetNumberOfComponents() == 1)
  {
    values.resize(static_cast<size_t>(a->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    {
      values[static_cast<size_t>(i)] = a->GetComponent(i, 0);
    }
  }
  return values;
}

std::vector<std::string> SplitNames(const char* text)
{
  std::vector<std::string> names;
  std::istringstream in(text ? text : "");
  std::string name;
  while (in >> name)
  {
    names.push_back(name);
  }
  return names;
}

/// The input's poly data leaves with points.
std::vector<vtkPolyData*> Leaves(vtkDataObject* input)
{
  std::vector<vtkPolyData*> leaves;
  if (auto* poly = vtkPolyData::SafeDownCast(input))
  {
    leaves.push_back(poly);
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    for (vtkDataObject* node : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      auto* leaf = vtkPolyData::SafeDownCast(node);
      if (!leaf)
      {
        throw morphnode::InputError(
          std::string("a leaf is a ") + node->GetClassName() + ", not a vtkPolyData");
      }
      if (leaf->GetNumberOfPoints() > 0)
      {
        leaves.push_back(leaf);
      }
    }
  }
  else
  {
    throw morphnode::InputError(std::string("the input is a ") +
      (input ? input->GetClassName() : "null object") +
      ", not a vtkPolyData or a composite data set of them");
  }
  if (leaves.empty())
  {
    throw morphnode::InputError("the input has no points");
  }
  return leaves;
}

/// The leaves as a scene in their nodes' frames. Skinned leaves (vtkMorphSkinArrays.h: shown
/// at rest in world space) bring their skeleton as the scene's nodes, their skin and
/// influences, and go back to bind space (morphnode::GltfUnskinPart), so that the file
/// keeps the avatar's skeleton and skins. Other leaves are grouped into root nodes without
/// transform by NodeName (and by their targets, which glTF makes the same for every
/// primitive of a mesh). `frames`: each node's centre and axes (the leaves' NodeOrigin and
/// NodeAxes; a joint's from its rest transform); `bounds`: of every leaf; `humanoid` and
/// `rangeMaps`: a VRM avatar's bones and look-at (vtkMorphSkinArrays.h).
morphnode::GltfScene ToScene(const std::vector<vtkPolyData*>& leaves,
  std::vector<morphnode::GltfNodeFrame>& frames, double bounds[6],
  std::map<std::string, std::string>& humanoid, morphnode::EyeRangeMaps& rangeMaps)
{
  namespace skin = vtkMorphSkinArrays;
  morphnode::GltfScene scene;
  scene.SceneName = "MorphNode";
  for (int k = 0; k < 3; ++k)
  {
    bounds[2 * k] = VTK_DOUBLE_MAX;
    bounds[2 * k + 1] = -VTK_DOUBLE_MAX;
  }
  // The skeleton first, from the first skinned leaf: its joints are nodes 0 .. n-1.
  morphnode::Skeleton skeleton;
  for (vtkPolyData* leaf : leaves)
  {
    if (skin::IsSkinned(leaf))
    {
      skeleton = skin::GetSkin(leaf, "skinned part").Bones;
      scene.Nodes = morphnode::GltfNodesFromSkeleton(skeleton);
      break;
    }
  }
  const size_t joints = scene.Nodes.size();
  for (const auto& node : scene.Nodes)
  {
    const morphnode::GltfMatrix& w = node.World;
    frames.push_back({ { { w[12], w[13], w[14] } },
      { { w[0], w[1], w[2], w[4], w[5], w[6], w[8], w[9], w[10] } } });
  }
  std::vector<morphnode::GltfMatrix> worlds;
  for (const auto& node : scene.Nodes)
  {
    worlds.push_back(node.World);
  }
  std::vector<std::vector<std::string>> nodeTargets(joints);
  for (size_t i = 0; i < leaves.size(); ++i)
  {
    vtkPolyData* leaf = leaves[i];
    std::string nodeName;
    morphnode::GltfPart part = ToPart(leaf, "part" + std::to_string(i), nodeName);
    std::vector<std::string> targets;
    for (const auto& t : part.Targets)
    {
      targets.push_back(t.Name);
    }
    double b[6];
    leaf->GetBounds(b);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
    }
    int node = -1;
    if (skin::IsSkinned(leaf))
    {
      skin::Skin s = skin::GetSkin(leaf, part.Name);
      if (humanoid.empty())
      {
        humanoid = s.Humanoid;
        rangeMaps = s.RangeMaps;
      }
      bool same = s.Bones.GetNumberOfJoints() == joints;
      for (size_t j = 0; same && j < joints; ++j)
      {
        same = s.Bones.GetJoint(j).Name == scene.Nodes[j].Name &&
          s.Bones.GetJoint(j).Parent == scene.Nodes[j].Parent;
      }
      if (!same)
      {
        throw morphnode::InputError(
          "part '" + part.Name + "' is skinned to another skeleton than the first skinned part");
      }
      morphnode::GltfSkin gskin;
      gskin.Joints = s.Joints.Joints;
      for (const auto& m : s.Joints.InverseBind)
      {
        gskin.InverseBind.push_back(morphnode::GltfFromGlm(m));
      }
      int index = -1;
      for (size_t k = 0; k < scene.Skins.size(); ++k)
      {
        if (scene.Skins[k].Joints == gskin.Joints &&
          scene.Skins[k].InverseBind == gskin.InverseBind)
        {
          index = static_cast<int>(k);
        }
      }
      if (index < 0)
      {
        scene.Skins.push_back(std::move(gskin));
        index = static_cast<int>(scene.Skins.size() - 1);
      }
      part.Skin = index;
      part.Influences = std::move(s.Influences);
      node = skeleton.FindJoint(nodeName);
      if (node >= 0 && nodeTargets[static_cast<size_t>(node)].empty())
      {
        nodeTargets[static_cast<size_t>(node)] = targets;
      }
      morphnode::GltfUnskinPart(part, scene, worlds, "part '" + part.Name + "'");
    }
    if (node < 0)
    {
      for (size_t n = joints; n < scene.Nodes.size(); ++n)
      {
        if (scene.Nodes[n].Name == nodeName && nodeTargets[n] == targets)
        {
          node = static_cast<int>(n);
        }
      }
    }
    if (node < 0)
    {
      const bool taken = std::any_of(scene.Nodes.begin(), scene.Nodes.end(),
        [&nodeName](const morphnode::GltfNode& other) { return other.Name == nodeName; });
      morphnode::GltfNode gnode;
      gnode.Name = taken ? nodeName + "/" + part.Name : nodeName;
      gnode.InScene = true;
      scene.Nodes.push_back(gnode);
      nodeTargets.push_back(targets);
      morphnode::GltfNodeFrame frame;
      partdata::GetNodeFrame(leaf->GetFieldData(), frame.Origin, frame.Axes);
      frames.push_back(frame);
      node = static_cast<int>(scene.Nodes.size() - 1);
    }
    part.TransformApplied = false; // world space = the frame of a root without transform
    part.Node = node;
    scene.Parts.push_back(std::move(part));
  }
  return scene;
}

/// The materials and images of the file the parts were read from (vtkMorphTargetReader's
/// MaterialIndex and MaterialSource field data): the source scene's own, written back whole
/// by the core writer. Parts from several files, or a source that no longer loads, keep the
/// base colour materials made from their field data.
void AddSourceMaterials(
  morphnode::GltfScene& scene, const std::vector<vtkPolyData*>& leaves, vtkObject* self)
{
  std::string source;
  bool one = true;
  std::vector<int> indices;
  for (vtkPolyData* leaf : leaves)
  {
    const partdata::PartFields fields = partdata::GetPartFields(leaf->GetFieldData());
    const std::string& file = fields.MaterialSource;
    indices.push_back(file.empty() ? -1 : fields.MaterialIndex);
    if (!file.empty())
    {
      one = one && (source.empty() || source == file);
      source = file;
    }
  }
  if (source.empty() || !one)
  {
    return;
  }
  try
  {
    morphnode::GltfScene src = morphnode::LoadGltfScene(source);
    scene.Materials = std::move(src.Materials);
    scene.Images = std::move(src.Images);
    for (size_t i = 0; i < indices.size(); ++i)
    {
      if (indices[i] >= 0 && static_cast<size_t>(indices[i]) < scene.Materials.size())
      {
        scene.Parts[i].Material = indices[i];
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkWarningWithObjectMacro(self, << "the materials of " << source << " are not written ("
                                    << e.what() << "); base colours only");
    scene.Materials.clear();
    scene.Images.clear();
  }
}

/// Every numeric column of the performance table; the time column must be one.
morphnode::GltfPerformanceTable ToTable(vtkTable* table, const char* timeName)
{
  morphnode::GltfPerformanceTable t;
  t.Times = Column(table, timeName);
  if (t.Times.empty())
  {
    throw morphnode::InputError(
      std::string("the performance has no numeric time column '") + timeName + "'");
  }
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
  {
    const char* name = table->GetColumnName(c);
    if (!name || std::string(name) == timeName)
    {
      continue;
    }
    std::vector<double> values = Column(table, name);
    if (values.size() == t.Times.size())
    {
      t.Names.push_back(name);
      t.Columns.push_back(std::move(values));
    }
  }
  return t;
}
} // namespace

//------------------------------------------------------------------------------
vtkMorphGltfWriter::vtkMorphGltfWriter()
{
  this->SetNumberOfInputPorts(2);
  this->SetTimeArrayName("Time");
}

//------------------------------------------------------------------------------
vtkMorphGltfWriter::~vtkMorphGltfWriter()
{
  this->SetFileName(nullptr);
  this->SetTimeArrayName(nullptr);
  this->SetEyeNodeNames(nullptr);
}

//------------------------------------------------------------------------------
void vtkMorphGltfWriter::SetPerformanceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
void vtkMorphGltfWriter::SetPerformanceData(vtkTable* table)
{
  this->SetInputDataInternal(1, table);
}

//------------------------------------------------------------------------------
int vtkMorphGltfWriter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphGltfWriter::WriteData()
{
  this->NumberOfFrames = 0;
  this->NumberOfWeightColumns = 0;
  this->NumberOfParts = 0;
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro(<< "No FileName");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  vtkTable* table = this->GetNumberOfInputConnections(1) > 0 || this->GetInput(1)
    ? vtkTable::SafeDownCast(this->GetInput(1))
    : nullptr;
  try
  {
    // The output path first: a link, device or directory is refused before any work.
    morphnode::file::CheckOutputPath(this->FileName, "glTF file");
    const std::vector<vtkPolyData*> leaves = Leaves(this->GetInput(0));
    morphnode::GltfPerformanceSettings settings;
    double bounds[6];
    morphnode::GltfScene scene =
      ToScene(leaves, settings.NodeFrames, bounds, settings.Humanoid, settings.RangeMaps);
    AddSourceMaterials(scene, leaves, this);
    this->NumberOfParts = static_cast<int>(scene.Parts.size());

    morphnode::GltfPerformanceTable performance;
    const bool animated = table && table->GetNumberOfRows() > 0;
    if (animated)
    {
      performance = ToTable(table, this->TimeArrayName ? this->TimeArrayName : "Time");
    }
    settings.Interpolation = this->Interpolation == STEP ? morphnode::GltfInterpolation::Step
                                                         : morphnode::GltfInterpolation::Linear;
    settings.ApplyOptimizer = this->ApplyOptimizer;
    settings.OptimizerPreset = this->OptimizerPreset;
    settings.Threshold = this->Threshold;
    settings.MaxVertexError = this->MaxVertexError;
    settings.Hysteresis = this->Hysteresis;
    settings.HeadPose = this->WriteHeadPose;
    settings.EyeRotations = this->WriteEyeRotations;
    settings.HeadPivot = morphnode::HeadPivot(bounds);
    settings.EyeNodeNames = SplitNames(this->EyeNodeNames);
    settings.RelaxArms = this->RelaxArms;
    settings.ArmAngle = this->ArmAngle;
    morphnode::GltfWriteOptions options;
    options.Binary = !morphnode::text::HasExtension(this->FileName, ".gltf");
    morphnode::GltfPerformanceReport report;
    this->UpdateProgress(0.25);
    const std::vector<unsigned char> bytes = morphnode::WriteGltfPerformanceToMemory(
      scene, animated ? &performance : nullptr, settings, options, &report);
    if (animated && report.WeightColumns == 0)
    {
      vtkWarningMacro(<< "no column of the performance names a target of the face: only the "
                         "head and eye turns are animated");
    }
    // Beside the target, renamed onto it when complete (base/File.h): no half-written file,
    // never onto a link, a device or a directory.
    morphnode::file::WriteFileSafely(this->FileName,
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "glTF file");
    this->NumberOfFrames = static_cast<int>(report.Frames);
    this->NumberOfWeightColumns = static_cast<int>(report.WeightColumns);
    this->TurnsBones = report.Bones;
    this->NumberOfRelaxedArms = static_cast<int>(report.Relaxed.size());
    this->UpdateProgress(1.0);
  }
  catch (const std::exception& e)
  {
    this->NumberOfFrames = 0;
    this->NumberOfWeightColumns = 0;
    this->NumberOfParts = 0;
    this->NumberOfRelaxedArms = 0;
    vtkErrorMacro(<< this->FileName << ": " << e.what());
    this->SetErrorCode(vtkErrorCode::UserError);
  }
}

//------------------------------------------------------------------------------
void vtkMorphGltfWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "TimeArrayName: " << (this->TimeArrayName ? this->TimeArrayName : "(none)")
     << "\n";
  os << indent << "Interpolation: " << (this->Interpolation == STEP ? "STEP" : "LINEAR") << "\n";
  os << indent << "ApplyOptimizer: " << this->ApplyOptimizer << "\n";
  os << indent << "OptimizerPreset: " << this->OptimizerPreset << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "MaxVertexError: " << this->MaxVertexError << "\n";
  os << indent << "Hysteresis: " << this->Hysteresis << "\n";
  os << indent << "WriteHeadPose: " << this->WriteHeadPose << "\n";
  os << indent << "WriteEyeRotations: " << this->WriteEyeRotations << "\n";
  os << indent << "RelaxArms: " << this->RelaxArms << "\n";
  os << indent << "ArmAngle: " << this->ArmAngle << "\n";
  os << indent << "NumberOfRelaxedArms: " << this->NumberOfRelaxedArms << "\n";
  os << indent << "EyeNodeNames: " << (this->EyeNodeNames ? this->EyeNodeNames : "(none)") << "\n";
  os << indent << "NumberOfFrames: " << this->NumberOfFrames << "\n";
  os << indent << "NumberOfWeightColumns: " << this->NumberOfWeightColumns << "\n";
  os << indent << "NumberOfParts: " << this->NumberOfParts << "\n";
}
