// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphNodeFilter.h"

#include "vtkMorphModelAdapter.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "morph/MorphNode.h"
#include "morph/OptimizerPresets.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace adapter = vtkMorphModelAdapter;

// The VTK enums are the core's, value for value.
static_assert(vtkMorphNodeFilter::STRICT == static_cast<int>(morphnode::WeightMode::Strict) &&
    vtkMorphNodeFilter::NORMALIZE == static_cast<int>(morphnode::WeightMode::Normalize) &&
    vtkMorphNodeFilter::RELATIVE == static_cast<int>(morphnode::WeightMode::Relative),
  "vtkMorphNodeFilter::WeightModes must match morphnode::WeightMode");
static_assert(vtkMorphNodeFilter::MAXIMUM == static_cast<int>(morphnode::Redistribution::Maximum) &&
    vtkMorphNodeFilter::REMAINING == static_cast<int>(morphnode::Redistribution::Remaining) &&
    vtkMorphNodeFilter::NEUTRAL == static_cast<int>(morphnode::Redistribution::Neutral),
  "vtkMorphNodeFilter::RedistributionStrategies must match morphnode::Redistribution");
static_assert(vtkMorphNodeFilter::OPTIMIZER_NONE == static_cast<int>(morphnode::OptimizerPreset::None) &&
    vtkMorphNodeFilter::OPTIMIZER_FIXED_MAXIMUM ==
      static_cast<int>(morphnode::OptimizerPreset::FixedMaximum) &&
    vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING ==
      static_cast<int>(morphnode::OptimizerPreset::FixedRemaining) &&
    vtkMorphNodeFilter::OPTIMIZER_ADJUSTED == static_cast<int>(morphnode::OptimizerPreset::Adjusted) &&
    vtkMorphNodeFilter::OPTIMIZER_ERROR_BOUNDED ==
      static_cast<int>(morphnode::OptimizerPreset::ErrorBounded) &&
    vtkMorphNodeFilter::OPTIMIZER_ERROR_BOUNDED + 1 == morphnode::NumberOfOptimizerPresets,
  "vtkMorphNodeFilter::OptimizerPresets must match morphnode::OptimizerPreset");

namespace
{
/// Field-data arrays the filter writes; a neutral's arrays of these names are replaced.
const char* const OutputFieldArrays[] = { adapter::TargetNamesArray, adapter::EffectiveWeightsArray,
  adapter::ActiveTargetCountArray, adapter::ErrorBoundArray, adapter::DistNormArray };

bool SameWeight(double a, double b)
{
  return a == b || (a != a && b != b); // NaN set twice is no change either
}

/// `slot` when it has the layout of `prototype` and `holders` references are all it has
/// (nobody outside the filter holds it), else a new array of that layout in `slot`.
vtkDataArray* ReuseOrNew(
  vtkSmartPointer<vtkDataArray>& slot, vtkDataArray* prototype, vtkIdType numTuples, int holders)
{
  const bool reusable = slot && slot->GetReferenceCount() == holders &&
    slot->GetDataType() == prototype->GetDataType() &&
    slot->GetNumberOfComponents() == prototype->GetNumberOfComponents() &&
    slot->GetNumberOfTuples() == numTuples;
  if (!reusable)
  {
    slot.TakeReference(prototype->NewInstance());
    slot->SetName(prototype->GetName());
    slot->SetNumberOfComponents(prototype->GetNumberOfComponents());
    slot->SetNumberOfTuples(numTuples);
  }
  return slot;
}

/// Points a task blends at least: below that, handing work to another thread costs more
/// than it saves (a 1024-point range of positions and normals blends in about 1 us).
constexpr vtkIdType MinPointsPerTask = 2048;
}

struct vtkMorphNodeFilter::vtkInternals
{
  /// Requested weights, by index and by name; the one set last wins for a target (Order).
  struct Request
  {
    double Weight = 0.0;
    uint64_t Order = 0; // 0: not set
  };
  struct NamedRequest
  {
    std::string Name;
    Request Value;
    int Index = -1;                  // resolved against the model of generation Resolved
    uint64_t Resolved = 0;
  };
  std::vector<Request> ByIndex;
  std::vector<NamedRequest> ByName;
  uint64_t Orders = 0;

