// SPDX-License-Identifier: BSD-3-Clause
#include "StopSignal.h"

#include <csignal>

namespace morphnode
{
namespace appkit
{
namespace
{
volatile std::sig_atomic_t Received = 0;

extern "C" void OnStopSignal(int number)
{
  Received = number;
  // A second signal: the default action (the user insists).
  struct sigaction dfl = {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(number, &dfl, nullptr);
}
} // namespace

void InstallStopSignals()
{
  struct sigaction action = {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0; // no SA_RESTART: a waiting poll() returns EINTR
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

bool StopRequested()
{
  return Received != 0;
}

int StopSignalNumber()
{
  return static_cast<int>(Received);
}

DeferStopSignals::DeferStopSignals()
{
  sigset_t held;
  sigemptyset(&held);
  sigaddset(&held, SIGTERM);
  sigaddset(&held, SIGINT);
  sigprocmask(SIG_BLOCK, &held, &this->Previous);
}

DeferStopSignals::~DeferStopSignals()
{
  sigprocmask(SIG_SETMASK, &this->Previous, nullptr);
}
} // namespace appkit
} // namespace morphnode
