// SPDX-License-Identifier: BSD-3-Clause
#include "stream/StreamSession.h"

#include "audio/Resample.h"
#include "base/Error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#ifdef MORPHNODE_HAVE_OPUS
#include <opus.h>
#endif

namespace morphnode
{
namespace stream
{
/// The optimizer of one session: the avatar's model figures, its own hysteresis history.
class StreamSession::Decision : public WeightDecision
{
public:
  explicit Decision(const TargetDistances& distances) { this->SetTargetDistances(distances); }
  const std::vector<double>& Run(const std::vector<double>& requested)
  {
    return this->Decide(requested.data(), requested.size());
  }
};

struct StreamSession::OpusState
{
#ifdef MORPHNODE_HAVE_OPUS
  OpusEncoder* Encoder = nullptr;
  ~OpusState()
  {
    if (this->Encoder)
    {
      opus_encoder_destroy(this->Encoder);
    }
  }
#endif
};

/// The SynthesizedCallback, shared with the synthesizers handed to the pool (a job may
/// outlive its session: then it calls nothing).
struct StreamSession::Notifier
{
  std::mutex Mutex;
  std::function<void()> Callback;
  void Call()
  {
    // Under the lock: a session being destroyed waits for a call in flight (the callback
    // only posts to the session's thread).
    std::lock_guard<std::mutex> lock(this->Mutex);
    if (this->Callback)
    {
      this->Callback();
    }
  }
};

DueFrames FramesDue(uint64_t next, double now, double frameSeconds, double catchUpSeconds)
{
  DueFrames d;
  d.First = next;
  if (!(frameSeconds > 0.0) || !std::isfinite(now) || now < 0.0)
  {
    d.Last = next;
    return d;
  }
  const double due = std::floor(now / frameSeconds + 1e-9);
  const uint64_t last = due < 0.0 ? 0 : static_cast<uint64_t>(due);
  d.Last = std::max(last, next); // the timer fires at the frame's time; a hair early is on time
  d.Late = last > next;
  const double keep = std::floor(std::max(catchUpSeconds, 0.0) / frameSeconds + 1e-9);
  const uint64_t oldest = d.Last - std::min<uint64_t>(d.Last, static_cast<uint64_t>(keep));
  if (oldest > d.First)
  {
    d.Skipped = oldest - d.First;
    d.First = oldest;
  }
  return d;
}

bool HasOpus()
{
#ifdef MORPHNODE_HAVE_OPUS
  return true;
#else
  return false;
#endif
}

StreamSession::StreamSession(const StreamAvatar& avatar,
  const std::vector<std::string>& visemeChannels, LiveBehavior::Synthesizer synthesizer,
  const StreamSettings& settings)
  : Avatar(avatar)
  , Settings(settings)
  , Synthesize(std::move(synthesizer))
{
  if (!(std::isfinite(settings.FrameRate) && settings.FrameRate > 0.0 &&
        settings.FrameRate <= 240.0))
  {
    throw InputError("the stream's frame rate must be in (0, 240]");
  }
  if (settings.SampleRate < 8000 || settings.SampleRate > 48000)
  {
    throw InputError("the stream's sample rate must be in [8000, 48000]");
  }
  if (settings.PcmChunkMs < 10 || settings.PcmChunkMs > 1000)
  {
    throw InputError("a PCM chunk must be 10 to 1000 ms");
  }
  if (settings.Codec == AudioCodec::Opus)
  {
    const int r = settings.SampleRate;
    if (r != 8000 && r != 12000 && r != 16000 && r != 24000 && r != 48000)
    {
      throw InputError("Opus needs a sample rate of 8000, 12000, 16000, 24000 or 48000 Hz");
    }
#ifdef MORPHNODE_HAVE_OPUS
    this->Opus = std::make_unique<OpusState>();
    int error = 0;
    this->Opus->Encoder = opus_encoder_create(r, 1, OPUS_APPLICATION_VOIP, &error);
    if (error != OPUS_OK || !this->Opus->Encoder)
    {
      throw InputError(std::string("the Opus encoder cannot start: ") + opus_strerror(error));
    }
    opus_encoder_ctl(this->Opus->Encoder, OPUS_SET_BITRATE(24000));
#else
    throw InputError("this build has no Opus encoder (libopus-dev); ask for pcm16");
#endif
  }
  this->Live = std::make_unique<LiveBehavior>(visemeChannels, settings.Behavior, settings.Seed);
  this->Synthesized = std::make_shared<Notifier>();
  if (this->Synthesize)
  {
    this->Live->SetSynthesizer(this->Notifying(this->Synthesize));
  }
  this->Optimizer = std::make_unique<Decision>(avatar.GetModel().GetTargetDistances());
  this->Optimizer->SetWeightMode(WeightMode::Relative);
  this->Optimizer->SetOptimizerSettings(settings.Optimizer);
  this->Channels.assign(this->Live->GetNumberOfChannels(), 0.0);
  this->Requested.assign(avatar.GetTargetNames().size() + 1, 0.0);
}

StreamSession::~StreamSession()
{
  std::lock_guard<std::mutex> lock(this->Synthesized->Mutex);
  this->Synthesized->Callback = nullptr; // jobs still in the pool call nothing
}

LiveBehavior::Synthesizer StreamSession::Notifying(LiveBehavior::Synthesizer synthesizer) const
{
  return
    [synthesizer = std::move(synthesizer), notifier = this->Synthesized](const std::string& text)
  {
    // In a pool's job: wake the session once the job is final (SynthesisPool::WhenFinished).
    SynthesisPool::WhenFinished([notifier]() { notifier->Call(); });
    return synthesizer(text);
  };
}

void StreamSession::SetSynthesizedCallback(std::function<void()> callback)
{
  std::lock_guard<std::mutex> lock(this->Synthesized->Mutex);
  this->Synthesized->Callback = std::move(callback);
}

bool StreamSession::PickUp(double now)
{
  if (!this->Live->IsSynthesizing() || now <= this->LastTime)
  {
    return false;
  }
  this->Live->SynthesizeAhead(now);
  std::vector<LiveBehavior::AudioSegment> ready = this->Live->TakeAudio();
  if (ready.empty())
  {
    return false;
  }
  // The frame first (a page shows the mouth once it has it), then the sound (Tick).
  this->Held = std::move(ready);
  this->Tick(now);
  return true;
}

void StreamSession::SetSynthesisPool(std::shared_ptr<SynthesisPool> pool)
{
  this->Live->SetSynthesisPool(std::move(pool));
}

std::vector<LiveBehavior::SpeechError> StreamSession::TakeSpeechErrors()
{
  for (LiveBehavior::SpeechError& e : this->Live->TakeSpeechErrors())
  {
    this->SpeechErrors.push_back(std::move(e));
  }
  std::vector<LiveBehavior::SpeechError> out;
  out.swap(this->SpeechErrors);
  return out;
}

std::string StreamSession::Header(const std::string& sessionId, const std::string& avatarUrl) const
{
  StreamHeader h;
  h.Session = sessionId;
  h.FrameRate = this->Settings.FrameRate;
  h.SampleRate = this->Settings.SampleRate;
  h.Codec = this->Settings.Codec;
  h.Targets = this->Avatar.GetTargetNames();
  h.Rotations = this->Avatar.GetRotationNames();
  h.Avatar = avatarUrl;
  return FormatHeader(h);
}

uint32_t StreamSession::SampleOf(double t) const
{
  const double s = std::round(std::max(t, 0.0) * this->Settings.SampleRate);
  return s >= 4294967295.0 ? 4294967295u : static_cast<uint32_t>(s);
}

void StreamSession::Tick(double t)
{
  t = std::max(t, this->LastTime);
  this->LastTime = t;
  this->Live->Sample(t, this->Channels.data());
  this->Avatar.Map(this->Channels.data(), this->Weights, this->Rotations, this->Scratch);
  // The optimizer on the model's targets (neutral first, relative weights).
  std::copy(this->Weights.begin(), this->Weights.end(), this->Requested.begin() + 1);
  this->Requested[0] = 0.0;
  const std::vector<double>& effective = this->Optimizer->Run(this->Requested);
  Frame f;
  f.Sample = this->SampleOf(t);
  for (size_t k = 0; k < this->Weights.size(); ++k)
  {
    const uint8_t q = QuantizeWeight(effective[k + 1]);
    if (q > 0)
    {
      f.Targets.emplace_back(static_cast<uint8_t>(k), q);
    }
  }
  this->SentRotations.resize(this->Rotations.size());
  // The deadband in quantized units: a turn by angle a changes a component by at most
  // sin(a / 2) ~ a / 2.
  const double deadband =
    this->Settings.RotationDeadband * 3.14159265358979323846 / 360.0 * RotationScale;
  for (size_t r = 0; r < this->Rotations.size(); ++r)
  {
    const auto q = QuantizeRotation(this->Rotations[r]);
    int change = 0;
    for (int c = 0; c < 3; ++c)
    {
      change = std::max(change, std::abs(static_cast<int>(q[c]) - this->SentRotations[r][c]));
    }
    if (!this->RotationsSent || change > deadband)
    {
      f.Rotations.emplace_back(static_cast<uint8_t>(r), q);
      this->SentRotations[r] = q;
    }
  }
  this->RotationsSent = true;
  std::vector<uint8_t> bytes = EncodeFrame(f);
  this->FrameBytes += bytes.size();
  ++this->Frames;
  this->Outbox.push_back(std::move(bytes));
  this->Last = std::move(f);
  this->TakeAudio();
}

std::vector<std::vector<uint8_t>> StreamSession::TakeMessages()
{
  std::vector<std::vector<uint8_t>> out;
  out.swap(this->Outbox);
  return out;
}

void StreamSession::TakeAudio()
{
  std::vector<LiveBehavior::AudioSegment> segments;
  segments.swap(this->Held);
  for (LiveBehavior::AudioSegment& segment : this->Live->TakeAudio())
  {
    segments.push_back(std::move(segment));
  }
  for (const LiveBehavior::AudioSegment& segment : segments)
  {
    if (this->SoundStarts.size() < 256)
    {
      this->SoundStarts.emplace(segment.Id, segment.Start); // the first segment's start
    }
    this->QueueAudio(segment);
  }
}

void StreamSession::QueueAudio(const LiveBehavior::AudioSegment& segment)
{
  if (segment.Samples.empty())
  {
    return;
  }
  AudioBuffer in;
  in.SampleRate = segment.SampleRate;
  in.Channels = 1;
  in.Samples.resize(segment.Samples.size());
  for (size_t i = 0; i < segment.Samples.size(); ++i)
  {
    in.Samples[i] = segment.Samples[i] / 32768.0f;
  }
  const AudioBuffer out = Resample(in, this->Settings.SampleRate, ResampleQuality::Medium);
  std::vector<int16_t> pcm(out.Samples.size());
  for (size_t i = 0; i < pcm.size(); ++i)
  {
    pcm[i] = static_cast<int16_t>(
      std::lround(std::clamp(out.Samples[i], -1.0f, 32767.0f / 32768.0f) * 32768.0f));
  }
  const uint32_t first = this->SampleOf(segment.Start);
  const size_t chunk = this->Settings.Codec == AudioCodec::Opus
    ? static_cast<size_t>(this->Settings.SampleRate / 50)
    : static_cast<size_t>(this->Settings.SampleRate) *
      static_cast<size_t>(this->Settings.PcmChunkMs) / 1000;
  for (size_t begin = 0; begin < pcm.size(); begin += chunk)
  {
    const size_t n = std::min(chunk, pcm.size() - begin);
    AudioChunk a;
    a.Codec = this->Settings.Codec;
    a.Sample = first + static_cast<uint32_t>(begin);
    if (a.Codec == AudioCodec::Pcm16)
    {
      a.Frames = static_cast<uint16_t>(n);
      a.Payload.resize(2 * n);
      for (size_t i = 0; i < n; ++i)
      {
        const uint16_t v = static_cast<uint16_t>(pcm[begin + i]);
        a.Payload[2 * i] = static_cast<uint8_t>(v & 0xff);
        a.Payload[2 * i + 1] = static_cast<uint8_t>(v >> 8);
      }
    }
    else
    {
#ifdef MORPHNODE_HAVE_OPUS
      std::vector<int16_t> frame(chunk, 0); // the last packet padded with silence
      std::copy(pcm.begin() + static_cast<std::ptrdiff_t>(begin),
        pcm.begin() + static_cast<std::ptrdiff_t>(begin + n), frame.begin());
      unsigned char packet[1500];
      const int bytes = opus_encode(
        this->Opus->Encoder, frame.data(), static_cast<int>(chunk), packet, sizeof(packet));
      if (bytes < 0)
      {
        continue; // a packet lost: the client hears a gap, the session goes on
      }
      a.Frames = static_cast<uint16_t>(chunk);
      a.Payload.assign(packet, packet + bytes);
#endif
    }
    std::vector<uint8_t> message = EncodeAudio(a);
    this->AudioBytes += message.size();
    this->Outbox.push_back(std::move(message));
  }
}

dialog::Schedule StreamSession::Say(const dialog::SayCommand& c, double now)
{
  if (c.HasRecording() || !c.Timings.empty())
  {
    // (Recordings name files on the server: the command socket's external speech is the
    // window's; a stream session synthesizes its text.)
    throw InputError("a stream session speaks text only (no 'audio' or 'timings')");
  }
  LiveBehavior::Synthesizer voice;
  if (!c.Voice.empty())
  {
    if (!this->MakeVoice)
    {
      throw InputError("this server speaks with its own voice only (no 'voice' field)");
    }
    voice = this->MakeVoice(c.Voice); // InputError for a voice it does not have
    if (voice)
    {
      voice = this->Notifying(std::move(voice));
    }
  }
  if (this->Live->GetSynthesisPool())
  {
    // Nothing waits here: the pool synthesizes, Tick() schedules it when ready.
    const LiveBehavior::Timing timing =
      voice ? this->Live->Say(c.Text, now, voice) : this->Live->Say(c.Text, now);
    dialog::Schedule s(timing.Start, timing.End);
    s.Handle = timing.Id;
    return s;
  }
  const auto started = std::chrono::steady_clock::now();
  const LiveBehavior::Timing timing = voice ? this->Live->Say(c.Text, now + this->SayLead, voice)
                                            : this->Live->Say(c.Text, now + this->SayLead);
  const double took =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  // A running estimate that follows a slower machine at once and a faster one slowly.
  this->SayLead = took > this->SayLead ? std::min(took, 1.0) : 0.8 * this->SayLead + 0.2 * took;
  dialog::Schedule s(timing.Start, timing.End);
  s.Handle = timing.Id;
  for (const LiveBehavior::AudioSegment& segment : this->Live->TakeAudio())
  {
    if (segment.Id == timing.Id && std::isnan(s.Sound))
    {
      s.Sound = segment.Start;
    }
    if (this->SoundStarts.size() < 256)
    {
      this->SoundStarts.emplace(segment.Id, segment.Start);
    }
    this->QueueAudio(segment);
  }
  return s;
}

dialog::Schedule StreamSession::Gesture(const dialog::GestureCommand& c, double now)
{
  const auto timing = this->Live->Gesture(c.Name, now, c.Intensity, c.Duration);
  return dialog::Schedule(timing.Start, timing.End);
}

dialog::Schedule StreamSession::Mood(const dialog::MoodCommand& c, double now)
{
  const auto timing = this->Live->SetMood(c.Name, c.Intensity, now);
  return dialog::Schedule(timing.Start, timing.End);
}

dialog::Schedule StreamSession::LookAt(const dialog::LookAtCommand& c, double now)
{
  const auto timing = this->Live->LookAt(c.Yaw, c.Pitch, now, c.Duration);
  return dialog::Schedule(timing.Start, timing.End);
}

void StreamSession::StopSpeaking(double now)
{
  this->Live->StopSpeaking(now);
  StopMessage stop;
  stop.Sample = this->SampleOf(std::max(now, this->LastTime));
  std::vector<uint8_t> message = EncodeStop(stop);
  this->Outbox.push_back(std::move(message));
}

bool StreamSession::Refresh(unsigned long long handle, dialog::Schedule& when)
{
  const auto timing = this->Live->GetSpeechTiming(handle);
  const auto sound = this->SoundStarts.find(handle);
  if (timing.Id == 0)
  {
    if (sound != this->SoundStarts.end())
    {
      this->SoundStarts.erase(sound); // forgotten: its speech ended a while ago
    }
    return false;
  }
  // With a pool the start is known once the first chunk is ready (until then it stays
  // after the last frame, so "started" waits for the mouth).
  when.Start = timing.Start;
  when.End = timing.End;
  if (sound != this->SoundStarts.end())
  {
    when.Sound = sound->second;
  }
  return true;
}
} // namespace stream
} // namespace morphnode
