// SPDX-License-Identifier: BSD-3-Clause
#include "audio/Resample.h"

#include "base/Error.h"

#include <soxr.h>

#include <cmath>
#include <string>

namespace morphnode
{
AudioBuffer Resample(const AudioBuffer& audio, int targetRate, ResampleQuality quality)
{
  if (audio.SampleRate <= 0 || targetRate <= 0)
  {
    throw InputError("resampling needs sample rates > 0 (from " + std::to_string(audio.SampleRate) +
      " Hz to " + std::to_string(targetRate) + " Hz)");
  }
  if (audio.Channels <= 0 || audio.Samples.size() % static_cast<size_t>(audio.Channels) != 0)
  {
    throw InputError("resampling needs at least one channel and whole frames");
  }
  if (audio.SampleRate == targetRate)
  {
    return audio;
  }
  AudioBuffer out;
  out.SampleRate = targetRate;
  out.Channels = audio.Channels;
  const size_t frames = audio.GetFrameCount();
  if (frames == 0)
  {
    return out;
  }
  const double ratio = static_cast<double>(targetRate) / audio.SampleRate;
  const double outLength = static_cast<double>(frames) * ratio * audio.Channels;
  if (!(outLength <= static_cast<double>(MaxAudioSamples)))
  {
    // Decided before the memory is taken (docs/limits.md).
    throw InputError("resampling " + std::to_string(frames) + " frames from " +
      std::to_string(audio.SampleRate) + " Hz to " + std::to_string(targetRate) +
      " Hz would make more than " + std::to_string(MaxAudioSamples) + " samples");
  }
  const size_t outFrames = static_cast<size_t>(std::llround(static_cast<double>(frames) * ratio));
  out.Samples.resize(outFrames * static_cast<size_t>(audio.Channels));
  if (outFrames == 0)
  {
    return out;
  }
  unsigned long recipe = SOXR_MQ;
  switch (quality)
  {
    case ResampleQuality::Quick:
      recipe = SOXR_QQ;
      break;
    case ResampleQuality::Medium:
      recipe = SOXR_MQ;
      break;
    case ResampleQuality::High:
      recipe = SOXR_HQ;
      break;
  }
  const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT32_I, SOXR_FLOAT32_I);
  const soxr_quality_spec_t spec = soxr_quality_spec(recipe, 0);
  size_t done = 0;
  const soxr_error_t error = soxr_oneshot(audio.SampleRate, targetRate,
    static_cast<unsigned>(audio.Channels), audio.Samples.data(), frames, nullptr,
    out.Samples.data(), outFrames, &done, &io, &spec, nullptr);
  if (error)
  {
    throw InputError(std::string("resampling failed: ") + error);
  }
  // soxr_oneshot flushes, so `done` is outFrames up to rounding; pad the rest with silence.
  for (size_t i = done * static_cast<size_t>(audio.Channels); i < out.Samples.size(); ++i)
  {
    out.Samples[i] = 0.0f;
  }
  return out;
}
} // namespace morphnode
