// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the transfer's landmark files (morphnode::ParseTransferLandmarks).
#include "base/Error.h"
#include "transfer/Transfer.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const auto landmarks = morphnode::ParseTransferLandmarks(text, "fuzz");
    const auto& names = morphnode::TransferLandmarkNames();
    if (landmarks.size() > names.size())
    {
      std::abort(); // names are unique and known
    }
    for (const auto& l : landmarks)
    {
      if (!std::isfinite(l.Position.x) || !std::isfinite(l.Position.y) ||
        !std::isfinite(l.Position.z))
      {
        std::abort(); // the reader promised finite numbers
      }
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}
