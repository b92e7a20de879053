// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphRigBaker.h"

#include "vtkMorphModelAdapter.h"
#include "vtkMorphRigCache.h"

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

namespace
{
/// A new array of `prototype`'s type holding one dense delta set of a baked attribute.
template <typename T>
vtkSmartPointer<vtkDataArray> DeltaArray(const morphnode::MorphAttribute<T>& attribute,
  size_t target, vtkDataArray* prototype, const std::string& name)
{
  const size_t numPoints = attribute.GetNumberOfPoints();
  const int c = attribute.GetNumberOfComponents();
  std::vector<T> deltas(numPoints * static_cast<size_t>(c));
  attribute.GetTarget(target).ToDense(deltas.data());
  vtkSmartPointer<vtkDataArray> array;
  array.TakeReference(prototype->NewInstance());
  array->SetName(name.c_str());
  array->SetNumberOfComponents(c);
  array->SetNumberOfTuples(static_cast<vtkIdType>(numPoints));
  for (size_t p = 0; p < numPoints; ++p)
  {
    for (int j = 0; j < c; ++j)
    {
      array->SetComponent(static_cast<vtkIdType>(p), j, static_cast<double>(deltas[p * c + j]));
    }
  }
  return array;
}
} // namespace

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
    if (!vtkMorphModelAdapter::HasRelativeTargets(input))
    {
      throw morphnode::InputError("the input has no relative targets (point array "
                                  "'target0_position'): read the face with vtkMorphTargetReader");
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

    const vtkMorphModelAdapter::BuiltModel built =
      vtkMorphModelAdapter::BuildFromRelativeTargets(input, this->SparseCoverage);
    const morphnode::MorphMesh baked = rig.BakeModel(built.Model, shapes);
    const size_t numShapes = baked.GetNumberOfTargets() - 1;

    output->ShallowCopy(input);
    vtkPointData* pd = output->GetPointData();
    for (const std::string& name : built.ConsumedArrays)
    {
      pd->RemoveArray(name.c_str());
    }
    // Attributes are parallel to the bindings: points first, then the normals (if any).
    vtkPointData* inPD = input->GetPointData();
    for (size_t a = 0; a < baked.GetNumberOfAttributes(); ++a)
    {
      const bool isNormals = built.Bindings[a].IsNormals;
      const char* what = a == 0 ? "position" : (isNormals ? "normal" : nullptr);
      if (!what)
      {
        continue;
      }
      vtkDataArray* prototype = inPD->GetArray((std::string("target0_") + what).c_str());
      if (!prototype)
      {
        prototype = built.Bindings[a].Prototype;
      }
      for (size_t k = 0; k < numShapes; ++k)
      {
        const std::string name = "target" + std::to_string(k) + "_" + what;
        std::visit(
          [&](const auto& attribute) {
            pd->AddArray(DeltaArray(attribute, k + 1, prototype, name));
          },
          baked.GetAttribute(a));
      }
    }
    output->GetFieldData()->RemoveArray(vtkMorphModelAdapter::TargetNamesArray);
    output->GetFieldData()->AddArray(vtkMorphModelAdapter::MakeNamesArray(
      vtkMorphModelAdapter::TargetNamesArray, baked.GetTargetNames()));
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 1;
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
