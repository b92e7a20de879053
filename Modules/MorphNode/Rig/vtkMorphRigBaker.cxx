// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphRigBaker.h"

#include "vtkMorphRigCache.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "morph/MorphMesh.h"
#include "rig/Rig.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include <variant>
#include <vector>

vtkStandardNewMacro(vtkMorphRigBaker);

struct vtkMorphRigBaker::vtkInternals
{
  vtkMorphRigCache Rig;
  vtkSmartPointer<vtkStringArray> ShapeNames;
};

//------------------------------------------------------------------------------
vtkMorphRigBaker::vtkMorphRigBaker()
  : SparseCoverage(morphnode::MorphMesh::DefaultSparseCoverage)
  , Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkMorphRigBaker::~vtkMorphRigBaker() = default;

//------------------------------------------------------------------------------
void vtkMorphRigBaker::SetShapeNames(vtkStringArray* names)
{
  if (names && names->GetNumberOfValues() == 0)
  {
    names = nullptr;
  }
  if (!names && !this->Internals->ShapeNames)
  {
    return;
  }
  if (names)
  {
    auto copy = vtkSmartPointer<vtkStringArray>::New();
    copy->DeepCopy(names);
    this->Internals->ShapeNames = copy;
  }
  else
  {
    this->Internals->ShapeNames = nullptr;
  }
  this->Modified();
}

//------------------------------------------------------------------------------
vtkStringArray* vtkMorphRigBaker::GetShapeNames()
{
  return this->Internals->ShapeNames;
}

//------------------------------------------------------------------------------
void vtkMorphRigBaker::SetRigFileName(const char* value)
{
  const std::string v = value ? value : "";
  if (v != this->RigFileName)
  {
    this->RigFileName = v;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkMorphRigBaker::SetShapeSet(const char* value)
{
  const std::string v = value ? value : "";
  if (v != this->ShapeSet)
  {
    this->ShapeSet = v;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkMorphRigBaker::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0], 0);
  vtkPointSet* output = vtkPointSet::GetData(outputVector, 0);
  output->Initialize();
  vtkInternals& internals = *this->Internals;
  try
  {
    morphnode::Rig& rig = internals.Rig.Get(this->RigFileName, this->vtkObject::GetMTime());

    if (!input)
    {
      throw morphnode::InputError("no input: connect a face with relative targets to port 0");
    }
    if (!vtkMorphTargetArrays::HasTargets(input))
    {
      throw morphnode::InputError("the input has no relative targets (point array '" +
        vtkMorphTargetArrays::ArrayName(0, vtkMorphTargetArrays::Kind::Position) +
        "'): read the face with vtkMorphTargetReader");
    }

    std::vector<std::string> shapes;
    if (internals.ShapeNames)
    {
      for (vtkIdType i = 0; i < internals.ShapeNames->GetNumberOfValues(); ++i)
      {
        shapes.push_back(internals.ShapeNames->GetValue(i));
      }
    }
    else if (!this->ShapeSet.empty())
    {
      shapes = rig.GetSet(this->ShapeSet);
    }
    else
    {
      shapes = rig.GetShapeNames();
    }

    namespace arrays = vtkMorphTargetArrays;
    arrays::ReadOptions options;
    options.SparseCoverage = this->SparseCoverage;
    const arrays::MeshFromVTK face = arrays::ToMorphMesh(input, options);
    this->UpdateProgress(0.3);
    const morphnode::MorphMesh baked = rig.BakeModel(face.Mesh, shapes);
    this->UpdateProgress(0.8);

    // The baked targets replace the face's, in the types of the face's target arrays.
    vtkPointData* inPD = input->GetPointData();
    const vtkIdType numPoints = input->GetNumberOfPoints();
    auto typeOf = [&](arrays::Kind kind)
    {
      vtkDataArray* first = arrays::GetDeltas(inPD, 0, kind, numPoints);
      return first ? first->GetDataType() : -1;
    };
    output->ShallowCopy(input);
    vtkPointData* pd = output->GetPointData();
    arrays::RemoveTargetArrays(pd);
    arrays::AddTargetArrays(
      baked, pd, typeOf(arrays::Kind::Position), typeOf(arrays::Kind::Normal));
    arrays::SetTargetNames(output->GetFieldData(), baked.GetTargetNames());
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphRigBaker::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RigFileName: " << (this->RigFileName.empty() ? "(none)" : this->RigFileName)
     << "\n";
  os << indent << "ShapeSet: " << (this->ShapeSet.empty() ? "(all shapes)" : this->ShapeSet)
     << "\n";
  os << indent << "ShapeNames:";
  if (this->Internals->ShapeNames)
  {
    for (vtkIdType i = 0; i < this->Internals->ShapeNames->GetNumberOfValues(); ++i)
    {
      os << " " << this->Internals->ShapeNames->GetValue(i);
    }
    os << "\n";
  }
  else
  {
    os << " (none)\n";
  }
  os << indent << "SparseCoverage: " << this->SparseCoverage << "\n";
  this->Internals->Rig.Print(os, indent);
}
