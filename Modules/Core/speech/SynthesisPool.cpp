// SPDX-License-Identifier: BSD-3-Clause
#include "speech/SynthesisPool.h"

#include "base/Error.h"

#include <algorithm>
#include <cstdio>
#include <exception>

namespace morphnode
{
namespace
{
/// The callbacks the job a worker runs asked for (WhenFinished); null outside a job.
thread_local std::vector<std::function<void()>>* FinishedCallbacks = nullptr;
}

void SynthesisPool::WhenFinished(std::function<void()> callback)
{
  if (FinishedCallbacks && callback)
  {
    FinishedCallbacks->push_back(std::move(callback));
  }
}

std::shared_ptr<SynthesisJob> SynthesisJob::Ready(Utterance utterance)
{
  auto job = std::make_shared<SynthesisJob>();
  job->Status = State::Done;
  job->Result = std::move(utterance);
  job->Submitted = Clock::now();
  return job;
}

SynthesisJob::State SynthesisJob::GetState() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Status;
}

bool SynthesisJob::IsFinished() const
{
  const State s = this->GetState();
  return s != State::Queued && s != State::Running;
}

Utterance SynthesisJob::Take()
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  switch (this->Status)
  {
    case State::Done:
      return std::move(this->Result);
    case State::Failed:
    case State::Expired:
      throw InputError(this->Error);
    case State::Cancelled:
      throw InputError("the synthesis was cancelled");
    default:
      throw InputError("the synthesis has not finished");
  }
}

std::string SynthesisJob::GetError() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Error;
}

void SynthesisJob::Cancel()
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->Status == State::Queued)
  {
    this->Status = State::Cancelled;
    this->Work = nullptr;
  }
}

double SynthesisJob::GetWaitSeconds() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Waited;
}

double SynthesisJob::GetWorkSeconds() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Worked;
}

SynthesisPool::SynthesisPool(const SynthesisPoolSettings& settings)
  : Settings(settings)
{
  if (settings.Workers < 1 || settings.Workers > 64)
  {
    throw InputError("a synthesis pool needs 1 to 64 workers");
  }
  if (settings.MaxQueued == 0)
  {
    throw InputError("a synthesis pool's queue must hold at least one job");
  }
  if (!(settings.MaxWaitSeconds > 0.0))
  {
    throw InputError("a synthesis pool's longest wait must be above 0 seconds");
  }
  for (int i = 0; i < settings.Workers; ++i)
  {
    this->Workers.emplace_back([this]() { this->Run(); });
  }
}

SynthesisPool::~SynthesisPool()
{
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Stopping = true;
    for (auto& job : this->Queue)
    {
      job->Cancel();
    }
    this->Queue.clear();
  }
  this->Wake.notify_all();
  for (std::thread& t : this->Workers)
  {
    t.join();
  }
}

std::shared_ptr<SynthesisJob> SynthesisPool::Submit(Work work)
{
  if (!work)
  {
    throw InputError("a synthesis job needs work");
  }
  auto job = std::make_shared<SynthesisJob>();
  job->Work = std::move(work);
  job->Submitted = SynthesisJob::Clock::now();
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    // Cancelled jobs still in the queue hold no place.
    const auto cancelled = std::remove_if(this->Queue.begin(), this->Queue.end(),
      [](const std::shared_ptr<SynthesisJob>& j) { return j->IsFinished(); });
    this->Stats.Cancelled += static_cast<uint64_t>(this->Queue.end() - cancelled);
    this->Queue.erase(cancelled, this->Queue.end());
    if (this->Queue.size() >= this->Settings.MaxQueued)
    {
      ++this->Stats.Refused;
      throw InputError("the speech synthesis queue is full (" + std::to_string(this->Queue.size()) +
        " texts wait): try again later");
    }
    ++this->Stats.Submitted;
    this->Queue.push_back(job);
  }
  this->Wake.notify_one();
  return job;
}

