// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTrackFilter.h"

#include "base/Error.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationVector.h"
#include "vtkMorphCompositeLeaves.h"
#include "vtkPointSet.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <vector>

namespace
{
/// A composite leaf's block name ("" without one) and its description for messages.
template <typename Node>
void NameOf(const Node& node, std::string& name, std::string& description)
{
  const bool named = node.HasMetaData() && node.GetMetaData()->Has(vtkCompositeDataSet::NAME());
  name = named ? node.GetMetaData()->Get(vtkCompositeDataSet::NAME()) : "";
  description = named ? "part '" + name + "'" : "part " + std::to_string(node.GetFlatIndex());
}
} // namespace

//------------------------------------------------------------------------------
vtkMorphTrackFilter::vtkMorphTrackFilter()
  : Leaves(new vtkMorphCompositeLeaves)
{
  this->SetNumberOfInputPorts(2);
}

//------------------------------------------------------------------------------
vtkMorphTrackFilter::~vtkMorphTrackFilter() = default;

//------------------------------------------------------------------------------
void vtkMorphTrackFilter::SetTrackConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
int vtkMorphTrackFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkMorphTrackFilter::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The track animates the head: its time steps win (the executive copies port 0's only).
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* trackInfo = inputVector[1]->GetInformationObject(0);
  for (vtkInformationDoubleVectorKey* key : { vtkStreamingDemandDrivenPipeline::TIME_STEPS(),
         vtkStreamingDemandDrivenPipeline::TIME_RANGE() })
  {
    if (trackInfo && trackInfo->Has(key))
    {
      outInfo->CopyEntry(trackInfo, key);
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkMorphTrackFilter::StampTime(vtkDataObject* output, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (output && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
      outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
  }
}

//------------------------------------------------------------------------------
bool vtkMorphTrackFilter::ReadTrackRow(vtkInformationVector* trackVector,
  std::initializer_list<TrackColumn> columns, const char* table, bool requireAll)
{
  vtkTable* track = trackVector ? vtkTable::GetData(trackVector, 0) : nullptr;
  if (!track)
  {
    return false;
  }
  for (const TrackColumn& column : columns)
  {
    if (requireAll && !vtkDataArray::SafeDownCast(track->GetColumnByName(column.Name)))
    {
      throw morphnode::InputError(
        std::string(table) + " has no numeric column '" + column.Name + "'");
    }
  }
  if (track->GetNumberOfRows() < 1)
  {
    throw morphnode::InputError(std::string(table) + " has no rows");
  }
  for (const TrackColumn& column : columns)
  {
    if (auto* values = vtkDataArray::SafeDownCast(track->GetColumnByName(column.Name)))
    {
      *column.Value = values->GetComponent(0, 0);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkMorphTrackFilter::MovePartsInPlace(
  vtkDataObject* data, const MovePart& move, const char* what)
{
  int moved = 0;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    for (auto node : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      if (auto* points = vtkPointSet::SafeDownCast(node))
      {
        std::string name, description;
        NameOf(node, name, description);
        moved += move(points, name, description) ? 1 : 0;
      }
    }
    return moved;
  }
  if (auto* points = vtkPointSet::SafeDownCast(data))
  {
    return move(points, std::string(), "the input") ? 1 : 0;
  }
  throw morphnode::InputError(
    std::string("cannot ") + what + " a " + (data ? data->GetClassName() : "null data set"));
}

//------------------------------------------------------------------------------
bool vtkMorphTrackFilter::MoveInPlace(vtkInformationVector*, vtkDataObject*)
{
  vtkErrorMacro(<< this->GetClassName() << " cannot move parts inside another filter's pass");
  return false;
}

//------------------------------------------------------------------------------
int vtkMorphTrackFilter::MoveParts(
  vtkDataObject* input, vtkDataObject* output, const MovePart& move, const char* what)
{
  int moved = 0;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    // The last output's leaves let go first (a mover may write its kept leaf again).
    this->Leaves->Release();
    std::vector<vtkDataObject*> leaves;
    for (auto node : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      vtkDataObject* leaf = node;
      vtkPointSet* part = nullptr;
      if (auto* points = vtkPointSet::SafeDownCast(leaf))
      {
        std::string name, description;
        NameOf(node, name, description);
        part = move(points, name, description);
        moved += part ? 1 : 0;
      }
      leaves.push_back(part ? part : leaf);
    }
    auto* out = vtkCompositeDataSet::SafeDownCast(output);
    this->Leaves->Place(composite, leaves, out);
    out->GetFieldData()->ShallowCopy(composite->GetFieldData()); // the head's own (TargetNames)
    return moved;
  }
  if (auto* points = vtkPointSet::SafeDownCast(input))
  {
    auto* out = vtkPointSet::SafeDownCast(output);
    out->Initialize();
    vtkPointSet* part = move(points, std::string(), "the input");
    out->ShallowCopy(part ? part : points);
    return part ? 1 : 0;
  }
  throw morphnode::InputError(
    std::string("cannot ") + what + " a " + (input ? input->GetClassName() : "null input"));
}

//------------------------------------------------------------------------------
void vtkMorphTrackFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Track: " << (this->GetNumberOfInputConnections(1) > 0 ? "connected" : "none")
     << "\n";
}
