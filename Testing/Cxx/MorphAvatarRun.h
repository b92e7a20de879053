// SPDX-License-Identifier: BSD-3-Clause
// Runs the MorphAvatar program (MORPHNODE_AVATAR_EXE) for the tests that drive it as users
// do (TestMorphAvatar, TestMorphAvatarFrameBudget).
#ifndef MorphAvatarRun_h
#define MorphAvatarRun_h

#include "vtksys/SystemTools.hxx"

#include <cstdio>
#include <iostream>
#include <string>
#include <sys/wait.h>

namespace morphnode_test
{
struct AvatarRun
{
  int ExitCode = -1;
  std::string Text; // stdout and stderr
};

/// Runs `avatar arguments` once, collecting stdout and stderr.
inline AvatarRun RunAvatarOnce(const std::string& avatar, const std::string& arguments)
{
  AvatarRun run;
  const std::string command = "'" + avatar + "' " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe)
  {
    return run;
  }
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0)
  {
    run.Text.append(buffer, n);
  }
  const int status = pclose(pipe);
  run.ExitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

/// Runs the avatar; a run the X server refused (VTK aborts on "bad X server connection",
/// seen once in CI under load with `xvfb-run -a`) is retried, at most twice. Only that
/// message is retried: it says nothing about the avatar, every other failure counts.
inline AvatarRun RunAvatar(const std::string& arguments)
{
  const std::string avatar = MORPHNODE_AVATAR_EXE;
  AvatarRun run = RunAvatarOnce(avatar, arguments);
  for (int retry = 0; retry < 2 && run.Text.find("bad X server connection") != std::string::npos;
       ++retry)
  {
    std::cerr << "MorphAvatar could not connect to the X server; retrying\n";
    vtksys::SystemTools::Delay(1000);
    run = RunAvatarOnce(avatar, arguments);
  }
  return run;
}
} // namespace morphnode_test

#endif
