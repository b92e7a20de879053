// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file   vtkMorphMeshLevels.h
 * @brief  Mesh levels of detail in VTK data (private to the module): a part's ladder
 *         built from its VTK data, and the level a morphnode::ScalableScene shows of it
 *         as VTK data (docs/lod.md). Used by vtkMorphNodeFilter (MeshLevels) and
 *         vtkMorphLevelOfDetail; the decisions and the blend are the core's.
 *
 * The convention of a shown level (one output part):
 *
 * - points: the shown prefix of the part's one vertex buffer (the ladder's numbering), the
 *   blended and geomorphed positions;
 * - cells: the level's triangles (a part kept whole, see BuildLadder, keeps the input's
 *   cells: its numbering is the input's), with the input's cell data of each triangle
 *   (a reduced triangle is an input triangle with collapsed corners moved:
 *   morphnode::LadderLevel::OriginalTriangleIds);
 * - point data: every array of the input gathered to the shown points (target<k>_* arrays
 *   left out), the morphed ones (normals, ...) blended and geomorphed at the level, and
 *   `OriginalPointId` (vtkIdTypeArray): each point's id in the input part, by which
 *   anything per point of the full mesh (colours, tangents, picks) maps onto the level;
 *   extra point arrays of the caller (the filter's distance arrays) gathered likewise;
 *   skin arrays (vtkMorphSkinArrays) are gathered too, so a reduced skinned part still
 *   skins;
 * - field data: the input's, and `LevelOfDetail` (vtkDoubleArray, one tuple, components
 *   Level, MorphTowards, Alpha, ActiveTargets, Points): the part's shown level, the level
 *   it slides towards in a geomorph (-1: none) and how far, the active targets and the
 *   points the whole scene shows.
 *
 * Functions throw morphnode::InputError for bad input; callers turn that into vtkErrorMacro.
 */

#ifndef vtkMorphMeshLevels_h
#define vtkMorphMeshLevels_h

#include "lod/MorphLadder.h"
#include "lod/ScalableScene.h"
#include "morph/MorphScene.h"

#include "vtkSmartPointer.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

class vtkCellArray;
class vtkCompositeDataSet;
class vtkDataObject;
class vtkMorphNodeOutput;
class vtkCellData;
class vtkDataArray;
class vtkDoubleArray;
class vtkPoints;
class vtkPointData;
class vtkPointSet;
class vtkPolyData;

