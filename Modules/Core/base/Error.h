// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Error.h
/// @brief The one exception type the core throws for bad input.
///
/// The core validates every input it is given and reports problems by throwing
/// morphnode::InputError with a message meant for the user. VTK adapters catch it and
/// turn it into vtkErrorMacro plus an empty output, so no caller ever sees a crash.

#include <utf8.h>

#include <iterator>
#include <stdexcept>
#include <string>

namespace morphnode
{
/// The message is made valid UTF-8 here, once for every error (an invalid sequence quoted
/// from the input becomes U+FFFD), so that it reaches VTK's error events, Python and JSON
/// events intact (UTF8-CPP, Debian libutfcpp-dev).
class InputError : public std::runtime_error
{
public:
  explicit InputError(const std::string& message)
    : std::runtime_error(ValidUtf8(message))
  {
  }

  static std::string ValidUtf8(const std::string& text)
  {
    if (utf8::is_valid(text.begin(), text.end()))
    {
      return text;
    }
    std::string valid;
    valid.reserve(text.size() + 8);
    utf8::replace_invalid(text.begin(), text.end(), std::back_inserter(valid), 0xFFFD);
    return valid;
  }
};
} // namespace morphnode
