// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "speech/Pho.h"

#include <gtest/gtest.h>

#include <sstream>

using namespace morphnode;

namespace
{
/// The message of the InputError that parsing `text` throws ("" if none).
std::string ParseError(const std::string& text)
{
  try
  {
    ParsePho(text);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(Pho, ReadsPhonemesPitchCommentsAndCommands)
{
  const auto phonemes = ParsePho("; a comment\n"
                                 "_ 50\n"
                                 "h 51 ; trailing comment\n"
                                 "@ 61 50 120\n"
                                 "\n"
                                 "#\n"
                                 ";; T=2\n"
                                 "l 10 0 100 100% 90\n"
                                 ";; F=0.5\n"
                                 "@U 100 50 200\n");
  ASSERT_EQ(phonemes.size(), 5u);
  EXPECT_EQ(phonemes[1].Sampa, "h");
  EXPECT_DOUBLE_EQ(phonemes[1].Start, 0.05);
  EXPECT_DOUBLE_EQ(phonemes[1].Duration, 0.051);
  ASSERT_EQ(phonemes[2].Pitch.size(), 1u);
  EXPECT_DOUBLE_EQ(phonemes[2].Pitch[0].first, 0.5);
  EXPECT_DOUBLE_EQ(phonemes[2].Pitch[0].second, 120.0);
  // T=2 doubles later durations.
  EXPECT_DOUBLE_EQ(phonemes[3].Duration, 0.020);
  ASSERT_EQ(phonemes[3].Pitch.size(), 2u);
  EXPECT_DOUBLE_EQ(phonemes[3].Pitch[1].first, 1.0);
  EXPECT_DOUBLE_EQ(phonemes[3].Pitch[1].second, 90.0);
  // F=0.5 halves later pitch values.
  EXPECT_DOUBLE_EQ(phonemes[4].Pitch[0].second, 100.0);
  EXPECT_NEAR(phonemes[4].Start, 0.05 + 0.051 + 0.061 + 0.020, 1e-12);
}

TEST(Pho, RoundTripKeepsNamesTimesAndPitch)
{
  std::vector<TimedPhoneme> original;
  const char* names[] = { "_", "g", "u:", "t", "@", "n", "t", "a:", "k", "_" };
  double start = 0.0;
  for (int i = 0; i < 10; ++i)
  {
    TimedPhoneme p;
    p.Sampa = names[i];
    p.Start = start;
    p.Duration = 0.0123 * (i + 1) + 1.0 / 3.0 * 0.01;
    if (i % 3 == 1)
    {
      p.Pitch = { { 0.0, 110.5 }, { 0.25, 130.0 }, { 1.0, 97.125 } };
    }
    start += p.Duration;
    original.push_back(p);
  }
  std::stringstream file;
  WritePho(file, original);
  const auto back = ReadPho(file);
  ASSERT_EQ(back.size(), original.size());
  for (size_t i = 0; i < back.size(); ++i)
  {
    EXPECT_EQ(back[i].Sampa, original[i].Sampa);
    EXPECT_NEAR(back[i].Start, original[i].Start, 1e-12);
    EXPECT_NEAR(back[i].Duration, original[i].Duration, 1e-12);
    ASSERT_EQ(back[i].Pitch.size(), original[i].Pitch.size());
    for (size_t k = 0; k < back[i].Pitch.size(); ++k)
    {
      EXPECT_NEAR(back[i].Pitch[k].first, original[i].Pitch[k].first, 1e-12);
      EXPECT_NEAR(back[i].Pitch[k].second, original[i].Pitch[k].second, 1e-12);
    }
  }
  // The writer's output is itself stable.
  std::stringstream again;
  WritePho(again, back);
  EXPECT_EQ(again.str(), file.str());
}

TEST(Pho, WriterTurnsGapsIntoPauses)
{
  TimedPhoneme a{ "a:", 0.0, 0.1, {} }, b{ "b", 0.3, 0.05, {} };
  std::stringstream file;
  WritePho(file, { a, b });
  const auto back = ReadPho(file);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[1].Sampa, "_");
  EXPECT_NEAR(back[1].Duration, 0.2, 1e-12);
  EXPECT_NEAR(back[2].Start, 0.3, 1e-12);
}

TEST(Pho, WriterRejectsUnwritableNames)
{
  std::stringstream out;
  EXPECT_THROW(WritePho(out, { TimedPhoneme{ "", 0, 0.1, {} } }), InputError);
  EXPECT_THROW(WritePho(out, { TimedPhoneme{ "a b", 0, 0.1, {} } }), InputError);
  EXPECT_THROW(WritePho(out, { TimedPhoneme{ ";x", 0, 0.1, {} } }), InputError);
  EXPECT_THROW(WritePho(out, { TimedPhoneme{ "a", 0, -0.1, {} } }), InputError);
  EXPECT_THROW(WritePho(out, { TimedPhoneme{ "a", 0, 0.1, { { 1.5, 100.0 } } } }), InputError);
}

TEST(Pho, MalformedLinesNameTheirLine)
{
  const std::string good = "_ 50\n; comment\na 80\n";
  struct Case
  {
    std::string Line;
    std::string Expected; // part of the message
  };
  const Case cases[] = {
    { "b", "no duration" },
    { "b x", "duration 'x'" },
    { "b -5", "duration '-5'" },
    { "b 1e999", "duration" },
    { "b nan", "duration" },
    { "b 80 50", "pairs" },
    { "b 80 50 120 70", "pairs" },
    { "b 80 150 120", "position '150'" },
    { "b 80 -1 120", "position" },
    { "b 80 50 0", "pitch '0'" },
    { "b 80 50 abc", "pitch 'abc'" },
    { ";; T=0", "command T" },
    { ";; F=x", "command F" },
    { "b 4000000", "longer than an hour" },
  };
  for (const Case& c : cases)
  {
    const std::string message = ParseError(good + c.Line + "\nc 10\n");
    EXPECT_NE(message.find("pho line 4:"), std::string::npos) << c.Line << " -> " << message;
    EXPECT_NE(message.find(c.Expected), std::string::npos) << c.Line << " -> " << message;
  }
  EXPECT_EQ(ParseError(good), "");
}

TEST(Pho, IgnoresUnknownCommandsAndWindowsLineEnds)
{
  const auto phonemes = ParsePho(";; SPEAKER=bob\r\n;; just a remark\r\na 80 0 100\r\n");
  ASSERT_EQ(phonemes.size(), 1u);
  EXPECT_DOUBLE_EQ(phonemes[0].Pitch[0].second, 100.0);
}

TEST(Pho, MissingFileIsAnInputError)
{
  EXPECT_THROW(ReadPhoFile("/nonexistent/file.pho"), InputError);
}
