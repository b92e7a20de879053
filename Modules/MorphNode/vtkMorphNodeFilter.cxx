// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphNodeFilter.h"

#include "vtkMorphModelAdapter.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "budget/DeviceProfile.h"
#include "budget/FrameBudgetController.h"
#include "morph/MorphScene.h"
#include "morph/OptimizerPresets.h"
#include "morph/Weights.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <map>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <set>
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

/// Points a task blends at least: below that, handing work to another thread costs more
/// than it saves (a 1024-point range of positions and normals blends in about 1 us).
constexpr vtkIdType MinPointsPerTask = 2048;
}

namespace
{
/// The processes' exchange of their pieces' figures (SetController): every process sends its
/// piece (or that it has none, or its error) to every other, and all combine them in process
/// order, so that they decide exactly alike.
namespace exchange
{
using morphnode::NamedTargetDistances;

std::string Pack(const NamedTargetDistances* piece, const std::string& error)
{
  std::string out;
  if (!error.empty())
  {
    return "E" + error;
  }
  if (!piece)
  {
    return "0";
  }
  out.push_back('P');
  auto put = [&out](const void* p, size_t bytes) { out.append(static_cast<const char*>(p), bytes); };
  const uint64_t n = piece->Names.size();
  put(&n, sizeof(n));
  for (const std::string& name : piece->Names)
  {
    const uint64_t length = name.size();
    put(&length, sizeof(length));
    out += name;
  }
  put(piece->DistMorph.data(), n * sizeof(double));
  put(piece->MaxDisplacement.data(), n * sizeof(double));
  return out;
}

/// 'P' with `piece` filled, '0' (no piece), or 'E' with `error` filled.
char Unpack(const char* data, size_t size, NamedTargetDistances& piece, std::string& error)
{
  if (size == 0)
  {
    throw morphnode::InputError("internal: an empty message from another process");
  }
  if (data[0] == 'E')
  {
    error.assign(data + 1, size - 1);
    return 'E';
  }
  if (data[0] == '0')
  {
    return '0';
  }
  size_t at = 1;
  auto get = [&](void* p, size_t bytes) {
    if (bytes > size - at)
    {
      throw morphnode::InputError("internal: a truncated message from another process");
    }
    std::memcpy(p, data + at, bytes);
    at += bytes;
  };
  uint64_t n = 0;
  get(&n, sizeof(n));
  if (n > size)
  {
    throw morphnode::InputError("internal: a garbled message from another process");
  }
  piece.Names.resize(n);
  for (std::string& name : piece.Names)
  {
    uint64_t length = 0;
    get(&length, sizeof(length));
    if (length > size - at)
    {
      throw morphnode::InputError("internal: a truncated message from another process");
    }
    name.assign(data + at, length);
    at += length;
  }
  piece.DistMorph.resize(n);
  piece.MaxDisplacement.resize(n);
  get(piece.DistMorph.data(), n * sizeof(double));
  get(piece.MaxDisplacement.data(), n * sizeof(double));
  return 'P';
}

/// The whole model's figures: every process's piece, combined in process order. Throws the
/// first process's error (the same on every process) when any had one.
NamedTargetDistances Gather(
  vtkMultiProcessController* controller, const NamedTargetDistances* piece, const std::string& error)
{
  const std::string message = Pack(piece, error);
  const int processes = controller->GetNumberOfProcesses();
  const long long length = static_cast<long long>(message.size());
  std::vector<long long> lengths(static_cast<size_t>(processes), 0);
  if (!controller->AllGather(&length, lengths.data(), 1))
  {
    throw morphnode::InputError("the processes could not exchange their targets' figures");
  }
  std::vector<vtkIdType> recvLengths(lengths.begin(), lengths.end());
  std::vector<vtkIdType> offsets(static_cast<size_t>(processes), 0);
  vtkIdType total = 0;
  for (int r = 0; r < processes; ++r)
  {
    offsets[static_cast<size_t>(r)] = total;
    total += recvLengths[static_cast<size_t>(r)];
  }
  std::vector<char> all(static_cast<size_t>(total));
  if (!controller->AllGatherV(message.data(), all.data(), length, recvLengths.data(), offsets.data()))
  {
    throw morphnode::InputError("the processes could not exchange their targets' figures");
  }
  std::vector<NamedTargetDistances> pieces;
  for (int r = 0; r < processes; ++r)
  {
    NamedTargetDistances received;
    std::string failure;
    const char kind = Unpack(all.data() + offsets[static_cast<size_t>(r)],
      static_cast<size_t>(recvLengths[static_cast<size_t>(r)]), received, failure);
    if (kind == 'E')
    {
      throw morphnode::InputError(
        (r == controller->GetLocalProcessId() ? "" : "process " + std::to_string(r) + ": ") + failure);
    }
    if (kind == 'P')
    {
      pieces.push_back(std::move(received));
    }
  }
  if (pieces.empty())
  {
    throw morphnode::InputError("no process has a point in its input");
  }
  return morphnode::CombineTargetDistances(pieces);
}
} // namespace exchange

/// Points flagged as duplicates of another piece's (vtkGhostType, DUPLICATEPOINT): left out
/// of the model's sums. Empty when the data set flags none.
std::vector<uint8_t> DuplicateFlags(vtkPointSet* input)
{
  std::vector<uint8_t> flags;
  vtkUnsignedCharArray* ghosts = input ? input->GetPointGhostArray() : nullptr;
  if (!ghosts || ghosts->GetNumberOfTuples() != input->GetNumberOfPoints())
  {
    return flags;
  }
  bool any = false;
  flags.resize(static_cast<size_t>(input->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    flags[static_cast<size_t>(i)] = (ghosts->GetValue(i) & vtkDataSetAttributes::DUPLICATEPOINT) ? 1 : 0;
    any = any || flags[static_cast<size_t>(i)];
  }
  if (!any)
  {
    flags.clear();
  }
  return flags;
}

/// A leaf's name for messages: its metadata NAME, else its flat index.
std::string LeafName(vtkCompositeDataIterator* it)
{
  vtkInformation* meta = it->HasCurrentMetaData() ? it->GetCurrentMetaData() : nullptr;
  if (meta && meta->Has(vtkCompositeDataSet::NAME()) && meta->Get(vtkCompositeDataSet::NAME()))
  {
    return meta->Get(vtkCompositeDataSet::NAME());
  }
  return "#" + std::to_string(it->GetCurrentFlatIndex());
}

vtkSmartPointer<vtkCompositeDataIterator> Leaves(vtkCompositeDataSet* composite)
{
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(composite->NewIterator());
  it->SkipEmptyNodesOn();
  return it;
}
} // namespace

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

