// SPDX-License-Identifier: BSD-3-Clause
// Helpers shared by the VTK-level tests.
#ifndef MorphNodeTestUtilities_h
#define MorphNodeTestUtilities_h

#include "vtkCommand.h"
#include "vtkImageDifference.h"
#include "vtkImageExtractComponents.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPNGReader.h"
#include "vtkPNGWriter.h"
#include "vtkRenderWindow.h"
#include "vtkSmartPointer.h"
#include "vtkTesting.h"
#include "vtkWindowToImageFilter.h"

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace morphnode_test
{
/// Collects vtkErrorMacro / vtkWarningMacro messages of the objects it observes, so that
/// tests check for a clear message instead of letting it print.
class MessageCollector : public vtkCommand
{
public:
  static MessageCollector* New() { return new MessageCollector; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string text = data ? static_cast<const char*>(data) : "";
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings).push_back(text);
  }
  void Watch(vtkObject* object)
  {
    object->AddObserver(vtkCommand::ErrorEvent, this);
    object->AddObserver(vtkCommand::WarningEvent, this);
  }
  bool HasError(const std::string& fragment) const
  {
    for (const auto& e : this->Errors)
    {
      if (e.find(fragment) != std::string::npos)
      {
        return true;
      }
    }
    return false;
  }
  std::string AllErrors() const
  {
    std::string all;
    for (const auto& e : this->Errors)
    {
      all += e + "\n";
    }
    return all;
  }
  void Clear()
  {
    this->Errors.clear();
    this->Warnings.clear();
  }
  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;
};

/// Compares the render window with a baseline PNG (VTK's legacy image metric; 10 is
/// VTK's usual threshold). On failure the test image lands in `outputDir`; a missing
/// baseline fails too, after writing the image that would become the baseline.
inline bool MatchesBaseline(vtkRenderWindow* window, const std::string& baseline,
  const std::string& outputDir, double threshold = 10.0)
{
  vtkNew<vtkTesting> testing;
  testing->AddArgument("-V");
  testing->AddArgument(baseline.c_str());
  testing->AddArgument("-T");
  testing->AddArgument(outputDir.c_str());
  testing->SetRenderWindow(window);
  return testing->RegressionTest(threshold) == vtkTesting::PASSED;
}
/// VTK's legacy image error of the render window against a baseline PNG (what
/// MatchesBaseline compares with its threshold), or -1 when none could be computed. Lets a
/// test choose a threshold that sees what it is about and prove it with a negative control.
inline double BaselineError(
  vtkRenderWindow* window, const std::string& baseline, const std::string& outputDir)
{
  vtkNew<vtkTesting> testing;
  testing->AddArgument("-V");
  testing->AddArgument(baseline.c_str());
  testing->AddArgument("-T");
  testing->AddArgument(outputDir.c_str());
  testing->SetRenderWindow(window);
  std::ostringstream os;
  testing->RegressionTest(1e30, os);
  const std::string text = os.str();
  const std::string tag = "name=\"ImageError\"";
  const size_t at = text.find(tag);
  const size_t start = at == std::string::npos ? at : text.find('>', at);
  return start == std::string::npos ? -1.0 : std::atof(text.c_str() + start + 1);
}
/// The legacy metric of MatchesBaseline (vtkImageDifference: 3 x 3 averaging, shifts of up
/// to two pixels, the error summed over pixels that still differ), with a per-channel
/// tolerance of `tolerance` levels instead of vtkTesting's fixed 105. glTF materials drawn
/// gamma-correct (docs/materials.md) are paler and of lower contrast: an open mouth differs
/// from skin by 40 to 90 levels a channel, which 105 does not see. -1 when the baseline
/// cannot be read. The render is written to `outputDir`/<baseline name>-test.png.
inline double SensitiveBaselineError(vtkRenderWindow* window, const std::string& baseline,
  const std::string& outputDir, int tolerance = 24)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  const std::string name = baseline.substr(baseline.find_last_of('/') + 1);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName((outputDir + "/" + name.substr(0, name.size() - 4) + "-test.png").c_str());
  writer->Write();
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(baseline.c_str()))
  {
    return -1.0;
  }
  reader->SetFileName(baseline.c_str());
  vtkNew<vtkImageExtractComponents> rgb;
  rgb->SetInputConnection(reader->GetOutputPort());
  rgb->SetComponents(0, 1, 2);
  vtkNew<vtkImageDifference> difference;
  difference->SetInputConnection(grab->GetOutputPort());
  difference->SetImageConnection(rgb->GetOutputPort());
  difference->SetThreshold(tolerance);
  difference->AllowShiftOn();
  difference->AveragingOn();
  difference->Update();
  return difference->GetThresholdedError();
}
} // namespace morphnode_test

#endif
