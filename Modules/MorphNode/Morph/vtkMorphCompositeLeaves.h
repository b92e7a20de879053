// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphCompositeLeaves
 * @brief   a composite output in its input's structure with other leaves (private to MorphNode)
 *
 * What the morph node and the filters that move parts (vtkMorphTrackFilter::MoveParts) do
 * with a composite input: the output takes the input's structure (names and metadata, the
 * data assembly of a vtkPartitionedDataSetCollection) and the k-th non-empty leaf of the
 * input (in vtk::Range's order) is replaced by the k-th of the leaves given. For a
 * vtkPartitionedDataSetCollection the partitioned data sets are kept across executions and
 * filled again when nothing else holds them: the executive empties the output before every
 * execution, and making the structure anew (a ShallowCopy or CopyStructure of an avatar's
 * seven partitioned data sets) cost as much as posing its skeleton.
 *
 * @sa vtkMorphNodeOutput vtkMorphTrackFilter
 */
#ifndef vtkMorphCompositeLeaves_h
#define vtkMorphCompositeLeaves_h

#include "vtkSmartPointer.h"

#include <vector>

class vtkCompositeDataSet;
class vtkDataObject;
class vtkPartitionedDataSet;

class vtkMorphCompositeLeaves
{
public:
  /// `output` in `input`'s structure, the k-th non-empty leaf replaced by `leaves[k]` (the
  /// structure's leaves past `leaves` left empty).
  void Place(vtkCompositeDataSet* input, const std::vector<vtkDataObject*>& leaves,
    vtkCompositeDataSet* output);
  /// The kept partitioned data sets that nothing else holds let go of their leaves (the
  /// last output's), so that a leaf kept by its maker can be written again in place: call
  /// before making this execution's leaves.
  void Release();

private:
  std::vector<vtkSmartPointer<vtkPartitionedDataSet>> Sets;
};

#endif
