// SPDX-License-Identifier: BSD-3-Clause
// LiveBehavior with a SynthesisPool: Say() and Sample() never synthesize on the caller's
// thread; the avatar idles until the speech is ready, then speaks from the frame that
// picked it up; "started" is not announced early; failures and late chunks are reported
// with their utterance; stop cancels what waits.
#include "BehaviorTestUtilities.h"

#include "base/Error.h"
#include "behavior/LiveBehavior.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

using namespace morphnode;
using C = BehaviorChannel;

namespace
{
const std::vector<std::string> Visemes = { "sil", "PP", "aa", "E", "ou" };

class Gate
{
public:
  void Open()
  {
    std::lock_guard<std::mutex> lock(this->M);
    this->IsOpen = true;
    this->Cv.notify_all();
  }
  /// True when opened within `limit` seconds.
  bool Wait(double limit)
  {
    std::unique_lock<std::mutex> lock(this->M);
    return this->Cv.wait_for(
      lock, std::chrono::duration<double>(limit), [this] { return this->IsOpen; });
  }

private:
  std::mutex M;
  std::condition_variable Cv;
  bool IsOpen = false;
};

/// Samples from t in steps of 1/50 s (sleeping a little between samples, as a frame loop)
/// until the behaviour holds no synthesis job any more; returns the time reached.
double SampleUntilReady(LiveBehavior& live, double t, std::vector<double>& w)
{
  for (int i = 0; i < 2000 && live.IsSynthesizing(); ++i)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    t += 0.02;
    live.Sample(t, w.data());
  }
  return t;
}
} // namespace

TEST(LiveBehaviorPool, SayAndSampleNeverWaitForSynthesis)
{
  auto pool = std::make_shared<SynthesisPool>();
  LiveBehavior live(Visemes, behaviortest::QuietParameters(), 1);
  live.SetSynthesisPool(pool);
  auto gate = std::make_shared<Gate>();
  auto timedOut = std::make_shared<std::atomic<bool>>(false);
  const auto caller = std::this_thread::get_id();
  auto onCaller = std::make_shared<std::atomic<bool>>(false);
  live.SetSynthesizer(
    [gate, timedOut, caller, onCaller](const std::string&)
    {
      *onCaller = *onCaller || std::this_thread::get_id() == caller;
      // Held until the test opens the gate: a Say or Sample that waited for it would only
      // go on after this 3 s limit, and the test sees timedOut.
      if (!gate->Wait(3.0))
      {
        *timedOut = true;
      }
      Utterance u = behaviortest::MakeUtterance(1.0);
      u.Audio.assign(2205, 100);
      return u;
    });
  std::vector<double> w(live.GetNumberOfChannels());
  live.Sample(1.0, w.data());
  const LiveBehavior::Timing said = live.Say("Hello there.", 1.0);
  EXPECT_EQ(said.Id, 1u);
  EXPECT_FALSE(said.Final);
  EXPECT_TRUE(live.IsSpeaking(1.0));
  EXPECT_TRUE(live.IsSynthesizing());
  // Frames go on while the pool works: no mouth yet, "started" not due yet.
  double mouth = 0.0;
  double t = 1.0;
  for (int i = 0; i < 20; ++i)
  {
    t += 0.02;
    live.Sample(t, w.data());
    mouth = std::max(mouth, w[C::NumberOfBaseChannels + 2]);
    EXPECT_GT(live.GetSpeechTiming(said.Id).Start, t)
      << "the start stays after the last frame until ready";
  }
  EXPECT_EQ(mouth, 0.0);
  EXPECT_TRUE(live.TakeAudio().empty());
  gate->Open();
  const double pickedAt = t;
  t = SampleUntilReady(live, t, w);
  EXPECT_FALSE(*timedOut) << "Say() or Sample() waited for the synthesis";
  EXPECT_FALSE(*onCaller) << "synthesized on the caller's thread";
  const LiveBehavior::Timing ready = live.GetSpeechTiming(said.Id);
  ASSERT_EQ(ready.Id, said.Id);
  EXPECT_TRUE(ready.Final);
  EXPECT_GT(ready.Start, pickedAt)
    << "speech starts at the frame that picked it up, not in the past";
  EXPECT_LE(ready.Start, t);
  EXPECT_NEAR(ready.End - ready.Start, 1.0, 1e-9);
  const auto audio = live.TakeAudio();
  ASSERT_EQ(audio.size(), 1u);
  EXPECT_DOUBLE_EQ(audio[0].Start, ready.Start);
  for (; t < ready.End; t += 0.02)
  {
    live.Sample(t, w.data());
    mouth = std::max(mouth, w[C::NumberOfBaseChannels + 2]);
  }
  EXPECT_GT(mouth, 0.5) << "the mouth opens once the speech is ready";
}

