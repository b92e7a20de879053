// SPDX-License-Identifier: BSD-3-Clause
// Recordings into utterances by every route (transcript, timing file, recognition), and
// the PocketSphinx phoneme recognizer on real speech from pocketsphinx-testdata.
#include "MorphNodeTestErrors.h"
#include "align/PhonemeRecognizer.h"
#include "align/RecordingSpeech.h"
#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"
#include "base/Text.h"
#include "speech/Sampa.h"
#include "speech/SpeechSynthesizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

using namespace morphnode;

// PocketSphinx 5prealpha's phone-loop search leaks about 70 bytes per utterance inside
// libsphinxbase (history entries ckd_calloc'ed by the search and never freed; a small C
// program that only decodes shows the same). Not ours to free: LeakSanitizer, when this test
// runs under it, is told so.
extern "C" const char* __lsan_default_suppressions()
{
  return "leak:libsphinxbase.so\nleak:libpocketsphinx.so\n";
}

using morphnode_test::ErrorOf;

namespace
{
const std::string Output = MORPHNODE_TEST_OUTPUT_DIR;
const std::string LibriVox =
  "/usr/share/pocketsphinx/test/data/librivox/sense_and_sensibility_01_austen_64kb-0880.wav";

double MaxWeight(const Utterance& u, const std::string& viseme)
{
  const int c = u.Visemes.FindChannel(viseme);
  double m = 0.0;
  for (size_t f = 0; c >= 0 && f < u.Visemes.GetNumberOfFrames(); ++f)
  {
    m = std::max(m, u.Visemes.GetFrame(f)[c]);
  }
  return m;
}

/// "Bob met Pam" by another eSpeak voice, at 44.1 kHz.
AudioBuffer BobMetPam(SynthesisResult* truth = nullptr)
{
  SpeechSynthesizer speaker("en+m3", 150);
  speaker.SetEstimatePitch(false);
  const SynthesisResult r = speaker.Synthesize("Bob met Pam by the pool.");
  if (truth)
  {
    *truth = r;
  }
  return Resample(FromInt16Mono(r.Audio, r.SampleRate), 44100);
}
} // namespace

TEST(RecordingSpeech, TranscriptRouteGivesTheRecordingAFace)
{
  if (!IsTranscriptAlignmentAvailable())
  {
    GTEST_SKIP() << "built without eSpeak NG";
  }
  const AudioBuffer audio = BobMetPam();
  const std::string path = Output + "/recording_bob.wav";
  WriteWavFile(path, audio);
  SpeechOptions speech;
  RecordingOptions options;
  options.Transcript = "Bob met Pam by the pool.";
  double lastProgress = -1.0;
  options.Progress = [&lastProgress](double f)
  {
    lastProgress = f;
    return true;
  };
  RecordingReport report;
  const Utterance u = SpeakAudioFile(path, speech, options, &report);
  EXPECT_EQ(report.Route, RecordingRoute::Transcript);
  EXPECT_TRUE(report.Reliable);
  EXPECT_EQ(lastProgress, 1.0);
  EXPECT_EQ(u.SampleRate, 44100); // the recording's own sound, at its own rate
  EXPECT_GE(u.Audio.size(), audio.GetFrameCount());
  EXPECT_NEAR(u.Duration, audio.GetDuration(), 0.1);
  EXPECT_GT(MaxWeight(u, "PP"), 0.99); // b, m, p close the lips
  EXPECT_GE(report.Words.size(), 5u);
  EXPECT_FALSE(u.Cues.empty() && u.Phonemes.empty());
}

TEST(RecordingSpeech, TimingFileRouteAndItsWarnings)
{
  const AudioBuffer audio = []
  {
    AudioBuffer a;
    a.SampleRate = 16000;
    a.Channels = 1;
    a.Samples.assign(16000, 0.01f); // one second
    return a;
  }();
  const std::string grid = Output + "/recording_timing.TextGrid";
  std::ofstream(grid)
    << "File type = \"ooTextFile\"\nObject class = \"TextGrid\"\n0\n2.5\n<exists>\n1\n"
       "\"IntervalTier\"\n\"phones\"\n0\n2.5\n3\n0\n0.2\n\"sil\"\n0.2\n0.5\n\"M\"\n0.5\n2."
       "5\n\"AA1\"\n";
  SpeechOptions speech;
  std::vector<std::string> warnings;
  speech.Warn = CollectWarnings(warnings);
  RecordingOptions options;
  options.TimingFile = grid;
  RecordingReport report;
  const Utterance u = SpeakRecording(audio, speech, options, &report);
  EXPECT_EQ(report.Route, RecordingRoute::TimingFile);
  EXPECT_GT(MaxWeight(u, "PP"), 0.99);
  EXPECT_GT(MaxWeight(u, "aa"), 0.5);
  ASSERT_EQ(warnings.size(), 1u); // the timings outlast the recording by 1.5 s
  EXPECT_NE(warnings[0].find("past the end"), std::string::npos) << warnings[0];
  options.TimingFile = Output + "/no-such.TextGrid";
  EXPECT_THROW(SpeakRecording(audio, speech, options), InputError);
}

