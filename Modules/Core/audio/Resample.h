// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Resample.h
/// @brief Sample-rate conversion through libsoxr (the SoX resampler library, Debian
/// libsoxr-dev): band-limited, linear phase, no hand-written filters.

#include "audio/AudioBuffer.h"

namespace morphnode
{
enum class ResampleQuality
{
  Quick,  ///< cubic interpolation: fast, for analysis where aliasing does not matter
  Medium, ///< soxr's medium quality (default): plenty for speech analysis
  High    ///< soxr's high quality (20 bits), for sound that is played back
};

/// The buffer at `targetRate`, every channel converted (a buffer already at that rate is
/// returned as is). The length becomes round(frames * targetRate / rate). InputError for a
/// rate <= 0 or a malformed buffer.
AudioBuffer Resample(
  const AudioBuffer& audio, int targetRate, ResampleQuality quality = ResampleQuality::Medium);
} // namespace morphnode