  /// One data set of the input (the one input, or a leaf of a composite) with its model
  /// and the arrays its blend writes.
  struct Part
  {
    vtkPointSet* Input = nullptr; // this execution's data set (the neutral in the Java3D form)
    std::string Name;             // a leaf's name, for messages
    std::shared_ptr<const adapter::BuiltModel> Built; // null: an empty leaf, passed through
    int ScenePart = -1;                               // its part in Scene, -1: none
    /// Output arrays kept across executions: written again in place only when nothing but
    /// the filter holds them (the pipeline released the previous output), so that a
    /// snapshot kept downstream never changes under its holder.
    adapter::BlendOutputs Outputs;
    /// Where the blend writes each attribute: the output array itself, or for arrays of
    /// other types than the attribute's (integers) a buffer copied over afterwards.
    std::vector<morphnode::AttributeOutput> Where;
    std::vector<std::vector<float>> FloatScratch;
    std::vector<std::vector<double>> DoubleScratch;
    std::vector<vtkSmartPointer<vtkDataArray>> Distances; // built on first request
    bool Blended = false;                                 // in this execution
    /// A composite's output leaf, kept across executions and filled again in place when
    /// nothing but the filter holds it: making and filling 11 data sets per step cost a
    /// fifth of a head's Update. A kept leaf keeps its structure, cell data and the
    /// neutral's field data (the input cannot have changed: that rebuilds the model, and
    /// the parts); its points and point data are assembled again.
    vtkSmartPointer<vtkPointSet> OutputLeaf;
    bool LeafKept = false;
    bool HasDistNorm = false; // the kept leaf's field data holds DistNorm
  };
  std::vector<Part> Parts;
  bool Composite = false;
  /// SetTargetOffInPart: part name -> targets off there; applied to the scene's parts.
  std::map<std::string, std::vector<std::string>> TargetsOff;
  bool TargetsOffApplied = false; // some part of the scene has targets off

  void ApplyTargetsOff()
  {
    if (this->TargetsOff.empty() && !this->TargetsOffApplied)
    {
      return;
    }
    this->TargetsOffApplied = false;
    for (const Part& part : this->Parts)
    {
      if (part.ScenePart < 0)
      {
        continue;
      }
      auto it = this->TargetsOff.find(part.Name);
      if (it == this->TargetsOff.end())
      {
        it = this->TargetsOff.find(part.Name.substr(0, part.Name.rfind('/')));
      }
      static const std::vector<std::string> none;
      this->Scene.SetPartTargetsOff(
        static_cast<size_t>(part.ScenePart), it == this->TargetsOff.end() ? none : it->second);
      this->TargetsOffApplied = this->TargetsOffApplied || it != this->TargetsOff.end();
    }
  }

  /// This execution's inputs: the connections of port 0 (one form) or a composite's leaves.
  std::vector<vtkPointSet*> Inputs;
  vtkCompositeDataSet* CompositeInput = nullptr;
  std::vector<vtkPointSet*> LeafInputs;

  /// The model: the scene of the parts (targets matched by name, one decision), and what it
  /// was built from.
  morphnode::MorphScene Scene;
  bool HasScene = false; // the scene has parts (a process with an empty piece has none)
  bool Ready = false;    // a model was built from the current inputs
  morphnode::MorphMesh NamesModel; // the model's target names only, for lookups by name
  morphnode::TargetDistances ModelDistances;
  uint64_t Generation = 0; // counts the models built
  std::vector<std::pair<vtkDataObject*, vtkMTimeType>> From, BuiltFrom;
  double BuiltSparseCoverage = -1.0;

  bool Valid = false; // the last execution succeeded
  std::vector<double> Requested;
  std::vector<uint64_t> RequestOrder;
  vtkNew<vtkDoubleArray> DistNorm;

  /// Blend work: the point ranges of the parts to blend, one after the other, and the
  /// tasks, each a run of about `grain` points over one or more consecutive ranges (small
  /// parts share a task).
  struct Range
  {
    size_t Part;
    size_t Begin, End;
  };
  std::vector<Range> Ranges;
  std::vector<size_t> Tasks; // first range of each task, then Ranges.size()

  /// Made once per model, shared by every output.
  vtkSmartPointer<vtkStringArray> TargetNames;
  vtkSmartPointer<vtkDoubleArray> DistNormOut;
  /// The frame budget (FrameBudget > 0): a controller over the model as its one level,
  /// made again when the model or the method changes (keeping the cost model it measured),
  /// and the last execution's measurement, reported when the next one decides (so that in
  /// parallel every process exchanges it at the same point).
  morphnode::FrameBudgetController Budget;
  morphnode::ControllerSettings BudgetSettings;
  uint64_t BudgetGeneration = 0; // the model Budget was made for; 0: none
  std::vector<double> MovedPoints; // per model target, summed over every process's parts
  double ModelPoints = 0.0;
  bool BudgetDecided = false; // this execution's threshold came from Budget
  bool HasMeasurement = false;
  double MeasuredSeconds = 0.0, MeasuredTargetPoints = 0.0;

  /// Per-execution field data, rewritten in place when no one else holds them.
  vtkSmartPointer<vtkDataArray> EffectiveWeightsOut, ActiveTargetCountOut, ErrorBoundOut;

  const std::vector<std::string>& Names() const { return this->NamesModel.GetTargetNames(); }

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

  /// This execution's inputs from port 0.
  void CollectInputs(vtkInformationVector* port0)
  {
    this->Inputs.clear();
    this->LeafInputs.clear();
    this->CompositeInput = vtkCompositeDataSet::GetData(port0, 0);
    if (this->CompositeInput)
    {
      if (port0->GetNumberOfInformationObjects() > 1)
      {
        throw morphnode::InputError("a composite input (a whole head) must be the only connection of "
                                    "port 0; the Java3D form takes point sets");
      }
      auto it = Leaves(this->CompositeInput);
      for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
      {
        vtkDataObject* leaf = it->GetCurrentDataObject();
        auto* points = vtkPointSet::SafeDownCast(leaf);
        if (!points)
        {
          throw morphnode::InputError("part '" + this->LeafNames()[this->LeafInputs.size()] +
            "' of the composite input is a " + leaf->GetClassName() + "; the morph node blends point sets");
        }
        this->LeafInputs.push_back(points);
      }
      return;
    }
    for (int i = 0; i < port0->GetNumberOfInformationObjects(); ++i)
    {
      this->Inputs.push_back(vtkPointSet::GetData(port0, i));
    }
  }

