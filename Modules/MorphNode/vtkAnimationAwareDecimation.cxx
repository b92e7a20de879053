// SPDX-License-Identifier: BSD-3-Clause
#include "vtkAnimationAwareDecimation.h"

#include "base/Error.h"
#include "reduction/AnimationAwareReduction.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <cmath>
#include <map>
#include <string>

vtkStandardNewMacro(vtkAnimationAwareDecimation);

namespace
{
using morphnode::InputError;

/// k of an array named `target<k>_position`, -1 otherwise.
int PositionTargetIndex(const char* name)
{
  if (!name)
  {
    return -1;
  }
  const std::string s(name);
  const std::string prefix = "target", suffix = "_position";
  if (s.size() <= prefix.size() + suffix.size() || s.compare(0, prefix.size(), prefix) != 0 ||
    s.compare(s.size() - suffix.size(), suffix.size(), suffix) != 0)
  {
    return -1;
  }
  const std::string digits = s.substr(prefix.size(), s.size() - prefix.size() - suffix.size());
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
  {
    return -1;
  }
  return std::stoi(digits);
}

std::vector<float> ToFloats(vtkDataArray* array)
{
  const vtkIdType n = array->GetNumberOfTuples();
  std::vector<float> values(static_cast<size_t>(n) * 3);
  double t[3];
  for (vtkIdType i = 0; i < n; ++i)
  {
    array->GetTuple(i, t);
    for (int c = 0; c < 3; ++c)
    {
      values[3 * i + c] = static_cast<float>(t[c]);
    }
  }
  return values;
}

/// The core's view of the input; throws InputError for anything it cannot represent.
morphnode::MorphMesh ToMorphMesh(vtkPolyData* input)
{
  std::vector<uint32_t> triangles;
  std::vector<std::vector<float>> deltas;
  const vtkIdType np = input->GetNumberOfPoints();
  if (np == 0 || !input->GetPoints())
  {
    throw InputError("the input has no points");
  }
  if (input->GetNumberOfStrips() > 0)
  {
    throw InputError("the input has triangle strips; convert them with vtkTriangleFilter first");
  }
  const std::vector<float> positions = ToFloats(input->GetPoints()->GetData());

  vtkCellArray* polys = input->GetPolys();
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType size;
    const vtkIdType* ids;
    it->GetCurrentCell(size, ids);
    if (size != 3)
    {
      throw InputError("polygon " + std::to_string(it->GetCurrentCellId()) + " has " +
        std::to_string(size) + " points; the input must be triangles (use vtkTriangleFilter)");
    }
    for (int c = 0; c < 3; ++c)
    {
      triangles.push_back(static_cast<uint32_t>(ids[c]));
    }
  }
  if (triangles.empty())
  {
    throw InputError("the input has no triangles");
  }

  // target<k>_position for k = 0..n-1, without gaps.
  vtkPointData* pd = input->GetPointData();
  std::map<int, vtkDataArray*> targets;
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    const int k = PositionTargetIndex(pd->GetArrayName(a));
    if (k >= 0)
    {
      vtkDataArray* array = pd->GetArray(a);
      if (!array)
      {
        throw InputError(std::string("point array '") + pd->GetArrayName(a) + "' is not numeric");
      }
      targets[k] = array;
    }
  }
  int expected = 0;
  for (const auto& entry : targets)
  {
    if (entry.first != expected)
    {
      throw InputError("target arrays have a gap: target" + std::to_string(entry.first) +
        "_position exists but target" + std::to_string(expected) + "_position does not");
    }
    vtkDataArray* array = entry.second;
    if (array->GetNumberOfComponents() != 3 || array->GetNumberOfTuples() != np)
    {
      throw InputError(std::string("'") + array->GetName() + "' has " +
        std::to_string(array->GetNumberOfTuples()) + " tuples of " +
        std::to_string(array->GetNumberOfComponents()) + " components; expected " +
        std::to_string(np) + " tuples of 3");
    }
    deltas.push_back(ToFloats(array));
    ++expected;
  }
  if (vtkAbstractArray* names = input->GetFieldData()->GetAbstractArray("TargetNames"))
  {
    if (names->GetNumberOfValues() != static_cast<vtkIdType>(deltas.size() + 1))
    {
      throw InputError("field data TargetNames has " + std::to_string(names->GetNumberOfValues()) +
        " names, but the input has " + std::to_string(deltas.size()) +
        " targets plus the neutral");
    }
  }
  morphnode::MorphMesh mesh(static_cast<size_t>(np));
  mesh.SetTargetNames(morphnode::DefaultTargetNames(deltas.size() + 1));
  auto& attribute = mesh.AddAttribute<float>("Points", morphnode::AttributeRole::Position, 3);
  attribute.SetNeutral(positions.data());
  for (const auto& d : deltas)
  {
    attribute.AddRelativeTarget(d.data(), morphnode::MorphMesh::DefaultSparseCoverage);
  }
  mesh.SetTriangles(std::move(triangles));
  return mesh;
}
} // namespace

