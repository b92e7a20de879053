// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file LiveBehavior.h
/// @brief The endless, streaming behaviour of a live avatar: idle blinks, saccades, smiles
/// and head micro-motion keep coming for ever without a period, and every command
/// (say, gesture, mood, look, stop) is merged into what is already scheduled without
/// rebuilding it. The finite BehaviorController and this class share the idle generators
/// (IdleSchedule.h), the blending rules (Blackboard) and the gestures and moods (the data
/// of BehaviorLibrary).
///
/// Contract:
/// - Time is seconds on the caller's clock (any origin >= 0, e.g. seconds since start).
///   Sample(t) must be called with non-decreasing t; it generates the idle behaviour lazily
///   a little ahead of t and forgets what ended before t, so memory stays bounded however
///   long it runs (GetNumberOfHeldEvents()).
/// - Commands take `now`, the time they take effect; a `now` before the last sampled time
///   is moved to it (the past is never changed). A command changes nothing outside its own
///   span (Timing): sampling the same seed with and without it gives the same weights
///   before Timing.Start and after Timing.End, except moods, whose span is open-ended.
/// - The channel set is fixed at construction: the base channels (BehaviorChannel), then
///   the viseme channels given. An utterance using another viseme channel is an InputError.
/// - Speech: Say() splits the text into chunks (SplitSpeechChunks: the first one short),
///   synthesizes only the first one at once and the others lazily, shortly before they are
///   due (within SynthesisLookahead of the end of what is synthesized), in Sample() or
///   SynthesizeAhead(). So a long text starts after one short synthesis. A new utterance
///   starts at `now` or, when speech is still scheduled, right after it (queued).
/// - Asynchronous speech (SetSynthesisPool): Say() and Sample() never synthesize on the
///   caller's thread. Say() queues the text and submits its first chunk to the pool; each
///   Sample() picks up what the pool finished (never waiting for it) and schedules it at the
///   sampled time (or later: queued speech, the say's `now`), then submits the next chunk
///   when it is due (SynthesisLookahead). Meanwhile the avatar idles. Until its first chunk
///   is ready, a text's Timing is an estimate (Final false) whose Start stays after the
///   last sampled time, so "started" is never announced before the mouth moves. A chunk
///   the pool could not synthesize (failed, waited too long, queue full) ends its text and
///   is reported by TakeSpeechErrors() with its utterance id. The synthesizer is called
///   on the pool's threads: it must be thread-safe and capture what it uses by value.
/// - Sound: TakeAudio() hands over, once, each synthesized chunk's samples with the time
///   its first sample is due (the mouth lead of the speech options is already in it).
/// - Not thread-safe: one thread commands and samples (or guard it with a mutex).
///
///   morphnode::LiveBehavior live(morphnode::SelectVisemeMap(options).GetVisemes());
///   live.SetSynthesizer([&](const std::string& s) { return morphnode::SpeakText(s, options); });
///   auto said = live.Say("Hello. How are you today?", clock.Now());
///   std::vector<double> w(live.GetChannelNames().size());
///   for (;;) { live.Sample(clock.Now(), w.data()); for (auto& a : live.TakeAudio()) play(a); }

#include "behavior/BehaviorLibrary.h"
#include "behavior/BehaviorTypes.h"
#include "behavior/IdleSchedule.h"
#include "behavior/Timeline.h"
#include "speech/SpeechTypes.h"
#include "speech/SynthesisPool.h"

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
/// Splits a text for chunked synthesis: at sentence ends (. ! ? ; and line breaks), and a
/// piece longer than `maxChars` also at commas or, failing that, blanks. The first chunk is
/// cut further (at a comma or blank) to at most `firstMaxChars` so that speech starts
/// quickly. Chunks keep their punctuation, are trimmed, never empty; concatenated with
/// blanks they give the text's words in order. An empty or blank text gives no chunk.
std::vector<std::string> SplitSpeechChunks(
  const std::string& text, size_t firstMaxChars = 60, size_t maxChars = 200);

