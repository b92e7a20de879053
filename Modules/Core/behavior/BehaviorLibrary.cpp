// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/BehaviorLibrary.h"

#include "base/Error.h"
#include "base/LibraryMessage.h"
#include "base/Text.h"
#include "behavior/BehaviorScript.h"
#include "behavior/IdleSchedule.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace morphnode
{
namespace behavior_detail
{
const char*
DefaultBehaviorLibraryJson(); // behavior/data/behavior.json (DefaultBehaviorLibrary.cpp)
}

namespace
{
constexpr double Pi = 3.141592653589793;
using Json = nlohmann::json;

/// A 0..1 bump: zero slope at both ends, one per cycle: 0.5 - 0.5 cos(2 pi cycles u).
double Bumps(double u, double cycles)
{
  return 0.5 - 0.5 * std::cos(2.0 * Pi * cycles * u);
}

std::string Quoted(const std::string& s)
{
  return "'" + (s.size() > 64 ? s.substr(0, 64) + "..." : s) + "'";
}

/// Walks a JSON document, naming the path of every problem.
class Reader
{
public:
  explicit Reader(std::string origin)
    : Origin(std::move(origin))
  {
  }

  [[noreturn]] void Fail(const std::string& path, const std::string& what) const
  {
    throw InputError(this->Origin + ": " + (path.empty() ? "" : path + ": ") + what);
  }

  const Json& Object(const Json& j, const std::string& path) const
  {
    if (!j.is_object())
    {
      this->Fail(path, "expected an object");
    }
    return j;
  }

  /// Rejects keys outside `known` (a typo would otherwise be ignored silently).
  void Keys(const Json& j, const std::string& path, std::initializer_list<const char*> known) const
  {
    for (auto it = j.begin(); it != j.end(); ++it)
    {
      if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }))
      {
        std::string list;
        for (const char* k : known)
        {
          list += (list.empty() ? "" : ", ") + std::string(k);
        }
        this->Fail(path, "unknown key " + Quoted(it.key()) + " (known: " + list + ")");
      }
    }
  }

  double Number(const Json& j, const std::string& path, double lo, double hi) const
  {
    if (!j.is_number())
    {
      this->Fail(path, "expected a number");
    }
    const double v = j.get<double>();
    if (!(v >= lo && v <= hi))
    {
      std::ostringstream msg;
      msg << "value " << v << " is outside [" << lo << ", " << hi << "]";
      this->Fail(path, msg.str());
    }
    return v;
  }

  ParameterValue NumberOrParameter(
    const Json& j, const std::string& path, double lo, double hi) const
  {
    ParameterValue v;
    if (j.is_string())
    {
      v.Parameter = FindBehaviorParameter(j.get<std::string>());
      if (v.Parameter < 0)
      {
        this->Fail(path, "unknown behaviour parameter " + Quoted(j.get<std::string>()));
      }
      return v;
    }
    v.Value = this->Number(j, path, lo, hi);
    return v;
  }

  std::string String(const Json& j, const std::string& path) const
  {
    if (!j.is_string())
    {
      this->Fail(path, "expected a string");
    }
    return j.get<std::string>();
  }

  std::vector<std::string> Strings(const Json& j, const std::string& path) const
  {
    if (!j.is_array())
    {
      this->Fail(path, "expected an array of strings");
    }
    std::vector<std::string> out;
    for (size_t i = 0; i < j.size(); ++i)
    {
      out.push_back(this->String(j[i], path + "[" + std::to_string(i) + "]"));
    }
    return out;
  }

  OverrideMode Override(const Json& j, const std::string& path) const
  {
    const std::string name = this->String(j, path);
    try
    {
      return ParseOverrideMode(name);
    }
    catch (const InputError& e)
    {
      this->Fail(path, e.what());
    }
  }

  /// "shapes": { "MouthSmile": 0.7, ... } over the semantic shapes.
  std::array<double, Blackboard::NumberOfShapes> Shapes(
    const Json& j, const std::string& path) const
  {
    this->Object(j, path);
    std::array<double, Blackboard::NumberOfShapes> out{};
    for (auto it = j.begin(); it != j.end(); ++it)
    {
      int shape = -1;
      for (int s = 0; s < Blackboard::NumberOfShapes; ++s)
      {
        if (CanonicalBehaviorName(it.key()) == CanonicalBehaviorName(BehaviorChannel::Name(s)))
        {
          shape = s;
        }
      }
      if (shape < 0)
      {
        this->Fail(path,
          "unknown shape " + Quoted(it.key()) +
            " (known: EyesClosed, BrowsUp, BrowsFright, BrowsAngry, MouthSmile, MouthSad)");
      }
      out[shape] = this->Number(it.value(), path + "." + it.key(), -1.0, 1.0);
    }
    return out;
  }

  std::string Origin;
};

