// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: the face in flat arrays and as VTK polydata.
#include "ReductionStudy.h"

#include "vtkMorphTargetArrays.h"
#include "vtkMorphTargetReader.h"

#include "base/Error.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"

#include <algorithm>

namespace reductionstudy
{
morphnode::MorphMesh ToMorphMesh(const ReductionMesh& flat)
{
  morphnode::MorphMesh mesh(flat.GetNumberOfPoints());
  mesh.SetTargetNames(morphnode::DefaultTargetNames(flat.GetNumberOfTargets() + 1));
  auto& positions = mesh.AddAttribute<float>("Position", morphnode::AttributeRole::Position, 3);
  positions.SetNeutral(flat.Positions.data());
  for (const auto& d : flat.PositionDeltas)
  {
    positions.AddRelativeTarget(d.data(), morphnode::MorphMesh::DefaultSparseCoverage);
  }
  mesh.SetTriangles(flat.Triangles);
  return mesh;
}

ReductionMesh FromMorphMesh(const morphnode::MorphMesh& mesh)
{
  const auto& positions = std::get<morphnode::MorphAttribute<float>>(mesh.GetAttribute(0));
  ReductionMesh flat{ positions.GetNeutral(), mesh.GetTriangles(), {} };
  for (size_t k = 1; k < positions.GetNumberOfTargets(); ++k)
  {
    flat.PositionDeltas.emplace_back(flat.Positions.size());
    positions.GetTarget(k).ToDense(flat.PositionDeltas.back().data());
  }
  return flat;
}

Face LoadFace(const std::string& path)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(path.c_str());
  reader->SetMeshIndex(0); // the face mesh as one vtkPolyData
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  if (poly->GetNumberOfPoints() == 0)
  {
    throw morphnode::InputError("could not read a face from '" + path + "'");
  }
  Face face;
  for (int i = 0; i < reader->GetNumberOfTargets(); ++i)
  {
    face.Names.emplace_back(reader->GetTargetName(i));
  }
  const vtkIdType np = poly->GetNumberOfPoints();
  for (vtkIdType p = 0; p < np; ++p)
  {
    double x[3];
    poly->GetPoint(p, x);
    face.Mesh.Positions.insert(
      face.Mesh.Positions.end(), { float(x[0]), float(x[1]), float(x[2]) });
  }
  auto it = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType c = 0; c < n; ++c)
    {
      face.Mesh.Triangles.push_back(static_cast<uint32_t>(ids[c]));
    }
  }
  for (size_t k = 0; k + 1 < face.Names.size(); ++k)
  {
    vtkDataArray* d = poly->GetPointData()->GetArray(
      vtkMorphTargetArrays::ArrayName(k, vtkMorphTargetArrays::Kind::Position).c_str());
    std::vector<float> deltas(3 * np);
    for (vtkIdType p = 0; p < np; ++p)
    {
      double v[3];
      d->GetTuple(p, v);
      for (int c = 0; c < 3; ++c)
      {
        deltas[3 * p + c] = static_cast<float>(v[c]);
      }
    }
    face.Mesh.PositionDeltas.push_back(std::move(deltas));
  }
  return face;
}

vtkSmartPointer<vtkPolyData> ToPolyData(
  const float* positions, size_t np, const std::vector<uint32_t>& tris)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(static_cast<vtkIdType>(np));
  std::copy_n(positions, 3 * np, static_cast<float*>(points->GetVoidPointer(0)));
  poly->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  for (size_t t = 0; t + 2 < tris.size(); t += 3)
  {
    const vtkIdType ids[3] = { tris[t], tris[t + 1], tris[t + 2] };
    polys->InsertNextCell(3, ids);
  }
  poly->SetPolys(polys);
  return poly;
}
} // namespace reductionstudy