namespace vtkMorphMeshLevels
{
constexpr const char* OriginalPointIdArray = "OriginalPointId";
constexpr const char* LevelOfDetailArray = "LevelOfDetail";
/// Parts with fewer triangles are kept whole (a one-level ladder): nothing to gain.
constexpr size_t MinimumTriangles = 100;

/// A part's ladder: its model (`model`: the part's targets and attributes, as the morph
/// node's adapter built them; the triangles are read from `part`) and, for a skinned part,
/// its influences, reduced by morphnode::BuildMorphLadder with `settings`. A skinned part's
/// level errors also cover the poses its avatar takes (unless `settings` gives its own
/// SkinPoses): the head turned by 25 degrees, nodded by 15, the eyes turned by 25 (the bones
/// vtkMorphSkinFilter moves). A part that is
/// not a vtkPolyData of triangles only (lines, quads, strips, points), or has fewer than
/// MinimumTriangles, is kept whole: a one-level ladder in the input's numbering. `what`
/// names the part in messages.
std::shared_ptr<const morphnode::MorphLadder> BuildLadder(const morphnode::MorphMesh& model,
  vtkPointSet* part, const morphnode::LadderSettings& settings, const std::string& what);
/// The same with the part's model read from its target arrays (vtkMorphTargetArrays::ToMorphMesh,
/// normals included).
std::shared_ptr<const morphnode::MorphLadder> BuildLadder(
  vtkPointSet* part, const morphnode::LadderSettings& settings, const std::string& what);

/// The levels a scene shows, as VTK data. What depends on a part's level only (its cells and
/// their cell data, the input's arrays gathered to its points, OriginalPointId) is made once
/// per level and shared by every output of that level (so a downstream cache keyed on an
/// array, such as vtkMorphSkinFilter's skin, holds while the level does). Each part's output
/// data set, its points and its morphed arrays are kept across executions and written again
/// in place when no one else holds them (as vtkMorphNodeOutput keeps the filter's own), new
/// ones otherwise; a part the scene did not blend again keeps them untouched.
class Assembler
{
public:
  /// Forgets the levels made (a new scene or new inputs).
  void Reset();
  /// The level the scene's last frame shows of part `part` (whose input is `input`, the
  /// data set its ladder was built from), in the convention above, as the part's kept data
  /// set (a new one when the last is still held elsewhere). `extra`: point arrays over the
  /// input's points made elsewhere (vtkMorphNodeFilter's distance arrays), gathered to the
  /// level's points with the input's own (again only when they are other arrays).
  vtkPolyData* Assemble(const morphnode::ScalableScene& scene, size_t part, vtkPointSet* input,
    const std::vector<vtkDataArray*>& extra = {});
  /// Whether part `part`'s last Assemble gave the data set of the execution before, its
  /// structure and field data kept (only its points and morphed arrays written again).
  bool IsKept(size_t part) const
  {
    return part < this->Previous.size() && this->Previous[part].Kept;
  }
  /// The same, shallow-copied into `output`.
  void Assemble(const morphnode::ScalableScene& scene, size_t part, vtkPointSet* input,
    vtkPolyData* output, const std::vector<vtkDataArray*>& extra = {});

private:
  struct Level
  {
    vtkSmartPointer<vtkPointData> Gathered;
    vtkSmartPointer<vtkCellArray> Polys;     // null: the input's own cells
    vtkSmartPointer<vtkCellData> Cells;      // the input's cell data on Polys (null: the input's)
    std::vector<vtkDataArray*> ExtraSources; // not held: identify what Extras were made of
    std::vector<vtkSmartPointer<vtkDataArray>> Extras;
  };
  void MakeLevel(Level& made, const morphnode::MorphLadder& ladder, int level, vtkPointSet* input);
  std::vector<std::vector<Level>> Levels; // [part][level]
  /// Per part, the kept output: its data set, points, morphed arrays (in the ladder's
  /// attribute order, null for the positions and arrays not output) and LevelOfDetail.
  struct Kept
  {
    vtkSmartPointer<vtkPolyData> Output;
    int Level = -1; // the level Output's structure and gathered arrays are of,
    vtkPointData* GatheredFrom = nullptr;  // made from these (not held)
    std::vector<vtkDataArray*> ExtrasFrom; // (not held)
    bool Kept = false;                     // the last Assemble gave Output again, not restructured
    vtkSmartPointer<vtkPoints> Points;
    std::vector<vtkSmartPointer<vtkDataArray>> Morphed;
    vtkSmartPointer<vtkDoubleArray> LevelOfDetail;
  };
  std::vector<Kept> Previous;
};

/// A morph node's mesh levels (vtkMorphNodeFilter::MeshLevels): the ladders of its parts,
/// built once per model, one morphnode::ScalableScene over them (one level for the whole
/// model, chosen on screen and on time), and each part's shown level as VTK data. The
/// filter decides the weights (mode, optimizer, target level of detail) as without levels;
/// the scene chooses the level and blends it.
class SceneLevels
{
public:
  /// The parts of model `generation` (their models, their data sets and names, in the
  /// scene's order): the ladders are built again and their blend timed when the generation
  /// differs from the last one's.
  void SetParts(const std::vector<const morphnode::MorphMesh*>& models,
    const std::vector<vtkPointSet*>& parts, const std::vector<std::string>& names,
    uint64_t generation);
  /// One execution: the effective weights over the model's targets `names` (neutral
  /// first), passed to the scene by name; `settings` (the controller is made again only
  /// when they change); the pixels per model unit (0: time alone).
  const morphnode::SceneFrame& Update(const std::vector<std::string>& names,
    const std::vector<double>& weights, const morphnode::ControllerSettings& settings,
    double pixelsPerUnit);
  /// Part `part`'s shown level as VTK data (Assembler::Assemble, kept across executions),
  /// with `extra` point arrays over the part's input points gathered to it.
  vtkPolyData* Assemble(size_t part, const std::vector<vtkDataArray*>& extra = {});
  /// Assembler::IsKept.
  bool IsKept(size_t part) const { return this->Output.IsKept(part); }
  const morphnode::ScalableScene& GetScene() const { return this->Scene; }
  bool Empty() const { return this->Inputs.empty(); }
  void Clear();

  /// vtkMorphNodeFilter's MeshLevels: the level of the morph node's `scene` (model
  /// `generation`, target names `targetNames`, its effective weights) chosen with
  /// `settings` and `pixelsPerUnit`, and every part of `parts` shown at it in `output`: a
  /// composite in `compositeInput`'s structure, or the one vtkPolyData; with the distance
  /// maps gathered to the level's points when `distances`, and the morph node's field data.
  /// Returns the level. Throws morphnode::InputError for an output that is neither.
  int Show(const morphnode::MorphScene& scene, uint64_t generation,
    const std::vector<std::string>& targetNames, const morphnode::ControllerSettings& settings,
    double pixelsPerUnit, bool distances, vtkMorphNodeOutput& parts,
    vtkCompositeDataSet* compositeInput, vtkDataObject* output);

private:
  uint64_t Generation = 0;
  std::vector<vtkPointSet*> Inputs; // not held: the filter's inputs of this generation
  morphnode::ScalableScene Scene;
  bool Configured = false;
  std::vector<double> Weights; // scratch, over the scene's targets
  /// The filter's target names the map below was made for, and per scene target (neutral
  /// first) the index of its name in them (0: none).
  std::vector<std::string> MappedNames;
  std::vector<size_t> NameMap;
  Assembler Output;
};
} // namespace vtkMorphMeshLevels

#endif