  /// The composite input's leaves' names, in the iterator's order, for messages: a
  /// collection names its partitioned data sets (the reader's parts), not their partitions;
  /// other composites name their leaves (else "#<flat index>").
  std::vector<std::string> LeafNames() const
  {
    std::vector<std::string> names;
    auto* collection = vtkPartitionedDataSetCollection::SafeDownCast(this->CompositeInput);
    for (unsigned int d = 0; collection && d < collection->GetNumberOfPartitionedDataSets(); ++d)
    {
      vtkPartitionedDataSet* parts = collection->GetPartitionedDataSet(d);
      const char* name = collection->HasMetaData(d) && collection->GetMetaData(d)->Has(vtkCompositeDataSet::NAME())
        ? collection->GetMetaData(d)->Get(vtkCompositeDataSet::NAME())
        : nullptr;
      const unsigned int count = parts ? parts->GetNumberOfPartitions() : 0;
      for (unsigned int i = 0; i < count; ++i)
      {
        if (parts->GetPartitionAsDataObject(i))
        {
          const std::string part = name ? name : "#" + std::to_string(d);
          names.push_back(count > 1 ? part + "/" + std::to_string(i) : part);
        }
      }
    }
    if (!collection && this->CompositeInput)
    {
      auto it = Leaves(this->CompositeInput);
      for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
      {
        names.push_back(LeafName(it));
      }
    }
    names.resize(std::max(names.size(), this->LeafInputs.size() + 1), "?");
    return names;
  }

  /// Rebuilds the model when an input or the storage choice changed. In parallel, every
  /// process takes part in the exchange of a rebuild, whatever its input.
  void UpdateModel(vtkMorphNodeFilter* self)
  {
    this->From.clear();
    if (this->CompositeInput)
    {
      this->From.emplace_back(this->CompositeInput, this->CompositeInput->GetMTime());
      for (vtkPointSet* leaf : this->LeafInputs)
      {
        this->From.emplace_back(leaf, leaf->GetMTime());
      }
    }
    for (vtkPointSet* input : this->Inputs)
    {
      this->From.emplace_back(input, input ? input->GetMTime() : 0);
    }
    const bool composite = this->CompositeInput != nullptr;
    if (this->Ready && this->From == this->BuiltFrom && this->Composite == composite &&
      this->BuiltSparseCoverage == self->SparseCoverage)
    {
      return; // the same data set objects, unchanged: the same model
    }
    this->Ready = false;
    this->HasScene = false;
    this->Scene = morphnode::MorphScene();
    this->Parts.clear();
    this->BuiltFrom.clear();
    this->NamesModel.SetTargetNames({});
    this->Composite = composite;
    vtkMultiProcessController* controller = self->Controller;
    const bool parallel = controller && controller->GetNumberOfProcesses() > 1;
    self->UpdateProgress(0.0);

    std::string error;
    try
    {
      std::vector<std::shared_ptr<const morphnode::MorphMesh>> meshes;
      std::vector<std::vector<uint8_t>> flags;
      auto addPart = [&](Part part, adapter::BuiltModel built) {
        auto shared = std::make_shared<adapter::BuiltModel>(std::move(built));
        part.ScenePart = static_cast<int>(meshes.size());
        meshes.emplace_back(shared, &shared->Model);
        flags.push_back(DuplicateFlags(part.Input));
        part.Built = std::move(shared);
        this->Parts.push_back(std::move(part));
      };
      if (composite)
      {
        const std::vector<std::string> names = this->LeafNames();
        for (size_t i = 0; i < this->LeafInputs.size(); ++i)
        {
          vtkPointSet* leaf = this->LeafInputs[i];
          const std::string& name = names[i];
          Part part;
          part.Input = leaf;
          part.Name = name;
          if (leaf->GetNumberOfPoints() == 0)
          {
            this->Parts.push_back(std::move(part)); // an empty piece: passes through
            continue;
          }
          try
          {
            adapter::BuiltModel built = adapter::HasRelativeTargets(leaf)
              ? adapter::BuildFromRelativeTargets(leaf, self->SparseCoverage)
              : adapter::BuildFromAbsoluteTargets({ leaf }, self->SparseCoverage);
            addPart(std::move(part), std::move(built));
          }
          catch (const std::exception& e)
          {
            throw morphnode::InputError("part '" + name + "': " + e.what());
          }
        }
        if (meshes.empty() && !parallel)
        {
          throw morphnode::InputError("the composite input has no points in any part");
        }
      }
      else if (this->Inputs.empty())
      {
        throw morphnode::InputError("no input: connect the neutral (and the targets) to port 0");
      }
      else if (parallel && this->Inputs[0] && this->Inputs[0]->GetNumberOfPoints() == 0)
      {
        Part part; // an empty piece of the model on this process: passes through
        part.Input = this->Inputs[0];
        this->Parts.push_back(std::move(part));
      }
      else
      {
        Part part;
        part.Input = this->Inputs[0];
        addPart(std::move(part),
          this->Inputs.size() == 1 && adapter::HasRelativeTargets(this->Inputs[0])
            ? adapter::BuildFromRelativeTargets(this->Inputs[0], self->SparseCoverage)
            : adapter::BuildFromAbsoluteTargets(this->Inputs, self->SparseCoverage));
      }
      if (!meshes.empty())
      {
        this->Scene.SetParts(meshes, flags);
        this->HasScene = true;
      }
    }
    catch (const std::exception& e)
    {
      error = e.what();
      if (error.empty())
      {
        error = "the input could not be made into a model";
      }
    }
    if (parallel)
    {
      // The whole model's figures, the same on every process.
      const morphnode::NamedTargetDistances model = exchange::Gather(
        controller, this->HasScene && error.empty() ? &this->Scene.GetPartsDistances() : nullptr, error);
      if (this->HasScene)
      {
        this->Scene.SetModel(model);
      }
      this->NamesModel.SetTargetNames(model.Names);
      this->ModelDistances = morphnode::MakeTargetDistances(model);
    }
    else if (!error.empty())
    {
      throw morphnode::InputError(error);
    }
    else
    {
      this->NamesModel.SetTargetNames(this->Scene.GetTargetNames());
      this->ModelDistances = this->Scene.GetTargetDistances();
    }
    ++this->Generation;
    this->Ready = true;
    this->BuiltFrom = this->From;
    this->BuiltSparseCoverage = self->SparseCoverage;
    // What depends on the model only is made once per model and shared by every output.
    const auto& distNorm = this->ModelDistances.DistNorm;
    this->DistNorm->SetNumberOfValues(static_cast<vtkIdType>(distNorm.size()));
    std::copy(distNorm.begin(), distNorm.end(), this->DistNorm->GetPointer(0));
    this->TargetNames = adapter::MakeNamesArray(adapter::TargetNamesArray, this->Names());
    this->DistNormOut = vtkSmartPointer<vtkDoubleArray>::New();
    this->DistNormOut->DeepCopy(this->DistNorm);
  }

