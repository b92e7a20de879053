// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file   vtkMorphModelAdapter.h
 * @brief  Conversions between VTK data and the core's morphnode::MorphMesh (private).
 *
 * The morph node's side of VTK data: the Java3D form (one absolute vtkPointSet per target)
 * and the glTF form (one vtkPointSet with relative target arrays, read through
 * vtkMorphTargetArrays, which owns that convention), weights from tables, and writing
 * blended attributes back into VTK arrays of the original types. Every function throws
 * morphnode::InputError for bad input; callers turn that into vtkErrorMacro.
 */

#ifndef vtkMorphModelAdapter_h
#define vtkMorphModelAdapter_h

#include "vtkMorphTargetArrays.h"

#include "morph/MorphMesh.h"
#include "morph/MorphScene.h"
#include "morph/WeightRequests.h"

#include "vtkSmartPointer.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkCompositeDataSet;
class vtkDataArray;
class vtkDataObject;
class vtkFieldData;
class vtkMultiProcessController;
class vtkPointData;
class vtkPoints;
class vtkPointSet;
class vtkStringArray;
class vtkTable;

namespace vtkMorphModelAdapter
{
/// Field-data names the module reads and writes.
constexpr const char* TargetNamesArray = vtkMorphTargetArrays::TargetNamesArray;
constexpr const char* TargetNameArray = "TargetName";
constexpr const char* EffectiveWeightsArray = "EffectiveWeights";
constexpr const char* ActiveTargetCountArray = "ActiveTargetCount";
constexpr const char* ErrorBoundArray = "ErrorBound";
constexpr const char* DistNormArray = "DistNorm";
constexpr const char* AnimatedRegionArray = "AnimatedRegion";
constexpr const char* DistancePrefix = "Distance_";

/// A blended attribute and where it lives in VTK.
struct AttributeBinding
{
  std::string ArrayName;                   ///< empty for the points
  vtkSmartPointer<vtkDataArray> Prototype; ///< type and layout of the output array
  bool IsNormals = false;
};

/// Where one point array of the output comes from.
struct OutputArraySource
{
  int NeutralIndex; ///< index of the array in the neutral's point data
  int Blended;      ///< index into BlendOutputs::Arrays, or -1: the neutral's array passes
  int Attribute;    ///< vtkDataSetAttributes attribute type to keep, or -1
};

struct BuiltModel
{
  morphnode::MorphMesh Model;
  /// Parallel to Model's attributes.
  std::vector<AttributeBinding> Bindings;
  /// glTF form: point arrays of the input that must not reach the output.
  std::vector<std::string> ConsumedArrays;
  /// The output's point arrays in the neutral's order, worked out once per model so that
  /// an execution does no lookups by name (53 target arrays made pass-then-remove cost
  /// more than a speech frame's blend).
  std::vector<OutputArraySource> PointArrays;
};

/// The arrays a blend writes, kept from one execution to the next. An array is written
/// again in place only when nothing but this cache holds it (the pipeline released the
/// previous output); when anyone else still holds it, the spare set is written instead
/// (the one before it, which a renderer or a filter that holds one frame has let go of by
/// then), else a new one is made, so a snapshot kept downstream never changes under its
/// holder. The two sets alternate while a renderer holds each frame: no allocation, no
/// first touch of new pages per frame.
struct BlendOutputs
{
  vtkSmartPointer<vtkPoints> Points;
  /// Parallel to the bindings after the points.
  std::vector<vtkSmartPointer<vtkDataArray>> Arrays;
  /// The set before, held here while it may still be held downstream.
  vtkSmartPointer<vtkPoints> SparePoints;
  std::vector<vtkSmartPointer<vtkDataArray>> SpareArrays;
};

/// True if the point set carries glTF-style target arrays (vtkMorphTargetArrays::HasTargets).
bool HasRelativeTargets(vtkPointSet* input);

/// Java3D form: inputs[0] is the neutral, the others absolute targets.
BuiltModel BuildFromAbsoluteTargets(const std::vector<vtkPointSet*>& inputs, double sparseCoverage);
/// glTF form: one point set with relative target arrays (vtkMorphTargetArrays::ToMorphMesh).
BuiltModel BuildFromRelativeTargets(vtkPointSet* input, double sparseCoverage);
/// The Java3D form in one data set: the partitions of a vtkPartitionedDataSet none of which
/// carries target arrays (partition 0 the neutral, the others absolute targets), so that
/// the 14 geometries of a Java3D Morph cost the pipeline one connection, not 14. Empty for
/// anything else (a vtkPartitionedDataSet of parts with target arrays is a head).
std::vector<vtkPointSet*> AbsoluteShapes(vtkDataObject* input);
/// The glTF form when `inputs` is one point set with target arrays, else the Java3D form.
BuiltModel BuildModel(const std::vector<vtkPointSet*>& inputs, double sparseCoverage);

/// Requested weights (neutral first) from the first row of a table whose columns are
/// named after the model's targets (`model`'s SetTargets). Columns naming no target are
/// ignored; targets not named get 0; an unnamed neutral gets morphnode::ImplicitNeutralWeight.
/// `matched` counts the columns used.
std::vector<double> WeightsFromTable(
  vtkTable* table, const morphnode::WeightRequests& model, int& matched);

/// A vtkStringArray holding the names.
vtkSmartPointer<vtkStringArray> MakeNamesArray(
  const char* arrayName, const std::vector<std::string>& names);
/// A one-tuple-per-value vtkDoubleArray.
vtkSmartPointer<vtkDataArray> MakeDoubleArray(
  const char* arrayName, const std::vector<double>& values);

/// `slot` when it has the layout of `prototype` (type, components, `numTuples`) and
/// `holders` references are all it has (nobody outside the cache holds it), else the
/// `spare` array (swapped into `slot`) when it has that layout and only `spare` holds it,
/// else a new array of that layout in `slot`, the held one kept as the spare (see
/// BlendOutputs). Whichever is returned holds an earlier frame or nothing: the caller
/// writes all of it.
vtkDataArray* ReuseOrNew(vtkSmartPointer<vtkDataArray>& slot, vtkDataArray* prototype,
  vtkIdType numTuples, int holders, vtkSmartPointer<vtkDataArray>* spare = nullptr);

/// Fills `out` with the output's point arrays: the neutral's, each blended one in place of
/// the array it replaces (same attribute role), target arrays left out.
void AssemblePointData(
  vtkPointData* neutral, const BuiltModel& built, const BlendOutputs& outputs, vtkPointData* out);

/// Points flagged as duplicates of another piece's (vtkGhostType, DUPLICATEPOINT): left out
/// of the model's sums (morphnode::MorphScene::SetParts). Empty when the data set flags none.
std::vector<uint8_t> DuplicateFlags(vtkPointSet* input);

/// A composite's leaves' names, in the iterator's order (empty leaves skipped), for
/// messages: a collection names its partitioned data sets (the reader's parts), not their
/// partitions; other composites name their leaves (else "#<flat index>"). At least
/// `count` + 1 names ("?" for the missing).
std::vector<std::string> LeafNames(vtkCompositeDataSet* composite, size_t count);

/// The whole model's figures from every process's piece: each sends its piece (null: it
/// has none) or its `error` to all (a vtkMultiProcessStream through the controller's
/// AllGather), and all combine them in process order (morphnode::CombineTargetDistances),
/// so that every process decides exactly alike. Every process must call it. Throws
/// InputError with the first process's error (the same on every process) when any had
/// one, and when no process has a piece.
morphnode::NamedTargetDistances GatherModel(vtkMultiProcessController* controller,
  const morphnode::NamedTargetDistances* piece, const std::string& error);
} // namespace vtkMorphModelAdapter

#endif
