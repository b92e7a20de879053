// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file   vtkMorphTargetArrays.h
 * @brief  The glTF target-array convention in VTK data, and VTK <-> morphnode::MorphMesh
 *         (private to the module).
 *
 * The one place that knows how morph targets are laid out in VTK data, as vtkGLTFReader
 * (ApplyDeformationsToGeometry off) and vtkMorphTargetReader build them:
 *
 * - point arrays `target<k>_position` (and `target<k>_normal`), k = 0, 1, ... without gaps,
 *   3 components, one tuple per point, holding relative deltas (target k + 1 minus the
 *   neutral, whose values are the points and the active normals);
 * - field data `TargetNames`, a string array naming the neutral and then every target.
 *
 * Every VTK class of the module reads and writes targets through these functions, and
 * copies values between VTK arrays and the core with vtkArrayDispatch over
 * vtk::DataArrayValueRange (no per-value virtual calls for the common array types).
 * Functions throw morphnode::InputError for bad input; callers turn that into vtkErrorMacro.
 */

#ifndef vtkMorphTargetArrays_h
#define vtkMorphTargetArrays_h

#include "morph/MorphMesh.h"

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkDataArray;
class vtkDataObject;
class vtkDataSetAttributes;
class vtkFieldData;
class vtkIdList;
class vtkPointData;
class vtkPointSet;
class vtkPoints;
class vtkPolyData;
class vtkStringArray;

