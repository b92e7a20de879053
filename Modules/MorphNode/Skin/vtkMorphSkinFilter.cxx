// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphSkinFilter.h"

#include "vtkMorphPartData.h"
#include "vtkMorphSkinArrays.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "skin/AvatarBones.h"
#include "skin/Skinning.h"

#include "vtkCellData.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <map>
#include <memory>

vtkStandardNewMacro(vtkMorphSkinFilter);

namespace
{
/// Re-skins what may have changed since the previous frame (RestSkin::ApplyChanged) into
/// the kept output arrays: in parallel only when there is enough work to share.
template <typename T>
vtkIdType Reskin(const morphnode::RestSkin& skin, const T* points, const T* normals, T* outPoints,
  T* outNormals, const std::vector<size_t>& changedInput, size_t n)
{
  constexpr size_t Grain = 16384;
  if (n <= Grain || vtkSMPTools::GetEstimatedNumberOfThreads() < 2)
  {
    return static_cast<vtkIdType>(
      skin.ApplyChanged<T>(points, normals, outPoints, outNormals, changedInput, 0, n));
  }
  std::atomic<vtkIdType> count(0);
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), static_cast<vtkIdType>(Grain),
    [&](vtkIdType begin, vtkIdType end)
    {
      count += static_cast<vtkIdType>(skin.ApplyChanged<T>(points, normals, outPoints, outNormals,
        changedInput, static_cast<size_t>(begin), static_cast<size_t>(end)));
    });
  return count;
}

template <typename ArrayT>
auto* Pointer(vtkDataArray* a)
{
  return a ? ArrayT::FastDownCast(a)->GetPointer(0) : nullptr;
}

/// Grows `bounds` (xmin, xmax, ..., empty when min > max) to take [lo, hi] on each axis
/// (a point: lo = hi; axes of other bounds that are empty add nothing).
void AddToBounds(double bounds[6], const double lo[3], const double hi[3])
{
  for (int k = 0; k < 3; ++k)
  {
    if (lo[k] <= hi[k])
    {
      const bool empty = bounds[2 * k] > bounds[2 * k + 1];
      bounds[2 * k] = empty ? lo[k] : std::min(bounds[2 * k], lo[k]);
      bounds[2 * k + 1] = empty ? hi[k] : std::max(bounds[2 * k + 1], hi[k]);
    }
  }
}

vtkSmartPointer<vtkDataArray> NewLike(vtkDataArray* in)
{
  vtkSmartPointer<vtkDataArray> out;
  out.TakeReference(in->NewInstance());
  out->SetName(in->GetName());
  out->SetNumberOfComponents(3);
  out->SetNumberOfTuples(in->GetNumberOfTuples());
  return out;
}
} // namespace

/// One skeleton posed once per execution, shared by the parts bound to it (an avatar's
/// parts each carry the same skeleton).
struct PoseSlot
{
  morphnode::Skeleton Bones;
  std::map<std::string, std::string> Humanoid;
  morphnode::EyeRangeMaps RangeMaps;
  unsigned long Execution = 0;   ///< of World
  std::vector<glm::dmat4> World; ///< posed
  /// The distinct skins of its parts (an avatar's parts usually share one) and their joint
  /// matrices at World, formed once per execution.
  struct SkinMatrices
  {
    morphnode::SkinJoints Joints;
    unsigned long Execution = 0;
    std::vector<glm::dmat4> Matrices;
    /// Pose only: SkinJointDeltas at World, formed once per execution and shared by the
    /// parts of this skin (the same joints, inverse binds and skeleton rest: the same
    /// products).
    unsigned long DeltasExecution = 0;
    vtkSmartPointer<vtkFloatArray> Deltas;
  };
  std::vector<SkinMatrices> Skins;

  /// The index in Skins of `joints` (added when new).
  size_t FindSkin(const morphnode::SkinJoints& joints)
  {
    for (size_t k = 0; k < this->Skins.size(); ++k)
    {
      if (this->Skins[k].Joints.Joints == joints.Joints &&
        this->Skins[k].Joints.InverseBind == joints.InverseBind)
      {
        return k;
      }
    }
    this->Skins.push_back(SkinMatrices{ joints, 0, {}, 0, nullptr });
    return this->Skins.size() - 1;
  }
  /// The joint matrices of skin k at this execution's World.
  const std::vector<glm::dmat4>& Matrices(size_t k)
  {
    SkinMatrices& skin = this->Skins[k];
    if (skin.Execution != this->Execution)
    {
      skin.Matrices = skin.Joints.Matrices(this->World);
      skin.Execution = this->Execution;
    }
    return skin.Matrices;
  }

