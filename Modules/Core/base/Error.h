// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Error.h
/// @brief The one exception type the core throws for bad input.
///
/// The core validates every input it is given and reports problems by throwing
/// morphnode::InputError with a message meant for the user. VTK adapters catch it and
/// turn it into vtkErrorMacro plus an empty output, so no caller ever sees a crash.

#include <stdexcept>
#include <string>

namespace morphnode
{
class InputError : public std::runtime_error
{
public:
  explicit InputError(const std::string& message)
    : std::runtime_error(message)
  {
  }
};
} // namespace morphnode
