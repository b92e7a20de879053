// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: Rhubarb JSON reader, the writer on whatever it accepts, and the conversion
// of the cues to a viseme track.
#include "base/Error.h"
#include "speech/Rhubarb.h"

#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  static const morphnode::VisemeMap map =
    morphnode::VisemeMap::Builtin(morphnode::VisemeSet::German16, "de");
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try
  {
    const auto cues = morphnode::ReadRhubarbJson(in);
    std::stringstream out;
    morphnode::WriteRhubarbJson(out, cues);
    if (morphnode::ReadRhubarbJson(out).size() != cues.size())
    {
      std::abort();
    }
    // Blending is part of reading cues in practice; keep it short (the duration is bounded).
    if (!cues.empty() && cues.back().End < 60.0)
    {
      morphnode::CoarticulationOptions options;
      options.FrameRate = 30.0;
      morphnode::Coarticulate(
        morphnode::MouthCuesToVisemeSegments(cues, map), map, cues.back().End, options);
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}
