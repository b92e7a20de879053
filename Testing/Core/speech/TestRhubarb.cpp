// SPDX-License-Identifier: BSD-3-Clause
#include "MorphNodeTestSkips.h"
#include "base/Error.h"
#include "speech/Rhubarb.h"
#include "speech/Speech.h"

#include <gtest/gtest.h>

#include <sstream>

using namespace morphnode;

namespace
{
std::vector<MouthCue> Cues()
{
  return { { 0.0, 0.05, 'X' }, { 0.05, 0.27, 'D' }, { 0.27, 0.31, 'C' }, { 0.31, 0.43, 'B' },
    { 0.43, 0.47, 'A' }, { 0.47, 0.61, 'F' }, { 0.61, 0.65, 'G' }, { 0.65, 0.70, 'H' },
    { 0.70, 0.85, 'E' }, { 0.85, 1.0 / 3.0 + 0.6, 'X' } };
}

void ExpectSame(const std::vector<MouthCue>& a, const std::vector<MouthCue>& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i)
  {
    EXPECT_EQ(a[i].Shape, b[i].Shape) << i;
    EXPECT_DOUBLE_EQ(a[i].Start, b[i].Start) << i;
    EXPECT_DOUBLE_EQ(a[i].End, b[i].End) << i;
  }
}

