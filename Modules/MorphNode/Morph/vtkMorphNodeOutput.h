// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphNodeOutput
 * @brief   the morph node's output data sets, kept across executions (private to MorphNode)
 *
 * vtkMorphNodeFilter's parts (one per data set of its input: the one input or a
 * composite's leaves) and everything its output is assembled from: the arrays a blend
 * writes (written again in place only when nothing but this helper holds them, so that a
 * snapshot kept downstream never changes under its holder), a composite's output leaves and
 * partitioned data sets (kept likewise: making and filling 11 data sets per step cost a
 * fifth of a head's Update), the distance maps, and the field data (the model's target
 * names, the effective weights, active target count, error bound and DistNorm).
 *
 * The filter builds the parts (with vtkMorphModelAdapter) and the scene; per execution it
 * calls Prepare, blends the scene parts it returns into GetWhere() (the core's blend plan
 * over vtkSMPTools), then Finish and Assemble.
 *
 * @sa vtkMorphNodeFilter vtkMorphModelAdapter
 */
#ifndef vtkMorphNodeOutput_h
#define vtkMorphNodeOutput_h

#include "vtkMorphCompositeLeaves.h"
#include "vtkMorphModelAdapter.h"

#include "morph/MorphScene.h"

#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <memory>
#include <string>
#include <vector>

class vtkCompositeDataSet;
class vtkDataArray;
class vtkDataObject;
class vtkDoubleArray;
class vtkFieldData;
class vtkPointSet;
class vtkStringArray;

class vtkMorphNodeOutput
{
public:
  vtkMorphNodeOutput();

  /// One data set of the input (the one input, or a leaf of a composite) with its model
  /// and the arrays its blend writes.
  struct Part
  {
    vtkPointSet* Input = nullptr; ///< this execution's data set (the neutral in the Java3D form)
    std::string Name;             ///< a leaf's name, for messages
    std::shared_ptr<const vtkMorphModelAdapter::BuiltModel>
      Built;            ///< null: an empty leaf, passed through
    int ScenePart = -1; ///< its part in the scene, -1: none
    /// Output arrays kept across executions (vtkMorphModelAdapter::BlendOutputs).
    vtkMorphModelAdapter::BlendOutputs Outputs;
    /// Where the blend writes each attribute: the output array itself, or for arrays of
    /// other types than the attribute's (integers) a buffer copied over afterwards.
    std::vector<morphnode::AttributeOutput> Where;
    std::vector<std::vector<float>> FloatScratch;
    std::vector<std::vector<double>> DoubleScratch;
    std::vector<vtkSmartPointer<vtkDataArray>> Distances; ///< built on first request
    bool Blended = false;                                 ///< in this execution
    /// A composite's output leaf, filled again in place when nothing but this helper holds
    /// it. A kept leaf keeps its structure, cell data and the neutral's field data (the
    /// input cannot have changed: that rebuilds the model, and the parts); its points and
    /// point data are assembled again.
    vtkSmartPointer<vtkPointSet> OutputLeaf;
    bool LeafKept = false;
    bool HasDistNorm = false; ///< the kept leaf's field data holds DistNorm
    /// A skinned part's MorphedPointRanges (vtkMorphSkinArrays.h), made once per model.
    vtkSmartPointer<vtkDataArray> MovedRanges;
    std::weak_ptr<const vtkMorphModelAdapter::BuiltModel> MovedRangesOf;
    vtkSmartPointer<vtkIdTypeArray> MovedTime; ///< MorphedArraysTime, rewritten each frame
  };
  std::vector<Part> Parts;

  /// A new model: its target names (neutral first) and DistNorm, shared by every output.
  /// The parts are set by the caller (Parts).
  void SetModel(const std::vector<std::string>& names, const std::vector<double>& distNorm);
  /// The model's DistNorm (vtkMorphNodeFilter::GetDistNorm).
  vtkDoubleArray* GetDistNorm() const { return this->DistNorm; }

