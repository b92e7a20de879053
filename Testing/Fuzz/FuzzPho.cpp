// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the MBROLA .pho reader, and the writer on whatever it accepts.
#include "base/Error.h"
#include "speech/Pho.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const auto phonemes = morphnode::ParsePho(text);
    for (const auto& p : phonemes)
    {
      if (!std::isfinite(p.Start) || !(p.Duration >= 0.0))
      {
        std::abort(); // the reader promised finite, non-negative times
      }
    }
    // Whatever reads must write and read back to the same number of phonemes or more
    // (gaps cannot occur, so exactly the same).
    std::stringstream out;
    morphnode::WritePho(out, phonemes);
    if (morphnode::ReadPho(out).size() != phonemes.size())
    {
      std::abort();
    }
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  return 0;
}