GestureDefinition ParseGesture(
  const Reader& r, const std::string& name, const Json& j, const std::string& path)
{
  r.Object(j, path);
  r.Keys(j, path,
    { "aliases", "duration", "attack", "release", "shapes", "head", "blink", "overrideBlink",
      "overrideLookAt", "overrideMouth", "mouthShapes", "description" });
  GestureDefinition g;
  g.Name = name;
  if (j.contains("aliases"))
  {
    g.Aliases = r.Strings(j["aliases"], path + ".aliases");
  }
  if (j.contains("duration"))
  {
    g.Duration = r.Number(j["duration"], path + ".duration", 0.01, MaxBehaviorTime);
  }
  if (j.contains("attack"))
  {
    g.Attack = r.NumberOrParameter(j["attack"], path + ".attack", 0.0, 60.0);
  }
  if (j.contains("release"))
  {
    g.Release = r.NumberOrParameter(j["release"], path + ".release", 0.0, 60.0);
  }
  if (j.contains("shapes"))
  {
    g.Shapes = r.Shapes(j["shapes"], path + ".shapes");
  }
  if (j.contains("blink"))
  {
    if (!j["blink"].is_boolean())
    {
      r.Fail(path + ".blink", "expected true or false");
    }
    g.Blink = j["blink"].get<bool>();
  }
  if (j.contains("head"))
  {
    const std::string hp = path + ".head";
    const Json& h = r.Object(j["head"], hp);
    r.Keys(h, hp, { "motion", "amplitude", "cycle", "yaw", "pitch", "roll" });
    g.HasHead = true;
    if (h.contains("motion"))
    {
      const std::string motion = CanonicalBehaviorName(r.String(h["motion"], hp + ".motion"));
      if (motion == "hold")
      {
        g.Motion = HeadMotion::Hold;
      }
      else if (motion == "nod")
      {
        g.Motion = HeadMotion::Nod;
      }
      else if (motion == "shake")
      {
        g.Motion = HeadMotion::Shake;
      }
      else
      {
        r.Fail(hp + ".motion",
          "unknown motion " + Quoted(h["motion"].get<std::string>()) +
            " (known: hold, nod, shake)");
      }
    }
    if (h.contains("amplitude"))
    {
      g.Amplitude = r.NumberOrParameter(h["amplitude"], hp + ".amplitude", -90.0, 90.0);
    }
    if (h.contains("cycle"))
    {
      g.Cycle = r.Number(h["cycle"], hp + ".cycle", 0.05, 60.0);
    }
    const char* axes[3] = { "yaw", "pitch", "roll" };
    for (int a = 0; a < 3; ++a)
    {
      if (h.contains(axes[a]))
      {
        g.Head[a] = r.NumberOrParameter(h[axes[a]], hp + "." + axes[a], -90.0, 90.0);
      }
    }
    if (g.Motion != HeadMotion::Hold && !h.contains("amplitude"))
    {
      r.Fail(hp, "a nod or shake needs an amplitude");
    }
  }
  if (j.contains("overrideBlink"))
  {
    g.OverrideBlink = r.Override(j["overrideBlink"], path + ".overrideBlink");
  }
  if (j.contains("overrideLookAt"))
  {
    g.OverrideLookAt = r.Override(j["overrideLookAt"], path + ".overrideLookAt");
  }
  if (j.contains("overrideMouth"))
  {
    g.OverrideMouth = r.Override(j["overrideMouth"], path + ".overrideMouth");
  }
  if (j.contains("mouthShapes"))
  {
    g.MouthShapes = r.Strings(j["mouthShapes"], path + ".mouthShapes");
  }
  return g;
}