TEST(RecordingSpeech, BadInputs)
{
  SpeechOptions speech;
  EXPECT_NE(
    ErrorOf([&] { SpeakRecording(AudioBuffer{}, speech); }).find("empty"), std::string::npos);
  EXPECT_THROW(SpeakAudioFile(Output + "/no-such-recording.wav", speech), InputError);
  // Without a transcript, only English can be recognized.
  SpeechOptions german;
  german.Voice = "de";
  AudioBuffer audio;
  audio.SampleRate = 16000;
  audio.Channels = 1;
  audio.Samples.assign(16000, 0.0f);
  EXPECT_NE(
    ErrorOf([&] { SpeakRecording(audio, german); }).find("only English"), std::string::npos);
  RecordingOptions timing;
  timing.Route = RecordingRoute::TimingFile;
  EXPECT_NE(ErrorOf([&] { SpeakRecording(audio, speech, timing); }).find("needs a timing file"),
    std::string::npos);
  EXPECT_EQ(ParseRecordingRoute("Recognition"), RecordingRoute::Recognition);
  EXPECT_THROW(ParseRecordingRoute("guess"), InputError);
}

TEST(PhonemeRecognition, RealSpeechFromPocketsphinxTestdata)
{
  if (!IsPhonemeRecognitionAvailable())
  {
    GTEST_SKIP() << "built without PocketSphinx (MORPHNODE_ENABLE_POCKETSPHINX=OFF)";
  }
  if (!std::filesystem::exists(LibriVox))
  {
    GTEST_SKIP() << "pocketsphinx-testdata is not installed (" << LibriVox << ")";
  }
  // "he was not an ill disposed young man"
  const AudioBuffer audio = ReadAudioFile(LibriVox);
  const PhonemeRecognition r = RecognizePhonemes(audio);
  ASSERT_GT(r.Phonemes.size(), 15u);
  EXPECT_DOUBLE_EQ(r.Phonemes.front().Start, 0.0);
  for (size_t k = 1; k < r.Phonemes.size(); ++k)
  {
    EXPECT_NEAR(r.Phonemes[k].Start, r.Phonemes[k - 1].Start + r.Phonemes[k - 1].Duration, 1e-9);
  }
  EXPECT_NEAR(r.Phonemes.back().Start + r.Phonemes.back().Duration, audio.GetDuration(), 0.02);
  // Sounds that are there: the n of "not"/"an"/"man", the l of "ill", the s/z of "was"/"disposed".
  auto has = [&](const char* name)
  {
    return std::any_of(
      r.Phonemes.begin(), r.Phonemes.end(), [&](const TimedPhoneme& p) { return p.Sampa == name; });
  };
  EXPECT_TRUE(has("n"));
  EXPECT_TRUE(has("l"));
  EXPECT_TRUE(has("s") || has("z"));
  // The recognizer route of SpeakRecording: the same phonemes, and the recording as sound.
  RecordingReport report;
  SpeechOptions speech;
  std::vector<std::string> warnings;
  speech.Warn = CollectWarnings(warnings);
  const Utterance u = SpeakRecording(audio, speech, RecordingOptions{}, &report);
  EXPECT_EQ(report.Route, RecordingRoute::Recognition);
  // It says that it is the least precise route (the others do not: see above).
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("timed by English phoneme recognition, the least precise route"),
    std::string::npos)
    << warnings[0];
  EXPECT_EQ(u.SampleRate, audio.SampleRate);
  // Silence: nothing recognized is an error, not an empty face track.
  AudioBuffer silence;
  silence.SampleRate = 16000;
  silence.Channels = 1;
  silence.Samples.assign(32000, 0.0f);
  EXPECT_NE(ErrorOf([&] { RecognizePhonemes(silence); }).find("no speech"), std::string::npos);
  RecognitionOptions wrongModel;
  wrongModel.ModelDirectory = Output;
  EXPECT_NE(ErrorOf([&] { RecognizePhonemes(audio, wrongModel); }).find("pocketsphinx-en-us"),
    std::string::npos);
  RecognitionOptions cancel;
  cancel.Progress = [](double) { return false; };
  EXPECT_NE(
    ErrorOf([&] { RecognizePhonemes(audio, cancel); }).find("cancelled"), std::string::npos);
}