  /// Requested weights (neutral first): the table on port 1, else the assignments.
  void GatherRequested(vtkMorphNodeFilter* self, vtkTable* table)
  {
    const morphnode::MorphMesh& model = this->NamesModel;
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

  /// The scene's settings from the filter's.
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
    this->Scene.SetOptimizerSettings(settings);
    this->Scene.SetWeightMode(static_cast<morphnode::WeightMode>(self->WeightMode));
  }

  /// Points moved by each model target (the positions' non-zero deltas) over every part and,
  /// in parallel, every process; and the model's points.
  void CountMovedPoints(vtkMultiProcessController* controller, bool parallel)
  {
    this->MovedPoints.assign(this->Names().size(), 0.0);
    double points = 0.0;
    if (this->HasScene)
    {
      for (size_t p = 0; p < this->Scene.GetNumberOfParts(); ++p)
      {
        const morphnode::MorphMesh& mesh = this->Scene.GetPart(p);
        const std::vector<size_t>& targets = this->Scene.GetPartTargets(p);
        points += static_cast<double>(mesh.GetNumberOfPoints());
        std::visit(
          [&](const auto& positions) {
            for (size_t k = 1; k < positions.GetNumberOfTargets() && k < targets.size(); ++k)
            {
              if (targets[k] < this->MovedPoints.size())
              {
                this->MovedPoints[targets[k]] +=
                  static_cast<double>(positions.GetTarget(k).GetNumberOfMovedPoints());
              }
            }
          },
          mesh.GetAttribute(0));
      }
    }
    this->MovedPoints.push_back(points);
    if (parallel)
    {
      std::vector<double> sum(this->MovedPoints.size());
      if (!controller->AllReduce(this->MovedPoints.data(), sum.data(),
            static_cast<vtkIdType>(sum.size()), vtkCommunicator::SUM_OP))
      {
        throw morphnode::InputError("the processes could not exchange their moved points");
      }
      this->MovedPoints.swap(sum);
    }
    this->ModelPoints = this->MovedPoints.back();
    this->MovedPoints.pop_back();
  }

  /// With a frame budget: reports the last execution's measurement (in parallel the slowest
  /// process's) and lets the controller choose this execution's threshold, which replaces
  /// the scene's. Every process calls it (an empty piece too), after ApplySettings.
  void ChooseThreshold(vtkMorphNodeFilter* self)
  {
    this->BudgetDecided = false;
    self->FrameBudgetThreshold = -1.0;
    const bool targetLod = self->PixelsPerUnit > 0.0 && self->TargetPixelBound > 0.0;
    if ((self->FrameBudget <= 0.0 && !targetLod) || !this->Ready)
    {
      this->HasMeasurement = false;
      return;
    }
    vtkMultiProcessController* controller = self->Controller;
    const bool parallel = controller && controller->GetNumberOfProcesses() > 1;
    double measured[3] = { this->HasMeasurement ? 1.0 : 0.0, this->MeasuredSeconds,
      this->MeasuredTargetPoints };
    if (parallel)
    {
      double slowest[3];
      if (!controller->AllReduce(measured, slowest, 3, vtkCommunicator::MAX_OP))
      {
        throw morphnode::InputError("the processes could not exchange their morph times");
      }
      std::copy(slowest, slowest + 3, measured);
    }
    this->HasMeasurement = false;

    const morphnode::OptimizerSettings settings = this->HasScene
      ? this->Scene.GetOptimizerSettings()
      : morphnode::OptimizerSettings{};
    morphnode::ControllerSettings cs;
    cs.FrameBudget = self->FrameBudget > 0.0 ? 1e-3 * self->FrameBudget : 1.0; // target LOD alone: no limit
    cs.TargetPixelBound = targetLod ? self->TargetPixelBound : 0.0;
    cs.Strategy = settings.Strategy;
    cs.AdjustThreshold = settings.AdjustThreshold;
    cs.OptimizerHysteresis = settings.Hysteresis;
    cs.MaxActiveTargets = settings.MaxActiveTargets;
    cs.MaxVertexError = settings.MaxVertexError;
    cs.GeomorphFrames = 0;
    const morphnode::ControllerSettings& was = this->BudgetSettings;
    const bool sameModel = this->BudgetGeneration == this->Generation;
    if (!sameModel)
    {
      this->CountMovedPoints(controller, parallel);
    }
    else if (measured[0] > 0.0 && this->Budget.GetNumberOfLevels() > 0)
    {
      this->Budget.ReportMeasuredSeconds(measured[1], measured[2]);
    }
    if (!this->HasScene)
    {
      this->BudgetGeneration = this->Generation;
      return; // an empty piece: took part in the exchanges, decides nothing
    }
    if (!sameModel || this->Budget.GetNumberOfLevels() == 0 || was.FrameBudget != cs.FrameBudget ||
      was.Strategy != cs.Strategy || was.AdjustThreshold != cs.AdjustThreshold ||
      was.OptimizerHysteresis != cs.OptimizerHysteresis ||
      was.MaxActiveTargets != cs.MaxActiveTargets || was.MaxVertexError != cs.MaxVertexError ||
      was.TargetPixelBound != cs.TargetPixelBound)
    {
      // A first guess (about a desktop's blend), replaced by measurements from the first
      // execution on; what was measured survives a change of method.
      morphnode::CostModel cost;
      cost.Fixed = 50e-6;
      cost.PerTargetPoint = 2e-9;
      if (sameModel && this->Budget.GetNumberOfLevels() > 0)
      {
        cost = this->Budget.GetCostModel(0);
      }
      morphnode::LevelOfDetail level;
      level.Name = "model";
      level.NumberOfPoints = static_cast<size_t>(this->ModelPoints);
      level.MovedPoints = this->MovedPoints;
      level.Distances = this->Scene.GetTargetDistances();
      level.Cost = cost;
      this->Budget = morphnode::FrameBudgetController();
      this->Budget.SetSettings(cs);
      this->Budget.AddLevel(level);
      this->BudgetSettings = cs;
      this->BudgetGeneration = this->Generation;
    }
    std::vector<double> absolute;
    morphnode::ResolveWeights(this->Scene.GetWeightMode(), this->Requested.data(),
      this->Requested.size(), absolute);
    const morphnode::ControllerDecision decision =
      this->Budget.Update(absolute, targetLod ? self->PixelsPerUnit : 0.0);
    morphnode::OptimizerSettings chosen = settings;
    chosen.Threshold = self->FrameBudget > 0.0 ? decision.Threshold : settings.Threshold;
    if (decision.TargetErrorBound > 0.0)
    {
      // The target level of detail: the scene's own optimizer keeps the bound.
      chosen.MaxVertexError = chosen.MaxVertexError > 0.0
        ? std::min(chosen.MaxVertexError, decision.TargetErrorBound)
        : decision.TargetErrorBound;
    }
    this->Scene.SetOptimizerSettings(chosen);
    self->FrameBudgetThreshold = self->FrameBudget > 0.0 ? decision.Threshold : -1.0;
    this->BudgetDecided = true;
  }

