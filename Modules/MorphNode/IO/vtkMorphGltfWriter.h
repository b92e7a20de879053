// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphGltfWriter
 * @brief   writes a face or a whole head with its morph targets, and a performance (the
 *          weights, head pose and eye turns over time) as a glTF animation, to .glb/.gltf
 *
 * A thin adapter over morphnode::WriteGltfScene (Modules/Core/gltf/GltfWriter.h, which
 * writes through tinygltf; docs/gltf.md "Export"):
 *
 * @code
 * vtkNew<vtkMorphTargetReader> reader;       // the whole head (a composite) or one mesh
 * reader->SetFileName("ict_head_full53.glb");
 * vtkNew<vtkBehaviorTimeSource> behavior;
 * behavior->Say("Hello world", 0.5);
 * vtkNew<vtkMorphRigFilter> rig;             // when the channels do not name the targets
 * rig->SetRigFileName("Data/rigs/arkit.json");
 * rig->SetInputConnection(behavior->GetOutputPort(1)); // port 1: the whole track
 * rig->SetFaceConnection(reader->GetOutputPort());
 * vtkNew<vtkMorphGltfWriter> writer;
 * writer->SetInputConnection(reader->GetOutputPort());
 * writer->SetPerformanceConnection(rig->GetOutputPort());
 * writer->SetFileName("talk.glb");
 * writer->Write();
 * @endcode
 *
 * Input port 0: the neutral face as vtkMorphTargetReader gives it: a vtkPolyData, or a
 * composite (vtkPartitionedDataSetCollection, vtkMultiBlockDataSet) whose leaves are
 * vtkPolyData of triangles with the glTF target arrays (`target<k>_position`,
 * `target<k>_normal`, field data `TargetNames`), point data `Normals` (active normals) and
 * `COLOR_0`, and field data `PartName`, `NodeName`, `MaterialName`, `BaseColor`,
 * `NodeOrigin` (docs/scene.md). Leaves of one `NodeName` become the primitives of one glTF
 * node and mesh; points are in world space, so nodes carry no transform. Leaves that all
 * name one glTF file in `MaterialSource` (with `MaterialIndex`, as vtkMorphTargetReader
 * gives them) get that file's materials and images written back, point data `TCoords` as
 * `TEXCOORD_0`; other leaves a base colour material.
 *
 * Input port 1 (optional): the performance as ONE vtkTable holding the whole track, a
 * row per frame: a time column (TimeArrayName, default `Time`, seconds, strictly
 * increasing), columns named after targets (the weights, glTF-style relative), and the
 * behaviour's `HeadYaw`, `HeadPitch`, `HeadRoll` and `EyeYaw`, `EyePitch` (degrees,
 * morphnode::HeadPoseMatrix's convention). Other columns are ignored. This is
 * vtkBehaviorTimeSource's port 1, vtkMorphRigFilter's output on it, a track CSV read with
 * vtkDelimitedTextReader, or a table filled from numpy. A whole-track table, rather than
 * a sweep over a temporal source's time steps, because a writer then needs one ordinary
 * pipeline update (VTK 9.1 writers do not iterate over time), the frames are exactly the
 * track's (no resampling), the optimizer's hysteresis sees them in order, and 1800 frames
 * cost one table instead of 1800 executions upstream.
 *
 * The weights written are the table's, or, with ApplyOptimizer on, the effective weights
 * of the paper's optimizer deciding once per frame over the whole model, in frame order
 * (morphnode::MorphScene in Relative mode with OptimizerPreset, Threshold, MaxVertexError
 * and Hysteresis, the settings of vtkMorphNodeFilter): what vtkMorphNodeFilter blends when
 * the same frames pass through it in order.
 *
 * The adapter converts and calls morphnode::WriteGltfPerformanceToMemory
 * (Modules/Core/gltf/GltfPerformanceExport.h), which makes the performance: head pose
 * (WriteHeadPose, on by default, when the table has any head column) and eye turns
 * (WriteEyeRotations, when the table has EyeYaw or EyePitch). A skinned avatar (leaves with
 * the skin arrays of vtkMorphSkinArrays, as vtkMorphTargetReader gives a glTF skin) is
 * written with its skeleton (every node with its rest transform), its skins (joints,
 * inverse bind matrices, every JOINTS_n/WEIGHTS_n set; the points back in bind space) and,
 * when it has head, neck or eye joints, the head pose and gaze as rotation channels on those
 * joints, turned as vtkMorphSkinFilter turns them (GetTurnsBones). Otherwise the whole head
 * turns about morphnode::HeadPivot of its bounds and each eye node (morphnode::MakeEyeRig:
 * its convention, or the nodes named in EyeNodeNames; the default limits, no vergence)
 * about its `NodeOrigin` in its `NodeAxes`, exactly as vtkEyeGazeFilter with its defaults
 * turns it. Interpolation: LINEAR (default) or STEP. RelaxArms (off by default) writes a
 * T- or A-pose skinned avatar with its arms relaxed (its upper arm joints' node rotations
 * turned ArmAngle degrees out from straight down, as vtkMorphSkinFilter's RelaxArms shows
 * it: morphnode::RelaxGltfArms), so that any reader shows it at rest with its arms down
 * (GetNumberOfRelaxedArms).
 *
 * Errors (no input, leaves that are not triangle poly data, targets or arrays of the wrong
 * size, NaN, times that do not increase, a file that cannot be written) are reported with
 * vtkErrorMacro, the error code is set, and no file is left half written.
 *
 * @sa vtkMorphTargetReader vtkMorphNodeFilter vtkBehaviorTimeSource morphnode::WriteGltfScene
 */

