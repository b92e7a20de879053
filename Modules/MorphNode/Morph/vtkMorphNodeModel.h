// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphNodeModel
 * @brief   the morph node's model of its input: the data sets of port 0 in their form and
 *          the scene built from them (private to MorphNode)
 *
 * vtkMorphNodeFilter takes three forms on port 0: the Java3D form (absolute shapes as
 * connections, or as one vtkPartitionedDataSet), one point set with target arrays (the glTF
 * form), or a composite of such point sets (a whole head). Collect finds the form and the
 * data sets of this execution; Update builds a part per data set (vtkMorphModelAdapter)
 * and the core's morphnode::MorphScene of them, again only when a data set object, its
 * modification time or the storage choice changed. In parallel every process takes part in
 * the exchange of a rebuild (the whole model's figures), whatever its piece.
 *
 * @sa vtkMorphNodeFilter vtkMorphModelAdapter vtkMorphNodeOutput
 */
#ifndef vtkMorphNodeModel_h
#define vtkMorphNodeModel_h

#include "morph/MorphScene.h"

#include "vtkType.h"

#include <cstdint>
#include <utility>
#include <vector>

class vtkAlgorithm;
class vtkCompositeDataSet;
class vtkDataObject;
class vtkInformationVector;
class vtkMorphNodeOutput;
class vtkMultiProcessController;
class vtkPointSet;

namespace morphnode
{
class WeightRequests;
}

class vtkMorphNodeModel
{
public:
  /// This execution's data sets from port 0 (its input information).
  void Collect(vtkInformationVector* port0);

  /// Rebuilds the model when an input or `sparseCoverage` changed: the parts into
  /// `output.Parts` (cleared), the scene, the model's target names into `requests`
  /// (through vtkMorphNodeOutput::SetModel, with the figures, into `output` too). Throws
  /// morphnode::InputError for input that makes no model.
  void Update(double sparseCoverage, vtkMultiProcessController* controller,
    vtkMorphNodeOutput& output, morphnode::WeightRequests& requests, vtkAlgorithm* progress);

  /// True with more than one process.
  static bool IsParallel(vtkMultiProcessController* controller);

  morphnode::MorphScene Scene;
  /// This execution's inputs: the connections of port 0 (one form) or a composite's leaves.
  std::vector<vtkPointSet*> Inputs;
  vtkCompositeDataSet* CompositeInput = nullptr;
  std::vector<vtkPointSet*> LeafInputs;
  bool Composite = false;  ///< the model is a composite's
  bool HasScene = false;   ///< the scene has parts (a process with an empty piece has none)
  bool Ready = false;      ///< a model was built from the current inputs
  uint64_t Generation = 0; ///< counts the models built

private:
  /// Whether the model was built from these data set objects, unchanged, and settings.
  bool Unchanged(double sparseCoverage);
  /// The parts and the scene of this process's inputs (none for an empty piece).
  void BuildParts(double sparseCoverage, bool parallel, vtkMorphNodeOutput& output);

  std::vector<std::pair<vtkDataObject*, vtkMTimeType>> From, BuiltFrom;
  double BuiltSparseCoverage = -1.0;
};

#endif
