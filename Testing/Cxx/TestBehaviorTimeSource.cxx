// SPDX-License-Identifier: BSD-3-Clause
// vtkBehaviorTimeSource: time information through the morph filter, weights equal to the
// core's samples, reproducibility, commands and scripts, errors, pipeline economy, speech.
#include "vtkBehaviorTimeSource.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestUtilities.h"

#include "audio/AudioFile.h"
#include "base/Error.h"
#include "behavior/BehaviorAudio.h"
#include "behavior/BehaviorController.h"
#include "speech/Pho.h"
#include "speech/Rhubarb.h"
#include "speech/Speech.h"
#include "speech/TimingFiles.h"

#include "MorphNodeTestSkips.h"
#include "vtkCallbackCommand.h"
#include "vtkDelimitedTextWriter.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkInformation.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using morphnode_test::MessageCollector;

namespace
{
const std::string SourceDir = MORPHNODE_SOURCE_DIR;
const std::string OutputDir = MORPHNODE_TEST_OUTPUT_DIR;
const std::string DefaultFace = SourceDir + "/Data/DefaultFace/default_head.glb";
const std::string Corpus = SourceDir + "/Testing/Fuzz/corpus/";

/// The same commands on the VTK source and on a core controller.
template <typename Behavior>
void Greet(Behavior& b)
{
  b.SetSeed(7);
  b.SetMood("happy", 0.6, 0.0);
  b.Gesture("nod", 1.0, 0.8, 0.7);
  b.Gesture("raise_brows", 2.0, 1.0, 0.9);
  b.LookAt(15.0, 5.0, 2.5, 1.0);
  b.SetMood("sad", 0.8, 3.0);
}

double Value(vtkTable* table, const char* column, vtkIdType row = 0)
{
  auto* array = vtkDoubleArray::SafeDownCast(table->GetColumnByName(column));
  EXPECT_NE(array, nullptr) << "no column " << column;
  return array ? array->GetValue(row) : std::nan("");
}

/// The one-row table of port 0 at time t.
vtkTable* At(vtkBehaviorTimeSource* source, double t)
{
  source->UpdateTimeStep(t);
  return vtkTable::SafeDownCast(source->GetOutputDataObject(0));
}

vtkTable* Track(vtkBehaviorTimeSource* source)
{
  source->Update(1);
  return vtkTable::SafeDownCast(source->GetOutputDataObject(1));
}

struct Face
{
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkBehaviorTimeSource> Behavior;
  vtkNew<MessageCollector> Messages;
  Face()
  {
    this->Reader->SetFileName(DefaultFace.c_str());
    this->Reader->SetMeshIndex(
      0); // the head's skin (mesh 0, every Table 1 target), one vtkPolyData
    this->Morph->SetInputConnection(this->Reader->GetOutputPort());
    this->Morph->SetWeightsConnection(this->Behavior->GetOutputPort(0));
    this->Messages->Watch(this->Morph);
    this->Messages->Watch(this->Behavior);
    this->Messages->Watch(this->Reader);
  }
};

/// Counts executions (RequestData) of an algorithm.
struct ExecutionCounter
{
  int Count = 0;
  vtkNew<vtkCallbackCommand> Callback;
  explicit ExecutionCounter(vtkAlgorithm* algorithm)
  {
    this->Callback->SetClientData(this);
    this->Callback->SetCallback([](vtkObject*, unsigned long, void* self, void*)
      { ++static_cast<ExecutionCounter*>(self)->Count; });
    algorithm->AddObserver(vtkCommand::StartEvent, this->Callback);
  }
};

/// The options of the source's speech commands with its default settings.
morphnode::SpeechOptions PaperOptions()
{
  morphnode::SpeechOptions options;
  options.Voice = "en";
  options.Visemes = morphnode::VisemeSet::Paper6;
  return options;
}

/// Port 1 of the source equals the core controller's SampleTrack(), bit for bit.
void ExpectTrackEqualsCore(vtkBehaviorTimeSource* source, morphnode::BehaviorController& core)
{
  core.Prepare();
  const morphnode::WeightTrack expected = core.SampleTrack();
  vtkTable* track = Track(source);
  ASSERT_EQ(track->GetNumberOfRows(), static_cast<vtkIdType>(expected.GetNumberOfFrames()));
  ASSERT_EQ(
    track->GetNumberOfColumns(), static_cast<vtkIdType>(expected.GetNumberOfChannels() + 1));
  for (size_t c = 0; c < expected.GetNumberOfChannels(); ++c)
  {
    auto* column = vtkDoubleArray::SafeDownCast(track->GetColumn(static_cast<vtkIdType>(c + 1)));
    ASSERT_NE(column, nullptr);
    ASSERT_EQ(std::string(column->GetName()), expected.GetChannels()[c]);
    for (size_t f = 0; f < expected.GetNumberOfFrames(); ++f)
    {
      ASSERT_EQ(column->GetValue(static_cast<vtkIdType>(f)), expected.GetValue(f, c))
        << expected.GetChannels()[c] << " at frame " << f;
    }
  }
}

/// The largest value of a column of the track over [from, to] seconds.
double Peak(vtkTable* track, const char* column, double from = 0.0, double to = 1e9)
{
  double peak = 0.0;
  for (vtkIdType r = 0; r < track->GetNumberOfRows(); ++r)
  {
    const double t = Value(track, "Time", r);
    if (t >= from && t <= to)
    {
      peak = std::max(peak, Value(track, column, r));
    }
  }
  return peak;
}

/// A WAV file as 16-bit mono samples (audio/AudioFile.h reads it); empty when unreadable.
struct Wav
{
  int SampleRate = 0;
  std::vector<int16_t> Samples;
};
Wav ReadWav(const std::string& path)
{
  Wav wav;
  try
  {
    const morphnode::AudioBuffer audio = morphnode::ReadAudioFile(path);
    wav.SampleRate = audio.SampleRate;
    wav.Samples = morphnode::ToInt16Mono(audio);
  }
  catch (const morphnode::InputError& e)
  {
    ADD_FAILURE() << e.what();
  }
  return wav;
}
} // namespace

