// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the sound file reader (libsndfile through audio/AudioFile), then mono mixing,
// resampling and WAV writing of whatever it accepts.
#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try
  {
    const morphnode::AudioBuffer audio = morphnode::ReadAudioMemory(bytes, "fuzz input");
    if (audio.Channels <= 0 || audio.SampleRate <= 0 || audio.IsEmpty() ||
      audio.Samples.size() % static_cast<size_t>(audio.Channels) != 0)
    {
      std::abort(); // the reader promised a usable buffer
    }
    for (float s : audio.Samples)
    {
      if (!std::isfinite(s))
      {
        std::abort();
      }
    }
    if (audio.GetFrameCount() < 100000 && audio.SampleRate < 400000)
    {
      const morphnode::AudioBuffer mono = morphnode::MixToMono(audio);
      const morphnode::AudioBuffer resampled =
        morphnode::Resample(mono, 16000, morphnode::ResampleQuality::Quick);
      std::ostringstream out;
      morphnode::WriteWav(out, resampled.IsEmpty() ? mono : resampled);
    }
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  return 0;
}
