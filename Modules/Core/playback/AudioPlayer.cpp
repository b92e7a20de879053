// SPDX-License-Identifier: BSD-3-Clause
#include "playback/AudioPlayer.h"

#include "audio/Resample.h"
#include "base/Error.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#if MORPHNODE_HAVE_SDL2
#include <SDL.h>
#endif

namespace morphnode
{
namespace
{
using Clock = std::chrono::steady_clock;

int64_t Nanoseconds(Clock::time_point t)
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

struct Clip
{
  int64_t StartFrame = 0;
  std::vector<float> Samples;
  int64_t End() const { return this->StartFrame + static_cast<int64_t>(this->Samples.size()); }
};

#if MORPHNODE_HAVE_SDL2
/// A sound server or card this process could reach; without one SDL would only fail (and
/// ALSA print a page of errors), so the dummy driver is taken directly.
bool HasSoundDevice()
{
  std::error_code ignored;
  if (std::getenv("PULSE_SERVER") || std::filesystem::exists("/dev/snd", ignored))
  {
    return true;
  }
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  return runtime &&
    (std::filesystem::exists(std::filesystem::path(runtime) / "pulse" / "native", ignored) ||
      std::filesystem::exists(std::filesystem::path(runtime) / "pipewire-0", ignored));
}
#endif
} // namespace

struct AudioPlayer::Internals
{
  mutable std::mutex Mutex; // the clips and the position
  std::vector<Clip> Clips;
  int64_t Position = 0;   // timeline frame of the next frame the device takes
  int64_t Taken = 0;      // frames the device has taken since Open
  int64_t CallbackNs = 0; // steady time of the device's last request
  int64_t PositionAtCallback = 0;
  std::atomic<bool> Paused{ true };
  bool Open = false;
  bool DeviceClock = false; // GetTime() from the device's position
  int Rate = 22050;
  int Buffer = 512;
  std::string Driver = "none";
  // Without a device: the clock is the steady clock.
  double NullOffset = 0.0;
  Clock::time_point NullResumed;
#if MORPHNODE_HAVE_SDL2
  SDL_AudioDeviceID Device = 0;

