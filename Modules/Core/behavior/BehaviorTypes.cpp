// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/BehaviorTypes.h"

#include "base/Error.h"
#include "base/Text.h"
#include "behavior/BehaviorScript.h"
#include "speech/SpeechTypes.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace morphnode
{
namespace
{
const char* const ChannelNames[BehaviorChannel::NumberOfBaseChannels] = { "EyesClosed", "BrowsUp",
  "BrowsFright", "BrowsAngry", "MouthSmile", "MouthSad", "LookUp", "LookDown", "LookLeft",
  "LookRight", "HeadYaw", "HeadPitch", "HeadRoll", "EyeYaw", "EyePitch" };

/// Lower case without '_', '-' and blanks: "Raise_Brows" and "raise-brows" are one name.
std::string Canonical(const std::string& name)
{
  std::string out = text::ToLower(name);
  out.erase(
    std::remove_if(out.begin(), out.end(), [](char c) { return c == '_' || c == '-' || c == ' '; }),
    out.end());
  return out;
}

/// Quotes a user-given name for an error message, cut so that a huge input stays readable.
std::string Quoted(const std::string& name)
{
  return "'" + (name.size() > 64 ? name.substr(0, 64) + "..." : name) + "'";
}

struct Alias
{
  const char* Name;
  int Value;
};

const Alias GestureAliases[] = { { "smile", int(GestureKind::Smile) },
  { "sad", int(GestureKind::Sad) }, { "nod", int(GestureKind::Nod) },
  { "shake", int(GestureKind::Shake) }, { "headshake", int(GestureKind::Shake) },
  { "tilt", int(GestureKind::Tilt) }, { "raisebrows", int(GestureKind::RaiseBrows) },
  { "browsup", int(GestureKind::RaiseBrows) }, { "browraise", int(GestureKind::RaiseBrows) },
  { "raiseeyebrows", int(GestureKind::RaiseBrows) }, { "frown", int(GestureKind::Frown) },
  { "browsangry", int(GestureKind::Frown) }, { "fright", int(GestureKind::Fright) },
  { "browsfright", int(GestureKind::Fright) }, { "closeeyes", int(GestureKind::CloseEyes) },
  { "eyesclosed", int(GestureKind::CloseEyes) }, { "blink", int(GestureKind::Blink) } };

const Alias MoodAliases[] = { { "neutral", int(MoodKind::Neutral) },
  { "happy", int(MoodKind::Happy) }, { "joy", int(MoodKind::Happy) }, { "sad", int(MoodKind::Sad) },
  { "sadness", int(MoodKind::Sad) }, { "angry", int(MoodKind::Angry) },
  { "anger", int(MoodKind::Angry) }, { "afraid", int(MoodKind::Afraid) },
  { "fear", int(MoodKind::Afraid) }, { "surprised", int(MoodKind::Surprised) },
  { "surprise", int(MoodKind::Surprised) } };
} // namespace

const char* BehaviorChannel::Name(int id)
{
  return id >= 0 && id < NumberOfBaseChannels ? ChannelNames[id] : nullptr;
}

const std::vector<std::string>& BehaviorChannel::Names()
{
  static const std::vector<std::string> names(ChannelNames, ChannelNames + NumberOfBaseChannels);
  return names;
}

GestureKind ParseGestureName(const std::string& name)
{
  const std::string key = Canonical(name);
  for (const auto& a : GestureAliases)
  {
    if (key == a.Name)
    {
      return static_cast<GestureKind>(a.Value);
    }
  }
  throw InputError("unknown gesture " + Quoted(name) +
    " (known: smile, sad, nod, shake, tilt, raise_brows, frown, fright, close_eyes, blink)");
}

const char* GestureName(GestureKind kind)
{
  switch (kind)
  {
    case GestureKind::Smile:
      return "smile";
    case GestureKind::Sad:
      return "sad";
    case GestureKind::Nod:
      return "nod";
    case GestureKind::Shake:
      return "shake";
    case GestureKind::Tilt:
      return "tilt";
    case GestureKind::RaiseBrows:
      return "raise_brows";
    case GestureKind::Frown:
      return "frown";
    case GestureKind::Fright:
      return "fright";
    case GestureKind::CloseEyes:
      return "close_eyes";
    case GestureKind::Blink:
      return "blink";
  }
  return "?";
}

double DefaultGestureDuration(GestureKind kind)
{
  switch (kind)
  {
    case GestureKind::Nod:
      return 0.8;
    case GestureKind::Shake:
      return 1.2;
    case GestureKind::Blink:
      return 0.35;
    case GestureKind::RaiseBrows:
      return 1.0;
    case GestureKind::CloseEyes:
      return 2.0;
    default:
      return 1.5;
  }
}

MoodKind ParseMoodName(const std::string& name)
{
  const std::string key = Canonical(name);
  for (const auto& a : MoodAliases)
  {
    if (key == a.Name)
    {
      return static_cast<MoodKind>(a.Value);
    }
  }
  throw InputError(
    "unknown mood " + Quoted(name) + " (known: neutral, happy, sad, angry, afraid, surprised)");
}

const char* MoodName(MoodKind kind)
{
  switch (kind)
  {
    case MoodKind::Neutral:
      return "neutral";
    case MoodKind::Happy:
      return "happy";
    case MoodKind::Sad:
      return "sad";
    case MoodKind::Angry:
      return "angry";
    case MoodKind::Afraid:
      return "afraid";
    case MoodKind::Surprised:
      return "surprised";
  }
  return "?";
}

SyncPoints SyncPoints::Make(double start, double duration, double attack, double release)
{
  duration = std::max(0.0, duration);
  attack = std::max(0.0, attack);
  release = std::max(0.0, release);
  if (attack + release > duration && attack + release > 0.0)
  {
    const double scale = duration / (attack + release);
    attack *= scale;
    release *= scale;
  }
  SyncPoints s;
  s.Start = start;
  s.End = start + duration;
  s.Ready = s.StrokeStart = start + attack;
  s.Relax = s.StrokeEnd = std::max(s.Ready, s.End - release);
  s.Stroke = 0.5 * (s.StrokeStart + s.StrokeEnd);
  return s;
}

double SyncPoints::Envelope(double t) const
{
  if (!(t >= this->Start) || !(t <= this->End))
  {
    return 0.0;
  }
  if (t < this->Ready)
  {
    return Smoothstep((t - this->Start) / (this->Ready - this->Start));
  }
  if (t <= this->Relax)
  {
    return 1.0;
  }
  return Smoothstep((this->End - t) / (this->End - this->Relax));
}

// ------------------------------------------------------------------ parameters by name

namespace
{
struct ParameterField
{
  const char* Name;
  double BehaviorParameters::*Field;
};

#define MORPHNODE_PARAMETER(name)                                                                  \
  {                                                                                                \
#name, &BehaviorParameters::name                                                               \
  }
const ParameterField ParameterFields[] = { MORPHNODE_PARAMETER(BlinkRateRest),
  MORPHNODE_PARAMETER(BlinkRateSpeaking), MORPHNODE_PARAMETER(BlinkIntervalSigma),
  MORPHNODE_PARAMETER(BlinkMinInterval), MORPHNODE_PARAMETER(BlinkCloseTime),
  MORPHNODE_PARAMETER(BlinkClosedTime), MORPHNODE_PARAMETER(BlinkOpenTime),
  MORPHNODE_PARAMETER(SaccadeBase), MORPHNODE_PARAMETER(SaccadePerDegree),
  MORPHNODE_PARAMETER(SaccadeMaxAmplitude), MORPHNODE_PARAMETER(SaccadeRange),
  MORPHNODE_PARAMETER(FixationMean), MORPHNODE_PARAMETER(FixationSigma),
  MORPHNODE_PARAMETER(FixationMin), MORPHNODE_PARAMETER(HeadYawAmplitude),
  MORPHNODE_PARAMETER(HeadPitchAmplitude), MORPHNODE_PARAMETER(HeadRollAmplitude),
  MORPHNODE_PARAMETER(IdleSmileInterval), MORPHNODE_PARAMETER(IdleSmileIntensity),
  MORPHNODE_PARAMETER(HeadShareOfGaze), MORPHNODE_PARAMETER(HeadGazeTime),
  MORPHNODE_PARAMETER(EyeYawRange), MORPHNODE_PARAMETER(EyePitchRange),
  MORPHNODE_PARAMETER(NodAmplitude), MORPHNODE_PARAMETER(ShakeAmplitude),
  MORPHNODE_PARAMETER(TiltAmplitude), MORPHNODE_PARAMETER(SpeechNodAmplitude),
  MORPHNODE_PARAMETER(MoodFadeTime), MORPHNODE_PARAMETER(SpeechExpressionDamping) };
#undef MORPHNODE_PARAMETER
// Every field is in the table (all fields are doubles).
static_assert(sizeof(ParameterFields) / sizeof(ParameterFields[0]) * sizeof(double) ==
    sizeof(BehaviorParameters),
  "BehaviorParameters has a field that is not in ParameterFields");

const ParameterField& FindParameter(const std::string& name)
{
  const std::string key = Canonical(name);
  for (const ParameterField& p : ParameterFields)
  {
    if (Canonical(p.Name) == key)
    {
      return p;
    }
  }
  throw InputError("unknown behaviour parameter " + Quoted(name));
}
} // namespace

const std::vector<std::string>& BehaviorParameterNames()
{
  static const std::vector<std::string> names = []
  {
    std::vector<std::string> out;
    for (const ParameterField& p : ParameterFields)
    {
      out.emplace_back(p.Name);
    }
    return out;
  }();
  return names;
}

double GetBehaviorParameter(const BehaviorParameters& parameters, const std::string& name)
{
  return parameters.*(FindParameter(name).Field);
}

void SetBehaviorParameter(BehaviorParameters& parameters, const std::string& name, double value)
{
  parameters.*(FindParameter(name).Field) = value;
}
} // namespace morphnode

