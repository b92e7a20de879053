// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTrackSource.h"

#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkStreamingDemandDrivenPipeline.h"

//------------------------------------------------------------------------------
vtkMorphTrackSource::vtkMorphTrackSource()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
vtkMorphTrackSource::~vtkMorphTrackSource() = default;

//------------------------------------------------------------------------------
int vtkMorphTrackSource::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
  return 1;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkMorphTrackSource::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A request on port 0 (a time step) need not build the whole track of port 1: mark it
  // as not generated, so it stays out of date and executes when port 1 is asked for.
  if (this->GetNumberOfOutputPorts() > 1 &&
    request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_NOT_GENERATED()) &&
    request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) &&
    request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) == 0)
  {
    outputVector->GetInformationObject(1)->Set(vtkDemandDrivenPipeline::DATA_NOT_GENERATED(), 1);
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
void vtkMorphTrackSource::ClearTimeInformation(vtkInformationVector* outputVector)
{
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
}

//------------------------------------------------------------------------------
void vtkMorphTrackSource::SetTimeInformation(
  vtkInformationVector* outputVector, const double* steps, int numberOfSteps, double end)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (numberOfSteps > 0)
  {
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps, numberOfSteps);
  }
  const double range[2] = { 0.0, end };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
}

//------------------------------------------------------------------------------
double vtkMorphTrackSource::RequestedTime(vtkInformationVector* outputVector)
{
  vtkInformation* frameInfo = outputVector->GetInformationObject(0);
  return frameInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    ? frameInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    : 0.0;
}

//------------------------------------------------------------------------------
bool vtkMorphTrackSource::IsTrackWanted(vtkInformationVector* outputVector)
{
  return outputVector->GetNumberOfInformationObjects() > 1 &&
    !outputVector->GetInformationObject(1)->Get(vtkDemandDrivenPipeline::DATA_NOT_GENERATED());
}

//------------------------------------------------------------------------------
void vtkMorphTrackSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
