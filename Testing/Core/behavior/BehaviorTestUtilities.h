// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Shared helpers of the behaviour tests: synthetic utterances with known viseme timing.
#include "behavior/BehaviorController.h"
#include "speech/SpeechTypes.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace behaviortest
{
/// An utterance of `duration` seconds at 100 fps with channels sil, PP, aa, E: "aa" is fully
/// open over [0.2, 0.6] s (ramps of 50 ms), PP closed over [0.7, 0.8] s, silence elsewhere.
inline morphnode::Utterance MakeUtterance(double duration = 1.0)
{
  morphnode::Utterance u;
  u.Visemes = morphnode::WeightTrack({ "sil", "PP", "aa", "E" }, 100.0);
  const int frames = static_cast<int>(std::round(duration * 100.0)) + 1;
  for (int f = 0; f < frames; ++f)
  {
    const double t = f / 100.0;
    auto ramp = [t](double a, double b)
    {
      const double up = std::clamp((t - a) / 0.05 + 1.0, 0.0, 1.0);
      const double down = std::clamp((b - t) / 0.05 + 1.0, 0.0, 1.0);
      return std::min(up, down);
    };
    const double aa = ramp(0.2, 0.6), pp = ramp(0.7, 0.8);
    const double sil = std::max(0.0, 1.0 - aa - pp);
    u.Visemes.AppendFrame(std::vector<double>{ sil, pp, aa, 0.0 });
  }
  u.Duration = duration;
  return u;
}

/// Parameters without random idle contributions on the face, for exact checks.
inline morphnode::BehaviorParameters QuietParameters()
{
  morphnode::BehaviorParameters p;
  p.IdleSmileInterval = 0.0;
  p.HeadYawAmplitude = p.HeadPitchAmplitude = p.HeadRollAmplitude = 0.0;
  p.SaccadeMaxAmplitude = 0.0;
  return p;
}
} // namespace behaviortest