  /// The same skeleton (joints as stored, exactly), humanoid map and range maps.
  bool Same(const vtkMorphSkinArrays::Skin& skin) const
  {
    const morphnode::EyeRangeMaps& a = this->RangeMaps;
    const morphnode::EyeRangeMaps& b = skin.RangeMaps;
    if (this->Humanoid != skin.Humanoid || a.Enabled != b.Enabled || a.InnerMax != b.InnerMax ||
      a.InnerScale != b.InnerScale || a.OuterMax != b.OuterMax || a.OuterScale != b.OuterScale ||
      a.DownMax != b.DownMax || a.DownScale != b.DownScale || a.UpMax != b.UpMax ||
      a.UpScale != b.UpScale || this->Bones.GetNumberOfJoints() != skin.Bones.GetNumberOfJoints())
    {
      return false;
    }
    for (size_t j = 0; j < this->Bones.GetNumberOfJoints(); ++j)
    {
      const morphnode::Joint& p = this->Bones.GetJoint(j);
      const morphnode::Joint& q = skin.Bones.GetJoint(j);
      if (p.Name != q.Name || p.Parent != q.Parent)
      {
        return false;
      }
    }
    return this->Bones.RestLocals() == skin.Bones.RestLocals();
  }
};

class vtkMorphSkinFilter::vtkInternals
{
public:
  /// Per skinned leaf (by its SkinWeights array and that array's MTime): the skin read once.
  struct Entry
  {
    vtkMTimeType Time = 0;
    vtkMorphSkinArrays::Skin Skin;
    morphnode::RestSkin Rest;
    std::vector<glm::dmat4> RestMatrices;
    morphnode::AvatarBoneRoles Roles; ///< found once per skin
    std::shared_ptr<PoseSlot> Slot;   ///< its skeleton's pose
    size_t SlotSkin = 0;              ///< its skin in Slot->Skins
    /// The last frame's output (written again in place only where points changed, and only
    /// when nothing but this entry holds them: a snapshot kept downstream never changes).
    vtkSmartPointer<vtkDataArray> OutPoints, OutNormals;
    vtkSmartPointer<vtkPointSet> OutLeaf;
    /// The input leaf OutLeaf was last filled from (compared, never dereferenced: it may
    /// be gone).
    const vtkPointSet* OutLeafFrom = nullptr;
    vtkSmartPointer<vtkPoints> OutPointsObject;
    /// The last frame's input, to tell what can have changed: its arrays and the morph
    /// node's MorphedPointRanges (by address and modification time; never held, so that
    /// the morph node may write them in place).
    struct Seen
    {
      const void* Array = nullptr;
      vtkMTimeType Time = 0;
      bool operator==(const Seen& o) const
      {
        return this->Array == o.Array && this->Time == o.Time;
      }
    };
    Seen LastPoints, LastNormals, LastRanges;
    std::vector<size_t> ChangedInput; ///< this frame's
    bool Valid = false;               ///< the kept arrays hold the last frame
    unsigned long Execution = 0;      ///< the last execution that used the entry
    std::string Described;            ///< the roles as GetBones says them, for DescribedKey
    int DescribedKey = -1;
    bool HeadKnown = false;
    bool EyePart = false; ///< every point's largest weight on an eye joint or below it
    double HeadBounds[6] = { 1, -1, 1, -1, 1, -1 }; ///< empty when min > max
  };
  std::map<vtkDataArray*, Entry> Cache;
  unsigned long Execution = 0;
  /// Output leaves of this execution no entry holds any more (KeptLeaf).
  std::vector<vtkSmartPointer<vtkPointSet>> Replaced;
  /// The input's jawOpen target (JAW_AUTO), known for these names arrays (address, MTime).
  bool JawKnown = false;
  bool JawTarget = false;
  std::vector<std::pair<const void*, vtkMTimeType>> JawKey;

  /// The pose: the filter's properties, the pose table's first row (port 1) where it has
  /// a column.
  static morphnode::AvatarBonePose Angles(vtkMorphSkinFilter* self, vtkInformationVector* track)
  {
    morphnode::AvatarBonePose angles;
    angles.HeadYaw = self->HeadYaw;
    angles.HeadPitch = self->HeadPitch;
    angles.HeadRoll = self->HeadRoll;
    angles.EyeYaw = self->EyeYaw;
    angles.EyePitch = self->EyePitch;
    angles.JawOpen = self->JawOpen;
    angles.MaxJawAngle = self->MaxJawAngle;
    vtkMorphTrackFilter::ReadTrackRow(track,
      { { "HeadYaw", &angles.HeadYaw }, { "HeadPitch", &angles.HeadPitch },
        { "HeadRoll", &angles.HeadRoll }, { "EyeYaw", &angles.EyeYaw },
        { "EyePitch", &angles.EyePitch }, { "jawOpen", &angles.JawOpen } },
      "the pose table", false);
    if (!self->TurnHead)
    {
      angles.HeadYaw = angles.HeadPitch = angles.HeadRoll = 0.0;
    }
    angles.Vergence = self->Vergence;
    angles.NeckShare = self->NeckShare;
    angles.Limits.MaxYaw = self->MaxEyeYaw;
    angles.Limits.MaxUp = self->MaxEyeUp;
    angles.Limits.MaxDown = self->MaxEyeDown;
    angles.RelaxArms = self->RelaxArms;
    angles.ArmAngle = self->ArmAngle;
    return angles;
  }

