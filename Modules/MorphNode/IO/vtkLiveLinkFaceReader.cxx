// SPDX-License-Identifier: BSD-3-Clause
#include "vtkLiveLinkFaceReader.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "capture/CaptureMapping.h"
#include "capture/LiveLinkCsv.h"

#include "vtkAlgorithmOutput.h"
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
#include <memory>
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

  /// The face's target names (relative, no neutral): the connected face's, else
  /// SetTargetNames()'s, else none. False (an error reported) for a face without TargetNames.
  bool FaceTargets(vtkLiveLinkFaceReader* self, vtkInformationVector** inputVector,
    std::vector<std::string>& targets)
  {
    if (self->GetNumberOfInputConnections(0) > 0)
    {
      if (!vtkMorphTargetArrays::GetFaceTargetNames(
            vtkDataObject::GetData(inputVector[0], 0), targets))
      {
        vtkErrorWithObjectMacro(self, << "the face on input port 0 has no field data '"
                                      << vtkMorphTargetArrays::TargetNamesArray
                                      << "' (neutral first)");
        return false;
      }
    }
    else if (this->TargetNames)
    {
      for (vtkIdType i = 1; i < this->TargetNames->GetNumberOfValues(); ++i)
      {
        targets.push_back(this->TargetNames->GetValue(i));
      }
    }
    return true;
  }
};

//------------------------------------------------------------------------------
vtkLiveLinkFaceReader::vtkLiveLinkFaceReader()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(1);
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
  return index >= 0 && static_cast<size_t>(index) < names.size()
    ? names[static_cast<size_t>(index)].c_str()
    : nullptr;
}

int vtkLiveLinkFaceReader::GetNumberOfUnmappedNames()
{
  return static_cast<int>(this->Internals->Unmapped.size());
}

const char* vtkLiveLinkFaceReader::GetUnmappedName(int index)
{
  const auto& names = this->Internals->Unmapped;
  return index >= 0 && static_cast<size_t>(index) < names.size()
    ? names[static_cast<size_t>(index)].c_str()
    : nullptr;
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
int vtkLiveLinkFaceReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkMorphTrackSource::ClearTimeInformation(outputVector);
  if (!this->EnsureRead())
  {
    return 0;
  }
  const auto& times = this->Internals->Capture.Times;
  vtkMorphTrackSource::SetTimeInformation(outputVector, times.data(),
    static_cast<int>(times.size()), this->Internals->Capture.GetDuration());
  return 1;
}

//------------------------------------------------------------------------------
int vtkLiveLinkFaceReader::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkTable* frame = vtkTable::GetData(outputVector, 0);
  vtkTable* take = vtkTable::GetData(outputVector, 1);
  if (!frame || !take)
  {
    vtkErrorMacro(<< "the outputs are not vtkTables");
    return 0;
  }
  frame->Initialize();
  const bool takeWanted = vtkMorphTrackSource::IsTrackWanted(outputVector);
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

  std::vector<std::string> targets;
  if (!internals.FaceTargets(this, inputVector, targets))
  {
    return 0;
  }

  // The capture's channels as the face's (capture/CaptureMapping.h).
  std::unique_ptr<morphnode::CaptureFaceMapping> mapping;
  try
  {
    mapping = std::make_unique<morphnode::CaptureFaceMapping>(capture, targets);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  internals.Channels = mapping->GetChannels();
  internals.Unmapped = mapping->GetUnmapped();
  internals.Report = mapping->GetReport();
  std::vector<double> row(internals.Channels.size(), 0.0);
  auto fill = [&](double time) { mapping->Sample(time, row.data()); };
  const double t = vtkMorphTrackSource::RequestedTime(outputVector);
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
