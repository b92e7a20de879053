// SPDX-License-Identifier: BSD-3-Clause
#include "audio/AudioBuffer.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace
{
void CheckLayout(const AudioBuffer& audio)
{
  if (audio.Channels <= 0)
  {
    throw InputError("an audio buffer needs at least one channel");
  }
  if (audio.Samples.size() % static_cast<size_t>(audio.Channels) != 0)
  {
    throw InputError("an audio buffer's sample count must be a multiple of its channel count");
  }
}
} // namespace

AudioBuffer MixToMono(const AudioBuffer& audio)
{
  CheckLayout(audio);
  if (audio.Channels == 1)
  {
    return audio;
  }
  AudioBuffer mono;
  mono.SampleRate = audio.SampleRate;
  mono.Channels = 1;
  const size_t frames = audio.GetFrameCount();
  const size_t channels = static_cast<size_t>(audio.Channels);
  mono.Samples.resize(frames);
  for (size_t f = 0; f < frames; ++f)
  {
    double sum = 0.0;
    for (size_t c = 0; c < channels; ++c)
    {
      sum += audio.Samples[f * channels + c];
    }
    mono.Samples[f] = static_cast<float>(sum / static_cast<double>(channels));
  }
  return mono;
}

std::vector<int16_t> ToInt16Mono(const AudioBuffer& audio)
{
  const AudioBuffer mono = MixToMono(audio);
  std::vector<int16_t> out(mono.Samples.size());
  for (size_t i = 0; i < out.size(); ++i)
  {
    const float s = mono.Samples[i];
    // NaN becomes silence; everything else is clipped to the 16-bit range.
    const double v = std::isnan(s) ? 0.0 : std::clamp(std::round(s * 32768.0), -32768.0, 32767.0);
    out[i] = static_cast<int16_t>(v);
  }
  return out;
}

AudioBuffer FromInt16Mono(const std::vector<int16_t>& samples, int sampleRate)
{
  AudioBuffer audio;
  audio.SampleRate = sampleRate;
  audio.Channels = 1;
  audio.Samples.resize(samples.size());
  for (size_t i = 0; i < samples.size(); ++i)
  {
    audio.Samples[i] = static_cast<float>(samples[i] / 32768.0);
  }
  return audio;
}

double RootMeanSquare(const AudioBuffer& audio)
{
  if (audio.Samples.empty())
  {
    return 0.0;
  }
  double sum = 0.0;
  for (float s : audio.Samples)
  {
    sum += static_cast<double>(s) * s;
  }
  return std::sqrt(sum / static_cast<double>(audio.Samples.size()));
}
} // namespace morphnode
