// SPDX-License-Identifier: BSD-3-Clause
#include "ImageOutput.h"

#include "base/File.h"

#include "vtkContextView.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkRenderWindow.h"
#include "vtkWindowToImageFilter.h"

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace morphnode
{
namespace appkit
{
void MakeFolder(const std::string& folder)
{
  if (folder.empty())
  {
    return;
  }
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec)
  {
    throw std::runtime_error("cannot create the folder '" + folder + "' (" + ec.message() + ")");
  }
}

void WritePng(vtkRenderWindow* window, const std::string& file)
{
  MakeFolder(std::filesystem::path(file).parent_path().string());
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  // Beside the target, renamed onto it when complete (base/File.h): a failed write leaves
  // the old image alone; a link, device or directory at the path is refused.
  morphnode::file::SafeOutput out(file, "image");
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(out.GetTemporaryPath().c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0)
  {
    throw std::runtime_error("cannot write the image '" + file +
      "' (the disk is full or the folder not writable); the old file, if any, is unchanged");
  }
  out.Commit();
}

void WritePng(vtkContextView* view, const std::string& file)
{
  view->GetRenderWindow()->SetMultiSamples(0);
  view->GetRenderWindow()->OffScreenRenderingOn();
  view->GetRenderWindow()->Render();
  WritePng(view->GetRenderWindow(), file);
}
} // namespace appkit
} // namespace morphnode
