// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar live (AvatarLive.h): the dialog server and session of Modules/Core/dialog on
// the avatar's behaviour, in the window's loop or a headless real-time loop.
//
// The behaviour is a vtkLiveBehaviorSource over morphnode::LiveBehavior
// (behavior/LiveBehavior.h): endless, never looping, every command merged into what is
// scheduled without rebuilding it, long texts synthesized in chunks. It is the avatar
// pipeline's weights source in live mode (the same pipeline, another source), sampled at
// the clock's time of each frame; the vtkBehaviorTimeSource gives it its settings (seed,
// parameters, voice, viseme set).
#include "AvatarLive.h"

#include "Avatar.h"
#include "FrameRecorder.h"
#include "StopSignal.h"

#include "align/RecordingSpeech.h"
#include "audio/AudioFile.h"
#include "base/Error.h"
#include "behavior/LiveBehavior.h"
#include "dialog/DialogServer.h"
#include "dialog/DialogSession.h"
#include "speech/Speech.h"
#include "speech/TimingFiles.h"

#include "vtkLiveBehaviorSource.h"
#include "vtkNew.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

namespace morphavatar
{
namespace dialog = morphnode::dialog;

namespace
{
/// A sample this loud is heard (1 % of full scale).
constexpr int AudibleSample = 328;

/// Seconds from the first sample to the first audible one; NaN when silent.
double FirstSound(const std::vector<int16_t>& samples, int sampleRate)
{
  for (size_t i = 0; i < samples.size(); ++i)
  {
    if (std::abs(static_cast<int>(samples[i])) >= AudibleSample)
    {
      return static_cast<double>(i) / sampleRate;
    }
  }
  return std::nan("");
}

/// The dialog's commands on the live behaviour (behavior/LiveBehavior.h): merged into what
/// is scheduled, never rebuilding it; long texts synthesized in chunks.
/// `path` when it names a file inside `folder` (--speech-dir), as its canonical path: a
/// client may name files only there. InputError otherwise (and without a folder).
std::string InsideFolder(const std::string& path, const std::string& folder, const char* field)
{
  namespace fs = std::filesystem;
  if (folder.empty())
  {
    throw morphnode::InputError(std::string("'") + field +
      "' names a file: start the avatar with "
      "--speech-dir DIR, the folder clients may name recordings and timings in");
  }
  std::error_code error;
  const fs::path dir = fs::canonical(folder, error);
  const fs::path file = fs::canonical(fs::path(folder) / path, error);
  if (error || dir.empty())
  {
    throw morphnode::InputError(
      std::string("'") + field + "': no file '" + path + "' in the speech folder");
  }
  const std::string d = dir.string() + "/";
  if (file.string().compare(0, d.size(), d) != 0 || !fs::is_regular_file(file))
  {
    throw morphnode::InputError(std::string("'") + field + "': '" + path +
      "' is not a file inside the "
      "speech folder (--speech-dir)");
  }
  return file.string();
}

class LiveSink : public dialog::CommandSink
{
public:
  LiveSink(morphnode::LiveBehavior& live, const morphnode::SpeechOptions& speech)
    : Live(live)
    , Speech(speech)
  {
  }

