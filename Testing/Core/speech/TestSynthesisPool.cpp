// SPDX-License-Identifier: BSD-3-Clause
// SynthesisPool: jobs run on its workers, a job that waits too long is reported (not run,
// not dropped silently), a full queue refuses, cancelled jobs never run, failures carry
// their message.
#include "base/Error.h"
#include "speech/SynthesisPool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

using namespace morphnode;

namespace
{
/// A gate a job waits at (at most `limit` seconds, so a broken test cannot hang).
class Gate
{
public:
  void Open()
  {
    std::lock_guard<std::mutex> lock(this->M);
    this->IsOpen = true;
    this->C.notify_all();
  }
  bool Wait(double limit = 10.0)
  {
    std::unique_lock<std::mutex> lock(this->M);
    return this->C.wait_for(
      lock, std::chrono::duration<double>(limit), [this] { return this->IsOpen; });
  }

private:
  std::mutex M;
  std::condition_variable C;
  bool IsOpen = false;
};

Utterance Seconds(double d)
{
  Utterance u;
  u.Duration = d;
  return u;
}

/// Waits (bounded) until the job finished; false when it did not within 10 s.
bool Finishes(const std::shared_ptr<SynthesisJob>& job)
{
  for (int i = 0; i < 2000 && !job->IsFinished(); ++i)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return job->IsFinished();
}
} // namespace

TEST(SynthesisPool, JobsRunOnItsWorkersNotTheCaller)
{
  SynthesisPool pool;
  std::atomic<bool> onCaller{ true };
  const auto caller = std::this_thread::get_id();
  auto job = pool.Submit(
    [&]()
    {
      onCaller = std::this_thread::get_id() == caller;
      return Seconds(1.5);
    });
  ASSERT_TRUE(Finishes(job));
  EXPECT_FALSE(onCaller);
  EXPECT_EQ(job->GetState(), SynthesisJob::State::Done);
  EXPECT_DOUBLE_EQ(job->Take().Duration, 1.5);
  const SynthesisPoolStats s = pool.GetStats();
  EXPECT_EQ(s.Submitted, 1u);
  EXPECT_EQ(s.Done, 1u);
}

TEST(SynthesisPool, AJobThatWaitedTooLongIsReportedNotRun)
{
  SynthesisPoolSettings settings;
  settings.Workers = 1;
  settings.MaxWaitSeconds = 0.05;
  SynthesisPool pool(settings);
  Gate gate;
  auto busy = pool.Submit(
    [&]()
    {
      gate.Wait();
      return Seconds(1.0);
    });
  std::atomic<bool> ran{ false };
  auto late = pool.Submit(
    [&]()
    {
      ran = true;
      return Seconds(1.0);
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(150)); // longer than MaxWaitSeconds
  gate.Open();
  ASSERT_TRUE(Finishes(busy));
  ASSERT_TRUE(Finishes(late));
  EXPECT_EQ(busy->GetState(), SynthesisJob::State::Done);
  EXPECT_EQ(late->GetState(), SynthesisJob::State::Expired);
  EXPECT_FALSE(ran);
  EXPECT_NE(late->GetError().find("waited"), std::string::npos) << late->GetError();
  EXPECT_THROW(late->Take(), InputError);
  EXPECT_EQ(pool.GetStats().Expired, 1u);
  EXPECT_GE(pool.GetStats().MaxWaitSeconds, 0.05);
}

TEST(SynthesisPool, AFullQueueRefusesAndCancelledJobsNeverRun)
{
  SynthesisPoolSettings settings;
  settings.Workers = 1;
  settings.MaxQueued = 1;
  SynthesisPool pool(settings);
  Gate started, gate;
  auto busy = pool.Submit(
    [&]()
    {
      started.Open();
      gate.Wait();
      return Seconds(1.0);
    });
  ASSERT_TRUE(started.Wait()); // the worker holds it: the queue is empty again
  std::atomic<bool> ran{ false };
  auto queued = pool.Submit(
    [&]()
    {
      ran = true;
      return Seconds(1.0);
    });
  EXPECT_THROW(pool.Submit([]() { return Seconds(1.0); }), InputError);
  EXPECT_EQ(pool.GetStats().Refused, 1u);
  queued->Cancel();
  auto next = pool.Submit([]() { return Seconds(2.0); }); // the cancelled one holds no place
  gate.Open();
  ASSERT_TRUE(Finishes(next));
  EXPECT_FALSE(ran);
  EXPECT_EQ(queued->GetState(), SynthesisJob::State::Cancelled);
  EXPECT_DOUBLE_EQ(next->Take().Duration, 2.0);
}

TEST(SynthesisPool, FailuresCarryTheirMessageAndBadSettingsAreRefused)
{
  SynthesisPool pool;
  auto job = pool.Submit([]() -> Utterance { throw InputError("no such voice 'xx'"); });
  ASSERT_TRUE(Finishes(job));
  EXPECT_EQ(job->GetState(), SynthesisJob::State::Failed);
  EXPECT_EQ(job->GetError(), "no such voice 'xx'");
  EXPECT_EQ(pool.GetStats().Failed, 1u);
  SynthesisPoolSettings bad;
  bad.Workers = 0;
  EXPECT_THROW(SynthesisPool{ bad }, InputError);
  bad = SynthesisPoolSettings();
  bad.MaxQueued = 0;
  EXPECT_THROW(SynthesisPool{ bad }, InputError);
  EXPECT_TRUE(SynthesisJob::Ready(Seconds(0.5))->IsFinished());
}

// WhenFinished: the callback a job's work asks for runs once the job is final (its state
// Done or Failed when the callback looks), on the worker; outside a pool's job it is ignored.
TEST(SynthesisPool, WhenFinishedRunsOnceTheJobIsFinal)
{
  SynthesisPool pool;
  std::mutex m;
  std::vector<std::string> seen;
  std::shared_ptr<SynthesisJob> done, failed;
  Gate submitted;
  auto note = [&](std::shared_ptr<SynthesisJob>* job, const char* name)
  {
    return [&, job, name]()
    {
      submitted.Wait();
      std::lock_guard<std::mutex> lock(m);
      seen.push_back(std::string(name) + ((*job)->IsFinished() ? " final" : " not final"));
    };
  };
  done = pool.Submit(
    [&]()
    {
      SynthesisPool::WhenFinished(note(&done, "done"));
      return Seconds(0.5);
    });
  failed = pool.Submit(
    [&]() -> Utterance
    {
      SynthesisPool::WhenFinished(note(&failed, "failed"));
      throw InputError("no voice");
    });
  submitted.Open();
  ASSERT_TRUE(Finishes(done));
  ASSERT_TRUE(Finishes(failed));
  for (int i = 0; i < 2000; ++i)
  {
    {
      std::lock_guard<std::mutex> lock(m);
      if (seen.size() == 2)
      {
        break;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::lock_guard<std::mutex> lock(m);
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<std::string>{ "done final", "failed final" }));
  bool called = false;
  SynthesisPool::WhenFinished([&]() { called = true; }); // not in a job
  EXPECT_FALSE(called);
}