TEST(BehaviorTimeSource, ChannelsAndOutputs)
{
  vtkNew<vtkBehaviorTimeSource> source;
  EXPECT_EQ(source->GetNumberOfInputPorts(), 0);
  EXPECT_EQ(source->GetNumberOfOutputPorts(), 2);
  ASSERT_EQ(source->GetNumberOfChannels(), 15);
  EXPECT_STREQ(source->GetChannelName(0), "EyesClosed");
  EXPECT_STREQ(source->GetChannelName(1), "BrowsUp");
  EXPECT_STREQ(source->GetChannelName(10), "HeadYaw");
  EXPECT_STREQ(source->GetChannelName(14), "EyePitch");
  EXPECT_EQ(source->GetChannelIndex("HeadRoll"), 12);
  EXPECT_EQ(source->GetChannelIndex("Nope"), -1);
  EXPECT_STREQ(source->GetVisemeSetAsString(), "paper6");
  std::ostringstream printed;
  source->Print(printed);
  EXPECT_NE(printed.str().find("VisemeSet: paper6"), std::string::npos) << printed.str();
  EXPECT_NE(printed.str().find("Channels: EyesClosed BrowsUp"), std::string::npos) << printed.str();

  vtkTable* frame = At(source, 1.0);
  ASSERT_EQ(frame->GetNumberOfColumns(), 15);
  EXPECT_EQ(frame->GetNumberOfRows(), 1);
  for (int c = 0; c < 15; ++c)
  {
    EXPECT_STREQ(frame->GetColumn(c)->GetName(), source->GetChannelName(c));
    EXPECT_TRUE(vtkDoubleArray::SafeDownCast(frame->GetColumn(c)));
  }
  EXPECT_EQ(frame->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 1.0);

  // Default duration: at least 5 s; 30 fps -> 151 frames.
  EXPECT_DOUBLE_EQ(source->GetEffectiveDuration(), 5.0);
  vtkTable* track = Track(source);
  ASSERT_EQ(track->GetNumberOfColumns(), 16);
  EXPECT_STREQ(track->GetColumn(0)->GetName(), "Time");
  EXPECT_STREQ(track->GetColumn(1)->GetName(), "EyesClosed");
  ASSERT_EQ(track->GetNumberOfRows(), 151);
  EXPECT_DOUBLE_EQ(Value(track, "Time", 30), 1.0);
  // The track's frame at t = 1 s is the table of port 0 at t = 1 s.
  for (int c = 0; c < 15; ++c)
  {
    EXPECT_EQ(vtkDoubleArray::SafeDownCast(track->GetColumn(c + 1))->GetValue(30),
      Value(At(source, 1.0), source->GetChannelName(c)))
      << source->GetChannelName(c);
  }

  // The track exports as CSV.
  vtkNew<vtkDelimitedTextWriter> csv;
  const std::string csvPath = OutputDir + "/TestBehaviorTimeSource_track.csv";
  csv->SetFileName(csvPath.c_str());
  csv->SetInputConnection(source->GetOutputPort(1));
  ASSERT_EQ(csv->Write(), 1);
  std::ifstream in(csvPath);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("\"Time\",\"EyesClosed\",\"BrowsUp\"", 0), 0u) << header;
  int lines = 0;
  for (std::string line; std::getline(in, line);)
  {
    ++lines;
  }
  EXPECT_EQ(lines, 151);
}

TEST(BehaviorTimeSource, TimeStepsVisibleDownstreamOfTheMorphFilter)
{
  Face face;
  face.Behavior->SetFrameRate(25.0);
  face.Behavior->SetDuration(4.0);
  face.Morph->UpdateInformation();
  vtkInformation* info = face.Morph->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 101);
  const double* steps = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  EXPECT_EQ(steps[0], 0.0);
  EXPECT_DOUBLE_EQ(steps[1], 0.04);
  EXPECT_DOUBLE_EQ(steps[100], 4.0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()));
  const double* range = info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 4.0);

  // A command that lengthens the automatic duration changes the steps downstream.
  face.Behavior->SetDuration(0.0);
  face.Behavior->Gesture("nod", 9.0);
  face.Morph->UpdateInformation();
  range = info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  EXPECT_NEAR(range[1], 9.0 + 0.8 + 1.0, 1e-9);
  EXPECT_TRUE(face.Messages->Errors.empty()) << face.Messages->AllErrors();
}

TEST(BehaviorTimeSource, MorphFilterAtTimeTShowsTheCoreSampleAtT)
{
  Face face;
  Greet(*face.Behavior);
  face.Morph->SetWeightModeToRelative(); // effective weight of a target = its channel
  morphnode::BehaviorController core;
  Greet(core);
  core.Prepare();
  std::vector<double> expected(core.GetNumberOfChannels());

  vtkNew<vtkPoints> first;
  double largestMotion = 0.0;
  for (double t : { 0.0, 0.37, 1.4, 2.2, 2.75, 3.9, 4.25 })
  {
    face.Morph->UpdateTimeStep(t);
    auto* out = vtkPointSet::SafeDownCast(face.Morph->GetOutputDataObject(0));
    ASSERT_NE(out, nullptr);
    ASSERT_GT(out->GetNumberOfPoints(), 0);
    EXPECT_EQ(out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), t);
    core.Sample(t, expected);

    // The source's table is the core's sample, bit for bit.
    auto* table = vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(0));
    ASSERT_EQ(table->GetNumberOfColumns(), static_cast<vtkIdType>(expected.size()));
    for (size_t c = 0; c < expected.size(); ++c)
    {
      EXPECT_EQ(Value(table, core.GetChannelNames()[c].c_str()), expected[c])
        << core.GetChannelNames()[c] << " at t = " << t;
    }
    // The morph filter used them: each target's effective weight is its channel.
    const int n = face.Morph->GetNumberOfTargets();
    ASSERT_EQ(n, 13);
    double sum = 0.0;
    for (int k = 1; k < n; ++k)
    {
      const int c = core.FindChannel(face.Morph->GetTargetName(k));
      const double w = c < 0 ? 0.0 : expected[static_cast<size_t>(c)];
      EXPECT_NEAR(face.Morph->GetEffectiveWeight(k), w, 1e-12)
        << face.Morph->GetTargetName(k) << " at t = " << t;
      sum += w;
    }
    EXPECT_NEAR(face.Morph->GetEffectiveWeight(0), 1.0 - sum, 1e-12);
    if (t == 0.0)
    {
      first->DeepCopy(out->GetPoints());
    }
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      double p[3], q[3];
      out->GetPoint(i, p);
      first->GetPoint(i, q);
      largestMotion = std::max(
        largestMotion, std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]));
    }
  }
  EXPECT_GT(largestMotion, 1e-3) << "the face never moved";
  EXPECT_TRUE(face.Messages->Errors.empty()) << face.Messages->AllErrors();
}

