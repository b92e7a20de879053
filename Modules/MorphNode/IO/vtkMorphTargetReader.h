// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphTargetReader
 * @brief   reads a face or a whole head with morph targets, ready for vtkMorphNodeFilter
 *
 * Sources:
 *
 * - glTF 2.0 (`.gltf`, `.glb`) with morph targets, read by MorphNode's own validated loader
 *   (morphnode::LoadGltfScene, docs/gltf.md; VTK's vtkGLTFReader is not used: VTK 9.1 reads
 *   outside its buffers on damaged files and does not zero-fill sparse accessors without a
 *   bufferView). By default the WHOLE scene: every node that holds a mesh, every primitive,
 *   node transforms applied (TRS and matrix, nested), into a
 *   vtkPartitionedDataSetCollection (see below). Selecting one mesh or primitive
 *   (MeshName, MeshIndex >= 0 or PrimitiveIndex >= 0) gives one vtkPolyData as before:
 *   that primitive in its node's own frame (node transforms not applied).
 * - A set of OBJ files (a folder, or its neutral `.obj`): one neutral plus one file per
 *   shape with the same vertex order, name = file stem, as ICT-FaceKit and many scanned
 *   face datasets ship them (see morphnode::ReadObjSet). Polygons are triangulated; texture
 *   coordinates are not read (OBJ keeps them per corner, not per vertex). Always a
 *   vtkPolyData.
 *
 * Every part (and the one vtkPolyData) carries: points and triangles; point data
 * `target<k>_position` (and `target<k>_normal`) holding relative deltas, active normals
 * `Normals` (computed, with every target's normal deltas, when the file lacks them; see
 * NormalsMode), `COLOR_0` (unsigned char RGBA) when the file has vertex colours; field data
 * `TargetNames` (neutral first), `PartName`, `NodeName`, `MaterialName` (strings) and
 * `BaseColor` (the material's linear RGBA base colour factor, 4 doubles).
 *
 * The scene's output, a vtkPartitionedDataSetCollection (the composite type VTK 9.1 and
 * ParaView 5.11 recommend for new readers: ParaView shows, colours and selects its parts
 * by the data assembly, and vtkXMLPartitionedDataSetCollectionWriter writes it as .vtpc),
 * holds one vtkPartitionedDataSet per part (one primitive of one node, in the scene's
 * order), each with one vtkPolyData in world space; its metadata NAME() is the part's
 * name (`Head/M_Face`, `EyeLeft/M_IrisLeft`, `Teeth`). The data assembly mirrors the glTF
 * node tree (node names made valid XML names), with each part's index on its node. Parts
 * also carry `NodeOrigin` (3 doubles: their node's origin in world space) and `NodeAxes`
 * (9 doubles: the node's world x, y and z axes, normalized), so that eyes can be turned
 * about their own centre. Parts keep their own targets (an eye has none); the collection's
 * field data `TargetNames` lists every target of the scene by name (neutral first).
 *
 * Skinned parts (a glTF skin, docs/avatars.md) are shown in their rest pose: skinned at the
 * joints as stored (or as the animation has them with ANIMATION_TRANSFORMS), the mesh
 * node's own transform ignored as glTF requires, every JOINTS_n/WEIGHTS_n set used; their
 * target deltas and normals are skinned with them (morph first, then skin). They carry the
 * skin (vtkMorphSkinArrays.h: point data `SkinJoints`, `SkinWeights`; field data
 * `SkinJointIndices`, `SkinInverseBind`, `SkeletonNames`, `SkeletonParents`,
 * `SkeletonRest`), so that vtkMorphSkinFilter re-skins them when joints move. Their
 * NodeOrigin is the mesh node's (for a skinned eye not its centre: its joint turns it). In
 * the one-mesh mode a skinned primitive stays in its bind space, without the skin arrays.
 *
 * Parts (and the one vtkPolyData) of a glTF file also carry field data `DefaultWeights`:
 * the file's default morph weights of their targets (the node's `weights`, else the
 * mesh's, else zeros), one double per target in `TargetNames` order without the neutral.
 *
 * Animations (glTF): output port 1 is a vtkTable of one row: a column per morph target
 * name (neutral excluded) with its weight at the requested time, and for each node the
 * chosen animation moves, columns `<node>.translation` (3 components, times Scale),
 * `<node>.rotation` (4: the unit quaternion x, y, z, w) and `<node>.scale` (3), in the
 * node's parent frame as glTF gives them, node names as in the file
 * (`node<i>` when unnamed). Its field data holds `Time` and `AnimationName`. Connected to
 * vtkMorphNodeFilter's weights port (SetWeightsConnection) it drives the face: the filter
 * reads the columns named after its targets and ignores the others. Per-mesh weight
 * channels are mapped onto the composite head BY TARGET NAME
 * (morphnode::GltfWeightsByTargetName: a name several parts carry takes the value of its
 * first part in scene order; in the one-mesh mode, the selected part's node). With no
 * animation chosen (the default) the row holds the default weights and no time is
 * advertised: the reader behaves as it always did.
 *
 * Choose an animation by AnimationName or AnimationIndex; UpdateInformation() then
 * reports GetNumberOfAnimations() and their names, and both output ports advertise
 * TIME_STEPS (the animation's key times, or a regular grid at FrameRate frames per
 * second) and TIME_RANGE; the outputs are sampled at UPDATE_TIME_STEP (the first key when
 * none is requested) exactly as the glTF 2.0 specification defines STEP, LINEAR (slerp
 * for rotations) and CUBICSPLINE (morphnode::GltfAnimationPlayer), holding the first and
 * last values outside the keys. The outputs' DATA_TIME_STEP is the time sampled.
 *
 * ApplyAnimation decides what the geometry (port 0) shows of the animation:
 * ANIMATION_NOT_APPLIED (default: the rest pose, as without animation; drive the weights
 * through port 1 and vtkMorphNodeFilter), ANIMATION_TRANSFORMS (the animated node
 * transforms: head pose, eyes; parts in world space at that time, NodeOrigin and
 * NodeAxes follow), ANIMATION_TRANSFORMS_AND_WEIGHTS (what a glTF viewer shows, and what
 * vtkGLTFReader gives with ApplyDeformationsToGeometry: the animated weights blended into
 * the points and normals too; field data `AppliedWeights` then records them: do not blend
 * them a second time). In the one-mesh mode the part stays in its node's frame, so only
 * the weights can be applied.
 *
 * Bad files are reported with vtkErrorMacro (naming the file and the JSON pointer of the
 * fault) and give an empty output; the update fails. So does an animation name or index
 * the file does not have.
 *
 * @sa vtkMorphNodeFilter vtkMorphSkinFilter morphnode::LoadGltfScene
 */

#ifndef vtkMorphTargetReader_h
#define vtkMorphTargetReader_h

#include "vtkMorphNodeIOModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // For std::shared_ptr, std::unique_ptr
#include <string> // For std::string
#include <vector> // For std::vector

class vtkTable;
namespace morphnode
{
struct GltfScene;
}

class VTKMORPHNODEIO_EXPORT vtkMorphTargetReader : public vtkPolyDataAlgorithm
{
public:
  static vtkMorphTargetReader* New();
  vtkTypeMacro(vtkMorphTargetReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * A `.glb` / `.gltf` file, an OBJ set's folder, or its neutral `.obj`.
   */
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /**
   * glTF: one mesh to read instead of the whole scene, by name (wins when set) or index
   * (default -1: none), and its primitive (default -1: primitive 0 of the chosen mesh).
   * Any of them set (a name, an index >= 0) makes the output one vtkPolyData, in the
   * primitive's own node frame, as this reader gave before it read scenes;
   * PrimitiveIndex alone picks that primitive of mesh 0.
   */
  vtkSetStdStringFromCharMacro(MeshName);
  vtkGetCharFromStdStringMacro(MeshName);
  vtkSetClampMacro(MeshIndex, int, -1, VTK_INT_MAX);
  vtkGetMacro(MeshIndex, int);
  vtkSetClampMacro(PrimitiveIndex, int, -1, VTK_INT_MAX);
  vtkGetMacro(PrimitiveIndex, int);
  ///@}

  /**
   * True when the output is (or will be) the whole glTF scene as a
   * vtkPartitionedDataSetCollection: a glTF file with no mesh or primitive selected.
   */
  bool GetReadsWholeScene();

  ///@{
  /**
   * OBJ set given as a folder: the neutral's file name (default: `neutral.obj`, or
   * `generic_neutral_mesh.obj` as ICT-FaceKit names it).
   */
  vtkSetStdStringFromCharMacro(NeutralFileName);
  vtkGetCharFromStdStringMacro(NeutralFileName);
  ///@}

  ///@{
  /**
   * Scale applied to positions, deltas and node origins (e.g. 0.01 to read an OBJ set in
   * centimetres as metres). Default 1.
   */
  vtkSetMacro(Scale, double);
  vtkGetMacro(Scale, double);
  ///@}

  /// Normals policy.
  enum NormalsModes
  {
    NORMALS_FROM_FILE = 0,    ///< never compute
    NORMALS_WHEN_MISSING = 1, ///< compute all when the base or any target lacks them (default)
    NORMALS_ALWAYS = 2        ///< always compute from the geometry
  };
  vtkSetClampMacro(NormalsMode, int, NORMALS_FROM_FILE, NORMALS_ALWAYS);
  vtkGetMacro(NormalsMode, int);

  ///@{
  /**
   * glTF: the animation to play, by name (wins when set) or index (default -1: none).
   */
  vtkSetStdStringFromCharMacro(AnimationName);
  vtkGetCharFromStdStringMacro(AnimationName);
  vtkSetClampMacro(AnimationIndex, int, -1, VTK_INT_MAX);
  vtkGetMacro(AnimationIndex, int);
  ///@}

  ///@{
  /**
   * Time steps advertised for the chosen animation: 0 (default) its key times, each once;
   * a positive rate a regular grid from its first to its last key (the last key included).
   */
  vtkSetClampMacro(FrameRate, double, 0.0, 1000.0);
  vtkGetMacro(FrameRate, double);
  ///@}

  /// What the geometry shows of the animation (see the class description).
  enum ApplyAnimationModes
  {
    ANIMATION_NOT_APPLIED = 0,
    ANIMATION_TRANSFORMS = 1,
    ANIMATION_TRANSFORMS_AND_WEIGHTS = 2
  };
  vtkSetClampMacro(ApplyAnimation, int, ANIMATION_NOT_APPLIED, ANIMATION_TRANSFORMS_AND_WEIGHTS);
  vtkGetMacro(ApplyAnimation, int);

  ///@{
  /**
   * Animations of the file, known after UpdateInformation() (names; unnamed ones as
   * `animation<i>`), the index of the chosen one (-1: none) and its first and last key time.
   */
  int GetNumberOfAnimations() { return static_cast<int>(this->AnimationNames.size()); }
  const char* GetAnimationNameByIndex(int index);
  int GetChosenAnimation() { return this->ChosenAnimation; }
  double GetAnimationStartTime() { return this->AnimationRange[0]; }
  double GetAnimationEndTime() { return this->AnimationRange[1]; }
  ///@}

  /**
   * The weights table of output port 1 (see the class description).
   */
  vtkTable* GetWeightsOutput();

  ///@{
  /**
   * Targets read by the last update, neutral first: the one mesh's, or for a scene every
   * part's by name, in order of first appearance.
   */
  int GetNumberOfTargets() { return static_cast<int>(this->TargetNames.size()); }
  const char* GetTargetName(int index);
  ///@}

  /**
   * Meshes of the last glTF file read (names; unnamed ones as `mesh<i>`).
   */
  int GetNumberOfMeshes() { return static_cast<int>(this->MeshNames.size()); }
  const char* GetMeshNameByIndex(int index);

  /**
   * Parts of the last scene read (one vtkPolyData of the output each), by name; 1 when one
   * mesh or an OBJ set was read.
   */
  int GetNumberOfParts() { return static_cast<int>(this->PartNames.size()); }
  const char* GetPartName(int index);

protected:
  vtkMorphTargetReader();
  ~vtkMorphTargetReader() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  vtkTypeBool ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  /// Makes the output a vtkPartitionedDataSetCollection or a vtkPolyData (GetReadsWholeScene).
  virtual int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*);
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  std::string MeshName;
  std::string NeutralFileName;
  int MeshIndex = -1;
  int PrimitiveIndex = -1;
  double Scale = 1.0;
  int NormalsMode = NORMALS_WHEN_MISSING;
  std::string AnimationName;
  int AnimationIndex = -1;
  double FrameRate = 0.0;
  int ApplyAnimation = ANIMATION_NOT_APPLIED;

private:
  vtkMorphTargetReader(const vtkMorphTargetReader&) = delete;
  void operator=(const vtkMorphTargetReader&) = delete;

  void ReadObjSet(vtkPolyData* output);
  /// The glTF file into the outputs at the time `outputVector` asks for.
  void ReadGltf(vtkDataObject* output, vtkTable* weights, vtkInformationVector* outputVector);
  struct SceneCache;
  /// The glTF scene read with these transform options; kept while the file and the
  /// reader's properties are unchanged, so that a new time step reads nothing again.
  std::shared_ptr<const morphnode::GltfScene> LoadScene(bool applyTransforms);
  /// The animation chosen by name or index, -1 for none; throws for one the file lacks.
  int ResolveAnimation(const morphnode::GltfScene& scene) const;

  std::unique_ptr<SceneCache> Cache;
  std::vector<std::string> AnimationNames;
  int ChosenAnimation = -1;
  double AnimationRange[2] = { 0.0, 0.0 };

  std::vector<std::string> TargetNames;
  std::vector<std::string> MeshNames;
  std::vector<std::string> PartNames;
};

#endif
