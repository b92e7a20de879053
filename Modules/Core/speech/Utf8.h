// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Utf8.h
/// @brief The one place where the speech readers convert between UTF-8, UTF-16 and code
/// points (IPA labels, Praat's UTF-16 TextGrids), on UTF8-CPP (Debian libutfcpp-dev).

#include <string>

namespace morphnode
{
/// The code points of UTF-8 text; each invalid sequence becomes U+FFFD.
std::u32string DecodeUtf8(const std::string& text);
/// One code point as UTF-8.
std::string EncodeUtf8(char32_t codePoint);
/// UTF-16 code units as UTF-8. InputError for a broken surrogate pair.
std::string Utf16ToUtf8(const std::u16string& units);
} // namespace morphnode
