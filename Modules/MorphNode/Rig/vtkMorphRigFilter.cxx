// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphRigFilter.h"

#include "vtkMorphRigCache.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "morph/OptimizerPresets.h"
#include "rig/Rig.h"
#include "rig/RigOptimizer.h"

#include "vtkAbstractArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointSet.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkVariant.h"

#include <set>
#include <vector>

vtkStandardNewMacro(vtkMorphRigFilter);

struct vtkMorphRigFilter::vtkInternals
{
  vtkMorphRigCache Rig;
  vtkSmartPointer<vtkStringArray> TargetNames;
  morphnode::RigOptimizer Optimizer;
  /// What the shape figures were measured on (the face and its time, the rig's load time).
  vtkMTimeType FiguresFace = 0;
  vtkMTimeType FiguresRig = 0;
  vtkDataObject* FiguresOf = nullptr;

  /// The face's relative targets (no neutral), the rig bound to them: a connected face's
  /// names, else SetTargetNames', else the rig's declared ones.
  std::vector<std::string> BindTargets(morphnode::Rig& rig, vtkDataObject* face);
  /// The shapes measured on the face (again when the face or the rig changed) and the
  /// filter's optimizer settings.
  void PrepareOptimizer(vtkMorphRigFilter* self, const morphnode::Rig& rig, vtkDataObject* face);
};

namespace
{
/// The rig's shapes measured on every part of the face that carries target arrays.
morphnode::TargetDistances MeasureShapes(const morphnode::Rig& rig, vtkDataObject* face)
{
  std::vector<morphnode::NamedTargetDistances> pieces;
  auto add = [&](vtkDataObject* leaf)
  {
    auto* points = vtkPointSet::SafeDownCast(leaf);
    if (!points || !vtkMorphTargetArrays::HasTargets(points))
    {
      return;
    }
    vtkMorphTargetArrays::ReadOptions options;
    options.Normals = false;
    const auto read = vtkMorphTargetArrays::ToMorphMesh(points, options);
    pieces.push_back(morphnode::ComputeShapeDistances(rig, read.Mesh));
  };
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(face))
  {
    for (vtkDataObject* leaf : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      add(leaf);
    }
  }
  else
  {
    add(face);
  }
  if (pieces.empty())
  {
    throw morphnode::InputError("rig-aware optimization measures the shapes on the face's "
                                "geometry: connect a face with target arrays to port 1");
  }
  return morphnode::MakeTargetDistances(morphnode::CombineTargetDistances(pieces));
}
} // namespace

//------------------------------------------------------------------------------
std::vector<std::string> vtkMorphRigFilter::vtkInternals::BindTargets(
  morphnode::Rig& rig, vtkDataObject* face)
{
  std::vector<std::string> targets;
  if (face && !vtkMorphTargetArrays::GetFaceTargetNames(face, targets))
  {
    throw morphnode::InputError(std::string("the face on port 1 has no field data '") +
      vtkMorphTargetArrays::TargetNamesArray + "' (neutral first)");
  }
  if (!face && this->TargetNames)
  {
    for (vtkIdType i = 1; i < this->TargetNames->GetNumberOfValues(); ++i)
    {
      targets.push_back(this->TargetNames->GetValue(i));
    }
  }
  else if (!face) // a connected face's names win over the rig's declared ones
  {
    targets = rig.GetDeclaredTargets();
    if (targets.empty())
    {
      throw morphnode::InputError("no target names: connect the face to port 1, call "
                                  "SetTargetNames() or use a rig with a 'targets' list");
    }
  }
  try
  {
    rig.Bind(targets);
  }
  catch (const std::exception& e)
  {
    throw morphnode::InputError(std::string(e.what()) +
      (face || this->TargetNames
          ? " (target names are taken neutral first: the first one is skipped)"
          : ""));
  }
  return targets;
}

//------------------------------------------------------------------------------
void vtkMorphRigFilter::vtkInternals::PrepareOptimizer(
  vtkMorphRigFilter* self, const morphnode::Rig& rig, vtkDataObject* face)
{
  if (!face)
  {
    throw morphnode::InputError("rig-aware optimization measures the shapes on the face's "
                                "geometry: connect the face to port 1");
  }
  const vtkMTimeType rigTime = self->vtkObject::GetMTime();
  if (this->FiguresOf != face || this->FiguresFace != face->GetMTime() ||
    this->FiguresRig != rigTime || this->Optimizer.GetNumberOfShapes() != rig.GetNumberOfShapes())
  {
    this->Optimizer.SetShapeDistances(MeasureShapes(rig, face));
    this->FiguresOf = face;
    this->FiguresFace = face->GetMTime();
    this->FiguresRig = rigTime;
  }
  morphnode::OptimizerSettings settings =
    morphnode::MakeOptimizerSettings(static_cast<morphnode::OptimizerPreset>(self->OptimizerPreset),
      self->Threshold, self->MaxVertexError);
  settings.Hysteresis = self->Hysteresis;
  this->Optimizer.SetSettings(settings);
}

//------------------------------------------------------------------------------
vtkMorphRigFilter::vtkMorphRigFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkMorphRigFilter::~vtkMorphRigFilter() = default;

