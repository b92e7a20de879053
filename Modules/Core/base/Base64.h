// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Base64.h
/// @brief Base64 (RFC 4648, section 4: the standard alphabet) to bytes and back, for binary
/// payloads inside text protocols (a recording inside a dialog command, docs/dialog.md).
///
///   std::string bytes = morphnode::base64::Decode(text, "'audio_base64'"); // InputError
///   std::string text = morphnode::base64::Encode(bytes);
///
/// Written by hand on purpose: none of the libraries MorphNode links has a public one
/// (Boost.Beast's is in its `detail` namespace; Boost.Archive's dataflow iterators neither
/// take padding nor report where the input went wrong; OpenSSL and GLib are not linked, and
/// EVP_DecodeBlock returns padded lengths and accepts stray whitespace silently). Decoding is
/// strict, so a client's mistake reads as one clear message: only the alphabet, padding
/// only at the end (at most two '=', or none), ASCII whitespace skipped (line-wrapped MIME
/// output), and the unused bits of the last character must be zero (one text, one meaning).
/// Fuzzed by FuzzInlineSpeech (docs/fuzzing.md) against Boost.Archive's decoder.

#include "base/Error.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace morphnode
{
namespace base64
{
/// The bytes of `text`. InputError naming `what` and the offending character's offset for a
/// character outside the alphabet, misplaced or excess padding, a length that is no whole
/// number of bytes (one character left over), or non-zero trailing bits.
inline std::string Decode(std::string_view text, const std::string& what = "base64 data")
{
  static const auto value = [](unsigned char c) -> int
  {
    if (c >= 'A' && c <= 'Z')
    {
      return c - 'A';
    }
    if (c >= 'a' && c <= 'z')
    {
      return c - 'a' + 26;
    }
    if (c >= '0' && c <= '9')
    {
      return c - '0' + 52;
    }
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  const auto fail = [&what](size_t at, const std::string& why)
  {
    return InputError(
      what + " is not valid base64: " + why + " at character " + std::to_string(at));
  };
  std::string out;
  out.reserve(text.size() / 4 * 3 + 3);
  uint32_t bits = 0;     // pending bits, the newest at the bottom
  int pendingBits = 0;   // how many of them
  size_t characters = 0; // alphabet characters seen
  size_t padding = 0;
  size_t paddingAt = 0;
  for (size_t i = 0; i < text.size(); ++i)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n')
    {
      continue;
    }
    if (c == '=')
    {
      if (padding == 0)
      {
        paddingAt = i;
      }
      if (++padding > 2)
      {
        throw fail(i, "more than two '='");
      }
      continue;
    }
    const int v = value(c);
    if (v < 0)
    {
      throw fail(i,
        c >= 0x20 && c < 0x7f ? "'" + std::string(1, static_cast<char>(c)) + "'"
                              : "byte " + std::to_string(static_cast<int>(c)));
    }
    if (padding > 0)
    {
      throw fail(paddingAt, "'=' before the end");
    }
    bits = (bits << 6) | static_cast<uint32_t>(v);
    pendingBits += 6;
    ++characters;
    if (pendingBits >= 8)
    {
      pendingBits -= 8;
      out.push_back(static_cast<char>((bits >> pendingBits) & 0xffu));
      bits &= (1u << pendingBits) - 1u;
    }
  }
  const size_t rest = characters % 4; // 0: whole groups; 2 or 3: one or two bytes more
  if (rest == 1)
  {
    throw fail(text.size(),
      "one character too many or too few (the length is " + std::to_string(characters) +
        " characters)");
  }
  if (padding > 0 && (rest == 0 || rest + padding != 4))
  {
    throw fail(paddingAt, std::to_string(padding) + " '=' do not complete the last group");
  }
  if (bits != 0)
  {
    throw fail(text.size(), "the last character has bits set beyond the data");
  }
  return out;
}

/// The base64 text of `bytes`, padded with '=', without line breaks.
inline std::string Encode(std::string_view bytes)
{
  static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3)
  {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) |
      (uint32_t(uint8_t(bytes[i + 1])) << 8) | uint32_t(uint8_t(bytes[i + 2]));
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += alphabet[(v >> 6) & 63];
    out += alphabet[v & 63];
  }
  if (i + 1 == bytes.size())
  {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += "==";
  }
  else if (i + 2 == bytes.size())
  {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) | (uint32_t(uint8_t(bytes[i + 1])) << 8);
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += alphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}
} // namespace base64
} // namespace morphnode
