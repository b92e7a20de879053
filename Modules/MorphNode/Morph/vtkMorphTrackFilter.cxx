// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTrackFilter.h"

#include "vtkAlgorithmOutput.h"
#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationVector.h"
#include "vtkStreamingDemandDrivenPipeline.h"

//------------------------------------------------------------------------------
vtkMorphTrackFilter::vtkMorphTrackFilter()
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
void vtkMorphTrackFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Track: " << (this->GetNumberOfInputConnections(1) > 0 ? "connected" : "none")
     << "\n";
}
