// SPDX-License-Identifier: BSD-3-Clause
// The dialog protocol: every command with its fields, every kind of bad line (each with its
// reason, the id echoed when it could be read), events as one JSON line, line framing.
#include "dialog/DialogProtocol.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

using namespace morphnode::dialog;
using json = nlohmann::json;

namespace
{
ParsedLine Ok(const std::string& line)
{
  ParsedLine p = ParseCommand(line);
  EXPECT_TRUE(p.Ok()) << line << " -> " << p.Error.Reason << ": " << p.Error.Message;
  return p;
}

/// The error's reason (and a message for people).
std::string ReasonOf(const std::string& line)
{
  ParsedLine p = ParseCommand(line);
  EXPECT_FALSE(p.Ok()) << line;
  EXPECT_FALSE(p.Error.Message.empty()) << line;
  EXPECT_EQ(p.Error.Kind, EventKind::Error);
  return p.Error.Reason;
}

json EventJson(const Event& e)
{
  const std::string line = FormatEvent(e);
  EXPECT_FALSE(line.empty());
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1) << "one line: " << line;
  return json::parse(line);
}
} // namespace

TEST(DialogProtocol, Say)
{
  ParsedLine p = Ok(R"({"cmd":"say","text":"Hello there."})");
  ASSERT_TRUE(std::holds_alternative<SayCommand>(p.Cmd.Body));
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).Text, "Hello there.");
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).Voice, "");
  EXPECT_EQ(p.Cmd.Id, "");
  EXPECT_STREQ(CommandName(p.Cmd.Body), "say");
  p = Ok(R"(  {"voice":"de","text":"Hallo","cmd":"say","id":"u1"}  )");
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).Voice, "de");
  EXPECT_EQ(p.Cmd.Id, "\"u1\"");
  // Unicode text passes unchanged.
  p = Ok(R"({"cmd":"say","text":"Grüß dich \u00e9"})");
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).Text, "Grüß dich \xc3\xa9");
}

TEST(DialogProtocol, Gesture)
{
  ParsedLine p = Ok(R"({"cmd":"gesture","name":"nod"})");
  auto g = std::get<GestureCommand>(p.Cmd.Body);
  EXPECT_EQ(g.Name, "nod");
  EXPECT_EQ(g.Duration, 0.0);
  EXPECT_EQ(g.Intensity, 1.0);
  p = Ok(R"({"cmd":"gesture","name":"smile","duration":1.5,"intensity":0.25})");
  g = std::get<GestureCommand>(p.Cmd.Body);
  EXPECT_EQ(g.Duration, 1.5);
  EXPECT_EQ(g.Intensity, 0.25);
  EXPECT_STREQ(CommandName(p.Cmd.Body), "gesture");
}

TEST(DialogProtocol, Mood)
{
  ParsedLine p = Ok(R"({"cmd":"mood","name":"happy","intensity":0.6})");
  auto m = std::get<MoodCommand>(p.Cmd.Body);
  EXPECT_EQ(m.Name, "happy");
  EXPECT_EQ(m.Intensity, 0.6);
  EXPECT_EQ(std::get<MoodCommand>(Ok(R"({"cmd":"mood","name":"sad"})").Cmd.Body).Intensity, 1.0);
  EXPECT_STREQ(CommandName(p.Cmd.Body), "mood");
}

TEST(DialogProtocol, LookAt)
{
  ParsedLine p = Ok(R"({"cmd":"look_at","yaw":-20,"pitch":5.5,"duration":2})");
  auto l = std::get<LookAtCommand>(p.Cmd.Body);
  EXPECT_EQ(l.Yaw, -20.0);
  EXPECT_EQ(l.Pitch, 5.5);
  EXPECT_EQ(l.Duration, 2.0);
  l = std::get<LookAtCommand>(Ok(R"({"cmd":"look_at","yaw":0,"pitch":0})").Cmd.Body);
  EXPECT_EQ(l.Duration, 0.0);
  EXPECT_STREQ(CommandName(p.Cmd.Body), "look_at");
}

TEST(DialogProtocol, StopAndQuit)
{
  EXPECT_TRUE(std::holds_alternative<StopCommand>(Ok(R"({"cmd":"stop"})").Cmd.Body));
  EXPECT_TRUE(std::holds_alternative<QuitCommand>(Ok(R"({"cmd":"quit","id":7})").Cmd.Body));
  EXPECT_EQ(Ok(R"({"cmd":"quit","id":7})").Cmd.Id, "7");
  // A CRLF line (telnet, Windows clients) is the same line.
  EXPECT_TRUE(std::holds_alternative<StopCommand>(Ok("{\"cmd\":\"stop\"}\r").Cmd.Body));
}