//------------------------------------------------------------------------------
int vtkMorphRigFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphRigFilter::SetFaceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
void vtkMorphRigFilter::SetTargetNames(vtkStringArray* names)
{
  if (vtkMorphTargetArrays::AssignTargetNames(this->Internals->TargetNames, names))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkStringArray* vtkMorphRigFilter::GetTargetNames()
{
  return this->Internals->TargetNames;
}

//------------------------------------------------------------------------------
int vtkMorphRigFilter::GetNumberOfShapes()
{
  const morphnode::Rig* rig = this->Internals->Rig.GetLoaded();
  return rig ? static_cast<int>(rig->GetNumberOfShapes()) : 0;
}

//------------------------------------------------------------------------------
const char* vtkMorphRigFilter::GetShapeName(int index)
{
  const morphnode::Rig* rig = this->Internals->Rig.GetLoaded();
  if (!rig || index < 0 || index >= static_cast<int>(rig->GetNumberOfShapes()))
  {
    return nullptr;
  }
  return rig->GetShapeNames()[static_cast<size_t>(index)].c_str();
}

//------------------------------------------------------------------------------
void vtkMorphRigFilter::ResetHysteresis()
{
  this->Internals->Optimizer.ResetHistory();
}

//------------------------------------------------------------------------------
double vtkMorphRigFilter::GetLastErrorBound()
{
  return this->OptimizerPreset != 0 ? this->Internals->Optimizer.GetLastErrorBound() : 0.0;
}

//------------------------------------------------------------------------------
int vtkMorphRigFilter::GetLastActiveShapes()
{
  return this->OptimizerPreset != 0 ? this->Internals->Optimizer.GetLastActiveShapes() : 0;
}

//------------------------------------------------------------------------------
void vtkMorphRigFilter::SetRigFileName(const char* value)
{
  const std::string v = value ? value : "";
  if (v != this->RigFileName)
  {
    this->RigFileName = v;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkMorphRigFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkTable* input = vtkTable::GetData(inputVector[0], 0);
  vtkDataObject* face = vtkDataObject::GetData(inputVector[1], 0);
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  output->Initialize();
  if (!input)
  {
    vtkErrorMacro("no weights table on port 0");
    return 0;
  }
  vtkInternals& internals = *this->Internals;
  try
  {
    morphnode::Rig& rig = internals.Rig.Get(this->RigFileName, this->vtkObject::GetMTime());
    const std::vector<std::string> targets = internals.BindTargets(rig, face);

    // Columns: shape columns (numeric), face-target columns (dropped: the expanded value
    // wins), others (passed when asked).
    const std::set<std::string> targetSet(targets.begin(), targets.end());
    std::vector<morphnode::ShapeWeightColumn> shapeColumns;
    std::vector<vtkAbstractArray*> otherColumns;
    for (vtkIdType c = 0; c < input->GetNumberOfColumns(); ++c)
    {
      vtkAbstractArray* column = input->GetColumn(c);
      const char* name = column ? column->GetName() : nullptr;
      const int shape = name ? rig.FindShape(name) : -1;
      auto* numbers = vtkDataArray::SafeDownCast(column);
      if (shape >= 0 && (!numbers || numbers->GetNumberOfComponents() != 1))
      {
        throw morphnode::InputError(
          std::string("the weights column '") + name + "' is not a numeric one-component array");
      }
      if (shape >= 0)
      {
        shapeColumns.push_back(
          { static_cast<size_t>(shape), name, vtkMorphTargetArrays::ToVector<double>(numbers) });
      }
      else if (!(name && targetSet.count(name)) && this->PassOtherColumns)
      {
        otherColumns.push_back(column);
      }
    }

    const bool optimize = this->OptimizerPreset != 0;
    if (optimize)
    {
      internals.PrepareOptimizer(this, rig, face);
    }
    const std::vector<std::vector<double>> expanded =
      morphnode::ExpandShapeFrames(rig, shapeColumns, static_cast<size_t>(input->GetNumberOfRows()),
        optimize ? &internals.Optimizer : nullptr);
    for (size_t t = 0; t < targets.size(); ++t)
    {
      vtkNew<vtkDoubleArray> column;
      column->SetName(targets[t].c_str());
      column->SetNumberOfValues(static_cast<vtkIdType>(expanded[t].size()));
      std::copy(expanded[t].begin(), expanded[t].end(), column->GetPointer(0));
      output->AddColumn(column);
    }
    for (vtkAbstractArray* column : otherColumns)
    {
      output->AddColumn(column);
    }
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
        outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphRigFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RigFileName: " << (this->RigFileName.empty() ? "(none)" : this->RigFileName)
     << "\n";
  os << indent << "PassOtherColumns: " << (this->PassOtherColumns ? "On" : "Off") << "\n";
  os << indent << "OptimizerPreset: "
     << morphnode::OptimizerPresetName(
          static_cast<morphnode::OptimizerPreset>(this->OptimizerPreset))
     << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "MaxVertexError: " << this->MaxVertexError << "\n";
  os << indent << "Hysteresis: " << this->Hysteresis << "\n";
  os << indent << "TargetNames: ";
  if (this->Internals->TargetNames)
  {
    os << this->Internals->TargetNames->GetNumberOfValues() << " names\n";
  }
  else
  {
    os << "(none)\n";
  }
  this->Internals->Rig.Print(os, indent);
}
