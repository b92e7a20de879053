// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar live (AvatarLive.h): the dialog server and session of Modules/Core/dialog on
// the avatar's behaviour, in the window's loop or a headless real-time loop.
//
// The commands run on the vtkBehaviorTimeSource of the pipeline: each one is added at the
// clock's time and the source prepares its schedule again (idle behaviour of the same seed,
// so what was shown does not change). Its horizon grows ahead of the clock, so the avatar
// runs for as long as it is left running, without looping.
#include "AvatarLive.h"

#include "Avatar.h"

#include "base/Error.h"
#include "behavior/BehaviorTypes.h"
#include "dialog/DialogServer.h"
#include "dialog/DialogSession.h"
#include "speech/Speech.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <vector>

namespace morphavatar
{
namespace dialog = morphnode::dialog;

namespace
{
/// Seconds of behaviour prepared ahead of the clock, and when to extend it.
constexpr double Horizon = 600.0;
constexpr double HorizonMargin = 60.0;
/// A stopped utterance's mouth closes over this many seconds.
constexpr double StopFade = 0.12;
/// A viseme weight above this moves the mouth visibly; a sample above this is heard.
constexpr double MotionWeight = 0.05;
constexpr int AudibleSample = 328; // 1 % of full scale

/// The first time (seconds from the utterance's start) the mouth moves; its duration when
/// it never does.
double FirstMotion(const morphnode::Utterance& u)
{
  const morphnode::WeightTrack& v = u.Visemes;
  for (size_t f = 0; f < v.GetNumberOfFrames(); ++f)
  {
    const double* frame = v.GetFrame(f);
    for (size_t c = 0; c < v.GetNumberOfChannels(); ++c)
    {
      if (frame[c] > MotionWeight)
      {
        return v.GetTime(f);
      }
    }
  }
  return u.Duration;
}

/// The first audible sample's time; NaN without sound.
double FirstSound(const morphnode::Utterance& u)
{
  for (size_t i = 0; i < u.Audio.size(); ++i)
  {
    if (std::abs(static_cast<int>(u.Audio[i])) >= AudibleSample)
    {
      return static_cast<double>(i) / u.SampleRate;
    }
  }
  return std::nan("");
}

double UtteranceLength(const morphnode::Utterance& u)
{
  const morphnode::WeightTrack& v = u.Visemes;
  const double track = v.GetNumberOfFrames() > 0 ? v.GetTime(v.GetNumberOfFrames() - 1) : 0.0;
  return std::max(u.Duration, track);
}

/// The utterance up to `cut` seconds from its start, the mouth closing over StopFade.
morphnode::Utterance CutUtterance(const morphnode::Utterance& u, double cut)
{
  morphnode::Utterance out;
  out.SampleRate = u.SampleRate;
  for (const auto& p : u.Phonemes)
  {
    if (p.Start < cut)
    {
      out.Phonemes.push_back(p);
    }
  }
  for (const auto& c : u.Cues)
  {
    if (c.Start < cut)
    {
      out.Cues.push_back(c);
    }
  }
  const morphnode::WeightTrack& v = u.Visemes;
  out.Visemes = morphnode::WeightTrack(v.GetChannels(), v.GetFrameRate());
  const size_t channels = v.GetNumberOfChannels();
  std::vector<double> frame(channels);
  for (size_t f = 0; f < v.GetNumberOfFrames(); ++f)
  {
    const double t = v.GetTime(f);
    if (t > cut + StopFade)
    {
      break;
    }
    const double fade = t <= cut ? 1.0 : std::max(0.0, 1.0 - (t - cut) / StopFade);
    for (size_t c = 0; c < channels; ++c)
    {
      frame[c] = v.GetValue(f, c) * fade;
    }
    out.Visemes.AppendFrame(frame);
  }
  std::fill(frame.begin(), frame.end(), 0.0);
  out.Visemes.AppendFrame(frame); // closed
  const size_t samples = static_cast<size_t>(std::max(0.0, cut) * u.SampleRate);
  out.Audio.assign(u.Audio.begin(), u.Audio.begin() + std::min(samples, u.Audio.size()));
  out.Duration = std::min(u.Duration, cut + StopFade);
  return out;
}

/// The dialog's commands on the avatar's behaviour source.
class BehaviorSink : public dialog::CommandSink
{
public:
  BehaviorSink(Avatar& avatar, std::function<double()> clock)
    : A(avatar)
    , Clock(std::move(clock))
  {
  }

