// SPDX-License-Identifier: BSD-3-Clause
#include "speech/BuiltinVisemeTables.h"

#include <cstring>

namespace morphnode
{
namespace speech_detail
{
namespace
{
struct BuiltinTable
{
  const char* Key;
  const char* Json;
};

// The files of speech/data, each a raw string literal made by morphnode_embed_json
// (Modules/Core/CMakeLists.txt; the list in speech/CMakeLists.txt).
const BuiltinTable Tables[] = {
  {
    "german16_de",
#include "visemes_german16_de.json.inc"
  },
  {
    "german16_en",
#include "visemes_german16_en.json.inc"
  },
  {
    "oculus15_de",
#include "visemes_oculus15_de.json.inc"
  },
  {
    "oculus15_en",
#include "visemes_oculus15_en.json.inc"
  },
  {
    "paper6_de",
#include "visemes_paper6_de.json.inc"
  },
  {
    "paper6_en",
#include "visemes_paper6_en.json.inc"
  },
};
} // namespace

const char* BuiltinVisemeTableJson(const char* key)
{
  for (const BuiltinTable& table : Tables)
  {
    if (std::strcmp(key, table.Key) == 0)
    {
      return table.Json;
    }
  }
  return nullptr;
}
} // namespace speech_detail
} // namespace morphnode
