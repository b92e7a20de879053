// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphSkinFilter.h"

#include "vtkMorphSkinArrays.h"

#include "base/Error.h"
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
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <map>

vtkStandardNewMacro(vtkMorphSkinFilter);

namespace
{
/// A new float or double array of `in`'s type and name with the re-skinned 3-vectors.
template <typename T>
void Reskin(const morphnode::RestSkin& skin, const T* points, const T* normals, T* outPoints, T* outNormals, size_t n)
{
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), 2048, [&](vtkIdType begin, vtkIdType end) {
    skin.Apply<T>(points, normals, outPoints, outNormals, static_cast<size_t>(begin), static_cast<size_t>(end));
  });
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
    bool HeadKnown = false;
    double HeadBounds[6] = { 1, -1, 1, -1, 1, -1 }; ///< empty when min > max
  };
  std::map<vtkDataArray*, Entry> Cache;

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
    entry.Roles = morphnode::FindAvatarBones(entry.Skin.Bones);
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
  this->HasEyeBones = false;
  this->HasHeadBones = false;
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
    if (vtkTable* table = vtkTable::GetData(inputVector[1], 0))
    {
      if (table->GetNumberOfRows() < 1)
      {
        throw morphnode::InputError("the pose table has no rows");
      }
      for (auto [name, value] : { std::pair<const char*, double*>{ "HeadYaw", &angles.HeadYaw },
             { "HeadPitch", &angles.HeadPitch }, { "HeadRoll", &angles.HeadRoll }, { "EyeYaw", &angles.EyeYaw },
             { "EyePitch", &angles.EyePitch } })
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

    // One pose per skeleton; parts of one avatar share it (computed for the first part).
    auto reskin = [&](vtkPointSet* leaf, const std::string& what) -> vtkSmartPointer<vtkPointSet> {
      if (!vtkMorphSkinArrays::IsSkinned(leaf))
      {
        return nullptr;
      }
      vtkInternals::Entry& entry = this->Internals->Get(leaf, what);
      morphnode::AvatarBoneRoles roles = entry.Roles;
      this->HasEyeBones = this->HasEyeBones || roles.HasEyes();
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
      if (this->Bones.empty())
      {
        this->Bones = roles.Describe(entry.Skin.Bones);
      }
      morphnode::SkeletonPose pose(entry.Skin.Bones);
      morphnode::PoseAvatarBones(pose, roles, angles);
      ++this->NumberOfSkinnedParts;
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
      auto newPoints = NewLike(points);
      auto newNormals = normals ? NewLike(normals) : nullptr;
      const size_t n = static_cast<size_t>(leaf->GetNumberOfPoints());
      if (entry.Rest.GetNumberOfPoints() != n)
      {
        throw morphnode::InputError(what + ": the skin has " + std::to_string(entry.Rest.GetNumberOfPoints()) +
          " points, the part " + std::to_string(n));
      }
      if (auto* f = vtkFloatArray::FastDownCast(points))
      {
        Reskin<float>(entry.Rest, f->GetPointer(0), normals ? vtkFloatArray::FastDownCast(normals)->GetPointer(0) : nullptr,
          vtkFloatArray::FastDownCast(newPoints)->GetPointer(0),
          normals ? vtkFloatArray::FastDownCast(newNormals)->GetPointer(0) : nullptr, n);
      }
      else if (auto* d = vtkDoubleArray::FastDownCast(points))
      {
        Reskin<double>(entry.Rest, d->GetPointer(0), normals ? vtkDoubleArray::FastDownCast(normals)->GetPointer(0) : nullptr,
          vtkDoubleArray::FastDownCast(newPoints)->GetPointer(0),
          normals ? vtkDoubleArray::FastDownCast(newNormals)->GetPointer(0) : nullptr, n);
      }
      else
      {
        throw morphnode::InputError(what + ": skinned points must be float or double");
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
      for (double v : { angles.HeadYaw, angles.HeadPitch, angles.HeadRoll, angles.EyeYaw, angles.EyePitch })
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
        if (it->HasCurrentMetaData() && it->GetCurrentMetaData()->Has(vtkCompositeDataSet::NAME()))
        {
          name = std::string("part '") + it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME()) + "'";
        }
        if (auto posed = reskin(leaf, name))
        {
          out->SetDataSet(it, posed);
        }
      }
    }
    else if (auto* points = vtkPointSet::SafeDownCast(input))
    {
      auto* out = vtkPointSet::SafeDownCast(output);
      auto posed = reskin(points, "the input");
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
  os << indent << "HasEyeBones: " << this->HasEyeBones << "\n";
  os << indent << "HasHeadBones: " << this->HasHeadBones << "\n";
  os << indent << "Bones: " << (this->Bones.empty() ? "(none)" : this->Bones) << "\n";
}