  /// Keeps this execution's morph time for the next decision.
  void Measure(double seconds)
  {
    this->HasMeasurement = this->BudgetDecided;
    this->MeasuredSeconds = seconds;
    double targetPoints = 0.0;
    if (this->BudgetDecided)
    {
      const auto& w = this->Scene.GetEffectiveWeights();
      for (size_t i = 1; i < w.size() && i < this->MovedPoints.size(); ++i)
      {
        targetPoints += w[i] != 0.0 ? this->MovedPoints[i] : 0.0;
      }
    }
    this->MeasuredTargetPoints = targetPoints;
  }

  /// Output arrays of a part for this execution, and where the blend writes them.
  void PrepareOutputs(Part& part)
  {
    const morphnode::MorphMesh& mesh = part.Built->Model;
    const auto& bindings = part.Built->Bindings;
    const vtkIdType numPoints = static_cast<vtkIdType>(mesh.GetNumberOfPoints());
    const size_t numAttributes = mesh.GetNumberOfAttributes();
    adapter::BlendOutputs& outputs = part.Outputs;
    // The points' array is held by the vtkPoints and by `points` here.
    vtkSmartPointer<vtkDataArray> points = outputs.Points ? outputs.Points->GetData() : nullptr;
    const bool pointsFree = outputs.Points && outputs.Points->GetReferenceCount() == 1;
    vtkDataArray* pointArray = adapter::ReuseOrNew(points, bindings[0].Prototype, numPoints, pointsFree ? 2 : 0);
    if (!pointsFree || outputs.Points->GetData() != pointArray)
    {
      outputs.Points = vtkSmartPointer<vtkPoints>::New();
      outputs.Points->SetData(pointArray);
    }
    outputs.Arrays.resize(numAttributes - 1);
    part.Where.resize(numAttributes);
    part.FloatScratch.resize(numAttributes);
    part.DoubleScratch.resize(numAttributes);
    for (size_t a = 0; a < numAttributes; ++a)
    {
      vtkDataArray* out = a == 0
        ? pointArray
        : adapter::ReuseOrNew(outputs.Arrays[a - 1], bindings[a].Prototype, numPoints, 1);
      const size_t values = static_cast<size_t>(numPoints) * out->GetNumberOfComponents();
      if (std::holds_alternative<morphnode::MorphAttribute<float>>(mesh.GetAttribute(a)))
      {
        auto* direct = vtkFloatArray::FastDownCast(out);
        part.FloatScratch[a].resize(direct ? 0 : values);
        part.Where[a] = direct ? direct->GetPointer(0) : part.FloatScratch[a].data();
      }
      else
      {
        auto* direct = vtkDoubleArray::FastDownCast(out);
        part.DoubleScratch[a].resize(direct ? 0 : values);
        part.Where[a] = direct ? direct->GetPointer(0) : part.DoubleScratch[a].data();
      }
    }
  }

  /// Blends every part that needs it with the scene's effective weights, in parallel over
  /// point ranges of all parts together (morphnode::MorphScene::Blend). Leaves of a
  /// composite that no active target moves are not blended: they pass through.
  void Blend()
  {
    this->Tasks.clear();
    size_t total = 0;
    // The partitioned data sets of the last output that only the filter holds let go of
    // their leaves, which can then be kept.
    for (auto& set : this->OutputSets)
    {
      if (set && set->GetReferenceCount() == 1)
      {
        set->Initialize();
      }
    }
    for (Part& part : this->Parts)
    {
      if (this->Composite)
      {
        // Last execution's leaf: emptied for reuse (which frees the arrays it held for the
        // blend to write in place) when no one else holds it, else a new one.
        part.LeafKept = part.OutputLeaf && part.OutputLeaf->GetReferenceCount() == 1 &&
          part.OutputLeaf->IsA(part.Input->GetClassName());
        if (part.LeafKept)
        {
          // Frees the points and arrays it held, for the blend to write them in place.
          part.OutputLeaf->SetPoints(nullptr);
          part.OutputLeaf->GetPointData()->Initialize();
        }
        else
        {
          part.OutputLeaf.TakeReference(part.Input->NewInstance());
        }
      }
      part.Blended = part.ScenePart >= 0 &&
        (!this->Composite || this->Scene.IsPartMoved(static_cast<size_t>(part.ScenePart)));
      if (part.Blended)
      {
        this->PrepareOutputs(part);
        this->Scene.GetPartNode(static_cast<size_t>(part.ScenePart)).CheckOutputs(part.Where);
        total += part.Built->Model.GetNumberOfPoints();
      }
    }
    const int threads = vtkSMPTools::GetEstimatedNumberOfThreads();
    const bool serial = threads <= 1 || total < static_cast<size_t>(2 * MinPointsPerTask);
    // A few tasks per thread: enough to even out a busy core, few enough that handing them
    // out costs little next to blending them.
    const size_t grain = serial
      ? std::numeric_limits<size_t>::max()
      : std::max(static_cast<size_t>(MinPointsPerTask), total / static_cast<size_t>(4 * threads));
    this->Ranges.clear();
    size_t filled = 0; // points in the current task
    for (size_t p = 0; p < this->Parts.size(); ++p)
    {
      if (!this->Parts[p].Blended)
      {
        continue;
      }
      const size_t n = this->Parts[p].Built->Model.GetNumberOfPoints();
      for (size_t begin = 0; begin < n;)
      {
        if (filled == 0)
        {
          this->Tasks.push_back(this->Ranges.size());
        }
        const size_t end = begin + std::min(grain - filled, n - begin);
        this->Ranges.push_back({ p, begin, end });
        filled = (filled + end - begin) % grain;
        begin = end;
      }
    }
    this->Tasks.push_back(this->Ranges.size());
    const morphnode::MorphScene& scene = this->Scene;
    auto run = [this, &scene](size_t t) {
      for (size_t r = this->Tasks[t]; r < this->Tasks[t + 1]; ++r)
      {
        const Range& range = this->Ranges[r];
        const Part& part = this->Parts[range.Part];
        scene.Blend(static_cast<size_t>(part.ScenePart), part.Where, range.Begin, range.End);
      }
    };
    const size_t numTasks = this->Tasks.size() - 1;
    if (serial || numTasks <= 1)
    {
      for (size_t t = 0; t < numTasks; ++t)
      {
        run(t);
      }
    }
    else
    {
      vtkSMPTools::For(0, static_cast<vtkIdType>(numTasks), 1, [&run](vtkIdType begin, vtkIdType end) {
        for (vtkIdType t = begin; t < end; ++t)
        {
          run(static_cast<size_t>(t));
        }
      });
    }
    for (Part& part : this->Parts)
    {
      if (!part.Blended)
      {
        continue;
      }
      const size_t numAttributes = part.Built->Model.GetNumberOfAttributes();
      for (size_t a = 0; a < numAttributes; ++a)
      {
        vtkDataArray* out = a == 0 ? part.Outputs.Points->GetData() : part.Outputs.Arrays[a - 1].GetPointer();
        if (!part.FloatScratch[a].empty())
        {
          vtkMorphTargetArrays::CopyToArray(part.FloatScratch[a].data(), out);
        }
        else if (!part.DoubleScratch[a].empty())
        {
          vtkMorphTargetArrays::CopyToArray(part.DoubleScratch[a].data(), out);
        }
        out->Modified(); // written through raw pointers: renderers re-upload on MTime
      }
      part.Outputs.Points->Modified();
    }
  }

