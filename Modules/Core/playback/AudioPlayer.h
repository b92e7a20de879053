// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AudioPlayer.h
/// @brief The avatar's voice: plays sound clips placed on a timeline through the sound
/// device, and is the clock the picture follows.
///
/// GetTime() is the time of the sample being heard now (the samples the device has taken,
/// less its buffer, interpolated between the device's requests with the steady clock). A
/// picture drawn at GetTime() therefore cannot drift from the sound over minutes, whatever
/// the sound card's crystal does, and the mouth leads the sound by exactly the lead the
/// viseme track was made with (speech/Coarticulation: visemes start before their sound).
///
/// Devices: SDL2's audio (Debian libsdl2-dev), which picks PipeWire, PulseAudio or ALSA.
/// Where the machine has no sound device (CI, servers, containers) it plays to SDL's
/// "dummy" driver, which takes samples in real time: the same clock, no sound. Built
/// without SDL2 (MORPHNODE_ENABLE_PLAYBACK=OFF) the player is a steady clock that discards
/// the clips (GetDriverName() == "none").
///
///   morphnode::AudioPlayer player;
///   player.Open();
///   player.Schedule(speech, 0.5);          // a clip heard from t = 0.5 s
///   ... each frame: render the behaviour at player.GetTime()

#include "audio/AudioBuffer.h"

#include <cstdint>
#include <memory>
#include <string>

namespace morphnode
{
class AudioPlayer
{
public:
  struct Options
  {
    int SampleRate = 22050; ///< the rate asked of the device (clips are resampled to its rate)
    int BufferFrames = 512; ///< the device's buffer, frames (latency = BufferFrames / rate)
    /// An SDL audio driver ("pulseaudio", "alsa", "dummy", ...); empty: SDL's choice where the
    /// machine has a sound device, else "dummy". The environment's SDL_AUDIODRIVER wins.
    std::string Driver;
    /// The clock GetTime() reads: the device's position (Device), the steady clock (Steady),
    /// or Auto: the device's where sound is heard, the steady clock on SDL's dummy driver
    /// (nobody hears it, and a starved dummy thread runs slow: 19 % on a loaded machine).
    enum class ClockSource
    {
      Auto,
      Device,
      Steady
    };
    ClockSource Clock = ClockSource::Auto;
  };
  /// True when GetTime() follows the device (not the steady clock).
  bool IsDeviceClock() const;

  AudioPlayer();
  ~AudioPlayer();
  AudioPlayer(const AudioPlayer&) = delete;
  AudioPlayer& operator=(const AudioPlayer&) = delete;

  /// Opens the device and starts the clock at 0 (paused: SetPaused(false) starts it).
  /// InputError when no device can be opened, not even the dummy one.
  void Open(const Options& options);
  void Open() { this->Open(Options()); }
  void Close();
  bool IsOpen() const;
  /// "pulseaudio", "alsa", "dummy" (no sound device), "none" (built without SDL2).
  std::string GetDriverName() const;
  int GetSampleRate() const;
  /// The device buffer in seconds: how far the clock lags the samples taken.
  double GetLatency() const;

  /// Adds a clip (any rate and channel count; mixed to mono, resampled to the device's
  /// rate) heard from `start` seconds on the player's clock; clips may overlap (they add).
  /// A clip that starts in the past plays from its part at the present. Thread-safe.
  void Schedule(const AudioBuffer& clip, double start);
  /// Silences everything scheduled from time t on (stop speaking). Thread-safe.
  void CutFrom(double t);
  /// Removes every clip.
  void Clear();
  /// Seconds of scheduled sound not yet heard.
  double GetPendingSeconds() const;

  /// The clock: the time of the sample heard now, in seconds; it stands while paused.
  double GetTime() const;
  void SetPaused(bool paused);
  bool GetPaused() const;
  /// Moves the clock to t (e.g. restarting an animation); scheduled clips keep their times.
  void Seek(double t);

  /// Frames the device has taken since Open (for tests and the drift study).
  uint64_t GetFramesTaken() const;

private:
  /// The timeline frame the device takes next (without a device: the clock's).
  int64_t PresentFrame() const;

  struct Internals;
  std::unique_ptr<Internals> Impl;
};
} // namespace morphnode