  /// The model built from the current input (shared with Node), and what it was built from.
  std::shared_ptr<const adapter::BuiltModel> Built;
  uint64_t Generation = 0; // counts the models built
  std::vector<vtkPointSet*> Inputs;
  std::vector<std::pair<vtkDataObject*, vtkMTimeType>> From, BuiltFrom;
  double BuiltSparseCoverage = -1.0;

  morphnode::MorphNode Node;
  bool Valid = false; // the last execution succeeded
  std::vector<double> Requested;
  std::vector<uint64_t> RequestOrder;
  vtkNew<vtkDoubleArray> DistNorm;

  /// Output arrays kept across executions: written again in place only when nothing but
  /// the filter holds them (the pipeline released the previous output), so that a snapshot
  /// kept downstream never changes under its holder.
  adapter::BlendOutputs Outputs;
  /// Where the blend writes each attribute: the output array itself, or for arrays of
  /// other types than the attribute's (integers) a buffer copied over afterwards.
  std::vector<morphnode::AttributeOutput> Where;
  std::vector<std::vector<float>> FloatScratch;
  std::vector<std::vector<double>> DoubleScratch;
  /// Made once per model, shared by every output.
  vtkSmartPointer<vtkStringArray> TargetNames;
  vtkSmartPointer<vtkDoubleArray> DistNormOut;
  std::vector<vtkSmartPointer<vtkDataArray>> Distances; // built on first request
  /// Per-execution field data, rewritten in place when no one else holds them.
  vtkSmartPointer<vtkDataArray> EffectiveWeightsOut, ActiveTargetCountOut, ErrorBoundOut;

  const std::vector<std::string>& Names() const
  {
    static const std::vector<std::string> none;
    return this->Built ? this->Built->Model.GetTargetNames() : none;
  }

  /// Requested weight of target `index`; names resolve against the current model.
  double Get(int index) const
  {
    Request r{ index == 0 ? 1.0 : 0.0, 0 };
    if (index >= 0 && static_cast<size_t>(index) < this->ByIndex.size() &&
      this->ByIndex[static_cast<size_t>(index)].Order)
    {
      r = this->ByIndex[static_cast<size_t>(index)];
    }
    const auto& names = this->Names();
    if (index >= 0 && static_cast<size_t>(index) < names.size())
    {
      for (const NamedRequest& n : this->ByName)
      {
        if (n.Value.Order > r.Order && n.Name == names[static_cast<size_t>(index)])
        {
          r = n.Value;
        }
      }
    }
    return r.Weight;
  }

  void SetByIndex(size_t index, double weight)
  {
    if (index >= this->ByIndex.size())
    {
      this->ByIndex.resize(index + 1);
    }
    this->ByIndex[index] = { weight, ++this->Orders };
  }

  void SetByName(const std::string& name, double weight)
  {
    for (NamedRequest& n : this->ByName)
    {
      if (n.Name == name)
      {
        n.Value = { weight, ++this->Orders };
        return;
      }
    }
    this->ByName.push_back({ name, { weight, ++this->Orders }, -1, 0 });
  }

  /// Rebuilds the model when an input or the storage choice changed.
  void UpdateModel(vtkMorphNodeFilter* self)
  {
    this->From.clear();
    for (vtkPointSet* input : this->Inputs)
    {
      this->From.emplace_back(input, input ? input->GetMTime() : 0);
    }
    if (this->Built && this->From == this->BuiltFrom &&
      this->BuiltSparseCoverage == self->SparseCoverage)
    {
      return;
    }
    this->Built.reset();
    this->Node.SetMesh(nullptr);
    this->BuiltFrom.clear();
    if (this->Inputs.empty())
    {
      throw morphnode::InputError("no input: connect the neutral (and the targets) to port 0");
    }
    self->UpdateProgress(0.0);
    auto built = std::make_shared<adapter::BuiltModel>(
      this->Inputs.size() == 1 && adapter::HasRelativeTargets(this->Inputs[0])
        ? adapter::BuildFromRelativeTargets(this->Inputs[0], self->SparseCoverage)
        : adapter::BuildFromAbsoluteTargets(this->Inputs, self->SparseCoverage));
    this->Node.SetMesh(std::shared_ptr<const morphnode::MorphMesh>(built, &built->Model));
    this->Built = std::move(built);
    ++this->Generation;
    this->BuiltFrom = this->From;
    this->BuiltSparseCoverage = self->SparseCoverage;
    // What depends on the model only is made once per model and shared by every output.
    const auto& distNorm = this->Node.GetTargetDistances().DistNorm;
    this->DistNorm->SetNumberOfValues(static_cast<vtkIdType>(distNorm.size()));
    std::copy(distNorm.begin(), distNorm.end(), this->DistNorm->GetPointer(0));
    this->TargetNames = adapter::MakeNamesArray(adapter::TargetNamesArray, this->Names());
    this->DistNormOut = vtkSmartPointer<vtkDoubleArray>::New();
    this->DistNormOut->DeepCopy(this->DistNorm);
    this->Distances.clear();
    this->Outputs = {};
  }