TEST(DialogProtocol, MalformedLines)
{
  EXPECT_EQ(ReasonOf("{"), reason::Malformed);
  EXPECT_EQ(ReasonOf("say hello"), reason::Malformed);
  EXPECT_EQ(ReasonOf(R"({"cmd":"say","text":"hi"} {"cmd":"stop"})"), reason::Malformed);
  EXPECT_EQ(ReasonOf(R"({"cmd":"say","text":"hi",})"), reason::Malformed);
  // NUL bytes: inside a string and between values.
  static const char inString[] = "{\"cmd\":\"say\",\"text\":\"a\0b\"}";
  static const char after[] = "{\"cmd\":\"stop\"}\0";
  EXPECT_EQ(ReasonOf(std::string(inString, sizeof(inString) - 1)), reason::Malformed);
  EXPECT_EQ(ReasonOf(std::string(after, sizeof(after) - 1)), reason::Malformed);
  // A number beyond double's range.
  EXPECT_EQ(ReasonOf(R"({"cmd":"gesture","name":"nod","duration":1e400})"), reason::Malformed);
  // Invalid UTF-8 in a string.
  EXPECT_EQ(ReasonOf("{\"cmd\":\"say\",\"text\":\"\xff\xfe\"}"), reason::Malformed);
}

TEST(DialogProtocol, NotAnObject)
{
  EXPECT_EQ(ReasonOf("[1, 2]"), reason::NotObject);
  EXPECT_EQ(ReasonOf("42"), reason::NotObject);
  EXPECT_EQ(ReasonOf(R"("say")"), reason::NotObject);
  EXPECT_EQ(ReasonOf("null"), reason::NotObject);
}

TEST(DialogProtocol, MissingOrUnknownCommand)
{
  EXPECT_EQ(ReasonOf(R"({"text":"hello"})"), reason::MissingCmd);
  EXPECT_EQ(ReasonOf("{}"), reason::MissingCmd);
  EXPECT_EQ(ReasonOf(R"({"cmd":"dance"})"), reason::UnknownCmd);
  EXPECT_EQ(ReasonOf(R"({"cmd":"SAY","text":"hi"})"), reason::UnknownCmd);
  EXPECT_EQ(ReasonOf(R"({"cmd":""})"), reason::UnknownCmd);
  EXPECT_EQ(ReasonOf(R"({"cmd":5})"), reason::BadField);
  EXPECT_EQ(ReasonOf(R"({"cmd":["say"]})"), reason::BadField);
  EXPECT_EQ(ReasonOf(R"({"cmd":null})"), reason::BadField);
}

TEST(DialogProtocol, WrongFieldTypesAndRanges)
{
  const char* bad[] = {
    R"({"cmd":"say"})",                        // text missing
    R"({"cmd":"say","text":5})",               // not a string
    R"({"cmd":"say","text":""})",              // empty
    R"({"cmd":"say","text":"   "})",           // blank
    R"({"cmd":"say","text":"hi","voice":3})",  // voice not a string
    R"({"cmd":"say","text":"hi","voice":""})", // voice empty
    R"({"cmd":"gesture"})",                    // name missing
    R"({"cmd":"gesture","name":["nod"]})",     // name not a string
    R"({"cmd":"gesture","name":"nod","intensity":"high"})",
    R"({"cmd":"gesture","name":"nod","intensity":1.5})", // out of [0, 1]
    R"({"cmd":"gesture","name":"nod","intensity":-0.1})",
    R"({"cmd":"gesture","name":"nod","duration":-1})",
    R"({"cmd":"gesture","name":"nod","duration":true})", // a bool is not a number
    R"({"cmd":"mood","name":"happy","intensity":2})",
    R"({"cmd":"mood","name":"happy","intensity":null})",
    R"({"cmd":"mood","intensity":0.5})",
    R"({"cmd":"look_at","yaw":10})",   // pitch missing
    R"({"cmd":"look_at","pitch":10})", // yaw missing
    R"({"cmd":"look_at","yaw":"left","pitch":0})",
    R"({"cmd":"look_at","yaw":120,"pitch":0})", // beyond 90 degrees
    R"({"cmd":"look_at","yaw":0,"pitch":-91})",
    R"({"cmd":"look_at","yaw":0,"pitch":0,"duration":-2})",
    // Durations have a floor (issue 29: 1e-320 made the head pose NaN and ended the avatar).
    R"({"cmd":"gesture","name":"nod","duration":1e-320})",
    R"({"cmd":"gesture","name":"shake","duration":1e-20})",
    R"({"cmd":"gesture","name":"nod","duration":0.0099})",
    R"({"cmd":"gesture","name":"nod","duration":600.001})",
    R"({"cmd":"look_at","yaw":0,"pitch":0,"duration":5e-324})",
    R"({"cmd":"say","text":"hi","id":1.5})", // id: string or integer only
    R"({"cmd":"say","text":"hi","id":{"a":1}})",
    R"({"cmd":"say","text":"hi","id":[1]})",
    R"({"cmd":"say","text":"hi","id":true})",
    R"({"cmd":"say","text":"hi","id":null})",
  };
  for (const char* line : bad)
  {
    EXPECT_EQ(ReasonOf(line), reason::BadField) << line;
  }
  for (const char* line : { R"({"cmd":"gesture","name":"nod","duration":0.01})",
         R"({"cmd":"gesture","name":"nod","duration":0})",
         R"({"cmd":"gesture","name":"nod","duration":600})",
         R"({"cmd":"look_at","yaw":0,"pitch":0,"duration":0.01})" })
  {
    EXPECT_TRUE(ParseCommand(line).Ok()) << line;
  }
  const std::string longId = R"({"cmd":"stop","id":")" + std::string(MaxIdBytes + 1, 'x') + "\"}";
  EXPECT_EQ(ReasonOf(longId), reason::BadField);
  const std::string maxId = R"({"cmd":"stop","id":")" + std::string(MaxIdBytes, 'x') + "\"}";
  EXPECT_TRUE(ParseCommand(maxId).Ok());
}

