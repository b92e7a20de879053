// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Messages.h
/// @brief What a program's user reads when the content is at fault: `Program: what: why`
/// lines on stderr instead of VTK's log lines (time stamps, thread ids, colour codes, the
/// source file and line, the class and its address) and the pipeline's echo of them.

#include <string>

namespace morphnode
{
namespace appkit
{
/// From now on VTK errors and warnings print as `<program>: <message>` (warnings as
/// `<program>: warning: <message>`): the reporting class, its address and VTK's source
/// location are dropped, the executive's "returned failure for request" echo (the same
/// error once more with the request's dump) is left out, and VTK's logger stops writing to
/// stderr. ParseCommandLine calls it with the program's name.
void UseProgramMessages(const std::string& program);

/// VTK's error text reduced to the message: "ERROR: In <file>, line <n>\n<class> (<address>):
/// <message>\n\n" -> "<message>". Empty for the executive's "returned failure" echo.
std::string ProgramMessage(const std::string& vtkText);
} // namespace appkit
} // namespace morphnode
