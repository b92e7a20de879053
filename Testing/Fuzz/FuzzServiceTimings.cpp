// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: Azure viseme events and character alignments (ServiceTimings.h), the JSON
// parsing and checks (the eSpeak NG reading of aligned words is not fuzzed: it is eSpeak's).
#include "base/Error.h"
#include "speech/ServiceTimings.h"

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const auto phonemes = morphnode::ParseAzureVisemes(text);
    for (size_t i = 1; i < phonemes.size(); ++i)
    {
      if (phonemes[i].Start < phonemes[i - 1].Start)
      {
        std::abort();
      }
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  try
  {
    for (const auto& word : morphnode::ParseCharacterAlignment(text))
    {
      if (word.End < word.Start || word.Text.empty())
      {
        std::abort();
      }
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}
