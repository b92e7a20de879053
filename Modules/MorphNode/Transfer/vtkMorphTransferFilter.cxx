// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTransferFilter.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "base/Text.h"
#include "transfer/Transfer.h"

#include "vtkCellArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSignedCharArray.h"

vtkStandardNewMacro(vtkMorphTransferFilter);

vtkMorphTransferFilter::vtkMorphTransferFilter()
{
  this->SetNumberOfInputPorts(2);
}

vtkMorphTransferFilter::~vtkMorphTransferFilter() = default;

void vtkMorphTransferFilter::SetLandmarkFileName(const std::string& name)
{
  if (name != this->LandmarkFileName)
  {
    this->LandmarkFileName = name;
    this->Modified();
  }
}

int vtkMorphTransferFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkMorphTransferFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* target = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* sourceFace = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  output->Initialize();
  if (!target || !sourceFace)
  {
    vtkErrorMacro(<< "Needs a target (port 0) and a source face (port 1).");
    return 0;
  }
  try
  {
    // The source: the convention's targets as a MorphMesh (triangles required).
    vtkMorphTargetArrays::ReadOptions read;
    read.Normals = false;
    read.Triangles = true;
    const morphnode::TransferSource source =
      morphnode::MakeTransferSource(vtkMorphTargetArrays::ToMorphMesh(sourceFace, read).Mesh);
    // The target: its points and polygons as triangles.
    morphnode::TransferSurface surface;
    if (!target->GetPoints() || target->GetNumberOfPoints() == 0)
    {
      throw morphnode::InputError("target: no points");
    }
    surface.Points.resize(static_cast<size_t>(target->GetNumberOfPoints()));
    for (vtkIdType i = 0; i < target->GetNumberOfPoints(); ++i)
    {
      double p[3];
      target->GetPoint(i, p);
      surface.Points[static_cast<size_t>(i)] = { p[0], p[1], p[2] };
    }
    surface.Triangles = vtkMorphTargetArrays::GetTriangles(target, true);
    morphnode::TransferOptions options;
    options.Method = static_cast<morphnode::TransferMethod>(this->Method);
    options.MaxResidual = this->MaxResidual;
    options.RequireMouthOpening = this->RequireMouthOpening;
    if (!this->LandmarkFileName.empty())
    {
      options.TargetLandmarks = morphnode::ParseTransferLandmarks(
        morphnode::text::ReadFile(this->LandmarkFileName, "landmark file"), this->LandmarkFileName);
    }
    const morphnode::TransferResult r = morphnode::TransferTargets(source, surface, options);
    this->ResidualP95 = r.ResidualP95;
    this->Scale = r.Scale;

    vtkNew<vtkPoints> points;
    points->DeepCopy(target->GetPoints());
    vtkNew<vtkCellArray> polys;
    for (size_t t = 0; t < surface.GetNumberOfTriangles(); ++t)
    {
      const vtkIdType tri[3] = { surface.Triangles[3 * t], surface.Triangles[3 * t + 1],
        surface.Triangles[3 * t + 2] };
      polys->InsertNextCell(3, tri);
    }
    output->SetPoints(points);
    output->SetPolys(polys);
    // The target's own point arrays, but no old targets (they are replaced).
    vtkPointData* pd = output->GetPointData();
    pd->PassData(target->GetPointData());
    vtkMorphTargetArrays::RemoveTargetArrays(pd);
    const vtkIdType n = target->GetNumberOfPoints();
    for (size_t k = 0; k < r.Deltas.size(); ++k)
    {
      const std::string name =
        vtkMorphTargetArrays::ArrayName(k, vtkMorphTargetArrays::Kind::Position);
      pd->AddArray(
        vtkMorphTargetArrays::NewArray(VTK_FLOAT, name.c_str(), 3, n, r.Deltas[k].data()));
    }
    pd->AddArray(
      vtkMorphTargetArrays::NewArray(VTK_FLOAT, "TransferConfidence", 1, n, r.Confidence.data()));
    vtkNew<vtkSignedCharArray> side;
    side->SetName("TransferSide");
    side->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      side->SetValue(i, r.TargetSide[static_cast<size_t>(i)]);
    }
    pd->AddArray(side);
    std::vector<std::string> names{ "Neutral" };
    names.insert(names.end(), r.TargetNames.begin(), r.TargetNames.end());
    vtkMorphTargetArrays::SetTargetNames(output->GetFieldData(), names);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    return 0;
  }
  return 1;
}

void vtkMorphTransferFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "MaxResidual: " << this->MaxResidual << "\n";
  os << indent << "RequireMouthOpening: " << (this->RequireMouthOpening ? "On" : "Off") << "\n";
  os << indent << "LandmarkFileName: " << this->LandmarkFileName << "\n";
  os << indent << "ResidualP95: " << this->ResidualP95 << "\n";
  os << indent << "Scale: " << this->Scale << "\n";
}
