// SPDX-License-Identifier: BSD-3-Clause
#include "vtkLiveLinkFaceReader.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "capture/ArkitNames.h"
#include "capture/LiveLinkCsv.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTimeStamp.h"

#include <exception>
#include <vector>

vtkStandardNewMacro(vtkLiveLinkFaceReader);

struct vtkLiveLinkFaceReader::vtkInternals
{
  vtkSmartPointer<vtkStringArray> TargetNames;
  // The file as last read, and when (any change of the reader, Modified() included, reads
  // it again).
  bool Read = false;
  vtkTimeStamp ReadTime;
  morphnode::LiveLinkCapture Capture;
  // The mapping of the last execution.
  std::vector<std::string> Channels;
  std::vector<std::string> Unmapped;
  std::string Report;
};

namespace
{
bool IsAngle(const std::string& name)
{
  return morphnode::FindArkitShape(name) < 0;
}
} // namespace

//------------------------------------------------------------------------------
vtkLiveLinkFaceReader::vtkLiveLinkFaceReader()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(2);
}

vtkLiveLinkFaceReader::~vtkLiveLinkFaceReader() = default;

//------------------------------------------------------------------------------
void vtkLiveLinkFaceReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "TimecodeRate: " << this->TimecodeRate << "\n";
  os << indent << "PoseDegreesPerUnit: " << this->PoseDegreesPerUnit << "\n";
  os << indent << "TargetNames: ";
  if (this->Internals->TargetNames)
  {
    os << this->Internals->TargetNames->GetNumberOfValues() << " names\n";
  }
  else
  {
    os << "(none)\n";
  }
  os << indent << "Rows: " << this->Internals->Capture.GetNumberOfRows() << "\n";
  os << indent << "MappingReport: " << this->Internals->Report << "\n";
}

//------------------------------------------------------------------------------
int vtkLiveLinkFaceReader::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkLiveLinkFaceReader::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
  return 1;
}

void vtkLiveLinkFaceReader::SetFaceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(0, output);
}

//------------------------------------------------------------------------------
void vtkLiveLinkFaceReader::SetTargetNames(vtkStringArray* names)
{
  if (vtkMorphTargetArrays::AssignTargetNames(this->Internals->TargetNames, names))
  {
    this->Modified();
  }
}

vtkStringArray* vtkLiveLinkFaceReader::GetTargetNames()
{
  return this->Internals->TargetNames;
}

//------------------------------------------------------------------------------
vtkIdType vtkLiveLinkFaceReader::GetNumberOfRows()
{
  return static_cast<vtkIdType>(this->Internals->Capture.GetNumberOfRows());
}

double vtkLiveLinkFaceReader::GetDuration()
{
  return this->Internals->Capture.GetDuration();
}

int vtkLiveLinkFaceReader::GetNumberOfChannels()
{
  return static_cast<int>(this->Internals->Channels.size());
}

const char* vtkLiveLinkFaceReader::GetChannelName(int index)
{
  const auto& names = this->Internals->Channels;
  return index >= 0 && static_cast<size_t>(index) < names.size() ? names[static_cast<size_t>(index)].c_str() : nullptr;
}

int vtkLiveLinkFaceReader::GetNumberOfUnmappedNames()
{
  return static_cast<int>(this->Internals->Unmapped.size());
}

const char* vtkLiveLinkFaceReader::GetUnmappedName(int index)
{
  const auto& names = this->Internals->Unmapped;
  return index >= 0 && static_cast<size_t>(index) < names.size() ? names[static_cast<size_t>(index)].c_str() : nullptr;
}

const char* vtkLiveLinkFaceReader::GetMappingReport()
{
  return this->Internals->Report.c_str();
}

