// SPDX-License-Identifier: BSD-3-Clause
// Lip-sync files into utterances: either Rhubarb export told apart by its content, from a
// string or a file (errors naming the file), and .pho phonemes from a string.
#include "base/Error.h"
#include "speech/Pho.h"
#include "speech/Rhubarb.h"
#include "speech/Speech.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

using namespace morphnode;

namespace
{
const std::string SourceDir = MORPHNODE_SOURCE_DIR;
const std::string OutputDir = MORPHNODE_TEST_OUTPUT_DIR;
const std::string Corpus = SourceDir + "/Testing/Fuzz/corpus/";

std::string Write(const std::string& name, const std::string& text)
{
  const std::string path = OutputDir + "/TestSpeechFiles_" + name;
  std::ofstream(path) << text;
  return path;
}
} // namespace

TEST(SpeechFiles, RhubarbTsvAndJsonToldApartByTheirContent)
{
  const auto tsv = ParseRhubarb("0.00\tX\n0.05\tD\n0.27\tA\n0.43\tX\n");
  ASSERT_EQ(tsv.size(), 4u);
  EXPECT_EQ(tsv[1].Shape, 'D');
  EXPECT_EQ(tsv[1].End, 0.27);
  const auto json =
    ParseRhubarb("\n  {\"mouthCues\": [{\"start\": 0.0, \"end\": 0.05, \"value\": \"X\"},"
                 " {\"start\": 0.05, \"end\": 0.27, \"value\": \"D\"}]}");
  ASSERT_EQ(json.size(), 2u);
  EXPECT_EQ(json[1].Shape, 'D');
  EXPECT_EQ(json[1].End, 0.27);
  EXPECT_TRUE(ParseRhubarb("").empty());
  EXPECT_THROW(ParseRhubarb("0.0\tQ\n"), InputError);
  EXPECT_THROW(ParseRhubarb("{\"mouthCues\": 3}"), InputError);

  // The fuzz corpus seeds are real exports.
  EXPECT_EQ(ReadRhubarbFile(Corpus + "rhubarb_tsv/sample.tsv").size(), 10u);
  EXPECT_EQ(ReadRhubarbFile(Corpus + "rhubarb_json/sample.json").size(), 4u);
  for (const std::string bad :
    { "rhubarb_tsv/decreasing.tsv", "rhubarb_json/end_before_start.json" })
  {
    try
    {
      ReadRhubarbFile(Corpus + bad);
      FAIL() << bad << " was read";
    }
    catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(Corpus + bad), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(ReadRhubarbFile(OutputDir + "/no such file.tsv"), InputError);
}

TEST(SpeechFiles, CuesAndPhonemesBecomeUtterancesWithoutAudio)
{
  SpeechOptions options;
  options.Visemes = VisemeSet::Paper6;
  const Utterance cues =
    UtteranceFromMouthCues(ReadRhubarbFile(Corpus + "rhubarb_json/sample.json"), options);
  EXPECT_TRUE(cues.Audio.empty());
  EXPECT_DOUBLE_EQ(cues.Duration, 0.62);
  EXPECT_GE(cues.Visemes.FindChannel("A"), 0);

  const std::string pho = "_ 50\nh 60\nA: 200 50 120\n_ 100\n"; // English SAMPA
  const Utterance fromText = UtteranceFromPhonemes(ParsePho(pho), options);
  const Utterance fromFile = LoadPhoUtterance(Write("a.pho", pho), options);
  EXPECT_TRUE(fromText.Audio.empty());
  EXPECT_NEAR(fromText.Duration, 0.41, 1e-9);
  ASSERT_EQ(fromText.Phonemes.size(), fromFile.Phonemes.size());
  EXPECT_EQ(fromText.Visemes.GetChannels(), fromFile.Visemes.GetChannels());
  const int a = fromText.Visemes.FindChannel("A");
  ASSERT_GE(a, 0);
  double open = 0.0;
  for (size_t f = 0; f < fromText.Visemes.GetNumberOfFrames(); ++f)
  {
    EXPECT_EQ(fromText.Visemes.GetValue(f, static_cast<size_t>(a)),
      fromFile.Visemes.GetValue(f, static_cast<size_t>(a)));
    open = std::max(open, fromText.Visemes.GetValue(f, static_cast<size_t>(a)));
  }
  EXPECT_GT(open, 0.5) << "the long A: opens the mouth";

  // Nothing to say is an error, not an empty utterance.
  EXPECT_THROW(UtteranceFromPhonemes(ParsePho("; only a comment\n"), options), InputError);
  EXPECT_THROW(LoadPhoUtterance(Write("empty.pho", ""), options), InputError);
  EXPECT_THROW(UtteranceFromMouthCues(ParseRhubarb(""), options), InputError);
}