TEST(BehaviorTimeSource, SameSeedSameTrackOtherSeedDifferent)
{
  vtkNew<vtkBehaviorTimeSource> a, b, c;
  for (vtkBehaviorTimeSource* s : { a.Get(), b.Get(), c.Get() })
  {
    s->SetDuration(20.0);
    s->SetSeed(11);
    s->Gesture("smile", 2.0);
  }
  c->SetSeed(12);
  vtkTable* ta = Track(a);
  vtkTable* tb = Track(b);
  vtkTable* tc = Track(c);
  ASSERT_EQ(ta->GetNumberOfRows(), 601);
  ASSERT_EQ(tb->GetNumberOfRows(), ta->GetNumberOfRows());
  ASSERT_EQ(tc->GetNumberOfRows(), ta->GetNumberOfRows());
  bool identical = true;
  double difference = 0.0;
  for (vtkIdType col = 0; col < ta->GetNumberOfColumns(); ++col)
  {
    auto* ca = vtkDoubleArray::SafeDownCast(ta->GetColumn(col));
    auto* cb = vtkDoubleArray::SafeDownCast(tb->GetColumn(col));
    auto* cc = vtkDoubleArray::SafeDownCast(tc->GetColumn(col));
    for (vtkIdType r = 0; r < ta->GetNumberOfRows(); ++r)
    {
      identical = identical && ca->GetValue(r) == cb->GetValue(r);
      difference += std::abs(ca->GetValue(r) - cc->GetValue(r));
    }
  }
  EXPECT_TRUE(identical);
  EXPECT_GT(difference, 1.0);
  // The blink channel differs (blink times are per seed).
  double blinkDifference = 0.0;
  for (vtkIdType r = 0; r < ta->GetNumberOfRows(); ++r)
  {
    blinkDifference += std::abs(Value(ta, "EyesClosed", r) - Value(tc, "EyesClosed", r));
  }
  EXPECT_GT(blinkDifference, 0.5);
}

TEST(BehaviorTimeSource, GestureAndMoodVisibleAtTheirTime)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  source->SetSeed(3);
  ASSERT_TRUE(source->Gesture("nod", 2.0, 1.0, 1.0));
  ASSERT_TRUE(source->Gesture("frown", 5.0, 1.5, 0.8));
  ASSERT_TRUE(source->SetMood("sad", 1.0, 7.0));
  ASSERT_TRUE(source->LookAt(20.0, 0.0, 9.0, 1.0));

  // A 1 s nod has two nods (k = round(1 / 0.5)): -10 deg at u = 0.25 and 0.75.
  EXPECT_LT(Value(At(source, 2.25), "HeadPitch"), -7.0);
  EXPECT_LT(std::abs(Value(At(source, 1.5), "HeadPitch")), 2.0); // idle micro-motion only
  EXPECT_NEAR(Value(At(source, 5.75), "BrowsAngry"), 0.8, 1e-9); // in the hold
  EXPECT_EQ(Value(At(source, 4.9), "BrowsAngry"), 0.0);
  EXPECT_EQ(Value(At(source, 6.9), "MouthSad"), 0.0);
  EXPECT_NEAR(Value(At(source, 8.5), "MouthSad"), 0.7, 1e-9); // sad mood: MouthSad 0.7
  EXPECT_GT(Value(At(source, 9.5), "HeadYaw"), 5.0);          // the head takes 40 % of 20 deg
  EXPECT_GT(Value(At(source, 9.5), "LookLeft"), 0.2);

  // The same in the track, at the frames of those times (30 fps).
  vtkTable* track = Track(source);
  EXPECT_LT(Value(track, "HeadPitch", 2 * 30 + 7), -6.0); // t = 2.233
  EXPECT_NEAR(Value(track, "BrowsAngry", 5 * 30 + 22), 0.8, 1e-9);
  EXPECT_NEAR(Value(track, "MouthSad", 8 * 30 + 15), 0.7, 1e-9);
  EXPECT_EQ(Value(track, "MouthSad", 6 * 30 + 27), 0.0);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
}

TEST(BehaviorTimeSource, BadCommandsAndScriptsAreErrorsNotCrashes)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  const vtkMTimeType before = source->GetMTime();

  EXPECT_FALSE(source->Gesture("wiggle", 1.0));
  EXPECT_TRUE(messages->HasError("wiggle")) << messages->AllErrors();
  EXPECT_FALSE(source->Gesture("nod", 1.0, 0.5, 2.0)); // intensity out of [0, 1]
  EXPECT_FALSE(source->SetMood("grumpy", 0.5));
  EXPECT_FALSE(source->LookAt(200.0, 0.0, 1.0));
  EXPECT_FALSE(source->Gesture(nullptr, 1.0));
  EXPECT_FALSE(source->SpeakPhonemeFile("/nonexistent/file.pho"));
  EXPECT_FALSE(source->LoadScript("/nonexistent/script.txt"));
  messages->Clear();
  source->SetFrameRate(-5.0);
  EXPECT_EQ(source->GetFrameRate(), 30.0);
  source->SetDuration(std::nan(""));
  EXPECT_EQ(source->GetDuration(), 0.0);
  source->SetVisemeSet(7);
  EXPECT_EQ(source->GetVisemeSet(), vtkBehaviorTimeSource::PAPER6);
  EXPECT_FALSE(source->SetVisemeSetFromString("klingon"));
  EXPECT_EQ(messages->Errors.size(), 4u) << messages->AllErrors();
  EXPECT_EQ(source->GetMTime(), before) << "a rejected command modified the source";

  // A malformed script: rejected whole, with the line number.
  const std::string path = OutputDir + "/TestBehaviorTimeSource_bad.txt";
  {
    std::ofstream script(path);
    script << "seed 5\n"
              "at 0.5 gesture smile\n"
              "# a comment\n"
              "at 1.0 gesture nod duration 0.8 intensity 0.6\n"
              "at 2.0 gesture nod intensity lots\n";
  }
  messages->Clear();
  EXPECT_FALSE(source->LoadScript(path.c_str()));
  EXPECT_TRUE(messages->HasError("line 5")) << messages->AllErrors();
  EXPECT_TRUE(messages->HasError(path)) << messages->AllErrors();
  EXPECT_EQ(source->GetSeed(), 1u);
  EXPECT_EQ(source->GetMTime(), before);
  messages->Clear();
  EXPECT_FALSE(source->ParseScript("fps 30\nat 1 look 10\n"));
  EXPECT_TRUE(messages->HasError("line 2")) << messages->AllErrors();

  // After all that the source still works, and a good script is applied.
  EXPECT_TRUE(source->LoadScript((SourceDir + "/Data/scripts/bad-news.txt").c_str()))
    << messages->AllErrors();
  EXPECT_GT(source->GetMTime(), before);
  vtkTable* track = Track(source);
  EXPECT_GT(track->GetNumberOfRows(), 1);
}

