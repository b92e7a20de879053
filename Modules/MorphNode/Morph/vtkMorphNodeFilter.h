// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphNodeFilter
 * @brief   blends morph targets by weights, like Java3D's Morph node, with the
 *          weight optimizer of Berner (WSCG 2004) and an error-bounded one
 *
 * Targets arrive on input port 0 in one of two forms (and a whole head as a composite of
 * the second, see below):
 *
 * - Java3D style: several connections (AddInputConnection(0, ...)), each an absolute
 *   geometry (any vtkPointSet). Connection 0 is the neutral. All targets have the same
 *   number of points; cells come from the neutral.
 *   The same geometries may come as the partitions of one vtkPartitionedDataSet on one
 *   connection (partition 0 the neutral; no partition carries target arrays): the same
 *   result, but VTK's executive handles one connection instead of one per geometry (each
 *   connection costs it about 1.2 us per update). The output is then of the neutral's
 *   type. This is the way to use the Java3D form at speed: with the 14 shapes of the
 *   benchmark face, 14 connections cost VTK's executive ~22 us an update and miss the
 *   speed goals against Java3D's Morph (8x on speech frames, 12x with all 14 active); one
 *   vtkPartitionedDataSet of them costs what one input with target arrays costs (+0.3-1 us)
 *   and met them on a quiet machine (docs/benchmarks.md, "Both Java3D forms").
 * - glTF style: one vtkPointSet carrying relative targets as point-data arrays
 *   `target<k>_position` (and `target<k>_normal`), as vtkGLTFReader produces with
 *   ApplyDeformationsToGeometry off. Target 0 is the base mesh, `target<k>_*` target k+1.
 *
 * Target names come from a field-data string array `TargetNames` on the neutral (one
 * per target, neutral first); else, in the Java3D form, from a one-value string array
 * `TargetName` on each connection; else `Neutral`, `target0`, `target1`, ...
 *
 * Weights: SetWeight / SetWeightByName (Java3D's default is [1, 0, 0, ...]), or a
 * vtkTable on the optional input port 1 whose columns are named after targets (first
 * row used; columns naming no target are ignored, e.g. head pose). With a table, targets
 * it does not name get 0, and when it does not name the neutral, the neutral gets
 * max(0, 1 - sum of the others). Time (TIME_STEPS, UPDATE_TIME_STEP) flows through
 * port 1, so a temporal weight source animates the face.
 *
 * Weight modes (see morphnode::WeightMode): Strict (Java3D: |sum - 1| > 1e-4 is an
 * error; negative weights, such as a neutral of 1 - sum below 0, are accepted as Java3D
 * does), Normalize (default: divide by the sum; negative weights are an error), Relative
 * (glTF: neutral + sum w_i (target_i - neutral), no constraint). Every mode resolves to
 * absolute weights summing to 1, and the optimizer (see morphnode::WeightOptimizer) then
 * zeroes small weights and hands their weight on. The optimizer's method is picked by a
 * preset (SetOptimizerPreset, SetOptimizerPresetByName: none, fixed-maximum,
 * fixed-remaining, adjusted, error-bounded, see morphnode::OptimizerPreset) or by the
 * individual settings.
 *
 * Output: the neutral's structure (topology and cell data shared, not copied), with the
 * blended points and every point-data array that all targets carry with the same name
 * and component count: positions, normals (renormalized), texture coordinates, colours
 * (clamped to their type's range), other numeric arrays. Field data
 * `EffectiveWeights` (one double per target, the weights actually used),
 * `ActiveTargetCount` (non-neutral targets with a non-zero weight), `ErrorBound` (the
 * optimizer's bound on any vertex's deviation from the unoptimized result) and
 * `TargetNames`. With GenerateDistanceArrays, point data `AnimatedRegion` and
 * `Distance_<target>` (the paper's Figure 4) and field data `DistNorm` (its Table 1).
 *
 * A whole head: the input may also be a composite data set (the
 * vtkPartitionedDataSetCollection of vtkMorphTargetReader, a vtkMultiBlockDataSet, ...)
 * whose leaves are point sets in the glTF form, each with its own targets (an eye may have
 * none). The targets are matched by NAME (morphnode::MorphScene): the filter's targets are
 * every leaf's, neutral first, in order of first appearance; a weight set by name reaches
 * every leaf that has a target of that name and leaves the others untouched. The weight
 * mode and the optimizer decide once for the whole model, so that parts never disagree:
 * dist_morph is summed and the largest displacement M_i taken over all leaves, the budget
 * and the error bound count every leaf. The output has the input's structure, leaf by
 * leaf; every leaf's field data holds the same EffectiveWeights, ActiveTargetCount,
 * ErrorBound, TargetNames (the model's) and DistNorm, and its own distance arrays
 * (`Distance_<target>` is 0 on a leaf without that target). Leaves that no active target
 * moves pass through unblended. Plain vtkPolyData input behaves as before.
 *
 * In parallel (a Controller with more than one process, by default the global controller,
 * as in pvbatch and pvserver under MPI), each process holds a piece of the model, and the
 * decisions that depend on the whole model are still made over the whole model: the
 * processes exchange their targets' names, dist_morph sums and largest displacements once
 * per model (an all-gather, combined in process order, so every process decides exactly
 * the same), and points flagged as duplicates in the ghost array (vtkGhostType,
 * DUPLICATEPOINT) are left out of the sums. Every process must execute the filter
 * together, as with every parallel VTK filter; a process with an empty piece takes part
 * and gives an empty output.
 *
 * The algorithm is the core's morphnode::MorphNode; this class adapts VTK data to it.
 * Work follows the active targets (a zero weight costs nothing) and runs in parallel
 * over points with vtkSMPTools. Bad input (no input, mismatched point counts, NaN
 * weights, unknown names, ...) is reported with vtkErrorMacro, gives an empty output and
 * makes the update fail (Update() and UpdateTimeStep() return 0); the inputs are never
 * modified.
 *
 * @sa morphnode::MorphNode morphnode::ResolveWeights morphnode::WeightOptimizer vtkGLTFReader
 */

#ifndef vtkMorphNodeFilter_h
#define vtkMorphNodeFilter_h

#include "vtkMorphNodeModule.h" // For export macro
#include "vtkPointSetAlgorithm.h"

#include <memory> // For std::unique_ptr

class vtkDoubleArray;
class vtkMorphTrackFilter;
class vtkMultiProcessController;
#ifndef __VTK_WRAP__
namespace morphnode
{
class MorphMesh;
class MorphScene;
}
#endif

class VTKMORPHNODE_EXPORT vtkMorphNodeFilter : public vtkPointSetAlgorithm
{
public:
  static vtkMorphNodeFilter* New();
  vtkTypeMacro(vtkMorphNodeFilter, vtkPointSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Weight modes; values match morphnode::WeightMode.
  enum WeightModes
  {
    STRICT = 0,
    NORMALIZE = 1,
    RELATIVE = 2
  };

  /// Redistribution strategies of the optimizer; values match morphnode::Redistribution.
  enum RedistributionStrategies
  {
    MAXIMUM = 0,
    REMAINING = 1,
    NEUTRAL = 2
  };

  /// Optimizer presets; values match morphnode::OptimizerPreset, OPTIMIZER_CUSTOM means the
  /// individual settings.
  enum OptimizerPresets
  {
    OPTIMIZER_CUSTOM = -1,
    OPTIMIZER_NONE = 0,
    OPTIMIZER_FIXED_MAXIMUM = 1,
    OPTIMIZER_FIXED_REMAINING = 2,
    OPTIMIZER_ADJUSTED = 3,
    OPTIMIZER_ERROR_BOUNDED = 4
  };

  /**
   * Connect the weights (a vtkTable) to port 1.
   */
  void SetWeightsConnection(vtkAlgorithmOutput* output);

  ///@{
  /**
   * A skinned avatar posed in this filter's pass: a vtkMorphSkinFilter (nullptr, the
   * default: none) poses this filter's output itself, after the blend, as it would pose it
   * downstream (vtkMorphTrackFilter::MoveInPlace): morph first, then skin, in one pass of
   * VTK's executive instead of two, so that a frame skinned on the GPU (the skin filter's
   * SkinPoints off) costs the CPU little more than the morph (docs/benchmarks.md). Its
   * settings and reports stay the skin filter's (its changes re-execute this filter); it
   * reads the pose table on port 2 (SetPoseConnection), else the weights table on port 1
   * (columns naming no target are ignored here). A filter that cannot pose in place fails
   * the update. The skin filter need not be connected to anything, and must not pose this
   * output again downstream (re-skinned points would be skinned twice).
   */
  void SetPoseFilter(vtkMorphTrackFilter* filter);
  vtkGetObjectMacro(PoseFilter, vtkMorphTrackFilter);
  ///@}

  /**
   * Connect the pose table of the PoseFilter (a vtkTable: HeadYaw, EyeYaw, ... as
   * vtkMorphSkinFilter reads them) to the optional port 2; without it the filter reads the
   * weights table.
   */
  void SetPoseConnection(vtkAlgorithmOutput* output);

  /** The MTime of this filter and of its PoseFilter. */
  vtkMTimeType GetMTime() override;

  ///@{
  /**
   * Targets of the current input, neutral first. Known once the input data exists
   * (after the upstream pipeline or this filter has been updated); in the Java3D form
   * the count is the number of connections.
   */
  int GetNumberOfTargets();
  const char* GetTargetName(int index);
  /// -1 if no target has that name.
  int GetTargetIndex(const char* name);
  ///@}

  ///@{
  /**
   * Requested weights. Index 0 is the neutral. Indices and names are checked when the
   * filter executes (an unknown one is an error then). Setting the value a weight
   * already has does not modify the filter.
   */
  void SetWeight(int index, double weight);
  double GetWeight(int index);
  void SetWeightByName(const char* name, double weight);
  double GetWeightByName(const char* name);
  /// Back to Java3D's default weights [1, 0, 0, ...].
  void ResetWeights();
  ///@}

  ///@{
  /**
   * Targets that do not move one part of a composite input, named as the filter names
   * its leaves (the reader's part names; a partition "Name/i" matches "Name"): their
   * weights count as 0 there and still move the other parts (the core matches the
   * names: morphnode::MorphScene::SetTargetsOffByPartName). MorphAvatar turns the
   * eyeLook* targets off on the eyeballs when the eye joints turn them, so that the same
   * weights move only the lids. Names neither part nor target has are ignored.
   * Default: none.
   */
  void SetTargetOffInPart(const char* part, const char* target);
  void RemoveAllTargetsOffInParts();
  ///@}

  /**
   * Weights actually used by the last execution (after mode and optimizer); 0 before.
   */
  double GetEffectiveWeight(int index);
  /**
   * Non-neutral targets with a non-zero effective weight in the last execution.
   */
  vtkGetMacro(ActiveTargetCount, int);
  /**
   * The optimizer's bound on the distance of any vertex from the unoptimized result,
   * in the last execution (0 without optimizer).
   */
  vtkGetMacro(ErrorBound, double);

  ///@{
  /**
   * Weight mode; default NORMALIZE.
   */
  vtkSetClampMacro(WeightMode, int, STRICT, RELATIVE);
  vtkGetMacro(WeightMode, int);
  void SetWeightModeToStrict() { this->SetWeightMode(STRICT); }
  void SetWeightModeToNormalize() { this->SetWeightMode(NORMALIZE); }
  void SetWeightModeToRelative() { this->SetWeightMode(RELATIVE); }
  const char* GetWeightModeAsString();
  ///@}

  ///@{
  /**
   * The optimizer's method by preset (see morphnode::OptimizerPreset): OPTIMIZER_NONE,
   * OPTIMIZER_FIXED_MAXIMUM and OPTIMIZER_FIXED_REMAINING (the paper's fixed threshold
   * th_fix = Threshold, strategies 1 and 2), OPTIMIZER_ADJUSTED (the paper's adjusted
   * threshold), OPTIMIZER_ERROR_BOUNDED (no vertex farther than MaxVertexError from the
   * unoptimized result). A preset uses Threshold and MaxVertexError as set (the threshold
   * is kept, though unused, while the preset needs none) and sets RedistributionStrategy
   * and AdjustThreshold to its own; MaxActiveTargets and Hysteresis apply on top of any
   * method. OPTIMIZER_CUSTOM (default) uses the individual settings below; changing
   * RedistributionStrategy or AdjustThreshold switches to it.
   */
  virtual void SetOptimizerPreset(int preset);
  vtkGetMacro(OptimizerPreset, int);
  /// A preset by its name ("none", "fixed-maximum", "fixed-remaining", "adjusted",
  /// "error-bounded", case-insensitive, or "0".."4"), or "custom". An unknown name is an
  /// error and changes nothing.
  void SetOptimizerPresetByName(const char* name);
  /// The preset's name, or "custom".
  const char* GetOptimizerPresetAsString();
  ///@}

  ///@{
  /**
   * The paper's fixed threshold th_fix: absolute weights below it become 0 and their
   * weight is handed on by the redistribution strategy. 0 (default) turns it off.
   * Used by the threshold presets too.
   */
  vtkSetClampMacro(Threshold, double, 0.0, 1.0);
  vtkGetMacro(Threshold, double);
  ///@}

  ///@{
  /**
   * Where pruned weight goes: MAXIMUM (the largest remaining weight, the paper's
   * strategy 1), REMAINING (all remaining weights in proportion, strategy 2; default),
   * NEUTRAL (the neutral: no geometric side effect, beyond the paper). A change switches
   * the optimizer to OPTIMIZER_CUSTOM.
   */
  virtual void SetRedistributionStrategy(int strategy);
  vtkGetMacro(RedistributionStrategy, int);
  void SetRedistributionStrategyToMaximum() { this->SetRedistributionStrategy(MAXIMUM); }
  void SetRedistributionStrategyToRemaining() { this->SetRedistributionStrategy(REMAINING); }
  void SetRedistributionStrategyToNeutral() { this->SetRedistributionStrategy(NEUTRAL); }
  const char* GetRedistributionStrategyAsString();
  ///@}

  ///@{
  /**
   * The paper's improved method: per-target threshold th_adj = th_fix * (1 - dist_norm),
   * so targets that move the face a lot stay longer. Default off. A change switches the
   * optimizer to OPTIMIZER_CUSTOM.
   */
  virtual void SetAdjustThreshold(bool adjust);
  vtkGetMacro(AdjustThreshold, bool);
  vtkBooleanMacro(AdjustThreshold, bool);
  ///@}

  ///@{
  /**
   * Guarantee that no vertex moves by more than this (model units) from the
   * unoptimized result. Alone, prunes as much as that allows. 0 (default) = off.
   * Used by the error-bounded preset too.
   */
  vtkSetClampMacro(MaxVertexError, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxVertexError, double);
  ///@}

  ///@{
  /**
   * At most this many non-neutral active targets, chosen by geometric contribution
   * (weight times the target's largest displacement). 0 (default) = no budget.
   */
  vtkSetClampMacro(MaxActiveTargets, int, 0, VTK_INT_MAX);
  vtkGetMacro(MaxActiveTargets, int);
  ///@}

  ///@{
  /**
   * Hysteresis in [0, 1): a target active in the previous execution keeps its place unless
   * a decision beats it by this margin: it is pruned only below threshold * (1 -
   * Hysteresis), loses the budget's last place only to a target whose contribution exceeds
   * its own by 1 / (1 - Hysteresis), and the error bound prunes it only while the bound
   * stays within MaxVertexError * (1 - Hysteresis) (see morphnode::WeightOptimizer).
   * Default 0.
   */
  vtkSetClampMacro(Hysteresis, double, 0.0, 0.99);
  vtkGetMacro(Hysteresis, double);
  /// Forget which targets were active (e.g. after a jump in time).
  void ResetHysteresis();
  ///@}

  ///@{
  /**
   * A time budget for each execution's morph (weights, optimizer, blend and output), in
   * milliseconds; 0 (default) turns it off. When on, a morphnode::FrameBudgetController
   * picks the optimizer's threshold for every execution: of the candidates 0, 0.05, 0.1,
   * 0.2, 0.3 and 0.5 (with the method's redistribution and adjustment, and MaxActiveTargets,
   * MaxVertexError and Hysteresis as set) the one with the least error bound whose cost,
   * predicted from the measured times of the previous executions, fits the budget (the
   * cheapest when none does). It replaces Threshold for every method. The input is one
   * level of detail (no reduction ladder). In parallel the processes share their moved
   * points and the slowest process's time, so they choose alike.
   */
  vtkSetClampMacro(FrameBudget, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FrameBudget, double);
  ///@}

  ///@{
  /**
   * Target level of detail (docs/lod.md): PixelsPerUnit is how many pixels one model unit
   * spans on screen at the avatar (the application sets it each frame from its camera,
   * morphnode::ScreenPixelsPerUnit; 0, the default, is off). With TargetPixelBound > 0 too,
   * targets whose weighted reach projects below TargetPixelBound pixels are left out
   * through the optimizer's error bound (MaxVertexError becomes the smaller of its own and
   * TargetPixelBound / PixelsPerUnit) and its hysteresis, whether or not FrameBudget is on.
   */
  vtkSetClampMacro(PixelsPerUnit, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(PixelsPerUnit, double);
  vtkSetClampMacro(TargetPixelBound, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TargetPixelBound, double);
  ///@}

  ///@{
  /**
   * Mesh levels of detail (docs/lod.md; in builds with the reduction, HasMeshLevels()).
   * With MeshLevels on, every part gets a ladder of the animation-aware reduction (its full
   * mesh and 50, 25 and 10 % of its triangles over one vertex buffer; a part that is not
   * triangles, or has fewer than 100, is kept whole), built when the model is, and one
   * morphnode::ScalableScene chooses ONE level for the whole model every execution, every
   * part switching together: the coarsest whose largest part error (99th percentile of the
   * carried points' distances) projects to at most LevelPixelBound pixels at PixelsPerUnit
   * (without PixelsPerUnit: time alone), never finer than FinestLevel, coarser still when
   * FrameBudget asks, with geomorphs and hysteresis. The weights are decided as without
   * levels (mode, optimizer, target level of detail). The output's parts then hold the
   * level's points and triangles (vtkPolyData), every point array gathered to the level's
   * points with the morphed ones blended, point data `OriginalPointId` (each point's id in
   * its input part) and field data `LevelOfDetail` (Level, MorphTowards, Alpha,
   * ActiveTargets, Points); the cell data of each kept triangle (a reduced triangle is an
   * input triangle with collapsed corners moved) and, with GenerateDistanceArrays, the
   * distance arrays gathered to the level's points (by OriginalPointId). Off (the
   * default): the output is the input's structure, as always. Level is the level the last
   * execution showed (-1: levels off, or before).
   */
  vtkSetMacro(MeshLevels, bool);
  vtkGetMacro(MeshLevels, bool);
  vtkBooleanMacro(MeshLevels, bool);
  vtkSetClampMacro(LevelPixelBound, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(LevelPixelBound, double);
  vtkSetClampMacro(FinestLevel, int, 0, VTK_INT_MAX);
  vtkGetMacro(FinestLevel, int);
  vtkGetMacro(Level, int);
  static bool HasMeshLevels();
  ///@}

  ///@{
  /**
   * A device profile (morphnode::DeviceProfiles: "desktop", "laptop", "phone"; empty: none)
   * sets FrameBudget, TargetPixelBound, LevelPixelBound and FinestLevel to the profile's
   * (and keeps its name); an unknown name is an error and changes nothing. Setting one of
   * them afterwards overrides the profile's value.
   */
  void SetDeviceProfile(const char* name);
  vtkGetStringMacro(DeviceProfile);
  ///@}

  /**
   * The threshold the frame budget chose for the last execution; -1 when FrameBudget is
   * off or before an execution.
   */
  vtkGetMacro(FrameBudgetThreshold, double);
  /**
   * Milliseconds the last execution's morph took (weights, optimizer, blend, output; not
   * the building of the model), measured with or without a budget; 0 before one.
   */
  vtkGetMacro(MorphTime, double);

  ///@{
  /**
   * Add per-vertex distance arrays (`Distance_<target>`, `AnimatedRegion`) and the field
   * data `DistNorm`. Default off.
   */
  vtkSetMacro(GenerateDistanceArrays, bool);
  vtkGetMacro(GenerateDistanceArrays, bool);
  vtkBooleanMacro(GenerateDistanceArrays, bool);
  ///@}

  ///@{
  /**
   * Targets moving at most this fraction of the points store their deltas sparsely.
   * Default morphnode::MorphMesh::DefaultSparseCoverage.
   */
  vtkSetClampMacro(SparseCoverage, double, 0.0, 1.0);
  vtkGetMacro(SparseCoverage, double);
  ///@}

  /**
   * Normalized distances dist_norm of the targets (the paper's Table 1), neutral first,
   * from the last execution. The array is owned by the filter.
   */
  vtkDoubleArray* GetDistNorm();

  ///@{
  /**
   * The processes that hold the pieces of one model, whose decisions must agree. Default:
   * vtkMultiProcessController::GetGlobalController() when the filter is made (nullptr
   * without one). nullptr, or one process, decides on the local data alone.
   */
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

#ifndef __VTK_WRAP__
  /**
   * The core model built from the input by the last execution (nullptr before one, or
   * after an error): the one mesh, or for a composite input its first leaf's; for C++
   * tools that study the morph beyond the pipeline.
   */
  const morphnode::MorphMesh* GetMorphModel();
  /**
   * The core scene of the last execution (its parts, the model's targets, settings and
   * effective weights): valid while the filter lives; it has no parts before an
   * execution and after input that could not be made into one.
   */
  const morphnode::MorphScene* GetMorphScene();
#endif

protected:
  vtkMorphNodeFilter();
  ~vtkMorphNodeFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// The output of the input's type (a point set, or a composite data set).
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int ExecuteInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  void ReportReferences(vtkGarbageCollector*) override;

  int WeightMode = NORMALIZE;
  int OptimizerPreset = OPTIMIZER_CUSTOM;
  double Threshold = 0.0;
  int RedistributionStrategy = REMAINING;
  bool AdjustThreshold = false;
  double MaxVertexError = 0.0;
  int MaxActiveTargets = 0;
  double Hysteresis = 0.0;
  double FrameBudget = 0.0;
  double PixelsPerUnit = 0.0;
  double TargetPixelBound = 0.0;
  char* DeviceProfile = nullptr;
  bool MeshLevels = false;
  double LevelPixelBound = 1.0;
  int FinestLevel = 0;
  int Level = -1;
  bool GenerateDistanceArrays = false;
  double SparseCoverage;

  int ActiveTargetCount = 0;
  double ErrorBound = 0.0;
  double FrameBudgetThreshold = -1.0;
  double MorphTime = 0.0;
  vtkMultiProcessController* Controller = nullptr;
  vtkMorphTrackFilter* PoseFilter = nullptr;

private:
  vtkMorphNodeFilter(const vtkMorphNodeFilter&) = delete;
  void operator=(const vtkMorphNodeFilter&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
