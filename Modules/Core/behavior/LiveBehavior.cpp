// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/LiveBehavior.h"

#include "base/Error.h"
#include "behavior/BehaviorScript.h"
#include "behavior/Blackboard.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace morphnode
{
namespace
{
using C = BehaviorChannel;
constexpr double Infinity = std::numeric_limits<double>::infinity();

// Random streams of the live behaviour's own draws (the idle generators use 1..4).
enum LiveStream : uint64_t
{
  BlinkKeepStream = 101,
  ExtraBlinkStream = 102
};

bool IsBlank(char c)
{
  return std::isspace(static_cast<unsigned char>(c)) != 0;
}

std::string Trimmed(const std::string& s)
{
  size_t a = 0, b = s.size();
  while (a < b && IsBlank(s[a]))
  {
    ++a;
  }
  while (b > a && IsBlank(s[b - 1]))
  {
    --b;
  }
  return s.substr(a, b - a);
}

/// Cuts `piece` into parts of at most `max` characters, only after a character for which
/// `cut(i)` holds (then at the blank that follows it), greedily; parts that cannot be cut
/// stay longer.
template <typename F>
std::vector<std::string> CutGreedy(const std::string& piece, size_t max, F&& cut)
{
  std::vector<std::string> out;
  std::string rest = piece;
  while (rest.size() > max)
  {
    size_t best = std::string::npos; // cut after rest[best]
    for (size_t i = 0; i + 1 < rest.size(); ++i)
    {
      if (IsBlank(rest[i + 1]) && cut(rest, i))
      {
        if (i + 1 <= max || best == std::string::npos)
        {
          best = i;
        }
        if (i + 1 > max)
        {
          break;
        }
      }
    }
    if (best == std::string::npos)
    {
      break;
    }
    out.push_back(Trimmed(rest.substr(0, best + 1)));
    rest = Trimmed(rest.substr(best + 1));
  }
  if (!rest.empty())
  {
    out.push_back(rest);
  }
  return out;
}

std::vector<std::string> CutLong(const std::string& piece, size_t max)
{
  std::vector<std::string> out;
  for (const std::string& part :
    CutGreedy(piece, max, [](const std::string&s, size_t i) { return s[i] == ','; }))
  {
    for (std::string& word :
      CutGreedy(part, max, [](const std::string&s, size_t i) { return !IsBlank(s[i]); }))
    {
      out.push_back(std::move(word));
    }
  }
  return out;
}

} // namespace

std::vector<std::string> SplitSpeechChunks(
  const std::string& text, size_t firstMaxChars, size_t maxChars)
{
  firstMaxChars = std::max<size_t>(firstMaxChars, 1);
  maxChars = std::max<size_t>(maxChars, 1);
  // Sentences: after . ! ? ; followed by a blank, and at line breaks.
  std::vector<std::string> sentences;
  std::string current;
  for (size_t i = 0; i < text.size(); ++i)
  {
    const char c = text[i];
    if (c == '\n' || c == '\r')
    {
      sentences.push_back(Trimmed(current));
      current.clear();
      continue;
    }
    current += c;
    const bool end = c == '.' || c == '!' || c == '?' || c == ';';
    if (end && (i + 1 == text.size() || IsBlank(text[i + 1])))
    {
      sentences.push_back(Trimmed(current));
      current.clear();
    }
  }
  sentences.push_back(Trimmed(current));
  std::vector<std::string> chunks;
  for (const std::string& s : sentences)
  {
    if (s.empty())
    {
      continue;
    }
    const size_t max = chunks.empty() ? firstMaxChars : maxChars;
    std::vector<std::string> parts = CutLong(s, max);
    if (chunks.empty() && parts.size() > 1)
    {
      // Only the first part must be short; the rest of the sentence is cut normally.
      std::string rest;
      for (size_t k = 1; k < parts.size(); ++k)
      {
        rest += (rest.empty() ? "" : " ") + parts[k];
      }
      chunks.push_back(parts[0]);
      for (std::string& r : CutLong(rest, maxChars))
      {
        chunks.push_back(std::move(r));
      }
      continue;
    }
    for (std::string& p : parts)
    {
      chunks.push_back(std::move(p));
    }
  }
  return chunks;
}

// ------------------------------------------------------------------ construction

LiveBehavior::LiveBehavior(const std::vector<std::string>& visemeChannels,
  const BehaviorParameters& parameters, uint64_t seed, const BehaviorLibrary& library)
  : Parameters((CheckBehaviorParameters(parameters), parameters))
  , Seed(seed)
  , Library(library)
  , RestBlinks(parameters, seed)
  , BlinkKeep(seed, BlinkKeepStream)
  , ExtraBlinks(seed, ExtraBlinkStream)
  , Saccades(parameters, seed)
  , Smiles(parameters, seed)
  , Head(MakeHeadMicroMotion(parameters, seed))
  , MoodTrack(MoodEffect::Neutral())
{
  this->ChannelNames = C::Names();
  for (const std::string& name : visemeChannels)
  {
    if (std::find(this->ChannelNames.begin(), this->ChannelNames.end(), name) !=
      this->ChannelNames.end())
    {
      throw InputError(
        "viseme channel '" + name + "' is given twice or has the name of a behaviour channel");
    }
    this->ChannelNames.push_back(name);
  }
  this->SilentChannel.assign(this->ChannelNames.size(), 0);
  for (size_t c = C::NumberOfBaseChannels; c < this->ChannelNames.size(); ++c)
  {
    this->SilentChannel[c] = IsSilentViseme(this->ChannelNames[c]);
  }
  // Per gesture: the viseme channels its mouth override acts on.
  for (const GestureDefinition& g : this->Library.GetGestures())
  {
    std::vector<char> mask(this->ChannelNames.size(), 0);
    for (size_t c = C::NumberOfBaseChannels; c < this->ChannelNames.size(); ++c)
    {
      mask[c] = g.MouthShapes.empty() ? !this->SilentChannel[c]
                                      : std::find(g.MouthShapes.begin(), g.MouthShapes.end(),
                                          this->ChannelNames[c]) != g.MouthShapes.end();
    }
    this->MouthMasks.push_back(std::move(mask));
  }
  // The extra blink train covers the fastest rate a mood and speech can ask for.
  double moodMax = 1.0;
  for (const MoodDefinition& m : this->Library.GetMoods())
  {
    moodMax = std::max(moodMax, m.BlinkRate);
  }
  this->MaxBlinkFactor =
    moodMax * std::max(1.0, this->Parameters.BlinkRateSpeaking / this->Parameters.BlinkRateRest);
  this->NextExtraBlink =
    this->MaxBlinkFactor > 1.0 ? this->ExtraBlinks.Exponential(this->ExtraBlinkMean()) : Infinity;
}

double LiveBehavior::ExtraBlinkMean() const
{
  return 60.0 / (this->Parameters.BlinkRateRest * (this->MaxBlinkFactor - 1.0));
}

void LiveBehavior::SetSynthesizer(Synthesizer synthesizer)
{
  this->Synthesize = std::move(synthesizer);
}

LiveBehavior::~LiveBehavior()
{
  // Jobs still queued in the pool need not run any more (a running one finishes; its
  // work holds copies of what it uses).
  for (PendingSpeech& p : this->Pending)
  {
    if (p.Job)
    {
      p.Job->Cancel();
    }
  }
}

void LiveBehavior::SetSynthesisPool(std::shared_ptr<SynthesisPool> pool)
{
  this->Pool = std::move(pool);
}

double LiveBehavior::ClampNow(double now) const
{
  if (!std::isfinite(now) || now < 0.0 || now > MaxLiveTime)
  {
    throw InputError("command time is not a finite time in [0, 10^9] seconds");
  }
  return this->Sampled ? std::max(now, this->LastTime) : now;
}

// ------------------------------------------------------------------ commands

LiveBehavior::Timing LiveBehavior::Gesture(
  const std::string& name, double now, double intensity, double duration)
{
  const int index = this->Library.FindGestureIndex(name);
  if (index < 0)
  {
    this->Library.FindGesture(name); // throws, listing the known gestures
  }
  CheckBehaviorRange(intensity, 0.0, 1.0, "gesture intensity");
  CheckBehaviorRange(duration, 0.0, MaxBehaviorTime, "gesture duration");
  CheckBehaviorDuration(duration, "gesture duration");
  now = this->ClampNow(now);
  const GestureDefinition& g = this->Library.GetGestures()[index];
  LiveGesture live{ index, intensity, g.Sync(now, duration, this->Parameters) };
  if (g.Blink)
  {
    this->InsertBlink({ now, intensity, 0.0, 2, 1 });
  }
  this->Gestures.push_back(live);
  return { live.Sync.Start, live.Sync.End, 0, true };
}

LiveBehavior::Timing LiveBehavior::SetMood(const std::string& name, double intensity, double now)
{
  const MoodDefinition& m = this->Library.FindMood(name);
  CheckBehaviorRange(intensity, 0.0, 1.0, "mood intensity");
  now = this->ClampNow(now);
  this->MoodTrack.DropFrom(now);
  this->MoodTrack.Add(now, this->Parameters.MoodFadeTime, MoodEffect::Of(m, intensity));
  this->MoodTrack.Finalize();
  return { now, now + this->Parameters.MoodFadeTime, 0, true };
}

LiveBehavior::Timing LiveBehavior::LookAt(double yaw, double pitch, double now, double duration)
{
  CheckBehaviorRange(yaw, -90.0, 90.0, "look yaw");
  CheckBehaviorRange(pitch, -90.0, 90.0, "look pitch");
  CheckBehaviorRange(duration, -MaxBehaviorTime, MaxBehaviorTime, "look duration");
  if (duration > 0.0)
  {
    CheckBehaviorDuration(duration, "look duration");
  }
  now = this->ClampNow(now);
  const BehaviorParameters& p = this->Parameters;
  this->EyeGazeTrack.DropFrom(now);
  this->HeadGazeTrack.DropFrom(now);
  double from[3];
  this->EyeGazeTrack.Evaluate(now, from);
  // The eyes jump like a saccade; the head follows slower and takes its share.
  const double jump = std::hypot(yaw - from[0], pitch - from[1]);
  this->EyeGazeTrack.Add(now, SaccadeDuration(p, jump), { yaw, pitch, 1.0 });
  this->HeadGazeTrack.Add(
    now, p.HeadGazeTime, { p.HeadShareOfGaze * yaw, p.HeadShareOfGaze * pitch });
  double end = now + std::max(SaccadeDuration(p, jump), p.HeadGazeTime);
  if (duration > 0.0)
  {
    const double back = now + duration;
    const double eyeBack = SaccadeDuration(p, std::hypot(yaw, pitch));
    this->EyeGazeTrack.Add(back, eyeBack, { 0.0, 0.0, 0.0 });
    this->HeadGazeTrack.Add(back, p.HeadGazeTime, { 0.0, 0.0 });
    end = std::max(end, back + std::max(eyeBack, p.HeadGazeTime));
  }
  this->EyeGazeTrack.Finalize();
  this->HeadGazeTrack.Finalize();
  return { now, end, 0, true };
}

LiveBehavior::Timing LiveBehavior::Say(const std::string& text, double now)
{
  if (!this->Synthesize)
  {
    throw InputError("say: no synthesizer is set (LiveBehavior::SetSynthesizer)");
  }
  return this->Say(text, now, this->Synthesize);
}

LiveBehavior::Timing LiveBehavior::Say(
  const std::string& text, double now, const Synthesizer& synthesizer)
{
  if (!synthesizer)
  {
    throw InputError("say: no synthesizer given");
  }
  now = this->ClampNow(now);
  std::vector<std::string> chunks = SplitSpeechChunks(text);
  if (chunks.empty())
  {
    throw InputError("say: the text is empty");
  }
  const uint64_t id = this->NextId;
  if (this->Pool)
  {
    // Nothing is synthesized here: the text is queued and its first chunk submitted when
    // nothing is ahead of it; Sample() schedules it once the pool has it.
    ++this->NextId;
    const double spc =
      this->Pending.empty() ? this->SecondsPerChar : this->Pending.back().SecondsPerChar;
    PendingSpeech p{ id, std::move(chunks), spc, synthesizer };
    p.NotBefore = now;
    const double start = std::max(now, this->GetSpeechEnd());
    this->Pending.push_back(std::move(p));
    try
    {
      this->PumpSynthesis(now);
    }
    catch (const std::exception&)
    {
      // The pool refused it (full): the say is refused, nothing of it stays.
      if (!this->Pending.empty() && this->Pending.back().Id == id)
      {
        if (this->Pending.back().Job)
        {
          this->Pending.back().Job->Cancel();
        }
        this->Pending.pop_back();
      }
      throw;
    }
    Timing t = this->GetSpeechTiming(id);
    if (t.Id == 0)
    {
      t = Timing{ start, start, id, false }; // failed at once: reported by TakeSpeechErrors
    }
    t.Start = std::max(t.Start, start);
    t.End = std::max(t.End, t.Start);
    return t;
  }
  if (!this->Pending.empty())
  {
    // Earlier speech still waits for synthesis: queue the whole text behind it.
    ++this->NextId;
    PendingSpeech p{ id, std::move(chunks), this->Pending.back().SecondsPerChar, synthesizer };
    const double start = std::max(now, this->GetSpeechEnd());
    this->Pending.push_back(std::move(p));
    Timing t = this->GetSpeechTiming(id);
    t.Start = start;
    return t;
  }
  Utterance first = synthesizer(chunks.front());
  ++this->NextId;
  const Timing timing = this->AddUtterance(id, std::move(first), now);
  if (chunks.size() > 1)
  {
    const double spc =
      (timing.End - timing.Start) / static_cast<double>(std::max<size_t>(chunks[0].size(), 1));
    chunks.erase(chunks.begin());
    this->Pending.push_back({ id, std::move(chunks), spc, synthesizer });
  }
  return this->GetSpeechTiming(id);
}

LiveBehavior::Timing LiveBehavior::Speak(const Utterance& utterance, double now)
{
  now = this->ClampNow(now);
  const uint64_t id = this->NextId++;
  if (this->Pool && !this->Pending.empty())
  {
    // Keep the order without waiting: the ready utterance queues behind the texts.
    PendingSpeech p{ id, {}, this->Pending.back().SecondsPerChar, nullptr };
    p.NotBefore = now;
    p.JobSeconds = utterance.Duration;
    p.Job = SynthesisJob::Ready(utterance);
    this->Pending.push_back(std::move(p));
    Timing t = this->GetSpeechTiming(id);
    t.Id = id;
    return t;
  }
  if (!this->Pending.empty())
  {
    // Keep the order: synthesize what is queued first.
    this->SynthesizeAll();
  }
  return this->AddUtterance(id, utterance, now);
}

void LiveBehavior::SynthesizeAll()
{
  while (!this->Pending.empty())
  {
    this->SynthesizeNext();
  }
}

double LiveBehavior::PendingSeconds(const PendingSpeech& p)
{
  double chars = 0.0;
  for (const std::string& c : p.Chunks)
  {
    chars += static_cast<double>(c.size());
  }
  return chars * p.SecondsPerChar + (p.Job ? p.JobSeconds : 0.0);
}

void LiveBehavior::FailSpeech(uint64_t id, const std::string& message, bool busy)
{
  // A chunk that fails ends its text: the rest of it is dropped, the error kept.
  this->Errors.push_back({ id, "say: " + message, busy });
  for (PendingSpeech& p : this->Pending)
  {
    if (p.Id == id && p.Job)
    {
      p.Job->Cancel();
    }
  }
  this->Pending.erase(std::remove_if(this->Pending.begin(), this->Pending.end(),
                        [id](const PendingSpeech& p) { return p.Id == id; }),
    this->Pending.end());
}

void LiveBehavior::PumpSynthesis(double now)
{
  while (!this->Pending.empty())
  {
    PendingSpeech& front = this->Pending.front();
    if (front.Job)
    {
      if (!front.Job->IsFinished())
      {
        return; // never wait: the avatar idles meanwhile
      }
      const std::shared_ptr<SynthesisJob> job = std::move(front.Job);
      front.Job = nullptr;
      const uint64_t id = front.Id;
      const double notBefore = front.NotBefore;
      const size_t chars = front.JobChars;
      front.JobSeconds = 0.0;
      front.JobChars = 0;
      if (front.Chunks.empty())
      {
        this->Pending.pop_front();
      }
      try
      {
        const Timing t = this->AddUtterance(id, job->Take(), std::max(now, notBefore));
        if (chars > 0 && t.End > t.Start)
        {
          this->SecondsPerChar = (t.End - t.Start) / static_cast<double>(chars);
          for (PendingSpeech& p : this->Pending)
          {
            if (p.Id == id)
            {
              p.SecondsPerChar = this->SecondsPerChar;
            }
          }
        }
      }
      catch (const std::exception& e)
      {
        this->FailSpeech(id, e.what(), job->GetState() == SynthesisJob::State::Expired);
      }
      continue;
    }
    if (front.Chunks.empty())
    {
      this->Pending.pop_front();
      continue;
    }
    // The next chunk goes to the pool once what is scheduled ends within the lookahead.
    if (this->ScheduledSpeechEnd() - now > SynthesisLookahead)
    {
      return;
    }
    const std::string chunk = front.Chunks.front();
    const Synthesizer synthesize = front.Synthesize;
    front.Job = this->Pool->Submit([synthesize, chunk]() { return synthesize(chunk); });
    front.JobChars = chunk.size();
    front.JobSeconds = static_cast<double>(chunk.size()) * front.SecondsPerChar;
    front.Chunks.erase(front.Chunks.begin());
    return;
  }
}

void LiveBehavior::SynthesizeNext()
{
  PendingSpeech& front = this->Pending.front();
  const uint64_t id = front.Id;
  const Synthesizer synthesize = front.Synthesize;
  const std::string chunk = front.Chunks.front();
  front.Chunks.erase(front.Chunks.begin());
  if (front.Chunks.empty())
  {
    this->Pending.pop_front();
  }
  try
  {
    this->AddUtterance(id, synthesize(chunk), this->LastTime);
  }
  catch (const std::exception& e)
  {
    this->FailSpeech(id, e.what());
  }
}

void LiveBehavior::SynthesizeAhead(double now)
{
  if (this->Pool)
  {
    try
    {
      this->PumpSynthesis(now);
    }
    catch (const std::exception& e)
    {
      // The pool refused a later chunk (its queue is full): that text ends here.
      if (!this->Pending.empty())
      {
        this->FailSpeech(this->Pending.front().Id, e.what(), true);
      }
    }
    return;
  }
  while (!this->Pending.empty() && this->ScheduledSpeechEnd() - now <= SynthesisLookahead)
  {
    this->SynthesizeNext();
  }
}

double LiveBehavior::ScheduledSpeechEnd() const
{
  double end = -Infinity;
  for (const LiveUtterance& u : this->Utterances)
  {
    end = std::max(end, std::min(u.End, u.Cut));
  }
  return end;
}

LiveBehavior::Timing LiveBehavior::AddUtterance(uint64_t id, Utterance u, double now)
{
  CheckBehaviorRange(u.Duration, 0.0, MaxBehaviorTime, "utterance duration");
  const WeightTrack& v = u.Visemes;
  std::vector<int> map;
  for (const auto& name : v.GetChannels())
  {
    auto it = std::find(
      this->ChannelNames.begin() + C::NumberOfBaseChannels, this->ChannelNames.end(), name);
    if (it == this->ChannelNames.end())
    {
      throw InputError(
        "utterance viseme channel '" + name + "' is not one of the avatar's viseme channels");
    }
    map.push_back(static_cast<int>(it - this->ChannelNames.begin()));
  }
  const double trackLength = CheckUtteranceTrack(u);
  const double start = std::max(now, this->ScheduledSpeechEnd());
  LiveUtterance live;
  live.Id = id;
  live.Start = start;
  live.End = start + std::max(u.Duration, trackLength);
  live.Cut = Infinity;
  live.ChannelMap = std::move(map);
  for (const NonverbalCue& cue : u.Cues)
  {
    const SyncPoints sync = SpeechCueSync(cue, start + cue.Start, this->Parameters);
    if (cue.Type == NonverbalCue::Kind::Blink)
    {
      this->InsertBlink({ sync.Start, 1.0, 0.0, 3, 1 });
    }
    else
    {
      this->Cues.push_back({ cue.Type, sync, cue.Intensity });
    }
  }
  if (!u.Audio.empty())
  {
    this->Audio.push_back({ id, start, u.SampleRate, std::move(u.Audio) });
  }
  u.Audio.clear();
  u.Phonemes.clear();
  u.Cues.clear();
  live.Speech = std::move(u);
  const Timing timing{ live.Start, live.End, id, true };
  this->Utterances.push_back(std::move(live));
  return timing;
}

void LiveBehavior::StopSpeaking(double now)
{
  now = this->ClampNow(now);
  for (PendingSpeech& p : this->Pending)
  {
    if (p.Job)
    {
      p.Job->Cancel();
    }
  }
  this->Pending.clear();
  this->Audio.clear();
  this->Utterances.erase(std::remove_if(this->Utterances.begin(), this->Utterances.end(),
                           [now](const LiveUtterance& u) { return u.Start >= now; }),
    this->Utterances.end());
  for (LiveUtterance& u : this->Utterances)
  {
    u.Cut = std::min(u.Cut, now);
  }
  this->Cues.erase(std::remove_if(this->Cues.begin(), this->Cues.end(),
                     [now](const LiveCue& c) { return c.Sync.Start >= now; }),
    this->Cues.end());
  // Speech blink cues not started yet go too (idle and gesture blinks stay).
  this->Blinks.erase(std::remove_if(this->Blinks.begin(), this->Blinks.end(),
                       [now](const LiveBlink& b) { return b.Source == 3 && b.Start >= now; }),
    this->Blinks.end());
}

std::vector<LiveBehavior::AudioSegment> LiveBehavior::TakeAudio()
{
  std::vector<AudioSegment> out;
  out.swap(this->Audio);
  return out;
}

std::vector<std::string> LiveBehavior::TakeErrors()
{
  std::vector<std::string> out;
  for (SpeechError& e : this->Errors)
  {
    out.push_back(std::move(e.Message));
  }
  this->Errors.clear();
  return out;
}

std::vector<LiveBehavior::SpeechError> LiveBehavior::TakeSpeechErrors()
{
  std::vector<SpeechError> out;
  out.swap(this->Errors);
  return out;
}

bool LiveBehavior::IsSynthesizing() const
{
  return std::any_of(this->Pending.begin(), this->Pending.end(),
    [](const PendingSpeech& p) { return p.Job != nullptr; });
}

// ------------------------------------------------------------------ inspection

LiveBehavior::Timing LiveBehavior::GetSpeechTiming(uint64_t id) const
{
  Timing t;
  bool found = false;
  double end = -Infinity;
  for (const LiveUtterance& u : this->Utterances)
  {
    end = std::max(end, std::min(u.End, u.Cut));
    if (u.Id == id)
    {
      t.Start = found ? std::min(t.Start, u.Start) : u.Start;
      t.End = found ? std::max(t.End, std::min(u.End, u.Cut)) : std::min(u.End, u.Cut);
      found = true;
    }
  }
  // Queued chunks: estimated from the characters left, after everything before them.
  double estimate = std::max(end, this->LastTime);
  for (const PendingSpeech& p : this->Pending)
  {
    const double start = estimate;
    estimate += PendingSeconds(p);
    if (p.Id == id)
    {
      if (!found)
      {
        // With a pool, nothing of it is ready yet: it starts after the last sample at the
        // earliest (and not before its say).
        t.Start = this->Pool ? std::max({ start, p.NotBefore, this->LastTime + 1e-6 }) : start;
      }
      t.End = estimate;
      t.Final = false;
      found = true;
    }
  }
  if (found)
  {
    t.Id = id;
  }
  return t;
}

bool LiveBehavior::IsSpeaking(double t) const
{
  return !this->Pending.empty() || this->ScheduledSpeechEnd() > t;
}

double LiveBehavior::GetSpeechEnd() const
{
  double end = std::max(this->ScheduledSpeechEnd(), this->LastTime);
  for (const PendingSpeech& p : this->Pending)
  {
    end += PendingSeconds(p);
  }
  return end;
}

size_t LiveBehavior::GetNumberOfHeldEvents() const
{
  size_t n = this->Blinks.size() + this->SaccadeEvents.size() + this->SmileEvents.size() +
    this->Gestures.size() + this->Utterances.size() + this->Cues.size() +
    this->MoodTrack.GetNumberOfKeys() + this->EyeGazeTrack.GetNumberOfKeys() +
    this->HeadGazeTrack.GetNumberOfKeys();
  for (const PendingSpeech& p : this->Pending)
  {
    n += p.Chunks.size() + (p.Job ? 1 : 0);
  }
  return n;
}

std::vector<double> LiveBehavior::GetBlinkStarts(double from, double to) const
{
  std::vector<double> out;
  for (const LiveBlink& b : this->Blinks)
  {
    if (b.Decided == 1 && b.Start >= from && b.Start < to)
    {
      out.push_back(b.Start);
    }
  }
  return out;
}

std::vector<SaccadeEvent> LiveBehavior::GetSaccades(double from, double to) const
{
  std::vector<SaccadeEvent> out;
  for (const SaccadeEvent& s : this->SaccadeEvents)
  {
    if (s.Start >= from && s.Start < to && s.Start <= this->LastTime)
    {
      out.push_back(s);
    }
  }
  return out;
}

// ------------------------------------------------------------------ the idle generators

void LiveBehavior::InsertBlink(const LiveBlink& blink)
{
  auto it = std::upper_bound(this->Blinks.begin(), this->Blinks.end(), blink.Start,
    [](double v, const LiveBlink& b) { return v < b.Start; });
  this->Blinks.insert(it, blink);
}

void LiveBehavior::Extend(double horizon)
{
  while (this->RestBlinks.Peek() <= horizon)
  {
    const BlinkEvent b = this->RestBlinks.Next();
    this->InsertBlink({ b.Start, b.Amplitude, this->BlinkKeep.Uniform(), 0, -1 });
  }
  while (this->NextExtraBlink <= horizon)
  {
    const double amplitude = this->ExtraBlinks.Uniform(0.9, 1.0);
    this->InsertBlink({ this->NextExtraBlink, amplitude, this->ExtraBlinks.Uniform(), 1, -1 });
    this->NextExtraBlink += std::max(
      BlinkLength(this->Parameters), this->ExtraBlinks.Exponential(this->ExtraBlinkMean()));
  }
  while (this->Saccades.Peek() <= horizon)
  {
    // The mood at the saccade's start sets its range and the fixation after it.
    MoodEffect::Vector mood;
    this->MoodTrack.Evaluate(this->Saccades.Peek(), mood.data());
    BehaviorParameters p = this->Parameters;
    p.SaccadeRange *= mood[MoodEffect::SaccadeRange];
    p.SaccadeMaxAmplitude *= mood[MoodEffect::SaccadeRange];
    p.FixationMean *= mood[MoodEffect::Fixation];
    this->SaccadeEvents.push_back(this->Saccades.Next(p));
  }
  while (this->Smiles.Peek() <= horizon)
  {
    this->SmileEvents.push_back(this->Smiles.Next());
  }
}

void LiveBehavior::Forget(double t)
{
  const double blinkLength = BlinkLength(this->Parameters);
  while (!this->Blinks.empty() && this->Blinks.front().Start + blinkLength < t - ForgetAfter)
  {
    this->Blinks.pop_front();
  }
  while (this->SaccadeEvents.size() > 1 && this->SaccadeEvents[1].Start < t - ForgetAfter)
  {
    this->SaccadeEvents.pop_front();
  }
  while (!this->SmileEvents.empty() &&
    this->SmileEvents.front().Start + this->SmileEvents.front().Duration < t)
  {
    this->SmileEvents.pop_front();
  }
  this->Gestures.erase(std::remove_if(this->Gestures.begin(), this->Gestures.end(),
                         [t](const LiveGesture& g) { return g.Sync.End < t; }),
    this->Gestures.end());
  this->Cues.erase(std::remove_if(this->Cues.begin(), this->Cues.end(),
                     [t](const LiveCue& c) { return c.Sync.End < t; }),
    this->Cues.end());
  this->Utterances.erase(std::remove_if(this->Utterances.begin(), this->Utterances.end(),
                           [t](const LiveUtterance& u)
                           {
                             // Kept ForgetAfter longer: GetSpeechTiming still answers.
                             return std::min(u.End, u.Cut + StopFade) < t - ForgetAfter;
                           }),
    this->Utterances.end());
  this->MoodTrack.ForgetBefore(t);
  this->EyeGazeTrack.ForgetBefore(t);
  this->HeadGazeTrack.ForgetBefore(t);
}

double LiveBehavior::BlinkRateFactor(double t) const
{
  MoodEffect::Vector mood;
  this->MoodTrack.Evaluate(t, mood.data());
  double factor = mood[MoodEffect::BlinkRate];
  for (const LiveUtterance& u : this->Utterances)
  {
    if (t >= u.Start && t < std::min(u.End, u.Cut))
    {
      factor *= this->Parameters.BlinkRateSpeaking / this->Parameters.BlinkRateRest;
      break;
    }
  }
  return factor;
}

// ------------------------------------------------------------------ sampling

void LiveBehavior::Sample(double t, std::vector<double>& out)
{
  out.resize(this->ChannelNames.size());
  this->Sample(t, out.data());
}

void LiveBehavior::Sample(double t, double* out)
{
  if (!std::isfinite(t) || t < 0.0 || t > MaxLiveTime)
  {
    throw InputError("LiveBehavior: sample time is not a finite time in [0, 10^9] seconds");
  }
  if (this->Sampled && t < this->LastTime)
  {
    throw InputError("LiveBehavior: sample times must not decrease");
  }
  this->Sampled = true;
  this->LastTime = t;
  this->SynthesizeAhead(t);
  this->Extend(t + Lookahead);
  this->Forget(t);

  const BehaviorParameters& p = this->Parameters;
  const size_t channels = this->ChannelNames.size();
  std::fill(out, out + channels, 0.0);
  Blackboard bb;

  // Background: the mood.
  MoodEffect::Vector mood;
  this->MoodTrack.Evaluate(t, mood.data());
  for (int s = 0; s < Blackboard::NumberOfShapes; ++s)
  {
    bb.Background[s] += mood[MoodEffect::Shape0 + s];
  }
  for (int a = 0; a < 3; ++a)
  {
    bb.HeadBackground[a] += mood[MoodEffect::HeadYaw + a];
  }

  // Background: idle behaviour.
  double smile = 0.0;
  for (const IdleSmileEvent& e : this->SmileEvents)
  {
    const double x = (t - e.Start) / e.Duration;
    if (x > 0.0 && x < 1.0)
    {
      smile = std::max(smile, e.Intensity * Smoothstep(std::min(x, 1.0 - x) / 0.4));
    }
  }
  bb.Background[C::MouthSmile] += smile * std::max(0.0, mood[MoodEffect::IdleSmiles]);
  this->Head.Evaluate(t, bb.HeadIdle.data());
  for (double& h : bb.HeadIdle)
  {
    h *= mood[MoodEffect::HeadMotion];
  }
  {
    double yaw = 0.0, pitch = 0.0;
    for (auto it = this->SaccadeEvents.rbegin(); it != this->SaccadeEvents.rend(); ++it)
    {
      if (it->Start <= t)
      {
        const double a = it->Duration > 0.0 ? Smoothstep((t - it->Start) / it->Duration) : 1.0;
        yaw = it->FromYaw + a * (it->ToYaw - it->FromYaw);
        pitch = it->FromPitch + a * (it->ToPitch - it->FromPitch);
        break;
      }
    }
    // Where the mood rests the eyes, plus the idle saccades (both pause during a look).
    bb.Saccade = { yaw + mood[MoodEffect::GazeYaw], pitch + mood[MoodEffect::GazePitch] };
  }
  const double blinkLength = BlinkLength(p);
  for (LiveBlink& b : this->Blinks)
  {
    if (b.Start > t)
    {
      break;
    }
    if (b.Decided < 0)
    {
      // Thinning decides once, at the blink's start: the rest train is thinned when the
      // rate falls below the rest rate, the extra train fills in above it.
      const double factor = this->BlinkRateFactor(b.Start);
      const double keep = b.Source == 0
        ? std::min(1.0, factor)
        : (b.Source == 1 ? (factor - 1.0) / (this->MaxBlinkFactor - 1.0) : 1.0);
      b.Decided = b.Keep < keep ? 1 : 0;
    }
    if (b.Decided == 1 && t < b.Start + blinkLength)
    {
      bb.Blink = std::max(bb.Blink, b.Amplitude * BlinkLidCurve(p, t - b.Start));
    }
  }

  // Speech: visemes straight to the mouth channels (overlapping utterances: maximum).
  for (const LiveUtterance& u : this->Utterances)
  {
    const WeightTrack& v = u.Speech.Visemes;
    const size_t frames = v.GetNumberOfFrames();
    const double f = (t - u.Start) * v.GetFrameRate();
    if (frames == 0 || !(f >= 0.0) || f > static_cast<double>(frames - 1))
    {
      continue;
    }
    const double cut = t <= u.Cut ? 1.0 : Smoothstep((u.Cut + StopFade - t) / StopFade);
    const size_t f0 = static_cast<size_t>(f);
    const size_t f1 = std::min(f0 + 1, frames - 1);
    const double a = f - static_cast<double>(f0);
    const double* r0 = v.GetFrame(f0);
    const double* r1 = v.GetFrame(f1);
    for (size_t c = 0; c < u.ChannelMap.size(); ++c)
    {
      double& o = out[u.ChannelMap[c]];
      o = std::max(o, cut * (r0[c] + a * (r1[c] - r0[c])));
    }
  }
  double activity = 0.0;
  for (size_t c = C::NumberOfBaseChannels; c < channels; ++c)
  {
    activity += this->SilentChannel[c] ? 0.0 : out[c];
  }
  bb.SpeechActivity = activity;
  for (const LiveCue& cue : this->Cues)
  {
    bb.AddSpeechCue(cue.Kind, cue.Sync, cue.Intensity, t, p);
  }

  // Explicit gestures, and the overrides they carry (VRM 1.0 style).
  double blinkFactor = 1.0, lookFactor = 1.0;
  bool mouthOverride = false;
  this->MouthFactor.assign(channels, 1.0);
  for (const LiveGesture& g : this->Gestures)
  {
    const GestureDefinition& d = this->Library.GetGestures()[g.Definition];
    d.Contribute(g.Sync, g.Intensity, t, p, bb);
    const double w = g.Intensity * g.Sync.Envelope(t);
    blinkFactor *= OverrideFactor(d.OverrideBlink, w);
    lookFactor *= OverrideFactor(d.OverrideLookAt, w);
    if (d.OverrideMouth != OverrideMode::None && w > 0.0)
    {
      const double m = OverrideFactor(d.OverrideMouth, w);
      const std::vector<char>& mask = this->MouthMasks[g.Definition];
      for (size_t c = C::NumberOfBaseChannels; c < channels; ++c)
      {
        if (mask[c])
        {
          this->MouthFactor[c] *= m;
          mouthOverride = true;
        }
      }
    }
  }

  // Explicit gaze.
  bb.SetExplicitGaze(this->EyeGazeTrack, this->HeadGazeTrack, t);

  bb.Blink *= blinkFactor;
  bb.Saccade[0] *= lookFactor;
  bb.Saccade[1] *= lookFactor;
  bb.Resolve(p, out);
  for (int c : { C::LookUp, C::LookDown, C::LookLeft, C::LookRight })
  {
    out[c] *= lookFactor;
  }
  if (mouthOverride)
  {
    for (size_t c = C::NumberOfBaseChannels; c < channels; ++c)
    {
      out[c] *= this->MouthFactor[c];
    }
  }
  // The last defence: every command was checked where it was parsed and scheduled, but a
  // channel that still came out non-finite is neutral in this frame, never a failed frame.
  for (size_t c = 0; c < channels; ++c)
  {
    if (!std::isfinite(out[c]))
    {
      out[c] = 0.0;
      ++this->NonFiniteValues;
    }
  }
}
} // namespace morphnode
