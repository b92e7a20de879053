// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: Rhubarb XML reader (expat), and the JSON writer on whatever it accepts.
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
    const auto cues = morphnode::ReadRhubarbXml(in);
    std::stringstream out;
    morphnode::WriteRhubarbJson(out, cues);
    if (morphnode::ReadRhubarbJson(out).size() != cues.size())
    {
      std::abort();
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}