  static void Callback(void* userdata, Uint8* stream, int length)
  {
    auto* self = static_cast<Internals*>(userdata);
    float* out = reinterpret_cast<float*>(stream);
    const int64_t frames = length / static_cast<int>(sizeof(float));
    std::fill(out, out + frames, 0.0f);
    std::lock_guard<std::mutex> lock(self->Mutex);
    self->Taken += frames;
    self->CallbackNs = Nanoseconds(Clock::now());
    if (self->Paused.load())
    {
      self->PositionAtCallback = self->Position;
      return;
    }
    const int64_t begin = self->Position;
    const int64_t end = begin + frames;
    for (const Clip& clip : self->Clips)
    {
      const int64_t from = std::max(begin, clip.StartFrame);
      const int64_t to = std::min(end, clip.End());
      for (int64_t t = from; t < to; ++t)
      {
        out[t - begin] += clip.Samples[static_cast<size_t>(t - clip.StartFrame)];
      }
    }
    for (int64_t i = 0; i < frames; ++i)
    {
      out[i] = std::clamp(out[i], -1.0f, 1.0f);
    }
    self->Clips.erase(std::remove_if(self->Clips.begin(), self->Clips.end(),
                        [end](const Clip& c) { return c.End() <= end; }),
      self->Clips.end());
    self->Position = end;
    self->PositionAtCallback = end;
  }
#endif
};

AudioPlayer::AudioPlayer()
  : Impl(new Internals)
{
}

AudioPlayer::~AudioPlayer()
{
  this->Close();
}

void AudioPlayer::Open(const Options& options)
{
  if (options.SampleRate < 8000 || options.SampleRate > 192000)
  {
    throw InputError("audio player: sample rate must be in [8000, 192000] Hz");
  }
  if (options.BufferFrames < 64 || options.BufferFrames > 65536)
  {
    throw InputError("audio player: buffer must be in [64, 65536] frames");
  }
  this->Close();
  Internals& d = *this->Impl;
  d.Rate = options.SampleRate;
  d.Buffer = options.BufferFrames;
  d.Position = d.Taken = d.PositionAtCallback = 0;
  d.Paused = true;
  d.DeviceClock = false;
  d.NullOffset = 0.0;
  d.NullResumed = Clock::now();
#if MORPHNODE_HAVE_SDL2
  std::string driver = options.Driver;
  if (driver.empty() && !std::getenv("SDL_AUDIODRIVER") && !HasSoundDevice())
  {
    driver = "dummy";
  }
  auto tryOpen = [&](const std::string& name) -> bool
  {
    SDL_SetHint(SDL_HINT_AUDIODRIVER, name.empty() ? nullptr : name.c_str());
    if (SDL_InitSubSystem(SDL_INIT_AUDIO) != 0)
    {
      return false;
    }
    SDL_AudioSpec want{};
    SDL_AudioSpec have{};
    want.freq = options.SampleRate;
    want.format = AUDIO_F32SYS;
    want.channels = 1;
    want.samples = static_cast<Uint16>(std::min(options.BufferFrames, 32768));
    want.callback = &Internals::Callback;
    want.userdata = &d;
    d.Device = SDL_OpenAudioDevice(
      nullptr, 0, &want, &have, SDL_AUDIO_ALLOW_FREQUENCY_CHANGE | SDL_AUDIO_ALLOW_SAMPLES_CHANGE);
    if (d.Device == 0)
    {
      SDL_QuitSubSystem(SDL_INIT_AUDIO);
      return false;
    }
    d.Rate = have.freq;
    d.Buffer = have.samples;
    const char* current = SDL_GetCurrentAudioDriver();
    d.Driver = current ? current : "?";
    return true;
  };
  if (!tryOpen(driver) && (driver == "dummy" || !tryOpen("dummy")))
  {
    throw InputError(
      std::string("audio player: no sound device, not even SDL's dummy one: ") + SDL_GetError());
  }
  d.CallbackNs = Nanoseconds(Clock::now());
  d.DeviceClock = options.Clock == Options::ClockSource::Device ||
    (options.Clock == Options::ClockSource::Auto && d.Driver != "dummy");
  SDL_PauseAudioDevice(d.Device, 0); // the device runs; the clock stands until SetPaused(false)
#else
  (void)options.Driver;
  d.Driver = "none";
#endif
  d.Open = true;
}

void AudioPlayer::Close()
{
  Internals& d = *this->Impl;
  if (!d.Open)
  {
    return;
  }
#if MORPHNODE_HAVE_SDL2
  SDL_CloseAudioDevice(d.Device); // waits for a running callback
  d.Device = 0;
  SDL_QuitSubSystem(SDL_INIT_AUDIO);
#endif
  d.Open = false;
  std::lock_guard<std::mutex> lock(d.Mutex);
  d.Clips.clear();
}

bool AudioPlayer::IsOpen() const
{
  return this->Impl->Open;
}

std::string AudioPlayer::GetDriverName() const
{
  return this->Impl->Driver;
}

int AudioPlayer::GetSampleRate() const
{
  return this->Impl->Rate;
}

double AudioPlayer::GetLatency() const
{
  return static_cast<double>(this->Impl->Buffer) / this->Impl->Rate;
}

void AudioPlayer::Schedule(const AudioBuffer& clip, double start)
{
  if (!std::isfinite(start) || std::abs(start) > 1e7)
  {
    throw InputError("audio player: a clip's start time must be a finite number of seconds");
  }
  if (clip.IsEmpty())
  {
    return;
  }
  Internals& d = *this->Impl;
  Clip c;
  c.StartFrame = static_cast<int64_t>(std::llround(start * d.Rate));
  c.Samples = Resample(MixToMono(clip), d.Rate, ResampleQuality::High).Samples;
  const int64_t now = this->PresentFrame();
  std::lock_guard<std::mutex> lock(d.Mutex);
  // Without a device nothing takes the clips: forget those that are over.
  d.Clips.erase(
    std::remove_if(d.Clips.begin(), d.Clips.end(), [now](const Clip& k) { return k.End() <= now; }),
    d.Clips.end());
  d.Clips.push_back(std::move(c));
}

int64_t AudioPlayer::PresentFrame() const
{
  const Internals& d = *this->Impl;
#if MORPHNODE_HAVE_SDL2
  if (d.Open)
  {
    std::lock_guard<std::mutex> lock(d.Mutex);
    return d.Position;
  }
#endif
  return static_cast<int64_t>(std::llround(this->GetTime() * d.Rate));
}

void AudioPlayer::CutFrom(double t)
{
  Internals& d = *this->Impl;
  const int64_t frame = static_cast<int64_t>(std::llround(t * d.Rate));
  std::lock_guard<std::mutex> lock(d.Mutex);
  for (Clip& c : d.Clips)
  {
    if (c.End() > frame)
    {
      c.Samples.resize(static_cast<size_t>(std::max<int64_t>(0, frame - c.StartFrame)));
    }
  }
  d.Clips.erase(
    std::remove_if(d.Clips.begin(), d.Clips.end(), [](const Clip& c) { return c.Samples.empty(); }),
    d.Clips.end());
}

void AudioPlayer::Clear()
{
  std::lock_guard<std::mutex> lock(this->Impl->Mutex);
  this->Impl->Clips.clear();
}

double AudioPlayer::GetPendingSeconds() const
{
  const Internals& d = *this->Impl;
  const int64_t now = this->PresentFrame();
  std::lock_guard<std::mutex> lock(d.Mutex);
  int64_t end = now;
  for (const Clip& c : d.Clips)
  {
    end = std::max(end, c.End());
  }
  return static_cast<double>(end - now) / d.Rate;
}

bool AudioPlayer::IsDeviceClock() const
{
  return this->Impl->Open && this->Impl->DeviceClock;
}

double AudioPlayer::GetTime() const
{
  const Internals& d = *this->Impl;
#if MORPHNODE_HAVE_SDL2
  if (d.Open && d.DeviceClock)
  {
    std::lock_guard<std::mutex> lock(d.Mutex);
    // The sample heard now: the device has the last buffer still to play.
    double t = static_cast<double>(d.PositionAtCallback - d.Buffer) / d.Rate;
    if (!d.Paused.load())
    {
      const double since = (Nanoseconds(Clock::now()) - d.CallbackNs) * 1e-9;
      t += std::clamp(since, 0.0, static_cast<double>(d.Buffer) / d.Rate);
    }
    return std::max(0.0, t);
  }
#endif
  if (d.Paused.load())
  {
    return d.NullOffset;
  }
  return d.NullOffset + std::chrono::duration<double>(Clock::now() - d.NullResumed).count();
}

void AudioPlayer::SetPaused(bool paused)
{
  Internals& d = *this->Impl;
  if (paused == d.Paused.load())
  {
    return;
  }
  if (paused)
  {
    d.NullOffset = this->GetTime();
  }
  else
  {
    d.NullResumed = Clock::now();
  }
  d.Paused = paused;
}

bool AudioPlayer::GetPaused() const
{
  return this->Impl->Paused.load();
}

void AudioPlayer::Seek(double t)
{
  if (!std::isfinite(t) || t < 0.0)
  {
    throw InputError("audio player: seek to a time >= 0");
  }
  Internals& d = *this->Impl;
  {
    std::lock_guard<std::mutex> lock(d.Mutex);
    d.Position = static_cast<int64_t>(std::llround(t * d.Rate)) + d.Buffer;
    d.PositionAtCallback = d.Position;
    d.CallbackNs = Nanoseconds(Clock::now());
  }
  d.NullOffset = t;
  d.NullResumed = Clock::now();
}

uint64_t AudioPlayer::GetFramesTaken() const
{
  const Internals& d = *this->Impl;
#if MORPHNODE_HAVE_SDL2
  if (d.Open)
  {
    std::lock_guard<std::mutex> lock(d.Mutex);
    return static_cast<uint64_t>(d.Taken);
  }
#endif
  return static_cast<uint64_t>(std::llround(this->GetTime() * d.Rate));
}
} // namespace morphnode
