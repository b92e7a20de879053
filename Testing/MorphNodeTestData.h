// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The shared MakeHuman avatar the tests read where it lies (../shared/data, never copied into
// the repository), and the skip of a test that needs it, with the reason shown. A user's
// checkout without the data skips; CI fails without it (Testing/CMakeLists.txt checks its
// files).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace morphnode_test
{
/// A file of the shared avatar's folder (MORPHNODE_AVATAR_DIR): the avatar by default.
inline std::string AvatarFile(const std::string& name = "makehuman_avatar.glb")
{
  return std::string(MORPHNODE_AVATAR_DIR) + "/" + name;
}
} // namespace morphnode_test

/// At the start of a test that reads the shared avatar `path`: skips it when it is missing.
#define MORPHNODE_SKIP_WITHOUT_AVATAR(path)                                                        \
  if (!std::filesystem::exists(path))                                                              \
  GTEST_SKIP() << "MakeHuman avatar not found: " << (path) << " (MORPHNODE_AVATAR_DIR)"
