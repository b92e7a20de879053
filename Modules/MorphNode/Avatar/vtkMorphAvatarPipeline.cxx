// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphAvatarPipeline.h"

#include "behavior/HeadPose.h"

#include "vtkAlgorithm.h"
#include "vtkAlgorithmOutput.h"
#include "vtkBoundingBox.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkEyeGazeFilter.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigFilter.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"
#include "vtkObjectFactory.h"
#include "vtkTable.h"
#include "vtkTransform.h"

#include <array>

vtkStandardNewMacro(vtkMorphAvatarPipeline);

namespace
{
double Channel(vtkTable* table, const char* name)
{
  auto* data = table ? vtkArrayDownCast<vtkDataArray>(table->GetColumnByName(name)) : nullptr;
  return data && data->GetNumberOfTuples() > 0 ? data->GetTuple1(0) : 0.0;
}

/// The bounds of every point of a face (a data set, or the leaves of a composite).
bool FaceBounds(vtkDataObject* face, double bounds[6])
{
  vtkBoundingBox box;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(face))
  {
    for (vtkDataSet* leaf : vtkCompositeDataSet::GetDataSets(composite))
    {
      if (leaf->GetNumberOfPoints() > 0)
      {
        box.AddBounds(leaf->GetBounds());
      }
    }
  }
  else if (auto* set = vtkDataSet::SafeDownCast(face))
  {
    if (set->GetNumberOfPoints() > 0)
    {
      box.AddBounds(set->GetBounds());
    }
  }
  if (!box.IsValid())
  {
    return false;
  }
  box.GetBounds(bounds);
  return true;
}
} // namespace

//------------------------------------------------------------------------------
vtkMorphAvatarPipeline::vtkMorphAvatarPipeline()
{
  // The behaviour's channels are glTF-style weights: each adds its target's deltas, so a
  // blink does not weaken a vowel.
  this->Morph->SetWeightModeToRelative();
  this->Connect();
}

