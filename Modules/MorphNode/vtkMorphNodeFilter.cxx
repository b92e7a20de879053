// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphNodeFilter.h"

#include "vtkMorphModelAdapter.h"

#include "base/Error.h"
#include "morph/WeightOptimizer.h"
#include "morph/Weights.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

namespace adapter = vtkMorphModelAdapter;

namespace
{
/// Field-data arrays the filter writes; a neutral's arrays of these names are replaced.
const char* const OutputFieldArrays[] = { adapter::TargetNamesArray, adapter::EffectiveWeightsArray,
  adapter::ActiveTargetCountArray, adapter::ErrorBoundArray, adapter::DistNormArray };
}

struct vtkMorphNodeFilter::vtkInternals
{
  /// A weight set by index or by name; applied in the order they were set.
  struct Assignment
  {
    int Index; // -1 when set by name
    std::string Name;
    double Weight;
  };
  std::vector<Assignment> Assignments;

  /// The model built from the current input, and what it was built from.
  std::optional<adapter::BuiltModel> Built;
  std::vector<std::pair<vtkDataObject*, vtkMTimeType>> BuiltFrom;
  double BuiltSparseCoverage = -1.0;

  morphnode::WeightOptimizer Optimizer;
  std::vector<double> EffectiveWeights;
  vtkNew<vtkDoubleArray> DistNorm;

  /// Output arrays kept across executions (see adapter::BlendOutputs).
  adapter::BlendOutputs Outputs;
  /// Made once per model, shared by every output.
  vtkSmartPointer<vtkStringArray> TargetNames;
  vtkSmartPointer<vtkDoubleArray> DistNormOut;
  std::vector<vtkSmartPointer<vtkDataArray>> Distances; // built on first request
  /// Per-execution field data, rewritten in place when no one else holds them.
  vtkSmartPointer<vtkDataArray> EffectiveWeightsOut, ActiveTargetCountOut, ErrorBoundOut;

  /// The animated region and each target's per-point distance from the neutral.
  const std::vector<vtkSmartPointer<vtkDataArray>>& DistanceArrays()
  {
    if (this->Distances.empty() && this->Built)
    {
      const morphnode::MorphMesh& model = this->Built->Model;
      this->Distances.push_back(
        adapter::MakeDoubleArray(adapter::AnimatedRegionArray, model.ComputeAnimatedRegion()));
      for (size_t i = 1; i < model.GetNumberOfTargets(); ++i)
      {
        const std::string name = adapter::DistancePrefix + model.GetTargetNames()[i];
        this->Distances.push_back(
          adapter::MakeDoubleArray(name.c_str(), model.ComputePointDistances(i)));
      }
    }
    return this->Distances;
  }

  /// `values` in the ArrayT held by `slot`, rewritten in place when only `slot` holds it.
  template <typename ArrayT>
  static vtkDataArray* Values(
    vtkSmartPointer<vtkDataArray>& slot, const char* name, const std::vector<double>& values)
  {
    ArrayT* array = ArrayT::SafeDownCast(slot);
    if (!array || slot->GetReferenceCount() != 1)
    {
      auto fresh = vtkSmartPointer<ArrayT>::New();
      fresh->SetName(name);
      slot = fresh;
      array = fresh;
    }
    array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
    for (size_t i = 0; i < values.size(); ++i)
    {
      array->SetValue(static_cast<vtkIdType>(i), static_cast<typename ArrayT::ValueType>(values[i]));
    }
    array->Modified();
    return array;
  }

  void Set(int index, const std::string& name, double weight)
  {
    for (auto it = this->Assignments.begin(); it != this->Assignments.end(); ++it)
    {
      if (it->Index == index && it->Name == name)
      {
        this->Assignments.erase(it);
        break;
      }
    }
    this->Assignments.push_back({ index, name, weight });
  }

  /// Requested weight of target `index` from the assignments; names are resolved with
  /// `names` (may be empty before the first execution).
  double Requested(int index, const std::vector<std::string>& names) const
  {
    double w = index == 0 ? 1.0 : 0.0;
    for (const auto& a : this->Assignments)
    {
      const bool byIndex = a.Index == index;
      const bool byName = a.Index < 0 && index >= 0 && static_cast<size_t>(index) < names.size() &&
        names[static_cast<size_t>(index)] == a.Name;
      if (byIndex || byName)
      {
        w = a.Weight;
      }
    }
    return w;
  }
};

vtkStandardNewMacro(vtkMorphNodeFilter);

