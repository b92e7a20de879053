// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the weight track CSV reader (WeightTrack::ReadCsv), and WriteCsv on whatever
// it accepts: what it writes must read back to the same channels and frame count.
#include "base/Error.h"
#include "track/WeightTrack.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try
  {
    const morphnode::WeightTrack track = morphnode::WeightTrack::ReadCsv(in);
    const double rate = track.GetFrameRate();
    if (!(rate > 0.0) || !std::isfinite(rate) || track.GetNumberOfChannels() == 0)
    {
      std::abort();
    }
    for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
    {
      for (size_t c = 0; c < track.GetNumberOfChannels(); ++c)
      {
        if (!std::isfinite(track.GetValue(f, c)) ||
          !std::isfinite(track.Sample(track.GetTime(f), c)))
        {
          std::abort();
        }
      }
    }
    std::stringstream out;
    track.WriteCsv(out);
    morphnode::WeightTrack back;
    try
    {
      back = morphnode::WeightTrack::ReadCsv(out);
    }
    catch (const morphnode::InputError&)
    {
      std::abort(); // ReadCsv must accept what WriteCsv wrote
    }
    if (back.GetNumberOfChannels() != track.GetNumberOfChannels() ||
      back.GetNumberOfFrames() != track.GetNumberOfFrames())
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