TEST(DialogProtocol, UnknownFields)
{
  // A misspelt field is named (rather than "text missing").
  EXPECT_EQ(ReasonOf(R"({"cmd":"say","txt":"hi"})"), reason::UnknownField);
  EXPECT_EQ(ReasonOf(R"({"cmd":"say","text":"hi","speed":2})"), reason::UnknownField);
  EXPECT_EQ(ReasonOf(R"({"cmd":"stop","now":true})"), reason::UnknownField);
  EXPECT_EQ(ReasonOf(R"({"cmd":"quit","force":1})"), reason::UnknownField);
  EXPECT_EQ(ReasonOf(R"({"cmd":"mood","name":"happy","fade":1})"), reason::UnknownField);
  EXPECT_EQ(ReasonOf(R"({"cmd":"look_at","yaw":0,"pitch":0,"roll":0})"), reason::UnknownField);
  EXPECT_EQ(ReasonOf(R"({"cmd":"gesture","name":"nod","Name":"x"})"), reason::UnknownField);
}

TEST(DialogProtocol, ErrorsEchoIdAndCommand)
{
  ParsedLine p = ParseCommand(R"({"cmd":"gesture","id":"g-7","name":"nod","intensity":3})");
  ASSERT_FALSE(p.Ok());
  json e = EventJson(p.Error);
  EXPECT_EQ(e["event"], "error");
  EXPECT_EQ(e["id"], "g-7");
  EXPECT_EQ(e["cmd"], "gesture");
  EXPECT_EQ(e["reason"], reason::BadField);
  EXPECT_NE(e["message"].get<std::string>().find("intensity"), std::string::npos);

  p = ParseCommand(R"({"cmd":"fly","id":12})");
  e = EventJson(p.Error);
  EXPECT_EQ(e["id"], 12);
  EXPECT_FALSE(e.contains("cmd")); // not a command
  EXPECT_EQ(e["reason"], reason::UnknownCmd);

  p = ParseCommand(R"({"id":"x"})");
  e = EventJson(p.Error);
  EXPECT_EQ(e["id"], "x");
  EXPECT_EQ(e["reason"], reason::MissingCmd);

  // A bad id is not echoed.
  e = EventJson(ParseCommand(R"({"cmd":"stop","id":[1]})").Error);
  EXPECT_FALSE(e.contains("id"));
}

TEST(DialogProtocol, OversizedLine)
{
  const std::string text(200, 'a');
  const std::string line = R"({"cmd":"say","text":")" + text + "\"}";
  EXPECT_TRUE(ParseCommand(line, line.size()).Ok());
  ParsedLine p = ParseCommand(line, line.size() - 1);
  EXPECT_EQ(p.Error.Reason, reason::TooLong);
  EXPECT_NE(p.Error.Message.find(std::to_string(line.size() - 1)), std::string::npos);
}

TEST(DialogProtocol, Blank)
{
  EXPECT_TRUE(IsBlankLine(""));
  EXPECT_TRUE(IsBlankLine(" \t\r"));
  EXPECT_FALSE(IsBlankLine(" x"));
}

