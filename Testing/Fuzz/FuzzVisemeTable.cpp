// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the viseme table reader (VisemeMap::FromJson), then every lookup on the
// table it built (phonemes, pauses, unknown phonemes, Rhubarb shapes, dominance).
#include "base/Error.h"
#include "speech/VisemeMap.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const morphnode::VisemeMap map = morphnode::VisemeMap::FromJson(text, "fuzz");
    const int numVisemes = static_cast<int>(map.GetVisemes().size());
    auto inRange = [&](int v) { return v >= 0 && v < numVisemes; };
    if (numVisemes == 0 || !inRange(map.GetSilenceIndex()) || !inRange(map.GetFallbackIndex()) ||
      map.GetSilence().empty() || map.GetFallback().empty())
    {
      std::abort();
    }
    for (const auto& entry : map.GetPhonemeTable())
    {
      if (!inRange(entry.second) || map.MapPhoneme(entry.first) != entry.second)
      {
        std::abort();
      }
      map.IsClosurePhoneme(entry.first);
    }
    int warnings = 0;
    const auto warn = [&](const std::string&) { ++warnings; };
    if (!inRange(map.MapPhoneme("_", warn)) || !inRange(map.MapPhoneme("\x01unknown", warn)))
    {
      std::abort();
    }
    for (int v = 0; v < numVisemes; ++v)
    {
      if (!(map.GetDominance(v) > 0.0) || !std::isfinite(map.GetDominance(v)))
      {
        std::abort();
      }
      map.GetRhubarbShape(v);
    }
    for (const char shape : std::string("ABCDEFGHX?"))
    {
      const int v = map.GetVisemeOfShape(shape);
      if (v != -1 && !inRange(v))
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
