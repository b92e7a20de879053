// SPDX-License-Identifier: BSD-3-Clause
#include "Progress.h"

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <unistd.h> // isatty

namespace morphnode
{
namespace appkit
{
ProgressBar::ProgressBar(int total, std::string unit, bool enabled)
  : Total(total)
  , Unit(std::move(unit))
  , Enabled(enabled)
  , Tty(isatty(fileno(stderr)) != 0)
  , Begin(Clock::now())
{
}

void ProgressBar::Show(int done, const std::string& label)
{
  if (!this->Enabled)
  {
    return;
  }
  const auto now = Clock::now();
  const bool last = done >= this->Total;
  if (this->Tty && !last && now - this->LastShown < std::chrono::milliseconds(50))
  {
    return;
  }
  const int percent = this->Total > 0 ? static_cast<int>(100.0 * done / this->Total) : 100;
  if (!this->Tty && !last && percent / 10 == this->LastDecile)
  {
    return;
  }
  this->LastDecile = percent / 10;
  this->LastShown = now;
  const double elapsed = std::chrono::duration<double>(now - this->Begin).count();
  const double eta = done > 0 ? elapsed * (this->Total - done) / done : 0.0;
  const int width = 30;
  const int filled = this->Total > 0 ? width * std::min(done, this->Total) / this->Total : width;
  std::ostringstream os;
  os << (this->Tty ? "\r[" : "[") << std::string(filled, '#') << std::string(width - filled, '.')
     << "] " << std::setw(3) << percent << "%  " << done << "/" << this->Total << " " << this->Unit
     << "  " << (last ? "done in " : "ETA ") << std::fixed << std::setprecision(1)
     << (last ? elapsed : eta) << " s";
  if (!label.empty() && !last)
  {
    os << "  " << std::left << std::setw(32) << label; // padded: overwrites a longer one
  }
  os << "   ";
  std::cerr << os.str() << (this->Tty && !last ? "" : "\n") << std::flush;
}
} // namespace appkit
} // namespace morphnode