TEST(LiveBehaviorPool, ChunksKeepTheirOrderAndALateChunkIsReportedWithItsUtterance)
{
  SynthesisPoolSettings settings;
  settings.Workers = 1;
  settings.MaxWaitSeconds = 0.05;
  auto pool = std::make_shared<SynthesisPool>(settings);
  // Another user of the pool holds its only worker for a while.
  auto gate = std::make_shared<Gate>();
  auto busy = pool->Submit(
    [gate]()
    {
      gate->Wait(5.0);
      return behaviortest::MakeUtterance(0.1);
    });
  LiveBehavior live(Visemes, behaviortest::QuietParameters(), 1);
  live.SetSynthesisPool(pool);
  live.SetSynthesizer([](const std::string& text)
    { return behaviortest::MakeUtterance(0.02 * static_cast<double>(text.size())); });
  std::vector<double> w(live.GetNumberOfChannels());
  const auto late = live.Say("This waits too long.", 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  gate->Open();
  double t = SampleUntilReady(live, 0.0, w);
  auto errors = live.TakeSpeechErrors();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].Id, late.Id);
  EXPECT_TRUE(errors[0].Busy);
  EXPECT_NE(errors[0].Message.find("waited"), std::string::npos) << errors[0].Message;
  EXPECT_FALSE(live.IsSpeaking(t));
  EXPECT_EQ(live.GetSpeechTiming(late.Id).Id, 0u);

  // Without a queue: a two-chunk text and a ready utterance queued behind it play in order.
  const auto text = live.Say("First chunk. Second chunk follows.", t);
  const auto ready = live.Speak(behaviortest::MakeUtterance(0.5), t);
  EXPECT_GT(ready.Start, t);
  for (int i = 0; i < 3000 && live.IsSpeaking(t); ++i)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    t += 0.02;
    live.Sample(t, w.data());
  }
  EXPECT_TRUE(live.TakeSpeechErrors().empty());
  const auto first = live.GetSpeechTiming(text.Id), second = live.GetSpeechTiming(ready.Id);
  ASSERT_NE(first.Id, 0u);
  ASSERT_NE(second.Id, 0u);
  EXPECT_NEAR(first.End - first.Start, 0.02 * (12 + 21), 1e-9) << "both chunks were spoken";
  EXPECT_NEAR(second.Start, first.End, 1e-9);
}

TEST(LiveBehaviorPool, StopCancelsWhatWaitsForThePool)
{
  SynthesisPoolSettings settings;
  settings.Workers = 1;
  auto pool = std::make_shared<SynthesisPool>(settings);
  auto gate = std::make_shared<Gate>();
  auto busy = pool->Submit(
    [gate]()
    {
      gate->Wait(5.0);
      return behaviortest::MakeUtterance(0.1);
    });
  auto calls = std::make_shared<std::atomic<int>>(0);
  {
    LiveBehavior live(Visemes, behaviortest::QuietParameters(), 1);
    live.SetSynthesisPool(pool);
    live.SetSynthesizer(
      [calls](const std::string&)
      {
        ++*calls;
        return behaviortest::MakeUtterance(1.0);
      });
    live.Say("Never said.", 0.0);
    live.StopSpeaking(0.1);
    EXPECT_FALSE(live.IsSpeaking(0.1));
    live.Say("Nor this one, the behaviour ends first.", 0.2);
  }
  gate->Open();
  for (int i = 0; i < 400 && pool->GetStats().Cancelled < 2; ++i)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(pool->GetStats().Cancelled, 2u);
  EXPECT_EQ(*calls, 0);
}
