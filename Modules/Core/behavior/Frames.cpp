// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/Frames.h"

#include "base/Error.h"

#include <cmath>
#include <sstream>

namespace morphnode
{
size_t NumberOfFrames(double duration, double frameRate)
{
  if (!(frameRate > 0.0) || !std::isfinite(frameRate))
  {
    std::ostringstream msg;
    msg << "frame rate " << frameRate << " is not a positive number";
    throw InputError(msg.str());
  }
  if (!(duration >= 0.0) || !std::isfinite(duration))
  {
    std::ostringstream msg;
    msg << "duration " << duration << " is not a time in seconds >= 0";
    throw InputError(msg.str());
  }
  const double last = std::floor(duration * frameRate + 1e-9);
  if (!(last < 4294967296.0))
  {
    std::ostringstream msg;
    msg << duration << " s at " << frameRate << " frames per second are too many frames";
    throw InputError(msg.str());
  }
  return static_cast<size_t>(last) + 1;
}

std::vector<double> FrameTimes(double duration, double frameRate)
{
  const size_t frames = NumberOfFrames(duration, frameRate);
  if (frames > MaxTrackValues)
  {
    std::ostringstream msg;
    msg << duration << " s at " << frameRate << " frames per second are more than "
        << MaxTrackValues << " frames";
    throw InputError(msg.str());
  }
  std::vector<double> times(frames);
  for (size_t i = 0; i < times.size(); ++i)
  {
    times[i] = FrameTime(i, frameRate);
  }
  return times;
}
} // namespace morphnode
