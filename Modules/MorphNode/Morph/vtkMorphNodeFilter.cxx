// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphNodeFilter.h"

#include "vtkMorphModelAdapter.h"
#include "vtkMorphNodeModel.h"
#include "vtkMorphNodeOutput.h"
#include "vtkMorphTargetArrays.h"
#ifdef MORPHNODE_WITH_MESH_LEVELS
#include "vtkMorphMeshLevels.h"
#endif
#include "vtkMorphTrackFilter.h"

#include "base/Error.h"
#include "budget/DeviceProfile.h"
#include "budget/SceneBudgetController.h"
#include "morph/MorphScene.h"
#include "morph/OptimizerPresets.h"
#include "morph/WeightRequests.h"

#include "vtkCommunicator.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkGarbageCollector.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
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
static_assert(
  vtkMorphNodeFilter::OPTIMIZER_NONE == static_cast<int>(morphnode::OptimizerPreset::None) &&
    vtkMorphNodeFilter::OPTIMIZER_FIXED_MAXIMUM ==
      static_cast<int>(morphnode::OptimizerPreset::FixedMaximum) &&
    vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING ==
      static_cast<int>(morphnode::OptimizerPreset::FixedRemaining) &&
    vtkMorphNodeFilter::OPTIMIZER_ADJUSTED ==
      static_cast<int>(morphnode::OptimizerPreset::Adjusted) &&
    vtkMorphNodeFilter::OPTIMIZER_ERROR_BOUNDED ==
      static_cast<int>(morphnode::OptimizerPreset::ErrorBounded) &&
    vtkMorphNodeFilter::OPTIMIZER_ERROR_BOUNDED + 1 == morphnode::NumberOfOptimizerPresets,
  "vtkMorphNodeFilter::OptimizerPresets must match morphnode::OptimizerPreset");

namespace
{
bool SameWeight(double a, double b)
{
  return a == b || (a != a && b != b); // NaN set twice is no change either
}
} // namespace

struct vtkMorphNodeFilter::vtkInternals
{
  /// Requested weights by index and by name, and the model's target names.
  morphnode::WeightRequests Requests;
  std::vector<double> Requested; // this execution's, neutral first

  /// The model of port 0's data sets: the core's scene of the parts (targets matched by
  /// name, one decision). The parts and the output assembled from them: Output.
  vtkMorphNodeModel Model;
  vtkMorphNodeOutput Output;
  bool Valid = false; // the last execution succeeded

  /// SetTargetOffInPart: part name -> targets off there; the scene matches them to its
  /// parts' names (MorphScene::SetTargetsOffByPartName).
  std::map<std::string, std::vector<std::string>> TargetsOff;
  bool TargetsOffApplied = false; // some part of the scene has targets off

  void ApplyTargetsOff()
  {
    if (this->TargetsOff.empty() && !this->TargetsOffApplied)
    {
      return;
    }
    std::vector<std::string> names(this->Model.Scene.GetNumberOfParts());
    for (const vtkMorphNodeOutput::Part& part : this->Output.Parts)
    {
      if (part.ScenePart >= 0)
      {
        names[static_cast<size_t>(part.ScenePart)] = part.Name;
      }
    }
    this->TargetsOffApplied = this->Model.Scene.SetTargetsOffByPartName(names, this->TargetsOff);
  }

  /// The frame budget and target level of detail, and the blend's tasks.
  morphnode::SceneBudgetController Budget;
  morphnode::BlendPlan Plan;

  const std::vector<std::string>& Names() const { return this->Requests.GetTargets(); }

