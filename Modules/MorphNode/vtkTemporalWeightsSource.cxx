// SPDX-License-Identifier: BSD-3-Clause
#include "vtkTemporalWeightsSource.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkStreamingDemandDrivenPipeline.h"

//------------------------------------------------------------------------------
vtkTypeBool vtkTemporalWeightsSource::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A request on port 0 (a time step) need not build the whole track of port 1: mark it
  // as not generated, so it stays out of date and executes when port 1 is asked for.
  if (this->GetNumberOfOutputPorts() > 1 && request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_NOT_GENERATED()) &&
    request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) &&
    request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) == 0)
  {
    outputVector->GetInformationObject(1)->Set(vtkDemandDrivenPipeline::DATA_NOT_GENERATED(), 1);
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
double vtkTemporalWeightsSource::GetRequestedTime(vtkInformation* outInfo)
{
  return outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    : 0.0;
}

//------------------------------------------------------------------------------
bool vtkTemporalWeightsSource::IsTrackRequested(vtkInformationVector* outputVector)
{
  return this->GetNumberOfOutputPorts() > 1 &&
    !outputVector->GetInformationObject(1)->Get(vtkDemandDrivenPipeline::DATA_NOT_GENERATED());
}

//------------------------------------------------------------------------------
void vtkTemporalWeightsSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Track port: " << (this->GetNumberOfOutputPorts() > 1 ? "1" : "(none)") << "\n";
}