TEST(BehaviorTimeSource, ExecutesOnlyWhenSomethingChanged)
{
  Face face;
  ExecutionCounter source(face.Behavior);
  ExecutionCounter morph(face.Morph);
  face.Morph->UpdateTimeStep(1.0);
  EXPECT_EQ(source.Count, 1);
  EXPECT_EQ(morph.Count, 1);
  face.Morph->UpdateTimeStep(1.0);
  face.Behavior->SetSeed(face.Behavior->GetSeed());
  face.Behavior->SetFrameRate(30.0);
  face.Behavior->SetDuration(0.0);
  face.Behavior->SetVoice("en");
  face.Behavior->SetVisemeSetToPaper();
  face.Behavior->SetSpeechRate(face.Behavior->GetSpeechRate());
  face.Morph->UpdateTimeStep(1.0);
  EXPECT_EQ(source.Count, 1) << "re-executed without a change";
  EXPECT_EQ(morph.Count, 1);

  face.Morph->UpdateTimeStep(2.0); // another time: both run again
  EXPECT_EQ(source.Count, 2);
  EXPECT_EQ(morph.Count, 2);

  face.Behavior->Gesture("smile", 1.5); // a command: runs again at the same time
  face.Morph->UpdateTimeStep(2.0);
  EXPECT_EQ(source.Count, 3);
  EXPECT_EQ(morph.Count, 3);
  EXPECT_GT(
    Value(vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(0)), "MouthSmile"), 0.5);

  face.Behavior->SetSeed(99); // a real change of a setting
  face.Morph->UpdateTimeStep(2.0);
  EXPECT_EQ(source.Count, 4);
  face.Behavior->ClearCommands();
  face.Morph->UpdateTimeStep(2.0);
  EXPECT_EQ(source.Count, 5);
  morphnode::BehaviorController idle; // seed 99, no commands
  idle.SetSeed(99);
  idle.Prepare();
  std::vector<double> expected(idle.GetNumberOfChannels());
  idle.Sample(2.0, expected);
  EXPECT_EQ(Value(vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(0)), "MouthSmile"),
    expected[static_cast<size_t>(idle.FindChannel("MouthSmile"))]);

  // The track (port 1) is built only when port 1 is asked for, then kept.
  EXPECT_EQ(vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(1))->GetNumberOfRows(), 0);
  face.Behavior->Update(1);
  EXPECT_EQ(source.Count, 6);
  EXPECT_EQ(vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(1))->GetNumberOfRows(), 151);
  face.Behavior->Update(1);
  face.Morph->UpdateTimeStep(2.0);
  EXPECT_EQ(source.Count, 6);
  face.Morph->UpdateTimeStep(2.5); // port 0 runs again; the track stays as it is
  EXPECT_EQ(source.Count, 7);
  face.Behavior->Update(1);
  EXPECT_EQ(source.Count, 7);
  EXPECT_EQ(vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(1))->GetNumberOfRows(), 151);
  EXPECT_TRUE(face.Messages->Errors.empty()) << face.Messages->AllErrors();
}

TEST(BehaviorTimeSource, SayVisemesLieWithinTheSpeechOfTheWav)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  source->SetVoice("en");
  source->SetVisemeSetToPaper();
  ASSERT_TRUE(source->Say("Hello world", 1.0)) << messages->AllErrors();
  ASSERT_TRUE(source->Say("How are you?")) << messages->AllErrors(); // after the first
  EXPECT_EQ(source->GetNumberOfUtterances(), 2);
  EXPECT_TRUE(source->HasAudio());
  // The paper's visemes follow the base channels.
  ASSERT_GE(source->GetNumberOfChannels(), 15 + 4);
  for (const char* viseme : { "A", "E", "O", "sil" })
  {
    EXPECT_GE(source->GetChannelIndex(viseme), 15) << viseme;
  }

  const std::string wavPath = OutputDir + "/TestBehaviorTimeSource_say.wav";
  ASSERT_TRUE(source->WriteAudio(wavPath.c_str())) << messages->AllErrors();
  const Wav wav = ReadWav(wavPath);
  ASSERT_EQ(wav.SampleRate, 22050);
  const double duration = source->GetEffectiveDuration();
  EXPECT_GE(wav.Samples.size() / 22050.0, duration - 1e-3);
  // The speech span of the audio: first and last clearly audible samples.
  double first = -1.0, last = -1.0;
  for (size_t i = 0; i < wav.Samples.size(); ++i)
  {
    if (std::abs(static_cast<int>(wav.Samples[i])) > 1000)
    {
      last = static_cast<double>(i) / wav.SampleRate;
      if (first < 0.0)
      {
        first = last;
      }
    }
  }
  ASSERT_GE(first, 1.0) << "audio before the utterance's start";
  ASSERT_GT(last, first + 0.8);
  EXPECT_LT(first, 1.3);

  // Mouth activity (the non-silent visemes) only around the audible speech; the mouth
  // leads the sound by 50 ms and closes after it.
  vtkTable* track = Track(source);
  double maxInside = 0.0, maxOutside = 0.0, firstActive = -1.0, lastActive = -1.0;
  for (vtkIdType r = 0; r < track->GetNumberOfRows(); ++r)
  {
    const double t = Value(track, "Time", r);
    double activity = 0.0;
    for (const char* viseme : { "A", "E", "O", "S", "F", "L" })
    {
      if (track->GetColumnByName(viseme))
      {
        activity += Value(track, viseme, r);
      }
    }
    if (activity > 0.05)
    {
      lastActive = t;
      if (firstActive < 0.0)
      {
        firstActive = t;
      }
    }
    if (t >= first && t <= last)
    {
      maxInside = std::max(maxInside, activity);
    }
    else if (t < first - 0.15 || t > last + 0.25)
    {
      maxOutside = std::max(maxOutside, activity);
    }
  }
  EXPECT_GT(maxInside, 0.5);
  EXPECT_LT(maxOutside, 0.05);
  EXPECT_GE(firstActive, first - 0.15);
  EXPECT_LE(lastActive, last + 0.25);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();

  // eSpeak failing (an unknown voice) is an error, not a crash, and changes nothing.
  messages->Clear();
  const vtkMTimeType mtime = source->GetMTime();
  source->SetVoice("xx-nonexistent");
  EXPECT_FALSE(source->Say("Hello"));
  EXPECT_FALSE(messages->Errors.empty());
  EXPECT_EQ(source->GetNumberOfUtterances(), 2);
  EXPECT_GT(source->GetMTime(), mtime); // the voice changed, nothing else
}

