// SPDX-License-Identifier: BSD-3-Clause
#include "vtkEyeGazeFilter.h"

#include "vtkMorphRigCache.h"
#include "vtkMorphSkinArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gaze/EyeRig.h"
#include "gaze/EyeRotation.h"

#include "vtkCellData.h"
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
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkEyeGazeFilter);

namespace
{
std::string StringOf(vtkFieldData* fd, const char* name)
{
  auto* array = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  return array && array->GetNumberOfValues() > 0 ? array->GetValue(0) : std::string();
}

/// `count` doubles of a field data array, false when it is absent; InputError when it has
/// another size or holds a value that is not finite.
bool DoublesOf(vtkFieldData* fd, const char* name, double* values, int count, const std::string& part)
{
  vtkDataArray* array = fd ? fd->GetArray(name) : nullptr;
  if (!array)
  {
    return false;
  }
  if (array->GetNumberOfValues() != count)
  {
    throw morphnode::InputError("eye part " + morphnode::text::Quote(part) + ": field data " + name +
      " has " + std::to_string(array->GetNumberOfValues()) + " values, not " + std::to_string(count));
  }
  for (int i = 0; i < count; ++i)
  {
    values[i] = array->GetComponent(i / array->GetNumberOfComponents(), i % array->GetNumberOfComponents());
    if (!std::isfinite(values[i]))
    {
      throw morphnode::InputError("eye part " + morphnode::text::Quote(part) + ": field data " + name +
        " is not finite");
    }
  }
  return true;
}

/// A new array of `in`'s type and name holding `in`'s 3-vectors turned (points when
/// `points`, else directions).
vtkSmartPointer<vtkDataArray> Turned(vtkDataArray* in, const morphnode::RigidTurn& turn, bool points)
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
    morphnode::EyeRig rig;
    const std::array<double, 3> forward{ { self->EyeForward[0], self->EyeForward[1], self->EyeForward[2] } };
    const std::array<double, 3> up{ { self->EyeUp[0], self->EyeUp[1], self->EyeUp[2] } };
    rig.SetDefaultDirections(forward, up);
    morphnode::EyeLimits limits;
    limits.MaxYaw = self->MaxEyeYaw;
    limits.MaxUp = self->MaxEyeUp;
    limits.MaxDown = self->MaxEyeDown;
    rig.SetLimits(limits);
    for (const std::string& name : this->EyeNames)
    {
      morphnode::EyeSpec eye;
      eye.Name = name;
      eye.Side = morphnode::EyeRig::SideFromName(name);
      eye.Forward = forward;
      eye.Up = up;
      rig.AddEye(eye);
    }
    return rig;
  }

  /// The leaf turned when it is an eye (a new data set sharing everything but the turned
  /// points and normals), else nullptr.
  vtkSmartPointer<vtkPointSet> Turn(vtkPointSet* leaf, const std::string& blockName,
    const morphnode::EyeRig& rig, const morphnode::GazeAngles& gaze, double vergence)
  {
    if (vtkMorphSkinArrays::IsSkinned(leaf))
    {
      return nullptr; // a skinned eye turns with its joint (vtkMorphSkinFilter)
    }
    vtkFieldData* fd = leaf->GetFieldData();
    const std::string nodeName = StringOf(fd, "NodeName");
    std::string partName = StringOf(fd, "PartName");
    if (partName.empty())
    {
      partName = blockName;
    }
    morphnode::EyeSpec eye;
    if (!rig.FindEye(nodeName, partName, eye))
    {
      return nullptr;
    }
    const std::string name = partName.empty() ? nodeName : partName;
    std::array<double, 3> origin{ { 0, 0, 0 } };
    std::array<double, 9> axes{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
    DoublesOf(fd, "NodeOrigin", origin.data(), 3, name);
    DoublesOf(fd, "NodeAxes", axes.data(), 9, name);
    const morphnode::GazeAngles angles = morphnode::EyeAngles(gaze, vergence, eye.Side, rig.GetLimits());
    morphnode::RigidTurn turn;
    try
    {
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
      vtkDataSetAttributes* in = which == 0 ? static_cast<vtkDataSetAttributes*>(leaf->GetPointData())
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
    return out;
  }
};

//------------------------------------------------------------------------------
vtkEyeGazeFilter::vtkEyeGazeFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
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
int vtkEyeGazeFilter::FillInputPortInformation(int port, vtkInformation* info)
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
int vtkEyeGazeFilter::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A gaze table animates the eyes: its time steps win over the head's (the executive
  // copies only those of port 0).
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* gazeInfo = inputVector[1]->GetInformationObject(0);
  if (gazeInfo && gazeInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    outInfo->CopyEntry(gazeInfo, vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  }
  if (gazeInfo && gazeInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()))
  {
    outInfo->CopyEntry(gazeInfo, vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  return 1;
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
    if (vtkTable* table = vtkTable::GetData(inputVector[1], 0))
    {
      auto* yaw = vtkDataArray::SafeDownCast(table->GetColumnByName("EyeYaw"));
      auto* pitch = vtkDataArray::SafeDownCast(table->GetColumnByName("EyePitch"));
      if (!yaw || !pitch)
      {
        throw morphnode::InputError("the gaze table has no numeric EyeYaw and EyePitch columns");
      }
      if (table->GetNumberOfRows() < 1)
      {
        throw morphnode::InputError("the gaze table has no rows");
      }
      gaze = { yaw->GetComponent(0, 0), pitch->GetComponent(0, 0) };
    }
    if (!std::isfinite(gaze.Yaw) || !std::isfinite(gaze.Pitch))
    {
      throw morphnode::InputError("the gaze angles (EyeYaw, EyePitch) must be finite");
    }
    this->LastEyeYaw = gaze.Yaw;
    this->LastEyePitch = gaze.Pitch;
    const morphnode::EyeRig rig = this->Internals->MakeRig(this);
    this->UpdateProgress(0.1);

    if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
    {
      auto* out = vtkCompositeDataSet::SafeDownCast(output);
      out->ShallowCopy(composite); // the structure, names, assembly; leaves shared
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
        std::string blockName;
        if (it->HasCurrentMetaData() && it->GetCurrentMetaData()->Has(vtkCompositeDataSet::NAME()))
        {
          blockName = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
        }
        if (auto turned = this->Internals->Turn(leaf, blockName, rig, gaze, this->Vergence))
        {
          out->SetDataSet(it, turned);
          ++this->NumberOfEyeParts;
        }
      }
    }
    else if (auto* points = vtkPointSet::SafeDownCast(input))
    {
      auto* out = vtkPointSet::SafeDownCast(output);
      if (auto turned = this->Internals->Turn(points, std::string(), rig, gaze, this->Vergence))
      {
        out->ShallowCopy(turned);
        ++this->NumberOfEyeParts;
      }
      else
      {
        out->ShallowCopy(points);
      }
    }
    else
    {
      throw morphnode::InputError(std::string("cannot turn eyes in a ") + input->GetClassName());
    }

    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
        outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
    }
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
  os << (this->Internals->EyeNames.empty() ? " (none: the rig's or the default convention)\n" : "\n");
  os << indent << "RigFileName: " << (this->RigFileName ? this->RigFileName : "(none)") << "\n";
  this->Internals->RigCache.Print(os, indent);
  os << indent << "NumberOfEyeParts: " << this->NumberOfEyeParts << "\n";
  os << indent << "LastEyeYaw: " << this->LastEyeYaw << "\n";
  os << indent << "LastEyePitch: " << this->LastEyePitch << "\n";
}
