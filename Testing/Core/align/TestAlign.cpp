// SPDX-License-Identifier: BSD-3-Clause
// The align concept: MFCC features, DTW, and the transcript route (eSpeak NG synthesis of
// the transcript warped onto a recording), with its negative control and bad inputs.
#include "align/Dtw.h"
#include "align/Mfcc.h"
#include "align/TranscriptAligner.h"
#include "audio/Resample.h"
#include "base/Error.h"
#include "speech/Sampa.h"
#include "speech/SpeechSynthesizer.h"
#include "speech/VisemeMap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace morphnode;

namespace
{
const double Pi = 3.14159265358979323846;

AudioBuffer Tone(double hz, int rate, double seconds, double amplitude = 0.3)
{
  AudioBuffer a;
  a.SampleRate = rate;
  a.Channels = 1;
  for (size_t i = 0; i < static_cast<size_t>(seconds * rate); ++i)
  {
    a.Samples.push_back(static_cast<float>(amplitude * std::sin(2 * Pi * hz * i / rate)));
  }
  return a;
}

#define SKIP_WITHOUT_ESPEAK()                                                                      \
  if (!IsTranscriptAlignmentAvailable())                                                           \
  {                                                                                                \
    GTEST_SKIP() << "built without eSpeak NG (MORPHNODE_ENABLE_ESPEAK=OFF)";                       \
  }

/// Boundary errors of phonemes matched in order by name (the first phoneme excluded).
std::vector<double> BoundaryErrors(
  const std::vector<TimedPhoneme>& truth, const std::vector<TimedPhoneme>& test)
{
  std::vector<double> errors;
  size_t j = 0;
  for (size_t i = 1; i < truth.size(); ++i)
  {
    for (size_t k = j; k < test.size() && k < j + 4; ++k)
    {
      if (test[k].Sampa == truth[i].Sampa)
      {
        errors.push_back(std::abs(test[k].Start - truth[i].Start));
        j = k + 1;
        break;
      }
    }
  }
  return errors;
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.empty() ? INFINITY : v[v.size() / 2];
}

size_t Covering(const std::vector<TimedPhoneme>& p, double t)
{
  size_t k = 0;
  while (k + 1 < p.size() && p[k + 1].Start <= t)
  {
    ++k;
  }
  return k;
}

double Agreement(
  const std::vector<TimedPhoneme>& truth, const std::vector<TimedPhoneme>& test, double duration)
{
  const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, "en");
  size_t same = 0, total = 0;
  for (double t = 0.005; t < duration; t += 0.01, ++total)
  {
    same += map.MapPhoneme(truth[Covering(truth, t)].Sampa) ==
      map.MapPhoneme(test[Covering(test, t)].Sampa);
  }
  return static_cast<double>(same) / total;
}

const char* Sentence =
  "My mother bought five fresh apples, and we ate them all in the warm kitchen.";

/// A "recording": another eSpeak voice, slower, higher, at 44.1 kHz stereo with some noise.
struct Recording
{
  SynthesisResult Truth;
  AudioBuffer Audio;
};

Recording MakeRecording(const std::string& voice, int rate, int pitch)
{
  SpeechSynthesizer speaker(voice, rate);
  speaker.SetPitch(pitch);
  speaker.SetEstimatePitch(false);
  Recording r;
  r.Truth = speaker.Synthesize(Sentence);
  const AudioBuffer mono = Resample(FromInt16Mono(r.Truth.Audio, r.Truth.SampleRate), 44100);
  std::mt19937 random(7);
  std::normal_distribution<float> noise(0.0f, 0.003f);
  r.Audio.SampleRate = 44100;
  r.Audio.Channels = 2;
  for (float s : mono.Samples)
  {
    r.Audio.Samples.push_back(s + noise(random));
    r.Audio.Samples.push_back(0.8f * s + noise(random));
  }
  return r;
}
} // namespace

TEST(Mfcc, FramesAndSpectralShape)
{
  const MfccFeatures low = ComputeMfcc(Tone(300, 22050, 1.0));
  // 16 kHz, 25 ms windows every 10 ms: 1 + (16000 - 400) / 160 frames.
  EXPECT_EQ(low.Frames, 1u + (16000u - 400u) / 160u);
  EXPECT_EQ(low.Dimension, 13);
  EXPECT_NEAR(low.FrameTime(0), 0.0125, 1e-9);
  const MfccFeatures high = ComputeMfcc(Tone(3000, 22050, 1.0));
  // Different tones give clearly different cepstra; the same tone the same ones.
  double differ = 0.0, same = 0.0;
  for (int k = 1; k < 13; ++k)
  {
    differ += std::abs(low.Row(50)[k] - high.Row(50)[k]);
    same += std::abs(low.Row(50)[k] - low.Row(60)[k]);
  }
  EXPECT_GT(differ, 10.0 * same + 1.0);
  // A quieter tone: lower log energy by the power ratio (20 dB -> ln(100)).
  const MfccFeatures quiet = ComputeMfcc(Tone(300, 22050, 1.0, 0.03));
  EXPECT_NEAR(low.LogEnergy[50] - quiet.LogEnergy[50], std::log(100.0), 0.05);
  EXPECT_EQ(ComputeMfcc(Tone(300, 16000, 0.01)).Frames, 0u); // shorter than a frame
  MfccOptions bad;
  bad.Coefficients = 40;
  EXPECT_THROW(ComputeMfcc(Tone(300, 16000, 0.5), bad), InputError);
}

