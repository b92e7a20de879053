// SPDX-License-Identifier: BSD-3-Clause
// The dialog session on a recording sink: each command reaches the sink once with the
// clock's time, accepted / started / ended events follow the sink's schedule with the id,
// a refused command gets a rejected error and changes nothing, stop cuts speech short
// (interrupted), quit is reported, a later schedule (Refresh) moves the ended event.
#include "DialogTestUtilities.h"

#include "base/Error.h"
#include "dialog/DialogSession.h"

#include <gtest/gtest.h>

#include <string>

using namespace morphnode::dialog;
using namespace dialogtest;

namespace
{
/// Records the calls; says last 2 s with their sound 0.1 s after the mouth starts.
class RecordingSink : public CommandSink
{
public:
  std::vector<std::string> Calls;
  double SpeechEnd = 0.0;
  double RefreshedEnd = -1.0;

  Schedule Say(const SayCommand& c, double now) override
  {
    this->Calls.push_back("say " + c.Text + "@" + std::to_string(now));
    Schedule s(std::max(now, this->SpeechEnd), std::max(now, this->SpeechEnd) + 2.0);
    s.Sound = s.Start + 0.1;
    s.Handle = 1;
    this->SpeechEnd = s.End;
    return s;
  }
  Schedule Gesture(const GestureCommand& c, double now) override
  {
    if (c.Name != "nod")
    {
      throw morphnode::InputError("unknown gesture '" + c.Name + "'");
    }
    this->Calls.push_back("gesture " + c.Name);
    return Schedule(now, now + c.Duration);
  }
  Schedule Mood(const MoodCommand& c, double now) override
  {
    this->Calls.push_back("mood " + c.Name);
    return Schedule(now, now + 0.5);
  }
  Schedule LookAt(const LookAtCommand& c, double now) override
  {
    this->Calls.push_back("look " + std::to_string(static_cast<int>(c.Yaw)));
    return Schedule(now, now + 0.3);
  }
  void StopSpeaking(double now) override
  {
    this->Calls.push_back("stop@" + std::to_string(now));
    this->SpeechEnd = now;
  }
  bool Refresh(unsigned long long handle, Schedule& when) override
  {
    if (handle != 1 || this->RefreshedEnd < 0.0)
    {
      return false;
    }
    when.End = this->RefreshedEnd;
    return true;
  }
};

/// A session reading commands from a pipe (the stream client) and writing events to one.
struct Fixture
{
  int In[2];
  int Out[2];
  DialogServer Server;
  RecordingSink Sink;
  DialogSession Session{ Server, Sink };
  std::string Pending;