vtkAnimationAwareDecimation::vtkAnimationAwareDecimation() = default;
vtkAnimationAwareDecimation::~vtkAnimationAwareDecimation() = default;

int vtkAnimationAwareDecimation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input)
  {
    vtkErrorMacro(<< "No input.");
    return 1;
  }
  try
  {
    const morphnode::MorphMesh mesh = ToMorphMesh(input);
    morphnode::ReductionSettings settings;
    settings.AnimationWeight = this->AnimationWeight;
    settings.PoseQuadrics = this->PoseQuadrics;
    settings.MaxNormalDeviation = this->MaxNormalDeviation;
    if (this->NumberOfTriangles > 0)
    {
      settings.TargetTriangles = static_cast<size_t>(this->NumberOfTriangles);
    }
    else
    {
      const double keep = std::round((1.0 - this->TargetReduction) * mesh.GetNumberOfTriangles());
      if (keep < 1.0 || this->TargetReduction <= 0.0)
      {
        throw InputError("TargetReduction " + std::to_string(this->TargetReduction) +
          " leaves no triangle to remove or none to keep");
      }
      settings.TargetTriangles = static_cast<size_t>(keep);
    }
    this->UpdateProgress(0.1);
    const morphnode::ReductionResult result = morphnode::ReduceAnimationAware(mesh, settings);
    this->UpdateProgress(0.9);

    const auto& ids = result.OriginalPointIds;
    const vtkIdType n = static_cast<vtkIdType>(ids.size());
    vtkNew<vtkIdList> from;
    from->SetNumberOfIds(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      from->SetId(i, static_cast<vtkIdType>(ids[i]));
    }
    vtkNew<vtkPoints> points;
    points->SetDataType(input->GetPoints()->GetDataType());
    points->SetNumberOfPoints(n);
    input->GetPoints()->GetData()->GetTuples(from, points->GetData());

    vtkNew<vtkCellArray> polys;
    const std::vector<uint32_t>& triangles = result.Mesh.GetTriangles();
    polys->AllocateExact(static_cast<vtkIdType>(result.Mesh.GetNumberOfTriangles()),
      static_cast<vtkIdType>(triangles.size()));
    for (size_t t = 0; t < result.Mesh.GetNumberOfTriangles(); ++t)
    {
      const vtkIdType tri[3] = { triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2] };
      polys->InsertNextCell(3, tri);
    }

    output->Initialize();
    output->SetPoints(points);
    output->SetPolys(polys);
    // Every point array (normals, texture coordinates, every target's deltas) comes
    // unchanged from the point each output point is.
    vtkPointData* inPD = input->GetPointData();
    vtkPointData* outPD = output->GetPointData();
    outPD->CopyAllocate(inPD, n);
    outPD->SetNumberOfTuples(n);
    for (int a = 0; a < outPD->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* target = outPD->GetAbstractArray(a);
      vtkAbstractArray* source = inPD->GetAbstractArray(target->GetName());
      if (source)
      {
        source->GetTuples(from, target);
      }
    }
    vtkNew<vtkIdTypeArray> original;
    original->SetName("OriginalPointId");
    original->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      original->SetValue(i, from->GetId(i));
    }
    outPD->AddArray(original);
    output->GetFieldData()->PassData(input->GetFieldData());
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
  }
  return 1;
}

void vtkAnimationAwareDecimation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "NumberOfTriangles: " << this->NumberOfTriangles << "\n";
  os << indent << "AnimationWeight: " << this->AnimationWeight << "\n";
  os << indent << "PoseQuadrics: " << (this->PoseQuadrics ? "On" : "Off") << "\n";
  os << indent << "MaxNormalDeviation: " << this->MaxNormalDeviation << "\n";
}
