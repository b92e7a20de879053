// SPDX-License-Identifier: BSD-3-Clause
// VTK's own glTF evaluation, the implementation the cross-check tests compare MorphNode with
// (TestGltfSceneCrossCheck, TestMorphNodeGLTFCrossCheck).
#ifndef MorphNodeGltfReaderParts_h
#define MorphNodeGltfReaderParts_h

#include "MorphNodeMergeParts.h"

#include "vtkGLTFReader.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <string>
#include <vector>

namespace morphnode_test
{
/// Every vtkPolyData leaf vtkGLTFReader makes of `file`, in its order (the scene's nodes
/// depth first, primitives in order: MorphNode's part order), with the mesh weights applied
/// to the geometry when `deform` is on.
inline std::vector<vtkSmartPointer<vtkPolyData>> VtkGltfReaderParts(
  const std::string& file, bool deform)
{
  vtkNew<vtkGLTFReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetApplyDeformationsToGeometry(deform);
  reader->Update();
  std::vector<vtkSmartPointer<vtkPolyData>> parts;
  for (vtkPolyData* leaf : PolyDataLeaves(reader->GetOutput()))
  {
    if (leaf)
    {
      parts.emplace_back(leaf);
    }
  }
  return parts;
}
} // namespace morphnode_test

#endif
