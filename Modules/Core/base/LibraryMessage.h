// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file LibraryMessage.h
/// @brief Library exception texts (nlohmann/json, tinygltf) turned into messages for people:
/// what and where stay, the library's tags go (beside Text.h, which most of the core
/// includes, so that this helper does not rebuild it all).

#include <string>
#include <string_view>

namespace morphnode
{
namespace text
{
/// A library's exception text as a message for people: nlohmann/json's
/// "[json.exception.parse_error.101] parse error at line 1, column 2: ..." loses its tag
/// (what and where stay), control bytes become '?', and it is cut at 300 bytes.
inline std::string LibraryMessage(std::string_view what)
{
  if (what.rfind("[json.exception.", 0) == 0)
  {
    const size_t bracket = what.find("] ");
    if (bracket != std::string_view::npos)
    {
      what.remove_prefix(bracket + 2);
    }
  }
  std::string out(what.substr(0, 300));
  for (char& c : out)
  {
    const unsigned char u = static_cast<unsigned char>(c);
    c = (u < 32 || u == 127) ? '?' : c;
  }
  return what.size() > 300 ? out + "..." : out;
}

} // namespace text
} // namespace morphnode