class LiveBehavior
{
public:
  /// Turns text into an utterance (e.g. SpeakText with the avatar's speech options).
  using Synthesizer = std::function<Utterance(const std::string& text)>;

  /// Seconds ahead of the last sampled time that idle events are generated.
  static constexpr double Lookahead = 1.0;
  /// The next chunk of a Say() is synthesized once what is synthesized ends within this
  /// many seconds of the sampled time.
  static constexpr double SynthesisLookahead = 2.0;
  /// Seconds over which StopSpeaking() fades the mouth out.
  static constexpr double StopFade = 0.12;
  /// Seconds of speech per character of text, the estimate of a text's length until its
  /// first chunk is synthesized (then the chunk's own figure is used).
  static constexpr double DefaultSecondsPerChar = 0.07;
  /// Events are forgotten this many seconds after they ended (GetBlinkStarts, GetSaccades
  /// still see them).
  static constexpr double ForgetAfter = 2.0;
  /// The latest time accepted (about 31 years).
  static constexpr double MaxLiveTime = 1e9;

  /// The span of a command on the caller's clock. Id numbers utterances (Say/Speak) from 1;
  /// 0 for other commands. For a Say() whose later chunks are not synthesized yet, End is
  /// an estimate (Final false): GetSpeechTiming(Id) gives the exact one once known.
  struct Timing
  {
    double Start = 0.0;
    double End = 0.0;
    uint64_t Id = 0;
    bool Final = true;
  };
  /// One synthesized chunk's sound: play Samples so that sample 0 sounds at Start.
  struct AudioSegment
  {
    uint64_t Id = 0; ///< the utterance's Timing::Id
    double Start = 0.0;
    int SampleRate = 22050;
    std::vector<int16_t> Samples;
  };

  /// InputError for parameters out of range (BehaviorController::SetParameters' checks),
  /// a viseme channel named like a base channel, or duplicate viseme channels.
  explicit LiveBehavior(const std::vector<std::string>& visemeChannels,
    const BehaviorParameters& parameters = BehaviorParameters(), uint64_t seed = 1,
    const BehaviorLibrary& library = BehaviorLibrary::Default());

  /// A text of an utterance that could not be spoken (e.g. its synthesis failed or waited
  /// too long in the pool): Id is the utterance's Timing::Id.
  struct SpeechError
  {
    uint64_t Id = 0;
    std::string Message;
    /// The pool was too busy (the chunk waited too long, or its queue was full); false:
    /// synthesis itself failed.
    bool Busy = false;
  };

  ~LiveBehavior();
  LiveBehavior(const LiveBehavior&) = default;
  LiveBehavior& operator=(const LiveBehavior&) = default;
  LiveBehavior(LiveBehavior&&) = default;
  LiveBehavior& operator=(LiveBehavior&&) = default;

  void SetSynthesizer(Synthesizer synthesizer);
  /// Synthesizes on the pool's threads from now on (see the contract); nullptr: on the
  /// caller's thread (the default). Set it before the first Say().
  void SetSynthesisPool(std::shared_ptr<SynthesisPool> pool);
  const std::shared_ptr<SynthesisPool>& GetSynthesisPool() const { return this->Pool; }
  /// The base channels, then the viseme channels, fixed at construction.
  const std::vector<std::string>& GetChannelNames() const { return this->ChannelNames; }
  size_t GetNumberOfChannels() const { return this->ChannelNames.size(); }
  const BehaviorParameters& GetParameters() const { return this->Parameters; }
  const BehaviorLibrary& GetLibrary() const { return this->Library; }
  uint64_t GetSeed() const { return this->Seed; }