  Fixture()
  {
    EXPECT_EQ(pipe(this->In), 0);
    EXPECT_EQ(pipe(this->Out), 0);
    this->Server.AddStream(this->In[0], this->Out[1]);
  }
  ~Fixture()
  {
    for (int fd : { this->In[0], this->In[1], this->Out[0], this->Out[1] })
    {
      close(fd);
    }
  }
  void Command(const std::string& line, double now)
  {
    const std::string bytes = line + "\n";
    EXPECT_EQ(write(this->In[1], bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    this->Session.Receive(now, 200);
  }
  std::vector<json> Events(size_t count, int timeoutMs = 500)
  {
    return ReadEvents(this->Out[0], count, nullptr, this->Pending, timeoutMs);
  }
};
} // namespace

TEST(DialogSession, SayAcceptedStartedEnded)
{
  Fixture f;
  f.Command(R"({"cmd":"say","text":"Hello","id":"s1"})", 10.0);
  ASSERT_EQ(f.Sink.Calls.size(), 1u);
  EXPECT_EQ(f.Sink.Calls[0], "say Hello@" + std::to_string(10.0));
  auto e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "accepted");
  EXPECT_EQ(e[0]["id"], "s1");
  EXPECT_EQ(e[0]["cmd"], "say");
  EXPECT_DOUBLE_EQ(e[0]["time"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(e[0]["start"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(e[0]["end"].get<double>(), 12.0);
  EXPECT_DOUBLE_EQ(e[0]["sound"].get<double>(), 10.1);
  EXPECT_EQ(f.Session.GetNumberOfRunning(), 1u);

  f.Session.Advance(10.0);
  e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "started");
  EXPECT_EQ(e[0]["id"], "s1");
  EXPECT_GE(e[0]["latency_ms"].get<double>(), 0.0);
  EXPECT_LT(e[0]["latency_ms"].get<double>(), 60000.0);
  f.Session.Advance(11.0); // nothing new
  EXPECT_TRUE(f.Events(1, 50).empty());
  f.Session.Advance(12.0);
  e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "ended");
  EXPECT_EQ(e[0]["interrupted"], false);
  EXPECT_DOUBLE_EQ(e[0]["time"].get<double>(), 12.0);
  EXPECT_EQ(f.Session.GetNumberOfRunning(), 0u);
  f.Session.Advance(20.0);
  EXPECT_TRUE(f.Events(1, 50).empty()); // once only
}

TEST(DialogSession, EveryCommandReachesTheSink)
{
  Fixture f;
  f.Command(R"({"cmd":"gesture","name":"nod","duration":1,"id":1})", 1.0);
  f.Command(R"({"cmd":"mood","name":"happy","intensity":0.4,"id":2})", 1.0);
  f.Command(R"({"cmd":"look_at","yaw":15,"pitch":0,"id":3})", 1.0);
  EXPECT_EQ(f.Sink.Calls, (std::vector<std::string>{ "gesture nod", "mood happy", "look 15" }));
  auto e = f.Events(3);
  ASSERT_EQ(e.size(), 3u);
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_EQ(e[i]["event"], "accepted");
    EXPECT_EQ(e[i]["id"], i + 1);
  }
  EXPECT_EQ(e[1]["cmd"], "mood");
  EXPECT_EQ(e[2]["cmd"], "look_at");
  EXPECT_EQ(f.Session.GetNumberOfAccepted(), 3u);
  f.Session.Advance(5.0); // all started and ended
  e = f.Events(6);
  ASSERT_EQ(e.size(), 6u);
  EXPECT_EQ(f.Session.GetNumberOfRunning(), 0u);
}

TEST(DialogSession, RejectedCommandChangesNothing)
{
  Fixture f;
  f.Command(R"({"cmd":"gesture","name":"cartwheel","id":"g"})", 2.0);
  EXPECT_TRUE(f.Sink.Calls.empty());
  auto e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "error");
  EXPECT_EQ(e[0]["reason"], reason::Rejected);
  EXPECT_EQ(e[0]["id"], "g");
  EXPECT_EQ(e[0]["cmd"], "gesture");
  EXPECT_NE(e[0]["message"].get<std::string>().find("cartwheel"), std::string::npos);
  EXPECT_EQ(f.Session.GetNumberOfRunning(), 0u);
  EXPECT_EQ(f.Session.GetNumberOfRejected(), 1u);
  // A malformed line never reaches the sink either.
  f.Command(R"({"cmd":"say"})", 2.0);
  EXPECT_TRUE(f.Sink.Calls.empty());
  e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["reason"], reason::BadField);
}

TEST(DialogSession, StopInterruptsSpeech)
{
  Fixture f;
  f.Command(R"({"cmd":"say","text":"One","id":"a"})", 0.0); // 0 .. 2
  f.Command(R"({"cmd":"say","text":"Two","id":"b"})", 0.0); // queued: 2 .. 4
  f.Command(R"({"cmd":"gesture","name":"nod","duration":5,"id":"n"})", 0.0);
  f.Session.Advance(1.0); // a and the nod started
  f.Events(5);
  f.Command(R"({"cmd":"stop","id":"x"})", 1.0);
  EXPECT_EQ(f.Sink.Calls.back(), "stop@" + std::to_string(1.0));
  f.Session.Advance(1.0);
  auto e = f.Events(5);
  ASSERT_EQ(e.size(), 5u);
  // accepted stop; ended a (interrupted); ended b without ever starting; started/ended stop.
  EXPECT_EQ(e[0]["event"], "accepted");
  EXPECT_EQ(e[0]["cmd"], "stop");
  int endedSays = 0;
  for (const json& ev : e)
  {
    if (ev["event"] == "ended" && ev["cmd"] == "say")
    {
      ++endedSays;
      EXPECT_EQ(ev["interrupted"], true);
      EXPECT_DOUBLE_EQ(ev["end"].get<double>(), 1.0);
    }
    EXPECT_FALSE(ev["event"] == "started" && ev["id"] == "b") << "b never started";
  }
  EXPECT_EQ(endedSays, 2);
  // The gesture goes on: it is not speech.
  EXPECT_EQ(f.Session.GetNumberOfRunning(), 1u); // the nod
  f.Session.Advance(6.0);
  e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["id"], "n");
  EXPECT_EQ(e[0]["interrupted"], false);
}

