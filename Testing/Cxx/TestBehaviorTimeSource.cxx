// SPDX-License-Identifier: BSD-3-Clause
// vtkBehaviorTimeSource: time information through the morph filter, weights equal to the
// core's samples, reproducibility, commands and scripts, errors, pipeline economy, speech.
#include "vtkBehaviorTimeSource.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeTestUtilities.h"

#include "behavior/BehaviorController.h"
#include "speech/Speech.h"

#include "vtkCallbackCommand.h"
#include "vtkDelimitedTextWriter.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
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
const std::string DefaultFace = SourceDir + "/Data/DefaultFace/default_face.glb";

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
    this->Callback->SetCallback(
      [](vtkObject*, unsigned long, void* self, void*) { ++static_cast<ExecutionCounter*>(self)->Count; });
    algorithm->AddObserver(vtkCommand::StartEvent, this->Callback);
  }
};

struct Wav
{
  int SampleRate = 0;
  std::vector<int16_t> Samples;
};

Wav ReadWav(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Wav wav;
  if (bytes.size() < 44 || std::string(bytes.data(), 4) != "RIFF" ||
    std::string(bytes.data() + 36, 4) != "data")
  {
    return wav;
  }
  auto u32 = [&](size_t at) {
    return static_cast<uint32_t>(static_cast<unsigned char>(bytes[at])) |
      static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 8 |
      static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 16 |
      static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 3])) << 24;
  };
  wav.SampleRate = static_cast<int>(u32(24));
  const size_t n = std::min<size_t>(u32(40), bytes.size() - 44) / 2;
  wav.Samples.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    wav.Samples[i] = static_cast<int16_t>(static_cast<uint16_t>(static_cast<unsigned char>(bytes[44 + 2 * i])) |
      static_cast<uint16_t>(static_cast<unsigned char>(bytes[45 + 2 * i])) << 8);
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
      largestMotion = std::max(largestMotion, std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]));
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
  EXPECT_NEAR(Value(At(source, 5.75), "BrowsAngry"), 0.8, 1e-9);  // in the hold
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
  EXPECT_GT(Value(vtkTable::SafeDownCast(face.Behavior->GetOutputDataObject(0)), "MouthSmile"), 0.5);

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