TEST(Dtw, RecoversAKnownWarpAtEveryScale)
{
  // B is A played at 1.5x the length: row j of B matches row j / 1.5 of A.
  FeatureMatrix a, b;
  a.Dimension = b.Dimension = 2;
  a.Rows = 400;
  b.Rows = 600;
  auto shape = [](double x) {
    return std::vector<float>{ float(std::sin(x / 17.0)), float(std::cos(x / 5.0)) };
  };
  for (size_t i = 0; i < a.Rows; ++i)
  {
    const auto v = shape(static_cast<double>(i));
    a.Values.insert(a.Values.end(), v.begin(), v.end());
  }
  for (size_t j = 0; j < b.Rows; ++j)
  {
    const auto v = shape(static_cast<double>(j) / 1.5);
    b.Values.insert(b.Values.end(), v.begin(), v.end());
  }
  for (size_t maximumCells : { size_t(1) << 30, size_t(20000) })
  {
    DtwOptions options;
    options.MaximumCells = maximumCells; // the second forces three coarse levels
    const DtwResult r = AlignFeatures(a, b, {}, {}, options);
    ASSERT_EQ(r.Path.front(), std::make_pair(size_t(0), size_t(0)));
    ASSERT_EQ(r.Path.back(), std::make_pair(a.Rows - 1, b.Rows - 1));
    double worst = 0.0;
    for (size_t k = 1; k < r.Path.size(); ++k)
    {
      EXPECT_GE(r.Path[k].first, r.Path[k - 1].first);
      EXPECT_GE(r.Path[k].second, r.Path[k - 1].second);
      worst =
        std::max(worst, std::abs(static_cast<double>(r.Path[k].second) / 1.5 - r.Path[k].first));
    }
    EXPECT_LT(worst, 3.0) << "cells " << maximumCells;
    if (maximumCells < 1000000)
    {
      EXPECT_LT(r.CellsEvaluated, a.Rows * b.Rows / 3); // windows, not the whole matrix
    }
  }
}

TEST(Dtw, SlopeConstraintAndSilence)
{
  // A 3:1 length ratio cannot be matched within slopes 1/2..2 unless silence may stretch.
  FeatureMatrix a, b;
  a.Dimension = b.Dimension = 1;
  a.Rows = 10;
  b.Rows = 30;
  a.Values.assign(10, 1.0f);
  b.Values.assign(30, 1.0f);
  EXPECT_THROW(AlignFeatures(a, b, {}, {}), InputError);
  std::vector<bool> silentB(30, true);
  EXPECT_NO_THROW(AlignFeatures(a, b, {}, silentB));
  DtwOptions free;
  free.SlopeConstraint = false;
  EXPECT_NO_THROW(AlignFeatures(a, b, {}, {}, free));
  FeatureMatrix empty;
  empty.Dimension = 1;
  EXPECT_THROW(AlignFeatures(empty, b, {}, {}), InputError);
  EXPECT_THROW(AlignFeatures(a, b, std::vector<bool>(3), {}), InputError);
}