namespace vtkMorphTargetArrays
{
/// Field data naming the targets, neutral first.
constexpr const char* TargetNamesArray = "TargetNames";
/// Name of the Position attribute ToMorphMesh builds from the points.
constexpr const char* PointsAttributeName = "Points";

/// What a target array holds.
enum class Kind
{
  Position,
  Normal
};

/// `target<k>_position` / `target<k>_normal`: the deltas of relative target k (0-based,
/// the neutral not counted; MorphMesh target k + 1).
std::string ArrayName(size_t k, Kind kind);
/// True for any name of the form `target<digits>_<anything>`: an array of the convention
/// (vtkGLTFReader also writes `target<k>_tangent`), which is not a plain point array.
bool IsTargetArrayName(const char* name);

/// True if the point data has `target0_position`.
bool HasTargets(vtkPointData* pd);
bool HasTargets(vtkPointSet* input);
/// Number of relative targets: `target0_position` ... `target<n-1>_position`. Throws
/// InputError when one of them is not numeric with 3 components and `numPoints` tuples, or
/// a `target<k>_*` array has k >= n (targets must be numbered without gaps).
size_t CountTargets(vtkPointData* pd, vtkIdType numPoints);
/// `target<k>_position` or `target<k>_normal`, nullptr when absent. Throws InputError when
/// present but not numeric with 3 components and `numPoints` tuples.
vtkDataArray* GetDeltas(vtkPointData* pd, size_t k, Kind kind, vtkIdType numPoints);
/// Removes every `target<k>_*` array.
void RemoveTargetArrays(vtkPointData* pd);

/// The names in field data `TargetNames` (neutral first) when there are any, else
/// morphnode::DefaultTargetNames. Throws InputError when their count is not
/// `numTargets` (neutral included).
std::vector<std::string> GetTargetNames(vtkFieldData* fd, size_t numTargets);
/// The targets a face names, without the neutral: field data `TargetNames` of a data
/// object, or for a composite (a head of parts) the union over its leaves in order of first
/// appearance, as vtkMorphNodeFilter names a head's targets. False (and `targets` empty)
/// when nothing carries `TargetNames`.
bool GetFaceTargetNames(vtkDataObject* face, std::vector<std::string>& targets);
/// The number of targets a face has before it is read, the neutral not counted: for a
/// point set its `target<k>_position` arrays (consecutive from 0; layouts not checked), for
/// a composite (a head of parts) the distinct target names over its point-set leaves (each
/// leaf's GetTargetNames for its CountTargets); leaves that do not read are skipped (their
/// errors come when the face is read). 0 for anything else.
size_t CountFaceTargets(vtkDataObject* face);
/// Throws InputError when two targets share a name.
void CheckUniqueNames(const std::vector<std::string>& names);
/// For a class's SetTargetNames(): `slot` becomes a copy of `names` named `TargetNames`
/// (nullptr clears it). False when both were null, so nothing changed (no Modified()).
bool AssignTargetNames(vtkSmartPointer<vtkStringArray>& slot, vtkStringArray* names);
/// Replaces field data `TargetNames`.
void SetTargetNames(vtkFieldData* fd, const std::vector<std::string>& names);
/// A vtkStringArray named `arrayName` holding the names.
vtkSmartPointer<vtkStringArray> MakeNamesArray(
  const char* arrayName, const std::vector<std::string>& names);

/// All values of a numeric array as T, tuple-major (vtkArrayDispatch).
template <typename T>
std::vector<T> ToVector(vtkDataArray* array);
/// Writes `array`'s GetNumberOfValues() values from `values`, converted to the array's
/// type; integer types are rounded to the nearest (vtkArrayDispatch).
template <typename T>
void CopyToArray(const T* values, vtkDataArray* array);
/// A new array of VTK type `vtkType` (VTK_FLOAT, VTK_DOUBLE, ...) named `name`, holding
/// `numTuples` tuples of `components` from `values`.
template <typename T>
vtkSmartPointer<vtkDataArray> NewArray(
  int vtkType, const char* name, int components, vtkIdType numTuples, const T* values);

/// Adds an attribute to `mesh` from VTK arrays: `neutral` and one array per target (MorphMesh
/// targets 1, 2, ...), holding absolute values or deltas as `relative` says. Stored as float
/// when the neutral array is float, as double otherwise; integer arrays are clamped to
/// their type's range when blended. Throws InputError when an array is missing or its layout
/// differs from the neutral's (components, one tuple per point of the mesh).
void AddAttribute(morphnode::MorphMesh& mesh, const std::string& name,
  morphnode::AttributeRole role, vtkDataArray* neutral, const std::vector<vtkDataArray*>& targets,
  bool relative, double sparseCoverage);

/// Triangles of a poly data's polygons as 3 point ids each. `fan`: polygons of more points
/// are fan-triangulated from their first point; otherwise they are an error. Throws
/// InputError for triangle strips and, without `fan`, for polygons that are not triangles.
std::vector<uint32_t> GetTriangles(vtkPolyData* mesh, bool fan);

struct ReadOptions
{
  /// MorphAttribute storage choice; no effect on values.
  double SparseCoverage = morphnode::MorphMesh::DefaultSparseCoverage;
  /// Read the normals and their deltas (when the normals and every target's
  /// `target<k>_normal` exist).
  bool Normals = true;
  /// Read the polygons as triangles (the input must be a vtkPolyData of triangles).
  bool Triangles = false;
};

/// A mesh read from VTK data, and where its attributes came from.
struct MeshFromVTK
{
  morphnode::MorphMesh Mesh;
  /// The neutral normals the Normal attribute was built from (nullptr when none).
  vtkDataArray* Normals = nullptr;
  /// Names of the input's `target<k>_*` arrays (they have no place in a blended output).
  std::vector<std::string> TargetArrays;
};

/// The convention's targets as a MorphMesh: names from `TargetNames` (neutral first), the
/// Position attribute "Points" from the points and `target<k>_position`, and with
/// options.Normals a Normal attribute (named after the normals array) from the active
/// normals (or an array named Normal/Normals/NORMAL) and `target<k>_normal`. An attribute
/// is stored as float when its neutral array is float, as double otherwise. Throws
/// InputError for no input or no points, target arrays of the wrong layout or with gaps, a
/// `TargetNames` of the wrong length, duplicate target names, and (with options.Triangles)
/// anything but triangles.
MeshFromVTK ToMorphMesh(vtkPointSet* input, const ReadOptions& options);

/// Adds `target<k>_position` for the mesh's Position attribute and `target<k>_normal` for
/// its Normal attribute (the first of each role), arrays of `positionType` / `normalType`
/// (VTK_FLOAT, VTK_DOUBLE, ...; -1: the attribute's own type), replacing arrays of those
/// names.
void AddTargetArrays(
  const morphnode::MorphMesh& mesh, vtkPointData* pd, int positionType = -1, int normalType = -1);

/// `out` allocated like `in` (vtkDataSetAttributes::CopyAllocate), holding the tuples
/// `ids` of `in` in that order, array by array (vtkAbstractArray::GetTuples): a subset's
/// or a level's points (or cells) taking the input's arrays.
void GatherTuples(vtkDataSetAttributes* in, vtkIdList* ids, vtkDataSetAttributes* out);

/// `output` becomes a subset of `input`'s points: the first `numPoints` of `ids` (input point
/// ids), every point array gathered with them (vtkAbstractArray::GetTuples) plus
/// `OriginalPointId` (each point's id in the input), the triangles `triangles` (3 indices
/// into the subset each) and the input's field data. The points are `points` when given
/// (e.g. blended positions), else gathered from the input's in their type. The reduction and
/// level-of-detail filters' output.
void ExtractPointSubset(vtkPolyData* input, const std::vector<uint32_t>& ids, vtkIdType numPoints,
  const std::vector<uint32_t>& triangles, vtkPolyData* output, vtkPoints* points = nullptr);

/// The mesh in the convention: points (the Position attribute's neutral, same type), the
/// triangles, active normals (the Normal attribute, if any), target arrays and
/// `TargetNames`. Other attributes' neutral values become plain point arrays; throws
/// InputError when one of them has a target that moves it (the convention has no place for
/// such deltas) or when the mesh has no Position attribute of 3 components.
vtkSmartPointer<vtkPolyData> ToPolyData(const morphnode::MorphMesh& mesh);
} // namespace vtkMorphTargetArrays

#endif
