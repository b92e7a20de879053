// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file StopSignal.h
/// @brief SIGTERM and SIGINT as a request to stop, the way a `quit` command stops: the
/// programs' loops ask StopRequested() at every frame (at least every 200 ms) and end
/// normally (running commands get their ended events, files being written are completed,
/// sockets are closed and a Unix socket file removed, by the destructors that end every
/// run). A second signal ends the program at once (the default action).

#include <csignal>

namespace morphnode
{
namespace appkit
{
/// Installs the handlers (without SA_RESTART, so that a poll() waiting for commands
/// returns at once). Call once, early in main().
void InstallStopSignals();
/// True once SIGTERM or SIGINT arrived.
bool StopRequested();
/// The signal that asked to stop (0: none), for the message and the exit code.
int StopSignalNumber();

/// Holds SIGTERM and SIGINT back while it lives (a file being renamed into place): a signal
/// arriving meanwhile takes effect when it ends, so a batch program killed while it writes
/// its output leaves the whole file or none, never a `.part` file.
class DeferStopSignals
{
public:
  DeferStopSignals();
  ~DeferStopSignals();
  DeferStopSignals(const DeferStopSignals&) = delete;
  DeferStopSignals& operator=(const DeferStopSignals&) = delete;

private:
  sigset_t Previous;
};
} // namespace appkit
} // namespace morphnode