TEST(TranscriptAlignment, AnotherVoiceAndRateIsTimedWithinTwentyMilliseconds)
{
  SKIP_WITHOUT_ESPEAK();
  const Recording r = MakeRecording("en+f2", 135, 75);
  std::vector<double> progress;
  TranscriptAlignOptions options;
  options.Voice = "en";
  options.Progress = [&progress](double f)
  {
    progress.push_back(f);
    return true;
  };
  const TranscriptAlignment a = AlignTranscript(r.Audio, Sentence, options);
  EXPECT_TRUE(a.Reliable);
  EXPECT_NEAR(a.Duration, r.Truth.Duration, 0.01);
  EXPECT_LT(a.SynthesisRate, 160); // adapted to the slower recording
  const std::vector<double> errors = BoundaryErrors(r.Truth.Phonemes, a.Phonemes);
  EXPECT_GT(errors.size(), r.Truth.Phonemes.size() * 8 / 10);
  EXPECT_LT(Median(errors), 0.020);
  EXPECT_GT(Agreement(r.Truth.Phonemes, a.Phonemes, r.Truth.Duration), 0.85);
  // The phonemes tile the recording.
  EXPECT_EQ(a.Phonemes.front().Start, 0.0);
  for (size_t k = 1; k < a.Phonemes.size(); ++k)
  {
    EXPECT_NEAR(a.Phonemes[k].Start, a.Phonemes[k - 1].Start + a.Phonemes[k - 1].Duration, 1e-9);
  }
  EXPECT_NEAR(a.Phonemes.back().Start + a.Phonemes.back().Duration, a.Duration, 1e-9);
  // Words in order, in the transcript's order (eSpeak may join a function word to the
  // next, "in the"), the first and last ones right.
  ASSERT_GE(a.Words.size(), 13u);
  EXPECT_EQ(a.Words.front().Text, "My");
  EXPECT_EQ(a.Words.back().Text, "kitchen");
  const std::string sentence = Sentence;
  size_t at = 0;
  for (size_t k = 0; k < a.Words.size(); ++k)
  {
    at = sentence.find(a.Words[k].Text, at);
    EXPECT_NE(at, std::string::npos) << a.Words[k].Text;
    EXPECT_GE(a.Words[k].Start, k > 0 ? a.Words[k - 1].Start : 0.0);
  }
  // The word "five" starts where the truth's /f aI v/ does.
  const auto five = std::find_if(
    a.Words.begin(), a.Words.end(), [](const SynthesizedWord& w) { return w.Text == "five"; });
  ASSERT_NE(five, a.Words.end());
  for (size_t k = 0; k + 2 < r.Truth.Phonemes.size(); ++k)
  {
    if (r.Truth.Phonemes[k].Sampa == "f" && r.Truth.Phonemes[k + 1].Sampa == "aI")
    {
      EXPECT_NEAR(five->Start, r.Truth.Phonemes[k].Start, 0.03);
      break;
    }
  }
  // Progress from 0 to 1, never backwards.
  ASSERT_GE(progress.size(), 3u);
  EXPECT_EQ(progress.front(), 0.0);
  EXPECT_EQ(progress.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
}

TEST(TranscriptAlignment, GermanToo)
{
  SKIP_WITHOUT_ESPEAK();
  SpeechSynthesizer speaker("de+m3", 200);
  speaker.SetEstimatePitch(false);
  const char* text = "Die alten Bäume im Park verlieren im Herbst ihre bunten Blätter.";
  const SynthesisResult truth = speaker.Synthesize(text);
  TranscriptAlignOptions options;
  options.Voice = "de";
  const TranscriptAlignment a =
    AlignTranscript(FromInt16Mono(truth.Audio, truth.SampleRate), text, options);
  EXPECT_LT(Median(BoundaryErrors(truth.Phonemes, a.Phonemes)), 0.020);
}

TEST(TranscriptAlignment, ShuffledTranscriptScoresClearlyWorse)
{
  SKIP_WITHOUT_ESPEAK();
  // The negative control: the same recording, the transcript's words in another order.
  const Recording r = MakeRecording("en+m3", 160, 40);
  TranscriptAlignOptions options;
  std::vector<std::string> warnings;
  options.Warn = CollectWarnings(warnings);
  const TranscriptAlignment right = AlignTranscript(r.Audio, Sentence, options);
  const TranscriptAlignment wrong = AlignTranscript(r.Audio,
    "kitchen warm the in all them ate we and apples, fresh five bought mother My.", options);
  EXPECT_GT(right.Score, wrong.Score + 0.15) << right.Score << " vs " << wrong.Score;
  EXPECT_TRUE(right.Reliable);
  EXPECT_FALSE(wrong.Reliable);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("may not match"), std::string::npos);
  const double good = Agreement(r.Truth.Phonemes, right.Phonemes, r.Truth.Duration);
  const double bad = Agreement(r.Truth.Phonemes, wrong.Phonemes, r.Truth.Duration);
  EXPECT_GT(good, bad + 0.3) << good << " vs " << bad;
}

TEST(TranscriptAlignment, BadInputsAreClearErrors)
{
  SKIP_WITHOUT_ESPEAK();
  const Recording r = MakeRecording("en", 175, 50);
  auto error = [](const AudioBuffer& audio, const std::string& text, TranscriptAlignOptions o = {})
  {
    try
    {
      AlignTranscript(audio, text, o);
    }
    catch (const InputError& e)
    {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(error(AudioBuffer{}, Sentence).find("empty"), std::string::npos);
  EXPECT_NE(error(r.Audio, "   ").find("transcript is empty"), std::string::npos);
  AudioBuffer silence;
  silence.SampleRate = 16000;
  silence.Channels = 1;
  silence.Samples.assign(32000, 0.0f);
  EXPECT_NE(error(silence, Sentence).find("no speech"), std::string::npos);
  AudioBuffer noise = silence;
  std::mt19937 random(3);
  std::normal_distribution<float> gauss(0.0f, 0.1f);
  for (float& s : noise.Samples)
  {
    s = gauss(random);
  }
  EXPECT_NE(error(noise, Sentence).find("no speech"), std::string::npos);
  // A transcript far longer than the speech: refused, not stretched into nonsense.
  std::string longText;
  for (int i = 0; i < 6; ++i)
  {
    longText += std::string(Sentence) + " ";
  }
  EXPECT_NE(error(r.Audio, longText).find("does not match"), std::string::npos);
  TranscriptAlignOptions unknownVoice;
  unknownVoice.Voice = "no-such-voice";
  EXPECT_NE(error(r.Audio, Sentence, unknownVoice).find("no-such-voice"), std::string::npos);
  TranscriptAlignOptions cancel;
  cancel.Progress = [](double f) { return f < 0.5; };
  EXPECT_NE(error(r.Audio, Sentence, cancel).find("cancelled"), std::string::npos);
}