namespace morphnode
{
int FindBehaviorParameter(const std::string& name)
{
  const std::string key = Canonical(name);
  for (size_t i = 0; i < sizeof(ParameterFields) / sizeof(ParameterFields[0]); ++i)
  {
    if (Canonical(ParameterFields[i].Name) == key)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

double GetBehaviorParameter(const BehaviorParameters& parameters, int index)
{
  constexpr int count = static_cast<int>(sizeof(ParameterFields) / sizeof(ParameterFields[0]));
  return index >= 0 && index < count ? parameters.*(ParameterFields[index].Field) : 0.0;
}

std::string CanonicalBehaviorName(const std::string& name)
{
  return Canonical(name);
}

bool IsSilentViseme(const std::string& name)
{
  const std::string n = text::ToLower(name);
  return n == "sil" || n == "silence" || n == "x" || n == "_" || n == "rest" || n == "neutral";
}
} // namespace morphnode

namespace morphnode
{
void CheckBehaviorRange(double v, double lo, double hi, const char* what)
{
  if (!(v >= lo && v <= hi))
  {
    std::ostringstream msg;
    msg << what << " " << v << " is outside [" << lo << ", " << hi << "]";
    throw InputError(msg.str());
  }
}

double CheckUtteranceTrack(const Utterance& u)
{
  const WeightTrack& v = u.Visemes;
  for (size_t f = 0; f < v.GetNumberOfFrames(); ++f)
  {
    for (size_t c = 0; c < v.GetNumberOfChannels(); ++c)
    {
      if (!std::isfinite(v.GetValue(f, c)))
      {
        throw InputError("viseme track: a value that is not finite");
      }
    }
  }
  const double trackLength = v.GetNumberOfFrames() > 1
    ? static_cast<double>(v.GetNumberOfFrames() - 1) / v.GetFrameRate()
    : 0.0;
  CheckBehaviorRange(trackLength, 0.0, MaxBehaviorTime, "viseme track length");
  for (const auto& cue : u.Cues)
  {
    CheckBehaviorRange(cue.Start, 0.0, MaxBehaviorTime, "cue start");
    CheckBehaviorRange(cue.Duration, 0.0, MaxBehaviorTime, "cue duration");
    CheckBehaviorRange(cue.Intensity, 0.0, 1.0, "cue intensity");
  }
  return trackLength;
}

void CheckBehaviorParameters(const BehaviorParameters& p)
{
  auto CheckRange = CheckBehaviorRange;

  const double big = 1e6;
  CheckRange(p.BlinkRateRest, 0.1, 600.0, "BlinkRateRest");
  CheckRange(p.BlinkRateSpeaking, 0.1, 600.0, "BlinkRateSpeaking");
  CheckRange(p.BlinkIntervalSigma, 0.0, 3.0, "BlinkIntervalSigma");
  CheckRange(p.BlinkMinInterval, 0.0, big, "BlinkMinInterval");
  CheckRange(p.BlinkCloseTime, 0.01, 10.0, "BlinkCloseTime");
  CheckRange(p.BlinkClosedTime, 0.0, 10.0, "BlinkClosedTime");
  CheckRange(p.BlinkOpenTime, 0.01, 10.0, "BlinkOpenTime");
  CheckRange(p.SaccadeBase, 0.0, 10.0, "SaccadeBase");
  CheckRange(p.SaccadePerDegree, 0.0, 1.0, "SaccadePerDegree");
  CheckRange(p.SaccadeMaxAmplitude, 0.0, 90.0, "SaccadeMaxAmplitude");
  CheckRange(p.SaccadeRange, 0.0, 90.0, "SaccadeRange");
  CheckRange(p.FixationMean, 0.05, big, "FixationMean");
  CheckRange(p.FixationSigma, 0.0, 3.0, "FixationSigma");
  CheckRange(p.FixationMin, 0.05, big, "FixationMin");
  CheckRange(p.HeadYawAmplitude, 0.0, 90.0, "HeadYawAmplitude");
  CheckRange(p.HeadPitchAmplitude, 0.0, 90.0, "HeadPitchAmplitude");
  CheckRange(p.HeadRollAmplitude, 0.0, 90.0, "HeadRollAmplitude");
  CheckRange(p.IdleSmileInterval, -big, big, "IdleSmileInterval");
  CheckRange(p.IdleSmileIntensity, 0.0, 1.0, "IdleSmileIntensity");
  CheckRange(p.HeadShareOfGaze, 0.0, 1.0, "HeadShareOfGaze");
  CheckRange(p.HeadGazeTime, 0.0, 10.0, "HeadGazeTime");
  CheckRange(p.EyeYawRange, 1.0, 90.0, "EyeYawRange");
  CheckRange(p.EyePitchRange, 1.0, 90.0, "EyePitchRange");
  CheckRange(p.NodAmplitude, -90.0, 90.0, "NodAmplitude");
  CheckRange(p.ShakeAmplitude, -90.0, 90.0, "ShakeAmplitude");
  CheckRange(p.TiltAmplitude, -90.0, 90.0, "TiltAmplitude");
  CheckRange(p.SpeechNodAmplitude, -90.0, 90.0, "SpeechNodAmplitude");
  CheckRange(p.MoodFadeTime, 0.0, 60.0, "MoodFadeTime");
  CheckRange(p.SpeechExpressionDamping, 0.0, 1.0, "SpeechExpressionDamping");
}
} // namespace morphnode