std::string TsvError(const std::string& text)
{
  std::istringstream in(text);
  try
  {
    ReadRhubarbTsv(in);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(Rhubarb, TsvRoundTrip)
{
  std::stringstream file;
  WriteRhubarbTsv(file, Cues());
  EXPECT_EQ(file.str().substr(0, 15), "0\tX\n0.05\tD\n0.27");
  // TSV has no end for the last cue: it comes from the sound's length.
  ExpectSame(ReadRhubarbTsv(file, Cues().back().End), Cues());
  // A last cue that is not X gets a closing X, as Rhubarb writes it.
  auto cues = Cues();
  cues.pop_back();
  std::stringstream open;
  WriteRhubarbTsv(open, cues);
  const auto back = ReadRhubarbTsv(open);
  ASSERT_EQ(back.size(), cues.size() + 1);
  EXPECT_EQ(back.back().Shape, 'X');
  EXPECT_DOUBLE_EQ(back.back().Start, 0.85);
  back.size() > 1 ? ExpectSame({ back.begin(), back.end() - 1 }, cues) : void();
}

TEST(Rhubarb, JsonRoundTrip)
{
  std::stringstream file;
  WriteRhubarbJson(file, Cues(), "hello.wav", 2.5);
  EXPECT_NE(file.str().find("\"soundFile\": \"hello.wav\""), std::string::npos);
  EXPECT_NE(file.str().find("\"mouthCues\""), std::string::npos);
  ExpectSame(ReadRhubarbJson(file), Cues());
  // What Rhubarb itself writes.
  std::istringstream rhubarb(R"({"metadata": {"soundFile": "a.wav", "duration": 0.62},
    "mouthCues": [{"start": 0.00, "end": 0.05, "value": "X"}, {"start": 0.05, "end": 0.27, "value": "D"},
                  {"start": 0.27, "end": 0.62, "value": "X"}]})");
  const auto cues = ReadRhubarbJson(rhubarb);
  ASSERT_EQ(cues.size(), 3u);
  EXPECT_EQ(cues[1].Shape, 'D');
  EXPECT_DOUBLE_EQ(cues[2].End, 0.62);
}

TEST(Rhubarb, MalformedInputIsRejected)
{
  EXPECT_NE(TsvError("0.0\tX\n0.1\tQ\n").find("line 2"), std::string::npos);
  EXPECT_NE(TsvError("0.0\tX\n\nabc\tA\n").find("line 3"), std::string::npos);
  EXPECT_NE(TsvError("0.5\tX\n0.1\tA\n").find("line 2"), std::string::npos);
  EXPECT_NE(TsvError("0.5\tX\textra\n").find("line 1"), std::string::npos);
  EXPECT_NE(TsvError("-1\tX\n").find("line 1"), std::string::npos);
  EXPECT_EQ(TsvError("0\tX\n0.2\tA\n"), "");
  const char* badJson[] = {
    "", "[]", "{}", R"({"mouthCues": {}})", R"({"mouthCues": [1]})",
    R"({"mouthCues": [{"start": 0, "end": 1}]})",
    R"({"mouthCues": [{"start": 0, "end": 1, "value": "Z"}]})",
    R"({"mouthCues": [{"start": 1, "end": 0.5, "value": "A"}]})",
    R"({"mouthCues": [{"start": "0", "end": 1, "value": "A"}]})",
    R"({"mouthCues": [{"start": 1, "end": 2, "value": "A"}, {"start": 0, "end": 1, "value": "B"}]})"
  };
  for (const char* text : badJson)
  {
    std::istringstream in(text);
    EXPECT_THROW(ReadRhubarbJson(in), InputError) << text;
  }
  std::stringstream out;
  EXPECT_THROW(WriteRhubarbTsv(out, { { 0.0, 1.0, 'Q' } }), InputError);
  EXPECT_THROW(WriteRhubarbJson(out, { { 1.0, 0.5, 'A' } }), InputError);
}

TEST(Rhubarb, VisemesToShapesAndBack)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  // Each viseme set maps every viseme to a shape and every shape to a viseme.
  for (VisemeSet set : { VisemeSet::Oculus15, VisemeSet::German16, VisemeSet::Paper6 })
  {
    const VisemeMap map = VisemeMap::Builtin(set, "en");
    for (size_t v = 0; v < map.GetVisemes().size(); ++v)
    {
      EXPECT_TRUE(IsRhubarbShape(map.GetRhubarbShape(int(v))));
    }
    for (char shape : std::string("ABCDEFGHX"))
    {
      EXPECT_GE(map.GetVisemeOfShape(shape), 0) << shape;
    }
    EXPECT_EQ(map.GetRhubarbShape(map.GetSilenceIndex()), 'X');
  }
  const VisemeMap oculus = VisemeMap::Builtin(VisemeSet::Oculus15, "en");
  EXPECT_EQ(oculus.GetRhubarbShape(oculus.FindViseme("PP")), 'A');
  EXPECT_EQ(oculus.GetRhubarbShape(oculus.FindViseme("aa")), 'D');
  EXPECT_EQ(oculus.GetRhubarbShape(oculus.FindViseme("ou")), 'F');
  EXPECT_EQ(oculus.GetRhubarbShape(oculus.FindViseme("FF")), 'G');

  // A spoken utterance: every bilabial shows as an A cue at its time.
  SpeechOptions options;
  options.Voice = "en";
  const Utterance u = SpeakText("Bob met Pam. Mum.", options);
  const auto cues = VisemeTrackToMouthCues(u.Visemes, oculus, 0.07);
  ASSERT_FALSE(cues.empty());
  EXPECT_DOUBLE_EQ(cues.front().Start, 0.0);
  for (size_t i = 1; i < cues.size(); ++i)
  {
    EXPECT_DOUBLE_EQ(cues[i].Start, cues[i - 1].End);
    EXPECT_NE(cues[i].Shape, cues[i - 1].Shape);
    EXPECT_TRUE(
      cues[i].End - cues[i].Start >= 0.07 - 1e-9 || cues[i].Shape == 'A' || i + 1 == cues.size());
  }
  for (const auto& p : u.Phonemes)
  {
    if (p.Sampa == "b" || p.Sampa == "p" || p.Sampa == "m")
    {
      const double t = p.Start + 0.5 * p.Duration - options.Coarticulation.Lead;
      const bool covered = std::any_of(cues.begin(), cues.end(),
        [&](const MouthCue& c)
        { return c.Shape == 'A' && c.Start <= t + 1.0 / 60.0 && c.End >= t - 1.0 / 60.0; });
      EXPECT_TRUE(covered) << p.Sampa << " at " << p.Start;
    }
  }
  // Shapes back to a track: the A cues close the lips fully, D opens the jaw.
  SpeechOptions back;
  back.Coarticulation.Lead = 0.0;
  const Utterance fromCues = UtteranceFromMouthCues(Cues(), back);
  const size_t pp = static_cast<size_t>(oculus.FindViseme("PP"));
  const size_t aa = static_cast<size_t>(oculus.FindViseme("aa"));
  EXPECT_GE(fromCues.Visemes.Sample(0.45, pp), 0.999);
  EXPECT_GE(fromCues.Visemes.Sample(0.16, aa), 0.7);
  EXPECT_DOUBLE_EQ(fromCues.Duration, Cues().back().End);
}

