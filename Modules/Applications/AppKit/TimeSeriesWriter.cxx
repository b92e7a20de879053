// SPDX-License-Identifier: BSD-3-Clause
#include "TimeSeriesWriter.h"

#include "base/File.h"
#include "base/Text.h"

#include "HeadActors.h"
#include "ImageOutput.h"
#include "vtkMorphPartData.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkXMLMultiBlockDataWriter.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <locale>
#include <sstream>
#include <stdexcept>
#include <string>

namespace morphnode
{
namespace appkit
{
TimeSeriesWriter::TimeSeriesWriter(const std::string& pvd)
  : Pvd(pvd)
{
  const std::filesystem::path path(pvd);
  const std::string ext = path.extension().string();
  if (text::ToLower(ext) != ".pvd")
  {
    throw std::runtime_error("a time series needs a file name ending in .pvd, not '" + pvd + "'");
  }
  this->FolderPath = pvd.substr(0, pvd.size() - ext.size());
  this->Folder = std::filesystem::path(this->FolderPath).filename().string();
  MakeFolder(this->FolderPath);
}

void TimeSeriesWriter::Write(vtkDataObject* face, vtkTable* weights, double t)
{
  // The step's field data: the weights and the time, added to every part.
  vtkNew<vtkFieldData> step;
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
    step->AddArray(values);
    step->AddArray(channels);
  }
  vtkNew<vtkDoubleArray> time;
  time->SetName("TimeValue");
  time->InsertNextValue(t);
  step->AddArray(time);
  auto withStep = [&step](vtkPolyData* part)
  {
    auto copy = vtkSmartPointer<vtkPolyData>::New();
    copy->ShallowCopy(part);
    vtkNew<vtkFieldData> fieldData;
    fieldData->ShallowCopy(part->GetFieldData()); // the part's own stays untouched
    // A textured part's images (field data <Slot>Image, megabytes each) would be written
    // again in every step: they stay in the glTF file.
    for (const char* slot : vtkMorphPartData::TextureSlots)
    {
      fieldData->RemoveArray(vtkMorphPartData::ImageArray(slot).c_str());
    }
    for (int a = 0; a < step->GetNumberOfArrays(); ++a)
    {
      fieldData->AddArray(step->GetAbstractArray(a));
    }
    copy->SetFieldData(fieldData);
    return copy;
  };

  const std::vector<vtkPolyData*> parts = HeadParts(face);
  if (parts.empty())
  {
    throw std::runtime_error("a time step needs a polydata or a composite of polydata parts");
  }
  const bool onePart = vtkPolyData::SafeDownCast(face) != nullptr;
  char name[32];
  std::snprintf(name, sizeof(name), "face_%05d.%s", static_cast<int>(this->Entries.size()),
    onePart ? "vtp" : "vtm");
  const std::string file = this->FolderPath + "/" + name;
  vtkSmartPointer<vtkXMLWriter> writer;
  if (onePart)
  {
    auto polyWriter = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    polyWriter->SetInputData(withStep(parts[0]));
    writer = polyWriter;
  }
  else
  {
    vtkNew<vtkMultiBlockDataSet> blocks;
    blocks->SetNumberOfBlocks(static_cast<unsigned int>(parts.size()));
    for (size_t i = 0; i < parts.size(); ++i)
    {
      const auto block = static_cast<unsigned int>(i);
      blocks->SetBlock(block, withStep(parts[i]));
      const std::string label =
        vtkMorphPartData::GetPartName(parts[i]->GetFieldData(), "part " + std::to_string(i));
      blocks->GetMetaData(block)->Set(vtkCompositeDataSet::NAME(), label.c_str());
    }
    auto blockWriter = vtkSmartPointer<vtkXMLMultiBlockDataWriter>::New();
    blockWriter->SetInputData(blocks);
    writer = blockWriter;
  }
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
  std::ostringstream out; // written safely below (base/File.h)
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
  morphnode::file::WriteFileSafely(this->Pvd, out.str(), "--pvd");
  std::cout << "wrote " << this->Pvd << " (" << this->Entries.size() << " time steps in "
            << this->FolderPath << "/)\n";
}
} // namespace appkit
} // namespace morphnode