//------------------------------------------------------------------------------
bool vtkLiveLinkFaceReader::EnsureRead()
{
  vtkInternals& internals = *this->Internals;
  if (internals.Read && internals.ReadTime > this->GetMTime())
  {
    return true;
  }
  internals.Read = false;
  internals.Capture = morphnode::LiveLinkCapture();
  internals.Channels.clear();
  internals.Unmapped.clear();
  internals.Report.clear();
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "no FileName");
    return false;
  }
  try
  {
    morphnode::LiveLinkOptions options;
    options.TimecodeRate = this->TimecodeRate;
    options.PoseDegreesPerUnit = this->PoseDegreesPerUnit;
    internals.Capture = morphnode::ReadLiveLinkCsvFile(this->FileName, options);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    return false;
  }
  internals.Read = true;
  internals.ReadTime.Modified();
  return true;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkLiveLinkFaceReader::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A time step on port 0 need not build the whole take of port 1 (as vtkBehaviorTimeSource).
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_NOT_GENERATED()) &&
    request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) &&
    request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) == 0)
  {
    outputVector->GetInformationObject(1)->Set(vtkDemandDrivenPipeline::DATA_NOT_GENERATED(), 1);
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkLiveLinkFaceReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  if (!this->EnsureRead())
  {
    return 0;
  }
  const auto& times = this->Internals->Capture.Times;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
  double range[2] = { 0.0, this->Internals->Capture.GetDuration() };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

//------------------------------------------------------------------------------
int vtkLiveLinkFaceReader::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* frameInfo = outputVector->GetInformationObject(0);
  vtkTable* frame = vtkTable::GetData(outputVector, 0);
  vtkTable* take = vtkTable::GetData(outputVector, 1);
  if (!frame || !take)
  {
    vtkErrorMacro(<< "the outputs are not vtkTables");
    return 0;
  }
  frame->Initialize();
  const bool takeWanted = !outputVector->GetInformationObject(1)->Get(vtkDemandDrivenPipeline::DATA_NOT_GENERATED());
  if (takeWanted)
  {
    take->Initialize();
  }
  vtkInternals& internals = *this->Internals;
  internals.Channels.clear();
  internals.Unmapped.clear();
  internals.Report.clear();
  if (!this->EnsureRead())
  {
    return 0;
  }
  const morphnode::LiveLinkCapture& capture = internals.Capture;

  // The face's target names: the connected face, else SetTargetNames(), else none.
  std::vector<std::string> targets;
  if (this->GetNumberOfInputConnections(0) > 0)
  {
    if (!vtkMorphTargetArrays::GetFaceTargetNames(vtkDataObject::GetData(inputVector[0], 0), targets))
    {
      vtkErrorMacro(<< "the face on input port 0 has no field data '" << vtkMorphTargetArrays::TargetNamesArray
                    << "' (neutral first)");
      return 0;
    }
  }
  else if (internals.TargetNames)
  {
    for (vtkIdType i = 1; i < internals.TargetNames->GetNumberOfValues(); ++i)
    {
      targets.push_back(internals.TargetNames->GetValue(i));
    }
  }

  // Output column c = capture channel Source[c] (Mapped: through the rig instead).
  std::vector<int> source;
  std::vector<int> shapeChannel(morphnode::ArkitShapeCount, -1);
  morphnode::Rig rig;
  const bool mapped = !targets.empty();
  internals.Unmapped = capture.UnknownColumns;
  try
  {
    if (mapped)
    {
      morphnode::ArkitFaceMapping mapping;
      rig = morphnode::MakeArkitRig(targets, &mapping);
      internals.Channels = targets;
      source.assign(targets.size(), -1);
      for (size_t c = 0; c < capture.Channels.size(); ++c)
      {
        const int s = morphnode::FindArkitShape(capture.Channels[c]);
        if (s >= 0)
        {
          shapeChannel[static_cast<size_t>(s)] = static_cast<int>(c);
          if (mapping.Targets[static_cast<size_t>(s)].empty())
          {
            internals.Unmapped.push_back(capture.Channels[c]);
          }
        }
      }
      internals.Report = mapping.Report();
    }
    else
    {
      internals.Report = "no face: the " + std::to_string(morphnode::ArkitShapeCount - capture.MissingShapes.size()) +
        " ARKit shapes of the take by Apple's names";
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    internals.Channels.clear();
    return 0;
  }
  for (size_t c = 0; c < capture.Channels.size(); ++c)
  {
    if (!mapped || IsAngle(capture.Channels[c]))
    {
      internals.Channels.push_back(capture.Channels[c]);
      source.push_back(static_cast<int>(c));
    }
  }
  if (!internals.Unmapped.empty())
  {
    internals.Report += "; names that map to nothing:";
    for (const auto& name : internals.Unmapped)
    {
      internals.Report += " " + name;
    }
  }

  // One row of output values at `time`.
  std::vector<double> shapes(morphnode::ArkitShapeCount, 0.0);
  std::vector<double> row(internals.Channels.size(), 0.0);
  auto fill = [&](double time) {
    size_t first = 0;
    if (mapped)
    {
      for (size_t s = 0; s < shapes.size(); ++s)
      {
        shapes[s] = shapeChannel[s] >= 0 ? capture.Sample(time, static_cast<size_t>(shapeChannel[s])) : 0.0;
      }
      rig.Expand(shapes.data(), row.data());
      first = rig.GetNumberOfBoundTargets();
    }
    for (size_t c = first; c < row.size(); ++c)
    {
      row[c] = capture.Sample(time, static_cast<size_t>(source[c]));
    }
  };
  const double t = frameInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    ? frameInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    : 0.0;
  try
  {
    fill(t);
    for (size_t c = 0; c < row.size(); ++c)
    {
      vtkNew<vtkDoubleArray> column;
      column->SetName(internals.Channels[c].c_str());
      column->InsertNextValue(row[c]);
      frame->AddColumn(column);
    }
    frame->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), t);
    if (takeWanted)
    {
      const vtkIdType rows = static_cast<vtkIdType>(capture.GetNumberOfRows());
      std::vector<vtkSmartPointer<vtkDoubleArray>> columns(row.size() + 1);
      for (size_t c = 0; c < columns.size(); ++c)
      {
        columns[c] = vtkSmartPointer<vtkDoubleArray>::New();
        columns[c]->SetName(c == 0 ? "Time" : internals.Channels[c - 1].c_str());
        columns[c]->SetNumberOfValues(rows);
      }
      for (vtkIdType r = 0; r < rows; ++r)
      {
        const double time = capture.Times[static_cast<size_t>(r)];
        fill(time);
        columns[0]->SetValue(r, time);
        for (size_t c = 0; c < row.size(); ++c)
        {
          columns[c + 1]->SetValue(r, row[c]);
        }
        if (r % 1024 == 0)
        {
          this->UpdateProgress(static_cast<double>(r) / static_cast<double>(rows));
        }
      }
      for (const auto& column : columns)
      {
        take->AddColumn(column);
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    frame->Initialize();
    take->Initialize();
    return 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}