  /// Requested weights (neutral first): the table on port 1, else the assignments.
  void GatherRequested(vtkMorphNodeFilter* self, vtkTable* table)
  {
    const morphnode::MorphMesh& model = this->Built->Model;
    const size_t n = model.GetNumberOfTargets();
    if (table)
    {
      int matched = 0;
      this->Requested = adapter::WeightsFromTable(table, model, matched);
      if (matched == 0 && table->GetNumberOfColumns() > 0)
      {
        vtkWarningWithObjectMacro(self, << "the weights table on port 1 names none of the " << n
                                        << " targets; showing the neutral");
      }
      return;
    }
    this->Requested.assign(n, 0.0);
    this->Requested[0] = 1.0;
    this->RequestOrder.assign(n, 0);
    // Errors in the order the weights were set, as a user would read them.
    const NamedRequest* unknown = nullptr;
    size_t outOfRange = 0;
    uint64_t unknownOrder = 0, outOfRangeOrder = 0;
    for (size_t i = 0; i < this->ByIndex.size(); ++i)
    {
      const Request& r = this->ByIndex[i];
      if (r.Order && i >= n && (!outOfRangeOrder || r.Order < outOfRangeOrder))
      {
        outOfRange = i;
        outOfRangeOrder = r.Order;
      }
      else if (r.Order && i < n)
      {
        this->Requested[i] = r.Weight;
        this->RequestOrder[i] = r.Order;
      }
    }
    for (NamedRequest& named : this->ByName)
    {
      if (named.Resolved != this->Generation)
      {
        named.Index = model.FindTarget(named.Name);
        named.Resolved = this->Generation;
      }
      if (named.Index < 0)
      {
        if (!unknown || named.Value.Order < unknownOrder)
        {
          unknown = &named;
          unknownOrder = named.Value.Order;
        }
        continue;
      }
      const size_t i = static_cast<size_t>(named.Index);
      if (named.Value.Order > this->RequestOrder[i])
      {
        this->Requested[i] = named.Value.Weight;
        this->RequestOrder[i] = named.Value.Order;
      }
    }
    std::ostringstream msg;
    if (outOfRangeOrder && (!unknown || outOfRangeOrder < unknownOrder))
    {
      msg << "a weight is set for target " << outOfRange << ", but the input has " << n
          << " targets (0.." << n - 1 << ", neutral first)";
      throw morphnode::InputError(msg.str());
    }
    if (unknown)
    {
      msg << "a weight is set for target '" << unknown->Name
          << "', but no target has that name; targets:";
      for (const auto& name : model.GetTargetNames())
      {
        msg << " " << name;
      }
      throw morphnode::InputError(msg.str());
    }
  }

  /// The node's settings from the filter's.
  void ApplySettings(vtkMorphNodeFilter* self)
  {
    morphnode::OptimizerSettings settings;
    if (self->OptimizerPreset >= 0)
    {
      settings = morphnode::MakeOptimizerSettings(
        static_cast<morphnode::OptimizerPreset>(self->OptimizerPreset), self->Threshold,
        self->MaxVertexError);
    }
    else
    {
      settings.Threshold = self->Threshold;
      settings.Strategy = static_cast<morphnode::Redistribution>(self->RedistributionStrategy);
      settings.AdjustThreshold = self->AdjustThreshold;
      settings.MaxVertexError = self->MaxVertexError;
    }
    settings.MaxActiveTargets = self->MaxActiveTargets;
    settings.Hysteresis = self->Hysteresis;
    this->Node.SetOptimizerSettings(settings);
    this->Node.SetWeightMode(static_cast<morphnode::WeightMode>(self->WeightMode));
  }

