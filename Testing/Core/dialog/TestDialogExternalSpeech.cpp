// SPDX-License-Identifier: BSD-3-Clause
// External speech through the command protocol: `say` with a recording on the server and
// its timings (docs/dialog.md), the text then optional (the transcript), and its errors.
#include "dialog/DialogProtocol.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <utility>
#include <variant>

using namespace morphnode::dialog;

TEST(DialogProtocol, SayWithARecordingAndItsTimings)
{
  ParsedLine p =
    ParseCommand(R"({"cmd":"say","id":7,"audio":"/srv/take.wav","timings":"/srv/take.json",)"
                 R"("timings_format":"azure-visemes"})");
  ASSERT_TRUE(p.Ok()) << p.Error.Message;
  const auto& say = std::get<SayCommand>(p.Cmd.Body);
  EXPECT_EQ(say.Audio, "/srv/take.wav");
  EXPECT_EQ(say.Timings, "/srv/take.json");
  EXPECT_EQ(say.TimingsFormat, "azure-visemes");
  EXPECT_EQ(say.Text, "");
  // A recording with its transcript (timed by alignment).
  p = ParseCommand(R"({"cmd":"say","audio":"/srv/take.wav","text":"Hello there."})");
  ASSERT_TRUE(p.Ok()) << p.Error.Message;
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).Text, "Hello there.");
  // Errors: timings without a recording, an empty recording name, text still needed alone.
  for (const char* line : { R"({"cmd":"say","text":"x","timings":"/srv/t.tsv"})",
         R"({"cmd":"say","audio":""})", R"({"cmd":"say","audio":5})", R"({"cmd":"say"})" })
  {
    const ParsedLine bad = ParseCommand(line);
    EXPECT_FALSE(bad.Ok()) << line;
    EXPECT_EQ(bad.Error.Reason, "bad_field") << line << ": " << bad.Error.Message;
  }
  const ParsedLine misspelt = ParseCommand(R"({"cmd":"say","audio":"/a.wav","timing":"/t.tsv"})");
  EXPECT_EQ(misspelt.Error.Reason, "unknown_field");
  EXPECT_NE(misspelt.Error.Message.find("audio, timings, timings_format"), std::string::npos)
    << misspelt.Error.Message;
}

