// SPDX-License-Identifier: BSD-3-Clause
// A head's parts as one mesh: the reference the scene tests and the scene benchmark compare
// vtkMorphNodeFilter on a composite with (Testing/Cxx/TestMorphNodeScene.cxx,
// Testing/Benchmarks/BenchMorph.cxx).
#ifndef MorphNodeMergeParts_h
#define MorphNodeMergeParts_h

#include "vtkCellArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <string>
#include <vector>

namespace morphnode_test
{
/// The vtkPolyData leaves of a composite, in its order.
inline std::vector<vtkPolyData*> PolyDataLeaves(vtkDataObject* data)
{
  std::vector<vtkPolyData*> leaves;
  auto* composite = vtkCompositeDataSet::SafeDownCast(data);
  if (!composite)
  {
    return leaves;
  }
  for (vtkDataObject* leaf : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
  {
    leaves.push_back(vtkPolyData::SafeDownCast(leaf));
  }
  return leaves;
}

/// A string array of field data, as strings.
inline std::vector<std::string> FieldStrings(vtkFieldData* fd, const char* name)
{
  std::vector<std::string> values;
  auto* a = vtkStringArray::SafeDownCast(fd->GetAbstractArray(name));
  for (vtkIdType i = 0; a && i < a->GetNumberOfValues(); ++i)
  {
    values.push_back(a->GetValue(i));
  }
  return values;
}

/// Every part of a head as ONE vtkPolyData: the points in part order, the triangles, the
/// normals (zeros for parts without), and one target<k>_position/_normal per target of the
/// whole head (by name, in order of first appearance; zeros on the points of parts without
/// that target).
inline vtkSmartPointer<vtkPolyData> MergeParts(vtkCompositeDataSet* head)
{
  std::vector<std::string> names{ "Neutral" };
  std::vector<vtkPolyData*> parts = PolyDataLeaves(head);
  vtkIdType total = 0;
  for (vtkPolyData* part : parts)
  {
    for (const std::string& name : FieldStrings(part->GetFieldData(), "TargetNames"))
    {
      if (std::find(names.begin(), names.end(), name) == names.end())
      {
        names.push_back(name);
      }
    }
    total += part->GetNumberOfPoints();
  }
  auto merged = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkFloatArray> points, normals;
  points->SetNumberOfComponents(3);
  points->SetNumberOfTuples(total);
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(total);
  std::vector<vtkSmartPointer<vtkFloatArray>> deltas, normalDeltas;
  for (size_t k = 0; k + 1 < names.size(); ++k)
  {
    for (auto* list : { &deltas, &normalDeltas })
    {
      auto a = vtkSmartPointer<vtkFloatArray>::New();
      a->SetName(
        ("target" + std::to_string(k) + (list == &deltas ? "_position" : "_normal")).c_str());
      a->SetNumberOfComponents(3);
      a->SetNumberOfTuples(total);
      a->Fill(0.0);
      list->push_back(a);
    }
  }
  vtkNew<vtkCellArray> polys;
  vtkIdType offset = 0;
  for (vtkPolyData* part : parts)
  {
    const vtkIdType n = part->GetNumberOfPoints();
    const std::vector<std::string> own = FieldStrings(part->GetFieldData(), "TargetNames");
    for (vtkIdType i = 0; i < n; ++i)
    {
      points->SetTuple(offset + i, part->GetPoints()->GetData()->GetTuple(i));
      vtkDataArray* partNormals = part->GetPointData()->GetNormals();
      const double none[3] = { 0, 0, 0 };
      normals->SetTuple(offset + i, partNormals ? partNormals->GetTuple(i) : none);
    }
    for (size_t k = 1; k < own.size(); ++k)
    {
      const size_t m =
        static_cast<size_t>(std::find(names.begin(), names.end(), own[k]) - names.begin()) - 1;
      vtkDataArray* d =
        part->GetPointData()->GetArray(("target" + std::to_string(k - 1) + "_position").c_str());
      vtkDataArray* nd =
        part->GetPointData()->GetArray(("target" + std::to_string(k - 1) + "_normal").c_str());
      for (vtkIdType i = 0; i < n; ++i)
      {
        deltas[m]->SetTuple(offset + i, d->GetTuple(i));
        if (nd)
        {
          normalDeltas[m]->SetTuple(offset + i, nd->GetTuple(i));
        }
      }
    }
    const vtkIdType* cell = nullptr;
    vtkIdType size = 0;
    vtkCellArray* partPolys = part->GetPolys();
    for (partPolys->InitTraversal(); partPolys->GetNextCell(size, cell);)
    {
      std::vector<vtkIdType> ids(cell, cell + size);
      for (vtkIdType& id : ids)
      {
        id += offset;
      }
      polys->InsertNextCell(size, ids.data());
    }
    offset += n;
  }
  vtkNew<vtkPoints> p;
  p->SetData(points);
  merged->SetPoints(p);
  merged->SetPolys(polys);
  merged->GetPointData()->SetNormals(normals);
  for (size_t k = 0; k < deltas.size(); ++k)
  {
    merged->GetPointData()->AddArray(deltas[k]);
    merged->GetPointData()->AddArray(normalDeltas[k]);
  }
  vtkNew<vtkStringArray> targetNames;
  targetNames->SetName("TargetNames");
  for (const std::string& name : names)
  {
    targetNames->InsertNextValue(name);
  }
  merged->GetFieldData()->AddArray(targetNames);
  return merged;
}

} // namespace morphnode_test

#endif
