// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/Blackboard.h"

#include "behavior/IdleSchedule.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace
{
double Clamp01(double v)
{
  return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
}
} // namespace

void Blackboard::SetExplicitGaze(const FadeTrack<3>& eye, const FadeTrack<2>& head, double t)
{
  double e[3], h[2];
  eye.Evaluate(t, e);
  head.Evaluate(t, h);
  this->Gaze = { e[0], e[1] };
  this->Ownership[GazeGroup] = e[2];
  this->HeadGaze = { h[0], h[1], 0.0 };
}

void Blackboard::Resolve(const BehaviorParameters& p, double* out) const
{
  using C = BehaviorChannel;
  const double relaxed = 1.0 - 0.5 * Clamp01(this->Relax);

  // Brows: explicit gestures own the group.
  const double browsFree = 1.0 - Clamp01(this->Ownership[BrowsGroup]);
  for (int c : { C::BrowsUp, C::BrowsFright, C::BrowsAngry })
  {
    const double background = (this->Background[c] + this->Speech[c]) * relaxed;
    out[c] = Clamp01(browsFree * background + this->Explicit[c]);
  }

  // Expression: explicit gestures own the group; speech damps it.
  const double expressionFree = 1.0 - Clamp01(this->Ownership[ExpressionGroup]);
  const double speechDamping = 1.0 - p.SpeechExpressionDamping * Clamp01(this->SpeechActivity);
  for (int c : { C::MouthSmile, C::MouthSad })
  {
    const double background = (this->Background[c] + this->Speech[c]) * relaxed;
    out[c] = Clamp01((expressionFree * background + this->Explicit[c]) * speechDamping);
  }

  // Lids: blinks merge, close-eyes takes the maximum.
  const double lid = Clamp01(this->Background[C::EyesClosed]);
  out[C::EyesClosed] = Clamp01(std::max(lid + (1.0 - lid) * Clamp01(this->Blink), this->CloseEyes));

  // Head.
  const double headFree = 1.0 - Clamp01(this->Ownership[HeadGroup]);
  for (int a = 0; a < 3; ++a)
  {
    out[C::HeadYaw + a] = headFree * this->HeadIdle[a] + this->HeadBackground[a] +
      this->HeadGaze[a] + this->HeadSpeech[a] + this->HeadExplicit[a];
  }

  // Gaze: the eyes hold the target against the head.
  const double saccadeShare = 1.0 - Clamp01(this->Ownership[GazeGroup]);
  const double eyeYaw =
    std::clamp(this->Gaze[0] + saccadeShare * this->Saccade[0] - out[C::HeadYaw], -p.EyeYawRange,
      p.EyeYawRange);
  const double eyePitch =
    std::clamp(this->Gaze[1] + saccadeShare * this->Saccade[1] - out[C::HeadPitch],
      -p.EyePitchRange, p.EyePitchRange);
  out[C::EyeYaw] = eyeYaw;
  out[C::EyePitch] = eyePitch;
  out[C::LookLeft] = Clamp01(eyeYaw / p.EyeYawRange);
  out[C::LookRight] = Clamp01(-eyeYaw / p.EyeYawRange);
  out[C::LookUp] = Clamp01(eyePitch / p.EyePitchRange);
  out[C::LookDown] = Clamp01(-eyePitch / p.EyePitchRange);
}

void Blackboard::AddSpeechCue(NonverbalCue::Kind kind, const SyncPoints& sync, double intensity,
  double t, const BehaviorParameters& p)
{
  using C = BehaviorChannel;
  const double e = sync.Envelope(t);
  switch (kind)
  {
    case NonverbalCue::Kind::BrowRaise:
      this->Speech[C::BrowsUp] += 0.6 * intensity * e;
      break;
    case NonverbalCue::Kind::Relax:
      this->Relax = std::max(this->Relax, intensity * e);
      break;
    case NonverbalCue::Kind::Nod:
      if (e > 0.0)
      {
        // One bump down and up: 0.5 - 0.5 cos(2 pi u).
        const double u = (t - sync.Start) / (sync.End - sync.Start);
        this->HeadSpeech[1] -=
          p.SpeechNodAmplitude * intensity * (0.5 - 0.5 * std::cos(6.283185307179586 * u));
      }
      break;
    case NonverbalCue::Kind::Blink: // played with the other blinks
      break;
  }
}

SyncPoints SpeechCueSync(const NonverbalCue& cue, double start, const BehaviorParameters& p)
{
  switch (cue.Type)
  {
    case NonverbalCue::Kind::BrowRaise:
      return SyncPoints::Make(start, std::max(cue.Duration, 0.3), 0.1, 0.15);
    case NonverbalCue::Kind::Nod:
      return SyncPoints::Make(start, std::max(cue.Duration, 0.4), 0.0, 0.0);
    case NonverbalCue::Kind::Relax:
      return SyncPoints::Make(start, std::max(cue.Duration, 0.3), 0.15, 0.15);
    case NonverbalCue::Kind::Blink:
      return SyncPoints::Make(start, BlinkLength(p), p.BlinkCloseTime, p.BlinkOpenTime);
  }
  return SyncPoints::Make(start, cue.Duration, 0.0, 0.0);
}
} // namespace morphnode
