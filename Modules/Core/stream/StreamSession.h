// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file StreamSession.h
/// @brief One remote face's session: its own live behaviour (idle, moods, speech), the
/// optimizer deciding which targets each frame keeps, and the messages of the stream
/// (stream/StreamProtocol.h) it makes: a frame per Tick, the speech's sound as it is
/// synthesized, a stop when speech is cut. It is the dialog's CommandSink, so a
/// dialog::DialogSession runs the page's commands (and the command socket's) on it.
///
///   morphnode::stream::StreamSession s(avatar, visemes, synthesizer, settings);
///   morphnode::dialog::DialogSession dialog(sendEvent, s);
///   send(s.Header("a1", "/avatar.glb"));
///   every 1/fps: s.Tick(t); for (auto& m : s.TakeMessages()) send(m); dialog.Advance(t);
///
/// Time t is seconds since the session started, on the stream's audio clock: sample
/// round(t * SampleRate). Not thread-safe: one thread (or strand) per session.

#include "behavior/LiveBehavior.h"
#include "dialog/DialogSession.h"
#include "morph/WeightDecision.h"
#include "stream/StreamAvatar.h"
#include "stream/StreamProtocol.h"

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
namespace stream
{
struct StreamSettings
{
  double FrameRate = 30.0;
  /// The audio clock; Opus needs 8000, 12000, 16000, 24000 or 48000.
  int SampleRate = 24000;
  AudioCodec Codec = AudioCodec::Pcm16;
  /// The optimizer (MakeOptimizerSettings); Threshold 0 and no bound: every non-zero
  /// target is sent.
  OptimizerSettings Optimizer;
  /// Milliseconds of sound per PCM chunk (Opus chunks are one 20 ms packet).
  int PcmChunkMs = 100;
  /// A rotation is sent again once it turned more than this (degrees) from the one last
  /// sent: micro-motion below it is not worth its 6 bytes. 0: whenever it changes.
  double RotationDeadband = 0.1;
  BehaviorParameters Behavior;
  uint64_t Seed = 1;
};

/// True when this build can encode Opus (Debian libopus-dev found).
bool HasOpus();

/// The frames a session's frame timer sends when it fires at `now` (seconds on the
/// session's clock) and frame `next` (at next * frameSeconds) is the first not yet sent:
/// every frame from `next` up to the one due now (floor(now / frameSeconds)), but none
/// older than `catchUpSeconds` before now. A timer that fired late (a loaded machine)
/// still delivers the frames a client's jitter buffer can use instead of leaving a gap in
/// the picture; older ones it would drop anyway. First > Last: nothing is due yet.
struct DueFrames
{
  uint64_t First = 0, Last = 0;
  bool Late = false;    ///< more than one frame behind (a late tick)
  uint64_t Skipped = 0; ///< frames too old to send
};
DueFrames FramesDue(uint64_t next, double now, double frameSeconds, double catchUpSeconds);

class StreamSession : public dialog::CommandSink
{
public:
  /// InputError for bad settings (rates, an Opus rate Opus lacks, Opus without libopus).
  StreamSession(const StreamAvatar& avatar, const std::vector<std::string>& visemeChannels,
    LiveBehavior::Synthesizer synthesizer, const StreamSettings& settings);
  ~StreamSession() override;
  StreamSession(const StreamSession&) = delete;
  StreamSession& operator=(const StreamSession&) = delete;

  /// Synthesizes on the pool's threads (LiveBehavior::SetSynthesisPool): a say never
  /// blocks the session; its speech starts at the first frame after it is ready. Set it
  /// before the first say; shared by every session of a server.
  void SetSynthesisPool(std::shared_ptr<SynthesisPool> pool);
  /// Called on a pool thread whenever synthesis for this session finished (any of its
  /// chunks, any voice): e.g. to run PickUp() on the session's thread at once rather than
  /// at the next frame. Set it before the first say; it must be thread-safe.
  void SetSynthesizedCallback(std::function<void()> callback);
  /// True while speech waits for the pool.
  bool IsSynthesizing() const { return this->Live->IsSynthesizing(); }
  /// Between frames (now after the last Tick): takes what the pool finished and starts it
  /// at `now` rather than at the next frame, with a frame at `now` (Tick(now): the frame,
  /// then the sound, for TakeMessages()). False: nothing was ready (nothing queued).
  bool PickUp(double now);
  /// Makes the synthesizer of a say's `voice` (InputError for a voice it does not have).
  /// Without it, a say with a voice is refused.
  using VoiceSynthesizers = std::function<LiveBehavior::Synthesizer(const std::string& voice)>;
  void SetVoiceSynthesizers(VoiceSynthesizers make) { this->MakeVoice = std::move(make); }