// Rhubarb is run on recordings (its main use): its cues in TSV, JSON or XML with the
// recording give the recording a mouth, in sync (the cues' times are the sound's times).
TEST(RecordingSpeech, RhubarbCuesOfTheRecording)
{
  AudioBuffer audio;
  audio.SampleRate = 16000;
  audio.Channels = 1;
  audio.Samples.assign(16000, 0.01f); // one second
  const std::string tsv = Output + "/recording_cues.tsv";
  const std::string json = Output + "/recording_cues.json";
  const std::string xml = Output + "/recording_cues.xml";
  const std::string unnamed = Output + "/recording_cues.dat";
  std::ofstream(tsv) << "0.00\tX\n0.20\tA\n0.40\tD\n0.80\tX\n";
  std::ofstream(json) << R"({"metadata": {"soundFile": "r.wav", "duration": 1.0}, "mouthCues": [
    {"start": 0.0, "end": 0.2, "value": "X"}, {"start": 0.2, "end": 0.4, "value": "A"},
    {"start": 0.4, "end": 0.8, "value": "D"}, {"start": 0.8, "end": 1.0, "value": "X"}]})";
  const std::string xmlText = R"(<?xml version="1.0" encoding="utf-8"?>
<rhubarbResult><metadata><soundFile>r.wav</soundFile><duration>1.00</duration></metadata>
<mouthCues><mouthCue start="0.00" end="0.20">X</mouthCue><mouthCue start="0.20" end="0.40">A</mouthCue>
<mouthCue start="0.40" end="0.80">D</mouthCue><mouthCue start="0.80" end="1.00">X</mouthCue></mouthCues>
</rhubarbResult>)";
  std::ofstream(xml) << xmlText;
  std::ofstream(unnamed) << xmlText;
  SpeechOptions speech;
  for (const std::string& file : { tsv, json, xml, unnamed })
  {
    RecordingOptions options;
    options.TimingFile = file;
    if (file == unnamed)
    {
      options.Timing.Format = ParseTimingFormat("rhubarb-xml"); // --timings-format
    }
    RecordingReport report;
    const Utterance u = SpeakRecording(audio, speech, options, &report);
    EXPECT_EQ(report.Route, RecordingRoute::TimingFile) << file;
    ASSERT_FALSE(u.Audio.empty()) << file;
    EXPECT_NEAR(static_cast<double>(u.Audio.size()) / u.SampleRate, 1.0, 1e-3) << file;
    // In sync: closed lips (A, 0.2-0.4 s) around 0.3 s less the mouth's lead, open (D,
    // 0.4-0.8 s) around 0.6 s, rest before 0.1 s.
    const double lead = speech.Coarticulation.Lead;
    const int pp = u.Visemes.FindChannel("PP");
    const int aa = u.Visemes.FindChannel("aa");
    ASSERT_GE(pp, 0);
    ASSERT_GE(aa, 0);
    EXPECT_GT(u.Visemes.Sample(0.3 - lead, static_cast<size_t>(pp)), 0.99) << file;
    EXPECT_GT(u.Visemes.Sample(0.6 - lead, static_cast<size_t>(aa)), 0.5) << file;
    EXPECT_LT(u.Visemes.Sample(0.6 - lead, static_cast<size_t>(pp)), 0.1) << file;
    EXPECT_LT(u.Visemes.Sample(0.05, static_cast<size_t>(aa)), 0.1) << file;
  }
  // Without the format, an unknown extension and XML content still tells (<rhubarbResult).
  RecordingOptions guessed;
  guessed.TimingFile = unnamed;
  EXPECT_NO_THROW(SpeakRecording(audio, speech, guessed));
}