// Rhubarb's XML export as its documentation shows it (`--exportFormat xml`).
TEST(Rhubarb, XmlExportReadsLikeJson)
{
  const std::string xml = R"(<?xml version="1.0" encoding="utf-8"?>
<rhubarbResult>
  <metadata>
    <soundFile>C:\Users\Daniel\Desktop\av\rhubarb\tests\resources\abcdefghx.wav</soundFile>
    <duration>6.92</duration>
  </metadata>
  <mouthCues>
    <mouthCue start="0.00" end="0.01">X</mouthCue>
    <mouthCue start="0.01" end="0.08">E</mouthCue>
    <mouthCue start="0.08" end="0.29">B</mouthCue>
    <mouthCue start="0.29" end="0.36">A</mouthCue>
    <mouthCue start="0.36" end="6.92">X</mouthCue>
  </mouthCues>
</rhubarbResult>
)";
  const std::string json = R"({"metadata": {"soundFile": "x.wav", "duration": 6.92}, "mouthCues": [
    {"start": 0.00, "end": 0.01, "value": "X"}, {"start": 0.01, "end": 0.08, "value": "E"},
    {"start": 0.08, "end": 0.29, "value": "B"}, {"start": 0.29, "end": 0.36, "value": "A"},
    {"start": 0.36, "end": 6.92, "value": "X"}]})";
  std::istringstream in(xml), jin(json);
  const auto cues = ReadRhubarbXml(in);
  ASSERT_EQ(cues.size(), 5u);
  EXPECT_EQ(cues[3].Shape, 'A');
  EXPECT_DOUBLE_EQ(cues[3].Start, 0.29);
  EXPECT_DOUBLE_EQ(cues[4].End, 6.92);
  ExpectSame(cues, ReadRhubarbJson(jin));
  ExpectSame(ParseRhubarb(xml), cues); // '<' first: XML
}

TEST(Rhubarb, MalformedXmlIsRejected)
{
  auto error = [](const std::string& body)
  {
    std::istringstream in("<rhubarbResult><mouthCues>\n" + body + "</mouthCues></rhubarbResult>");
    try
    {
      ReadRhubarbXml(in);
    }
    catch (const InputError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(R"(<mouthCue start="0" end="1">A</mouthCue>)"), "");
  EXPECT_NE(error(R"(<mouthCue start="0" end="1">Q</mouthCue>)").find("line 2: a mouthCue's shape"),
    std::string::npos);
  EXPECT_NE(error(R"(<mouthCue start="0">A</mouthCue>)").find("needs 'start' and 'end'"),
    std::string::npos);
  EXPECT_NE(error(R"(<mouthCue start="x" end="1">A</mouthCue>)").find("time in seconds"),
    std::string::npos);
  EXPECT_NE(error(R"(<mouthCue start="-1" end="1">A</mouthCue>)").find("time in seconds"),
    std::string::npos);
  EXPECT_NE(error(R"(<mouthCue start="2" end="1">A</mouthCue>)").find("ends before it starts"),
    std::string::npos);
  EXPECT_NE(
    error(R"(<mouthCue start="1" end="2">A</mouthCue><mouthCue start="0" end="1">X</mouthCue>)")
      .find("starts before"),
    std::string::npos);
  EXPECT_NE(error(R"(<mouthCue start="0" end="1"><b/>A</mouthCue>)").find("only its shape"),
    std::string::npos);
  EXPECT_NE(
    error(R"(<mouthCue start="0" end="1">A</mouthCu>)").find("not valid XML"), std::string::npos);
  std::istringstream empty("");
  EXPECT_THROW(ReadRhubarbXml(empty), InputError);
}