  /// Whether the jaw joint may turn (TurnJaw; JAW_AUTO: when no part of `input` has a
  /// jawOpen target), decided once per execution, and asked only for a skeleton with a jaw
  /// joint: the walk over the parts' target names cost a tenth of posing an avatar without.
  bool JawAllowed(vtkMorphSkinFilter* self, vtkDataObject* input)
  {
    if (this->JawAllowedExecution != this->Execution)
    {
      this->JawAllowedValue =
        self->TurnJaw == JAW_ON || (self->TurnJaw == JAW_AUTO && !this->HasJawTarget(input));
      this->JawAllowedExecution = this->Execution;
    }
    return this->JawAllowedValue;
  }
  unsigned long JawAllowedExecution = 0;
  bool JawAllowedValue = false;

  /// Whether a part of the input has a jawOpen target (the mouth opened by it, not by the
  /// jaw joint: JAW_AUTO); decided again only when the leaves' target names arrays change
  /// (the morph node passes the model's one array on every frame).
  bool HasJawTarget(vtkDataObject* input)
  {
    std::vector<std::pair<const void*, vtkMTimeType>> key;
    auto note = [&key](vtkDataObject* leaf)
    {
      vtkAbstractArray* names = leaf && leaf->GetFieldData()
        ? leaf->GetFieldData()->GetAbstractArray(vtkMorphTargetArrays::TargetNamesArray)
        : nullptr;
      key.emplace_back(names, names ? names->GetMTime() : 0);
    };
    if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
    {
      for (vtkDataObject* leaf :
        vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
      {
        note(leaf);
      }
    }
    else
    {
      note(input);
    }
    if (!this->JawKnown || key != this->JawKey)
    {
      std::vector<std::string> names;
      vtkMorphTargetArrays::GetFaceTargetNames(input, names);
      this->JawTarget = morphnode::NamesJawOpenTarget(names);
      this->JawKey = std::move(key);
      this->JawKnown = true;
    }
    return this->JawTarget;
  }

  Entry& Get(vtkPointSet* leaf, const std::string& what)
  {
    vtkDataArray* weights = leaf->GetPointData()->GetArray(vtkMorphSkinArrays::WeightsArray);
    auto it = this->Cache.find(weights);
    if (it != this->Cache.end() && it->second.Time == weights->GetMTime())
    {
      return it->second;
    }
    if (this->Cache.size() > 256)
    {
      this->Cache.clear(); // parts of earlier inputs
    }
    Entry entry;
    entry.Time = weights->GetMTime();
    entry.Skin = vtkMorphSkinArrays::GetSkin(leaf, what);
    entry.RestMatrices = entry.Skin.RestMatrices();
    entry.Roles = morphnode::FindAvatarBones(entry.Skin.Bones, entry.Skin.Humanoid);
    entry.EyePart = morphnode::TurnedByEyeJoints(
      entry.Skin.Influences, entry.Skin.Joints.Joints, entry.Skin.Bones, entry.Roles);
    entry.Rest = morphnode::RestSkin(entry.Skin.Influences, entry.RestMatrices, what);
    for (const auto& [array, other] : this->Cache)
    {
      if (other.Slot && other.Slot->Same(entry.Skin))
      {
        entry.Slot = other.Slot;
        break;
      }
    }
    if (!entry.Slot)
    {
      entry.Slot = std::make_shared<PoseSlot>();
      entry.Slot->Bones = entry.Skin.Bones;
      entry.Slot->Humanoid = entry.Skin.Humanoid;
      entry.Slot->RangeMaps = entry.Skin.RangeMaps;
    }
    entry.SlotSkin = entry.Slot->FindSkin(entry.Skin.Joints);
    return this->Cache[weights] = std::move(entry);
  }

  /// The leaf posed only (SkinPoints off): a new data set sharing everything with the input
  /// (points, normals, arrays), whose field data adds SkinJointDeltas (the skin's per-joint
  /// products of this pose) and SkinPose. No per-point work.
  vtkPointSet* PoseOnly(vtkMorphSkinFilter* self, Entry& entry, vtkPointSet* leaf,
    const std::string& what, PoseSlot& slot, const morphnode::AvatarBonePose& angles,
    const morphnode::AvatarBoneRoles& roles, bool inPlace)
  {
    const size_t n = static_cast<size_t>(leaf->GetNumberOfPoints());
    if (entry.Rest.GetNumberOfPoints() != n)
    {
      throw morphnode::InputError(what + ": the skin has " +
        std::to_string(entry.Rest.GetNumberOfPoints()) + " points, the part " + std::to_string(n));
    }
    PoseSlot::SkinMatrices& skin = slot.Skins[entry.SlotSkin];
    if (skin.DeltasExecution != this->Execution)
    {
      // Once per skin and execution: the products of the first part's RestSkin (every part
      // of this skin has the same rest matrices). A new array: the last frame's may still be
      // drawn or held downstream.
      entry.Rest.SetPose(slot.Matrices(entry.SlotSkin));
      skin.Deltas = vtkSmartPointer<vtkFloatArray>::New();
      skin.Deltas->SetName(vtkMorphSkinArrays::JointDeltasArray);
      skin.Deltas->SetNumberOfComponents(12);
      // The core's products are column-major 3x4; the convention's are the three rows (what
      // a shader takes as three vec4).
      const std::vector<float>& deltas = entry.Rest.GetDeltas();
      const size_t joints = entry.Rest.GetNumberOfJoints();
      skin.Deltas->SetNumberOfTuples(static_cast<vtkIdType>(joints));
      float* d = skin.Deltas->GetPointer(0);
      for (size_t k = 0; k < joints; ++k)
      {
        for (size_t r = 0; r < 3; ++r)
        {
          for (size_t c = 0; c < 4; ++c)
          {
            d[12 * k + 4 * r + c] = deltas[12 * k + 3 * c + r];
          }
        }
      }
      skin.DeltasExecution = this->Execution;
    }
    vtkPointSet* out = inPlace ? leaf : this->KeptLeaf(entry, leaf);
    entry.Execution = this->Execution;
    entry.OutPointsObject = nullptr; // the CPU path's kept arrays no longer hold a frame
    // The points are the input's: the morph's ranges (MorphedPointRanges) still hold.
    this->SetField(out, angles, roles, false);
    out->GetFieldData()->AddArray(skin.Deltas);
    ++self->NumberOfPosedOnlyParts;
    return out;
  }

  /// True when nothing but this filter holds `o`.
  static bool Free(vtkObjectBase* o) { return o && o->GetReferenceCount() == 1; }

  /// The entry's output leaf of the last frame (with its field data and points object),
  /// filled again with `leaf` (CopyLeaf) when nothing else holds it (the output composite
  /// let go of it), else a new one, and its kept points object let go.
  vtkPointSet* KeptLeaf(Entry& entry, vtkPointSet* leaf)
  {
    bool sameLeaf = entry.OutLeafFrom == leaf;
    if (!Free(entry.OutLeaf) || !entry.OutLeaf->IsA(leaf->GetClassName()) ||
      entry.Execution == this->Execution)
    {
      if (entry.OutLeaf && entry.Execution == this->Execution)
      {
        // Handed over for another leaf this execution: held until it is placed.
        this->Replaced.push_back(entry.OutLeaf);
      }
      entry.OutLeaf.TakeReference(leaf->NewInstance());
      entry.OutPointsObject = nullptr;
      sameLeaf = false;
    }
    CopyLeaf(entry.OutLeaf, leaf, sameLeaf);
    entry.OutLeafFrom = leaf;
    return entry.OutLeaf;
  }

  /// out->ShallowCopy(leaf), into field data only `out` holds: a shallow copy fills the data
  /// set's own field data object with the input's arrays, and SetField adds to it. When
  /// `out` is a polygonal leaf last filled from `leaf` itself (the morph node's kept output
  /// leaf, frame after frame) and shares its cells, only the points and attribute arrays are
  /// handed over: a full ShallowCopy (information keys, cells, links, garbage-collector
  /// checks) of the avatar's seven leaves cost more than posing them.
  static void CopyLeaf(vtkPointSet* out, vtkPointSet* leaf, bool sameLeaf)
  {
    if (out->GetFieldData() && out->GetFieldData()->GetReferenceCount() != 1)
    {
      out->SetFieldData(vtkSmartPointer<vtkFieldData>::New());
    }
    auto* outPolys = vtkPolyData::SafeDownCast(out);
    auto* inPolys = vtkPolyData::SafeDownCast(leaf);
    if (sameLeaf && outPolys && inPolys && out->GetFieldData() &&
      outPolys->GetVerts() == inPolys->GetVerts() && outPolys->GetLines() == inPolys->GetLines() &&
      outPolys->GetPolys() == inPolys->GetPolys() && outPolys->GetStrips() == inPolys->GetStrips())
    {
      if (out->GetPoints() != leaf->GetPoints())
      {
        out->SetPoints(leaf->GetPoints());
      }
      PassArrays(out->GetPointData(), leaf->GetPointData());
      PassArrays(out->GetCellData(), leaf->GetCellData());
      out->GetFieldData()->ShallowCopy(leaf->GetFieldData());
      out->Modified();
      return;
    }
    out->ShallowCopy(leaf);
    if (!out->GetFieldData())
    {
      out->SetFieldData(vtkSmartPointer<vtkFieldData>::New());
    }
  }

  /// `out` takes `in`'s arrays again: with the same names in the same order and the same
  /// attribute choices (the morph node's arrays of the frame in place of the last frame's),
  /// only the arrays replaced since, by name (a part has three or four); else a shallow copy.
  static void PassArrays(vtkDataSetAttributes* out, vtkDataSetAttributes* in)
  {
    const int n = in->GetNumberOfArrays();
    int ia[vtkDataSetAttributes::NUM_ATTRIBUTES], ib[vtkDataSetAttributes::NUM_ATTRIBUTES];
    in->GetAttributeIndices(ia);
    out->GetAttributeIndices(ib);
    bool same = out->GetNumberOfArrays() == n && std::equal(std::begin(ia), std::end(ia), ib);
    std::vector<vtkAbstractArray*> replaced;
    for (int i = 0; same && i < n; ++i)
    {
      vtkAbstractArray* a = in->GetAbstractArray(i);
      vtkAbstractArray* b = out->GetAbstractArray(i);
      if (a != b)
      {
        same = a && b && a->GetName() && b->GetName() && std::string(a->GetName()) == b->GetName();
        replaced.push_back(a);
      }
    }
    if (!same)
    {
      out->ShallowCopy(in);
      return;
    }
    for (vtkAbstractArray* a : replaced)
    {
      out->AddArray(a); // in place of the array of its name, its attribute choice kept
    }
  }

  /// The output's field data (the input's arrays, CopyLeaf) with SkinPose, without the
  /// morph's ranges when the points moved (they describe the input's arrays).
  void SetField(vtkPointSet* out, const morphnode::AvatarBonePose& angles,
    const morphnode::AvatarBoneRoles& roles, bool removeRanges = true)
  {
    vtkFieldData* field = out->GetFieldData();
    if (removeRanges)
    {
      field->RemoveArray(vtkMorphSkinArrays::MorphedRangesArray);
      field->RemoveArray(vtkMorphSkinArrays::MorphedTimeArray);
    }
    // One SkinPose array per execution (and jaw role), shared by the parts: the angles are
    // the execution's.
    const size_t jaw = roles.Jaw >= 0 ? 1 : 0;
    if (this->PoseExecution[jaw] != this->Execution)
    {
      vtkNew<vtkDoubleArray> pose;
      pose->SetName("SkinPose");
      pose->SetNumberOfValues(6);
      vtkIdType k = 0;
      for (double v : { angles.HeadYaw, angles.HeadPitch, angles.HeadRoll, angles.EyeYaw,
             angles.EyePitch, jaw ? angles.JawOpen : 0.0 })
      {
        pose->SetValue(k++, v);
      }
      this->Pose[jaw] = pose;
      this->PoseExecution[jaw] = this->Execution;
    }
    field->AddArray(this->Pose[jaw]);
  }
  vtkSmartPointer<vtkDoubleArray> Pose[2]; ///< SkinPose without and with the jaw joint
  unsigned long PoseExecution[2] = { 0, 0 };

  /// The leaf re-skinned at the pose `angles` asks (a new data set sharing all but points and
  /// normals; `inPlace`: the leaf itself, given new points and normals), nullptr when it is
  /// not skinned or stays at rest; updates the filter's report (skinned parts, eye and head
  /// bones, head bounds, bones).
  vtkPointSet* Repose(vtkMorphSkinFilter* self, vtkPointSet* leaf, const std::string& what,
    const morphnode::AvatarBonePose& angles, vtkDataObject* input, const std::string& partName,
    bool inPlace)
  {
    if (!vtkMorphSkinArrays::IsSkinned(leaf))
    {
      return nullptr;
    }
    vtkInternals::Entry& entry = this->Get(leaf, what);
    morphnode::AvatarBoneRoles roles = entry.Roles;
    self->HasEyeBones = self->HasEyeBones || roles.HasEyes();
    if (entry.EyePart)
    {
      const std::string name = vtkMorphPartData::GetPartName(leaf->GetFieldData(), partName);
      if (!name.empty() &&
        std::find(self->EyeParts.begin(), self->EyeParts.end(), name) == self->EyeParts.end())
      {
        self->EyeParts.push_back(name);
      }
    }
    self->HasHeadBones = self->HasHeadBones || roles.Head >= 0;
    if (!entry.HeadKnown && roles.Head >= 0)
    {
      // The points whose largest weight is on the head or below it, at rest.
      for (size_t i : morphnode::PointsUnderJoint(
             entry.Skin.Bones, entry.Skin.Joints, entry.Skin.Influences, roles.Head))
      {
        if (static_cast<vtkIdType>(i) < leaf->GetNumberOfPoints())
        {
          const double* q = leaf->GetPoint(static_cast<vtkIdType>(i));
          AddToBounds(entry.HeadBounds, q, q);
        }
      }
      entry.HeadKnown = true;
    }
    if (entry.HeadKnown)
    {
      const double* b = entry.HeadBounds;
      const double lo[3] = { b[0], b[2], b[4] }, hi[3] = { b[1], b[3], b[5] };
      AddToBounds(self->HeadBounds, lo, hi);
    }
    if (!self->TurnEyes)
    {
      roles.LeftEye = roles.RightEye = -1;
    }
    if (roles.Jaw >= 0 && !this->JawAllowed(self, input))
    {
      roles.Jaw = -1;
    }
    self->JawByBone = self->JawByBone || roles.Jaw >= 0;
    if (self->Bones.empty())
    {
      // Described once per skin and choice of eyes and jaw.
      const int key = (self->TurnEyes ? 1 : 0) + (roles.Jaw >= 0 ? 2 : 0);
      if (entry.DescribedKey != key)
      {
        entry.Described = roles.Describe(entry.Skin.Bones);
        entry.DescribedKey = key;
      }
      self->Bones = entry.Described;
    }
    PoseSlot& slot = *entry.Slot;
    if (slot.Execution != this->Execution)
    {
      // Once per skeleton and execution (the roles and angles are the same for its parts).
      morphnode::SkeletonPose pose(slot.Bones);
      morphnode::AvatarBonePose posed = angles;
      posed.RangeMaps = slot.RangeMaps; // a VRM's look-at (vtkMorphSkinArrays.h)
      morphnode::PoseAvatarBones(pose, roles, posed);
      slot.World = pose.World();
      slot.Execution = this->Execution;
    }
    ++self->NumberOfSkinnedParts;
    const bool wasValid = entry.Valid;
    entry.Valid = false; // the pose moves on: the kept arrays hold this frame only when written
    if (!self->SkinPoints)
    {
      // Pose only where a renderer can skin: one rest matrix per point's joints (the deltas
      // suffice) and one set of four influences; else re-skinned here as with SkinPoints.
      if (entry.Rest.AllSharedRest() && entry.Skin.Influences.PerPoint == 4)
      {
        return this->PoseOnly(self, entry, leaf, what, slot, angles, roles, inPlace);
      }
      std::string name = vtkMorphPartData::GetPartName(leaf->GetFieldData(), partName);
      name = name.empty() ? what : name;
      if (std::find(self->CPUSkinnedParts.begin(), self->CPUSkinnedParts.end(), name) ==
        self->CPUSkinnedParts.end())
      {
        self->CPUSkinnedParts.push_back(name);
      }
    }
    if (!entry.Rest.SetPose(slot.Matrices(entry.SlotSkin)))
    {
      if (inPlace)
      {
        // At rest, as the input: what an earlier frame's pose left is not this frame's.
        leaf->GetFieldData()->RemoveArray("SkinPose");
        leaf->GetFieldData()->RemoveArray(vtkMorphSkinArrays::JointDeltasArray);
      }
      return nullptr; // at rest
    }
    vtkPointSet* out = inPlace ? leaf : this->KeptLeaf(entry, leaf);
    if (inPlace)
    {
      out->GetFieldData()->RemoveArray(vtkMorphSkinArrays::JointDeltasArray); // posed only before
    }
    vtkDataArray* points = leaf->GetPoints()->GetData();
    vtkDataArray* normals = leaf->GetPointData()->GetNormals();
    if (normals &&
      (normals->GetNumberOfComponents() != 3 || normals->GetDataType() != points->GetDataType()))
    {
      normals = nullptr;
    }
    const size_t n = static_cast<size_t>(leaf->GetNumberOfPoints());
    if (entry.Rest.GetNumberOfPoints() != n)
    {
      throw morphnode::InputError(what + ": the skin has " +
        std::to_string(entry.Rest.GetNumberOfPoints()) + " points, the part " + std::to_string(n));
    }
    if (!vtkFloatArray::FastDownCast(points) && !vtkDoubleArray::FastDownCast(points))
    {
      throw morphnode::InputError(what + ": skinned points must be float or double");
    }
    // The kept arrays, written again in place where points changed, when only this entry
    // holds them (and the entry serves one leaf this execution); else new ones, all
    // re-skinned.
    // (The points array is also held by the kept points object when that is free.)
    const int ownHolders =
      Free(entry.OutPointsObject) && entry.OutPointsObject->GetData() == entry.OutPoints ? 1 : 0;
    auto kept = [&](vtkSmartPointer<vtkDataArray>& a, vtkDataArray* like)
    {
      const int holders = 1 + (a == entry.OutPoints ? ownHolders : 0);
      return a && a->GetReferenceCount() == holders && a->GetDataType() == like->GetDataType() &&
        a->GetNumberOfTuples() == like->GetNumberOfTuples();
    };
    const bool all = !wasValid || entry.Execution == this->Execution ||
      !kept(entry.OutPoints, points) || (normals != nullptr) != (entry.OutNormals != nullptr) ||
      (normals && !kept(entry.OutNormals, normals));
    entry.Execution = this->Execution;
    if (all)
    {
      entry.OutPoints = NewLike(points);
      entry.OutNormals = normals ? NewLike(normals) : nullptr;
    }
    // What input can have changed since the last frame: nothing when its arrays are the same,
    // unmodified; else the morph node's MorphedPointRanges when the last frame came from the
    // same model (outside them the input is the neutral's); else all.
    using Seen = vtkInternals::Entry::Seen;
    const Seen seenPoints{ points, points->GetMTime() };
    const Seen seenNormals{ normals, normals ? normals->GetMTime() : 0 };
    auto* ranges = vtkIdTypeArray::SafeDownCast(
      leaf->GetFieldData()->GetArray(vtkMorphSkinArrays::MorphedRangesArray));
    // The ranges hold for the arrays the morph node wrote (MorphedArraysTime), not after a
    // filter in between moved the points or changed the normals.
    auto* written = vtkIdTypeArray::SafeDownCast(
      leaf->GetFieldData()->GetArray(vtkMorphSkinArrays::MorphedTimeArray));
    vtkDataArray* inNormals = leaf->GetPointData()->GetNormals();
    if (ranges &&
      (ranges->GetNumberOfComponents() != 2 || !written || written->GetNumberOfValues() != 2 ||
        written->GetValue(0) != static_cast<vtkIdType>(points->GetMTime()) ||
        written->GetValue(1) != (inNormals ? static_cast<vtkIdType>(inNormals->GetMTime()) : 0)))
    {
      ranges = nullptr;
    }
    const Seen seenRanges{ ranges, ranges ? ranges->GetMTime() : 0 };
    std::vector<size_t>& changedInput = entry.ChangedInput;
    changedInput.clear();
    const bool sameInput = seenPoints == entry.LastPoints && seenNormals == entry.LastNormals;
    const bool sameModel = ranges && seenRanges == entry.LastRanges;
    if (!all && sameInput)
    {
      // unchanged input: only points whose joints changed
    }
    else if (!all && sameModel)
    {
      const vtkIdType* r = ranges->GetPointer(0);
      const vtkIdType count = 2 * ranges->GetNumberOfTuples();
      for (vtkIdType i = 0; i + 1 < count; i += 2)
      {
        // Sorted, disjoint, within the points (else all).
        const vtkIdType lo = changedInput.empty() ? 0 : static_cast<vtkIdType>(changedInput.back());
        if (r[i] < lo || r[i + 1] < r[i] || r[i + 1] > static_cast<vtkIdType>(n))
        {
          changedInput = { 0, n };
          break;
        }
        changedInput.push_back(static_cast<size_t>(r[i]));
        changedInput.push_back(static_cast<size_t>(r[i + 1]));
      }
    }
    else
    {
      changedInput = { 0, n };
    }
    entry.LastPoints = seenPoints;
    entry.LastNormals = seenNormals;
    entry.LastRanges = seenRanges;
    if (vtkFloatArray::FastDownCast(points))
    {
      self->NumberOfReskinnedPoints += Reskin<float>(entry.Rest, Pointer<vtkFloatArray>(points),
        Pointer<vtkFloatArray>(normals), Pointer<vtkFloatArray>(entry.OutPoints),
        Pointer<vtkFloatArray>(entry.OutNormals), changedInput, n);
    }
    else
    {
      self->NumberOfReskinnedPoints += Reskin<double>(entry.Rest, Pointer<vtkDoubleArray>(points),
        Pointer<vtkDoubleArray>(normals), Pointer<vtkDoubleArray>(entry.OutPoints),
        Pointer<vtkDoubleArray>(entry.OutNormals), changedInput, n);
    }
    entry.Valid = true;
    // Written through raw pointers: renderers upload again on MTime.
    entry.OutPoints->Modified();
    vtkDataArray* newPoints = entry.OutPoints;
    vtkDataArray* newNormals = entry.OutNormals;
    if (newNormals)
    {
      newNormals->Modified();
    }
    if (!Free(entry.OutPointsObject))
    {
      entry.OutPointsObject = vtkSmartPointer<vtkPoints>::New();
    }
    entry.OutPointsObject->SetData(newPoints);
    out->SetPoints(entry.OutPointsObject);
    if (newNormals)
    {
      out->GetPointData()->SetNormals(newNormals);
    }
    this->SetField(out, angles, roles);
    return out;
  }
};

//------------------------------------------------------------------------------
vtkMorphSkinFilter::vtkMorphSkinFilter()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkMorphSkinFilter::~vtkMorphSkinFilter() = default;

//------------------------------------------------------------------------------
void vtkMorphSkinFilter::SetPoseConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
int vtkMorphSkinFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  if (!this->PoseParts(inputVector[1], vtkDataObject::GetData(inputVector[0], 0), output, false))
  {
    if (output)
    {
      output->Initialize();
    }
    return 0;
  }
  vtkMorphTrackFilter::StampTime(output, outputVector);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkMorphSkinFilter::MoveInPlace(vtkInformationVector* track, vtkDataObject* data)
{
  return this->PoseParts(track, data, nullptr, true);
}

//------------------------------------------------------------------------------
bool vtkMorphSkinFilter::PoseParts(
  vtkInformationVector* track, vtkDataObject* input, vtkDataObject* output, bool inPlace)
{
  this->ClearReports();
  ++this->Internals->Execution;
  this->Internals->Replaced.clear();
  try
  {
    if (!input || (!inPlace && !output))
    {
      throw morphnode::InputError("no input");
    }
    const morphnode::AvatarBonePose angles = this->Internals->Angles(this, track);
    // One pose per skeleton; parts of one avatar share it (computed for the first part).
    const MovePart pose =
      [&](vtkPointSet* part, const std::string& name, const std::string& description)
    { return this->Internals->Repose(this, part, description, angles, input, name, inPlace); };
    if (inPlace)
    {
      vtkMorphTrackFilter::MovePartsInPlace(input, pose, "pose");
    }
    else
    {
      vtkMorphTrackFilter::MoveParts(input, output, pose, "pose");
    }
    return true;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    this->NumberOfSkinnedParts = 0;
    this->NumberOfPosedOnlyParts = 0;
    return false;
  }
}

//------------------------------------------------------------------------------
void vtkMorphSkinFilter::ClearReports()
{
  this->NumberOfSkinnedParts = 0;
  this->NumberOfReskinnedPoints = 0;
  this->NumberOfPosedOnlyParts = 0;
  this->CPUSkinnedParts.clear();
  this->HasEyeBones = false;
  this->EyeParts.clear();
  this->HasHeadBones = false;
  this->JawByBone = false;
  this->HeadBounds[0] = this->HeadBounds[2] = this->HeadBounds[4] = 1.0;
  this->HeadBounds[1] = this->HeadBounds[3] = this->HeadBounds[5] = -1.0;
  this->Bones.clear();
}

//------------------------------------------------------------------------------
const char* vtkMorphSkinFilter::GetEyePart(int i)
{
  return i >= 0 && i < static_cast<int>(this->EyeParts.size())
    ? this->EyeParts[static_cast<size_t>(i)].c_str()
    : nullptr;
}
//------------------------------------------------------------------------------
const char* vtkMorphSkinFilter::GetCPUSkinnedPart(int i)
{
  return i >= 0 && i < static_cast<int>(this->CPUSkinnedParts.size())
    ? this->CPUSkinnedParts[static_cast<size_t>(i)].c_str()
    : nullptr;
}

//------------------------------------------------------------------------------
bool vtkMorphSkinFilter::GetHeadBounds(double bounds[6])
{
  if (!this->HasHeadBones || this->HeadBounds[0] > this->HeadBounds[1])
  {
    return false;
  }
  std::copy(this->HeadBounds, this->HeadBounds + 6, bounds);
  return true;
}

//------------------------------------------------------------------------------
void vtkMorphSkinFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "HeadYaw: " << this->HeadYaw << "\n";
  os << indent << "HeadPitch: " << this->HeadPitch << "\n";
  os << indent << "HeadRoll: " << this->HeadRoll << "\n";
  os << indent << "EyeYaw: " << this->EyeYaw << "\n";
  os << indent << "EyePitch: " << this->EyePitch << "\n";
  os << indent << "Vergence: " << this->Vergence << "\n";
  os << indent << "MaxEyeYaw: " << this->MaxEyeYaw << "\n";
  os << indent << "MaxEyeUp: " << this->MaxEyeUp << "\n";
  os << indent << "MaxEyeDown: " << this->MaxEyeDown << "\n";
  os << indent << "NeckShare: " << this->NeckShare << "\n";
  os << indent << "TurnHead: " << this->TurnHead << "\n";
  os << indent << "TurnEyes: " << this->TurnEyes << "\n";
  os << indent << "RelaxArms: " << this->RelaxArms << "\n";
  os << indent << "ArmAngle: " << this->ArmAngle << "\n";
  os << indent << "NumberOfSkinnedParts: " << this->NumberOfSkinnedParts << "\n";
  os << indent << "SkinPoints: " << this->SkinPoints << "\n";
  os << indent << "NumberOfReskinnedPoints: " << this->NumberOfReskinnedPoints << "\n";
  os << indent << "NumberOfPosedOnlyParts: " << this->NumberOfPosedOnlyParts << "\n";
  os << indent << "CPUSkinnedParts:";
  for (const auto& part : this->CPUSkinnedParts)
  {
    os << " " << part;
  }
  os << "\n";
  os << indent << "HasEyeBones: " << this->HasEyeBones << "\n";
  os << indent << "EyeParts:";
  for (const auto& part : this->EyeParts)
  {
    os << " " << part;
  }
  os << "\n";
  os << indent << "HasHeadBones: " << this->HasHeadBones << "\n";
  os << indent << "Bones: " << (this->Bones.empty() ? "(none)" : this->Bones) << "\n";
}
