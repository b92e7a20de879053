// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/BehaviorController.h"

#include "base/Error.h"
#include "behavior/BehaviorLibrary.h"
#include "behavior/Blackboard.h"

#include "base/Text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace morphnode
{
namespace
{
using C = BehaviorChannel;

void CheckRange(double v, double lo, double hi, const char* what)
{
  CheckBehaviorRange(v, lo, hi, what);
}

void CheckStart(double start)
{
  CheckRange(start, 0.0, MaxBehaviorTime, "start time");
}

/// The built-in data (BehaviorLibrary::Default(), behavior/data/behavior.json) of a compiled
/// gesture or mood: one definition for the finite controller and the live behaviour.
const GestureDefinition& Definition(GestureKind kind)
{
  static const std::vector<const GestureDefinition*> table = []
  {
    std::vector<const GestureDefinition*> out;
    for (int k = 0; k <= static_cast<int>(GestureKind::Blink); ++k)
    {
      out.push_back(
        &BehaviorLibrary::Default().FindGesture(GestureName(static_cast<GestureKind>(k))));
    }
    return out;
  }();
  return *table[static_cast<size_t>(kind)];
}

/// The moods of the mood vector (Happy .. Surprised).
const MoodDefinition& Definition(int moodIndex)
{
  static const std::vector<const MoodDefinition*> table = []
  {
    std::vector<const MoodDefinition*> out;
    for (int m = 1; m <= NumberOfMoods; ++m)
    {
      out.push_back(&BehaviorLibrary::Default().FindMood(MoodName(static_cast<MoodKind>(m))));
    }
    return out;
  }();
  return *table[static_cast<size_t>(moodIndex)];
}
} // namespace

// ------------------------------------------------------------------ configuration

void BehaviorController::SetSeed(uint64_t seed)
{
  this->Seed = seed;
  this->Changed();
}

void BehaviorController::SetFrameRate(double fps)
{
  CheckRange(fps, 1e-3, 1000.0, "frame rate");
  this->FrameRate = fps;
  this->Changed();
}

void BehaviorController::SetDuration(double seconds)
{
  CheckRange(seconds, 0.0, MaxBehaviorTime, "duration");
  this->Duration = seconds;
  this->Changed();
}

void BehaviorController::SetParameters(const BehaviorParameters& p)
{
  CheckBehaviorParameters(p);
  this->Parameters = p;
  this->Changed();
}

void BehaviorController::SetSynthesizer(Synthesizer synthesizer)
{
  this->Synthesize = std::move(synthesizer);
}

void BehaviorController::SetPhonemeFileLoader(PhonemeFileLoader loader)
{
  this->LoadPhonemes = std::move(loader);
}

// ------------------------------------------------------------------ commands

void BehaviorController::Say(const std::string& text, double start)
{
  if (!this->Synthesize)
  {
    throw InputError("say: no synthesizer is set (BehaviorController::SetSynthesizer)");
  }
  this->AddUtterance(this->Synthesize(text), start);
}

void BehaviorController::Speak(const Utterance& utterance, double start)
{
  this->AddUtterance(utterance, start);
}

void BehaviorController::SpeakPhonemeFile(const std::string& path, double start)
{
  if (!this->LoadPhonemes)
  {
    throw InputError(
      "phonemes: no phoneme file loader is set (BehaviorController::SetPhonemeFileLoader)");
  }
  this->AddUtterance(this->LoadPhonemes(path), start);
}

void BehaviorController::AddUtterance(Utterance u, double start)
{
  if (start < 0.0 && std::isfinite(start))
  {
    start = 0.0; // AfterPrevious
    for (const auto& s : this->Utterances)
    {
      start = std::max(start, s.End);
    }
  }
  CheckStart(start);
  CheckRange(u.Duration, 0.0, MaxBehaviorTime, "utterance duration");
  const WeightTrack& v = u.Visemes;
  for (const auto& name : v.GetChannels())
  {
    for (const auto& base : C::Names())
    {
      if (name == base)
      {
        throw InputError("viseme channel '" + name + "' has the name of a behaviour channel");
      }
    }
  }
  const double trackLength = CheckUtteranceTrack(u);
  ScheduledUtterance s;
  s.Start = start;
  s.End = start + std::max(u.Duration, trackLength);
  s.Speech = std::move(u);
  this->Utterances.push_back(std::move(s));
  this->Changed();
}

void BehaviorController::Gesture(
  const std::string& name, double start, double duration, double intensity)
{
  this->Gesture(ParseGestureName(name), start, duration, intensity);
}

void BehaviorController::Gesture(GestureKind kind, double start, double duration, double intensity)
{
  CheckStart(start);
  CheckRange(duration, -MaxBehaviorTime, MaxBehaviorTime, "gesture duration");
  if (duration > 0.0)
  {
    CheckBehaviorDuration(duration, "gesture duration");
  }
  CheckRange(intensity, 0.0, 1.0, "gesture intensity");
  ScheduledGesture g;
  g.Kind = kind;
  g.Start = start;
  g.Duration = duration > 0.0 ? duration : DefaultGestureDuration(kind);
  g.Intensity = intensity;
  g.Sync = GestureSync(g, this->Parameters);
  this->Gestures.push_back(g);
  this->Changed();
}

SyncPoints BehaviorController::GestureSync(const ScheduledGesture& g, const BehaviorParameters& p)
{
  return Definition(g.Kind).Sync(g.Start, g.Duration, p);
}

void BehaviorController::SetMood(
  const std::string& name, double intensity, double start, double fade)
{
  this->SetMood(ParseMoodName(name), intensity, start, fade);
}

void BehaviorController::SetMood(MoodKind mood, double intensity, double start, double fade)
{
  CheckStart(start);
  CheckRange(intensity, 0.0, 1.0, "mood intensity");
  CheckRange(fade, -MaxBehaviorTime, MaxBehaviorTime, "mood fade");
  this->Moods.push_back({ mood, intensity, start, fade });
  this->Changed();
}

void BehaviorController::LookAt(double yaw, double pitch, double start, double duration)
{
  CheckRange(yaw, -90.0, 90.0, "look yaw");
  CheckRange(pitch, -90.0, 90.0, "look pitch");
  CheckStart(start);
  CheckRange(duration, -MaxBehaviorTime, MaxBehaviorTime, "look duration");
  if (duration > 0.0)
  {
    CheckBehaviorDuration(duration, "look duration");
  }
  this->Looks.push_back({ yaw, pitch, start, duration, this->Looks.size() });
  this->Changed();
}

void BehaviorController::ClearCommands()
{
  this->Gestures.clear();
  this->Utterances.clear();
  this->Moods.clear();
  this->Looks.clear();
  this->Changed();
}

// ------------------------------------------------------------------ scripts

void BehaviorController::Apply(const BehaviorScript& script)
{
  // All or nothing: a bad line leaves this controller as it was.
  BehaviorController next = *this;
  if (script.Seed)
  {
    next.SetSeed(*script.Seed);
  }
  if (script.FrameRate)
  {
    next.SetFrameRate(*script.FrameRate);
  }
  if (script.Duration)
  {
    next.SetDuration(*script.Duration);
  }
  for (const BehaviorCommand& c : script.Commands)
  {
    try
    {
      switch (c.Type)
      {
        case BehaviorCommand::Kind::Say:
          next.Say(c.Text, c.Start);
          break;
        case BehaviorCommand::Kind::Phonemes:
        {
          const bool relative = !c.Text.empty() && c.Text[0] != '/';
          next.SpeakPhonemeFile(relative ? script.BaseDirectory + c.Text : c.Text, c.Start);
          break;
        }
        case BehaviorCommand::Kind::Gesture:
          next.Gesture(c.Text, c.Start, c.Duration, c.Intensity);
          break;
        case BehaviorCommand::Kind::Mood:
          next.SetMood(c.Text, c.Intensity, c.Start, c.Fade);
          break;
        case BehaviorCommand::Kind::Look:
          next.LookAt(c.Yaw, c.Pitch, c.Start, c.Duration);
          break;
      }
    }
    catch (const InputError& e)
    {
      throw InputError("line " + std::to_string(c.Line) + ": " + e.what());
    }
  }
  *this = std::move(next);
}

void BehaviorController::LoadScript(const std::string& path)
{
  const BehaviorScript script = LoadBehaviorScript(path);
  try
  {
    this->Apply(script);
  }
  catch (const InputError& e)
  {
    throw InputError(path + ": " + e.what());
  }
}

void BehaviorController::ParseScript(const std::string& text)
{
  this->Apply(ParseBehaviorScript(text));
}

// ------------------------------------------------------------------ preparation

void BehaviorController::BuildChannels()
{
  this->ChannelNames = C::Names();
  this->VisemeChannelMaps.clear();
  for (const auto& u : this->Utterances)
  {
    std::vector<int> map;
    for (const auto& name : u.Speech.Visemes.GetChannels())
    {
      auto it = std::find(this->ChannelNames.begin(), this->ChannelNames.end(), name);
      if (it == this->ChannelNames.end())
      {
        it = this->ChannelNames.insert(this->ChannelNames.end(), name);
      }
      map.push_back(static_cast<int>(it - this->ChannelNames.begin()));
    }
    this->VisemeChannelMaps.push_back(std::move(map));
  }
  this->SilentChannel.assign(this->ChannelNames.size(), 0);
  for (size_t c = C::NumberOfBaseChannels; c < this->ChannelNames.size(); ++c)
  {
    this->SilentChannel[c] = IsSilentViseme(this->ChannelNames[c]);
  }
}

void BehaviorController::BuildGaze()
{
  const BehaviorParameters& p = this->Parameters;
  std::vector<LookCommand> looks = this->Looks;
  std::sort(looks.begin(), looks.end(),
    [](const LookCommand& a, const LookCommand& b)
    { return a.Start < b.Start || (a.Start == b.Start && a.Order < b.Order); });
  this->EyeGazeTrack.Clear();
  this->HeadGazeTrack.Clear();
  double fromYaw = 0.0, fromPitch = 0.0; // where the previous look left the gaze
  for (size_t i = 0; i < looks.size(); ++i)
  {
    const LookCommand& l = looks[i];
    // The eyes jump like a saccade; the head follows slower and takes its share.
    const double jump = std::hypot(l.Yaw - fromYaw, l.Pitch - fromPitch);
    this->EyeGazeTrack.Add(l.Start, SaccadeDuration(p, jump), { l.Yaw, l.Pitch, 1.0 });
    this->HeadGazeTrack.Add(
      l.Start, p.HeadGazeTime, { p.HeadShareOfGaze * l.Yaw, p.HeadShareOfGaze * l.Pitch });
    fromYaw = l.Yaw, fromPitch = l.Pitch;
    const double end = l.Start + l.Duration;
    const bool returns = l.Duration > 0.0 && (i + 1 == looks.size() || looks[i + 1].Start > end);
    if (returns)
    {
      this->EyeGazeTrack.Add(
        end, SaccadeDuration(p, std::hypot(l.Yaw, l.Pitch)), { 0.0, 0.0, 0.0 });
      this->HeadGazeTrack.Add(end, p.HeadGazeTime, { 0.0, 0.0 });
      fromYaw = fromPitch = 0.0;
    }
  }
  this->EyeGazeTrack.Finalize();
  this->HeadGazeTrack.Finalize();
}

void BehaviorController::BuildBlinks(const std::vector<std::pair<double, double>>& closedEyes)
{
  const BehaviorParameters& p = this->Parameters;
  const double length = BlinkLength(p);
  // Closed spans merged and sorted, so that each blink is checked by one binary search.
  std::vector<std::pair<double, double>> closed = closedEyes;
  std::sort(closed.begin(), closed.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& c : closed)
  {
    if (!merged.empty() && c.first <= merged.back().second)
    {
      merged.back().second = std::max(merged.back().second, c.second);
    }
    else
    {
      merged.push_back(c);
    }
  }
  auto underClosedEyes = [&](double start)
  {
    // The first span ending after the blink starts is the only one it can overlap.
    auto it = std::upper_bound(merged.begin(), merged.end(), start,
      [](double v, const std::pair<double, double>& c) { return v < c.second; });
    return it != merged.end() && start + length > it->first;
  };
  std::vector<BlinkEvent> blinks;
  for (const BlinkEvent& b : this->Idle.Blinks)
  {
    if (!underClosedEyes(b.Start))
    {
      blinks.push_back(b);
    }
  }
  for (const ScheduledCue& cue : this->Cues)
  {
    if (cue.Kind == NonverbalCue::Kind::Blink && !underClosedEyes(cue.Sync.Start))
    {
      blinks.push_back({ cue.Sync.Start, 1.0 });
    }
  }
  for (const ScheduledGesture& g : this->Gestures)
  {
    if (g.Kind == GestureKind::Blink)
    {
      blinks.push_back({ g.Sync.Start, g.Intensity }); // explicit: merged, never dropped
    }
  }
  std::stable_sort(blinks.begin(), blinks.end(),
    [](const BlinkEvent& a, const BlinkEvent& b) { return a.Start < b.Start; });
  this->Idle.Blinks = std::move(blinks);
  std::vector<std::pair<double, double>> spans;
  for (const BlinkEvent& b : this->Idle.Blinks)
  {
    spans.emplace_back(b.Start, b.Start + length);
  }
  this->BlinkIndex.Build(spans);
}

void BehaviorController::Prepare()
{
  const BehaviorParameters& p = this->Parameters;
  for (auto& g : this->Gestures)
  {
    g.Sync = GestureSync(g, p);
  }
  if (this->Duration > 0.0)
  {
    this->EffectiveDuration = this->Duration;
  }
  else
  {
    double last = 0.0;
    for (const auto& g : this->Gestures)
    {
      last = std::max(last, g.Sync.End);
    }
    for (const auto& u : this->Utterances)
    {
      last = std::max(last, u.End);
      for (const auto& cue : u.Speech.Cues)
      {
        last = std::max(last, u.Start + cue.Start + cue.Duration);
      }
    }
    for (const auto& m : this->Moods)
    {
      last = std::max(last, m.Start + std::max(m.Fade, p.MoodFadeTime));
    }
    for (const auto& l : this->Looks)
    {
      last = std::max(last, l.Start + std::max(l.Duration, 0.0) + p.HeadGazeTime);
    }
    this->EffectiveDuration = std::max(5.0, last + 1.0);
  }

  this->BuildChannels();

  // Speech: its intervals (blinks come faster) and its cues on the absolute time axis.
  std::vector<std::pair<double, double>> speaking, utteranceSpans, cueSpans;
  this->Cues.clear();
  for (const auto& u : this->Utterances)
  {
    speaking.emplace_back(u.Start, u.End);
    utteranceSpans.emplace_back(u.Start, u.End);
    for (const NonverbalCue& cue : u.Speech.Cues)
    {
      const double start = u.Start + cue.Start;
      ScheduledCue s;
      s.Kind = cue.Type;
      s.Intensity = cue.Intensity;
      s.Sync = SpeechCueSync(cue, start, p);
      this->Cues.push_back(s);
      cueSpans.emplace_back(s.Sync.Start, s.Sync.End);
    }
  }

  this->Idle = IdleSchedule::Generate(p, this->Seed, this->EffectiveDuration, speaking);

  std::vector<std::pair<double, double>> closedEyes, gestureSpans, smileSpans;
  for (const auto& g : this->Gestures)
  {
    gestureSpans.emplace_back(g.Sync.Start, g.Sync.End);
    if (g.Kind == GestureKind::CloseEyes)
    {
      closedEyes.emplace_back(g.Sync.Start, g.Sync.End);
    }
  }
  this->BuildBlinks(closedEyes);
  for (const auto& s : this->Idle.Smiles)
  {
    smileSpans.emplace_back(s.Start, s.Start + s.Duration);
  }
  this->GestureIndex.Build(gestureSpans);
  this->UtteranceIndex.Build(utteranceSpans);
  this->CueIndex.Build(cueSpans);
  this->SmileIndex.Build(smileSpans);

  // Moods: one at a time; each change fades from the current state.
  this->MoodTrack.Clear();
  for (const auto& m : this->Moods)
  {
    std::array<double, NumberOfMoods> target{};
    if (m.Mood != MoodKind::Neutral)
    {
      target[static_cast<int>(m.Mood) - 1] = m.Intensity;
    }
    this->MoodTrack.Add(m.Start, m.Fade < 0.0 ? p.MoodFadeTime : m.Fade, target);
  }
  this->MoodTrack.Finalize();

  this->BuildGaze();
  this->Prepared = true;
}

int BehaviorController::FindChannel(const std::string& name) const
{
  auto it = std::find(this->ChannelNames.begin(), this->ChannelNames.end(), name);
  return it == this->ChannelNames.end() ? -1 : static_cast<int>(it - this->ChannelNames.begin());
}

// ------------------------------------------------------------------ sampling

void BehaviorController::Sample(double t, double* out) const
{
  if (!this->Prepared)
  {
    throw InputError("BehaviorController: call Prepare() after changing the behaviour");
  }
  if (!std::isfinite(t))
  {
    throw InputError("BehaviorController: sample time is not finite");
  }
  const BehaviorParameters& p = this->Parameters;
  const size_t channels = this->ChannelNames.size();
  std::fill(out, out + channels, 0.0);
  Blackboard bb;

  // Background: mood.
  double mood[NumberOfMoods];
  this->MoodTrack.Evaluate(t, mood);
  for (int m = 0; m < NumberOfMoods; ++m)
  {
    const MoodDefinition& d = Definition(m);
    for (int s = 0; s < Blackboard::NumberOfShapes; ++s)
    {
      bb.Background[s] += mood[m] * d.Shapes[s];
    }
    bb.HeadBackground[1] += mood[m] * d.Head[1];
  }
  const double happy = mood[0];
  const double negative = std::max({ mood[1], mood[2], mood[3] });

  // Background: idle behaviour.
  double smile = 0.0;
  this->SmileIndex.ForEachCandidate(t,
    [&](uint32_t i)
    {
      const IdleSmileEvent& e = this->Idle.Smiles[i];
      const double x = (t - e.Start) / e.Duration;
      if (x > 0.0 && x < 1.0)
      {
        smile = std::max(smile, e.Intensity * Smoothstep(std::min(x, 1.0 - x) / 0.4));
      }
    });
  // Happiness makes idle smiles broader; a negative mood holds them back.
  bb.Background[C::MouthSmile] += smile * (1.0 + happy) * (1.0 - negative);
  this->Idle.Head.Evaluate(t, bb.HeadIdle.data());
  this->Idle.GazeOffset(t, bb.Saccade[0], bb.Saccade[1]);
  this->BlinkIndex.ForEachCandidate(t,
    [&](uint32_t i)
    {
      const BlinkEvent& b = this->Idle.Blinks[i];
      bb.Blink = std::max(bb.Blink, b.Amplitude * BlinkLidCurve(p, t - b.Start));
    });

  // Speech: visemes straight to the mouth channels (overlapping utterances: maximum).
  this->UtteranceIndex.ForEachCandidate(t,
    [&](uint32_t i)
    {
      const ScheduledUtterance& u = this->Utterances[i];
      const WeightTrack& v = u.Speech.Visemes;
      const size_t frames = v.GetNumberOfFrames();
      const double f = (t - u.Start) * v.GetFrameRate();
      if (frames == 0 || !(f >= 0.0) || f > static_cast<double>(frames - 1))
      {
        return;
      }
      const size_t f0 = static_cast<size_t>(f);
      const size_t f1 = std::min(f0 + 1, frames - 1);
      const double a = f - static_cast<double>(f0);
      const double* r0 = v.GetFrame(f0);
      const double* r1 = v.GetFrame(f1);
      const std::vector<int>& map = this->VisemeChannelMaps[i];
      for (size_t c = 0; c < map.size(); ++c)
      {
        double& o = out[map[c]];
        o = std::max(o, r0[c] + a * (r1[c] - r0[c]));
      }
    });
  double activity = 0.0;
  for (size_t c = C::NumberOfBaseChannels; c < channels; ++c)
  {
    activity += this->SilentChannel[c] ? 0.0 : out[c];
  }
  bb.SpeechActivity = activity;

  // Speech: cues.
  this->CueIndex.ForEachCandidate(t,
    [&](uint32_t i)
    {
      const ScheduledCue& cue = this->Cues[i];
      bb.AddSpeechCue(cue.Kind, cue.Sync, cue.Intensity, t, p);
    });

  // Explicit gestures: the shapes and head motion of their data.
  this->GestureIndex.ForEachCandidate(t,
    [&](uint32_t i)
    {
      const ScheduledGesture& g = this->Gestures[i];
      Definition(g.Kind).Contribute(g.Sync, g.Intensity, t, p, bb);
    });

  // Explicit gaze.
  bb.SetExplicitGaze(this->EyeGazeTrack, this->HeadGazeTrack, t);

  bb.Resolve(p, out);
}

void BehaviorController::Sample(double t, std::vector<double>& out) const
{
  out.resize(this->ChannelNames.size());
  this->Sample(t, out.data());
}

size_t BehaviorController::GetNumberOfFrames() const
{
  return NumberOfFrames(this->EffectiveDuration, this->FrameRate);
}

WeightTrack BehaviorController::SampleTrack() const
{
  if (!this->Prepared)
  {
    throw InputError("BehaviorController: call Prepare() after changing the behaviour");
  }
  const size_t frames = this->GetNumberOfFrames();
  const size_t channels = this->ChannelNames.size();
  if (channels > 0 && frames > MaxTrackValues / channels)
  {
    std::ostringstream msg;
    msg << "a track of " << frames << " frames x " << channels << " channels is more than "
        << MaxTrackValues << " values: sample the behaviour one time at a time instead";
    throw InputError(msg.str());
  }
  WeightTrack track(this->ChannelNames, this->FrameRate);
  std::vector<double> row(channels);
  for (size_t f = 0; f < frames; ++f)
  {
    this->Sample(this->GetFrameTime(f), row.data());
    track.AppendFrame(row.data());
  }
  return track;
}

WeightTrack BehaviorController::GenerateTrack()
{
  this->Prepare();
  return this->SampleTrack();
}
} // namespace morphnode
