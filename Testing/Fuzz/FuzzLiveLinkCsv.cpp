// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the Live Link Face CSV reader (ReadLiveLinkCsv), then WriteLiveLinkCsv on
// whatever it accepts: what it writes must read back with the same channels and rows, and
// every value must be finite.
#include "base/Error.h"
#include "capture/LiveLinkCsv.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  morphnode::LiveLinkOptions options;
  // The first byte picks the rate, so that 24, 30 and 60 fps timecodes are all explored.
  options.TimecodeRate = size > 0 ? (data[0] % 3 == 0 ? 60 : data[0] % 3 == 1 ? 30 : 24) : 60;
  try
  {
    const morphnode::LiveLinkCapture capture = morphnode::ReadLiveLinkCsv(in, options);
    if (capture.Times.empty() ||
      capture.Values.size() != capture.Times.size() * capture.Channels.size())
    {
      std::abort();
    }
    for (size_t r = 0; r < capture.GetNumberOfRows(); ++r)
    {
      if (!std::isfinite(capture.Times[r]) || (r > 0 && !(capture.Times[r] > capture.Times[r - 1])))
      {
        std::abort();
      }
    }
    for (double v : capture.Values)
    {
      if (!std::isfinite(v))
      {
        std::abort();
      }
    }
    for (size_t c = 0; c < capture.Channels.size(); ++c)
    {
      if (!std::isfinite(capture.Sample(capture.GetDuration() * 0.37, c)))
      {
        std::abort();
      }
    }
    std::stringstream out;
    morphnode::WriteLiveLinkCsv(out, capture, options);
    morphnode::LiveLinkCapture back;
    try
    {
      back = morphnode::ReadLiveLinkCsv(out, options);
    }
    catch (const morphnode::InputError&)
    {
      // Rows closer than a thousandth of a frame collapse onto one timecode when written;
      // that is the only way the writer's output may be refused.
      return 0;
    }
    if (back.GetNumberOfRows() != capture.GetNumberOfRows())
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