  // ---- commands (InputError for unknown names, values out of range, no synthesizer) ----
  /// Synthesizes the first chunk now (with a pool: submits it) and queues the speech (see
  /// the contract above). With a pool, InputError also when its queue is full.
  Timing Say(const std::string& text, double now);
  /// The same with another synthesizer for this text's chunks (e.g. another voice).
  Timing Say(const std::string& text, double now, const Synthesizer& synthesizer);
  /// Schedules a ready utterance (queued after the scheduled speech, like Say).
  Timing Speak(const Utterance& utterance, double now);
  /// A gesture of the library from `now`; intensity in [0, 1]; duration <= 0: its default.
  Timing Gesture(
    const std::string& name, double now, double intensity = 1.0, double duration = 0.0);
  /// Fades to the mood (intensity in [0, 1]) over MoodFadeTime from `now`; one mood at a
  /// time, "neutral" fades every mood out. Span: [now, infinity) (End = now + fade).
  Timing SetMood(const std::string& name, double intensity, double now);
  /// Looks at (yaw, pitch) degrees; back to the front after `duration` seconds, or held
  /// until the next look when duration <= 0. A look ends any earlier one.
  Timing LookAt(double yawDeg, double pitchDeg, double now, double duration = 0.0);
  /// Ends all speech at `now`: the mouth fades out over StopFade, queued and unsynthesized
  /// chunks are dropped, audio not yet taken is discarded. The caller stops its own sound.
  void StopSpeaking(double now);

  // ---- output -------------------------------------------------------------------------
  /// Fills out[0 .. GetNumberOfChannels()) with the behaviour at t. InputError when t is
  /// not finite or smaller than the previous sampled time.
  void Sample(double t, double* out);
  void Sample(double t, std::vector<double>& out);
  /// Synthesizes the chunks due by `now` + SynthesisLookahead (Sample() does it too). With
  /// a pool: schedules the chunks it finished and submits the next one due; never waits.
  void SynthesizeAhead(double now);
  /// The sound of the chunks synthesized since the last call (take it regularly: it is
  /// held until taken).
  std::vector<AudioSegment> TakeAudio();
  /// Errors of chunks synthesized in Sample()/SynthesizeAhead() since the last call (the
  /// rest of that text is dropped); the first chunk's errors are thrown by Say().
  std::vector<std::string> TakeErrors();
  /// The same errors with the utterance each ended (TakeErrors and this share one list).
  std::vector<SpeechError> TakeSpeechErrors();
  /// True while a chunk is with the synthesis pool (submitted, not yet picked up).
  bool IsSynthesizing() const;

  // ---- inspection ---------------------------------------------------------------------
  /// The current timing of an utterance (exact once Final); Id 0 when unknown (forgotten
  /// ForgetAfter seconds after its end).
  Timing GetSpeechTiming(uint64_t id) const;
  /// True while speech is scheduled at or after t (including unsynthesized chunks).
  bool IsSpeaking(double t) const;
  /// The end of all scheduled speech (an estimate while chunks wait for synthesis).
  double GetSpeechEnd() const;
  double GetLastSampleTime() const { return this->LastTime; }
  /// Channel values Sample() found non-finite and set to 0 (none: every command's values
  /// are checked; a count above 0 is a bug to report, the frame still renders).
  size_t GetNumberOfNonFiniteValues() const { return this->NonFiniteValues; }
  /// Events held in memory (blinks, saccades, smiles, gestures, utterances, fade keys,
  /// pending chunks): bounded over any run without commands piling up.
  size_t GetNumberOfHeldEvents() const;
  /// The blinks actually played so far whose start is in [from, to) and not yet forgotten
  /// (idle and speech-rate blinks after thinning, speech cues and blink gestures; blinks
  /// blocked by an override are not counted). For studies and tests.
  std::vector<double> GetBlinkStarts(double from, double to) const;
  /// The idle saccades started in [from, to), up to the last sampled time, not yet forgotten.
  std::vector<SaccadeEvent> GetSaccades(double from, double to) const;

private:
  struct LiveBlink
  {
    double Start;
    double Amplitude;
    double Keep;      ///< uniform draw: kept when below the rate ratio at Start
    int Source;       ///< 0 rest train, 1 extra train, 2 blink gesture, 3 speech cue
    int Decided = -1; ///< -1 until sampled at its start, then 1 played, 0 thinned out
  };
  struct LiveGesture
  {
    int Definition; ///< index into the library's gestures
    double Intensity;
    SyncPoints Sync;
  };
  struct LiveUtterance
  {
    uint64_t Id;
    Utterance Speech; ///< visemes only (audio handed over, phonemes and cues dropped)
    double Start, End;
    double Cut; ///< StopSpeaking time (infinity when not cut)
    std::vector<int> ChannelMap;
  };
  struct PendingSpeech
  {
    uint64_t Id;
    std::vector<std::string> Chunks; ///< not yet synthesized, in order
    double SecondsPerChar;           ///< from the first chunk, for the estimate
    Synthesizer Synthesize;          ///< the one the text was said with
    /// With a pool: the chunk being synthesized (taken out of Chunks), its estimated
    /// seconds, and the earliest start of the text (the say's `now`).
    std::shared_ptr<SynthesisJob> Job = nullptr;
    double JobSeconds = 0.0;
    size_t JobChars = 0;
    double NotBefore = 0.0;
  };
  struct LiveCue
  {
    NonverbalCue::Kind Kind;
    SyncPoints Sync;
    double Intensity;
  };