TEST(BehaviorTimeSource, PaperVisemesDriveTheDefaultFace)
{
  MORPHNODE_SKIP_WITHOUT_ESPEAK();
  Face face;
  face.Morph->SetWeightModeToRelative();
  ASSERT_TRUE(face.Behavior->Say("Hello! How are you?", 0.2)) << face.Messages->AllErrors();
  face.Morph->UpdateInformation();
  face.Morph->Update();
  // Every viseme channel but `sil` names a target of the default face.
  for (int c = 15; c < face.Behavior->GetNumberOfChannels(); ++c)
  {
    const std::string name = face.Behavior->GetChannelName(c);
    if (name != "sil")
    {
      EXPECT_GE(face.Morph->GetTargetIndex(name.c_str()), 1) << name;
    }
  }
  // While speaking, mouth targets are active in the morph.
  int activeFrames = 0;
  for (double t = 0.3; t < 1.5; t += 0.1)
  {
    face.Morph->UpdateTimeStep(t);
    double mouth = 0.0;
    for (const char* target : { "A", "E", "O", "S", "F", "L" })
    {
      mouth += face.Morph->GetEffectiveWeight(face.Morph->GetTargetIndex(target));
    }
    activeFrames += mouth > 0.3 ? 1 : 0;
  }
  EXPECT_GE(activeFrames, 4);
  EXPECT_TRUE(face.Messages->Errors.empty()) << face.Messages->AllErrors();
}

TEST(BehaviorTimeSource, RhubarbCuesFromFilesAndText)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  morphnode::BehaviorController core;
  const morphnode::SpeechOptions options = PaperOptions();

  // A TSV export (the fuzz corpus seed) at 1 s, a JSON export queued after it.
  vtkMTimeType mtime = source->GetMTime();
  ASSERT_TRUE(source->SpeakRhubarbFile((Corpus + "rhubarb_tsv/sample.tsv").c_str(), 1.0))
    << messages->AllErrors();
  EXPECT_GT(source->GetMTime(), mtime);
  core.Speak(morphnode::UtteranceFromMouthCues(
               morphnode::ReadRhubarbFile(Corpus + "rhubarb_tsv/sample.tsv"), options),
    1.0);
  mtime = source->GetMTime();
  ASSERT_TRUE(source->SpeakRhubarbFile((Corpus + "rhubarb_json/sample.json").c_str()))
    << messages->AllErrors();
  EXPECT_GT(source->GetMTime(), mtime);
  core.Speak(morphnode::UtteranceFromMouthCues(
    morphnode::ReadRhubarbFile(Corpus + "rhubarb_json/sample.json"), options));
  // The same cues as text, TSV and JSON.
  ASSERT_TRUE(source->SpeakRhubarbCues("0.0\tX\n0.1\tD\n0.5\tX\n", 4.0)) << messages->AllErrors();
  core.Speak(
    morphnode::UtteranceFromMouthCues(morphnode::ParseRhubarb("0.0\tX\n0.1\tD\n0.5\tX\n"), options),
    4.0);
  const char* json = R"({"mouthCues": [{"start": 0, "end": 0.1, "value": "X"},
    {"start": 0.1, "end": 0.4, "value": "A"}, {"start": 0.4, "end": 0.5, "value": "X"}]})";
  ASSERT_TRUE(source->SpeakRhubarbCues(json, 5.0)) << messages->AllErrors();
  core.Speak(morphnode::UtteranceFromMouthCues(morphnode::ParseRhubarb(json), options), 5.0);

  ASSERT_EQ(source->GetNumberOfUtterances(), 4);
  EXPECT_FALSE(source->HasAudio()); // cues carry no sound
  EXPECT_EQ(source->GetUtteranceStart(0), 1.0);
  EXPECT_NEAR(source->GetUtteranceEnd(0), 1.85, 1e-9); // the last TSV cue starts at 0.85
  EXPECT_EQ(source->GetUtteranceStart(1), source->GetUtteranceEnd(0)); // queued after it
  EXPECT_EQ(source->GetUtteranceStart(3), 5.0);
  // The paper's visemes drive the mouth: bit for bit what the core makes of the cues.
  ExpectTrackEqualsCore(source, core);
  vtkTable* track = Track(source);
  EXPECT_GT(Peak(track, "A", 4.15, 4.45), 0.5) << "Rhubarb D (wide open) on the A target";
  EXPECT_LT(Peak(track, "A", 0.0, 0.9), 0.01) << "nothing before the first cues";
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();

  // Bad files and text: an error naming the problem, false, nothing changed.
  mtime = source->GetMTime();
  const struct
  {
    std::string Path, Fragment;
  } bad[] = {
    { Corpus + "rhubarb_tsv/decreasing.tsv", "before the previous cue" },
    { Corpus + "rhubarb_json/end_before_start.json", "ends before it starts" },
    { Corpus + "rhubarb_json/huge_end.json", "duration" },
    { Corpus + "rhubarb_tsv/huge.tsv", "rhubarb" },
    { OutputDir + "/no such file.tsv", "cannot be opened" },
    { Corpus + "pho/hello.pho", "rhubarb tsv line 1" },
  };
  for (const auto& b : bad)
  {
    messages->Clear();
    EXPECT_FALSE(source->SpeakRhubarbFile(b.Path.c_str(), 0.0)) << b.Path;
    EXPECT_TRUE(messages->HasError("SpeakRhubarbFile")) << messages->AllErrors();
    EXPECT_TRUE(messages->HasError(b.Fragment)) << b.Path << ": " << messages->AllErrors();
  }
  messages->Clear();
  EXPECT_FALSE(source->SpeakRhubarbCues("0.0\tQ\n", 0.0));
  EXPECT_FALSE(source->SpeakRhubarbCues("{\"mouthCues\": [", 0.0));
  EXPECT_FALSE(source->SpeakRhubarbCues(nullptr, 0.0)); // no cues at all
  EXPECT_TRUE(messages->HasError("no mouth cues")) << messages->AllErrors();
  EXPECT_FALSE(source->SpeakRhubarbFile(nullptr, 0.0));
  EXPECT_FALSE(source->SpeakRhubarbCues("0.0\tA\n", -HUGE_VAL)); // a start that is no time
  EXPECT_EQ(messages->Errors.size(), 5u) << messages->AllErrors();
  EXPECT_EQ(source->GetNumberOfUtterances(), 4);
  EXPECT_EQ(source->GetMTime(), mtime) << "a rejected command modified the source";
}