//------------------------------------------------------------------------------
vtkMorphAvatarPipeline::~vtkMorphAvatarPipeline() = default;

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::Connect()
{
  vtkAlgorithmOutput* weights = this->Weights;
  const bool rig = !this->RigFileName.empty();
  const bool mapped = rig && this->RigMapsWeights && !this->UseFaceAnimation;
  this->Morph->SetInputConnection(this->Reader->GetOutputPort());
  if (this->UseFaceAnimation)
  {
    this->Morph->SetWeightsConnection(this->Reader->GetOutputPort(1));
  }
  else if (mapped)
  {
    this->Rig->SetInputConnection(weights);
    this->Rig->SetFaceConnection(this->Reader->GetOutputPort());
    this->Morph->SetWeightsConnection(this->Rig->GetOutputPort());
  }
  else
  {
    this->Morph->SetWeightsConnection(weights);
  }
  if (!mapped)
  {
    this->Rig->SetInputConnection(nullptr);
    this->Rig->SetFaceConnection(nullptr);
  }
  this->Rig->SetRigFileName(mapped ? this->RigFileName.c_str() : nullptr);
  // The skin filter poses the skeleton in the morph node's pass (one pass instead of two):
  // it reads the behaviour's head pose and gaze on the morph node's port 2.
  this->Morph->SetPoseFilter(this->Skin);
  this->Morph->SetPoseConnection(weights);
  this->Gaze->SetInputConnection(this->Morph->GetOutputPort());
  this->Gaze->SetGazeConnection(this->UseFaceAnimation ? nullptr : weights);
  this->Gaze->SetRigFileName(rig ? this->RigFileName.c_str() : nullptr);
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::SetFileName(const char* path)
{
  this->Reader->SetFileName(path);
  this->Modified();
}

const char* vtkMorphAvatarPipeline::GetFileName()
{
  return this->Reader->GetFileName();
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::SetRigFileName(const char* path)
{
  const std::string p = path ? path : "";
  if (p != this->RigFileName)
  {
    this->RigFileName = p;
    this->Connect();
    this->Modified();
  }
}

const char* vtkMorphAvatarPipeline::GetRigFileName()
{
  return this->RigFileName.c_str();
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::SetWeightsConnection(vtkAlgorithmOutput* output)
{
  if (output != this->Weights)
  {
    this->Weights = output;
    this->WeightsProducer = output ? output->GetProducer() : nullptr;
    this->Connect();
    this->Modified();
  }
}

vtkAlgorithmOutput* vtkMorphAvatarPipeline::GetWeightsConnection()
{
  return this->Weights;
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::SetRigMapsWeights(bool maps)
{
  if (maps != this->RigMapsWeights)
  {
    this->RigMapsWeights = maps;
    this->Connect();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::SetUseFaceAnimation(bool use)
{
  if (use != this->UseFaceAnimation)
  {
    this->UseFaceAnimation = use;
    this->Connect();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkMorphTargetReader* vtkMorphAvatarPipeline::GetReader()
{
  return this->Reader;
}

vtkMorphRigFilter* vtkMorphAvatarPipeline::GetRig()
{
  return this->Rig;
}

vtkMorphNodeFilter* vtkMorphAvatarPipeline::GetMorph()
{
  return this->Morph;
}

vtkEyeGazeFilter* vtkMorphAvatarPipeline::GetGaze()
{
  return this->Gaze;
}

vtkMorphSkinFilter* vtkMorphAvatarPipeline::GetSkin()
{
  return this->Skin;
}

vtkAlgorithmOutput* vtkMorphAvatarPipeline::GetOutputPort()
{
  return this->Gaze->GetOutputPort();
}

vtkDataObject* vtkMorphAvatarPipeline::GetOutputDataObject()
{
  return this->Gaze->GetOutputDataObject(0);
}

vtkTransform* vtkMorphAvatarPipeline::GetHeadPose()
{
  return this->HeadPose;
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::GetHeadPivot(double pivot[3])
{
  std::copy(this->Pivot, this->Pivot + 3, pivot);
}

//------------------------------------------------------------------------------
bool vtkMorphAvatarPipeline::UpdateTimeStep(double t)
{
  if (!this->Gaze->UpdateTimeStep(t))
  {
    return false;
  }
  // The pivot of the face as read (its neutral), once per reading.
  vtkDataObject* face = this->Reader->GetOutputDataObject(0);
  if (face && face->GetMTime() != this->PivotTime)
  {
    double bounds[6];
    if (FaceBounds(face, bounds))
    {
      const std::array<double, 3> pivot = morphnode::HeadPivot(bounds);
      std::copy(pivot.begin(), pivot.end(), this->Pivot);
    }
    this->PivotTime = face->GetMTime();
  }
  // A skinned avatar turns its head by its joints: the whole body must not turn. A glTF
  // animation's weights have no head angles: the identity.
  vtkTable* weights = nullptr;
  if (!this->Skin->GetHasHeadBones() && !this->UseFaceAnimation && this->Weights)
  {
    weights = vtkTable::SafeDownCast(
      this->Weights->GetProducer()->GetOutputDataObject(this->Weights->GetIndex()));
  }
  SetHeadPoseFromWeights(this->HeadPose, weights, this->Pivot);
  return true;
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::SetHeadPoseFromWeights(
  vtkTransform* transform, vtkTable* weights, const double pivot[3])
{
  if (!transform)
  {
    return;
  }
  morphnode::HeadAngles angles;
  angles.Yaw = Channel(weights, "HeadYaw");
  angles.Pitch = Channel(weights, "HeadPitch");
  angles.Roll = Channel(weights, "HeadRoll");
  // A non-finite angle turns the head to 0 in that frame instead of failing it.
  transform->SetMatrix(
    morphnode::HeadPoseMatrix(morphnode::FiniteHeadAngles(angles), { pivot[0], pivot[1], pivot[2] })
      .data());
}

//------------------------------------------------------------------------------
void vtkMorphAvatarPipeline::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent
     << "FileName: " << (this->Reader->GetFileName() ? this->Reader->GetFileName() : "(none)")
     << "\n";
  os << indent << "RigFileName: " << (this->RigFileName.empty() ? "(none)" : this->RigFileName)
     << "\n";
  os << indent << "WeightsConnection: " << this->Weights.GetPointer() << "\n";
  os << indent << "RigMapsWeights: " << this->RigMapsWeights << "\n";
  os << indent << "UseFaceAnimation: " << this->UseFaceAnimation << "\n";
  os << indent << "HeadPivot: (" << this->Pivot[0] << ", " << this->Pivot[1] << ", "
     << this->Pivot[2] << ")\n";
  os << indent << "Reader: " << this->Reader.GetPointer() << "\n";
  os << indent << "Rig: " << this->Rig.GetPointer() << "\n";
  os << indent << "Morph: " << this->Morph.GetPointer() << "\n";
  os << indent << "Gaze: " << this->Gaze.GetPointer() << "\n";
  os << indent << "Skin: " << this->Skin.GetPointer() << "\n";
}
