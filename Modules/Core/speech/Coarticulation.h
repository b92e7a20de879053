// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Coarticulation.h
/// @brief Viseme weight tracks by the dominance model of Cohen & Massaro (1993).
///
/// Every segment s (a phoneme with its viseme T_s) has a dominance over time
///   D_s(t) = a_s * exp(-theta_s * |tau|^c),  tau = t - centre_s,
/// with theta_s = ThetaBefore / h^c before the centre (t < centre) and ThetaAfter / h^c
/// after it, h = max(duration / 2, MinimumHalfWidth): the rate scales with the segment, so
/// a segment dominates its own span at any speech rate, and ThetaBefore < ThetaAfter lets
/// the next viseme rise early (anticipatory coarticulation). Channel v of the track is
///   F_v(t) = sum_{s: T_s = v} D_s(t) / sum_s D_s(t),
/// so the channels sum to 1 (the silence channel is the neutral face; rest segments of it,
/// as wide as their neighbour, precede the first segment and follow the last). Closure segments
/// (p b m) must close the lips completely, so their channel is the maximum of F_v and a
/// closure envelope that is 1 over the middle of the segment (never averaged away); the
/// other channels shrink to keep the sum 1. The mouth leads the sound by `Lead`: the frame
/// at time t shows F(t + Lead).

#include "speech/SpeechTypes.h"
#include "speech/VisemeMap.h"
#include "speech/Warning.h"
#include "track/WeightTrack.h"

#include <vector>

namespace morphnode
{
struct CoarticulationOptions
{
  double FrameRate = 60.0; ///< frames per second of the track
  /// Seconds the mouth runs ahead of the audio. Viewers accept picture ahead of sound up to
  /// ~125 ms but notice sound ahead from ~45 ms; 50 ms sits safely inside.
  double Lead = 0.05;
  double ThetaBefore = 1.4;       ///< decay before the centre, per half-width^c (anticipation)
  double ThetaAfter = 2.0;        ///< decay after the centre (carry-over)
  double Power = 1.0;             ///< c
  double MinimumHalfWidth = 0.02; ///< seconds; keeps very short segments from spiking
  /// Fraction of a closure segment's duration held at full closure, centred on it; at
  /// least one frame, so a sampled track always shows the closure.
  double ClosureHold = 0.4;
};

/// One viseme over a time span: what the dominance model blends.
struct VisemeSegment
{
  int Viseme = 0;
  double Start = 0.0;    ///< seconds
  double Duration = 0.0; ///< seconds
  bool Closure = false;  ///< lips must close fully (bilabial)
};

/// Maps phonemes to segments (unknown phonemes warn, see VisemeMap::MapPhoneme).
std::vector<VisemeSegment> PhonemesToVisemeSegments(
  const std::vector<TimedPhoneme>& phonemes, const VisemeMap& map, const WarningHandler& warn = {});

/// The viseme track over [0, duration] (ceil(duration * FrameRate) + 1 frames), one channel
/// per viseme of `map`. InputError for bad options (frame rate <= 0, thetas <= 0, ...).
WeightTrack Coarticulate(const std::vector<VisemeSegment>& segments, const VisemeMap& map,
  double duration, const CoarticulationOptions& options = {});

/// PhonemesToVisemeSegments then Coarticulate.
WeightTrack CoarticulatePhonemes(const std::vector<TimedPhoneme>& phonemes, const VisemeMap& map,
  double duration, const CoarticulationOptions& options = {}, const WarningHandler& warn = {});
} // namespace morphnode