  double ClampNow(double now) const;
  double ExtraBlinkMean() const;
  void InsertBlink(const LiveBlink& blink);
  void Extend(double horizon);
  void Forget(double t);
  double BlinkRateFactor(double t) const;
  double ScheduledSpeechEnd() const;
  void SynthesizeNext();
  void PumpSynthesis(double now);
  void FailSpeech(uint64_t id, const std::string& message, bool busy = false);
  static double PendingSeconds(const PendingSpeech& p);
  void SynthesizeAll();
  Timing AddUtterance(uint64_t id, Utterance utterance, double now);

  BehaviorParameters Parameters;
  uint64_t Seed;
  BehaviorLibrary Library;
  Synthesizer Synthesize;
  std::shared_ptr<SynthesisPool> Pool;
  double SecondsPerChar = DefaultSecondsPerChar; ///< of the last chunk synthesized
  std::vector<std::string> ChannelNames;
  std::vector<char> SilentChannel;
  std::vector<std::vector<char>> MouthMasks; ///< per gesture: viseme channels it overrides
  std::vector<double> MouthFactor;           ///< per channel, scratch of Sample()
  double LastTime = 0.0;
  bool Sampled = false;
  size_t NonFiniteValues = 0;

  // Idle generators (shared with IdleSchedule::Generate) and their held events.
  BlinkTrain RestBlinks;
  BehaviorRandom BlinkKeep, ExtraBlinks;
  double MaxBlinkFactor = 1.0; ///< the fastest blink rate a mood and speech ask, / rest rate
  double NextExtraBlink = 0.0;
  SaccadeTrain Saccades;
  SmileTrain Smiles;
  HeadMicroMotion Head;
  std::deque<LiveBlink> Blinks; ///< sorted by start
  std::deque<SaccadeEvent> SaccadeEvents;
  std::deque<IdleSmileEvent> SmileEvents;

  // Commands.
  std::deque<LiveGesture> Gestures;
  std::deque<LiveUtterance> Utterances;
  std::deque<LiveCue> Cues;
  std::deque<PendingSpeech> Pending;
  std::vector<AudioSegment> Audio;
  std::vector<SpeechError> Errors;
  uint64_t NextId = 1;
  FadeTrack<MoodEffect::Size> MoodTrack;
  FadeTrack<3> EyeGazeTrack;  ///< yaw, pitch, look ownership
  FadeTrack<2> HeadGazeTrack; ///< the head's share
};
} // namespace morphnode
