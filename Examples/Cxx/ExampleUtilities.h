// SPDX-License-Identifier: BSD-3-Clause
// Small helpers the example and study programs share (header-only; not part of the API).
#ifndef MorphNodeExampleUtilities_h
#define MorphNodeExampleUtilities_h

#include "vtkContextView.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkRenderWindow.h"
#include "vtkWindowToImageFilter.h"

#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace morphnode_examples
{
/// "0.1,0.2,0.3" -> {0.1, 0.2, 0.3}; empty items are skipped, a bad number throws
/// std::invalid_argument (std::stod).
inline std::vector<double> ParseList(const std::string& text)
{
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    if (!item.empty())
    {
      values.push_back(std::stod(item));
    }
  }
  return values;
}

/// Renders a chart view offscreen (no multisampling, so files are reproducible) to a PNG,
/// creating the file's folder if needed. Throws std::runtime_error when it cannot write.
inline void WritePng(vtkContextView* view, const std::string& file)
{
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();
  std::error_code ec;
  if (!folder.empty())
  {
    std::filesystem::create_directories(folder, ec);
  }
  view->GetRenderWindow()->SetMultiSamples(0);
  view->GetRenderWindow()->OffScreenRenderingOn();
  view->GetRenderWindow()->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(view->GetRenderWindow());
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (ec || writer->GetErrorCode() != 0)
  {
    throw std::runtime_error("cannot write the image '" + file + "'" +
      (ec ? " (" + ec.message() + ")" : std::string()));
  }
}
} // namespace morphnode_examples

#endif
