// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarLive.h
/// @brief MorphAvatar live: commands from a dialog system (docs/dialog.md) as JSON lines on
/// standard input (--commands-stdin) and local sockets (--listen 127.0.0.1:PORT,
/// --listen unix:PATH), run on the behaviour while the avatar runs in real time, with
/// accepted / started / ended / error events back. The window's loop (AvatarInteractive)
/// or a headless loop (--offscreen, for tests and the latency study) polls the commands
/// every frame without blocking it.

#include "AvatarOptions.h"

namespace morphavatar
{
struct Avatar;

/// True when the options ask for commands (--listen or --commands-stdin).
bool IsLive(const Options& options);
/// Runs the avatar live until a quit command, the window closes, --exit-after passes, or
/// (headless, commands on stdin only) standard input ends and everything said has ended.
/// Returns the exit code; 1 with a message when a --listen address cannot be used.
int RunLive(Avatar& avatar);
} // namespace morphavatar