  /// Blends every attribute with the node's effective weights into Outputs, in parallel
  /// over point ranges (morphnode::MorphNode::Blend).
  void Blend()
  {
    const morphnode::MorphMesh& mesh = this->Built->Model;
    const auto& bindings = this->Built->Bindings;
    const vtkIdType numPoints = static_cast<vtkIdType>(mesh.GetNumberOfPoints());
    const size_t numAttributes = mesh.GetNumberOfAttributes();
    // The points' array is held by the vtkPoints and by `points` here.
    vtkSmartPointer<vtkDataArray> points = this->Outputs.Points ? this->Outputs.Points->GetData() : nullptr;
    const bool pointsFree = this->Outputs.Points && this->Outputs.Points->GetReferenceCount() == 1;
    vtkDataArray* pointArray = ReuseOrNew(points, bindings[0].Prototype, numPoints, pointsFree ? 2 : 0);
    if (!pointsFree || this->Outputs.Points->GetData() != pointArray)
    {
      this->Outputs.Points = vtkSmartPointer<vtkPoints>::New();
      this->Outputs.Points->SetData(pointArray);
    }
    this->Outputs.Arrays.resize(numAttributes - 1);
    this->Where.resize(numAttributes);
    this->FloatScratch.resize(numAttributes);
    this->DoubleScratch.resize(numAttributes);
    for (size_t a = 0; a < numAttributes; ++a)
    {
      vtkDataArray* out = a == 0
        ? pointArray
        : ReuseOrNew(this->Outputs.Arrays[a - 1], bindings[a].Prototype, numPoints, 1);
      const size_t values = static_cast<size_t>(numPoints) * out->GetNumberOfComponents();
      if (std::holds_alternative<morphnode::MorphAttribute<float>>(mesh.GetAttribute(a)))
      {
        auto* direct = vtkFloatArray::FastDownCast(out);
        this->FloatScratch[a].resize(direct ? 0 : values);
        this->Where[a] = direct ? direct->GetPointer(0) : this->FloatScratch[a].data();
      }
      else
      {
        auto* direct = vtkDoubleArray::FastDownCast(out);
        this->DoubleScratch[a].resize(direct ? 0 : values);
        this->Where[a] = direct ? direct->GetPointer(0) : this->DoubleScratch[a].data();
      }
    }
    const morphnode::MorphNode& node = this->Node;
    node.CheckOutputs(this->Where);
    const int threads = vtkSMPTools::GetEstimatedNumberOfThreads();
    if (threads <= 1 || numPoints < 2 * MinPointsPerTask)
    {
      node.Blend(this->Where, 0, static_cast<size_t>(numPoints));
    }
    else
    {
      // A few ranges per thread: enough to even out a busy core, few enough that handing
      // them out costs little next to blending them.
      const vtkIdType grain = std::max(MinPointsPerTask, numPoints / (4 * threads));
      vtkSMPTools::For(0, numPoints, grain, [this, &node](vtkIdType begin, vtkIdType end) {
        node.Blend(this->Where, static_cast<size_t>(begin), static_cast<size_t>(end));
      });
    }
    for (size_t a = 0; a < numAttributes; ++a)
    {
      vtkDataArray* out = a == 0 ? pointArray : this->Outputs.Arrays[a - 1].GetPointer();
      if (!this->FloatScratch[a].empty())
      {
        vtkMorphTargetArrays::CopyToArray(this->FloatScratch[a].data(), out);
      }
      else if (!this->DoubleScratch[a].empty())
      {
        vtkMorphTargetArrays::CopyToArray(this->DoubleScratch[a].data(), out);
      }
      out->Modified(); // written through raw pointers: renderers re-upload on MTime
    }
    this->Outputs.Points->Modified();
  }

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
  template <typename ArrayT, typename Range>
  static vtkDataArray* Values(vtkSmartPointer<vtkDataArray>& slot, const char* name, const Range& values)
  {
    ArrayT* array = ArrayT::SafeDownCast(slot);
    if (!array || slot->GetReferenceCount() != 1)
    {
      auto fresh = vtkSmartPointer<ArrayT>::New();
      fresh->SetName(name);
      slot = fresh;
      array = fresh;
    }
    array->SetNumberOfValues(static_cast<vtkIdType>(std::size(values)));
    vtkIdType i = 0;
    for (const auto value : values)
    {
      array->SetValue(i++, static_cast<typename ArrayT::ValueType>(value));
    }
    array->Modified();
    return array;
  }

