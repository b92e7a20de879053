// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file BehaviorTypes.h
/// @brief The vocabulary of the behaviour control: output channels, gestures, moods, BML-like
/// sync points and the figures (blink rates, saccade law, ...) that drive idle behaviour.
///
/// Angles are in degrees, seen from the character: yaw > 0 turns to its left, pitch > 0
/// looks up, roll > 0 tilts the top of the head to its left.

#include <string>
#include <vector>

namespace morphnode
{
struct Utterance;
/// The fixed output channels, in output order. The viseme channels of scheduled
/// utterances follow them (see BehaviorController::GetChannelNames()).
struct BehaviorChannel
{
  enum Id : int
  {
    EyesClosed = 0, ///< both lids, 0..1
    BrowsUp,        ///< 0..1
    BrowsFright,    ///< inner brows raised, 0..1
    BrowsAngry,     ///< brows lowered and drawn together, 0..1
    MouthSmile,     ///< 0..1
    MouthSad,       ///< 0..1
    LookUp,         ///< gaze shapes 0..1, derived from EyeYaw/EyePitch
    LookDown,
    LookLeft,
    LookRight,
    HeadYaw, ///< degrees
    HeadPitch,
    HeadRoll,
    EyeYaw, ///< degrees, relative to the head
    EyePitch,
    NumberOfBaseChannels
  };
  /// The contract name of a base channel ("EyesClosed", ...); nullptr when out of range.
  static const char* Name(int id);
  /// All base channel names in output order.
  static const std::vector<std::string>& Names();
};

enum class GestureKind
{
  Smile,      ///< MouthSmile
  Sad,        ///< MouthSad
  Nod,        ///< head pitch down and up, one nod per ~0.5 s of duration
  Shake,      ///< head yaw left-right, one swing per ~0.4 s of duration
  Tilt,       ///< head roll
  RaiseBrows, ///< BrowsUp
  Frown,      ///< BrowsAngry
  Fright,     ///< BrowsFright
  CloseEyes,  ///< EyesClosed, held for the duration
  Blink       ///< one blink at the start, amplitude = intensity
};

/// Parses a gesture name: case-insensitive, '_' and '-' ignored, a few aliases
/// ("browsup", "angry", "afraid", ...). Throws InputError naming an unknown gesture.
GestureKind ParseGestureName(const std::string& name);
const char* GestureName(GestureKind kind);
/// Used when a gesture is given a duration <= 0 (seconds).
double DefaultGestureDuration(GestureKind kind);

enum class MoodKind
{
  Neutral,
  Happy,
  Sad,
  Angry,
  Afraid,
  Surprised
};
/// The moods that carry an intensity (all but Neutral), i.e. the mood vector's size.
constexpr int NumberOfMoods = 5;
/// Throws InputError naming an unknown mood.
MoodKind ParseMoodName(const std::string& name);
const char* MoodName(MoodKind kind);

/// BML 1.0 sync points of one behaviour (seconds, non-decreasing).
struct SyncPoints
{
  double Start = 0.0;
  double Ready = 0.0; ///< attack done
  double StrokeStart = 0.0;
  double Stroke = 0.0; ///< the most meaningful instant
  double StrokeEnd = 0.0;
  double Relax = 0.0; ///< release begins
  double End = 0.0;

  /// Attack and release are clamped so that they fit the duration together.
  static SyncPoints Make(double start, double duration, double attack, double release);
  /// Attack/hold/release envelope: smoothstep up over [Start, Ready], 1 over
  /// [Ready, Relax], smoothstep down over [Relax, End], 0 outside.
  double Envelope(double t) const;
};

/// 3x^2 - 2x^3 on x clamped to [0, 1]: a ramp with zero slope at both ends.
inline double Smoothstep(double x)
{
  x = x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
  return x * x * (3.0 - 2.0 * x);
}

/// Every figure the behaviour uses; the defaults are the published ones where there are
/// some (REFERENCE.md section 4), chosen otherwise (documented in docs/behavior.md).
struct BehaviorParameters
{
  // Blinks: log-normal intervals, rate depends on whether the character speaks.
  double BlinkRateRest = 17.0;     ///< blinks per minute at rest / listening
  double BlinkRateSpeaking = 26.0; ///< blinks per minute in conversation
  double BlinkIntervalSigma = 0.5; ///< shape of the log-normal interval distribution
  double BlinkMinInterval = 0.4;   ///< seconds; no blink starts before the last is over
  double BlinkCloseTime = 0.10;    ///< seconds, fast closing
  double BlinkClosedTime = 0.04;   ///< seconds fully closed
  double BlinkOpenTime = 0.20;     ///< seconds, slower opening

