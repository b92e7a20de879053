// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphSkinFilter.h"

#include "vtkMorphSkinArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "skin/AvatarBones.h"
#include "skin/Skinning.h"

#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>

vtkStandardNewMacro(vtkMorphSkinFilter);

namespace
{
/// Re-skins what changed since the previous frame (RestSkin::ApplyChanged) into the kept
/// output arrays.
template <typename T>
vtkIdType Reskin(const morphnode::RestSkin& skin, const T* points, const T* normals, T* lastPoints, T* lastNormals,
  T* outPoints, T* outNormals, size_t n, bool all)
{
  std::atomic<vtkIdType> count(0);
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), 4096, [&](vtkIdType begin, vtkIdType end) {
    count += static_cast<vtkIdType>(skin.ApplyChanged<T>(points, normals, lastPoints, lastNormals, outPoints,
      outNormals, static_cast<size_t>(begin), static_cast<size_t>(end), all));
  });
  return count;
}

template <typename ArrayT>
auto* Pointer(vtkDataArray* a)
{
  return a ? ArrayT::FastDownCast(a)->GetPointer(0) : nullptr;
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
    /// The last frame's output (written again in place only where points changed, and only
    /// when nothing but this entry holds them: a snapshot kept downstream never changes) and
    /// its input (to see which points the morph moved).
    vtkSmartPointer<vtkDataArray> OutPoints, OutNormals, LastPoints, LastNormals;
    bool Valid = false;          ///< the kept arrays hold the last frame
    unsigned long Execution = 0; ///< the last execution that used the entry
    bool HeadKnown = false;
    bool EyePart = false; ///< every point's largest weight on an eye joint or below it
    double HeadBounds[6] = { 1, -1, 1, -1, 1, -1 }; ///< empty when min > max
  };
  std::map<vtkDataArray*, Entry> Cache;
  unsigned long Execution = 0;

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
    entry.EyePart =
      morphnode::TurnedByEyeJoints(entry.Skin.Influences, entry.Skin.Joints.Joints, entry.Skin.Bones, entry.Roles);
    entry.Rest = morphnode::RestSkin(entry.Skin.Influences, entry.RestMatrices, what);
    return this->Cache[weights] = std::move(entry);
  }
};

//------------------------------------------------------------------------------
vtkMorphSkinFilter::vtkMorphSkinFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
}

//------------------------------------------------------------------------------
vtkMorphSkinFilter::~vtkMorphSkinFilter() = default;