  /// The avatar file's URL for the header, when not the server's default (e.g. the file
  /// prepared for the page's device).
  void SetAvatarUrl(std::string url) { this->AvatarUrl = std::move(url); }
  const std::string& GetAvatarUrl() const { return this->AvatarUrl; }

  /// The header text message.
  std::string Header(const std::string& sessionId, const std::string& avatarUrl) const;
  const StreamSettings& GetSettings() const { return this->Settings; }
  LiveBehavior& GetBehavior() { return *this->Live; }

  /// The frame at t (behaviour sampled, mapped, optimized, quantized) and any sound
  /// synthesized meanwhile, queued for TakeMessages(). t never goes back (moved forward).
  void Tick(double t);
  /// The binary messages made since the last call, in order.
  std::vector<std::vector<uint8_t>> TakeMessages();
  /// The sample of t on the audio clock.
  uint32_t SampleOf(double t) const;

  // ---- dialog::CommandSink --------------------------------------------------------------
  /// Without a pool: synthesizes the first chunk and schedules it at now + the time
  /// synthesis takes (a running estimate, measured on every say): the client hears the
  /// sound's start rather than losing what "passed" while it was synthesized. With a pool:
  /// queues the text and returns at once (times are estimates until Refresh has them).
  dialog::Schedule Say(const dialog::SayCommand& command, double now) override;
  /// Seconds a say is scheduled after its command (the synthesis estimate).
  double GetSayLead() const { return this->SayLead; }
  dialog::Schedule Gesture(const dialog::GestureCommand& command, double now) override;
  dialog::Schedule Mood(const dialog::MoodCommand& command, double now) override;
  dialog::Schedule LookAt(const dialog::LookAtCommand& command, double now) override;
  /// Ends speech at now and queues a stop message: the client drops its queued sound and
  /// frames from then on.
  void StopSpeaking(double now) override;
  bool Refresh(unsigned long long handle, dialog::Schedule& when) override;
  /// Says whose speech could not be made (synthesis failed, waited too long for the pool,
  /// the pool's queue was full) since the last call: the say's Schedule::Handle and why.
  /// DialogSession::Fail reports them to the client.
  std::vector<LiveBehavior::SpeechError> TakeSpeechErrors();

  // ---- figures ---------------------------------------------------------------------------
  /// The last frame's weights before quantization (stream target order) and as sent.
  const std::vector<double>& GetLastWeights() const { return this->Weights; }
  const Frame& GetLastFrame() const { return this->Last; }
  uint64_t GetFrameBytes() const { return this->FrameBytes; }
  uint64_t GetAudioBytes() const { return this->AudioBytes; }
  uint64_t GetNumberOfFrames() const { return this->Frames; }

private:
  void TakeAudio();
  void QueueAudio(const LiveBehavior::AudioSegment& segment);
  /// The synthesizer, telling the SynthesizedCallback when a pool job of it is finished.
  LiveBehavior::Synthesizer Notifying(LiveBehavior::Synthesizer synthesizer) const;
  struct Notifier;
  std::shared_ptr<Notifier> Synthesized;
  VoiceSynthesizers MakeVoice;
  std::string AvatarUrl;
  std::vector<LiveBehavior::SpeechError> SpeechErrors;
  std::vector<LiveBehavior::AudioSegment> Held; ///< picked up, sent after PickUp's frame
  std::map<uint64_t, double> SoundStarts; ///< utterance id -> its sound's start (held briefly)

  const StreamAvatar& Avatar;
  StreamSettings Settings;
  std::unique_ptr<LiveBehavior> Live;
  LiveBehavior::Synthesizer Synthesize;
  class Decision;
  std::unique_ptr<Decision> Optimizer;
  std::vector<double> Channels, Weights, Requested, Scratch;
  std::vector<std::array<double, 4>> Rotations;
  std::vector<std::array<int16_t, 3>> SentRotations;
  bool RotationsSent = false;
  Frame Last;
  std::vector<std::vector<uint8_t>> Outbox;
  double LastTime = 0.0;
  double SayLead = 0.05;
  uint64_t FrameBytes = 0, AudioBytes = 0, Frames = 0;
  struct OpusState;
  std::unique_ptr<OpusState> Opus;
};
} // namespace stream
} // namespace morphnode
