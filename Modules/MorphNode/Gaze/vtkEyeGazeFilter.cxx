// SPDX-License-Identifier: BSD-3-Clause
#include "vtkEyeGazeFilter.h"

#include "vtkMorphPartData.h"
#include "vtkMorphRigCache.h"
#include "vtkMorphSkinArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gaze/EyeRig.h"
#include "gaze/EyeRotation.h"

#include "vtkCellData.h"
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
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkEyeGazeFilter);

namespace
{
/// A new array of `in`'s type and name holding `in`'s 3-vectors turned (points when
/// `points`, else directions).
vtkSmartPointer<vtkDataArray> Turned(
  vtkDataArray* in, const morphnode::RigidTurn& turn, bool points)
{
  vtkSmartPointer<vtkDataArray> out;
  out.TakeReference(in->NewInstance());
  out->SetName(in->GetName());
  out->SetNumberOfComponents(3);
  const vtkIdType n = in->GetNumberOfTuples();
  out->SetNumberOfTuples(n);
  auto* fin = vtkFloatArray::FastDownCast(in);
  auto* din = vtkDoubleArray::FastDownCast(in);
  if (fin)
  {
    float* o = vtkFloatArray::FastDownCast(out)->GetPointer(0);
    points ? turn.TurnPoints(fin->GetPointer(0), o, n) : turn.TurnVectors(fin->GetPointer(0), o, n);
  }
  else if (din)
  {
    double* o = vtkDoubleArray::FastDownCast(out)->GetPointer(0);
    points ? turn.TurnPoints(din->GetPointer(0), o, n) : turn.TurnVectors(din->GetPointer(0), o, n);
  }
  else
  {
    double t[3];
    for (vtkIdType i = 0; i < n; ++i)
    {
      in->GetTuple(i, t);
      points ? turn.TurnPoints(t, t, 1) : turn.TurnVectors(t, t, 1);
      out->SetTuple(i, t);
    }
  }
  return out;
}
} // namespace

class vtkEyeGazeFilter::vtkInternals
{
public:
  std::vector<std::string> EyeNames;
  vtkMorphRigCache RigCache;

  /// The eye rig of the filter's settings: named eyes, else the rig file's eyes section,
  /// else the default convention with the filter's directions and limits.
  morphnode::EyeRig MakeRig(vtkEyeGazeFilter* self)
  {
    const std::string rigFile = self->RigFileName ? self->RigFileName : "";
    if (self->Internals->EyeNames.empty() && !rigFile.empty())
    {
      const morphnode::Rig& rig = this->RigCache.Get(rigFile, self->GetMTime());
      if (rig.HasEyes())
      {
        return rig.GetEyes();
      }
    }
    const std::array<double, 3> forward{ { self->EyeForward[0], self->EyeForward[1],
      self->EyeForward[2] } };
    const std::array<double, 3> up{ { self->EyeUp[0], self->EyeUp[1], self->EyeUp[2] } };
    morphnode::EyeLimits limits;
    limits.MaxYaw = self->MaxEyeYaw;
    limits.MaxUp = self->MaxEyeUp;
    limits.MaxDown = self->MaxEyeDown;
    return morphnode::MakeEyeRig(this->EyeNames, forward, up, limits);
  }

  /// This execution's turned eyes (MoveParts hands them over by pointer).
  std::vector<vtkSmartPointer<vtkPointSet>> TurnedEyes;