// Inline external speech: the recording's bytes in base64 (`audio_base64`) and the timing
// file's text or JSON (`timings_inline`), so that a client on another machine or without
// the speech folder hands over what its TTS returned.
TEST(DialogProtocol, SayWithInlineAudioAndTimings)
{
  // "RIFF" and two bytes more, the padding's two cases and none.
  ParsedLine p = ParseCommand(
    R"({"cmd":"say","id":"r1","audio_base64":"UklGRgAB","timings_inline":"0.00\tX\n0.30\tA\n"})");
  ASSERT_TRUE(p.Ok()) << p.Error.Message;
  const auto& say = std::get<SayCommand>(p.Cmd.Body);
  EXPECT_EQ(say.AudioData, std::string("RIFF\0\x01", 6));
  EXPECT_EQ(say.TimingsData, "0.00\tX\n0.30\tA\n");
  EXPECT_TRUE(say.HasRecording());
  EXPECT_TRUE(say.Audio.empty());
  for (const auto& [encoded, bytes] : std::initializer_list<std::pair<const char*, std::string>>{
         { "Zm9vYg==", "foob" }, { "Zm9vYmE=", "fooba" }, { "Zm9vYmFy", "foobar" },
         { "Zm9vYg", "foob" }, { "Zm9v\\nYmFy", "foobar" } })
  {
    p = ParseCommand(std::string(R"({"cmd":"say","audio_base64":")") + encoded + "\"}");
    ASSERT_TRUE(p.Ok()) << encoded << ": " << p.Error.Message;
    EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).AudioData, bytes) << encoded;
  }
  // Timings as JSON: an object as it is (Rhubarb JSON, Azure, character alignments); an
  // array of speech marks as Polly's lines; another array as it is (Azure's events).
  p = ParseCommand(R"({"cmd":"say","audio_base64":"AAAA","timings_inline":{"mouthCues":[]}})");
  ASSERT_TRUE(p.Ok()) << p.Error.Message;
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).TimingsData, R"({"mouthCues":[]})");
  p = ParseCommand(
    R"({"cmd":"say","audio_base64":"AAAA","timings_inline":[)"
    R"({"time":0,"type":"viseme","value":"sil"},{"time":120,"type":"viseme","value":"p"}]})");
  ASSERT_TRUE(p.Ok()) << p.Error.Message;
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).TimingsData,
    "{\"time\":0,\"type\":\"viseme\",\"value\":\"sil\"}\n"
    "{\"time\":120,\"type\":\"viseme\",\"value\":\"p\"}\n");
  p = ParseCommand(
    R"({"cmd":"say","audio":"a.wav","timings_inline":[{"AudioOffset":0,"VisemeId":0}]})");
  ASSERT_TRUE(p.Ok()) << p.Error.Message;
  EXPECT_EQ(std::get<SayCommand>(p.Cmd.Body).TimingsData, R"([{"AudioOffset":0,"VisemeId":0}])");

  // Errors: each a bad_field event that says what is wrong (and where, for base64).
  const std::pair<const char*, const char*> bad[] = {
    { R"({"cmd":"say","audio_base64":"UklG*gAB"})", "is not valid base64: '*' at character 4" },
    { R"({"cmd":"say","audio_base64":"UklGR"})", "one character too many or too few" },
    { R"({"cmd":"say","audio_base64":"UklGRg=A"})", "'=' before the end at character 6" },
    { R"({"cmd":"say","audio_base64":"UklGRg==="})", "more than two '='" },
    { R"({"cmd":"say","audio_base64":"UklGRgAB="})", "do not complete the last group" },
    { R"({"cmd":"say","audio_base64":"Zm9vYh=="})", "bits set beyond the data" },
    { R"({"cmd":"say","audio_base64":"Zm9v\u00e9"})", "byte 195 at character 4" },
    { R"({"cmd":"say","audio_base64":""})", "'audio_base64' must not be empty" },
    { R"({"cmd":"say","audio_base64":"===="})", "more than two '='" },
    { R"({"cmd":"say","audio_base64":"=="})", "do not complete the last group" },
    { R"({"cmd":"say","audio_base64":7})", "'audio_base64' must be a string" },
    { R"({"cmd":"say","audio":"a.wav","audio_base64":"AAAA"})", "not both" },
    { R"({"cmd":"say","audio_base64":"AAAA","timings":"t.tsv","timings_inline":"0 X"})",
      "not both" },
    { R"({"cmd":"say","text":"Hi","timings_inline":"0.0\tX"})",
      "go with 'audio' or 'audio_base64'" },
    { R"({"cmd":"say","audio_base64":"AAAA","timings_inline":" "})", "must not be empty" },
    { R"({"cmd":"say","audio_base64":"AAAA","timings_inline":5})", "timings' text" },
    { R"({"cmd":"say","audio_base64":"AAAA","timings_inline":[]})", "timings' text" },
  };
  for (const auto& [line, message] : bad)
  {
    const ParsedLine e = ParseCommand(line);
    ASSERT_FALSE(e.Ok()) << line;
    EXPECT_EQ(e.Error.Reason, "bad_field") << line << ": " << e.Error.Message;
    EXPECT_NE(e.Error.Message.find(message), std::string::npos) << line << ": " << e.Error.Message;
    EXPECT_EQ(e.Error.Cmd, "say");
  }
  // The line limit bounds the recording (the framer drops longer lines as they come).
  const std::string line =
    R"({"cmd":"say","audio_base64":")" + std::string(DefaultMaxLineBytes, 'A') + "\"}";
  EXPECT_EQ(ParseCommand(line).Error.Reason, "too_long");
}
