// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphCompositeLeaves.h"

#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"

//------------------------------------------------------------------------------
void vtkMorphCompositeLeaves::Release()
{
  for (auto& set : this->Sets)
  {
    if (set && set->GetReferenceCount() == 1)
    {
      set->Initialize();
    }
  }
}

//------------------------------------------------------------------------------
void vtkMorphCompositeLeaves::Place(vtkCompositeDataSet* input,
  const std::vector<vtkDataObject*>& leaves, vtkCompositeDataSet* output)
{
  auto* collection = vtkPartitionedDataSetCollection::SafeDownCast(input);
  auto* outCollection = vtkPartitionedDataSetCollection::SafeDownCast(output);
  if (!collection || !outCollection)
  {
    // The copied structure's leaves are all empty: walk both without skipping empty nodes
    // (same structure, same order) and fill the output where the input has a leaf.
    output->CopyStructure(input);
    const auto outNodes = vtk::Range(output);
    auto out = outNodes.begin();
    size_t k = 0;
    for (vtkDataObject* leaf : vtk::Range(input))
    {
      if (out == outNodes.end() || k == leaves.size())
      {
        break;
      }
      if (leaf)
      {
        *out = leaves[k++];
      }
      ++out;
    }
    return;
  }
  // The input's partitioned data sets, names and metadata, with the leaves, in the
  // iterator's order.
  const unsigned int numSets = collection->GetNumberOfPartitionedDataSets();
  outCollection->SetNumberOfPartitionedDataSets(numSets);
  this->Sets.resize(numSets);
  size_t k = 0;
  for (unsigned int d = 0; d < numSets; ++d)
  {
    vtkPartitionedDataSet* in = collection->GetPartitionedDataSet(d);
    vtkSmartPointer<vtkPartitionedDataSet>& out = this->Sets[d];
    if (!in)
    {
      outCollection->SetPartitionedDataSet(d, nullptr);
      continue;
    }
    if (!out || out->GetReferenceCount() != 1)
    {
      out = vtkSmartPointer<vtkPartitionedDataSet>::New();
    }
    out->Initialize();
    const unsigned int numPartitions = in->GetNumberOfPartitions();
    out->SetNumberOfPartitions(numPartitions);
    for (unsigned int i = 0; i < numPartitions; ++i)
    {
      if (in->GetPartitionAsDataObject(i) && k < leaves.size())
      {
        out->SetPartition(i, leaves[k++]);
      }
      if (in->HasMetaData(i))
      {
        out->GetMetaData(i)->Copy(in->GetMetaData(i));
      }
    }
    outCollection->SetPartitionedDataSet(d, out);
    if (collection->HasMetaData(d))
    {
      outCollection->GetMetaData(d)->Copy(collection->GetMetaData(d));
    }
  }
  outCollection->SetDataAssembly(collection->GetDataAssembly());
}