TEST(BehaviorTimeSource, PhonemesFromPhoFilesAndText)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  morphnode::BehaviorController core;
  const morphnode::SpeechOptions options = PaperOptions();

  ASSERT_TRUE(source->SpeakPhonemeFile((Corpus + "pho/hello.pho").c_str(), 0.5))
    << messages->AllErrors();
  core.Speak(morphnode::LoadPhoUtterance(Corpus + "pho/hello.pho", options), 0.5);
  const std::string pho = "; a comment\n_ 50\nh 60\nA: 200 50 120\n_ 100\n";
  const vtkMTimeType mtime = source->GetMTime();
  ASSERT_TRUE(source->SpeakPhonemes(pho.c_str())) << messages->AllErrors(); // after hello
  EXPECT_GT(source->GetMTime(), mtime);
  core.Speak(morphnode::UtteranceFromPhonemes(morphnode::ParsePho(pho), options));
  ASSERT_EQ(source->GetNumberOfUtterances(), 2);
  EXPECT_EQ(source->GetUtteranceStart(1), source->GetUtteranceEnd(0));
  EXPECT_FALSE(source->HasAudio());
  ExpectTrackEqualsCore(source, core);
  const double start = source->GetUtteranceStart(1);
  EXPECT_GT(Peak(Track(source), "A", start + 0.11, start + 0.31), 0.5)
    << "the long A: opens the mouth";

  // Bad phonemes: errors with the line, nothing changed.
  const vtkMTimeType before = source->GetMTime();
  messages->Clear();
  EXPECT_FALSE(source->SpeakPhonemeFile((Corpus + "pho/odd_pitch.pho").c_str(), 0.0));
  EXPECT_TRUE(messages->HasError("pho line 1")) << messages->AllErrors();
  EXPECT_FALSE(source->SpeakPhonemes("_ 50\nb -3\n", 0.0));
  EXPECT_TRUE(messages->HasError("pho line 2")) << messages->AllErrors();
  EXPECT_FALSE(source->SpeakPhonemeFile((OutputDir + "/missing.pho").c_str(), 0.0));
  EXPECT_TRUE(messages->HasError("missing.pho")) << messages->AllErrors();
  EXPECT_EQ(messages->Errors.size(), 3u) << messages->AllErrors();
  EXPECT_EQ(source->GetNumberOfUtterances(), 2);
  EXPECT_EQ(source->GetMTime(), before);
}

TEST(BehaviorTimeSource, VisemeTableFileChangesTheChannelsOfLaterSpeech)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  EXPECT_STREQ(source->GetVisemeTableFileName(), "");
  vtkMTimeType mtime = source->GetMTime();
  EXPECT_FALSE(source->SetVisemeTableFileName((OutputDir + "/no_table.json").c_str()));
  EXPECT_TRUE(messages->HasError("SetVisemeTableFileName")) << messages->AllErrors();
  EXPECT_STREQ(source->GetVisemeTableFileName(), "");
  EXPECT_EQ(source->GetMTime(), mtime);
  messages->Clear();

  // The Oculus table as a file while the set says PAPER6: the file wins.
  const std::string table = SourceDir + "/Modules/Core/speech/data/visemes_oculus15_en.json";
  ASSERT_TRUE(source->SetVisemeTableFileName(table.c_str())) << messages->AllErrors();
  EXPECT_EQ(source->GetVisemeTableFileName(), table);
  EXPECT_GT(source->GetMTime(), mtime);
  mtime = source->GetMTime();
  EXPECT_TRUE(source->SetVisemeTableFileName(table.c_str())); // the same: no change
  EXPECT_EQ(source->GetMTime(), mtime);
  ASSERT_TRUE(source->SpeakPhonemes("_ 50\np 80\nA: 200\n_ 50\n", 0.0)) << messages->AllErrors();
  EXPECT_GE(source->GetChannelIndex("PP"), 15);
  EXPECT_GE(source->GetChannelIndex("aa"), 15);
  EXPECT_EQ(source->GetChannelIndex("A"), -1);
  std::ostringstream printed;
  source->Print(printed);
  EXPECT_NE(printed.str().find("VisemeTableFileName: " + table), std::string::npos)
    << printed.str();

  // Back to the built-in table of the set.
  ASSERT_TRUE(source->SetVisemeTableFileName(nullptr));
  ASSERT_TRUE(source->SpeakPhonemes("_ 50\np 80\nA: 200\n_ 50\n", 1.0));
  EXPECT_GE(source->GetChannelIndex("A"), 15);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
}

TEST(BehaviorTimeSource, BehaviorParametersByName)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  ASSERT_EQ(source->GetNumberOfBehaviorParameters(), 29);
  EXPECT_STREQ(source->GetBehaviorParameterName(0), "BlinkRateRest");
  EXPECT_EQ(source->GetBehaviorParameterName(29), nullptr);
  EXPECT_TRUE(messages->HasError("no parameter 29")) << messages->AllErrors();
  messages->Clear();
  EXPECT_EQ(source->GetBehaviorParameter("BlinkRateRest"), 17.0);
  EXPECT_EQ(source->GetBehaviorParameter("head_share_of_gaze"), 0.4);
  std::ostringstream printed;
  source->Print(printed);
  EXPECT_NE(printed.str().find("BehaviorParameters: (defaults)"), std::string::npos)
    << printed.str();

  source->SetDuration(60.0);
  auto blinks = [&]()
  {
    vtkTable* track = Track(source);
    int count = 0;
    for (vtkIdType r = 1; r < track->GetNumberOfRows(); ++r)
    {
      count += Value(track, "EyesClosed", r) > 0.5 && Value(track, "EyesClosed", r - 1) <= 0.5;
    }
    return count;
  };
  const int rest = blinks();
  vtkMTimeType mtime = source->GetMTime();
  ASSERT_TRUE(source->SetBehaviorParameter("BlinkRateRest", 40.0)) << messages->AllErrors();
  EXPECT_GT(source->GetMTime(), mtime);
  EXPECT_EQ(source->GetBehaviorParameter("BlinkRateRest"), 40.0);
  EXPECT_EQ(source->GetBehaviorParameters().BlinkRateRest, 40.0);
  const int fast = blinks();
  EXPECT_GT(fast, rest + 10) << rest << " blinks a minute at 17/min, " << fast << " at 40/min";
  printed.str("");
  source->Print(printed);
  EXPECT_NE(printed.str().find("BehaviorParameters: BlinkRateRest=40"), std::string::npos)
    << printed.str();

  // The same value: no change. Unknown names and values out of range: errors, no change.
  mtime = source->GetMTime();
  EXPECT_TRUE(source->SetBehaviorParameter("BlinkRateRest", 40.0));
  EXPECT_FALSE(source->SetBehaviorParameter("BlinkSpeed", 3.0));
  EXPECT_TRUE(messages->HasError("'BlinkSpeed'")) << messages->AllErrors();
  EXPECT_FALSE(source->SetBehaviorParameter("BlinkRateRest", -1.0));
  EXPECT_TRUE(messages->HasError("BlinkRateRest")) << messages->AllErrors();
  EXPECT_FALSE(source->SetBehaviorParameter("EyeYawRange", std::nan("")));
  EXPECT_TRUE(std::isnan(source->GetBehaviorParameter("nope")));
  EXPECT_EQ(messages->Errors.size(), 4u) << messages->AllErrors();
  EXPECT_EQ(source->GetBehaviorParameter("BlinkRateRest"), 40.0);
  EXPECT_EQ(source->GetMTime(), mtime);
  source->ResetBehaviorParameters();
  EXPECT_GT(source->GetMTime(), mtime);
  EXPECT_EQ(source->GetBehaviorParameter("BlinkRateRest"), 17.0);
  EXPECT_EQ(blinks(), rest);
}

