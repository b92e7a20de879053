// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: Rhubarb TSV reader, and the writer on whatever it accepts.
#include "base/Error.h"
#include "speech/Rhubarb.h"

#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try
  {
    const auto cues = morphnode::ReadRhubarbTsv(in, 1e3);
    std::stringstream out;
    morphnode::WriteRhubarbTsv(out, cues);
    morphnode::ReadRhubarbTsv(out);
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}
