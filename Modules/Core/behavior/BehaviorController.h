// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file BehaviorController.h
/// @brief The behaviour control of the paper's section 3: commands (speak, gesture, mood,
/// look) and unconscious idle behaviour (blinks, saccades, head micro-motion, smiles),
/// synchronized on a Blackboard, sampled as a fixed set of channels at any time.
///
/// Use: configure (seed, frame rate, duration, parameters, synthesizer), add commands (or
/// a script), Prepare(), then Sample(t, out) as often as needed, or SampleTrack() for every
/// frame (GenerateTrack() = Prepare() + SampleTrack()).
/// Prepare() fixes the channel set (the base channels, then the viseme channels of the
/// scheduled utterances) and precomputes every schedule, so Sample() is cheap, const and
/// allocation-free. Any later change needs a new Prepare() (GenerateTrack() calls it).
///
///   morphnode::BehaviorController behavior;
///   behavior.SetSeed(7);
///   behavior.SetMood("happy", 0.6, 0.0);
///   behavior.Gesture("nod", 1.0, 0.8, 0.7);
///   behavior.Prepare();
///   std::vector<double> w(behavior.GetNumberOfChannels());
///   behavior.Sample(1.25, w.data());

#include "behavior/BehaviorScript.h"
#include "behavior/BehaviorTypes.h"
#include "behavior/Frames.h"
#include "behavior/IdleSchedule.h"
#include "behavior/Timeline.h"
#include "speech/SpeechTypes.h"
#include "track/WeightTrack.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace morphnode
{
class BehaviorController
{
public:
  /// Turns text into an utterance (the speech engineers' synthesizer).
  using Synthesizer = std::function<Utterance(const std::string& text)>;
  /// Loads a phoneme file (e.g. MBROLA .pho) into an utterance.
  using PhonemeFileLoader = std::function<Utterance(const std::string& path)>;

  /// A start time that queues an utterance after the end of the last one (or at 0).
  static constexpr double AfterPrevious = -1.0;

  struct ScheduledGesture
  {
    GestureKind Kind = GestureKind::Smile;
    double Start = 0.0;
    double Duration = 0.0; ///< as requested, or the default
    double Intensity = 1.0;
    /// Its BML sync points (they depend on the parameters; rebuilt by Prepare()).
    SyncPoints Sync;
  };
  struct ScheduledUtterance
  {
    Utterance Speech;
    double Start = 0.0;
    double End = 0.0; ///< Start + the longer of Speech.Duration and the viseme track
  };

  // ---- configuration ------------------------------------------------------------------
  void SetSeed(uint64_t seed);
  uint64_t GetSeed() const { return this->Seed; }
  /// Frame rate of GenerateTrack(); InputError unless in (0, 1000].
  void SetFrameRate(double fps);
  double GetFrameRate() const { return this->FrameRate; }
  /// Length of the idle schedule and of GenerateTrack(); 0 (the default) means the end of
  /// the last command plus 1 s, at least 5 s. InputError unless in [0, MaxBehaviorTime].
  void SetDuration(double seconds);
  double GetDuration() const { return this->Duration; }
  /// InputError for non-positive rates, times or ranges.
  void SetParameters(const BehaviorParameters& parameters);
  const BehaviorParameters& GetParameters() const { return this->Parameters; }
  void SetSynthesizer(Synthesizer synthesizer);
  void SetPhonemeFileLoader(PhonemeFileLoader loader);

  // ---- commands (times in seconds; InputError for unknown names or values out of range) --
  /// Synthesizes `text` with the synthesizer (InputError if none is set) and schedules it.
  void Say(const std::string& text, double start = AfterPrevious);
  /// Schedules an utterance. InputError if one of its viseme channels is named like a base
  /// channel, or its track is malformed.
  void Speak(const Utterance& utterance, double start = AfterPrevious);
  /// Loads a phoneme file through the phoneme loader (InputError if none is set).
  void SpeakPhonemeFile(const std::string& path, double start = AfterPrevious);
  /// duration <= 0 takes the gesture's default; intensity in [0, 1].
  void Gesture(
    const std::string& name, double start, double duration = 0.0, double intensity = 1.0);
  void Gesture(GestureKind kind, double start, double duration = 0.0, double intensity = 1.0);
  /// The mood fades from its current state over `fade` seconds (< 0: MoodFadeTime).
  /// One mood at a time: the others fade out; "neutral" fades all out.
  void SetMood(const std::string& name, double intensity, double start = 0.0, double fade = -1.0);
  void SetMood(MoodKind mood, double intensity, double start = 0.0, double fade = -1.0);
  /// Looks at (yaw, pitch) degrees from `start`; back to the front after `duration`
  /// seconds, or held until the next look when duration <= 0. A look ends any earlier one.
  void LookAt(double yaw, double pitch, double start, double duration = 0.0);
  /// Removes every command (keeps the configuration).
  void ClearCommands();

  // ---- scripts -----------------------------------------------------------------------
  /// Applies a script's settings and commands; InputError prefixed with "line N: ".
  void Apply(const BehaviorScript& script);
  void LoadScript(const std::string& path);
  void ParseScript(const std::string& text);

  // ---- output ------------------------------------------------------------------------
  /// Fixes the channels and precomputes all schedules.
  void Prepare();
  bool IsPrepared() const { return this->Prepared; }
  /// The channel names in output order (valid after Prepare()).
  const std::vector<std::string>& GetChannelNames() const { return this->ChannelNames; }
  size_t GetNumberOfChannels() const { return this->ChannelNames.size(); }
  /// -1 when absent.
  int FindChannel(const std::string& name) const;
  /// The duration GenerateTrack() covers (after Prepare()).
  double GetEffectiveDuration() const { return this->EffectiveDuration; }
  /// Fills out[0 .. GetNumberOfChannels()) with the behaviour at time t (seconds).
  /// Throws InputError if not prepared since the last change.
  void Sample(double t, double* out) const;
  void Sample(double t, std::vector<double>& out) const;
  /// The frames of the prepared behaviour (behavior/Frames.h): t_i = GetFrameTime(i) =
  /// i / GetFrameRate(), i = 0 .. floor(GetEffectiveDuration() * GetFrameRate()).
  size_t GetNumberOfFrames() const;
  double GetFrameTime(size_t frame) const { return FrameTime(frame, this->FrameRate); }
  /// Samples the prepared behaviour at each of its frames. InputError if not prepared since
  /// the last change, or when the track would hold more than MaxTrackValues values.
  WeightTrack SampleTrack() const;
  /// Prepare(), then SampleTrack().
  WeightTrack GenerateTrack();

  // ---- inspection ------------------------------------------------------------------
  const std::vector<ScheduledGesture>& GetGestures() const { return this->Gestures; }
  const std::vector<ScheduledUtterance>& GetUtterances() const { return this->Utterances; }
  /// The idle schedule of the last Prepare(); its Blinks hold every blink actually played
  /// (idle, speech cues and blink gestures; blinks under closed eyes dropped).
  const IdleSchedule& GetIdleSchedule() const { return this->Idle; }

private:
  struct MoodCommand
  {
    MoodKind Mood;
    double Intensity, Start, Fade;
  };
  struct LookCommand
  {
    double Yaw, Pitch, Start, Duration;
    size_t Order;
  };
  struct ScheduledCue
  {
    NonverbalCue::Kind Kind;
    SyncPoints Sync;
    double Intensity;
  };
  void Changed() { this->Prepared = false; }
  static SyncPoints GestureSync(const ScheduledGesture& gesture, const BehaviorParameters& p);
  void AddUtterance(Utterance utterance, double start);
  void BuildChannels();
  void BuildGaze();
  void BuildBlinks(const std::vector<std::pair<double, double>>& closedEyes);

  // Configuration and commands.
  uint64_t Seed = 1;
  double FrameRate = 30.0;
  double Duration = 0.0;
  BehaviorParameters Parameters;
  Synthesizer Synthesize;
  PhonemeFileLoader LoadPhonemes;
  std::vector<ScheduledGesture> Gestures;
  std::vector<ScheduledUtterance> Utterances;
  std::vector<MoodCommand> Moods;
  std::vector<LookCommand> Looks;

  // Prepared state.
  bool Prepared = false;
  double EffectiveDuration = 0.0;
  std::vector<std::string> ChannelNames;
  std::vector<std::vector<int>> VisemeChannelMaps; ///< per utterance: its channel -> output
  std::vector<char> SilentChannel;                 ///< per output channel
  std::vector<ScheduledCue> Cues;
  IdleSchedule Idle;
  IntervalIndex GestureIndex, UtteranceIndex, CueIndex, BlinkIndex, SmileIndex;
  FadeTrack<NumberOfMoods> MoodTrack;
  FadeTrack<3> EyeGazeTrack;  ///< yaw, pitch, look ownership
  FadeTrack<2> HeadGazeTrack; ///< the head's share
};
} // namespace morphnode
