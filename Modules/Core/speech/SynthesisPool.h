// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SynthesisPool.h
/// @brief Speech synthesis off the caller's thread: a bounded queue and N worker threads
/// that turn texts into utterances, so a real-time loop (a render loop, a stream session's
/// frame timer) submits a text and keeps going; it picks the utterance up once it is ready
/// (SynthesisJob::IsFinished never blocks). LiveBehavior::SetSynthesisPool uses it.
///
/// Contract:
/// - Submit() queues a job (first come, first served) or throws InputError when MaxQueued
///   jobs already wait: the caller reports it (a say refused), nothing is dropped silently.
/// - A job that waited in the queue longer than MaxWaitSeconds is not run: it finishes as
///   Expired with a message saying how long it waited. The caller reports it like a failure.
/// - A job whose work throws finishes as Failed with the exception's message.
/// - Cancel() of a queued job: it never runs. A running job runs to its end (its result is
///   dropped by whoever cancelled it).
/// - WhenFinished(), called by a job's own work, runs a callback on the worker once that
///   job is finished (Done or Failed, Take() ready): a real-time loop that waits for the
///   utterance can be woken at once instead of finding it at its next frame.
/// - The destructor cancels what waits and joins the workers (after the running jobs).
/// - eSpeak NG is one engine per process (SpeechSynthesizer.h): its part of the work is
///   serialized whatever the worker count; the rest (pitch estimation, coarticulation,
///   viseme tracks) runs in parallel.
///
///   auto pool = std::make_shared<morphnode::SynthesisPool>();
///   auto job = pool->Submit([=] { return morphnode::SpeakText(text, options); });
///   ... every frame: if (job->IsFinished()) { Utterance u = job->Take(); ... }

#include "speech/SpeechTypes.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace morphnode
{
class SynthesisJob
{
public:
  enum class State
  {
    Queued,
    Running,
    Done,
    Failed,  ///< the work threw (GetError)
    Expired, ///< waited longer than the pool's MaxWaitSeconds, not run (GetError)
    Cancelled
  };

  /// A job that is already done (e.g. a ready utterance queued behind synthesized speech).
  static std::shared_ptr<SynthesisJob> Ready(Utterance utterance);

  State GetState() const;
  /// Done, Failed, Expired or Cancelled. Never blocks.
  bool IsFinished() const;
  /// Done: the utterance (moved out; once). Otherwise InputError with GetError() (or
  /// "not finished" / "cancelled").
  Utterance Take();
  /// Failed or Expired: why. Empty otherwise.
  std::string GetError() const;
  /// A queued job never runs; a running one is left to finish.
  void Cancel();
  /// Seconds it waited in the queue (until a worker took it) and the work took.
  double GetWaitSeconds() const;
  double GetWorkSeconds() const;

private:
  friend class SynthesisPool;
  using Clock = std::chrono::steady_clock;
  mutable std::mutex Mutex;
  State Status = State::Queued;
  std::function<Utterance()> Work;
  Utterance Result;
  std::string Error;
  Clock::time_point Submitted;
  double Waited = 0.0, Worked = 0.0;
};

struct SynthesisPoolSettings
{
  /// Worker threads (>= 1).
  int Workers = 1;
  /// Jobs that may wait at once; Submit() refuses more.
  size_t MaxQueued = 1024;
  /// A job waiting longer than this is not run (Expired): speech that late is no answer.
  double MaxWaitSeconds = 3.0;
};

struct SynthesisPoolStats
{
  uint64_t Submitted = 0, Done = 0, Failed = 0, Expired = 0, Refused = 0, Cancelled = 0;
  size_t Queued = 0;  ///< waiting now
  size_t Running = 0; ///< being worked on now
  double MeanWaitSeconds = 0.0, MaxWaitSeconds = 0.0, MeanWorkSeconds = 0.0;
};

class SynthesisPool
{
public:
  using Work = std::function<Utterance()>;

  /// InputError for Workers < 1 or > 64, MaxQueued 0, a MaxWaitSeconds not > 0.
  explicit SynthesisPool(const SynthesisPoolSettings& settings = SynthesisPoolSettings());
  ~SynthesisPool();
  SynthesisPool(const SynthesisPool&) = delete;
  SynthesisPool& operator=(const SynthesisPool&) = delete;

  /// Queues the work. InputError when MaxQueued jobs wait already (counted as Refused).
  std::shared_ptr<SynthesisJob> Submit(Work work);
  /// Called from inside a job's work (on a worker): `callback` runs on that worker once the
  /// job is finished, after its state is final (an exception it throws is ignored). Not
  /// within a pool's job: ignored (a synthesizer used directly finishes in its caller).
  static void WhenFinished(std::function<void()> callback);
  SynthesisPoolStats GetStats() const;
  const SynthesisPoolSettings& GetSettings() const { return this->Settings; }

private:
  void Run();

  SynthesisPoolSettings Settings;
  mutable std::mutex Mutex;
  std::condition_variable Wake;
  std::deque<std::shared_ptr<SynthesisJob>> Queue;
  std::vector<std::thread> Workers;
  bool Stopping = false;
  SynthesisPoolStats Stats;
  double WaitSum = 0.0, WorkSum = 0.0;
};
} // namespace morphnode