//------------------------------------------------------------------------------
vtkMorphNodeFilter::vtkMorphNodeFilter()
  : SparseCoverage(morphnode::MorphMesh::DefaultSparseCoverage)
  , Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
  this->Internals->DistNorm->SetName(adapter::DistNormArray);
}

//------------------------------------------------------------------------------
vtkMorphNodeFilter::~vtkMorphNodeFilter() = default;

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
    info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetWeightsConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::GetNumberOfTargets()
{
  if (this->Internals->Built)
  {
    return static_cast<int>(this->Internals->Built->Model.GetNumberOfTargets());
  }
  const int connections = this->GetNumberOfInputConnections(0);
  if (connections != 1)
  {
    return connections;
  }
  // One connection: the glTF form if the data carries target arrays.
  vtkPointSet* input = vtkPointSet::SafeDownCast(this->GetInputDataObject(0, 0));
  if (!adapter::HasRelativeTargets(input))
  {
    return 1;
  }
  int n = 1;
  while (input->GetPointData()->GetAbstractArray(("target" + std::to_string(n - 1) + "_position").c_str()))
  {
    ++n;
  }
  return n;
}

//------------------------------------------------------------------------------
const char* vtkMorphNodeFilter::GetTargetName(int index)
{
  if (!this->Internals->Built || index < 0 ||
    index >= static_cast<int>(this->Internals->Built->Model.GetNumberOfTargets()))
  {
    return nullptr;
  }
  return this->Internals->Built->Model.GetTargetNames()[static_cast<size_t>(index)].c_str();
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::GetTargetIndex(const char* name)
{
  if (!this->Internals->Built || !name)
  {
    return -1;
  }
  return this->Internals->Built->Model.FindTarget(name);
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetWeight(int index, double weight)
{
  if (index < 0)
  {
    vtkErrorMacro(<< "SetWeight: target index " << index << " is negative");
    return;
  }
  const auto& names = this->Internals->Built ? this->Internals->Built->Model.GetTargetNames()
                                             : std::vector<std::string>();
  const double current = this->Internals->Requested(index, names);
  const bool same = current == weight || (current != current && weight != weight);
  this->Internals->Set(index, std::string(), weight);
  if (!same)
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetWeight(int index)
{
  const auto& names = this->Internals->Built ? this->Internals->Built->Model.GetTargetNames()
                                             : std::vector<std::string>();
  return this->Internals->Requested(index, names);
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetWeightByName(const char* name, double weight)
{
  if (!name || !*name)
  {
    vtkErrorMacro(<< "SetWeightByName: empty target name");
    return;
  }
  const double current = this->GetWeightByName(name);
  this->Internals->Set(-1, name, weight);
  if (!(current == weight || (current != current && weight != weight)))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetWeightByName(const char* name)
{
  if (!name)
  {
    return 0.0;
  }
  const int index = this->GetTargetIndex(name);
  if (index >= 0)
  {
    return this->GetWeight(index);
  }
  double w = 0.0; // not yet resolvable: the last value set by that name
  for (const auto& a : this->Internals->Assignments)
  {
    if (a.Index < 0 && a.Name == name)
    {
      w = a.Weight;
    }
  }
  return w;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetWeights()
{
  if (!this->Internals->Assignments.empty())
  {
    this->Internals->Assignments.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetEffectiveWeight(int index)
{
  const auto& w = this->Internals->EffectiveWeights;
  return index >= 0 && static_cast<size_t>(index) < w.size() ? w[static_cast<size_t>(index)] : 0.0;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetHysteresis()
{
  this->Internals->Optimizer.ResetHistory();
}

//------------------------------------------------------------------------------
vtkDoubleArray* vtkMorphNodeFilter::GetDistNorm()
{
  return this->Internals->DistNorm;
}

//------------------------------------------------------------------------------
const morphnode::MorphMesh* vtkMorphNodeFilter::GetMorphModel()
{
  return this->Internals->Built ? &this->Internals->Built->Model : nullptr;
}

//------------------------------------------------------------------------------
const char* vtkMorphNodeFilter::GetWeightModeAsString()
{
  return morphnode::WeightModeName(static_cast<morphnode::WeightMode>(this->WeightMode));
}

//------------------------------------------------------------------------------
const char* vtkMorphNodeFilter::GetRedistributionStrategyAsString()
{
  return morphnode::RedistributionName(
    static_cast<morphnode::Redistribution>(this->RedistributionStrategy));
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::ExecuteInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The executive copies time only from the first connection of port 0; the weights
  // source on port 1 is what animates the face, so its time wins.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* weightsInfo = inputVector[1]->GetInformationObject(0);
  if (weightsInfo && weightsInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    outInfo->CopyEntry(weightsInfo, vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  }
  if (weightsInfo && weightsInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()))
  {
    outInfo->CopyEntry(weightsInfo, vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* output = vtkPointSet::GetData(outputVector, 0);
  vtkInternals& internals = *this->Internals;
  internals.EffectiveWeights.clear();
  this->ActiveTargetCount = 0;
  this->ErrorBound = 0.0;

  const int numConnections = inputVector[0]->GetNumberOfInformationObjects();
  std::vector<vtkPointSet*> inputs;
  for (int i = 0; i < numConnections; ++i)
  {
    inputs.push_back(vtkPointSet::GetData(inputVector[0], i));
  }
  vtkTable* weightsTable = vtkTable::GetData(inputVector[1], 0);

  try
  {
    // 1. The model: rebuilt only when an input or the storage choice changed.
    std::vector<std::pair<vtkDataObject*, vtkMTimeType>> from;
    for (vtkPointSet* input : inputs)
    {
      from.emplace_back(input, input ? input->GetMTime() : 0);
    }
    if (!internals.Built || from != internals.BuiltFrom ||
      internals.BuiltSparseCoverage != this->SparseCoverage)
    {
      internals.Built.reset();
      internals.BuiltFrom.clear();
      if (inputs.empty())
      {
        throw morphnode::InputError("no input: connect the neutral (and the targets) to port 0");
      }
      this->UpdateProgress(0.0);
      internals.Built = inputs.size() == 1 && adapter::HasRelativeTargets(inputs[0])
        ? adapter::BuildFromRelativeTargets(inputs[0], this->SparseCoverage)
        : adapter::BuildFromAbsoluteTargets(inputs, this->SparseCoverage);
      internals.BuiltFrom = from;
      internals.BuiltSparseCoverage = this->SparseCoverage;
      internals.Optimizer.SetTargetDistances(internals.Built->Model.ComputeDistances());
      const auto& distNorm = internals.Optimizer.GetTargetDistances().DistNorm;
      internals.DistNorm->SetNumberOfValues(static_cast<vtkIdType>(distNorm.size()));
      for (size_t i = 0; i < distNorm.size(); ++i)
      {
        internals.DistNorm->SetValue(static_cast<vtkIdType>(i), distNorm[i]);
      }
      // What depends on the model only is made once per model and shared by every output.
      internals.TargetNames =
        adapter::MakeNamesArray(adapter::TargetNamesArray, internals.Built->Model.GetTargetNames());
      internals.DistNormOut = vtkSmartPointer<vtkDoubleArray>::New();
      internals.DistNormOut->DeepCopy(internals.DistNorm);
      internals.Distances.clear();
      internals.Outputs = {};
    }
    const morphnode::MorphMesh& model = internals.Built->Model;
    const auto& names = model.GetTargetNames();
    const size_t n = model.GetNumberOfTargets();
    this->UpdateProgress(0.3);

    // 2. Requested weights: the table on port 1, else the assignments.
    std::vector<double> requested(n);
    if (weightsTable)
    {
      int matched = 0;
      requested = adapter::WeightsFromTable(weightsTable, model, matched);
      if (matched == 0 && weightsTable->GetNumberOfColumns() > 0)
      {
        vtkWarningMacro(<< "the weights table on port 1 names none of the " << n
                        << " targets; showing the neutral");
      }
    }
    else
    {
      for (const auto& a : internals.Assignments)
      {
        if (a.Index >= static_cast<int>(n))
        {
          std::ostringstream msg;
          msg << "a weight is set for target " << a.Index << ", but the input has " << n
              << " targets (0.." << n - 1 << ", neutral first)";
          throw morphnode::InputError(msg.str());
        }
        if (a.Index < 0 && model.FindTarget(a.Name) < 0)
        {
          std::ostringstream msg;
          msg << "a weight is set for target '" << a.Name << "', but no target has that name; "
              << "targets:";
          for (const auto& name : names)
          {
            msg << " " << name;
          }
          throw morphnode::InputError(msg.str());
        }
      }
      for (size_t i = 0; i < n; ++i)
      {
        requested[i] = internals.Requested(static_cast<int>(i), names);
      }
    }

    // 3. Weight rules, then the optimizer.
    const std::vector<double> absolute =
      morphnode::ResolveWeights(static_cast<morphnode::WeightMode>(this->WeightMode), requested);
    morphnode::OptimizerSettings settings;
    settings.Threshold = this->Threshold;
    settings.Strategy = static_cast<morphnode::Redistribution>(this->RedistributionStrategy);
    settings.AdjustThreshold = this->AdjustThreshold;
    settings.MaxVertexError = this->MaxVertexError;
    settings.MaxActiveTargets = this->MaxActiveTargets;
    settings.Hysteresis = this->Hysteresis;
    internals.Optimizer.SetSettings(settings);
    const std::vector<double> effective = internals.Optimizer.Optimize(absolute);
    this->UpdateProgress(0.4);

    // 4. Blend.
    adapter::Blend(*internals.Built, effective, internals.Outputs);
    this->UpdateProgress(0.9);

    // 5. Output: the neutral's structure, blended arrays in place of the neutral's.
    vtkPointSet* neutral = inputs[0];
    output->CopyStructure(neutral);
    output->SetPoints(internals.Outputs.Points);
    adapter::AssemblePointData(
      neutral->GetPointData(), *internals.Built, internals.Outputs, output->GetPointData());
    output->GetCellData()->PassData(neutral->GetCellData());

    if (this->GenerateDistanceArrays)
    {
      for (vtkDataArray* array : internals.DistanceArrays())
      {
        output->GetPointData()->AddArray(array);
      }
    }

    vtkFieldData* fd = output->GetFieldData();
    vtkFieldData* neutralFD = neutral->GetFieldData();
    for (int a = 0; a < neutralFD->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* array = neutralFD->GetAbstractArray(a);
      const char* name = array ? array->GetName() : nullptr;
      const bool ours = name &&
        std::any_of(std::begin(OutputFieldArrays), std::end(OutputFieldArrays),
          [name](const char* own) { return std::strcmp(own, name) == 0; });
      if (array && !ours)
      {
        fd->AddArray(array);
      }
    }
    fd->AddArray(internals.TargetNames);
    fd->AddArray(internals.Values<vtkDoubleArray>(internals.EffectiveWeightsOut, adapter::EffectiveWeightsArray, effective));
    const int activeTargets = morphnode::CountActiveTargets(effective);
    fd->AddArray(internals.Values<vtkIntArray>(internals.ActiveTargetCountOut, adapter::ActiveTargetCountArray,
      { static_cast<double>(activeTargets) }));
    fd->AddArray(internals.Values<vtkDoubleArray>(
      internals.ErrorBoundOut, adapter::ErrorBoundArray, { internals.Optimizer.GetLastErrorBound() }));
    if (this->GenerateDistanceArrays)
    {
      fd->AddArray(internals.DistNormOut);
    }

    internals.EffectiveWeights = effective;
    this->ActiveTargetCount = activeTargets;
    this->ErrorBound = internals.Optimizer.GetLastErrorBound();

    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
        outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
    this->UpdateProgress(1.0);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    internals.EffectiveWeights.clear();
    this->ActiveTargetCount = 0;
    this->ErrorBound = 0.0;
    return 1;
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightMode: " << this->GetWeightModeAsString() << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "RedistributionStrategy: " << this->GetRedistributionStrategyAsString() << "\n";
  os << indent << "AdjustThreshold: " << (this->AdjustThreshold ? "On" : "Off") << "\n";
  os << indent << "MaxVertexError: " << this->MaxVertexError << "\n";
  os << indent << "MaxActiveTargets: " << this->MaxActiveTargets << "\n";
  os << indent << "Hysteresis: " << this->Hysteresis << "\n";
  os << indent << "GenerateDistanceArrays: " << (this->GenerateDistanceArrays ? "On" : "Off") << "\n";
  os << indent << "SparseCoverage: " << this->SparseCoverage << "\n";
  os << indent << "NumberOfTargets: "
     << (this->Internals->Built ? static_cast<int>(this->Internals->Built->Model.GetNumberOfTargets()) : 0)
     << "\n";
  os << indent << "Weights (requested):";
  for (const auto& a : this->Internals->Assignments)
  {
    os << " ";
    if (a.Index >= 0)
    {
      os << a.Index;
    }
    else
    {
      os << a.Name;
    }
    os << "=" << a.Weight;
  }
  os << "\n";
  os << indent << "EffectiveWeights:";
  for (double w : this->Internals->EffectiveWeights)
  {
    os << " " << w;
  }
  os << "\n";
  os << indent << "ActiveTargetCount: " << this->ActiveTargetCount << "\n";
  os << indent << "ErrorBound: " << this->ErrorBound << "\n";
}
