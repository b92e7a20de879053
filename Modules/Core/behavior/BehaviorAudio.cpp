// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/BehaviorAudio.h"

#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace morphnode
{
AudioBuffer MixUtteranceAudio(
  const std::vector<BehaviorController::ScheduledUtterance>& utterances, double minimumDuration)
{
  if (!(minimumDuration >= 0.0) || !std::isfinite(minimumDuration))
  {
    std::ostringstream msg;
    msg << "audio mix: minimum duration " << minimumDuration << " is not a time in seconds >= 0";
    throw InputError(msg.str());
  }
  AudioBuffer mix;
  mix.Channels = 1;
  mix.SampleRate = 0;
  double end = minimumDuration;
  for (const auto& u : utterances)
  {
    if (!u.Speech.Audio.empty() && u.Speech.SampleRate > 0 && u.Start >= 0.0)
    {
      mix.SampleRate = std::max(mix.SampleRate, u.Speech.SampleRate);
      end =
        std::max(end, u.Start + static_cast<double>(u.Speech.Audio.size()) / u.Speech.SampleRate);
    }
  }
  if (mix.SampleRate == 0)
  {
    mix.SampleRate = DefaultMixSampleRate;
  }
  const double rate = mix.SampleRate;
  // The memory budget of one sound (MaxAudioSamples, 1 GiB of float: 3.4 h at 22050 Hz;
  // docs/limits.md), decided before the mix is allocated. (A 16-bit WAV file would hold
  // 2^31.)
  if (!(end * rate < static_cast<double>(MaxAudioSamples)))
  {
    std::ostringstream msg;
    msg << "audio mix: " << end << " s at " << mix.SampleRate << " Hz is more than "
        << MaxAudioSamples << " samples (docs/limits.md)";
    throw InputError(msg.str());
  }
  const size_t n = static_cast<size_t>(std::max(0.0, std::ceil(end * rate - 1e-9)));
  mix.Samples.assign(n, 0.0f);

  for (const auto& u : utterances)
  {
    if (u.Speech.Audio.empty() || u.Speech.SampleRate <= 0 || !(u.Start >= 0.0))
    {
      continue;
    }
    AudioBuffer sound = FromInt16Mono(u.Speech.Audio, u.Speech.SampleRate);
    if (u.Speech.SampleRate != mix.SampleRate)
    {
      sound = Resample(sound, mix.SampleRate, ResampleQuality::High);
    }
    const double first = std::round(u.Start * rate);
    if (!(first < static_cast<double>(n)))
    {
      continue;
    }
    const size_t offset = static_cast<size_t>(first);
    const size_t count = std::min(n - offset, sound.Samples.size());
    for (size_t j = 0; j < count; ++j)
    {
      mix.Samples[offset + j] += sound.Samples[j];
    }
  }
  return mix;
}

AudioBuffer MixBehaviorAudio(const BehaviorController& behavior)
{
  if (!behavior.IsPrepared())
  {
    throw InputError("BehaviorController: call Prepare() after changing the behaviour");
  }
  return MixUtteranceAudio(behavior.GetUtterances(), behavior.GetEffectiveDuration());
}

void WriteBehaviorAudio(const std::string& path, const BehaviorController& behavior)
{
  const AudioBuffer mix = MixBehaviorAudio(behavior);
  WriteWavFile(path, ToInt16Mono(mix), mix.SampleRate);
}
} // namespace morphnode
