// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphTargetReader
 * @brief   reads a face with morph targets into one vtkPolyData ready for vtkMorphNodeFilter
 *
 * Sources:
 *
 * - glTF 2.0 (`.gltf`, `.glb`) with morph targets, read with VTK's own glTF loader. Adds
 *   what vtkGLTFReader lacks: target names from `mesh.extras.targetNames`, normals (and
 *   normal deltas for every target) computed when the file has none, the choice of the
 *   mesh (by name or index) and primitive, and a single vtkPolyData instead of a
 *   multiblock. Node transforms are not applied: the mesh is read in its own frame.
 * - A set of OBJ files (a folder, or its neutral `.obj`): one neutral plus one file per
 *   shape with the same vertex order, name = file stem, as ICT-FaceKit and many scanned
 *   face datasets ship them (see morphnode::ReadObjSet). Polygons are triangulated; texture
 *   coordinates are not read (OBJ keeps them per corner, not per vertex).
 *
 * Output: the neutral's geometry with point-data arrays `target<k>_position` (and
 * `target<k>_normal`) holding relative deltas, active normals `Normals`, and field data
 * `TargetNames` (neutral first). Bad files are reported with vtkErrorMacro and give an
 * empty output.
 *
 * @sa vtkMorphNodeFilter vtkGLTFReader
 */

#ifndef vtkMorphTargetReader_h
#define vtkMorphTargetReader_h

#include "vtkMorphNodeModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // For std::string
#include <vector> // For std::vector

class VTKMORPHNODE_EXPORT vtkMorphTargetReader : public vtkPolyDataAlgorithm
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
   * glTF: the mesh to read, by name (wins when set) or index (default 0), and the
   * primitive of that mesh (default 0).
   */
  vtkSetStdStringFromCharMacro(MeshName);
  vtkGetCharFromStdStringMacro(MeshName);
  vtkSetClampMacro(MeshIndex, int, 0, VTK_INT_MAX);
  vtkGetMacro(MeshIndex, int);
  vtkSetClampMacro(PrimitiveIndex, int, 0, VTK_INT_MAX);
  vtkGetMacro(PrimitiveIndex, int);
  ///@}

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
   * Scale applied to positions (e.g. 0.01 to read an OBJ set in centimetres as metres).
   * Default 1.
   */
  vtkSetMacro(Scale, double);
  vtkGetMacro(Scale, double);
  ///@}

  /// Normals policy.
  enum NormalsModes
  {
    NORMALS_FROM_FILE = 0,   ///< never compute
    NORMALS_WHEN_MISSING = 1, ///< compute all when the base or any target lacks them (default)
    NORMALS_ALWAYS = 2       ///< always compute from the geometry
  };
  vtkSetClampMacro(NormalsMode, int, NORMALS_FROM_FILE, NORMALS_ALWAYS);
  vtkGetMacro(NormalsMode, int);

  ///@{
  /**
   * Targets read by the last update, neutral first.
   */
  int GetNumberOfTargets() { return static_cast<int>(this->TargetNames.size()); }
  const char* GetTargetName(int index);
  ///@}

  /**
   * Meshes of the last glTF file read (names; unnamed ones as `mesh<i>`).
   */
  int GetNumberOfMeshes() { return static_cast<int>(this->MeshNames.size()); }
  const char* GetMeshNameByIndex(int index);

protected:
  vtkMorphTargetReader();
  ~vtkMorphTargetReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  std::string MeshName;
  std::string NeutralFileName;
  int MeshIndex = 0;
  int PrimitiveIndex = 0;
  double Scale = 1.0;
  int NormalsMode = NORMALS_WHEN_MISSING;

private:
  vtkMorphTargetReader(const vtkMorphTargetReader&) = delete;
  void operator=(const vtkMorphTargetReader&) = delete;

  void ReadGLTF(vtkPolyData* output);
  void ReadObjSet(vtkPolyData* output);
  void FinishOutput(vtkPolyData* output);

  std::vector<std::string> TargetNames;
  std::vector<std::string> MeshNames;
};

#endif
