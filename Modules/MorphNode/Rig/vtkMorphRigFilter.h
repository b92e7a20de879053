// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphRigFilter
 * @brief   expands semantic shape weights (visemes, expressions) into a face's own
 *          morph-target weights through a rig file (morphnode::Rig::Expand)
 *
 * Input port 0: a vtkTable of semantic weights, one column per rig shape (`EyesClosed`,
 * `BrowsUp`, `A`, `PP`, ...), as a behaviour or speech source emits them. Every row is
 * expanded; a column that names no rig shape is treated as described below.
 *
 * The face's target names come from, in this order:
 * 1. the optional input port 1: the face itself (e.g. vtkMorphTargetReader's output),
 *    whose field data `TargetNames` (neutral first) is read; for a composite dataset the
 *    first leaf that has it;
 * 2. SetTargetNames(): an array laid out like that field data, **neutral first** (so the
 *    face's own `TargetNames` array can be passed as it is);
 * 3. the rig's declared `targets` list.
 *
 * Output: a table with the same number of rows. Its first columns are the face's
 * relative targets (no neutral), in the face's order, as vtkDoubleArray holding
 *   target[t] = clamp(sum_s shape[s] * coefficient(s, t), 0, 1),
 * ready for vtkMorphNodeFilter::SetWeightsConnection (use that filter's RELATIVE weight
 * mode: these are glTF-style weights). Shapes without a column weigh 0.
 *
 * Other input columns (naming neither a rig shape nor a face target, e.g. head pose or
 * time) are passed through unchanged after the target columns when PassOtherColumns is
 * on (default); else dropped. A column named after a face target itself is always
 * dropped: the expanded value is the one the output carries.
 *
 * Rig-aware optimization (OptimizerPreset other than OPTIMIZER_NONE, the default): the
 * optimizer of the paper (morphnode::WeightOptimizer, presets as vtkMorphNodeFilter's)
 * decides per rig shape, before the expansion (morphnode::RigOptimizer): a viseme's targets
 * are kept or pruned together, so a closure (PP: jawOpen cancelled by mouthClose) or a
 * rounding survives every method. The shapes are measured on the face's geometry (port 1,
 * a point set or a composite of parts with `target<k>_position` arrays). Leave the
 * optimizer of the vtkMorphNodeFilter downstream off (it would prune targets again). Rows
 * are decided in order; the hysteresis history carries over from one execution to the
 * next (ResetHysteresis forgets it).
 *
 * Time: TIME_STEPS / TIME_RANGE flow from port 0 to the output and UPDATE_TIME_STEP back
 * up, so a temporal weight source animates the face through this filter.
 *
 * The rig file is read when it is first needed and again only when the file name changes
 * or the filter is modified (Modified(), any setter); every execution re-binds it to the
 * current target names. Errors (unreadable or invalid rig, a rig naming a target the
 * face lacks, a shape column that is not numeric, a non-finite weight) are reported with
 * vtkErrorMacro and give an empty output table.
 *
 * @sa morphnode::Rig vtkMorphRigBaker vtkMorphNodeFilter
 */

#ifndef vtkMorphRigFilter_h
#define vtkMorphRigFilter_h

#include "vtkMorphNodeRigModule.h" // For export macro
#include "vtkTableAlgorithm.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkStringArray;

class VTKMORPHNODERIG_EXPORT vtkMorphRigFilter : public vtkTableAlgorithm
{
public:
  static vtkMorphRigFilter* New();
  vtkTypeMacro(vtkMorphRigFilter, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The rig file (JSON, format in docs/rigs.md), e.g. Data/rigs/arkit.json.
   */
  /// Setting the current value does not modify the filter.
  virtual void SetRigFileName(const char* value);
  vtkGetCharFromStdStringMacro(RigFileName);
  ///@}

  /**
   * Connect the face (a dataset with field data `TargetNames`) to the optional port 1.
   */
  void SetFaceConnection(vtkAlgorithmOutput* output);

  ///@{
  /**
   * The face's target names, neutral first (as in the field data `TargetNames`); used
   * when nothing is connected to port 1. The array is copied. nullptr clears them.
   */
  void SetTargetNames(vtkStringArray* names);
  vtkStringArray* GetTargetNames();
  ///@}

  ///@{
  /**
   * Pass input columns that name neither a rig shape nor a face target through to the
   * output. Default on.
   */
  vtkSetMacro(PassOtherColumns, bool);
  vtkGetMacro(PassOtherColumns, bool);
  vtkBooleanMacro(PassOtherColumns, bool);
  ///@}

  ///@{
  /**
   * Rig-aware optimization: the method (vtkMorphNodeFilter::OptimizerPresets values 0..4:
   * none, fixed-maximum, fixed-remaining, adjusted, error-bounded; default none), its
   * threshold th_fix, its error bound eps (model units) and the hysteresis in [0, 1).
   */
  vtkSetClampMacro(OptimizerPreset, int, 0, 4);
  vtkGetMacro(OptimizerPreset, int);
  vtkSetClampMacro(Threshold, double, 0.0, 1.0);
  vtkGetMacro(Threshold, double);
  vtkSetClampMacro(MaxVertexError, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxVertexError, double);
  vtkSetClampMacro(Hysteresis, double, 0.0, 0.99);
  vtkGetMacro(Hysteresis, double);
  /// Forget which shapes were active (after a jump in time).
  void ResetHysteresis();
  /// The last row's optimizer bound on the vertex error and the shapes it kept (both 0 with
  /// the optimizer off).
  double GetLastErrorBound();
  int GetLastActiveShapes();
  ///@}

  ///@{
  /**
   * The rig as last read (empty / 0 before the first execution or after an error).
   */
  int GetNumberOfShapes();
  const char* GetShapeName(int index);
  ///@}

protected:
  vtkMorphRigFilter();
  ~vtkMorphRigFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string RigFileName;
  bool PassOtherColumns = true;
  int OptimizerPreset = 0;
  double Threshold = 0.1;
  double MaxVertexError = 0.0;
  double Hysteresis = 0.0;

private:
  vtkMorphRigFilter(const vtkMorphRigFilter&) = delete;
  void operator=(const vtkMorphRigFilter&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