  /// Readies this execution's output arrays (and a composite's leaves) and returns the
  /// scene parts to blend: those of parts with a model that, for a composite, some active
  /// target moves (the others pass through).
  std::vector<size_t> Prepare(const morphnode::MorphScene& scene, bool composite);
  /// Where each scene part's blend writes (after Prepare), indexed by scene part.
  const std::vector<const std::vector<morphnode::AttributeOutput>*>& GetWhere() const
  {
    return this->WhereByScenePart;
  }
  /// After the blend: buffers copied into the arrays of other types, arrays Modified().
  void Finish();

  /// Fills `output` (the input's type): the neutral's structure with the blended arrays in
  /// place of the neutral's (or the neutral's own when not blended), distance maps when
  /// `distances`, field data; for a composite `input`, one such data set per leaf in the
  /// input's structure. `scene` is null for a piece without one. Throws InputError for an
  /// output that does not fit the parts.
  void Assemble(vtkDataObject* output, vtkCompositeDataSet* input,
    const morphnode::MorphScene* scene, bool distances);

  /// The model's target names and this execution's field data (EffectiveWeights,
  /// ActiveTargetCount, ErrorBound, and DistNorm when `distances`) for output data sets
  /// assembled elsewhere (the filter's mesh levels, vtkMorphMeshLevels): added to each of
  /// `fds`, except to those `kept` (an output that holds the last execution's arrays, which
  /// are rewritten in place when only this helper and the kept outputs hold them) unless
  /// new arrays had to be made.
  void AddFieldArrays(const std::vector<vtkFieldData*>& fds, const std::vector<bool>& kept,
    const morphnode::MorphScene* scene, bool distances);
  /// A part's distance maps over its input's points (made on first request, kept with the
  /// part), as Assemble adds them: for outputs assembled elsewhere (the mesh levels gather
  /// them to a level's points).
  std::vector<vtkDataArray*> GetDistanceArrays(Part& part, const morphnode::MorphScene* scene);
  /// The last output's partitioned data sets that only this helper holds let go of their
  /// leaves (Prepare does this first), so that a leaf assembled elsewhere can be kept.
  void ReleaseLeaves();
  /// A composite output's structure (the input's) holding the parts' OutputLeaf, and its
  /// field data: the last step of Assemble, for leaves assembled elsewhere.
  void PlaceLeaves(vtkCompositeDataSet* input, vtkCompositeDataSet* output);

private:
  const std::vector<vtkSmartPointer<vtkDataArray>>& DistanceArrays(
    Part& part, const morphnode::MorphScene* scene);
  std::vector<vtkDataArray*> FieldArrays(
    const morphnode::MorphScene* scene, bool distances, int kept, bool& fresh);
  /// A blended skinned part's MorphedPointRanges and MorphedArraysTime (of `output`'s points
  /// and normals) into `fd`; removed from other parts.
  static void SetMovedRanges(Part& part, vtkPointSet* output, vtkFieldData* fd);
  void AssemblePart(Part& part, vtkPointSet* output, const morphnode::MorphScene* scene,
    bool distances, const std::vector<vtkDataArray*>& fieldArrays, bool kept);
  void AssembleComposite(vtkCompositeDataSet* input, vtkCompositeDataSet* output,
    const morphnode::MorphScene* scene, bool distances);
  static void PrepareArrays(Part& part);

  std::vector<std::string> Names;
  vtkNew<vtkDoubleArray> DistNorm;
  /// Made once per model, shared by every output.
  vtkSmartPointer<vtkStringArray> TargetNames;
  vtkSmartPointer<vtkDoubleArray> DistNormOut;
  /// Per-execution field data, rewritten in place when no one else holds them.
  vtkSmartPointer<vtkDataArray> EffectiveWeightsOut, ActiveTargetCountOut, ErrorBoundOut;
  /// The output's structure (a collection's partitioned data sets kept like the leaves).
  vtkMorphCompositeLeaves Leaves;
  std::vector<const std::vector<morphnode::AttributeOutput>*> WhereByScenePart;
};

#endif