  dialog::Schedule Say(const dialog::SayCommand& c, double now) override
  {
    vtkBehaviorTimeSource* b = this->A.Behavior;
    morphnode::SpeechOptions options;
    options.Voice = c.Voice.empty() ? std::string(b->GetVoice()) : c.Voice;
    options.Rate = b->GetSpeechRate();
    options.Visemes = static_cast<morphnode::VisemeSet>(b->GetVisemeSet());
    options.VisemeTablePath = b->GetVisemeTableFileName() ? b->GetVisemeTableFileName() : "";
    morphnode::Utterance u = morphnode::SpeakText(c.Text, options); // InputError: rejected
    // After the synthesis, or after the speech already scheduled.
    const double start = std::max({ now, this->Clock(), this->SpeechEnd });
    if (!b->Speak(u, start))
    {
      throw morphnode::InputError("the behaviour did not take the utterance (see stderr)");
    }
    const double length = UtteranceLength(u);
    dialog::Schedule s(start + std::min(FirstMotion(u), length), start + length);
    s.Sound = start + FirstSound(u);
    this->SpeechEnd = s.End;
    this->Said.push_back(Spoken{ std::move(u), start });
    return s;
  }

  dialog::Schedule Gesture(const dialog::GestureCommand& c, double now) override
  {
    const morphnode::GestureKind kind = morphnode::ParseGestureName(c.Name); // InputError
    const double duration = c.Duration > 0.0 ? c.Duration : morphnode::DefaultGestureDuration(kind);
    if (!this->A.Behavior->Gesture(c.Name.c_str(), now, duration, c.Intensity))
    {
      throw morphnode::InputError("the behaviour did not take the gesture (see stderr)");
    }
    this->Commands.push_back([c, now, duration](vtkBehaviorTimeSource* b) {
      b->Gesture(c.Name.c_str(), now, duration, c.Intensity);
    });
    return dialog::Schedule(now, now + duration);
  }

  dialog::Schedule Mood(const dialog::MoodCommand& c, double now) override
  {
    morphnode::ParseMoodName(c.Name); // InputError for unknown moods
    if (!this->A.Behavior->SetMood(c.Name.c_str(), c.Intensity, now))
    {
      throw morphnode::InputError("the behaviour did not take the mood (see stderr)");
    }
    this->Commands.push_back(
      [c, now](vtkBehaviorTimeSource* b) { b->SetMood(c.Name.c_str(), c.Intensity, now); });
    return dialog::Schedule(now, now + this->A.Behavior->GetBehaviorParameters().MoodFadeTime);
  }

  dialog::Schedule LookAt(const dialog::LookAtCommand& c, double now) override
  {
    if (!this->A.Behavior->LookAt(c.Yaw, c.Pitch, now, c.Duration))
    {
      throw morphnode::InputError("the behaviour did not take the look (see stderr)");
    }
    this->Commands.push_back(
      [c, now](vtkBehaviorTimeSource* b) { b->LookAt(c.Yaw, c.Pitch, now, c.Duration); });
    return dialog::Schedule(now, now + c.Duration);
  }

  /// The source has no way to take speech back: its commands are made again, the start-up
  /// ones (options) and this session's, with speech cut at `now` and later speech left out.
  void StopSpeaking(double now) override
  {
    vtkBehaviorTimeSource* b = this->A.Behavior;
    b->ClearCommands();
    this->A.SetUpBehavior();
    for (const auto& command : this->Commands)
    {
      command(b);
    }
    std::vector<Spoken> kept;
    for (Spoken& s : this->Said)
    {
      if (s.Start >= now)
      {
        continue; // not begun: dropped
      }
      if (s.Start + UtteranceLength(s.Speech) > now)
      {
        s.Speech = CutUtterance(s.Speech, now - s.Start);
      }
      b->Speak(s.Speech, s.Start);
      kept.push_back(std::move(s));
    }
    this->Said = std::move(kept);
    this->SpeechEnd = now;
    this->Horizon = 0.0;
    this->KeepAhead(now);
  }

  /// Keeps the behaviour prepared well ahead of t (the source's duration).
  void KeepAhead(double t)
  {
    if (t + HorizonMargin > this->Horizon)
    {
      this->Horizon = t + Horizon;
      this->A.Behavior->SetDuration(this->Horizon);
      this->A.Duration = this->Horizon;
    }
  }

private:
  struct Spoken
  {
    morphnode::Utterance Speech;
    double Start;
  };
  Avatar& A;
  std::function<double()> Clock;
  double SpeechEnd = 0.0;
  double Horizon = 0.0;
  std::vector<Spoken> Said;
  std::vector<std::function<void(vtkBehaviorTimeSource*)>> Commands;
};

/// The server, the session and the clock of one live run.
struct Live
{
  Avatar& A;
  dialog::DialogServer Server;
  std::unique_ptr<BehaviorSink> Sink;
  std::unique_ptr<dialog::DialogSession> Session;
  Clock::time_point T0;
  bool Stdin = false;