MoodDefinition ParseMood(
  const Reader& r, const std::string& name, const Json& j, const std::string& path)
{
  r.Object(j, path);
  r.Keys(j, path,
    { "aliases", "shapes", "head", "blinkRate", "saccadeRange", "fixation", "gaze", "headMotion",
      "idleSmiles", "description" });
  MoodDefinition m;
  m.Name = name;
  if (j.contains("aliases"))
  {
    m.Aliases = r.Strings(j["aliases"], path + ".aliases");
  }
  if (j.contains("shapes"))
  {
    m.Shapes = r.Shapes(j["shapes"], path + ".shapes");
  }
  if (j.contains("head"))
  {
    const std::string hp = path + ".head";
    const Json& h = r.Object(j["head"], hp);
    r.Keys(h, hp, { "yaw", "pitch", "roll" });
    const char* axes[3] = { "yaw", "pitch", "roll" };
    for (int a = 0; a < 3; ++a)
    {
      if (h.contains(axes[a]))
      {
        m.Head[a] = r.Number(h[axes[a]], hp + "." + axes[a], -45.0, 45.0);
      }
    }
  }
  if (j.contains("gaze"))
  {
    const std::string gp = path + ".gaze";
    const Json& g = r.Object(j["gaze"], gp);
    r.Keys(g, gp, { "yaw", "pitch" });
    if (g.contains("yaw"))
    {
      m.Gaze[0] = r.Number(g["yaw"], gp + ".yaw", -45.0, 45.0);
    }
    if (g.contains("pitch"))
    {
      m.Gaze[1] = r.Number(g["pitch"], gp + ".pitch", -45.0, 45.0);
    }
  }
  // Factors: within [0.1, 10] for rates and times (a zero blink rate would stop the eyes),
  // [0, 10] for amplitudes.
  auto factor = [&](const char* key, double lo, double& v)
  {
    if (j.contains(key))
    {
      v = r.Number(j[key], path + "." + key, lo, 10.0);
    }
  };
  factor("blinkRate", 0.1, m.BlinkRate);
  factor("saccadeRange", 0.0, m.SaccadeRange);
  factor("fixation", 0.1, m.Fixation);
  factor("headMotion", 0.0, m.HeadMotion);
  factor("idleSmiles", 0.0, m.IdleSmiles);
  return m;
}

template <typename T>
int FindByName(const std::vector<T>& items, const std::string& name)
{
  const std::string key = CanonicalBehaviorName(name);
  for (size_t i = 0; i < items.size(); ++i)
  {
    if (CanonicalBehaviorName(items[i].Name) == key)
    {
      return static_cast<int>(i);
    }
  }
  for (size_t i = 0; i < items.size(); ++i)
  {
    for (const auto& a : items[i].Aliases)
    {
      if (CanonicalBehaviorName(a) == key)
      {
        return static_cast<int>(i);
      }
    }
  }
  return -1;
}

template <typename T>
std::string KnownNames(const std::vector<T>& items)
{
  std::string out;
  for (const auto& i : items)
  {
    out += (out.empty() ? "" : ", ") + i.Name;
  }
  return out;
}

template <typename T>
void AddOrReplace(std::vector<T>& items, T item)
{
  const std::string key = CanonicalBehaviorName(item.Name);
  for (auto& i : items)
  {
    if (CanonicalBehaviorName(i.Name) == key)
    {
      i = std::move(item);
      return;
    }
  }
  items.push_back(std::move(item));
}
} // namespace

// ------------------------------------------------------------------ overrides

OverrideMode ParseOverrideMode(const std::string& name)
{
  const std::string key = CanonicalBehaviorName(name);
  if (key == "none")
  {
    return OverrideMode::None;
  }
  if (key == "blend")
  {
    return OverrideMode::Blend;
  }
  if (key == "block")
  {
    return OverrideMode::Block;
  }
  throw InputError("unknown override " + Quoted(name) + " (known: none, blend, block)");
}