  /// The leaf turned when it is an eye (a new data set sharing everything but the turned
  /// points and normals, held in TurnedEyes), else nullptr.
  vtkPointSet* Turn(vtkPointSet* leaf, const std::string& blockName, const morphnode::EyeRig& rig,
    const morphnode::GazeAngles& gaze, double vergence)
  {
    if (vtkMorphSkinArrays::IsSkinned(leaf))
    {
      return nullptr; // a skinned eye turns with its joint (vtkMorphSkinFilter)
    }
    vtkFieldData* fd = leaf->GetFieldData();
    const std::string nodeName = vtkMorphPartData::GetNodeName(fd);
    const std::string partName = vtkMorphPartData::GetPartName(fd, blockName);
    morphnode::EyeSpec eye;
    if (!rig.FindEye(nodeName, partName, eye))
    {
      return nullptr;
    }
    const std::string name = partName.empty() ? nodeName : partName;
    std::array<double, 3> origin{ { 0, 0, 0 } };
    std::array<double, 9> axes{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
    const morphnode::GazeAngles angles =
      morphnode::EyeAngles(gaze, vergence, eye.Side, rig.GetLimits());
    morphnode::RigidTurn turn;
    try
    {
      vtkMorphPartData::GetNodeFrame(fd, origin, axes);
      turn = morphnode::EyeTurn(angles, origin, axes, eye);
    }
    catch (const morphnode::InputError& e)
    {
      throw morphnode::InputError("eye part " + morphnode::text::Quote(name) + ": " + e.what());
    }

    vtkSmartPointer<vtkPointSet> out;
    out.TakeReference(leaf->NewInstance());
    out->ShallowCopy(leaf);
    if (vtkPoints* points = leaf->GetPoints())
    {
      vtkNew<vtkPoints> turned;
      turned->SetData(Turned(points->GetData(), turn, true));
      out->SetPoints(turned);
    }
    for (int which = 0; which < 2; ++which)
    {
      vtkDataSetAttributes* in = which == 0
        ? static_cast<vtkDataSetAttributes*>(leaf->GetPointData())
        : static_cast<vtkDataSetAttributes*>(leaf->GetCellData());
      vtkDataSetAttributes* o = which == 0 ? static_cast<vtkDataSetAttributes*>(out->GetPointData())
                                           : static_cast<vtkDataSetAttributes*>(out->GetCellData());
      vtkDataArray* normals = in->GetNormals();
      if (normals && normals->GetNumberOfComponents() == 3)
      {
        o->SetNormals(Turned(normals, turn, false));
      }
    }
    // Field data of its own (the input's arrays shared), with what the eye was turned by.
    vtkNew<vtkFieldData> field;
    field->ShallowCopy(fd);
    vtkNew<vtkDoubleArray> applied;
    applied->SetName("EyeGaze");
    applied->SetNumberOfValues(2);
    applied->SetValue(0, angles.Yaw);
    applied->SetValue(1, angles.Pitch);
    field->AddArray(applied);
    vtkNew<vtkStringArray> side;
    side->SetName("EyeSide");
    side->InsertNextValue(morphnode::EyeSideName(eye.Side));
    field->AddArray(side);
    out->SetFieldData(field);
    this->TurnedEyes.push_back(out);
    return out;
  }
};

//------------------------------------------------------------------------------
vtkEyeGazeFilter::vtkEyeGazeFilter()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkEyeGazeFilter::~vtkEyeGazeFilter()
{
  this->SetRigFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkEyeGazeFilter::AddEyeName(const char* name)
{
  if (!name)
  {
    return;
  }
  this->Internals->EyeNames.emplace_back(name);
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkEyeGazeFilter::RemoveAllEyeNames()
{
  if (!this->Internals->EyeNames.empty())
  {
    this->Internals->EyeNames.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkEyeGazeFilter::GetNumberOfEyeNames()
{
  return static_cast<int>(this->Internals->EyeNames.size());
}

//------------------------------------------------------------------------------
const char* vtkEyeGazeFilter::GetEyeName(int i)
{
  if (i < 0 || i >= this->GetNumberOfEyeNames())
  {
    return nullptr;
  }
  return this->Internals->EyeNames[static_cast<size_t>(i)].c_str();
}

//------------------------------------------------------------------------------
void vtkEyeGazeFilter::SetGazeConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
int vtkEyeGazeFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  this->NumberOfEyeParts = 0;
  if (!input || !output)
  {
    vtkErrorMacro(<< "no input");
    return 0;
  }
  try
  {
    // The gaze: the table's first row, else the properties.
    morphnode::GazeAngles gaze{ this->EyeYaw, this->EyePitch };
    vtkMorphTrackFilter::ReadTrackRow(inputVector[1],
      { { "EyeYaw", &gaze.Yaw }, { "EyePitch", &gaze.Pitch } }, "the gaze table", true);
    if (!std::isfinite(gaze.Yaw) || !std::isfinite(gaze.Pitch))
    {
      throw morphnode::InputError("the gaze angles (EyeYaw, EyePitch) must be finite");
    }
    this->LastEyeYaw = gaze.Yaw;
    this->LastEyePitch = gaze.Pitch;
    const morphnode::EyeRig rig = this->Internals->MakeRig(this);
    this->UpdateProgress(0.1);

    this->Internals->TurnedEyes.clear();
    this->NumberOfEyeParts = vtkMorphTrackFilter::MoveParts(
      input, output,
      [&](vtkPointSet* part, const std::string& name, const std::string&)
      { return this->Internals->Turn(part, name, rig, gaze, this->Vergence); },
      "turn eyes in");
    vtkMorphTrackFilter::StampTime(output, outputVector);
    this->UpdateProgress(1.0);
    return 1;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    this->NumberOfEyeParts = 0;
    return 0;
  }
}

//------------------------------------------------------------------------------
void vtkEyeGazeFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "EyeYaw: " << this->EyeYaw << "\n";
  os << indent << "EyePitch: " << this->EyePitch << "\n";
  os << indent << "Vergence: " << this->Vergence << "\n";
  os << indent << "MaxEyeYaw: " << this->MaxEyeYaw << "\n";
  os << indent << "MaxEyeUp: " << this->MaxEyeUp << "\n";
  os << indent << "MaxEyeDown: " << this->MaxEyeDown << "\n";
  os << indent << "EyeForward: (" << this->EyeForward[0] << ", " << this->EyeForward[1] << ", "
     << this->EyeForward[2] << ")\n";
  os << indent << "EyeUp: (" << this->EyeUp[0] << ", " << this->EyeUp[1] << ", " << this->EyeUp[2]
     << ")\n";
  os << indent << "EyeNames:";
  for (const std::string& name : this->Internals->EyeNames)
  {
    os << " '" << name << "'";
  }
  os << (this->Internals->EyeNames.empty() ? " (none: the rig's or the default convention)\n"
                                           : "\n");
  os << indent << "RigFileName: " << (this->RigFileName ? this->RigFileName : "(none)") << "\n";
  this->Internals->RigCache.Print(os, indent);
  os << indent << "NumberOfEyeParts: " << this->NumberOfEyeParts << "\n";
  os << indent << "LastEyeYaw: " << this->LastEyeYaw << "\n";
  os << indent << "LastEyePitch: " << this->LastEyePitch << "\n";
}