  /// Requested weights (neutral first): the table on port 1, else the assignments.
  void GatherRequested(vtkMorphNodeFilter* self, vtkTable* table)
  {
    if (!table)
    {
      this->Requests.Resolve(this->Requested);
      return;
    }
    int matched = 0;
    this->Requested = adapter::WeightsFromTable(table, this->Requests, matched);
    if (matched == 0 && table->GetNumberOfColumns() > 0)
    {
      vtkWarningWithObjectMacro(self, << "the weights table on port 1 names none of the "
                                      << this->Names().size() << " targets; showing the neutral");
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
    this->Model.Scene.SetOptimizerSettings(settings);
    this->Model.Scene.SetWeightMode(static_cast<morphnode::WeightMode>(self->WeightMode));
  }

  /// With a frame budget or a target level of detail, the core's controller chooses this
  /// execution's optimizer settings; in parallel from the slowest process's last
  /// measurement and the whole model's moved points (every process calls it, after
  /// ApplySettings, an empty piece too).
  void ChooseThreshold(vtkMorphNodeFilter* self)
  {
    morphnode::SceneBudgetController::Goals goals;
    goals.FrameBudget = 1e-3 * self->FrameBudget;
    goals.TargetPixelBound = self->TargetPixelBound;
    goals.PixelsPerUnit = self->PixelsPerUnit;
    if (!goals.Any() || !this->Model.Ready)
    {
      this->Budget.Skip();
      return;
    }
    vtkMultiProcessController* controller = self->Controller;
    const std::array<double, 3> mine = this->Budget.GetMeasurement();
    std::array<double, 3> measured = mine;
    if (vtkMorphNodeModel::IsParallel(controller) &&
      !controller->AllReduce(mine.data(), measured.data(), 3, vtkCommunicator::MAX_OP))
    {
      throw morphnode::InputError("the processes could not exchange their morph times");
    }
    if (this->Budget.NeedsModel(this->Model.Generation))
    {
      const std::vector<double> piece = morphnode::SceneBudgetController::MovedPoints(
        this->Model.HasScene ? &this->Model.Scene : nullptr, this->Names().size());
      std::vector<double> moved = piece;
      if (vtkMorphNodeModel::IsParallel(controller) &&
        !controller->AllReduce(piece.data(), moved.data(), static_cast<vtkIdType>(moved.size()),
          vtkCommunicator::SUM_OP))
      {
        throw morphnode::InputError("the processes could not exchange their moved points");
      }
      this->Budget.SetModel(this->Model.Generation, std::move(moved));
    }
    if (!this->Model.HasScene)
    {
      this->Budget.Skip(); // an empty piece: took part in the exchanges, decides nothing
      return;
    }
    self->FrameBudgetThreshold =
      this->Budget.Decide(this->Model.Scene, this->Requested, goals, measured);
  }

  // ---- Mesh levels (MeshLevels; docs/lod.md). The core decides and blends (ScalableScene
  // over the parts' ladders); vtkMorphMeshLevels converts. Each process chooses its level
  // from its own parts.
#ifdef MORPHNODE_WITH_MESH_LEVELS
  vtkMorphMeshLevels::SceneLevels Levels;
#endif

  void ClearLevels()
  {
#ifdef MORPHNODE_WITH_MESH_LEVELS
    this->Levels.Clear();
#endif
  }

  /// Steps 3 and 4 with mesh levels: the scene's level blended with the effective weights,
  /// each part's level as the output's data set, in the input's structure
  /// (vtkMorphMeshLevels::SceneLevels::Show).
  void ShowLevels(vtkMorphNodeFilter* self, vtkDataObject* output)
  {
#ifdef MORPHNODE_WITH_MESH_LEVELS
    morphnode::ControllerSettings settings;
    settings.Thresholds = { 0.0 }; // the weights are the filter's already
    settings.FrameBudget = self->FrameBudget > 0.0 ? 1e-3 * self->FrameBudget : 1.0;
    settings.PixelBound = self->PixelsPerUnit > 0.0 ? self->LevelPixelBound : 0.0;
    settings.FinestLevel = self->FinestLevel;
    settings.MaxGeomorphPixels = 1.0;
    // Without a frame budget the level follows the screen alone: no decision reads the cost
    // models, so they are not refitted to every execution's measured time.
    settings.MeasurementWindow = self->FrameBudget > 0.0 ? settings.MeasurementWindow : 0;
    self->Level = this->Levels.Show(this->Model.Scene, this->Model.Generation, this->Names(),
      settings, self->PixelsPerUnit, self->GenerateDistanceArrays, this->Output,
      this->Model.CompositeInput, output);
    self->UpdateProgress(0.9);
#else
    (void)self;
    (void)output;
    throw morphnode::InputError(
      "MeshLevels: this build has no mesh levels (MORPHNODE_ENABLE_REDUCTION off)");
#endif
  }
  // ---- End of mesh levels.

  /// Blends every part that needs it with the scene's effective weights, in parallel over
  /// point ranges of all parts together (the core's blend plan). Leaves of a composite that
  /// no active target moves are not blended: they pass through.
  void Blend()
  {
    const std::vector<size_t> parts =
      this->Output.Prepare(this->Model.Scene, this->Model.Composite);
    this->Model.Scene.PlanBlend(parts, vtkSMPTools::GetEstimatedNumberOfThreads(), this->Plan);
    const auto& where = this->Output.GetWhere();
    const size_t numTasks = this->Plan.GetNumberOfTasks();
    if (this->Plan.Serial)
    {
      for (size_t t = 0; t < numTasks; ++t)
      {
        this->Model.Scene.BlendTask(this->Plan, t, where);
      }
    }
    else
    {
      vtkSMPTools::For(0, static_cast<vtkIdType>(numTasks), 1,
        [this, &where](vtkIdType begin, vtkIdType end)
        {
          for (vtkIdType t = begin; t < end; ++t)
          {
            this->Model.Scene.BlendTask(this->Plan, static_cast<size_t>(t), where);
          }
        });
    }
    this->Output.Finish();
  }
};

vtkStandardNewMacro(vtkMorphNodeFilter);

//------------------------------------------------------------------------------
vtkMorphNodeFilter::vtkMorphNodeFilter()
  : SparseCoverage(morphnode::MorphMesh::DefaultSparseCoverage)
  , Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(3);
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

//------------------------------------------------------------------------------
vtkMorphNodeFilter::~vtkMorphNodeFilter()
{
  this->SetController(nullptr);
  this->SetPoseFilter(nullptr);
  delete[] this->DeviceProfile;
}

//------------------------------------------------------------------------------
bool vtkMorphNodeFilter::HasMeshLevels()
{
#ifdef MORPHNODE_WITH_MESH_LEVELS
  return true;
#else
  return false;
#endif
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
    this->SetLevelPixelBound(profile.PixelBound);
    this->SetFinestLevel(profile.FinestLevel);
    delete[] this->DeviceProfile;
    this->DeviceProfile = new char[profile.Name.size() + 1];
    std::copy(
      profile.Name.c_str(), profile.Name.c_str() + profile.Name.size() + 1, this->DeviceProfile);
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
    // vtkCompositeDataSet first: VTK's composite executive then sees at its first string
    // compare that this filter takes composites itself and never iterates over them
    // (vtkCompositeDataPipeline::ShouldIterateOverInput, called 7 times an update); with
    // vtkPointSet first it checked the input against every type each time, ~0.8 us an update.
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
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
  const std::vector<vtkPointSet*> shapes = adapter::AbsoluteShapes(input);
  // The output is of the input's type; the Java3D form in one data set gives the neutral's.
  vtkDataObject* like = shapes.empty() ? input : shapes[0];
  if (vtkCompositeDataSet::SafeDownCast(input))
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    vtkDataObject* output = vtkDataObject::GetData(outInfo);
    if (!output || !output->IsA(like->GetClassName()))
    {
      vtkSmartPointer<vtkDataObject> fresh;
      fresh.TakeReference(like->NewInstance());
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
void vtkMorphNodeFilter::SetPoseConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetPoseFilter(vtkMorphTrackFilter* filter)
{
  if (filter == this->PoseFilter)
  {
    return;
  }
  if (this->PoseFilter)
  {
    // Kept output leaves hold the field data it added (SkinPose, ...): new leaves.
    for (auto& part : this->Internals->Output.Parts)
    {
      part.OutputLeaf = nullptr;
    }
  }
  vtkMorphTrackFilter* old = this->PoseFilter;
  this->PoseFilter = filter;
  if (filter)
  {
    filter->Register(this);
  }
  if (old)
  {
    old->UnRegister(this);
  }
  this->Modified();
}

//------------------------------------------------------------------------------
vtkMTimeType vtkMorphNodeFilter::GetMTime()
{
  const vtkMTimeType own = this->Superclass::GetMTime();
  return this->PoseFilter ? std::max(own, this->PoseFilter->GetMTime()) : own;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ReportReferences(vtkGarbageCollector* collector)
{
  this->Superclass::ReportReferences(collector);
  // The pose filter may hold a pipeline that holds this filter.
  vtkGarbageCollectorReport(collector, this->PoseFilter, "PoseFilter");
}

//------------------------------------------------------------------------------
int vtkMorphNodeFilter::GetNumberOfTargets()
{
  if (this->Internals->Model.Ready)
  {
    return static_cast<int>(this->Internals->Names().size());
  }
  const int connections = this->GetNumberOfInputConnections(0);
  if (connections != 1)
  {
    return connections;
  }
  // The Java3D form in one data set: its shapes; a composite: every leaf's target names, by
  // name; one point set: its target arrays.
  vtkDataObject* input = this->GetInputDataObject(0, 0);
  const size_t shapes = adapter::AbsoluteShapes(input).size();
  return static_cast<int>(shapes ? shapes : 1 + vtkMorphTargetArrays::CountFaceTargets(input));
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
  if (!this->Internals->Model.Ready || !name)
  {
    return -1;
  }
  return this->Internals->Requests.FindTarget(name);
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::SetWeight(int index, double weight)
{
  if (index < 0)
  {
    vtkErrorMacro(<< "SetWeight: target index " << index << " is negative");
    return;
  }
  const double current = this->GetWeight(index);
  this->Internals->Requests.SetByIndex(static_cast<size_t>(index), weight);
  if (!SameWeight(current, weight))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetWeight(int index)
{
  return index >= 0 ? this->Internals->Requests.Get(static_cast<size_t>(index)) : 0.0;
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
  this->Internals->Requests.SetByName(name, weight);
  if (!SameWeight(current, weight))
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetWeightByName(const char* name)
{
  return name ? this->Internals->Requests.GetByName(name) : 0.0;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetWeights()
{
  if (this->Internals->Requests.Clear())
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
double vtkMorphNodeFilter::GetEffectiveWeight(int index)
{
  const auto& w = this->Internals->Model.Scene.GetEffectiveWeights();
  return this->Internals->Valid && index >= 0 && static_cast<size_t>(index) < w.size()
    ? w[static_cast<size_t>(index)]
    : 0.0;
}

//------------------------------------------------------------------------------
void vtkMorphNodeFilter::ResetHysteresis()
{
  this->Internals->Model.Scene.ResetHistory();
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
  return this->Internals->Output.GetDistNorm();
}

//------------------------------------------------------------------------------
const morphnode::MorphMesh* vtkMorphNodeFilter::GetMorphModel()
{
  for (const auto& part : this->Internals->Output.Parts)
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
  return &this->Internals->Model.Scene;
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
    internals.Model.Collect(inputVector[0]);
    internals.Model.Update(
      this->SparseCoverage, this->Controller, internals.Output, internals.Requests, this);
    this->UpdateProgress(0.3);

    // 2. Weight rules and the optimizer, once for the whole model: the core scene. With a
    // frame budget the controller chooses the threshold from the measured morph times.
    const auto started = std::chrono::steady_clock::now();
    if (internals.Model.HasScene)
    {
      internals.GatherRequested(this, vtkTable::GetData(inputVector[1], 0));
      internals.ApplySettings(this);
    }
    internals.ChooseThreshold(this);
    if (internals.Model.HasScene)
    {
      internals.ApplyTargetsOff();
      internals.Model.Scene.SetWeights(internals.Requested);
    }
    this->UpdateProgress(0.4);

    this->Level = -1;
    if (this->MeshLevels && (internals.Model.HasScene || !vtkMorphNodeFilter::HasMeshLevels()))
    {
      // 3-4. Mesh levels: the core's ScalableScene chooses the level and blends it; the
      // output holds each part's level (vtkMorphMeshLevels).
      internals.ShowLevels(this, output);
    }
    else
    {
      internals.ClearLevels();
      // 3. The blend, in parallel over the points of every part, into arrays of the input's types.
      internals.Blend();
      this->UpdateProgress(0.9);

      // 4. The output: the input's structure with the blended arrays and field data.
      internals.Output.Assemble(output, internals.Model.CompositeInput,
        internals.Model.HasScene ? &internals.Model.Scene : nullptr, this->GenerateDistanceArrays);
    }
    if (this->PoseFilter)
    {
      // 5. The skeleton posed (and the parts skinned) in this pass, on this output.
      vtkInformationVector* pose =
        this->GetNumberOfInputConnections(2) > 0 ? inputVector[2] : inputVector[1];
      if (!this->PoseFilter->MoveInPlace(pose, output))
      {
        throw morphnode::InputError(
          std::string("the pose filter (") + this->PoseFilter->GetClassName() + ") failed");
      }
    }
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
        outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - started;
    internals.Budget.Measure(internals.Model.Scene, took.count());
    this->MorphTime = 1e3 * took.count();
    internals.Valid = internals.Model.HasScene;
    this->ActiveTargetCount =
      internals.Model.HasScene ? internals.Model.Scene.GetActiveTargetCount() : 0;
    this->ErrorBound = internals.Model.HasScene ? internals.Model.Scene.GetErrorBound() : 0.0;
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
  os << indent << "DeviceProfile: " << (this->DeviceProfile ? this->DeviceProfile : "(none)")
     << "\n";
  os << indent << "MeshLevels: " << (this->MeshLevels ? "On" : "Off") << "\n";
  os << indent << "LevelPixelBound: " << this->LevelPixelBound << " px\n";
  os << indent << "FinestLevel: " << this->FinestLevel << "\n";
  os << indent << "Level: " << this->Level << "\n";
  os << indent << "FrameBudgetThreshold: " << this->FrameBudgetThreshold << "\n";
  os << indent << "MorphTime: " << this->MorphTime << " ms\n";
  os << indent << "GenerateDistanceArrays: " << (this->GenerateDistanceArrays ? "On" : "Off")
     << "\n";
  os << indent << "SparseCoverage: " << this->SparseCoverage << "\n";
  os << indent << "NumberOfTargets: " << internals.Names().size() << "\n";
  os << indent << "NumberOfParts: " << internals.Output.Parts.size() << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "PoseFilter: " << (this->PoseFilter ? this->PoseFilter->GetClassName() : "(none)")
     << "\n";
  os << indent << "Pose: " << (this->GetNumberOfInputConnections(2) > 0 ? "connected" : "none")
     << "\n";
  const std::string requested = internals.Requests.Describe();
  os << indent << "Weights (requested):" << (requested.empty() ? "" : " ") << requested << "\n";
  os << indent << "EffectiveWeights:";
  if (internals.Valid)
  {
    for (double w : internals.Model.Scene.GetEffectiveWeights())
    {
      os << " " << w;
    }
  }
  os << "\n";
  os << indent << "ActiveTargetCount: " << this->ActiveTargetCount << "\n";
  os << indent << "ErrorBound: " << this->ErrorBound << "\n";
}
