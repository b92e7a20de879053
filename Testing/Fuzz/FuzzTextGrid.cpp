// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the Praat TextGrid reader (long and short text formats, UTF-8 and UTF-16)
// and the phone-tier conversion on whatever it accepts.
#include "base/Error.h"
#include "speech/TextGrid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try
  {
    const morphnode::TextGrid grid = morphnode::ParseTextGrid(bytes);
    for (const auto& tier : grid.Tiers)
    {
      double previous = -INFINITY;
      for (const auto& item : tier.Items)
      {
        // The reader promised ordered, non-negative-length items inside the grid.
        if (!(item.End >= item.Start) ||
          item.Start < previous - 1e-6 * std::max(1.0, std::abs(previous)))
        {
          std::abort();
        }
        previous = item.End;
      }
    }
    const auto phonemes = morphnode::TextGridPhonemes(grid);
    for (const auto& p : phonemes)
    {
      if (p.Sampa.empty() || !std::isfinite(p.Start) || !(p.Duration > 0.0))
      {
        std::abort();
      }
    }
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  return 0;
}
