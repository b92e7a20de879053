// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file   vtkMorphSkinArrays.h
 * @brief  The skin convention in VTK data (private to the module): what a skinned part
 *         carries so that it can be re-skinned when its joints move (docs/avatars.md).
 *
 * A skinned part (vtkMorphTargetReader's, of a glTF skin) is shown in its rest pose: its
 * points, normals and `target<k>_*` deltas (vtkMorphTargetArrays.h) are skinned at the pose
 * in `SkeletonRest`, so that a morph node blends them as any other part's. It also carries:
 *
 * - point data `SkinJoints` (vtkUnsignedShortArray) and `SkinWeights` (vtkFloatArray), the
 *   same number of components (4 per glTF JOINTS_n/WEIGHTS_n set): joint indices into the
 *   skin's joints and their weights, renormalized;
 * - field data `SkinJointIndices` (vtkIntArray, one per joint of the skin: its index in the
 *   skeleton) and `SkinInverseBind` (vtkDoubleArray, 16 components per joint of the skin:
 *   the inverse bind matrix, column-major);
 * - field data `SkeletonNames` (vtkStringArray), `SkeletonParents` (vtkIntArray, -1 for a
 *   root) and `SkeletonRest` (vtkDoubleArray, 16 components per joint: the local transform
 *   the part is shown at, column-major): every node of the scene;
 * - for a VRM avatar (gltf/GltfVrm.h), field data `HumanoidBones` (vtkStringArray of
 *   "bone=node name", VRM's humanBones) and `LookAtRangeMaps` (vtkDoubleArray of 8: inner,
 *   outer, down, up input maxima and output scales, when its look-at turns bones).
 *
 * A morph node's output of a blended skinned part also carries field data
 * `MorphedPointRanges` (vtkIdTypeArray, 2 components: [first, last) runs of the points some
 * target moves; a new array per model, never modified): outside them the points and
 * normals are the neutral's at every frame, so vtkMorphSkinFilter re-skins only these when
 * no joint of theirs moved. With it `MorphedArraysTime` (vtkIdTypeArray of 2: the
 * modification times of the points and normals arrays the morph node wrote): the ranges hold
 * only for those arrays (not after a filter that moved the points in between).
 *
 * vtkMorphSkinFilter's "pose only" output (SkinPoints off) of a skinned part keeps the points
 * (rest pose, morphed) and adds field data `SkinJointDeltas` (vtkFloatArray, 12 components,
 * one tuple per joint of the skin, in SkinJointIndices' order): the 3x4 of
 * J_k(pose) J_k(rest)^-1 by rows (row 0, row 1, row 2, each x y z translation), the products
 * morphnode::RestSkin forms. A renderer skins each point as linear blend skinning does:
 * M = sum_k w_k Delta_k over the point's first four SkinJoints/SkinWeights, p' = M p, the
 * normal by M's cofactor, renormalized. It holds only where the joints of every point share
 * one rest matrix (RestSkin::AllSharedRest) and a point has at most four influences; the
 * filter re-skins other parts itself. vtkMorphSkinMapper draws it. (This output keeps the
 * morph's MorphedPointRanges: its points are the input's.)
 *
 * Functions throw morphnode::InputError for bad input; callers turn that into vtkErrorMacro.
 */

#ifndef vtkMorphSkinArrays_h
#define vtkMorphSkinArrays_h

#include "gltf/GltfScene.h"
#include "gltf/GltfVrm.h"
#include "skin/AvatarBones.h"
#include "skin/Skeleton.h"
#include "skin/Skinning.h"

#include <map>
#include <string>
#include <vector>

class vtkDataSet;
class vtkPolyData;

namespace vtkMorphSkinArrays
{
constexpr const char* JointsArray = "SkinJoints";
constexpr const char* WeightsArray = "SkinWeights";
constexpr const char* JointIndicesArray = "SkinJointIndices";
constexpr const char* InverseBindArray = "SkinInverseBind";
constexpr const char* SkeletonNamesArray = "SkeletonNames";
constexpr const char* SkeletonParentsArray = "SkeletonParents";
constexpr const char* SkeletonRestArray = "SkeletonRest";
constexpr const char* HumanoidBonesArray = "HumanoidBones";
constexpr const char* LookAtRangeMapsArray = "LookAtRangeMaps";
constexpr const char* MorphedRangesArray = "MorphedPointRanges";
constexpr const char* MorphedTimeArray = "MorphedArraysTime";
constexpr const char* JointDeltasArray = "SkinJointDeltas";

/// True when the data set carries `SkinWeights`.
bool IsSkinned(vtkDataSet* data);

/// Adds the convention's arrays for a skinned part (part.Skin >= 0) shown at the node local
/// transforms `locals` (one per node of the scene); `scale` as the reader's Scale (applied
/// to translations, so that the skin matches the scaled points).
void AddSkin(vtkPolyData* poly, const morphnode::GltfScene& scene, const morphnode::GltfPart& part,
  const std::vector<morphnode::GltfMatrix>& locals, double scale);

/// Adds what a VRM avatar says of its bones (HumanoidBones, LookAtRangeMaps) to a skinned
/// part; nothing for a file that is no VRM.
void AddVrm(vtkPolyData* poly, const morphnode::GltfVrm& vrm);

/// A skinned part's skeleton (validated), skin joints and influences.
struct Skin
{
  /// VRM's humanoid map (bone -> node name) and look-at range maps, when the part has them.
  std::map<std::string, std::string> Humanoid;
  morphnode::EyeRangeMaps RangeMaps;
  morphnode::Skeleton Bones;
  morphnode::SkinJoints Joints;
  morphnode::SkinInfluences Influences;
  /// The skin's joint matrices at the pose the part is shown at.
  std::vector<glm::dmat4> RestMatrices() const;
};

/// Reads the convention back, checked (sizes, indices, finite values). `what` names the part.
Skin GetSkin(vtkDataSet* data, const std::string& what);
} // namespace vtkMorphSkinArrays

#endif
