// SPDX-License-Identifier: BSD-3-Clause
#include "TimeSeriesWriter.h"

#include "ImageOutput.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <locale>
#include <stdexcept>

namespace morphnode
{
namespace appkit
{
TimeSeriesWriter::TimeSeriesWriter(const std::string& pvd)
  : Pvd(pvd)
{
  const std::filesystem::path path(pvd);
  std::string ext = path.extension().string();
  for (char& c : ext)
  {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (ext != ".pvd")
  {
    throw std::runtime_error("a time series needs a file name ending in .pvd, not '" + pvd + "'");
  }
  this->FolderPath = pvd.substr(0, pvd.size() - ext.size());
  this->Folder = std::filesystem::path(this->FolderPath).filename().string();
  MakeFolder(this->FolderPath);
}

void TimeSeriesWriter::Write(vtkPolyData* face, vtkTable* weights, double t)
{
  vtkNew<vtkPolyData> copy;
  copy->ShallowCopy(face);
  vtkNew<vtkFieldData> fieldData;
  fieldData->ShallowCopy(face->GetFieldData()); // the face's own stays untouched
  copy->SetFieldData(fieldData);
  if (weights && weights->GetNumberOfRows() > 0)
  {
    vtkNew<vtkDoubleArray> values;
    values->SetName("BehaviorWeights");
    vtkNew<vtkStringArray> channels;
    channels->SetName("BehaviorChannels");
    for (vtkIdType c = 0; c < weights->GetNumberOfColumns(); ++c)
    {
      channels->InsertNextValue(weights->GetColumnName(c));
      values->InsertNextValue(weights->GetValue(0, c).ToDouble());
    }
    fieldData->AddArray(values);
    fieldData->AddArray(channels);
  }
  vtkNew<vtkDoubleArray> time;
  time->SetName("TimeValue");
  time->InsertNextValue(t);
  fieldData->AddArray(time);

  char name[32];
  std::snprintf(name, sizeof(name), "face_%05d.vtp", static_cast<int>(this->Entries.size()));
  const std::string file = this->FolderPath + "/" + name;
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(copy);
  writer->SetFileName(file.c_str());
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  if (writer->Write() != 1)
  {
    throw std::runtime_error("cannot write " + file);
  }
  this->Entries.emplace_back(t, this->Folder + "/" + name);
}

void TimeSeriesWriter::Close()
{
  std::ofstream out(this->Pvd);
  out.imbue(std::locale::classic());
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& entry : this->Entries)
  {
    out << "    <DataSet timestep=\"" << std::setprecision(9) << entry.first
        << "\" group=\"\" part=\"0\" file=\"" << entry.second << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  out.close();
  if (!out)
  {
    throw std::runtime_error("cannot write " + this->Pvd);
  }
  std::cout << "wrote " << this->Pvd << " (" << this->Entries.size() << " time steps in "
            << this->FolderPath << "/)\n";
}
} // namespace appkit
} // namespace morphnode