//------------------------------------------------------------------------------
void vtkMorphSkinFilter::SetPoseConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
int vtkMorphSkinFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphSkinFilter::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A pose table animates the bones: its time steps win (the executive copies port 0's only).
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* poseInfo = inputVector[1]->GetInformationObject(0);
  if (poseInfo && poseInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    outInfo->CopyEntry(poseInfo, vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  }
  if (poseInfo && poseInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()))
  {
    outInfo->CopyEntry(poseInfo, vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphSkinFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  this->NumberOfSkinnedParts = 0;
  this->NumberOfReskinnedPoints = 0;
  ++this->Internals->Execution;
  this->HasEyeBones = false;
  this->EyeParts.clear();
  this->HasHeadBones = false;
  this->JawByBone = false;
  this->HeadBounds[0] = this->HeadBounds[2] = this->HeadBounds[4] = 1.0;
  this->HeadBounds[1] = this->HeadBounds[3] = this->HeadBounds[5] = -1.0;
  this->Bones.clear();
  if (!input || !output)
  {
    vtkErrorMacro(<< "no input");
    return 0;
  }
  try
  {
    morphnode::AvatarBonePose angles;
    angles.HeadYaw = this->HeadYaw;
    angles.HeadPitch = this->HeadPitch;
    angles.HeadRoll = this->HeadRoll;
    angles.EyeYaw = this->EyeYaw;
    angles.EyePitch = this->EyePitch;
    angles.JawOpen = this->JawOpen;
    angles.MaxJawAngle = this->MaxJawAngle;
    if (vtkTable* table = vtkTable::GetData(inputVector[1], 0))
    {
      if (table->GetNumberOfRows() < 1)
      {
        throw morphnode::InputError("the pose table has no rows");
      }
      for (auto [name, value] : { std::pair<const char*, double*>{ "HeadYaw", &angles.HeadYaw },
             { "HeadPitch", &angles.HeadPitch }, { "HeadRoll", &angles.HeadRoll }, { "EyeYaw", &angles.EyeYaw },
             { "EyePitch", &angles.EyePitch }, { "jawOpen", &angles.JawOpen } })
      {
        if (auto* column = vtkDataArray::SafeDownCast(table->GetColumnByName(name)))
        {
          *value = column->GetComponent(0, 0);
        }
      }
    }
    if (!this->TurnHead)
    {
      angles.HeadYaw = angles.HeadPitch = angles.HeadRoll = 0.0;
    }
    angles.Vergence = this->Vergence;
    angles.NeckShare = this->NeckShare;
    angles.Limits.MaxYaw = this->MaxEyeYaw;
    angles.Limits.MaxUp = this->MaxEyeUp;
    angles.Limits.MaxDown = this->MaxEyeDown;
    angles.RelaxArms = this->RelaxArms;
    angles.ArmAngle = this->ArmAngle;
    // The jaw joint only where no jawOpen target opens the mouth (JAW_AUTO).
    bool jawTarget = false;
    if (this->TurnJaw == JAW_AUTO)
    {
      auto scan = [&jawTarget](vtkDataObject* leaf) {
        auto* names = leaf ? vtkStringArray::SafeDownCast(leaf->GetFieldData()->GetAbstractArray("TargetNames")) : nullptr;
        for (vtkIdType i = 0; names && i < names->GetNumberOfValues(); ++i)
        {
          std::string n = morphnode::text::ToLower(names->GetValue(i));
          n.erase(std::remove(n.begin(), n.end(), '_'), n.end());
          jawTarget = jawTarget || n == "jawopen";
        }
      };
      if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
      {
        vtkSmartPointer<vtkCompositeDataIterator> it;
        it.TakeReference(composite->NewIterator());
        for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
        {
          scan(it->GetCurrentDataObject());
        }
      }
      else
      {
        scan(input);
      }
    }
    const bool jawAllowed = this->TurnJaw == JAW_ON || (this->TurnJaw == JAW_AUTO && !jawTarget);

    // One pose per skeleton; parts of one avatar share it (computed for the first part).
    auto reskin = [&](vtkPointSet* leaf, const std::string& what,
                    const std::string& partName) -> vtkSmartPointer<vtkPointSet> {
      if (!vtkMorphSkinArrays::IsSkinned(leaf))
      {
        return nullptr;
      }
      vtkInternals::Entry& entry = this->Internals->Get(leaf, what);
      morphnode::AvatarBoneRoles roles = entry.Roles;
      this->HasEyeBones = this->HasEyeBones || roles.HasEyes();
      if (entry.EyePart)
      {
        auto* part = vtkStringArray::SafeDownCast(leaf->GetFieldData()->GetAbstractArray("PartName"));
        const std::string name = part && part->GetNumberOfValues() ? part->GetValue(0) : partName;
        if (!name.empty() && std::find(this->EyeParts.begin(), this->EyeParts.end(), name) == this->EyeParts.end())
        {
          this->EyeParts.push_back(name);
        }
      }
      this->HasHeadBones = this->HasHeadBones || roles.Head >= 0;
      if (!entry.HeadKnown && roles.Head >= 0)
      {
        // The points whose largest weight is on the head or below it, at rest.
        const morphnode::SkinInfluences& inf = entry.Skin.Influences;
        for (vtkIdType i = 0; i < leaf->GetNumberOfPoints(); ++i)
        {
          size_t best = 0;
          for (size_t k = 1; k < inf.PerPoint; ++k)
          {
            best = inf.Weights[static_cast<size_t>(i) * inf.PerPoint + k] > inf.Weights[static_cast<size_t>(i) * inf.PerPoint + best] ? k : best;
          }
          const int joint = entry.Skin.Joints.Joints[inf.Joints[static_cast<size_t>(i) * inf.PerPoint + best]];
          if (entry.Skin.Bones.IsAncestor(roles.Head, joint))
          {
            const double* q = leaf->GetPoint(i);
            for (int k = 0; k < 3; ++k)
            {
              const bool empty = entry.HeadBounds[2 * k] > entry.HeadBounds[2 * k + 1];
              entry.HeadBounds[2 * k] = empty ? q[k] : std::min(entry.HeadBounds[2 * k], q[k]);
              entry.HeadBounds[2 * k + 1] = empty ? q[k] : std::max(entry.HeadBounds[2 * k + 1], q[k]);
            }
          }
        }
        entry.HeadKnown = true;
      }
      for (int k = 0; k < 3 && entry.HeadKnown; ++k)
      {
        if (entry.HeadBounds[2 * k] <= entry.HeadBounds[2 * k + 1])
        {
          const bool empty = this->HeadBounds[2 * k] > this->HeadBounds[2 * k + 1];
          this->HeadBounds[2 * k] = empty ? entry.HeadBounds[2 * k] : std::min(this->HeadBounds[2 * k], entry.HeadBounds[2 * k]);
          this->HeadBounds[2 * k + 1] = empty ? entry.HeadBounds[2 * k + 1] : std::max(this->HeadBounds[2 * k + 1], entry.HeadBounds[2 * k + 1]);
        }
      }
      if (!this->TurnEyes)
      {
        roles.LeftEye = roles.RightEye = -1;
      }
      if (!jawAllowed)
      {
        roles.Jaw = -1;
      }
      this->JawByBone = this->JawByBone || roles.Jaw >= 0;
      if (this->Bones.empty())
      {
        this->Bones = roles.Describe(entry.Skin.Bones);
      }
      morphnode::SkeletonPose pose(entry.Skin.Bones);
      morphnode::AvatarBonePose posed = angles;
      posed.RangeMaps = entry.Skin.RangeMaps; // a VRM's look-at (vtkMorphSkinArrays.h)
      morphnode::PoseAvatarBones(pose, roles, posed);
      ++this->NumberOfSkinnedParts;
      const bool wasValid = entry.Valid;
      entry.Valid = false; // the pose moves on: the kept arrays hold this frame only when written
      if (!entry.Rest.SetPose(entry.Skin.Joints.Matrices(pose.World())))
      {
        return nullptr; // at rest
      }
      vtkSmartPointer<vtkPointSet> out;
      out.TakeReference(leaf->NewInstance());
      out->ShallowCopy(leaf);
      vtkDataArray* points = leaf->GetPoints()->GetData();
      vtkDataArray* normals = leaf->GetPointData()->GetNormals();
      if (normals && (normals->GetNumberOfComponents() != 3 || normals->GetDataType() != points->GetDataType()))
      {
        normals = nullptr;
      }
      const size_t n = static_cast<size_t>(leaf->GetNumberOfPoints());
      if (entry.Rest.GetNumberOfPoints() != n)
      {
        throw morphnode::InputError(what + ": the skin has " + std::to_string(entry.Rest.GetNumberOfPoints()) +
          " points, the part " + std::to_string(n));
      }
      if (!vtkFloatArray::FastDownCast(points) && !vtkDoubleArray::FastDownCast(points))
      {
        throw morphnode::InputError(what + ": skinned points must be float or double");
      }
      // The kept arrays, written again in place where points changed, when only this entry
      // holds them (and the entry serves one leaf this execution); else new ones, all
      // re-skinned.
      auto kept = [&](vtkSmartPointer<vtkDataArray>& a, vtkDataArray* like) {
        return a && a->GetReferenceCount() == 1 && a->GetDataType() == like->GetDataType() &&
          a->GetNumberOfTuples() == like->GetNumberOfTuples();
      };
      bool all = !wasValid || entry.Execution == this->Internals->Execution || !kept(entry.OutPoints, points) ||
        !kept(entry.LastPoints, points) || (normals != nullptr) != (entry.OutNormals != nullptr) ||
        (normals && (!kept(entry.OutNormals, normals) || !kept(entry.LastNormals, normals)));
      entry.Execution = this->Internals->Execution;
      if (all)
      {
        entry.OutPoints = NewLike(points);
        entry.LastPoints = NewLike(points);
        entry.OutNormals = normals ? NewLike(normals) : nullptr;
        entry.LastNormals = normals ? NewLike(normals) : nullptr;
      }
      if (vtkFloatArray::FastDownCast(points))
      {
        this->NumberOfReskinnedPoints += Reskin<float>(entry.Rest, Pointer<vtkFloatArray>(points), Pointer<vtkFloatArray>(normals),
          Pointer<vtkFloatArray>(entry.LastPoints), Pointer<vtkFloatArray>(entry.LastNormals),
          Pointer<vtkFloatArray>(entry.OutPoints), Pointer<vtkFloatArray>(entry.OutNormals), n, all);
      }
      else
      {
        this->NumberOfReskinnedPoints += Reskin<double>(entry.Rest, Pointer<vtkDoubleArray>(points), Pointer<vtkDoubleArray>(normals),
          Pointer<vtkDoubleArray>(entry.LastPoints), Pointer<vtkDoubleArray>(entry.LastNormals),
          Pointer<vtkDoubleArray>(entry.OutPoints), Pointer<vtkDoubleArray>(entry.OutNormals), n, all);
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
      vtkNew<vtkPoints> p;
      p->SetData(newPoints);
      out->SetPoints(p);
      if (newNormals)
      {
        out->GetPointData()->SetNormals(newNormals);
      }
      vtkNew<vtkFieldData> field;
      field->ShallowCopy(leaf->GetFieldData());
      vtkNew<vtkDoubleArray> used;
      used->SetName("SkinPose");
      for (double v : { angles.HeadYaw, angles.HeadPitch, angles.HeadRoll, angles.EyeYaw, angles.EyePitch,
             roles.Jaw >= 0 ? angles.JawOpen : 0.0 })
      {
        used->InsertNextValue(v);
      }
      field->AddArray(used);
      out->SetFieldData(field);
      return out;
    };

    if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
    {
      auto* out = vtkCompositeDataSet::SafeDownCast(output);
      out->ShallowCopy(composite);
      vtkSmartPointer<vtkCompositeDataIterator> it;
      it.TakeReference(out->NewIterator());
      it->SkipEmptyNodesOn();
      for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
      {
        auto* leaf = vtkPointSet::SafeDownCast(it->GetCurrentDataObject());
        if (!leaf)
        {
          continue;
        }
        std::string name = "part " + std::to_string(it->GetCurrentFlatIndex());
        std::string partName;
        if (it->HasCurrentMetaData() && it->GetCurrentMetaData()->Has(vtkCompositeDataSet::NAME()))
        {
          partName = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
          name = "part '" + partName + "'";
        }
        if (auto posed = reskin(leaf, name, partName))
        {
          out->SetDataSet(it, posed);
        }
      }
    }
    else if (auto* points = vtkPointSet::SafeDownCast(input))
    {
      auto* out = vtkPointSet::SafeDownCast(output);
      out->Initialize(); // lets go of the last frame's arrays, for them to be written in place
      auto posed = reskin(points, "the input", "");
      out->ShallowCopy(posed ? posed.GetPointer() : points);
    }
    else
    {
      throw morphnode::InputError(std::string("cannot pose a ") + input->GetClassName());
    }
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(
        vtkDataObject::DATA_TIME_STEP(), outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
    return 1;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    this->NumberOfSkinnedParts = 0;
    return 0;
  }
}

//------------------------------------------------------------------------------
const char* vtkMorphSkinFilter::GetEyePart(int i)
{
  return i >= 0 && i < static_cast<int>(this->EyeParts.size()) ? this->EyeParts[static_cast<size_t>(i)].c_str()
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
  os << indent << "JawOpen: " << this->JawOpen << "\n";
  os << indent << "MaxJawAngle: " << this->MaxJawAngle << "\n";
  os << indent << "TurnJaw: " << this->TurnJaw << "\n";
  os << indent << "JawByBone: " << this->JawByBone << "\n";
  os << indent << "RelaxArms: " << this->RelaxArms << "\n";
  os << indent << "ArmAngle: " << this->ArmAngle << "\n";
  os << indent << "NumberOfSkinnedParts: " << this->NumberOfSkinnedParts << "\n";
  os << indent << "NumberOfReskinnedPoints: " << this->NumberOfReskinnedPoints << "\n";
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