TEST(BehaviorTimeSource, FramesAndTimeStepsAreTheCoreFrames)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  source->SetFrameRate(24.0);
  source->SetDuration(2.3);
  ASSERT_EQ(source->GetNumberOfFrames(), 56); // floor(2.3 * 24) + 1 = 55 + 1
  EXPECT_EQ(
    source->GetNumberOfFrames(), static_cast<vtkIdType>(morphnode::NumberOfFrames(2.3, 24.0)));
  source->UpdateInformation();
  vtkInformation* info = source->GetOutputInformation(0);
  ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 56);
  const double* steps = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  for (vtkIdType i = 0; i < 56; ++i)
  {
    ASSERT_EQ(steps[i], source->GetFrameTime(i));
    ASSERT_EQ(steps[i], morphnode::FrameTime(static_cast<size_t>(i), 24.0));
  }
  vtkTable* track = Track(source);
  ASSERT_EQ(track->GetNumberOfRows(), 56);
  for (vtkIdType i = 0; i < 56; ++i)
  {
    ASSERT_EQ(Value(track, "Time", i), steps[i]);
  }
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_EQ(source->GetFrameTime(56), -1.0);
  EXPECT_EQ(source->GetFrameTime(-1), -1.0);
  EXPECT_EQ(messages->Errors.size(), 2u);
}

TEST(BehaviorTimeSource, ATrackTooLargeIsAnErrorWithEmptyOutputs)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  source->SetFrameRate(1000.0);
  source->SetDuration(86400.0); // 86.4 million frames: sampled one time at a time only
  EXPECT_EQ(source->GetNumberOfFrames(), 86400001);
  source->UpdateInformation();
  vtkInformation* info = source->GetOutputInformation(0);
  EXPECT_FALSE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
    << "86 million time steps";
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()));
  EXPECT_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE())[1], 86400.0);

  // Port 0 at any time works.
  vtkTable* frame = At(source, 43200.25);
  EXPECT_EQ(frame->GetNumberOfColumns(), 15);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  // Port 1: RequestData fails with an error, and both outputs are empty.
  EXPECT_EQ(source->GetExecutive()->Update(1), 0);
  EXPECT_TRUE(messages->HasError("one time at a time")) << messages->AllErrors();
  EXPECT_EQ(vtkTable::SafeDownCast(source->GetOutputDataObject(0))->GetNumberOfColumns(), 0);
  EXPECT_EQ(vtkTable::SafeDownCast(source->GetOutputDataObject(1))->GetNumberOfColumns(), 0);
  // A shorter behaviour recovers.
  messages->Clear();
  source->SetDuration(2.0);
  EXPECT_EQ(Track(source)->GetNumberOfRows(), 2001);
  EXPECT_EQ(At(source, 1.0)->GetNumberOfColumns(), 15);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
}

TEST(BehaviorTimeSource, ControllerIsReadOnlyAndChangesGoThroughTheSource)
{
  auto source = vtkSmartPointer<vtkBehaviorTimeSource>::New();
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  ExecutionCounter executions(source);
  source->Gesture("smile", 1.0);
  // GetController() is const and prepared: C++ code samples it directly.
  const morphnode::BehaviorController& controller = source->GetController();
  ASSERT_TRUE(controller.IsPrepared());
  std::vector<double> row;
  controller.Sample(1.5, row);
  EXPECT_EQ(row[static_cast<size_t>(controller.FindChannel("MouthSmile"))],
    Value(At(source, 1.5), "MouthSmile"));
  EXPECT_EQ(executions.Count, 1);
  // Asking for the same time again, or reading the controller, runs nothing.
  At(source, 1.5);
  source->GetController();
  EXPECT_EQ(executions.Count, 1);

  // An utterance built in C++ (with sound) goes through Speak: modified, re-executed.
  morphnode::Utterance u =
    morphnode::UtteranceFromPhonemes(morphnode::ParsePho("_ 50\nA: 300\n_ 50\n"), PaperOptions());
  u.Audio.assign(static_cast<size_t>(0.4 * 22050), int16_t(1000));
  u.SampleRate = 22050;
  const vtkMTimeType mtime = source->GetMTime();
  ASSERT_TRUE(source->Speak(u, 2.0)) << messages->AllErrors();
  EXPECT_GT(source->GetMTime(), mtime);
  EXPECT_TRUE(source->HasAudio());
  EXPECT_GT(Value(At(source, 2.2), "A"), 0.5);
  EXPECT_EQ(executions.Count, 2);
  const std::string wav = OutputDir + "/TestBehaviorTimeSource_speak.wav";
  ASSERT_TRUE(source->WriteAudio(wav.c_str())) << messages->AllErrors();
  const Wav written = ReadWav(wav);
  const morphnode::AudioBuffer mix = morphnode::MixBehaviorAudio(source->GetController());
  EXPECT_EQ(written.Samples, morphnode::ToInt16Mono(mix)) << "WriteAudio writes the core's mix";
  EXPECT_EQ(written.Samples[44100], 1000); // t = 2.0 s
  EXPECT_FALSE(source->WriteAudio("/nonexistent/folder/speech.wav"));
  EXPECT_TRUE(messages->HasError("WriteAudio")) << messages->AllErrors();

  // A copy of the controller keeps working after the source is gone.
  morphnode::BehaviorController copy = source->GetController();
  source = nullptr;
  copy.Prepare();
  copy.Sample(2.2, row);
  EXPECT_GT(row[static_cast<size_t>(copy.FindChannel("A"))], 0.5);
  if (morphnode::SpeechSynthesizer::IsAvailable())
  {
    copy.Say("Hi", 3.0); // through the source's speech settings, kept by the copy
    EXPECT_EQ(copy.GetUtterances().size(), 2u);
  }
}

