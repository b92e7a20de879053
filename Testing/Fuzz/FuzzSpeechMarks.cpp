// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: speech-mark JSON lines (Amazon Polly style): visemes, phonemes, words.
#include "base/Error.h"
#include "speech/SpeechMarks.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const morphnode::SpeechMarks marks = morphnode::ParseSpeechMarks(text);
    double end = 0.0;
    for (const auto& p : marks.Phonemes)
    {
      // Ordered, positive durations, no gaps: what the viseme pipeline relies on.
      if (p.Sampa.empty() || !std::isfinite(p.Start) || !(p.Duration > 0.0) ||
        std::abs(p.Start - end) > 1e-9 * std::max(1.0, end))
      {
        std::abort();
      }
      end = p.Start + p.Duration;
    }
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  return 0;
}
