// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Text.h
/// @brief The one home of the small text helpers every reader and writer of the core uses:
/// locale-independent numbers (a German locale must not turn "0.5" into 0), ASCII
/// lower-casing, whitespace splitting and trimming, whole-file reading (base/File.h), and quoting
/// of untrusted tokens in error messages.

#include "base/Error.h"
#include "base/File.h"

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace morphnode
{
namespace text
{
/// Splits on spaces and tabs.
inline std::vector<std::string_view> SplitWhitespace(std::string_view line)
{
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < line.size())
  {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
    {
      ++i;
    }
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t')
    {
      ++j;
    }
    if (j > i)
    {
      tokens.push_back(line.substr(i, j - i));
    }
    i = j;
  }
  return tokens;
}

inline std::string_view Trim(std::string_view s)
{
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r' || s[b] == '\n'))
  {
    ++b;
  }
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r' || s[e - 1] == '\n'))
  {
    --e;
  }
  return s.substr(b, e - b);
}

/// The whole token as a finite number (from_chars: no locale; a leading '+' accepted, as
/// OBJ and CSV writers sometimes emit it).
template <typename T>
inline bool ParseNumber(std::string_view token, T& value)
{
  if (!token.empty() && token[0] == '+')
  {
    token.remove_prefix(1);
  }
  if (token.empty())
  {
    return false;
  }
  const char* end = token.data() + token.size();
  auto result = std::from_chars(token.data(), end, value);
  if (result.ec != std::errc() || result.ptr != end)
  {
    return false;
  }
  if constexpr (std::is_floating_point_v<T>)
  {
    return std::isfinite(value);
  }
  return true;
}

/// Shortest text that reads back to the same double.
inline std::string FormatNumber(double value)
{
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

/// Printable form of a token for an error message (long or binary input shortened).
inline std::string Quote(std::string_view token)
{
  std::string out = "'";
  for (size_t i = 0; i < token.size() && i < 40; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    out += (c < 32 || c == 127) ? '?' : static_cast<char>(c);
  }
  if (token.size() > 40)
  {
    out += "...";
  }
  return out + "'";
}

/// ASCII lower case (names, keys and voices are ASCII; no locale).
inline std::string ToLower(std::string_view s)
{
  std::string out(s);
  for (char& c : out)
  {
    if (c >= 'A' && c <= 'Z')
    {
      c = static_cast<char>(c - 'A' + 'a');
    }
  }
  return out;
}

/// True when `path` ends in `extension` (".glb"), ASCII case ignored: "HEAD.GLB" is a GLB.
/// The one test of a file's kind by its name.
inline bool HasExtension(std::string_view path, std::string_view extension)
{
  return path.size() >= extension.size() &&
    ToLower(path.substr(path.size() - extension.size())) == ToLower(extension);
}

/// The whole file as bytes: a regular file (links resolved) of at most maxBytes, checked
/// before it is read (base/File.h). Throws InputError "<what> '<path>' ..." naming why.
inline std::string ReadFile(const std::string& path, const std::string& what = "file",
  uint64_t maxBytes = file::DefaultMaxReadBytes)
{
  return file::ReadFile(path, what, maxBytes);
}
} // namespace text
} // namespace morphnode