TEST(DialogProtocol, EventsAreOneJsonLine)
{
  Event e;
  e.Kind = EventKind::Accepted;
  e.Id = "\"a\\nb\""; // an id holding a newline (escaped in JSON)
  e.Cmd = "say";
  e.Time = 1.25;
  e.Start = 1.5;
  e.End = 3.0;
  e.Sound = 1.6;
  json j = EventJson(e);
  EXPECT_EQ(j["event"], "accepted");
  EXPECT_EQ(j["id"], "a\nb");
  EXPECT_EQ(j["cmd"], "say");
  EXPECT_DOUBLE_EQ(j["time"].get<double>(), 1.25);
  EXPECT_DOUBLE_EQ(j["start"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(j["end"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["sound"].get<double>(), 1.6);
  EXPECT_FALSE(j.contains("reason"));
  EXPECT_FALSE(j.contains("latency_ms"));
  EXPECT_FALSE(j.contains("interrupted")); // only on ended

  Event ended;
  ended.Kind = EventKind::Ended;
  ended.Interrupted = true;
  j = EventJson(ended);
  EXPECT_EQ(j["event"], "ended");
  EXPECT_EQ(j["interrupted"], true);
  EXPECT_FALSE(j.contains("time")); // NaN times are left out

  // A message quoting bad bytes still gives valid JSON.
  j = EventJson(MakeError(reason::Rejected, "unknown gesture '\xff\n'"));
  EXPECT_EQ(j["reason"], "rejected");
  EXPECT_EQ(std::string(EventName(EventKind::Started)), "started");
}

TEST(LineFramer, SplitsAndJoins)
{
  LineFramer f(100);
  auto items = f.Feed("{\"a\":1}\n{\"b\"", 12);
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].Line, "{\"a\":1}");
  EXPECT_TRUE(f.HasPartialLine());
  EXPECT_EQ(f.GetPartialLength(), 4u);
  items = f.Feed(":2}\n\n", 5);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].Line, "{\"b\":2}");
  EXPECT_EQ(items[1].Line, "");
  EXPECT_FALSE(f.HasPartialLine());
}

TEST(LineFramer, OversizedLinesAreDroppedWithBoundedMemory)
{
  LineFramer f(10);
  // Exactly the limit passes; a trailing '\r' does not count.
  auto items = f.Feed("0123456789\n0123456789\r\n", 23);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_FALSE(items[0].TooLong);
  EXPECT_FALSE(items[1].TooLong);
  items = f.Feed("01234567890\n", 12);
  ASSERT_EQ(items.size(), 1u);
  EXPECT_TRUE(items[0].TooLong);
  EXPECT_EQ(items[0].Length, 11u);
  EXPECT_TRUE(items[0].Line.empty());
  // A megabyte in pieces without a newline: one too-long item when the newline comes, and
  // the next line is read normally.
  const std::string piece(4096, 'x');
  for (int i = 0; i < 256; ++i)
  {
    EXPECT_TRUE(f.Feed(piece.data(), piece.size()).empty());
  }
  EXPECT_EQ(f.GetPartialLength(), 256u * 4096u);
  items = f.Feed("x\nok\n", 5);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_TRUE(items[0].TooLong);
  EXPECT_EQ(items[0].Length, 256u * 4096u + 1u);
  EXPECT_FALSE(items[1].TooLong);
  EXPECT_EQ(items[1].Line, "ok");
}

TEST(LineFramer, Reset)
{
  LineFramer f(10);
  f.Feed("abc", 3);
  f.Reset();
  EXPECT_FALSE(f.HasPartialLine());
  auto items = f.Feed("d\n", 2);
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].Line, "d");
}

// Issue 29: a duplicate key took the last value; a command means one thing to every reader.
TEST(DialogProtocol, DuplicateKeysAreRefused)
{
  for (const char* line :
    { R"({"cmd":"say","text":"yes","text":"no"})", R"({"cmd":"gesture","name":"nod","cmd":"quit"})",
      R"({"cmd":"look_at","yaw":1,"pitch":2,"yaw":80})" })
  {
    const ParsedLine p = ParseCommand(line);
    ASSERT_FALSE(p.Ok()) << line;
    EXPECT_EQ(p.Error.Reason, reason::Malformed) << line;
    EXPECT_NE(p.Error.Message.find("appears twice"), std::string::npos) << p.Error.Message;
  }
  // The same key in different objects is fine.
  EXPECT_TRUE(ParseCommand(R"({"cmd":"say","text":"a","id":"text"})").Ok());
}