  /// A part's animated region and each of the model's targets' per-point distance from the
  /// neutral (zeros for a target the part does not have).
  const std::vector<vtkSmartPointer<vtkDataArray>>& DistanceArrays(Part& part)
  {
    if (!part.Distances.empty())
    {
      return part.Distances;
    }
    const auto& names = this->Names();
    const size_t n = part.Input ? static_cast<size_t>(part.Input->GetNumberOfPoints()) : 0;
    if (!part.Built || part.ScenePart < 0)
    {
      const std::vector<double> zeros(n, 0.0);
      part.Distances.push_back(adapter::MakeDoubleArray(adapter::AnimatedRegionArray, zeros));
      for (size_t i = 1; i < names.size(); ++i)
      {
        part.Distances.push_back(adapter::MakeDoubleArray((adapter::DistancePrefix + names[i]).c_str(), zeros));
      }
      return part.Distances;
    }
    const morphnode::MorphMesh& model = part.Built->Model;
    part.Distances.push_back(
      adapter::MakeDoubleArray(adapter::AnimatedRegionArray, model.ComputeAnimatedRegion()));
    const std::vector<size_t>& targets = this->Scene.GetPartTargets(static_cast<size_t>(part.ScenePart));
    std::vector<size_t> own(names.size(), 0); // the part's target of each scene target, 0: none
    for (size_t k = 1; k < targets.size(); ++k)
    {
      own[targets[k]] = k;
    }
    for (size_t i = 1; i < names.size(); ++i)
    {
      const std::string name = adapter::DistancePrefix + names[i];
      part.Distances.push_back(adapter::MakeDoubleArray(name.c_str(),
        own[i] ? model.ComputePointDistances(own[i]) : std::vector<double>(model.GetNumberOfPoints(), 0.0)));
    }
    return part.Distances;
  }