const char* OverrideModeName(OverrideMode mode)
{
  switch (mode)
  {
    case OverrideMode::None:
      return "none";
    case OverrideMode::Blend:
      return "blend";
    case OverrideMode::Block:
      return "block";
  }
  return "?";
}

double OverrideFactor(OverrideMode mode, double w)
{
  w = w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
  switch (mode)
  {
    case OverrideMode::None:
      return 1.0;
    case OverrideMode::Blend:
      return 1.0 - w;
    case OverrideMode::Block:
      return w > 0.0 ? 0.0 : 1.0;
  }
  return 1.0;
}

double ParameterValue::Resolve(const BehaviorParameters& p) const
{
  return this->Parameter >= 0 ? GetBehaviorParameter(p, this->Parameter) : this->Value;
}

// ------------------------------------------------------------------ gestures

SyncPoints GestureDefinition::Sync(double start, double duration, const BehaviorParameters& p) const
{
  if (this->Blink) // a blink keeps its own lid curve
  {
    return SyncPoints::Make(start, BlinkLength(p), p.BlinkCloseTime, p.BlinkOpenTime);
  }
  return SyncPoints::Make(start, duration > 0.0 ? duration : this->Duration,
    this->Attack.Resolve(p), this->Release.Resolve(p));
}

void GestureDefinition::Contribute(const SyncPoints& sync, double intensity, double t,
  const BehaviorParameters& p, Blackboard& bb) const
{
  const double e = sync.Envelope(t);
  if (!(e > 0.0) || this->Blink)
  {
    return;
  }
  auto own = [&](int group) { bb.Ownership[group] = std::max(bb.Ownership[group], e); };
  using C = BehaviorChannel;
  bool brows = false, expression = false;
  for (int s = 0; s < Blackboard::NumberOfShapes; ++s)
  {
    const double w = this->Shapes[s];
    if (w == 0.0)
    {
      continue;
    }
    if (s == C::EyesClosed)
    {
      bb.CloseEyes = std::max(bb.CloseEyes, intensity * w * e);
      continue;
    }
    bb.Explicit[s] += intensity * w * e;
    brows = brows || s == C::BrowsUp || s == C::BrowsFright || s == C::BrowsAngry;
    expression = expression || s == C::MouthSmile || s == C::MouthSad;
  }
  if (brows)
  {
    own(Blackboard::BrowsGroup);
  }
  if (expression)
  {
    own(Blackboard::ExpressionGroup);
  }
  if (!this->HasHead)
  {
    return;
  }
  const double span = sync.End - sync.Start;
  if (!(span > 0.0) ||
    !std::isfinite(span)) // (durations have a floor; a span lost to rounding has no motion)
  {
    return;
  }
  const double u = std::min(1.0, std::max(0.0, (t - sync.Start) / span));
  const double cycles = std::max(1.0, std::round(span / this->Cycle));
  switch (this->Motion)
  {
    case HeadMotion::Nod: // down and up, one bump per cycle
      bb.HeadExplicit[1] -= this->Amplitude.Resolve(p) * intensity * Bumps(u, cycles);
      break;
    case HeadMotion::Shake: // left-right swings in a smooth window
      bb.HeadExplicit[0] +=
        this->Amplitude.Resolve(p) * intensity * std::sin(Pi * u) * std::sin(2.0 * Pi * cycles * u);
      break;
    case HeadMotion::Hold:
      for (int a = 0; a < 3; ++a)
      {
        bb.HeadExplicit[a] += this->Head[a].Resolve(p) * intensity * e;
      }
      break;
  }
  own(Blackboard::HeadGroup);
}

// ------------------------------------------------------------------ moods

MoodEffect::Vector MoodEffect::Neutral()
{
  Vector v{};
  v[BlinkRate] = v[SaccadeRange] = v[Fixation] = v[HeadMotion] = v[IdleSmiles] = 1.0;
  return v;
}

