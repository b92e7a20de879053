// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DialogSession.h
/// @brief Runs dialog commands on something that behaves (a CommandSink: the avatar's
/// behaviour) and tells the clients: accepted when a command is scheduled, started and
/// ended as the avatar's clock passes its times, error when the sink refuses it.
///
/// Driven from the render loop, never blocking longer than the timeout it is given:
///
///   morphnode::dialog::DialogSession session(server, sink);
///   for (;;) {
///     session.Receive(clock());        // poll, run the commands at the clock's time
///     render(clock());
///     session.Advance(clock());        // started / ended events of what was shown
///     if (session.QuitRequested()) break;
///   }
///
/// The session knows nothing of the behaviour itself: the sink schedules and says when.

#include "dialog/DialogProtocol.h"
#include "dialog/DialogServer.h"

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace morphnode
{
namespace dialog
{
/// When a command runs, on the avatar's clock (seconds).
struct Schedule
{
  double Start = 0.0;
  double End = 0.0;
  /// Say: when its sound starts (NaN: no sound). Start is its first mouth motion.
  double Sound;
  /// The sink's own handle of the command (e.g. an utterance's id), non-zero when its
  /// times may still change (CommandSink::Refresh).
  unsigned long long Handle = 0;
  Schedule();
  Schedule(double start, double end);
};

/// What a dialog session commands. Each call schedules at or after `now` and returns when
/// the command will run; throw morphnode::InputError for what cannot be done (e.g. an
/// unknown gesture): the client gets an error event (rejected) and nothing changes.
class CommandSink
{
public:
  virtual ~CommandSink() = default;
  virtual Schedule Say(const SayCommand& command, double now) = 0;
  virtual Schedule Gesture(const GestureCommand& command, double now) = 0;
  virtual Schedule Mood(const MoodCommand& command, double now) = 0;
  virtual Schedule LookAt(const LookAtCommand& command, double now) = 0;
  /// Ends speech at `now` (what was said so far stays said; later utterances are dropped).
  virtual void StopSpeaking(double now) = 0;
  /// The current times of a command scheduled with a Handle (e.g. a long text whose end
  /// was an estimate until all of it was synthesized). False: unchanged (the default).
  virtual bool Refresh(unsigned long long handle, Schedule& when)
  {
    (void)handle;
    (void)when;
    return false;
  }
};

class DialogSession
{
public:
  using ClientId = DialogServer::ClientId;
  using TimePoint = DialogServer::TimePoint;

  /// Where events go when there is no DialogServer (e.g. a WebSocket session of
  /// stream/StreamServer.h): called for every event, in order.
  using EventOutput = std::function<void(ClientId client, const Event& event)>;

  DialogSession(DialogServer& server, CommandSink& sink);
  /// A session whose commands come from elsewhere (Execute) and whose events go to
  /// `output`; Receive() then returns 0 and Shutdown() flushes nothing.
  DialogSession(EventOutput output, CommandSink& sink);

  /// Polls the server (waiting at most timeoutMs) and runs every command that arrived at
  /// the clock time `now`. Returns the number of commands run (accepted).
  size_t Receive(double now, int timeoutMs = 0);
  /// Runs one command from `client` at `now` (Receive() calls it; also for commands from
  /// elsewhere, e.g. tests). `arrived`: when it arrived (for latency_ms).
  bool Execute(ClientId client, const Command& command, double now, TimePoint arrived);
  /// Sends started and ended events of the commands whose start or end `now` reached.
  /// Call it after rendering the frame at `now`.
  void Advance(double now);
  /// An accepted command with this Schedule::Handle failed after all (e.g. its speech
  /// could not be synthesized): its client gets an error event (reasonCode, message, the
  /// command's id) and the command ends now, interrupted, without having started. False
  /// when no running command has the handle.
  bool Fail(unsigned long long handle, const std::string& reasonCode, const std::string& message,
    double now);
  /// Every command still running ends, interrupted (e.g. before quitting); sends the events
  /// and flushes them (at most timeoutMs).
  void Shutdown(double now, int timeoutMs = 200);

  /// A quit command was accepted.
  bool QuitRequested() const { return this->Quit; }
  /// Commands accepted and not yet ended.
  size_t GetNumberOfRunning() const { return this->Running.size(); }
  size_t GetNumberOfAccepted() const { return this->Accepted; }
  size_t GetNumberOfRejected() const { return this->Rejected; }

private:
  struct Tracked
  {
    ClientId Client;
    std::string Id;
    std::string Cmd;
    bool IsSay = false;
    Schedule When;
    TimePoint Arrived;
    bool Started = false;
    bool Stopped = false; ///< cut short (stop, shutdown)
    bool Done = false;
  };
  Event MakeEvent(EventKind kind, const Tracked& t, double now) const;
  void Send(ClientId client, const Event& event);
  /// Half-closed clients with nothing running are closed (DialogServer::ReleaseEnded).
  void ReleaseEnded();

  DialogServer* Server = nullptr;
  EventOutput Output;
  CommandSink& Sink;
  std::vector<Tracked> Running;
  bool Quit = false;
  size_t Accepted = 0;
  size_t Rejected = 0;
};
} // namespace dialog
} // namespace morphnode
