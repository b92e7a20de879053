// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Utf8.h"

#include "base/Error.h"

#include <utf8.h>

#include <cstdint>
#include <iterator>

namespace morphnode
{
std::u32string DecodeUtf8(const std::string& text)
{
  std::string valid;
  valid.reserve(text.size());
  utf8::replace_invalid(text.begin(), text.end(), std::back_inserter(valid), 0xFFFD);
  std::u32string out;
  utf8::utf8to32(valid.begin(), valid.end(), std::back_inserter(out));
  return out;
}

std::string EncodeUtf8(char32_t codePoint)
{
  std::string out;
  try
  {
    utf8::append(static_cast<uint32_t>(codePoint), std::back_inserter(out));
  }
  catch (const utf8::exception&)
  {
    utf8::append(static_cast<uint32_t>(0xFFFD), std::back_inserter(out));
  }
  return out;
}

std::string Utf16ToUtf8(const std::u16string& units)
{
  std::string out;
  out.reserve(units.size());
  try
  {
    utf8::utf16to8(units.begin(), units.end(), std::back_inserter(out));
  }
  catch (const utf8::exception&)
  {
    throw InputError("broken UTF-16 surrogate pair");
  }
  return out;
}
} // namespace morphnode