  // Saccades (Lee et al. 2002): duration = SaccadeBase + SaccadePerDegree * amplitude.
  double SaccadeBase = 0.025;        ///< seconds
  double SaccadePerDegree = 0.0024;  ///< seconds per degree
  double SaccadeMaxAmplitude = 15.0; ///< degrees; the amplitude law has a long tail
  double SaccadeRange = 10.0;        ///< degrees; idle gaze stays within this of the target
  double FixationMean = 1.2;         ///< seconds between saccades (log-normal)
  double FixationSigma = 0.6;
  double FixationMin = 0.25; ///< seconds

  // Head micro-motion: three incommensurate sines per axis, amplitudes in degrees.
  double HeadYawAmplitude = 2.0;
  double HeadPitchAmplitude = 1.5;
  double HeadRollAmplitude = 0.8;

  // Occasional smiles (Poisson events), more frequent with a happy mood.
  double IdleSmileInterval = 25.0; ///< mean seconds between idle smiles; <= 0 disables
  double IdleSmileIntensity = 0.3; ///< peak MouthSmile of an idle smile

  // Gaze.
  double HeadShareOfGaze = 0.4; ///< part of a LookAt turned by the head (the eyes do the rest)
  double HeadGazeTime = 0.45;   ///< seconds for the head to follow a LookAt
  double EyeYawRange = 30.0;    ///< degrees of EyeYaw giving LookLeft/LookRight = 1
  double EyePitchRange = 25.0;  ///< degrees of EyePitch giving LookUp/LookDown = 1

  // Head gestures: peak angles at intensity 1, degrees.
  double NodAmplitude = 10.0;      ///< pitch down per nod
  double ShakeAmplitude = 15.0;    ///< yaw each way
  double TiltAmplitude = 8.0;      ///< roll
  double SpeechNodAmplitude = 5.0; ///< a Nod cue of an utterance

  // Moods and the blackboard.
  double MoodFadeTime = 0.8;            ///< seconds (smoothstep) when a mood changes
  double SpeechExpressionDamping = 0.7; ///< MouthSmile/MouthSad *= 1 - this * speech activity
};

/// The parameters by name, for bindings and files: the field names above in declaration
/// order ("BlinkRateRest", ..., "SpeechExpressionDamping").
const std::vector<std::string>& BehaviorParameterNames();
/// The field of that name (names are matched as gestures are: case, '_' and '-' do not
/// matter). InputError naming an unknown parameter. The ranges are checked by
/// BehaviorController::SetParameters.
double GetBehaviorParameter(const BehaviorParameters& parameters, const std::string& name);
void SetBehaviorParameter(BehaviorParameters& parameters, const std::string& name, double value);
/// InputError naming the first parameter out of its range (non-positive rates, times or
/// ranges, ...): the checks of BehaviorController::SetParameters and LiveBehavior.
void CheckBehaviorParameters(const BehaviorParameters& parameters);
/// InputError "<what> <v> is outside [lo, hi]" unless lo <= v <= hi.
void CheckBehaviorRange(double v, double lo, double hi, const char* what);
/// InputError unless an utterance's viseme values are finite, its viseme track and its cues
/// lie within MaxBehaviorTime and the cues' intensities within [0, 1]: the checks both
/// BehaviorController and LiveBehavior make before scheduling one. Returns the viseme
/// track's length in seconds.
double CheckUtteranceTrack(const Utterance& utterance);
/// The index of a parameter in BehaviorParameterNames() (matched as above), -1 if none.
int FindBehaviorParameter(const std::string& name);
/// The parameter of that index (no check beyond the range: 0 for an index out of range).
double GetBehaviorParameter(const BehaviorParameters& parameters, int index);

/// A name as gestures, moods and parameters match it: lower case without '_', '-', blanks.
std::string CanonicalBehaviorName(const std::string& name);
/// Viseme channels that mean a closed, resting mouth ("sil", "silence", "X", "_", "rest",
/// "neutral", any case): they do not count as speech activity.
bool IsSilentViseme(const std::string& name);
} // namespace morphnode