  /// `values` in the ArrayT held by `slot`, rewritten in place when only `slot` and
  /// `holders` more references (the filter's kept output leaves) hold it; `fresh` tells
  /// whether a new array was made.
  template <typename ArrayT, typename Range>
  static vtkDataArray* Values(vtkSmartPointer<vtkDataArray>& slot, const char* name, const Range& values,
    int holders, bool& fresh)
  {
    ArrayT* array = ArrayT::SafeDownCast(slot);
    fresh = !array || slot->GetReferenceCount() != 1 + holders;
    if (fresh)
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

  /// This execution's field data arrays, shared by every output data set: EffectiveWeights,
  /// ActiveTargetCount, ErrorBound (rewritten in place when only the filter and its `kept`
  /// output leaves hold them: `fresh` tells whether any is new, so that kept leaves need
  /// it), and DistNorm when distances are asked for.
  std::vector<vtkDataArray*> FieldArrays(vtkMorphNodeFilter* self, int kept, bool& fresh)
  {
    const morphnode::MorphScene& scene = this->Scene;
    static const std::vector<double> none;
    const auto& effective = this->HasScene ? scene.GetEffectiveWeights() : none;
    std::vector<vtkDataArray*> arrays;
    bool made[3] = { false, false, false };
    arrays.push_back(Values<vtkDoubleArray>(
      this->EffectiveWeightsOut, adapter::EffectiveWeightsArray, effective, kept, made[0]));
    const int active[] = { this->HasScene ? scene.GetActiveTargetCount() : 0 };
    arrays.push_back(Values<vtkIntArray>(
      this->ActiveTargetCountOut, adapter::ActiveTargetCountArray, active, kept, made[1]));
    const double bound[] = { this->HasScene ? scene.GetErrorBound() : 0.0 };
    arrays.push_back(Values<vtkDoubleArray>(this->ErrorBoundOut, adapter::ErrorBoundArray, bound, kept, made[2]));
    fresh = made[0] || made[1] || made[2];
    if (self->GenerateDistanceArrays)
    {
      arrays.push_back(this->DistNormOut);
    }
    return arrays;
  }

  /// A data set of the output: the neutral's structure, blended arrays in place of the
  /// neutral's (or the neutral's own when it is not blended), field data.
  void AssembleOutput(vtkMorphNodeFilter* self, Part& part, vtkPointSet* neutral, vtkPointSet* output,
    const std::vector<vtkDataArray*>& fieldArrays, bool kept = false)
  {
    if (!kept)
    {
      output->CopyStructure(neutral);
    }
    vtkPointData* pd = output->GetPointData();
    if (part.Blended)
    {
      output->SetPoints(part.Outputs.Points);
      adapter::AssemblePointData(neutral->GetPointData(), *part.Built, part.Outputs, pd);
    }
    else if (part.Built)
    {
      // Not moved: the neutral's points and arrays as they are, the target arrays left out.
      output->SetPoints(neutral->GetPoints());
      for (const adapter::OutputArraySource& source : part.Built->PointArrays)
      {
        vtkAbstractArray* array = neutral->GetPointData()->GetAbstractArray(source.NeutralIndex);
        if (array)
        {
          const int index = pd->AddArray(array);
          if (source.Attribute >= 0)
          {
            pd->SetActiveAttribute(index, source.Attribute);
          }
        }
      }
    }
    else
    {
      output->SetPoints(neutral->GetPoints());
      pd->PassData(neutral->GetPointData());
      vtkMorphTargetArrays::RemoveTargetArrays(pd);
    }
    if (self->GenerateDistanceArrays)
    {
      for (vtkDataArray* array : this->DistanceArrays(part))
      {
        pd->AddArray(array);
      }
    }
    vtkFieldData* fd = output->GetFieldData();
    if (kept)
    {
      // The neutral's field data, the model's names and (unless `fieldArrays` holds new
      // ones) this execution's arrays, rewritten in place, are there already.
      if (part.HasDistNorm != self->GenerateDistanceArrays)
      {
        if (self->GenerateDistanceArrays)
        {
          fd->AddArray(this->DistNormOut);
        }
        else
        {
          fd->RemoveArray(adapter::DistNormArray);
        }
        part.HasDistNorm = self->GenerateDistanceArrays;
      }
      for (vtkDataArray* array : fieldArrays)
      {
        fd->AddArray(array);
      }
      return;
    }
    part.HasDistNorm = self->GenerateDistanceArrays;
    output->GetCellData()->PassData(neutral->GetCellData());
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
    fd->AddArray(this->TargetNames);
    for (vtkDataArray* array : fieldArrays)
    {
      fd->AddArray(array);
    }
  }

  /// The output of a composite input: its structure, one assembled data set per leaf.
  void AssembleComposite(vtkMorphNodeFilter* self, vtkCompositeDataSet* output)
  {
    const int kept = static_cast<int>(
      std::count_if(this->Parts.begin(), this->Parts.end(), [](const Part& p) { return p.LeafKept; }));
    bool fresh = false;
    const std::vector<vtkDataArray*> fieldArrays = this->FieldArrays(self, kept, fresh);
    const std::vector<vtkDataArray*> none;
    for (Part& part : this->Parts)
    {
      this->AssembleOutput(self, part, part.Input, part.OutputLeaf,
        part.LeafKept && !fresh ? none : fieldArrays, part.LeafKept);
    }
    auto* collection = vtkPartitionedDataSetCollection::SafeDownCast(this->CompositeInput);
    auto* outCollection = vtkPartitionedDataSetCollection::SafeDownCast(output);
    if (collection && outCollection)
    {
      this->AssembleCollection(collection, outCollection);
    }
    else
    {
      output->CopyStructure(this->CompositeInput);
      auto it = Leaves(this->CompositeInput);
      size_t i = 0;
      for (it->InitTraversal(); !it->IsDoneWithTraversal() && i < this->Parts.size(); it->GoToNextItem(), ++i)
      {
        output->SetDataSet(it, this->Parts[i].OutputLeaf);
      }
    }
    output->GetFieldData()->PassData(this->CompositeInput->GetFieldData());
    output->GetFieldData()->AddArray(this->TargetNames);
  }

  /// The partitioned data sets of a collection's output, kept across executions like the
  /// leaves (a new one when anyone else holds it).
  std::vector<vtkSmartPointer<vtkPartitionedDataSet>> OutputSets;

  /// A collection's output: the input's structure (partitioned data sets, their names and
  /// metadata, the data assembly, shared) holding the parts' output leaves, in the
  /// iterator's order (CopyStructure, made anew each step, cost as much as the blend of a
  /// small head).
  void AssembleCollection(vtkPartitionedDataSetCollection* input, vtkPartitionedDataSetCollection* output)
  {
    const unsigned int numSets = input->GetNumberOfPartitionedDataSets();
    output->SetNumberOfPartitionedDataSets(numSets);
    this->OutputSets.resize(numSets);
    size_t leaf = 0;
    for (unsigned int d = 0; d < numSets; ++d)
    {
      vtkPartitionedDataSet* in = input->GetPartitionedDataSet(d);
      vtkSmartPointer<vtkPartitionedDataSet>& out = this->OutputSets[d];
      if (!in)
      {
        output->SetPartitionedDataSet(d, nullptr);
        continue;
      }
      if (!out || out->GetReferenceCount() != 1)
      {
        out = vtkSmartPointer<vtkPartitionedDataSet>::New();
      }
      out->Initialize();
      const unsigned int numPartitions = in->GetNumberOfPartitions();
      out->SetNumberOfPartitions(numPartitions);
      for (unsigned int i = 0; i < numPartitions; ++i)
      {
        if (in->GetPartitionAsDataObject(i) && leaf < this->Parts.size())
        {
          out->SetPartition(i, this->Parts[leaf++].OutputLeaf);
        }
        if (in->HasMetaData(i))
        {
          out->GetMetaData(i)->Copy(in->GetMetaData(i));
        }
      }
      output->SetPartitionedDataSet(d, out);
      if (input->HasMetaData(d))
      {
        output->GetMetaData(d)->Copy(input->GetMetaData(d));
      }
    }
    output->SetDataAssembly(input->GetDataAssembly());
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
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

//------------------------------------------------------------------------------
vtkMorphNodeFilter::~vtkMorphNodeFilter()
{
  this->SetController(nullptr);
  delete[] this->DeviceProfile;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetDeviceProfile(const char* name)
{
  if (!name || !*name)
  {
    if (this->DeviceProfile)
    {
      delete[] this->DeviceProfile;
      this->DeviceProfile = nullptr;
      this->Modified();
    }
    return;
  }
  try
  {
    const morphnode::DeviceProfile& profile = morphnode::FindDeviceProfile(name);
    this->SetFrameBudget(1e3 * profile.FrameBudget);
    this->SetTargetPixelBound(profile.TargetPixelBound);
    delete[] this->DeviceProfile;
    this->DeviceProfile = new char[profile.Name.size() + 1];
    std::copy(profile.Name.c_str(), profile.Name.c_str() + profile.Name.size() + 1, this->DeviceProfile);
    this->Modified();
  }
  catch (const morphnode::InputError& e)
  {
    vtkErrorMacro(<< e.what());
  }
}

//------------------------------------------------------------------------------
vtkCxxSetObjectMacro(vtkMorphNodeFilter, Controller, vtkMultiProcessController);

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
    info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::FillOutputPortInformation(int, vtkInformation* info)
{
  // The input's type: a point set, or a composite data set (a whole head).
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkDataObject");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::RequestDataObject(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkDataObject* input = inInfo ? vtkDataObject::GetData(inInfo) : nullptr;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    vtkDataObject* output = vtkDataObject::GetData(outInfo);
    if (!output || !output->IsA(composite->GetClassName()))
    {
      vtkSmartPointer<vtkDataObject> fresh;
      fresh.TakeReference(composite->NewInstance());
      outInfo->Set(vtkDataObject::DATA_OBJECT(), fresh);
    }
    return 1;
  }
  return this->Superclass::RequestDataObject(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetWeightsConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::GetNumberOfTargets()
{
  if (this->Internals->Ready)
  {
    return static_cast<int>(this->Internals->Names().size());
  }
  const int connections = this->GetNumberOfInputConnections(0);
  if (connections != 1)
  {
    return connections;
  }
  // A composite: every leaf's target names, by name.
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(this->GetInputDataObject(0, 0)))
  {
    std::set<std::string> targets; // the leaves' targets, the neutral not counted
    auto it = Leaves(composite);
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      auto* leaf = vtkPointSet::SafeDownCast(it->GetCurrentDataObject());
      try
      {
        const size_t n = leaf ? vtkMorphTargetArrays::CountTargets(leaf->GetPointData(), leaf->GetNumberOfPoints()) : 0;
        const auto names = vtkMorphTargetArrays::GetTargetNames(leaf ? leaf->GetFieldData() : nullptr, n + 1);
        targets.insert(names.begin() + 1, names.end());
      }
      catch (const std::exception&)
      {
        // Bad leaves are reported when the filter executes.
      }
    }
    return 1 + static_cast<int>(targets.size());
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
  if (!this->Internals->Ready || !name)
  {
    return -1;
  }
  return this->Internals->NamesModel.FindTarget(name);
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
void vtkMorphNodeFilter::SetTargetOffInPart(const char* part, const char* target)
{
  if (!part || !target)
  {
    return;
  }
  auto& off = this->Internals->TargetsOff[part];
  if (std::find(off.begin(), off.end(), target) == off.end())
  {
    off.emplace_back(target);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::RemoveAllTargetsOffInParts()
{
  if (!this->Internals->TargetsOff.empty())
  {
    this->Internals->TargetsOff.clear();
    this->Modified();
  }
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
  const auto& w = this->Internals->Scene.GetEffectiveWeights();
  return this->Internals->Valid && index >= 0 && static_cast<size_t>(index) < w.size()
    ? w[static_cast<size_t>(index)]
    : 0.0;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetHysteresis()
{
  this->Internals->Scene.ResetHistory();
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
  for (const auto& part : this->Internals->Parts)
  {
    if (part.Built)
    {
      return &part.Built->Model;
    }
  }
  return nullptr;
}

//------------------------------------------------------------------------------
const morphnode::MorphScene* vtkMorphNodeFilter::GetMorphScene()
{
  return &this->Internals->Scene;
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
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  vtkInternals& internals = *this->Internals;
  internals.Valid = false;
  this->ActiveTargetCount = 0;
  this->ErrorBound = 0.0;
  this->FrameBudgetThreshold = -1.0;
  this->MorphTime = 0.0;
  try
  {
    // 1. The model, rebuilt only when an input or the storage choice changed (in parallel,
    // with every process's figures).
    internals.CollectInputs(inputVector[0]);
    internals.UpdateModel(this);
    this->UpdateProgress(0.3);

    // 2. Weight rules and the optimizer, once for the whole model: the core scene. With a
    // frame budget the controller chooses the threshold from the measured morph times.
    const auto started = std::chrono::steady_clock::now();
    if (internals.HasScene)
    {
      internals.GatherRequested(this, vtkTable::GetData(inputVector[1], 0));
      internals.ApplySettings(this);
    }
    internals.ChooseThreshold(this);
    if (internals.HasScene)
    {
      internals.ApplyTargetsOff();
      internals.Scene.SetWeights(internals.Requested);
    }
    this->UpdateProgress(0.4);

    // 3. The blend, in parallel over the points of every part, into arrays of the input's types.
    internals.Blend();
    this->UpdateProgress(0.9);

    // 4. The output: the input's structure with the blended arrays and field data.
    if (auto* composite = vtkCompositeDataSet::SafeDownCast(output))
    {
      internals.AssembleComposite(this, composite);
    }
    else if (auto* points = vtkPointSet::SafeDownCast(output); points && internals.Parts.size() == 1)
    {
      bool fresh = false;
      internals.AssembleOutput(this, internals.Parts[0], internals.Parts[0].Input, points,
        internals.FieldArrays(this, 0, fresh));
    }
    else
    {
      throw morphnode::InputError(std::string("internal: an output of type ") + output->GetClassName() +
        " for an input of " + std::to_string(internals.Parts.size()) + " parts");
    }
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
        outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - started;
    internals.Measure(took.count());
    this->MorphTime = 1e3 * took.count();
    internals.Valid = internals.HasScene;
    this->ActiveTargetCount = internals.HasScene ? internals.Scene.GetActiveTargetCount() : 0;
    this->ErrorBound = internals.HasScene ? internals.Scene.GetErrorBound() : 0.0;
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
  for (const auto& [part, targets] : internals.TargetsOff)
  {
    os << indent << "TargetsOffInPart " << part << ":";
    for (const auto& t : targets)
    {
      os << " " << t;
    }
    os << "\n";
  }
  os << indent << "OptimizerPreset: " << this->GetOptimizerPresetAsString() << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "RedistributionStrategy: " << this->GetRedistributionStrategyAsString() << "\n";
  os << indent << "AdjustThreshold: " << (this->AdjustThreshold ? "On" : "Off") << "\n";
  os << indent << "MaxVertexError: " << this->MaxVertexError << "\n";
  os << indent << "MaxActiveTargets: " << this->MaxActiveTargets << "\n";
  os << indent << "Hysteresis: " << this->Hysteresis << "\n";
  os << indent << "FrameBudget: " << this->FrameBudget << " ms\n";
  os << indent << "PixelsPerUnit: " << this->PixelsPerUnit << "\n";
  os << indent << "TargetPixelBound: " << this->TargetPixelBound << " px\n";
  os << indent << "DeviceProfile: " << (this->DeviceProfile ? this->DeviceProfile : "(none)") << "\n";
  os << indent << "FrameBudgetThreshold: " << this->FrameBudgetThreshold << "\n";
  os << indent << "MorphTime: " << this->MorphTime << " ms\n";
  os << indent << "GenerateDistanceArrays: " << (this->GenerateDistanceArrays ? "On" : "Off") << "\n";
  os << indent << "SparseCoverage: " << this->SparseCoverage << "\n";
  os << indent << "NumberOfTargets: " << internals.Names().size() << "\n";
  os << indent << "NumberOfParts: " << internals.Parts.size() << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
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
    for (double w : internals.Scene.GetEffectiveWeights())
    {
      os << " " << w;
    }
  }
  os << "\n";
  os << indent << "ActiveTargetCount: " << this->ActiveTargetCount << "\n";
  os << indent << "ErrorBound: " << this->ErrorBound << "\n";
}
