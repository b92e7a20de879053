// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AudioBuffer.h
/// @brief Sampled sound in memory: interleaved float samples in [-1, 1] at a rate, with
/// the conversions every user needs (mono mix, 16-bit samples, duration).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace morphnode
{
/// Limits of sound the core takes, decided before decoding or resampling (docs/limits.md):
/// a header's rate outside them is refused at once, a longer sound while it is decoded,
/// a resampling whose result would be longer before its memory is taken.
constexpr int MinSampleRate = 4000;   ///< Hz (a 1 Hz header would be resampled 16,000x)
constexpr int MaxSampleRate = 384000; ///< Hz
constexpr int MaxAudioChannels = 64;
/// Samples (all channels) in one buffer: 2^28, 1 GiB of float (about 2.3 h mono at 32 kHz,
/// 46 min of 48 kHz stereo).
constexpr size_t MaxAudioSamples = size_t(1) << 28;
/// Seconds of sound in one file.
constexpr double MaxAudioSeconds = 3.0 * 3600.0;
struct AudioBuffer
{
  /// Interleaved: frame f, channel c at Samples[f * Channels + c]. Nominally in [-1, 1].
  std::vector<float> Samples;
  int SampleRate = 0; ///< frames per second
  int Channels = 0;

  /// Number of frames (samples per channel); 0 when Channels <= 0.
  size_t GetFrameCount() const
  {
    return this->Channels > 0 ? this->Samples.size() / static_cast<size_t>(this->Channels) : 0;
  }
  /// Seconds; 0 when the rate is not set.
  double GetDuration() const
  {
    return this->SampleRate > 0 ? static_cast<double>(this->GetFrameCount()) / this->SampleRate
                                : 0.0;
  }
  bool IsEmpty() const { return this->GetFrameCount() == 0; }
};

/// The average of the channels, one float per frame (a mono buffer is returned as is).
/// InputError when Channels <= 0 or the sample count is not a multiple of it.
AudioBuffer MixToMono(const AudioBuffer& audio);

/// Mono 16-bit samples (mixed, clipped to the 16-bit range, rounded).
std::vector<int16_t> ToInt16Mono(const AudioBuffer& audio);

/// A mono buffer from 16-bit samples (/ 32768).
AudioBuffer FromInt16Mono(const std::vector<int16_t>& samples, int sampleRate);

/// Root mean square of the samples (all channels); 0 for an empty buffer.
double RootMeanSquare(const AudioBuffer& audio);
} // namespace morphnode