TEST(BehaviorTimeSource, AnyTimingFileAndScriptsReadingThem)
{
  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  morphnode::BehaviorController core;
  const morphnode::SpeechOptions options = PaperOptions();
  const std::string textGrid = Corpus + "textgrid/mfa_long.TextGrid";
  const std::string marks = Corpus + "speech_marks/polly.marks";

  ASSERT_TRUE(source->SpeakTimingFile(textGrid.c_str(), 0.5)) << messages->AllErrors();
  core.Speak(morphnode::LoadTimingFile(textGrid, options), 0.5);
  ASSERT_TRUE(source->SpeakTimingFile(marks.c_str())) << messages->AllErrors();
  core.Speak(morphnode::LoadTimingFile(marks, options));
  ASSERT_TRUE(source->SpeakTimingFile((Corpus + "rhubarb_json/sample.json").c_str(), 4.0));
  core.Speak(morphnode::LoadTimingFile(Corpus + "rhubarb_json/sample.json", options), 4.0);
  ASSERT_TRUE(source->SpeakTimingFile((Corpus + "pho/hello.pho").c_str(), 5.0));
  core.Speak(morphnode::LoadTimingFile(Corpus + "pho/hello.pho", options), 5.0);
  EXPECT_EQ(source->GetNumberOfUtterances(), 4);
  EXPECT_FALSE(source->HasAudio());
  ExpectTrackEqualsCore(source, core);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();

  // A script's `phonemes` command reads every timing file too (the source's loader).
  vtkNew<vtkBehaviorTimeSource> scripted;
  messages->Watch(scripted);
  const std::string script = "at 0.5 phonemes \"" + textGrid + "\"\nat 4 phonemes \"" + Corpus +
    "rhubarb_json/sample.json\"\n";
  ASSERT_TRUE(scripted->ParseScript(script.c_str())) << messages->AllErrors();
  morphnode::BehaviorController scriptCore;
  scriptCore.Speak(morphnode::LoadTimingFile(textGrid, options), 0.5);
  scriptCore.Speak(morphnode::LoadTimingFile(Corpus + "rhubarb_json/sample.json", options), 4.0);
  ExpectTrackEqualsCore(scripted, scriptCore);

  // Bad timing files: errors naming the file, nothing changed.
  const vtkMTimeType mtime = source->GetMTime();
  for (const std::string& bad :
    { Corpus + "textgrid/out_of_order.TextGrid", Corpus + "speech_marks/out_of_order.marks",
      Corpus + "rhubarb_tsv/decreasing.tsv", OutputDir + "/missing.TextGrid" })
  {
    messages->Clear();
    EXPECT_FALSE(source->SpeakTimingFile(bad.c_str(), 0.0)) << bad;
    EXPECT_TRUE(messages->HasError("SpeakTimingFile")) << messages->AllErrors();
    EXPECT_TRUE(messages->HasError(bad)) << messages->AllErrors();
  }
  EXPECT_EQ(source->GetNumberOfUtterances(), 4);
  EXPECT_EQ(source->GetMTime(), mtime);
}

TEST(BehaviorTimeSource, RecordingsWithTheirTranscriptOrTimings)
{
  if (!morphnode::SpeechSynthesizer::IsAvailable())
  {
    GTEST_SKIP() << "built without eSpeak NG: no recording to align";
  }
  // A "recording": eSpeak NG saying a sentence, as a WAV file.
  morphnode::SpeechOptions voice = PaperOptions();
  const morphnode::Utterance spoken = morphnode::SpeakText("Hello world, how are you?", voice);
  const std::string wav = OutputDir + "/TestBehaviorTimeSource_recording.wav";
  morphnode::WriteWavFile(wav, spoken.Audio, spoken.SampleRate);
  const double length = static_cast<double>(spoken.Audio.size()) / spoken.SampleRate;

  vtkNew<vtkBehaviorTimeSource> source;
  vtkNew<MessageCollector> messages;
  messages->Watch(source);
  const vtkMTimeType mtime = source->GetMTime();
  ASSERT_TRUE(source->SpeakAudioFile(wav.c_str(), "Hello world, how are you?", 1.0))
    << messages->AllErrors();
  EXPECT_GT(source->GetMTime(), mtime);
  EXPECT_TRUE(source->HasAudio()) << "the recording is the utterance's sound";
  EXPECT_EQ(source->GetUtteranceStart(0), 1.0);
  EXPECT_GE(source->GetUtteranceEnd(0), 1.0 + length - 1e-6);
  EXPECT_LT(source->GetUtteranceEnd(0), 1.0 + length + 0.3);

  // The recording is in the WAV at 1 s, and the mouth moves while it sounds.
  const std::string out = OutputDir + "/TestBehaviorTimeSource_recording_mix.wav";
  ASSERT_TRUE(source->WriteAudio(out.c_str())) << messages->AllErrors();
  const Wav mix = ReadWav(out);
  ASSERT_EQ(mix.SampleRate, spoken.SampleRate);
  double first = -1.0, last = -1.0;
  for (size_t i = 0; i < mix.Samples.size(); ++i)
  {
    if (std::abs(static_cast<int>(mix.Samples[i])) > 1000)
    {
      last = static_cast<double>(i) / mix.SampleRate;
      first = first < 0.0 ? last : first;
    }
  }
  ASSERT_GE(first, 1.0);
  ASSERT_LE(last, 1.0 + length + 0.3);
  vtkTable* track = Track(source);
  double inside = 0.0, before = 0.0;
  for (vtkIdType r = 0; r < track->GetNumberOfRows(); ++r)
  {
    const double t = Value(track, "Time", r);
    double mouth = 0.0;
    for (const char* viseme : { "A", "E", "O", "S", "F", "L" })
    {
      mouth += track->GetColumnByName(viseme) ? Value(track, viseme, r) : 0.0;
    }
    if (t >= first && t <= last)
    {
      inside = std::max(inside, mouth);
    }
    else if (t < first - 0.15)
    {
      before = std::max(before, mouth);
    }
  }
  EXPECT_GT(inside, 0.5);
  EXPECT_LT(before, 0.05);

  // The same recording timed by a timing file of it (its phonemes as .pho).
  const std::string pho = OutputDir + "/TestBehaviorTimeSource_recording.pho";
  morphnode::WritePhoFile(pho, spoken.Phonemes);
  ASSERT_TRUE(source->SpeakAudioFileWithTimings(wav.c_str(), pho.c_str())) << messages->AllErrors();
  EXPECT_EQ(source->GetNumberOfUtterances(), 2);
  EXPECT_EQ(source->GetUtteranceStart(1), source->GetUtteranceEnd(0));
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();

  // Bad recordings: errors, nothing changed.
  const vtkMTimeType after = source->GetMTime();
  EXPECT_FALSE(source->SpeakAudioFile((OutputDir + "/missing.wav").c_str(), "Hello"));
  EXPECT_FALSE(source->SpeakAudioFile((Corpus + "pho/hello.pho").c_str(), "Hello")); // no sound
  EXPECT_FALSE(source->SpeakAudioFileWithTimings(wav.c_str(), nullptr));
  EXPECT_FALSE(
    source->SpeakAudioFileWithTimings(wav.c_str(), (OutputDir + "/missing.TextGrid").c_str()));
  EXPECT_EQ(messages->Errors.size(), 4u) << messages->AllErrors();
  EXPECT_TRUE(messages->HasError("SpeakAudioFileWithTimings: a timing file is needed"))
    << messages->AllErrors();
  EXPECT_EQ(source->GetNumberOfUtterances(), 2);
  EXPECT_EQ(source->GetMTime(), after);
}
