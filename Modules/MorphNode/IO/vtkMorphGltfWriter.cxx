// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphGltfWriter.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/File.h"
#include "behavior/HeadPose.h"
#include "gaze/EyeRig.h"
#include "gaze/EyeRotation.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfWriter.h"
#include "morph/MorphScene.h"
#include "morph/OptimizerPresets.h"

#include "vtkAbstractArray.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
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
#include <cctype>
#include <filesystem>
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

std::string FieldString(vtkFieldData* fd, const char* name)
{
  auto* a = vtkStringArray::SafeDownCast(fd ? fd->GetAbstractArray(name) : nullptr);
  return a && a->GetNumberOfValues() > 0 ? a->GetValue(0) : std::string();
}

/// The first `n` values of a numeric field-data array, or empty.
std::vector<double> FieldNumbers(vtkFieldData* fd, const char* name, vtkIdType n)
{
  auto* a = vtkDataArray::SafeDownCast(fd ? fd->GetAbstractArray(name) : nullptr);
  std::vector<double> values;
  if (a && a->GetNumberOfValues() >= n)
  {
    const int nc = a->GetNumberOfComponents();
    for (vtkIdType i = 0; i < n; ++i)
    {
      values.push_back(a->GetComponent(i / nc, static_cast<int>(i % nc)));
    }
  }
  return values;
}

std::vector<float> ToFloats(vtkDataArray* a)
{
  return arrays::ToVector<float>(a);
}

