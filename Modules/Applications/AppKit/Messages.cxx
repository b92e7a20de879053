// SPDX-License-Identifier: BSD-3-Clause
#include "Messages.h"

#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"

#include <iostream>
#include <regex>

namespace morphnode
{
namespace appkit
{
namespace
{
/// Prints VTK's errors and warnings as the program's own lines.
class ProgramOutputWindow : public vtkOutputWindow
{
public:
  static ProgramOutputWindow* New();
  vtkTypeMacro(ProgramOutputWindow, vtkOutputWindow);

  std::string Program;

  void DisplayErrorText(const char* text) override { this->Print(text, ""); }
  void DisplayWarningText(const char* text) override { this->Print(text, "warning: "); }
  void DisplayGenericWarningText(const char* text) override { this->Print(text, "warning: "); }
  void DisplayText(const char* text) override
  {
    if (text)
    {
      std::cerr << text;
    }
  }
  void DisplayDebugText(const char*) override {}

private:
  void Print(const char* text, const char* kind)
  {
    const std::string message = ProgramMessage(text ? text : "");
    if (!message.empty())
    {
      std::cerr << this->Program << ": " << kind << message << "\n";
    }
  }
};
vtkStandardNewMacro(ProgramOutputWindow);
} // namespace

std::string ProgramMessage(const std::string& vtkText)
{
  std::string text = vtkText;
  // "ERROR: In /path/file.cxx, line 123\n" / "Warning: In ...".
  static const std::regex location(R"(^(ERROR|Warning|Generic Warning): In [^\n]*, line [0-9]+\n)");
  text = std::regex_replace(text, location, "", std::regex_constants::format_first_only);
  if (text.find("returned failure for request") != std::string::npos)
  {
    return ""; // the executive repeating an error already shown
  }
  // "vtkSomeClass (0x55d1c0ffee00): " before the message.
  static const std::regex object(R"(^[A-Za-z_][A-Za-z0-9_:]* \((0x)?[0-9a-fA-F]+\): )");
  text = std::regex_replace(text, object, "", std::regex_constants::format_first_only);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\r'))
  {
    text.pop_back();
  }
  return text;
}

void UseProgramMessages(const std::string& program)
{
  vtkNew<ProgramOutputWindow> window;
  window->Program = program;
  vtkOutputWindow::SetInstance(window);
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}
} // namespace appkit
} // namespace morphnode