TEST(DialogSession, Quit)
{
  Fixture f;
  f.Command(R"({"cmd":"say","text":"Bye","id":1})", 3.0);
  EXPECT_FALSE(f.Session.QuitRequested());
  f.Command(R"({"cmd":"quit","id":2})", 3.5);
  EXPECT_TRUE(f.Session.QuitRequested());
  f.Session.Shutdown(3.5);
  auto e = f.Events(4);
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[1]["event"], "accepted");
  EXPECT_EQ(e[1]["cmd"], "quit");
  EXPECT_EQ(e[3]["event"], "ended"); // the speech, cut by the shutdown
  EXPECT_EQ(e[3]["id"], 1);
  EXPECT_EQ(e[3]["interrupted"], true);
}

TEST(DialogSession, RefreshedScheduleMovesTheEnd)
{
  Fixture f;
  f.Command(R"({"cmd":"say","text":"A long text","id":"l"})", 0.0); // estimated end 2
  f.Sink.RefreshedEnd = 3.5;
  f.Session.Advance(2.5);
  auto e = f.Events(3, 200);
  ASSERT_EQ(e.size(), 2u); // accepted, started; not ended at 2.5
  f.Session.Advance(3.5);
  e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "ended");
  EXPECT_DOUBLE_EQ(e[0]["end"].get<double>(), 3.5);
}

// Issue 29: a client that sends its commands and half-closes (`nc -N`) still gets their
// events; its socket is released when they have ended.
TEST(DialogSession, HalfClosedClientGetsItsEvents)
{
  DialogServer server;
  RecordingSink sink;
  DialogSession session(server, sink);
  const std::string address = server.Listen("127.0.0.1:0");
  const size_t colon = address.rfind(':');
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<uint16_t>(std::stoi(address.substr(colon + 1))));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof(to)), 0);
  const std::string line = R"({"cmd":"gesture","name":"nod","duration":1,"id":"h"})"
                           "\n";
  ASSERT_EQ(write(fd, line.data(), line.size()), static_cast<ssize_t>(line.size()));
  shutdown(fd, SHUT_WR);
  for (int i = 0; i < 20 && sink.Calls.empty(); ++i)
  {
    session.Receive(5.0, 50);
  }
  ASSERT_EQ(sink.Calls.size(), 1u);
  session.Advance(5.0);
  session.Advance(6.0); // ended
  std::string pending;
  const auto events = ReadEvents(fd, 3, &server, pending, 1000);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0]["event"], "accepted");
  EXPECT_EQ(events[1]["event"], "started");
  EXPECT_EQ(events[2]["event"], "ended");
  EXPECT_EQ(events[2]["id"], "h");
  // Released: the server closed its side, the client reads the end.
  char byte;
  EXPECT_EQ(read(fd, &byte, 1), 0);
  close(fd);
}

// An accepted say whose speech cannot be made after all (e.g. the synthesis pool was too
// busy): its client gets an error with the say's id, then ended (interrupted), never
// started.
TEST(DialogSession, FailEndsAnAcceptedSayWithAnError)
{
  Fixture f;
  f.Command(R"({"cmd":"say","text":"Too late","id":"late"})", 5.0); // starts at 5 (sink)
  auto e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "accepted");
  EXPECT_FALSE(f.Session.Fail(2, reason::Overloaded, "not this one", 4.0)); // unknown handle
  EXPECT_TRUE(f.Session.Fail(1, reason::Overloaded, "the server is busy", 4.5));
  e = f.Events(1);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0]["event"], "error");
  EXPECT_EQ(e[0]["reason"], "overloaded");
  EXPECT_EQ(e[0]["id"], "late");
  EXPECT_EQ(e[0]["cmd"], "say");
  f.Session.Advance(5.0);
  e = f.Events(2, 200);
  ASSERT_EQ(e.size(), 1u) << "ended only: it never started";
  EXPECT_EQ(e[0]["event"], "ended");
  EXPECT_EQ(e[0]["interrupted"], true);
  EXPECT_EQ(f.Session.GetNumberOfRunning(), 0u);
  EXPECT_FALSE(f.Session.Fail(1, reason::Overloaded, "once", 6.0));
}
