// SPDX-License-Identifier: BSD-3-Clause
// base/Text.h: ASCII lower-casing (no locale, bytes above 127 untouched) and the test of a
// file's kind by its extension, case ignored.
#include "base/Text.h"

#include <gtest/gtest.h>

using namespace morphnode;

TEST(Text, ToLowerIsAsciiOnly)
{
  EXPECT_EQ(text::ToLower("Raise_Brows-AZ09"), "raise_brows-az09");
  EXPECT_EQ(text::ToLower("\xC3\x84"), "\xC3\x84") << "UTF-8 bytes are left alone";
  EXPECT_EQ(text::ToLower(""), "");
}

TEST(Text, HasExtensionIgnoresCase)
{
  EXPECT_TRUE(text::HasExtension("head.glb", ".glb"));
  EXPECT_TRUE(text::HasExtension("HEAD.GLB", ".glb"));
  EXPECT_TRUE(text::HasExtension("a/b.TextGrid", ".textgrid"));
  EXPECT_FALSE(text::HasExtension("head.gltf", ".glb"));
  EXPECT_FALSE(text::HasExtension("glb", ".glb")) << "shorter than the extension";
  EXPECT_FALSE(text::HasExtension("head.glb.bak", ".glb"));
}