  /// The neutral's structure, blended arrays in place of the neutral's, field data.
  void AssembleOutput(vtkMorphNodeFilter* self, vtkPointSet* neutral, vtkPointSet* output)
  {
    output->CopyStructure(neutral);
    output->SetPoints(this->Outputs.Points);
    adapter::AssemblePointData(neutral->GetPointData(), *this->Built, this->Outputs, output->GetPointData());
    output->GetCellData()->PassData(neutral->GetCellData());
    if (self->GenerateDistanceArrays)
    {
      for (vtkDataArray* array : this->DistanceArrays())
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
    const morphnode::MorphNode& node = this->Node;
    fd->AddArray(this->TargetNames);
    fd->AddArray(Values<vtkDoubleArray>(
      this->EffectiveWeightsOut, adapter::EffectiveWeightsArray, node.GetEffectiveWeights()));
    const int active[] = { node.GetActiveTargetCount() };
    fd->AddArray(Values<vtkIntArray>(this->ActiveTargetCountOut, adapter::ActiveTargetCountArray, active));
    const double bound[] = { node.GetErrorBound() };
    fd->AddArray(Values<vtkDoubleArray>(this->ErrorBoundOut, adapter::ErrorBoundArray, bound));
    if (self->GenerateDistanceArrays)
    {
      fd->AddArray(this->DistNormOut);
    }
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
  const auto& names = this->Internals->Names();
  return index >= 0 && static_cast<size_t>(index) < names.size()
    ? names[static_cast<size_t>(index)].c_str()
    : nullptr;
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
  const double current = this->Internals->Get(index);
  this->Internals->SetByIndex(static_cast<size_t>(index), weight);
  if (!SameWeight(current, weight))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetWeight(int index)
{
  return this->Internals->Get(index);
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
  this->Internals->SetByName(name, weight);
  if (!SameWeight(current, weight))
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
  for (const auto& named : this->Internals->ByName) // not yet resolvable: the value set
  {
    if (named.Name == name)
    {
      return named.Value.Weight;
    }
  }
  return 0.0;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetWeights()
{
  vtkInternals& internals = *this->Internals;
  if (!internals.ByIndex.empty() || !internals.ByName.empty())
  {
    internals.ByIndex.clear();
    internals.ByName.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetEffectiveWeight(int index)
{
  const auto& w = this->Internals->Node.GetEffectiveWeights();
  return this->Internals->Valid && index >= 0 && static_cast<size_t>(index) < w.size()
    ? w[static_cast<size_t>(index)]
    : 0.0;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetHysteresis()
{
  this->Internals->Node.ResetHistory();
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetOptimizerPreset(int preset)
{
  preset = std::max<int>(OPTIMIZER_CUSTOM, std::min<int>(preset, OPTIMIZER_ERROR_BOUNDED));
  if (preset >= 0)
  {
    // The preset's own strategy and adjustment, so that the getters tell what is used.
    const morphnode::OptimizerSettings s =
      morphnode::MakeOptimizerSettings(static_cast<morphnode::OptimizerPreset>(preset), 0.0, 0.0);
    if (this->RedistributionStrategy != static_cast<int>(s.Strategy) ||
      this->AdjustThreshold != s.AdjustThreshold)
    {
      this->RedistributionStrategy = static_cast<int>(s.Strategy);
      this->AdjustThreshold = s.AdjustThreshold;
      this->Modified();
    }
  }
  if (this->OptimizerPreset != preset)
  {
    this->OptimizerPreset = preset;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetOptimizerPresetByName(const char* name)
{
  if (!name)
  {
    vtkErrorMacro(<< "SetOptimizerPresetByName: no name");
    return;
  }
  if (std::strcmp(name, "custom") == 0)
  {
    this->SetOptimizerPreset(OPTIMIZER_CUSTOM);
    return;
  }
  try
  {
    this->SetOptimizerPreset(static_cast<int>(morphnode::ParseOptimizerPreset(name)));
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "SetOptimizerPresetByName: " << e.what() << " or custom");
  }
}

//------------------------------------------------------------------------------
const char* vtkMorphNodeFilter::GetOptimizerPresetAsString()
{
  return this->OptimizerPreset >= 0
    ? morphnode::OptimizerPresetName(static_cast<morphnode::OptimizerPreset>(this->OptimizerPreset))
    : "custom";
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetRedistributionStrategy(int strategy)
{
  strategy = std::max<int>(MAXIMUM, std::min<int>(strategy, NEUTRAL));
  if (this->RedistributionStrategy != strategy)
  {
    this->RedistributionStrategy = strategy;
    this->OptimizerPreset = OPTIMIZER_CUSTOM;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetAdjustThreshold(bool adjust)
{
  if (this->AdjustThreshold != adjust)
  {
    this->AdjustThreshold = adjust;
    this->OptimizerPreset = OPTIMIZER_CUSTOM;
    this->Modified();
  }
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
const morphnode::MorphNode* vtkMorphNodeFilter::GetMorphNode()
{
  return &this->Internals->Node;
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
  internals.Valid = false;
  this->ActiveTargetCount = 0;
  this->ErrorBound = 0.0;
  try
  {
    // 1. The mesh, rebuilt only when an input or the storage choice changed.
    internals.Inputs.clear();
    for (int i = 0; i < inputVector[0]->GetNumberOfInformationObjects(); ++i)
    {
      internals.Inputs.push_back(vtkPointSet::GetData(inputVector[0], i));
    }
    internals.UpdateModel(this);
    this->UpdateProgress(0.3);

    // 2. Weight rules and the optimizer: the core node.
    internals.GatherRequested(this, vtkTable::GetData(inputVector[1], 0));
    internals.ApplySettings(this);
    internals.Node.SetWeights(internals.Requested);
    this->UpdateProgress(0.4);

    // 3. The blend, in parallel over points, into arrays of the input's types.
    internals.Blend();
    this->UpdateProgress(0.9);

    // 4. The output: the neutral's structure with the blended arrays and field data.
    internals.AssembleOutput(this, internals.Inputs[0], output);
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
        outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
    internals.Valid = true;
    this->ActiveTargetCount = internals.Node.GetActiveTargetCount();
    this->ErrorBound = internals.Node.GetErrorBound();
    this->UpdateProgress(1.0);
    return 1;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    return 0;
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const vtkInternals& internals = *this->Internals;
  os << indent << "WeightMode: " << this->GetWeightModeAsString() << "\n";
  os << indent << "OptimizerPreset: " << this->GetOptimizerPresetAsString() << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "RedistributionStrategy: " << this->GetRedistributionStrategyAsString() << "\n";
  os << indent << "AdjustThreshold: " << (this->AdjustThreshold ? "On" : "Off") << "\n";
  os << indent << "MaxVertexError: " << this->MaxVertexError << "\n";
  os << indent << "MaxActiveTargets: " << this->MaxActiveTargets << "\n";
  os << indent << "Hysteresis: " << this->Hysteresis << "\n";
  os << indent << "GenerateDistanceArrays: " << (this->GenerateDistanceArrays ? "On" : "Off") << "\n";
  os << indent << "SparseCoverage: " << this->SparseCoverage << "\n";
  os << indent << "NumberOfTargets: " << internals.Names().size() << "\n";
  os << indent << "Weights (requested):";
  for (size_t i = 0; i < internals.ByIndex.size(); ++i)
  {
    if (internals.ByIndex[i].Order)
    {
      os << " " << i << "=" << internals.ByIndex[i].Weight;
    }
  }
  for (const auto& named : internals.ByName)
  {
    os << " " << named.Name << "=" << named.Value.Weight;
  }
  os << "\n";
  os << indent << "EffectiveWeights:";
  if (internals.Valid)
  {
    for (double w : internals.Node.GetEffectiveWeights())
    {
      os << " " << w;
    }
  }
  os << "\n";
  os << indent << "ActiveTargetCount: " << this->ActiveTargetCount << "\n";
  os << indent << "ErrorBound: " << this->ErrorBound << "\n";
}