  dialog::Schedule Say(const dialog::SayCommand& c, double now) override
  {
    morphnode::LiveBehavior::Timing timing;
    if (c.HasRecording())
    {
      // External speech: the dialog system's own voice, a recording on this machine or
      // inline in the command, with its timings (a file or inline) or its transcript; the
      // recording is the sound, the mouth its timing.
      const std::string folder = this->A ? this->A->Opt.SpeechDir : std::string();
      const std::string timings =
        c.Timings.empty() ? "" : InsideFolder(c.Timings, folder, "timings");
      morphnode::SpeechOptions options = this->Speech;
      if (!c.Voice.empty())
      {
        options.Voice = c.Voice;
      }
      morphnode::RecordingOptions recording;
      recording.Transcript = c.Text;
      // (The transcript's acoustic check costs 0.2 s of a core per second of speech: too
      // long for the frame loop; the alignment's score still warns.)
      recording.Align.AcousticCheck = false;
      recording.TimingFile = timings;
      recording.TimingData = c.TimingsData;
      if (!c.TimingsFormat.empty())
      {
        recording.Timing.Format = morphnode::ParseTimingFormat(c.TimingsFormat);
      }
      // The same reader for both: libsndfile from the file, or from memory (virtual I/O).
      const morphnode::AudioBuffer sound = c.AudioData.empty()
        ? morphnode::ReadAudioFile(InsideFolder(c.Audio, folder, "audio"))
        : morphnode::ReadAudioMemory(c.AudioData, "'audio_base64'");
      timing = this->Live.Speak(morphnode::SpeakRecording(sound, options, recording), now);
    }
    else if (c.Voice.empty())
    {
      timing = this->Live.Say(c.Text, now); // the first chunk now, the others later
    }
    else
    {
      // Another voice, for every chunk of this text.
      morphnode::SpeechOptions options = this->Speech;
      options.Voice = c.Voice;
      if (this->Voices.insert(c.Voice).second)
      {
        // A voice's first use: a word at once, so that a voice eSpeak NG does not have is
        // rejected now, not when a queued chunk is synthesized later.
        try
        {
          morphnode::SpeakText("a", options);
        }
        catch (...)
        {
          this->Voices.erase(c.Voice);
          throw;
        }
      }
      timing = this->Live.Say(c.Text, now,
        [options](const std::string& text) { return morphnode::SpeakText(text, options); });
    }
    dialog::Schedule s(timing.Start, timing.End);
    s.Handle = timing.Id;
    for (auto& segment : this->Live.TakeAudio())
    {
      if (segment.Id == timing.Id && std::isnan(s.Sound))
      {
        s.Sound = segment.Start + FirstSound(segment.Samples, segment.SampleRate);
      }
      if (this->A)
      {
        this->A->PlaySound(segment.Samples, segment.SampleRate, segment.Start);
      }
    }
    return s;
  }

  dialog::Schedule Gesture(const dialog::GestureCommand& c, double now) override
  {
    const auto timing = this->Live.Gesture(c.Name, now, c.Intensity, c.Duration);
    return dialog::Schedule(timing.Start, timing.End);
  }

  dialog::Schedule Mood(const dialog::MoodCommand& c, double now) override
  {
    const auto timing = this->Live.SetMood(c.Name, c.Intensity, now);
    return dialog::Schedule(timing.Start, timing.End);
  }

  dialog::Schedule LookAt(const dialog::LookAtCommand& c, double now) override
  {
    const auto timing = this->Live.LookAt(c.Yaw, c.Pitch, now, c.Duration);
    return dialog::Schedule(timing.Start, timing.End);
  }

  void StopSpeaking(double now) override
  {
    this->Live.StopSpeaking(now);
    if (this->A)
    {
      this->A->CutSound(now);
    }
  }

  bool Refresh(unsigned long long handle, dialog::Schedule& when) override
  {
    const auto timing = this->Live.GetSpeechTiming(handle);
    if (timing.Id == 0)
    {
      return false;
    }
    when.End = timing.End; // (the start stays the first chunk's)
    return true;
  }

  /// Where the speech plays (the avatar's player), or null.
  Avatar* A = nullptr;

private:
  morphnode::LiveBehavior& Live;
  morphnode::SpeechOptions Speech;
  std::set<std::string> Voices; ///< voices that synthesized once
};

/// The server, the session, the behaviour and the clock of one live run.
struct Live
{
  Avatar& A;
  dialog::DialogServer Server;
  /// The weights source of the pipeline in live mode; its core behaviour takes the
  /// commands (LiveSink) and gives the sound of later chunks and their errors.
  vtkNew<vtkLiveBehaviorSource> Source;
  std::unique_ptr<LiveSink> Sink;
  std::unique_ptr<dialog::DialogSession> Session;
  bool Stdin = false;

