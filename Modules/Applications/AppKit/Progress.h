// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Progress.h
/// @brief The progress bar of the MorphNode programs, on stderr: in place on a terminal
/// (at most 20 updates a second), every 10 % in a log; with the time left, and the time
/// taken at the end.

#include <chrono>
#include <string>

namespace morphnode
{
namespace appkit
{
class ProgressBar
{
public:
  /// `total` steps of `unit` ("frames", "methods"); a disabled bar prints nothing.
  explicit ProgressBar(int total, std::string unit = "frames", bool enabled = true);

  /// `done` of the total steps are done; `label` names the one under way.
  /// Prints e.g. "[#######.......]  50%  12/25 frames  ETA 1.2 s".
  void Show(int done, const std::string& label = std::string());

private:
  using Clock = std::chrono::steady_clock;
  int Total;
  std::string Unit;
  bool Enabled;
  bool Tty;
  Clock::time_point Begin;
  Clock::time_point LastShown;
  int LastDecile = -1;
};
} // namespace appkit
} // namespace morphnode
