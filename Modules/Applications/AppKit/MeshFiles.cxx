// SPDX-License-Identifier: BSD-3-Clause
#include "MeshFiles.h"

#include "base/Error.h"
#include "base/Text.h"

#include "vtkCellArray.h"
#include "vtkCleanPolyData.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkPLYReader.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSTLReader.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleFilter.h"
#include "vtkXMLPolyDataReader.h"

#include <cmath>
#include <filesystem>

namespace morphnode
{
namespace appkit
{
GltfScene ReadMeshScene(const std::string& fileName)
{
  const std::string ext = text::ToLower(std::filesystem::path(fileName).extension().string());
  if (ext == ".glb" || ext == ".gltf")
  {
    return LoadGltfScene(fileName);
  }
  if (!std::filesystem::is_regular_file(fileName))
  {
    throw InputError(fileName + ": no such file");
  }
  vtkSmartPointer<vtkAlgorithm> reader;
  bool weld = false;
  if (ext == ".obj")
  {
    auto r = vtkSmartPointer<vtkOBJReader>::New();
    r->SetFileName(fileName.c_str());
    reader = r;
  }
  else if (ext == ".ply")
  {
    auto r = vtkSmartPointer<vtkPLYReader>::New();
    r->SetFileName(fileName.c_str());
    reader = r;
  }
  else if (ext == ".stl")
  {
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(fileName.c_str());
    reader = r;
    weld = true;
  }
  else if (ext == ".vtp")
  {
    auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    r->SetFileName(fileName.c_str());
    reader = r;
  }
  else
  {
    throw InputError(fileName + ": unknown mesh format (glb, gltf, obj, ply, stl or vtp)");
  }
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(reader->GetOutputPort());
  triangles->PassVertsOff();
  triangles->PassLinesOff();
  vtkNew<vtkCleanPolyData> clean;
  vtkAlgorithm* last = triangles;
  if (weld)
  {
    clean->SetInputConnection(triangles->GetOutputPort());
    clean->PointMergingOn();
    clean->SetTolerance(0.0);
    last = clean;
  }
  last->Update();
  vtkPolyData* mesh = vtkPolyData::SafeDownCast(last->GetOutputDataObject(0));
  if (!mesh || mesh->GetNumberOfPolys() == 0 || reader->GetErrorCode() != 0)
  {
    throw InputError(fileName + ": no triangles could be read");
  }
  GltfScene scene;
  scene.Scene = 0;
  GltfNode node;
  node.Name = "Mesh";
  node.Mesh = 0;
  node.InScene = true;
  scene.Nodes.push_back(node);
  GltfMesh gm;
  gm.Name = "Mesh";
  gm.NumberOfPrimitives = 1;
  scene.Meshes.push_back(gm);
  GltfPart part;
  part.Name = "Mesh";
  part.Node = 0;
  part.Mesh = 0;
  part.Primitive = 0;
  part.TransformApplied = true;
  const vtkIdType n = mesh->GetNumberOfPoints();
  part.Positions.resize(3 * size_t(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    mesh->GetPoint(i, p);
    for (int k = 0; k < 3; ++k)
    {
      if (!std::isfinite(p[k]))
      {
        throw InputError(fileName + ": point " + std::to_string(i) + " is not finite");
      }
      part.Positions[3 * size_t(i) + size_t(k)] = float(p[k]);
    }
  }
  vtkCellArray* polys = mesh->GetPolys();
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (polys->InitTraversal(); polys->GetNextCell(npts, pts);)
  {
    if (npts != 3)
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      part.Triangles.push_back(uint32_t(pts[k]));
    }
  }
  scene.Parts.push_back(std::move(part));
  return scene;
}
} // namespace appkit
} // namespace morphnode