  Live(Avatar& avatar, const dialog::DialogServer::Settings& settings)
    : A(avatar)
    , Server(settings)
  {
  }
  /// The avatar's clock (AvatarClock.cxx): the sound's where it plays, else the window's
  /// (pausable) time or seconds since the start.
  double Now() const { return this->A.ClockNow(); }
  /// Before a frame at t: commands that arrived run now; the frame's update samples the
  /// source at t. False to stop.
  bool Before(double t)
  {
    this->Session->Receive(this->BehaviorTime(t), 0);
    this->Source->Modified(); // commands may have come
    return !this->Session->QuitRequested() &&
      !morphnode::appkit::StopRequested(); // SIGTERM/SIGINT: as quit
  }
  /// After the frame at t is on the screen: the sound of chunks synthesized while sampling
  /// (later chunks of long texts) and their errors, then started / ended events.
  void After(double t)
  {
    for (const auto& segment : this->Source->GetLiveBehavior().TakeAudio())
    {
      this->A.PlaySound(segment.Samples, segment.SampleRate, segment.Start);
    }
    for (const std::string& error : this->Source->GetLiveBehavior().TakeErrors())
    {
      std::cerr << "MorphAvatar: " << error << "\n";
    }
    this->Session->Advance(this->BehaviorTime(t));
  }
  /// The behaviour's time for the clock's t: the same, unless the window's clock went back
  /// ('r' restarts it), where the behaviour goes on from where it was.
  double BehaviorTime(double t) { return this->Source->GetBehaviorTime(t); }
  /// Headless with commands on stdin only: stdin ended and nothing runs any more.
  bool Finished() const
  {
    return this->Stdin && this->Server.GetAddresses().empty() &&
      !this->Server.IsConnected(dialog::DialogServer::StreamClient) &&
      this->Session->GetNumberOfRunning() == 0;
  }
};

/// Unix socket files to remove when the program ends through exit() rather than through
/// the server's destructor: Xlib ends the program with exit(1) when the X display is lost.
std::vector<std::string>& SocketFiles()
{
  static std::vector<std::string> files;
  return files;
}

void RemoveSocketFiles()
{
  for (const std::string& path : SocketFiles())
  {
    ::unlink(path.c_str());
  }
}

void RemoveAtExit(const std::string& address)
{
  if (address.rfind("unix:", 0) != 0)
  {
    return;
  }
  if (SocketFiles().empty())
  {
    std::atexit(RemoveSocketFiles);
  }
  SocketFiles().push_back(address.substr(5));
}

/// Every frame at the frame rate in real time, offscreen; a command arriving between frames
/// runs at once and the next frame is rendered at once.
int RunHeadless(Live& live)
{
  Avatar& a = live.A;
  a.Window->OffScreenRenderingOn();
  const double frame = 1.0 / a.Fps;
  // --frames / --video: the session recorded at the frame rate (the frame shown at each
  // frame's time, repeated when a render comes late) with the sound as it was played.
  std::unique_ptr<morphnode::appkit::FrameRecorder> recorder;
  int recorded = 0;
  if (!a.Opt.FramesDir.empty() || !a.Opt.Video.empty())
  {
    try
    {
      recorder = std::make_unique<morphnode::appkit::FrameRecorder>(a.Window, a.Fps);
      if (a.Opt.CommandsStdin)
      {
        recorder->SetLog(std::cerr); // stdout carries the events
      }
      if (!a.Opt.FramesDir.empty())
      {
        recorder->SetFramesFolder(a.Opt.FramesDir);
      }
      if (!a.Opt.Video.empty())
      {
        recorder->SetVideo(a.Opt.Video);
      }
    }
    catch (const std::exception& e)
    {
      std::cerr << "MorphAvatar: " << e.what() << "\n";
      return 1;
    }
  }
  auto finish = [&]()
  {
    live.Session->Shutdown(live.Now());
    if (!recorder)
    {
      return 0;
    }
    try
    {
      // The last frame shown holds until the session ends (a slow render or a quit that
      // came before the next frame must not shorten the recording against its sound).
      for (const int last = static_cast<int>(std::floor(live.Now() * a.Fps + 1e-9));
           recorded <= last; ++recorded)
      {
        recorder->Capture(recorded);
      }
      recorder->Finish([&a](const std::string& wav) { return a.WriteSessionSound(wav); });
    }
    catch (const std::exception& e)
    {
      std::cerr << "MorphAvatar: " << e.what() << "\n";
      return 1;
    }
    return 0;
  };
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
    try
    {
      // Every frame slot up to now shows this render (none skipped, none twice).
      for (const int last = static_cast<int>(std::floor(t * a.Fps + 1e-9));
           recorder && recorded <= last; ++recorded)
      {
        recorder->Capture(recorded);
      }
    }
    catch (const std::exception& e)
    {
      std::cerr << "MorphAvatar: " << e.what() << "\n";
      live.Session->Shutdown(live.Now());
      return 1;
    }
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
      const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now()).count();
      if (left <= 0 || live.Session->QuitRequested() || morphnode::appkit::StopRequested())
      {
        break;
      }
      if (live.Session->Receive(live.Now(), static_cast<int>(left)) > 0)
      {
        break; // show it now rather than at the next frame's time
      }
    }
  }
  return finish();
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
  // The live behaviour: the behaviour source's settings (seed, parameters, voice, viseme
  // set); the speech, gestures, moods and looks come as commands.
  vtkBehaviorTimeSource* source = a.Behavior;
  if (!live.Source->CopySettings(source))
  {
    return 1; // the error is reported
  }
  const morphnode::SpeechOptions speech = source->GetSpeechOptions();
  try
  {
    // Every address bound before any is announced: a refused one (a remote host without
    // --listen-remote, a port in use) is the only message, and nothing listens.
    std::vector<std::string> bound;
    for (const std::string& address : a.Opt.Listen)
    {
      bound.push_back(live.Server.Listen(address));
      RemoveAtExit(bound.back());
    }
    for (const std::string& address : bound)
    {
      std::cerr << "MorphAvatar: listening on " << address << std::endl;
    }
  }
  catch (const morphnode::InputError& e)
  {
    std::cerr << "MorphAvatar: " << e.what() << "\n";
    return 1;
  }
  if (!a.Opt.Script.empty() || !a.Opt.Audio.empty() || !a.Opt.Timings.empty())
  {
    std::cerr << "MorphAvatar: live, the avatar takes its speech and gestures as commands; "
                 "--script, --audio and --timings are left out\n";
  }
  if (a.Opt.CommandsStdin)
  {
    live.Server.AddStream(0, 1);
    live.Stdin = true;
  }
  // The same pipeline with another weights source in the behaviour's place (the rig, the
  // morph, the eyes, the skin and the head pose read it; a take stays the take).
  if (a.Pipeline->GetWeightsConnection() == source->GetOutputPort(0))
  {
    a.Pipeline->SetWeightsConnection(live.Source->GetOutputPort());
  }
  live.Sink = std::make_unique<LiveSink>(live.Source->GetLiveBehavior(), speech);
  live.Sink->A = &a;
  live.Session = std::make_unique<dialog::DialogSession>(live.Server, *live.Sink);
  a.Duration = std::numeric_limits<double>::infinity(); // no end, no loop
  a.StartClock(false); // the sound device opens; speech is scheduled as it is said
  if (!a.Opt.Say.empty())
  {
    dialog::Command greeting;
    dialog::SayCommand say;
    say.Text = a.Opt.Say;
    greeting.Body = say;
    live.Session->Execute(dialog::DialogServer::StreamClient, greeting, 0.5, Clock::now());
  }
  if (a.Opt.Offscreen)
  {
    a.RecordSound = !a.Opt.Video.empty();
    return RunHeadless(live);
  }
  // The window's loop (AvatarInteractive.cxx) calls LiveFrame around every frame.
  a.LiveFrame = [&live](double t, bool rendered)
  {
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
