// SPDX-License-Identifier: BSD-3-Clause
// External speech through the command protocol: `say` with a recording on the server and
// its timings (docs/dialog.md), the text then optional (the transcript), and its errors.
#include "dialog/DialogProtocol.h"

#include <gtest/gtest.h>

#include <string>
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