// Timings in memory (inline in a dialog command) time the recording as their file does, and
// the recording read from its bytes (libsndfile's virtual I/O) sounds as the file does.
TEST(RecordingSpeech, InlineTimingsAndAudioLikeTheirFiles)
{
  AudioBuffer audio;
  audio.SampleRate = 16000;
  audio.Channels = 1;
  for (size_t i = 0; i < 16000; ++i)
  {
    audio.Samples.push_back(i >= 4800 && i < 12800 ? 0.25f * std::sin(0.0864f * i) : 0.0f);
  }
  const std::string wav = Output + "/inline_recording.wav";
  const std::string marks = Output + "/inline_recording.marks";
  WriteWavFile(wav, audio);
  const std::string text = "{\"time\":0,\"type\":\"viseme\",\"value\":\"sil\"}\n"
                           "{\"time\":300,\"type\":\"viseme\",\"value\":\"p\"}\n"
                           "{\"time\":450,\"type\":\"viseme\",\"value\":\"a\"}\n"
                           "{\"time\":800,\"type\":\"viseme\",\"value\":\"sil\"}\n";
  std::ofstream(marks) << text;
  SpeechOptions speech;
  RecordingOptions fromFile;
  fromFile.TimingFile = marks;
  RecordingOptions inMemory;
  inMemory.TimingData = text;
  RecordingReport report;
  const Utterance a = SpeakAudioFile(wav, speech, fromFile);
  const Utterance b = SpeakRecording(
    ReadAudioMemory(text::ReadFile(wav, "test"), "bytes"), speech, inMemory, &report);
  EXPECT_EQ(report.Route, RecordingRoute::TimingFile);
  EXPECT_EQ(a.Audio, b.Audio);
  ASSERT_EQ(a.Phonemes.size(), b.Phonemes.size());
  for (size_t k = 0; k < a.Phonemes.size(); ++k)
  {
    EXPECT_EQ(a.Phonemes[k].Sampa, b.Phonemes[k].Sampa);
    EXPECT_DOUBLE_EQ(a.Phonemes[k].Start, b.Phonemes[k].Start);
  }
  const int pp = b.Visemes.FindChannel("PP");
  ASSERT_GE(pp, 0);
  EXPECT_GT(b.Visemes.Sample(0.375 - speech.Coarticulation.Lead, static_cast<size_t>(pp)), 0.5);
  // Inline timings that tell no format: the message names them and the dialog field.
  inMemory.TimingData = "no timings here";
  const std::string error = ErrorOf([&] { SpeakRecording(audio, speech, inMemory); });
  EXPECT_NE(error.find("'inline timings': cannot tell the timing format"), std::string::npos)
    << error;
  EXPECT_NE(error.find("'timings_format'"), std::string::npos) << error;
}

// The transcript check on short real recordings (pocketsphinx-testdata's cards, 1.1 to
// 3.5 s, one speaker far from eSpeak's voice): no warning for any recording's own
// transcript, a warning (or the tempo's "does not match" error) for every other
// recording's transcript and for an unrelated sentence. The alignment score alone warns
// on 3 of the 5 right ones (no threshold separates); the acoustic check is relative to
// what the audio supports (docs/speech.md).
TEST(TranscriptAlignment, TranscriptCheckOnShortRealRecordings)
{
  if (!IsTranscriptAlignmentAvailable() || !IsPhonemeRecognitionAvailable())
  {
    GTEST_SKIP() << "needs eSpeak NG and PocketSphinx";
  }
  const std::string cards = "/usr/share/pocketsphinx/test/data/cards/";
  if (!std::filesystem::exists(cards + "001.wav"))
  {
    GTEST_SKIP() << "pocketsphinx-testdata is not installed (" << cards << ")";
  }
  // cards.transcription
  const std::vector<std::string> transcripts = { "ten of clubs", "four queen of clubs",
    "seven of clubs", "five five", "eight of spades four of clubs seven of hearts",
    "the weather is nice today" };
  size_t right = 0, wrong = 0;
  for (size_t r = 0; r < 5; ++r)
  {
    const AudioBuffer audio = ReadAudioFile(cards + "00" + std::to_string(r + 1) + ".wav");
    for (size_t t = 0; t < transcripts.size(); ++t)
    {
      std::vector<std::string> warnings;
      TranscriptAlignOptions options;
      options.Warn = CollectWarnings(warnings);
      std::string error;
      TranscriptAlignment a;
      try
      {
        a = AlignTranscript(audio, transcripts[t], options);
      }
      catch (const InputError& e)
      {
        error = e.what();
      }
      const std::string what = "recording " + std::to_string(r + 1) + " with '" + transcripts[t] +
        "': score " + std::to_string(a.Score) + ", fit ratio " + std::to_string(a.FitRatio) + " " +
        error + (warnings.empty() ? "" : warnings[0]);
      if (t == r)
      {
        EXPECT_TRUE(error.empty() && warnings.empty() && a.Reliable) << what;
        EXPECT_LE(a.FitRatio, options.MaximumFitRatio) << what; // the check ran
        right += error.empty() && warnings.empty();
        continue;
      }
      const bool refused = error.find("does not match") != std::string::npos;
      const bool warned = warnings.size() == 1 && !a.Reliable &&
        warnings[0].find("the transcript may not match the recording") != std::string::npos &&
        warnings[0].find("timed by aligning this transcript") != std::string::npos;
      EXPECT_TRUE(refused || warned) << what;
      wrong += refused || warned;
    }
  }
  EXPECT_EQ(right, 5u);
  EXPECT_EQ(wrong, 25u);
}