#ifndef vtkMorphGltfWriter_h
#define vtkMorphGltfWriter_h

#include "vtkMorphNodeIOModule.h" // For export macro
#include "vtkWriter.h"

class vtkTable;

class VTKMORPHNODEIO_EXPORT vtkMorphGltfWriter : public vtkWriter
{
public:
  static vtkMorphGltfWriter* New();
  vtkTypeMacro(vtkMorphGltfWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Interpolations
  {
    LINEAR = 0,
    STEP = 1
  };

  ///@{
  /**
   * The file: GLB unless the name ends in `.gltf` (JSON with the buffer embedded).
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /**
   * The performance (input port 1): a vtkTable, one row per frame.
   */
  void SetPerformanceConnection(vtkAlgorithmOutput* output);
  void SetPerformanceData(vtkTable* table);
  ///@}

  ///@{
  /**
   * The time column of the performance, default "Time".
   */
  vtkSetStringMacro(TimeArrayName);
  vtkGetStringMacro(TimeArrayName);
  ///@}

  ///@{
  /**
   * LINEAR (default) or STEP.
   */
  vtkSetClampMacro(Interpolation, int, LINEAR, STEP);
  vtkGetMacro(Interpolation, int);
  void SetInterpolationToLinear() { this->SetInterpolation(LINEAR); }
  void SetInterpolationToStep() { this->SetInterpolation(STEP); }
  ///@}

  ///@{
  /**
   * Write the optimizer's effective weights instead of the table's (default off).
   */
  vtkSetMacro(ApplyOptimizer, bool);
  vtkGetMacro(ApplyOptimizer, bool);
  vtkBooleanMacro(ApplyOptimizer, bool);
  ///@}

  ///@{
  /**
   * The optimizer, as in vtkMorphNodeFilter: a preset (0 none, 1 fixed-maximum, 2
   * fixed-remaining, 3 adjusted (default), 4 error-bounded; morphnode::OptimizerPreset),
   * its threshold (default 0.1), the vertex error bound of preset 4 (model units, default
   * 0) and the hysteresis (default 0).
   */
  vtkSetClampMacro(OptimizerPreset, int, 0, 4);
  vtkGetMacro(OptimizerPreset, int);
  vtkSetClampMacro(Threshold, double, 0.0, 1.0);
  vtkGetMacro(Threshold, double);
  vtkSetClampMacro(MaxVertexError, double, 0.0, 1e30);
  vtkGetMacro(MaxVertexError, double);
  vtkSetClampMacro(Hysteresis, double, 0.0, 0.99);
  vtkGetMacro(Hysteresis, double);
  ///@}

  ///@{
  /**
   * Head pose and eye turns from the table's angle columns (both on by default).
   */
  vtkSetMacro(WriteHeadPose, bool);
  vtkGetMacro(WriteHeadPose, bool);
  vtkBooleanMacro(WriteHeadPose, bool);
  vtkSetMacro(WriteEyeRotations, bool);
  vtkGetMacro(WriteEyeRotations, bool);
  vtkBooleanMacro(WriteEyeRotations, bool);
  ///@}

  ///@{
  /**
   * Names of the nodes the eye angles turn, separated by spaces; empty (default): the
   * nodes morphnode::EyeRig's convention finds (EyeLeft, eye_R, LeftEye, ...).
   */
  vtkSetStringMacro(EyeNodeNames);
  vtkGetStringMacro(EyeNodeNames);
  ///@}

  ///@{
  /**
   * What the last successful write held: frames, weight columns used, parts.
   */
  vtkGetMacro(NumberOfFrames, int);
  vtkGetMacro(NumberOfWeightColumns, int);
  vtkGetMacro(NumberOfParts, int);
  ///@}

  /**
   * True when the last write turned the avatar's bones (head, neck and eye joints of a
   * skinned avatar, as rotation channels on the joints) rather than nodes.
   */
  vtkGetMacro(TurnsBones, bool);

  ///@{
  /**
   * Write a T- or A-pose skinned avatar with its arms lowered to ArmAngle degrees from
   * straight down (default off, 12), as vtkMorphSkinFilter's RelaxArms and ArmAngle show it.
   */
  vtkSetMacro(RelaxArms, bool);
  vtkGetMacro(RelaxArms, bool);
  vtkBooleanMacro(RelaxArms, bool);
  vtkSetClampMacro(ArmAngle, double, 0.0, 90.0);
  vtkGetMacro(ArmAngle, double);
  ///@}

  /**
   * The upper arm joints the last write relaxed (0 without RelaxArms, for an avatar without
   * arm joints or with its arms already down).
   */
  vtkGetMacro(NumberOfRelaxedArms, int);

protected:
  vtkMorphGltfWriter();
  ~vtkMorphGltfWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  char* FileName = nullptr;
  char* TimeArrayName = nullptr;
  char* EyeNodeNames = nullptr;
  int Interpolation = LINEAR;
  bool ApplyOptimizer = false;
  int OptimizerPreset = 3;
  double Threshold = 0.1;
  double MaxVertexError = 0.0;
  double Hysteresis = 0.0;
  bool WriteHeadPose = true;
  bool WriteEyeRotations = true;
  int NumberOfFrames = 0;
  int NumberOfWeightColumns = 0;
  int NumberOfParts = 0;
  bool TurnsBones = false;
  bool RelaxArms = false;
  double ArmAngle = 12.0;
  int NumberOfRelaxedArms = 0;

private:
  vtkMorphGltfWriter(const vtkMorphGltfWriter&) = delete;
  void operator=(const vtkMorphGltfWriter&) = delete;
};

#endif
