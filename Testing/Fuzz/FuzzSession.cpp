// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: command sequences run through the whole live path, not only the parser.
// Each input line is one dialog command line (docs/dialog.md); the line's first byte, when
// it is a digit, sets how far the clock moves before it (0..9 tenths of a second, '9' also
// samples at the exact start of what was scheduled). Every accepted command reaches a
// DialogSession whose sink is a LiveBehavior (behavior/LiveBehavior.h, with a stand-in
// synthesizer), the behaviour is sampled as the render loop would, and the head pose is
// built from its angles. Checked: every channel finite at every sample, the head angles
// finite and HeadPoseMatrix succeeding on them, the schedules finite. An InputError from
// the sink is the expected answer to a command it refuses (the session turns it into an
// error event); anything else escaping is a finding.
#include "base/Error.h"
#include "behavior/BehaviorTypes.h"
#include "behavior/HeadPose.h"
#include "behavior/LiveBehavior.h"
#include "dialog/DialogProtocol.h"
#include "dialog/DialogSession.h"
#include "speech/SpeechTypes.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace
{
using namespace morphnode;
using namespace morphnode::dialog;

/// A voice that needs no speech engine: 0.2 s per word, the mouth open in the middle.
Utterance StandIn(const std::string& text)
{
  Utterance u;
  size_t words = 1;
  for (char c : text)
  {
    words += c == ' ' ? 1 : 0;
  }
  const double duration = 0.2 * static_cast<double>(std::min<size_t>(words, 50));
  u.Visemes = WeightTrack({ "sil", "aa" }, 50.0);
  const int frames = static_cast<int>(duration * 50.0) + 1;
  for (int f = 0; f < frames; ++f)
  {
    const double open = (f % 10) / 10.0;
    u.Visemes.AppendFrame(std::vector<double>{ 1.0 - open, open });
  }
  u.Duration = duration;
  return u;
}

void Check(bool ok)
{
  if (!ok)
  {
    std::abort();
  }
}

void CheckSchedule(const Schedule& s)
{
  Check(std::isfinite(s.Start) && std::isfinite(s.End) && s.End >= s.Start);
}

class LiveSink : public CommandSink
{
public:
  explicit LiveSink(LiveBehavior& live)
    : Live(live)
  {
  }
  Schedule Say(const SayCommand& c, double now) override
  {
    const auto t = this->Live.Say(c.Text, now);
    this->Live.TakeAudio();
    return this->Made(t);
  }
  Schedule Gesture(const GestureCommand& c, double now) override
  {
    return this->Made(this->Live.Gesture(c.Name, now, c.Intensity, c.Duration));
  }
  Schedule Mood(const MoodCommand& c, double now) override
  {
    return this->Made(this->Live.SetMood(c.Name, c.Intensity, now));
  }
  Schedule LookAt(const LookAtCommand& c, double now) override
  {
    return this->Made(this->Live.LookAt(c.Yaw, c.Pitch, now, c.Duration));
  }
  void StopSpeaking(double now) override { this->Live.StopSpeaking(now); }

  double LastStart = 0.0;

private:
  Schedule Made(const LiveBehavior::Timing& t)
  {
    Schedule s(t.Start, t.End);
    CheckSchedule(s);
    this->LastStart = t.Start;
    return s;
  }
  LiveBehavior& Live;
};

void Sample(LiveBehavior& live, double t, std::vector<double>& w)
{
  live.Sample(t, w);
  for (double v : w)
  {
    Check(std::isfinite(v));
  }
  HeadAngles a;
  a.Yaw = w[BehaviorChannel::HeadYaw];
  a.Pitch = w[BehaviorChannel::HeadPitch];
  a.Roll = w[BehaviorChannel::HeadRoll];
  const auto m = HeadPoseMatrix(a, { 0.0, 1.6, 0.0 }); // throws on a non-finite angle
  for (double v : m)
  {
    Check(std::isfinite(v));
  }
  Check(live.GetNumberOfNonFiniteValues() == 0);
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size > 8192)
  {
    return 0; // a few dozen commands are enough; longer inputs only cost time
  }
  LiveBehavior live({ "sil", "aa" });
  live.SetSynthesizer(StandIn);
  LiveSink sink(live);
  DialogServer server; // no clients: the session's events go nowhere
  DialogSession session(server, sink);
  std::vector<double> w;
  double now = 0.0;
  Sample(live, now, w);
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  size_t pos = 0;
  int commands = 0;
  while (pos < text.size() && commands < 64)
  {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos)
    {
      end = text.size();
    }
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    bool atStart = false;
    if (!line.empty() && line[0] >= '0' && line[0] <= '9')
    {
      now += 0.1 * (line[0] - '0');
      atStart = line[0] == '9';
      line.remove_prefix(1);
    }
    ++commands;
    ParsedLine parsed = ParseCommand(line);
    if (!parsed.Ok())
    {
      continue;
    }
    session.Execute(DialogServer::StreamClient, parsed.Cmd, now, DialogServer::TimePoint());
    // The frame at the command's own start, then a few after it, as the render loop does.
    if (atStart && sink.LastStart >= now)
    {
      Sample(live, sink.LastStart, w);
      now = sink.LastStart;
    }
    for (int i = 0; i < 4; ++i)
    {
      now += 1.0 / 60.0;
      Sample(live, now, w);
      session.Advance(now);
    }
  }
  session.Shutdown(now, 0);
  return 0;
}
