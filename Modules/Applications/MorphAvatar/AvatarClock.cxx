// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar's real-time clock and its voice: in the window and in live runs the speech
// plays on the sound device (playback/AudioPlayer) and the picture is drawn at the time of
// the sample heard now, so that picture and sound cannot drift apart over minutes and the
// mouth leads the sound by the viseme track's own lead. --mute (or no device that opens):
// the steady clock, as before.
#include "Avatar.h"

#include "audio/AudioBuffer.h"
#include "base/Error.h"
#include "behavior/BehaviorAudio.h"

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
  if (this->Player)
  {
    this->Player->CutFrom(t);
  }
}
} // namespace morphavatar
