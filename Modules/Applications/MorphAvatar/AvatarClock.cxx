// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar's real-time clock and its voice: in the window and in live runs the speech
// plays on the sound device (playback/AudioPlayer) and the picture is drawn at the time of
// the sample heard now, so that picture and sound cannot drift apart over minutes and the
// mouth leads the sound by the viseme track's own lead. --mute (or no device that opens):
// the steady clock, as before.
#include "Avatar.h"

#include "audio/AudioBuffer.h"
#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"
#include "behavior/BehaviorAudio.h"

#include <algorithm>
#include <cmath>
#include <iostream>

namespace morphavatar
{
namespace
{
/// The prepared behaviour's speech from time 0 (the window's non-live run).
void ScheduleBehaviorSound(Avatar& a)
{
  if (!a.Player || !a.Behavior->HasAudio())
  {
    return;
  }
  try
  {
    a.Player->Schedule(morphnode::MixBehaviorAudio(a.Behavior->GetController()), 0.0);
  }
  catch (const morphnode::InputError& e)
  {
    std::cerr << "MorphAvatar: the speech cannot be played: " << e.what() << "\n";
  }
}
} // namespace

void Avatar::StartClock(bool scheduleBehaviorSound)
{
  if (this->ClockStarted)
  {
    return;
  }
  this->ClockStarted = true;
  this->Start = this->MeasureStart = this->Launched = Clock::now();
  this->StartTime = 0.0;
  this->Paused = false;
  if (this->Opt.Mute)
  {
    return;
  }
  try
  {
    this->Player = std::make_unique<morphnode::AudioPlayer>();
    this->Player->Open();
    if (!this->Opt.Quiet)
    {
      std::cerr << "MorphAvatar: sound through " << this->Player->GetDriverName()
                << (this->Player->IsDeviceClock() ? "" : " (no sound device: the steady clock)")
                << "\n";
    }
  }
  catch (const morphnode::InputError& e)
  {
    std::cerr << "MorphAvatar: no sound (" << e.what() << ")\n";
    this->Player.reset();
    return;
  }
  if (scheduleBehaviorSound)
  {
    ScheduleBehaviorSound(*this);
  }
  this->Player->SetPaused(false);
}

double Avatar::ClockNow() const
{
  if (this->Player)
  {
    return this->Player->GetTime();
  }
  if (this->Paused)
  {
    return this->StartTime;
  }
  return this->StartTime + std::chrono::duration<double>(Clock::now() - this->Start).count();
}

void Avatar::SetClockPaused(bool paused)
{
  if (paused == this->Paused)
  {
    return;
  }
  const double now = this->ClockNow();
  this->Paused = paused;
  this->Start = Clock::now();
  this->StartTime = now;
  if (this->Player)
  {
    this->Player->SetPaused(paused);
  }
}

void Avatar::SeekClock(double t)
{
  this->Start = Clock::now();
  this->StartTime = t;
  if (this->Player)
  {
    this->Player->Clear();
    this->Player->Seek(t);
    if (!this->LiveFrame)
    {
      ScheduleBehaviorSound(*this);
    }
  }
}

void Avatar::PlaySound(const std::vector<int16_t>& samples, int sampleRate, double start)
{
  if (this->RecordSound && !samples.empty() && sampleRate > 0)
  {
    this->SessionSound.push_back(
      { samples, sampleRate, start, start + static_cast<double>(samples.size()) / sampleRate });
  }
  if (!this->Player || samples.empty())
  {
    return;
  }
  try
  {
    this->Player->Schedule(morphnode::FromInt16Mono(samples, sampleRate), start);
  }
  catch (const morphnode::InputError& e)
  {
    std::cerr << "MorphAvatar: a sound cannot be played: " << e.what() << "\n";
  }
}

void Avatar::CutSound(double t)
{
  for (SoundSegment& segment : this->SessionSound)
  {
    segment.End = std::min(segment.End, std::max(t, segment.Start));
  }
  if (this->Player)
  {
    this->Player->CutFrom(t);
  }
}
} // namespace morphavatar

namespace morphavatar
{
bool Avatar::WriteSessionSound(const std::string& wav) const
{
  constexpr int rate = 22050;
  std::vector<float> mix;
  try
  {
    for (const SoundSegment& segment : this->SessionSound)
    {
      morphnode::AudioBuffer sound = morphnode::FromInt16Mono(segment.Samples, segment.SampleRate);
      if (sound.SampleRate != rate)
      {
        sound = morphnode::Resample(sound, rate);
      }
      const size_t first = static_cast<size_t>(std::max(0.0, std::round(segment.Start * rate)));
      const size_t count = std::min(sound.Samples.size(),
        static_cast<size_t>(std::max(0.0, std::round((segment.End - segment.Start) * rate))));
      if (mix.size() < first + count)
      {
        mix.resize(first + count, 0.0f);
      }
      for (size_t i = 0; i < count; ++i)
      {
        mix[first + i] += sound.Samples[i];
      }
    }
    morphnode::AudioBuffer out;
    out.SampleRate = rate;
    out.Channels = 1;
    out.Samples = std::move(mix);
    for (float& v : out.Samples)
    {
      v = std::clamp(v, -1.0f, 1.0f);
    }
    if (out.Samples.empty())
    {
      out.Samples.assign(rate / 10, 0.0f); // a session without speech: a little silence
    }
    morphnode::WriteWavFile(wav, out);
  }
  catch (const std::exception& e)
  {
    std::cerr << "MorphAvatar: cannot write the session's sound " << wav << ": " << e.what()
              << "\n";
    return false;
  }
  return true;
}
} // namespace morphavatar
