// SPDX-License-Identifier: BSD-3-Clause
// Behaviour scripts: both formats, line-numbered errors, the example scripts, robustness.
#include "BehaviorTestUtilities.h"

#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "behavior/BehaviorScript.h"
#include "behavior/Random.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace morphnode;
using behaviortest::MakeUtterance;

namespace
{
const std::string ScriptDir = std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/";

std::string ReadFile(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The error message of parsing `text`, or "" when it parses.
std::string ParseError(const std::string& text)
{
  try
  {
    ParseBehaviorScript(text);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}

bool Contains(const std::string& s, const std::string& part)
{
  return s.find(part) != std::string::npos;
}

BehaviorController WithSynthesizer()
{
  BehaviorController b;
  b.SetSynthesizer([](const std::string& text) { return MakeUtterance(0.5 + 0.05 * text.size()); });
  return b;
}

void ExpectSameCommands(const BehaviorScript& a, const BehaviorScript& b)
{
  ASSERT_EQ(a.Commands.size(), b.Commands.size());
  for (size_t i = 0; i < a.Commands.size(); ++i)
  {
    const BehaviorCommand &x = a.Commands[i], &y = b.Commands[i];
    EXPECT_EQ(x.Type, y.Type) << i;
    EXPECT_EQ(x.Start, y.Start) << i;
    EXPECT_EQ(x.Text, y.Text) << i;
    EXPECT_EQ(x.Duration, y.Duration) << i;
    EXPECT_EQ(x.Intensity, y.Intensity) << i;
    EXPECT_EQ(x.Fade, y.Fade) << i;
    EXPECT_EQ(x.Yaw, y.Yaw) << i;
    EXPECT_EQ(x.Pitch, y.Pitch) << i;
  }
  EXPECT_EQ(a.Seed, b.Seed);
  EXPECT_EQ(a.FrameRate, b.FrameRate);
  EXPECT_EQ(a.Duration, b.Duration);
}
} // namespace

TEST(BehaviorScript, ParsesTheTextFormat)
{
  const BehaviorScript s = ParseBehaviorScript("# a comment\n"
                                               "seed 42\n"
                                               "fps 25\r\n"
                                               "at 0.5 say \"Hello \\\"world\\\"\"  # trailing\n"
                                               "at 1.0 gesture Nod duration 0.8 intensity 0.7\n"
                                               "\n"
                                               "at 0 mood happy 0.6 fade 1.5\n"
                                               "at 2 look 10 -5 duration 1\n"
                                               "at 3 phonemes hello.pho\n"
                                               "AT 4 mood neutral\n");
  EXPECT_EQ(s.Seed, 42u);
  EXPECT_EQ(s.FrameRate, 25.0);
  ASSERT_EQ(s.Commands.size(), 6u);
  EXPECT_EQ(s.Commands[0].Type, BehaviorCommand::Kind::Say);
  EXPECT_EQ(s.Commands[0].Text, "Hello \"world\"");
  EXPECT_EQ(s.Commands[0].Line, 4);
  EXPECT_EQ(s.Commands[1].Text, "nod");
  EXPECT_EQ(s.Commands[1].Duration, 0.8);
  EXPECT_EQ(s.Commands[1].Intensity, 0.7);
  EXPECT_EQ(s.Commands[2].Type, BehaviorCommand::Kind::Mood);
  EXPECT_EQ(s.Commands[2].Fade, 1.5);
  EXPECT_EQ(s.Commands[2].Line, 7);
  EXPECT_EQ(s.Commands[3].Yaw, 10.0);
  EXPECT_EQ(s.Commands[3].Pitch, -5.0);
  EXPECT_EQ(s.Commands[4].Type, BehaviorCommand::Kind::Phonemes);
  EXPECT_EQ(s.Commands[4].Text, "hello.pho");
  EXPECT_EQ(s.Commands[5].Text, "neutral");
}

TEST(BehaviorScript, JsonAndTextExamplesAgree)
{
  const BehaviorScript text = LoadBehaviorScript(ScriptDir + "greeting.txt");
  const BehaviorScript json = LoadBehaviorScript(ScriptDir + "greeting.json");
  ExpectSameCommands(text, json);
  EXPECT_EQ(json.Commands[2].Line, 8); // each JSON command knows its line
  EXPECT_EQ(text.BaseDirectory, ScriptDir);
}

TEST(BehaviorScript, MalformedTextNamesTheLine)
{
  const char* const bad[] = {
    "at 0 mood happy\nat 1 gesture nod\nat 2 gesture wink\n",          // unknown gesture
    "seed 1\n\nat x say hi\n",                                         // bad time
    "# c\nat 0 say hi\nat 1 gesture nod duration\n",                   // missing value
    "fps 30\nduration 5\nat 1 gesture nod intensity 1.5\n",            // out of range
    "at 0 say hi\n\nat 2 say \"unterminated\n",                        // quote
    "at 0 say hi\nat 1 look 10\nat 2 look 10 x\n",                     // line 2 fails first? no: 2
    "a\nb\nat 1 dance\n",                                              // line 1 fails first
    "at 0 mood happy\nat 1 mood happy 0.5 fade -1\nat 1 mood bored\n", // negative fade
  };
  const int lines[] = { 3, 3, 3, 3, 3, 2, 1, 2 };
  for (size_t i = 0; i < std::size(bad); ++i)
  {
    const std::string message = ParseError(bad[i]);
    EXPECT_TRUE(Contains(message, "line " + std::to_string(lines[i]) + ":"))
      << "case " << i << ": " << message;
  }
  EXPECT_TRUE(Contains(ParseError("\n\nat 2 gesture wink\n"), "wink"));
  EXPECT_TRUE(Contains(ParseError("at 0 mood bored 0.5\n"), "bored"));
  EXPECT_TRUE(Contains(ParseError("at 0 dance\n"), "unknown command 'dance'"));
  EXPECT_TRUE(Contains(ParseError("at 1e9 gesture nod\n"), "line 1:"));
  EXPECT_TRUE(Contains(ParseError("at nan gesture nod\n"), "line 1:"));
  EXPECT_TRUE(Contains(ParseError("seed -3\n"), "line 1:"));
}

TEST(BehaviorScript, MalformedJsonNamesTheLine)
{
  // Syntax error: the missing comma is seen on line 4.
  EXPECT_TRUE(Contains(
    ParseError("{\n \"commands\": [\n  {\"at\": 0, \"mood\": \"happy\"}\n  {\"at\": 1}\n]}"),
    "line 4:"));
  // Semantics: the command's own line.
  const std::string unknown = ParseError("{\"commands\": [\n"
                                         "  {\"at\": 0, \"mood\": \"happy\"},\n"
                                         "  {\"at\": 1,\n"
                                         "   \"gesture\": \"wink\"}\n"
                                         "]}");
  EXPECT_TRUE(Contains(unknown, "line 3:")) << unknown;
  EXPECT_TRUE(Contains(unknown, "wink")) << unknown;
  EXPECT_TRUE(Contains(ParseError("[\n{\"at\": 0},\n]"), "line "));  // trailing comma
  EXPECT_TRUE(Contains(ParseError("[\n\n{\"at\": 0}]"), "line 3:")); // no kind
  EXPECT_TRUE(
    Contains(ParseError("[{\"at\": 0, \"say\": \"a\", \"gesture\": \"nod\"}]"), "exactly one"));
  EXPECT_TRUE(
    Contains(ParseError("[{\"at\": \"soon\", \"gesture\": \"nod\"}]"), "'at' must be a number"));
  EXPECT_TRUE(Contains(ParseError("{\"seed\": 1,\n \"fsp\": 30}"), "unknown key 'fsp'"));
  EXPECT_TRUE(Contains(ParseError("[{\"at\": 0, \"look\": [1]}]"), "look"));
  EXPECT_TRUE(Contains(ParseError("[\n 3\n]"), "line "));
  EXPECT_TRUE(Contains(ParseError("{\"commands\": {}}"), "array"));
}

TEST(BehaviorScript, ApplyReportsTheLineOfACommandThatCannotRun)
{
  BehaviorController b; // no synthesizer
  try
  {
    b.ParseScript("at 0 mood happy\nat 1 say \"Hello\"\n");
    FAIL();
  }
  catch (const InputError& e)
  {
    EXPECT_TRUE(Contains(e.what(), "line 2:")) << e.what();
    EXPECT_TRUE(Contains(e.what(), "synthesizer")) << e.what();
  }
  // All or nothing: the mood of line 1 was not applied.
  b.SetDuration(3.0);
  b.SetParameters(behaviortest::QuietParameters());
  b.Prepare();
  std::vector<double> w;
  b.Sample(2.0, w);
  EXPECT_EQ(w[BehaviorChannel::MouthSmile], 0.0);
}

TEST(BehaviorScript, PhonemesGoThroughTheLoaderRelativeToTheScript)
{
  const std::string dir = std::filesystem::temp_directory_path().string() + "/";
  const std::string path =
    dir + "morphnode-behavior-phonemes-" + std::to_string(::getpid()) + ".txt";
  {
    std::ofstream out(path);
    out << "at 1 phonemes hello.pho\n";
  }
  BehaviorController b;
  EXPECT_THROW(b.LoadScript(path), InputError);
  std::string loaded;
  b.SetPhonemeFileLoader(
    [&](const std::string& file)
    {
      loaded = file;
      return MakeUtterance(1.0);
    });
  b.LoadScript(path);
  std::remove(path.c_str());
  EXPECT_EQ(loaded, dir + "hello.pho");
  ASSERT_EQ(b.GetUtterances().size(), 1u);
  EXPECT_EQ(b.GetUtterances()[0].Start, 1.0);
}

TEST(BehaviorScript, ScriptAndApiGiveTheSameTrack)
{
  BehaviorController fromScript = WithSynthesizer();
  fromScript.LoadScript(ScriptDir + "greeting.txt");
  BehaviorController fromApi = WithSynthesizer();
  fromApi.SetSeed(2004);
  fromApi.SetFrameRate(30.0);
  fromApi.SetDuration(8.0);
  fromApi.SetMood("happy", 0.3, 0.0);
  fromApi.LookAt(12.0, 2.0, 0.2, 0.8);
  fromApi.Gesture("smile", 0.4, 1.6, 0.7);
  fromApi.Say("Hello! Nice to meet you.", 1.0);
  fromApi.Gesture("nod", 1.2, 0.8, 0.6);
  fromApi.Say("How are you today?", 3.2);
  fromApi.Gesture("raise_brows", 3.6, 0.9, 0.8);
  fromApi.SetMood("happy", 0.7, 5.5, 1.5);
  const WeightTrack a = fromScript.GenerateTrack(), b = fromApi.GenerateTrack();
  ASSERT_EQ(a.GetNumberOfFrames(), 241u);
  ASSERT_EQ(a.GetChannels(), b.GetChannels());
  for (size_t f = 0; f < a.GetNumberOfFrames(); ++f)
  {
    for (size_t c = 0; c < a.GetNumberOfChannels(); ++c)
    {
      ASSERT_EQ(a.GetValue(f, c), b.GetValue(f, c));
    }
  }
}

TEST(BehaviorScript, ExampleScriptsRun)
{
  for (const char* name : { "greeting.txt", "greeting.json", "bad-news.txt", "idle.txt" })
  {
    BehaviorController b = WithSynthesizer();
    ASSERT_NO_THROW(b.LoadScript(ScriptDir + name)) << name;
    const WeightTrack track = b.GenerateTrack();
    EXPECT_GT(track.GetNumberOfFrames(), 100u) << name;
  }
  // bad-news: the sad mood shows, the eyes close and the head shakes.
  BehaviorController b = WithSynthesizer();
  b.LoadScript(ScriptDir + "bad-news.txt");
  b.Prepare();
  std::vector<double> w;
  b.Sample(3.5, w);
  EXPECT_GT(w[BehaviorChannel::MouthSad], 0.3);
  b.Sample(5.0, w);
  EXPECT_EQ(w[BehaviorChannel::EyesClosed], 1.0);
}

TEST(BehaviorScript, GarbageNeverCrashes)
{
  // A small in-test fuzzer (the libFuzzer target fuzz_script goes further): mutations of
  // the example scripts throw InputError or parse, nothing else.
  const std::string seeds[] = { ReadFile(ScriptDir + "greeting.txt"),
    ReadFile(ScriptDir + "greeting.json"), ReadFile(ScriptDir + "bad-news.txt") };
  BehaviorRandom rng(99);
  const std::string alphabet = "at0123456789.-e \"\\\n{}[]:,#xyznod";
  for (int i = 0; i < 3000; ++i)
  {
    std::string s = seeds[i % 3];
    const int edits = 1 + static_cast<int>(rng.Uniform() * 8);
    for (int e = 0; e < edits && !s.empty(); ++e)
    {
      const size_t at = static_cast<size_t>(rng.Uniform() * s.size());
      const char c = alphabet[static_cast<size_t>(rng.Uniform() * alphabet.size())];
      switch (static_cast<int>(rng.Uniform() * 3))
      {
        case 0:
          s[at] = c;
          break;
        case 1:
          s.insert(s.begin() + at, c);
          break;
        default:
          s.erase(at, 1 + static_cast<size_t>(rng.Uniform() * 20));
          break;
      }
    }
    try
    {
      BehaviorController b = WithSynthesizer();
      b.ParseScript(s);
      b.SetDuration(std::min(b.GetDuration(), 30.0));
      b.Prepare();
      std::vector<double> w;
      b.Sample(1.0, w);
    }
    catch (const InputError&)
    {
    }
  }
}