SynthesisPoolStats SynthesisPool::GetStats() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  SynthesisPoolStats s = this->Stats;
  s.Queued = static_cast<size_t>(std::count_if(this->Queue.begin(), this->Queue.end(),
    [](const std::shared_ptr<SynthesisJob>& j) { return !j->IsFinished(); }));
  const uint64_t taken = s.Done + s.Failed + s.Expired;
  s.MeanWaitSeconds = taken ? this->WaitSum / static_cast<double>(taken) : 0.0;
  const uint64_t worked = s.Done + s.Failed;
  s.MeanWorkSeconds = worked ? this->WorkSum / static_cast<double>(worked) : 0.0;
  return s;
}

void SynthesisPool::Run()
{
  for (;;)
  {
    std::shared_ptr<SynthesisJob> job;
    {
      std::unique_lock<std::mutex> lock(this->Mutex);
      this->Wake.wait(lock, [this]() { return this->Stopping || !this->Queue.empty(); });
      if (this->Stopping)
      {
        return;
      }
      job = std::move(this->Queue.front());
      this->Queue.pop_front();
      ++this->Stats.Running;
    }
    const auto taken = SynthesisJob::Clock::now();
    Work work;
    double waited = 0.0;
    bool expired = false;
    {
      std::lock_guard<std::mutex> lock(job->Mutex);
      waited = std::chrono::duration<double>(taken - job->Submitted).count();
      job->Waited = waited;
      if (job->Status == SynthesisJob::State::Queued)
      {
        if (waited > this->Settings.MaxWaitSeconds)
        {
          char text[160];
          std::snprintf(text, sizeof(text),
            "the text waited %.1f s for speech synthesis (longest wait %.1f s): the server is "
            "busy, "
            "it was not spoken",
            waited, this->Settings.MaxWaitSeconds);
          job->Status = SynthesisJob::State::Expired;
          job->Error = text;
          job->Work = nullptr;
          expired = true;
        }
        else
        {
          job->Status = SynthesisJob::State::Running;
          work = std::move(job->Work);
          job->Work = nullptr;
        }
      }
    }
    Utterance result;
    std::string error;
    bool failed = false;
    std::vector<std::function<void()>> callbacks;
    if (work)
    {
      FinishedCallbacks = &callbacks;
      try
      {
        result = work();
      }
      catch (const std::exception& e)
      {
        failed = true;
        error = e.what();
      }
      catch (...)
      {
        failed = true;
        error = "speech synthesis failed";
      }
      FinishedCallbacks = nullptr;
    }
    const double worked = std::chrono::duration<double>(SynthesisJob::Clock::now() - taken).count();
    if (work)
    {
      std::lock_guard<std::mutex> lock(job->Mutex);
      job->Worked = worked;
      job->Status = failed ? SynthesisJob::State::Failed : SynthesisJob::State::Done;
      job->Error = std::move(error);
      job->Result = std::move(result);
    }
    // The job is final: whoever waits for it may take it now.
    for (const std::function<void()>& callback : callbacks)
    {
      try
      {
        callback();
      }
      catch (...)
      {
        // (A waiter that cannot be woken finds the job at its next look.)
      }
    }
    std::lock_guard<std::mutex> lock(this->Mutex);
    --this->Stats.Running;
    if (work)
    {
      ++(failed ? this->Stats.Failed : this->Stats.Done);
      this->WaitSum += waited;
      this->WorkSum += worked;
      this->Stats.MaxWaitSeconds = std::max(this->Stats.MaxWaitSeconds, waited);
    }
    else if (expired)
    {
      ++this->Stats.Expired;
      this->WaitSum += waited;
      this->Stats.MaxWaitSeconds = std::max(this->Stats.MaxWaitSeconds, waited);
    }
    else
    {
      ++this->Stats.Cancelled;
    }
  }
}
} // namespace morphnode