/// One leaf as a glTF part (world space) and its node name.
morphnode::GltfPart ToPart(vtkPolyData* poly, const std::string& fallbackName, std::string& nodeName)
{
  morphnode::GltfPart part;
  vtkFieldData* fd = poly->GetFieldData();
  part.Name = FieldString(fd, "PartName");
  if (part.Name.empty())
  {
    part.Name = fallbackName;
  }
  nodeName = FieldString(fd, "NodeName");
  if (nodeName.empty())
  {
    nodeName = part.Name;
  }
  part.MaterialName = FieldString(fd, "MaterialName");
  const std::vector<double> color = FieldNumbers(fd, "BaseColor", 4);
  if (color.size() == 4)
  {
    std::copy(color.begin(), color.end(), part.BaseColor.begin());
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
      throw morphnode::InputError("part '" + part.Name + "': COLOR_0 must be RGB or RGBA per point");
    }
    const double scale = colors->GetDataType() == VTK_UNSIGNED_CHAR ? 1.0 / 255.0
      : colors->GetDataType() == VTK_UNSIGNED_SHORT                 ? 1.0 / 65535.0
                                                                    : 1.0;
    part.Colors.resize(4 * static_cast<size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int c = 0; c < 4; ++c)
      {
        part.Colors[4 * i + c] = c < nc ? static_cast<float>(colors->GetComponent(i, c) * scale) : 1.0f;
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
  vtkDataObject* input = this->GetInput(0);
  vtkTable* table = this->GetNumberOfInputConnections(1) > 0 || this->GetInput(1)
    ? vtkTable::SafeDownCast(this->GetInput(1))
    : nullptr;
  try
  {
    // The output path first: a link, device or directory is refused before any work.
    morphnode::file::CheckOutputPath(this->FileName ? this->FileName : "", "glTF file");
    // The parts, grouped into nodes by NodeName (and by their targets, which glTF makes
    // the same for every primitive of a mesh).
    morphnode::GltfScene scene;
    std::vector<std::string> nodeNames;
    std::vector<std::vector<std::string>> nodeTargets;
    std::vector<std::array<double, 3>> nodeOrigins;
    std::vector<std::array<double, 9>> nodeAxes;
    std::vector<std::string> nodePartNames;
    std::vector<vtkPolyData*> leaves;
    if (auto* poly = vtkPolyData::SafeDownCast(input))
    {
      leaves.push_back(poly);
    }
    else if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
    {
      vtkSmartPointer<vtkCompositeDataIterator> it;
      it.TakeReference(composite->NewIterator());
      for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
      {
        auto* leaf = vtkPolyData::SafeDownCast(it->GetCurrentDataObject());
        if (!leaf)
        {
          throw morphnode::InputError(std::string("a leaf is a ") +
            it->GetCurrentDataObject()->GetClassName() + ", not a vtkPolyData");
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
    double bounds[6] = { VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX,
      VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
    std::vector<std::shared_ptr<const morphnode::MorphMesh>> meshes;
    for (size_t i = 0; i < leaves.size(); ++i)
    {
      std::string nodeName;
      morphnode::GltfPart part = ToPart(leaves[i], "part" + std::to_string(i), nodeName);
      std::vector<std::string> targets;
      for (const auto& t : part.Targets)
      {
        targets.push_back(t.Name);
      }
      int node = -1;
      for (size_t n = 0; n < nodeNames.size(); ++n)
      {
        if (nodeNames[n] == nodeName && nodeTargets[n] == targets)
        {
          node = static_cast<int>(n);
        }
      }
      if (node < 0)
      {
        const bool taken = std::find(nodeNames.begin(), nodeNames.end(), nodeName) != nodeNames.end();
        nodeNames.push_back(nodeName);
        nodeTargets.push_back(targets);
        const std::vector<double> origin = FieldNumbers(leaves[i]->GetFieldData(), "NodeOrigin", 3);
        nodeOrigins.push_back(origin.size() == 3 ? std::array<double, 3>{ { origin[0], origin[1], origin[2] } }
                                                 : std::array<double, 3>{ { 0, 0, 0 } });
        const std::vector<double> axes = FieldNumbers(leaves[i]->GetFieldData(), "NodeAxes", 9);
        std::array<double, 9> a{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
        if (axes.size() == 9)
        {
          std::copy(axes.begin(), axes.end(), a.begin());
        }
        nodeAxes.push_back(a);
        nodePartNames.push_back(part.Name);
        morphnode::GltfNode gnode;
        gnode.Name = taken ? nodeName + "/" + part.Name : nodeName;
        gnode.InScene = true;
        scene.Nodes.push_back(gnode);
        node = static_cast<int>(scene.Nodes.size() - 1);
      }
      part.Node = node;
      double b[6];
      leaves[i]->GetBounds(b);
      for (int k = 0; k < 3; ++k)
      {
        bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
        bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
      }
      if (this->ApplyOptimizer && table)
      {
        arrays::ReadOptions options;
        options.Normals = false;
        meshes.push_back(std::make_shared<morphnode::MorphMesh>(arrays::ToMorphMesh(leaves[i], options).Mesh));
      }
      scene.Parts.push_back(std::move(part));
    }
    // The materials and images of the file the parts were read from (vtkMorphTargetReader's
    // MaterialIndex and MaterialSource field data): the source scene's own, written back whole
    // by the core writer. Parts from several files, or a source that no longer loads, keep the
    // base colour materials made from their field data.
    {
      std::string source;
      bool one = true;
      std::vector<int> indices;
      for (vtkPolyData* leaf : leaves)
      {
        const std::string file = FieldString(leaf->GetFieldData(), "MaterialSource");
        const std::vector<double> index = FieldNumbers(leaf->GetFieldData(), "MaterialIndex", 1);
        indices.push_back(file.empty() || index.size() != 1 ? -1 : static_cast<int>(index[0]));
        if (!file.empty())
        {
          one = one && (source.empty() || source == file);
          source = file;
        }
      }
      if (!source.empty() && one)
      {
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
          vtkWarningMacro(<< "the materials of " << source << " are not written (" << e.what()
                          << "); base colours only");
          scene.Materials.clear();
          scene.Images.clear();
        }
      }
    }
    scene.SceneName = "MorphNode";
    this->NumberOfParts = static_cast<int>(scene.Parts.size());

    // The performance.
    std::unique_ptr<morphnode::GltfPerformance> performance;
    if (table && table->GetNumberOfRows() > 0)
    {
      performance = std::make_unique<morphnode::GltfPerformance>();
      morphnode::GltfPerformance& p = *performance;
      p.Interpolation = this->Interpolation == STEP ? morphnode::GltfInterpolation::Step
                                                    : morphnode::GltfInterpolation::Linear;
      const char* timeName = this->TimeArrayName ? this->TimeArrayName : "Time";
      p.Times = Column(table, timeName);
      if (p.Times.empty())
      {
        throw morphnode::InputError(std::string("the performance has no numeric time column '") + timeName + "'");
      }
      const size_t frames = p.Times.size();
      // Weight columns: those naming a target of some part, in the table's order.
      std::vector<std::vector<double>> columns;
      for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
      {
        const char* name = table->GetColumnName(c);
        if (!name)
        {
          continue;
        }
        const bool isTarget = std::any_of(nodeTargets.begin(), nodeTargets.end(),
          [name](const std::vector<std::string>& t) { return std::find(t.begin(), t.end(), name) != t.end(); });
        if (!isTarget)
        {
          continue;
        }
        std::vector<double> values = Column(table, name);
        if (values.size() != frames)
        {
          throw morphnode::InputError(std::string("the performance's column '") + name + "' is not numeric");
        }
        p.TargetNames.push_back(name);
        columns.push_back(std::move(values));
      }
      this->NumberOfWeightColumns = static_cast<int>(p.TargetNames.size());
      if (p.TargetNames.empty())
      {
        vtkWarningMacro(<< "no column of the performance names a target of the face: only the "
                           "head and eye turns are animated");
      }
      p.Weights.resize(frames * p.TargetNames.size());
      for (size_t f = 0; f < frames; ++f)
      {
        for (size_t c = 0; c < columns.size(); ++c)
        {
          p.Weights[f * columns.size() + c] = columns[c][f];
        }
      }
      if (this->ApplyOptimizer && !p.TargetNames.empty())
      {
        morphnode::MorphScene model;
        model.SetParts(meshes);
        morphnode::OptimizerSettings settings = morphnode::MakeOptimizerSettings(
          static_cast<morphnode::OptimizerPreset>(this->OptimizerPreset), this->Threshold,
          this->MaxVertexError);
        settings.Hysteresis = this->Hysteresis;
        model.SetOptimizerSettings(settings);
        model.SetWeightMode(morphnode::WeightMode::Relative);
        std::vector<int> index(p.TargetNames.size());
        for (size_t c = 0; c < index.size(); ++c)
        {
          index[c] = model.FindTarget(p.TargetNames[c]);
        }
        std::vector<double> requested(model.GetNumberOfTargets(), 0.0);
        for (size_t f = 0; f < frames; ++f)
        {
          std::fill(requested.begin(), requested.end(), 0.0);
          for (size_t c = 0; c < index.size(); ++c)
          {
            requested[static_cast<size_t>(index[c])] = p.Weights[f * index.size() + c];
          }
          const std::vector<double>& effective = model.SetWeights(requested);
          for (size_t c = 0; c < index.size(); ++c)
          {
            p.Weights[f * index.size() + c] = effective[static_cast<size_t>(index[c])];
          }
          if (f % 256 == 0)
          {
            this->UpdateProgress(0.5 * static_cast<double>(f) / static_cast<double>(frames));
          }
        }
      }
      // Head pose about the head's pivot; eyes about their node origins.
      auto angles = [&](const char* name) {
        std::vector<double> v = Column(table, name);
        return v.size() == frames ? v : std::vector<double>();
      };
      const std::vector<double> yaw = angles("HeadYaw");
      const std::vector<double> pitch = angles("HeadPitch");
      const std::vector<double> roll = angles("HeadRoll");
      auto quaternions = [&](const std::vector<double>& y, const std::vector<double>& pi,
                           const std::vector<double>& r) {
        std::vector<double> q;
        q.reserve(4 * frames);
        for (size_t f = 0; f < frames; ++f)
        {
          morphnode::HeadAngles a;
          a.Yaw = y.empty() ? 0.0 : y[f];
          a.Pitch = pi.empty() ? 0.0 : pi[f];
          a.Roll = r.empty() ? 0.0 : r[f];
          const auto m = morphnode::HeadPoseMatrix(a, { { 0, 0, 0 } });
          const auto quat = morphnode::GltfQuaternionFromRowMajor(m);
          q.insert(q.end(), quat.begin(), quat.end());
        }
        return q;
      };
      if (this->WriteHeadPose && (!yaw.empty() || !pitch.empty() || !roll.empty()))
      {
        morphnode::GltfRotationTrack head;
        head.Pivot = morphnode::HeadPivot(bounds);
        head.Rotations = quaternions(yaw, pitch, roll);
        p.Rotations.push_back(std::move(head));
      }
      const std::vector<double> eyeYaw = angles("EyeYaw");
      const std::vector<double> eyePitch = angles("EyePitch");
      if (this->WriteEyeRotations && (!eyeYaw.empty() || !eyePitch.empty()))
      {
        // The eyes and their turns as vtkEyeGazeFilter finds and turns them (its defaults:
        // morphnode::EyeRig's convention or the named nodes, its limits, no vergence).
        morphnode::EyeRig rig;
        for (const std::string& eye : SplitNames(this->EyeNodeNames))
        {
          morphnode::EyeSpec spec;
          spec.Name = eye;
          spec.Side = morphnode::EyeRig::SideFromName(eye);
          rig.AddEye(spec);
        }
        for (size_t n = 0; n < scene.Nodes.size(); ++n)
        {
          morphnode::EyeSpec eye;
          if (scene.Nodes[n].Name != nodeNames[n] || !rig.FindEye(nodeNames[n], nodePartNames[n], eye))
          {
            continue;
          }
          std::vector<double> q;
          q.reserve(4 * frames);
          for (size_t f = 0; f < frames; ++f)
          {
            morphnode::GazeAngles gaze;
            gaze.Yaw = eyeYaw.empty() ? 0.0 : eyeYaw[f];
            gaze.Pitch = eyePitch.empty() ? 0.0 : eyePitch[f];
            const morphnode::GazeAngles turned = morphnode::EyeAngles(gaze, 0.0, eye.Side, rig.GetLimits());
            const std::array<double, 9> r = morphnode::EyeRotationMatrix(turned, nodeAxes[n], eye.Forward, eye.Up);
            const std::array<double, 16> m{ { r[0], r[1], r[2], 0, r[3], r[4], r[5], 0, r[6], r[7], r[8], 0, 0, 0, 0, 1 } };
            const auto quat = morphnode::GltfQuaternionFromRowMajor(m);
            q.insert(q.end(), quat.begin(), quat.end());
          }
          p.Rotations.push_back({ scene.Nodes[n].Name, nodeOrigins[n], std::move(q) });
        }
      }
      this->NumberOfFrames = static_cast<int>(frames);
    }
    this->UpdateProgress(0.5);
    // Beside the target, renamed onto it when complete (base/File.h): no half-written file,
    // never onto a link, a device or a directory.
    const std::string target = this->FileName;
    std::string extension = std::filesystem::path(target).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
      [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    morphnode::GltfWriteOptions options;
    options.Binary = extension != ".gltf";
    const std::vector<unsigned char> bytes = morphnode::WriteGltfSceneToMemory(scene, performance.get(), options);
    morphnode::file::WriteFileSafely(target,
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "glTF file");
    this->UpdateProgress(1.0);
  }
  catch (const std::exception& e)
  {
    this->NumberOfFrames = 0;
    this->NumberOfWeightColumns = 0;
    this->NumberOfParts = 0;
    vtkErrorMacro(<< this->FileName << ": " << e.what());
    this->SetErrorCode(vtkErrorCode::UserError);
  }
}

//------------------------------------------------------------------------------
void vtkMorphGltfWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "TimeArrayName: " << (this->TimeArrayName ? this->TimeArrayName : "(none)") << "\n";
  os << indent << "Interpolation: " << (this->Interpolation == STEP ? "STEP" : "LINEAR") << "\n";
  os << indent << "ApplyOptimizer: " << this->ApplyOptimizer << "\n";
  os << indent << "OptimizerPreset: " << this->OptimizerPreset << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "MaxVertexError: " << this->MaxVertexError << "\n";
  os << indent << "Hysteresis: " << this->Hysteresis << "\n";
  os << indent << "WriteHeadPose: " << this->WriteHeadPose << "\n";
  os << indent << "WriteEyeRotations: " << this->WriteEyeRotations << "\n";
  os << indent << "EyeNodeNames: " << (this->EyeNodeNames ? this->EyeNodeNames : "(none)") << "\n";
  os << indent << "NumberOfFrames: " << this->NumberOfFrames << "\n";
  os << indent << "NumberOfWeightColumns: " << this->NumberOfWeightColumns << "\n";
  os << indent << "NumberOfParts: " << this->NumberOfParts << "\n";
}