  Live(Avatar& avatar, const dialog::DialogServer::Settings& settings)
    : A(avatar)
    , Server(settings)
  {
  }
  /// The avatar's clock: the window's (pausable) time, or seconds since the start.
  double Now() const
  {
    if (this->A.Paused)
    {
      return this->A.StartTime;
    }
    return this->A.StartTime + std::chrono::duration<double>(Clock::now() - this->A.Start).count();
  }
  /// Before a frame at t: commands that arrived run now. False to stop.
  bool Before(double t)
  {
    this->Sink->KeepAhead(t);
    this->Session->Receive(t, 0);
    return !this->Session->QuitRequested();
  }
  /// After the frame at t is on the screen: started / ended events.
  void After(double t) { this->Session->Advance(t); }
  /// Headless with commands on stdin only: stdin ended and nothing runs any more.
  bool Finished() const
  {
    return this->Stdin && this->Server.GetAddresses().empty() &&
      !this->Server.IsConnected(dialog::DialogServer::StreamClient) &&
      this->Session->GetNumberOfRunning() == 0;
  }
};

/// Every frame at the frame rate in real time, offscreen; commands arriving between frames
/// run at once (they do not wait for the next frame).
int RunHeadless(Live& live)
{
  Avatar& a = live.A;
  a.Window->OffScreenRenderingOn();
  const double frame = 1.0 / a.Fps;
  auto next = Clock::now();
  for (;;)
  {
    const double t = live.Now();
    if (!live.Before(t))
    {
      break;
    }
    if (!a.Update(t))
    {
      std::cerr << "MorphAvatar: the face could not be morphed at t = " << t << " (see above)\n";
      return 1;
    }
    a.Overlay->SetInput(a.OverlayText(true, ++a.FramesRendered, 0).c_str());
    a.Window->Render();
    live.After(t);
    if (live.Finished() || (a.Opt.ExitAfter >= 0.0 && t >= a.Opt.ExitAfter))
    {
      break;
    }
    next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(frame));
    if (next < Clock::now())
    {
      next = Clock::now(); // late: no catching up with a burst of frames
    }
    for (;;)
    {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now()).count();
      if (left <= 0 || live.Session->QuitRequested())
      {
        break;
      }
      live.Session->Receive(live.Now(), static_cast<int>(left));
    }
  }
  live.Session->Shutdown(live.Now());
  return 0;
}
} // namespace

bool IsLive(const Options& o)
{
  return !o.Listen.empty() || o.CommandsStdin;
}

int RunLive(Avatar& a)
{
  std::signal(SIGPIPE, SIG_IGN); // a client gone: write() fails instead of killing us
  dialog::DialogServer::Settings settings;
  settings.AllowRemote = a.Opt.ListenRemote;
  Live live(a, settings);
  try
  {
    for (const std::string& address : a.Opt.Listen)
    {
      std::cerr << "MorphAvatar: listening on " << live.Server.Listen(address) << std::endl;
    }
  }
  catch (const morphnode::InputError& e)
  {
    std::cerr << "MorphAvatar: " << e.what() << "\n";
    return 1;
  }
  if (a.Opt.CommandsStdin)
  {
    live.Server.AddStream(0, 1);
    live.Stdin = true;
  }
  live.Sink = std::make_unique<BehaviorSink>(a, [&live]() { return live.Now(); });
  live.Session = std::make_unique<dialog::DialogSession>(live.Server, *live.Sink);
  a.Start = a.MeasureStart = a.Launched = Clock::now();
  a.StartTime = 0.0;
  live.Sink->KeepAhead(0.0);
  if (a.Opt.Offscreen)
  {
    return RunHeadless(live);
  }
  // The window's loop (AvatarInteractive.cxx) calls LiveFrame around every frame.
  a.LiveFrame = [&live](double t, bool rendered) {
    if (rendered)
    {
      live.After(t);
      return true;
    }
    return live.Before(t);
  };
  const int code = RunInteractive(a);
  live.Session->Shutdown(live.Now());
  a.LiveFrame = nullptr;
  return code;
}
} // namespace morphavatar