MoodEffect::Vector MoodEffect::Of(const MoodDefinition& m, double intensity)
{
  Vector target = Neutral();
  for (int s = 0; s < Blackboard::NumberOfShapes; ++s)
  {
    target[Shape0 + s] = m.Shapes[s];
  }
  target[HeadYaw] = m.Head[0];
  target[HeadPitch] = m.Head[1];
  target[HeadRoll] = m.Head[2];
  target[BlinkRate] = m.BlinkRate;
  target[SaccadeRange] = m.SaccadeRange;
  target[Fixation] = m.Fixation;
  target[GazeYaw] = m.Gaze[0];
  target[GazePitch] = m.Gaze[1];
  target[HeadMotion] = m.HeadMotion;
  target[IdleSmiles] = m.IdleSmiles;
  const Vector neutral = Neutral();
  Vector v;
  for (int i = 0; i < Size; ++i)
  {
    v[i] = neutral[i] + intensity * (target[i] - neutral[i]);
  }
  return v;
}

// ------------------------------------------------------------------ the library

const char* BehaviorLibrary::DefaultJson()
{
  return behavior_detail::DefaultBehaviorLibraryJson();
}

const BehaviorLibrary& BehaviorLibrary::Default()
{
  static const BehaviorLibrary library = FromJson(DefaultJson(), "built-in behaviour library");
  return library;
}

BehaviorLibrary BehaviorLibrary::FromJson(
  const std::string& text, const std::string& origin, const BehaviorLibrary* base)
{
  const Reader r(origin);
  Json doc;
  try
  {
    doc = Json::parse(text);
  }
  catch (const Json::exception& e)
  {
    r.Fail("", std::string("not valid JSON: ") + text::LibraryMessage(e.what()));
  }
  r.Object(doc, "(top level)");
  r.Keys(doc, "(top level)", { "gestures", "moods", "description" });
  BehaviorLibrary library = base ? *base : BehaviorLibrary();
  if (doc.contains("gestures"))
  {
    const Json& gestures = r.Object(doc["gestures"], "gestures");
    for (auto it = gestures.begin(); it != gestures.end(); ++it)
    {
      const std::string path = "gestures." + it.key();
      if (CanonicalBehaviorName(it.key()).empty())
      {
        r.Fail(path, "a gesture needs a name");
      }
      AddOrReplace(library.Gestures, ParseGesture(r, it.key(), it.value(), path));
    }
  }
  if (doc.contains("moods"))
  {
    const Json& moods = r.Object(doc["moods"], "moods");
    for (auto it = moods.begin(); it != moods.end(); ++it)
    {
      const std::string path = "moods." + it.key();
      if (CanonicalBehaviorName(it.key()).empty())
      {
        r.Fail(path, "a mood needs a name");
      }
      AddOrReplace(library.Moods, ParseMood(r, it.key(), it.value(), path));
    }
  }
  if (FindByName(library.Moods, "neutral") < 0)
  {
    MoodDefinition neutral;
    neutral.Name = "neutral";
    library.Moods.insert(library.Moods.begin(), neutral);
  }
  return library;
}

BehaviorLibrary BehaviorLibrary::Load(const std::string& path)
{
  return FromJson(text::ReadFile(path), path, &Default());
}

int BehaviorLibrary::FindGestureIndex(const std::string& name) const
{
  return FindByName(this->Gestures, name);
}

int BehaviorLibrary::FindMoodIndex(const std::string& name) const
{
  return FindByName(this->Moods, name);
}

const GestureDefinition& BehaviorLibrary::FindGesture(const std::string& name) const
{
  const int i = this->FindGestureIndex(name);
  if (i < 0)
  {
    throw InputError(
      "unknown gesture " + Quoted(name) + " (known: " + KnownNames(this->Gestures) + ")");
  }
  return this->Gestures[i];
}

const MoodDefinition& BehaviorLibrary::FindMood(const std::string& name) const
{
  const int i = this->FindMoodIndex(name);
  if (i < 0)
  {
    throw InputError("unknown mood " + Quoted(name) + " (known: " + KnownNames(this->Moods) + ")");
  }
  return this->Moods[i];
}
} // namespace morphnode
