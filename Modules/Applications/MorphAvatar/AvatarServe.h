// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarServe.h
/// @brief MorphAvatar --serve: the avatar's brain on a server and any browser its face
/// (docs/streaming.md). The face is read without VTK (a glTF/GLB file), prepared for remote
/// faces once (stream::StreamAvatar), and every browser that opens /stream gets its own
/// session (behaviour, speech, optimizer) from stream::StreamServer. With --listen the
/// command socket commands every session. Runs until SIGINT/SIGTERM or --exit-after.

#include "AvatarOptions.h"

namespace morphavatar
{
/// Returns the exit code: 0 after a clean stop, 1 with a message when the face, the rig or
/// an address cannot be used. Needs no display.
int RunServe(const Options& options);
} // namespace morphavatar
