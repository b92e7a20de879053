// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small locale-independent text helpers shared by the speech readers and writers.

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace morphnode
{
namespace speech_detail
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

/// The whole token as a finite number (from_chars: no locale, no leading '+').
inline bool ParseNumber(std::string_view token, double& value)
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
  return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
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
} // namespace speech_detail
} // namespace morphnode
