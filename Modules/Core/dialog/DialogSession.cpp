// SPDX-License-Identifier: BSD-3-Clause
#include "dialog/DialogSession.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <type_traits>
#include <utility>

namespace morphnode
{
namespace dialog
{
Schedule::Schedule()
  : Sound(std::numeric_limits<double>::quiet_NaN())
{
}

Schedule::Schedule(double start, double end)
  : Start(start)
  , End(end)
  , Sound(std::numeric_limits<double>::quiet_NaN())
{
}

DialogSession::DialogSession(DialogServer& server, CommandSink& sink)
  : Server(&server)
  , Sink(sink)
{
  server.HoldEndedClients(true); // a half-closed client gets the events of what it sent
}

DialogSession::DialogSession(EventOutput output, CommandSink& sink)
  : Output(std::move(output))
  , Sink(sink)
{
}

void DialogSession::Send(ClientId client, const Event& event)
{
  if (this->Server)
  {
    this->Server->Send(client, event);
  }
  else if (this->Output)
  {
    this->Output(client, event);
  }
}

size_t DialogSession::Receive(double now, int timeoutMs)
{
  size_t accepted = 0;
  if (!this->Server)
  {
    return 0;
  }
  for (const DialogServer::Incoming& in : this->Server->Poll(timeoutMs))
  {
    accepted += this->Execute(in.Client, in.Cmd, now, in.Arrived) ? 1 : 0;
  }
  this->ReleaseEnded();
  return accepted;
}

Event DialogSession::MakeEvent(EventKind kind, const Tracked& t, double now) const
{
  Event e;
  e.Kind = kind;
  e.Id = t.Id;
  e.Cmd = t.Cmd;
  e.Time = now;
  e.Start = t.When.Start;
  e.End = t.When.End;
  e.Sound = t.When.Sound;
  return e;
}

bool DialogSession::Execute(ClientId client, const Command& command, double now, TimePoint arrived)
{
  Tracked t;
  t.Client = client;
  t.Id = command.Id;
  t.Cmd = CommandName(command.Body);
  t.Arrived = arrived;
  t.When = Schedule(now, now);
  bool quit = false;
  try
  {
    std::visit(
      [&](const auto& c)
      {
        using T = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<T, SayCommand>)
        {
          t.When = this->Sink.Say(c, now);
          t.IsSay = true;
        }
        else if constexpr (std::is_same_v<T, GestureCommand>)
        {
          t.When = this->Sink.Gesture(c, now);
        }
        else if constexpr (std::is_same_v<T, MoodCommand>)
        {
          t.When = this->Sink.Mood(c, now);
        }
        else if constexpr (std::is_same_v<T, LookAtCommand>)
        {
          t.When = this->Sink.LookAt(c, now);
        }
        else if constexpr (std::is_same_v<T, StopCommand>)
        {
          this->Sink.StopSpeaking(now);
          // Every speech still running (or waiting) ends now, interrupted.
          for (Tracked& r : this->Running)
          {
            if (r.IsSay && r.When.End > now)
            {
              r.When.End = now;
              r.Stopped = true;
            }
          }
        }
        else
        {
          quit = true;
        }
      },
      command.Body);
  }
  catch (const std::exception& e)
  {
    ++this->Rejected;
    this->Send(client, MakeError(reason::Rejected, e.what(), t.Id, t.Cmd));
    return false;
  }
  if (!(std::isfinite(t.When.Start) && std::isfinite(t.When.End)))
  {
    t.When = Schedule(now, now);
  }
  t.When.End = std::max(t.When.End, t.When.Start);
  ++this->Accepted;
  this->Send(client, this->MakeEvent(EventKind::Accepted, t, now));
  if (quit)
  {
    this->Quit = true;
    return true;
  }
  this->Running.push_back(std::move(t));
  return true;
}

void DialogSession::Advance(double now)
{
  const auto wallNow = std::chrono::steady_clock::now();
  for (Tracked& t : this->Running)
  {
    if (t.When.Handle != 0 && !t.Stopped)
    {
      Schedule updated = t.When;
      if (this->Sink.Refresh(t.When.Handle, updated) && std::isfinite(updated.Start) &&
        std::isfinite(updated.End))
      {
        t.When = updated;
        t.When.End = std::max(t.When.End, t.When.Start);
      }
    }
    if (!t.Started && now >= t.When.Start && !(t.Stopped && t.When.End <= t.When.Start))
    {
      t.Started = true;
      Event e = this->MakeEvent(EventKind::Started, t, now);
      e.LatencyMs = std::chrono::duration<double, std::milli>(wallNow - t.Arrived).count();
      this->Send(t.Client, e);
    }
    if (now >= t.When.End)
    {
      Event e = this->MakeEvent(EventKind::Ended, t, now);
      e.Interrupted = t.Stopped;
      this->Send(t.Client, e);
      t.Done = true;
    }
  }
  this->Running.erase(std::remove_if(this->Running.begin(), this->Running.end(),
                        [](const Tracked& t) { return t.Done; }),
    this->Running.end());
  this->ReleaseEnded();
}

bool DialogSession::Fail(
  unsigned long long handle, const std::string& reasonCode, const std::string& message, double now)
{
  for (Tracked& t : this->Running)
  {
    if (handle != 0 && t.When.Handle == handle && !t.Done && !t.Stopped)
    {
      this->Send(t.Client, MakeError(reasonCode, message, t.Id, t.Cmd));
      t.Stopped = true;
      t.When.End = now;
      if (!t.Started)
      {
        t.When.Start = now; // never started: no started event, ended (interrupted) next
      }
      return true;
    }
  }
  return false;
}

void DialogSession::ReleaseEnded()
{
  if (!this->Server)
  {
    return; // events go to a callback: no connections to close
  }
  this->Server->ReleaseEnded(
    [this](ClientId client)
    {
      return std::any_of(this->Running.begin(), this->Running.end(),
        [client](const Tracked& t) { return t.Client == client; });
    });
}

void DialogSession::Shutdown(double now, int timeoutMs)
{
  for (Tracked& t : this->Running)
  {
    if (t.When.End > now)
    {
      t.When.End = now;
      t.Stopped = true;
    }
  }
  this->Advance(now);
  if (this->Server)
  {
    this->Server->Flush(timeoutMs);
  }
}
} // namespace dialog
} // namespace morphnode
