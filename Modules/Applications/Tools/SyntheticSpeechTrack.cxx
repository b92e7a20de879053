// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: a synthetic speech track, when no track is given.
#include "ReductionStudy.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

namespace reductionstudy
{
morphnode::WeightTrack MakeSyntheticSpeechTrack(
  const std::vector<std::string>& names, double seconds, unsigned seed)
{
  const double fps = 30.0;
  using Shape = std::map<std::string, double>;
  const std::vector<Shape> visemes = {
    { { "mouthClose", 0.5 }, { "mouthPress_L", 0.4 }, { "mouthPress_R", 0.4 },
      { "jawOpen", 0.05 } }, // PP
    { { "mouthRollLower", 0.5 }, { "mouthUpperUp_L", 0.25 }, { "mouthUpperUp_R", 0.25 },
      { "jawOpen", 0.1 } }, // FF
    { { "jawOpen", 0.2 }, { "mouthShrugUpper", 0.2 }, { "mouthStretch_L", 0.15 },
      { "mouthStretch_R", 0.15 } },                                            // TH/DD/nn
    { { "jawOpen", 0.25 }, { "mouthShrugLower", 0.2 } },                       // kk
    { { "mouthFunnel", 0.45 }, { "mouthPucker", 0.25 }, { "jawOpen", 0.15 } }, // CH
    { { "jawOpen", 0.1 }, { "mouthStretch_L", 0.3 }, { "mouthStretch_R", 0.3 },
      { "mouthClose", 0.1 } },                                                          // SS
    { { "jawOpen", 0.6 }, { "mouthLowerDown_L", 0.35 }, { "mouthLowerDown_R", 0.35 } }, // aa
    { { "jawOpen", 0.3 }, { "mouthStretch_L", 0.35 }, { "mouthStretch_R", 0.35 },
      { "mouthSmile_L", 0.2 }, { "mouthSmile_R", 0.2 } },                         // E
    { { "jawOpen", 0.2 }, { "mouthStretch_L", 0.3 }, { "mouthStretch_R", 0.3 } }, // ih
    { { "jawOpen", 0.4 }, { "mouthFunnel", 0.55 } },                              // oh
    { { "mouthPucker", 0.7 }, { "mouthFunnel", 0.3 }, { "jawOpen", 0.15 } },      // ou
  };
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // Viseme keys: centre time and shape; pauses are keys with no shape.
  struct Key
  {
    double Time;
    int Viseme; // -1 = silence
  };
  std::vector<Key> keys;
  double t = 0.3;
  double nextPause = 1.5 + 1.5 * uniform(rng);
  while (t < seconds - 0.3)
  {
    if (t > nextPause)
    {
      keys.push_back({ t + 0.2, -1 });
      t += 0.35 + 0.3 * uniform(rng);
      nextPause = t + 1.5 + 1.5 * uniform(rng);
      continue;
    }
    keys.push_back({ t, static_cast<int>(uniform(rng) * visemes.size()) % int(visemes.size()) });
    t += 0.07 + 0.1 * uniform(rng);
  }
  // Blinks, brow raises, gaze shifts.
  std::vector<double> blinks, brows;
  for (double b = 1.0 + 3.0 * uniform(rng); b < seconds; b += 1.0 + 5.0 * uniform(rng))
  {
    blinks.push_back(b);
  }
  for (double b = 2.0 + 2.0 * uniform(rng); b < seconds; b += 3.0 + 4.0 * uniform(rng))
  {
    brows.push_back(b);
  }
  struct Gaze
  {
    double Time, X, Y;
  };
  std::vector<Gaze> gaze = { { 0.0, 0.0, 0.0 } };
  for (double g = 0.8; g < seconds; g += 0.5 + 2.0 * uniform(rng))
  {
    gaze.push_back({ g, 0.5 * (uniform(rng) - 0.5), 0.4 * (uniform(rng) - 0.5) });
  }

  std::vector<std::string> channels(names.begin() + 1, names.end());
  morphnode::WeightTrack track(channels, fps);
  auto channel = [&](const std::string& n) { return track.FindChannel(n); };
  const size_t frames = static_cast<size_t>(seconds * fps);
  for (size_t f = 0; f < frames; ++f)
  {
    const double time = f / fps;
    std::vector<double> w(channels.size(), 0.0);
    // Coarticulation: dominance exp(-theta |t - c|) per key; bilabial closure dominates
    // more strongly so the lips do close.
    double total = 0.0;
    std::vector<double> shape(channels.size(), 0.0);
    for (const Key& k : keys)
    {
      const double dt = std::abs(time - k.Time);
      if (dt > 0.5)
      {
        continue;
      }
      const double dominance = (k.Viseme == 0 ? 2.0 : 1.0) * std::exp(-dt / 0.05);
      total += dominance;
      if (k.Viseme >= 0)
      {
        for (const auto& [name, value] : visemes[k.Viseme])
        {
          const int c = channel(name);
          if (c >= 0)
          {
            shape[c] += dominance * value;
          }
        }
      }
    }
    if (total > 1e-6)
    {
      // Fade out far from any key (long pauses).
      const double presence = std::min(1.0, total);
      for (size_t c = 0; c < w.size(); ++c)
      {
        w[c] = presence * shape[c] / total;
      }
    }
    auto add = [&](const std::string& n, double v)
    {
      const int c = channel(n);
      if (c >= 0)
      {
        w[c] = std::clamp(w[c] + v, 0.0, 1.0);
      }
    };
    for (double b : blinks)
    {
      const double dt = time - b;
      double lid = 0.0;
      if (dt >= 0.0 && dt < 0.1)
      {
        lid = dt / 0.1;
      }
      else if (dt >= 0.1 && dt < 0.15)
      {
        lid = 1.0;
      }
      else if (dt >= 0.15 && dt < 0.3)
      {
        lid = 1.0 - (dt - 0.15) / 0.15;
      }
      add("eyeBlink_L", lid);
      add("eyeBlink_R", lid);
    }
    for (double b : brows)
    {
      const double dt = time - b;
      if (dt >= 0.0 && dt < 0.8)
      {
        const double v = 0.5 * std::sin(M_PI * dt / 0.8);
        add("browInnerUp_L", v);
        add("browInnerUp_R", v);
        add("browOuterUp_L", 0.6 * v);
        add("browOuterUp_R", 0.6 * v);
      }
    }
    const Gaze* g = &gaze.front();
    for (const Gaze& candidate : gaze)
    {
      if (candidate.Time <= time)
      {
        g = &candidate;
      }
    }
    add(g->X > 0 ? "eyeLookOut_L" : "eyeLookIn_L", std::abs(g->X));
    add(g->X > 0 ? "eyeLookIn_R" : "eyeLookOut_R", std::abs(g->X));
    add(g->Y > 0 ? "eyeLookUp_L" : "eyeLookDown_L", std::abs(g->Y));
    add(g->Y > 0 ? "eyeLookUp_R" : "eyeLookDown_R", std::abs(g->Y));
    const double smile = 0.25 * (1.0 + std::sin(2.0 * M_PI * time / 9.0)) * 0.5;
    add("mouthSmile_L", smile);
    add("mouthSmile_R", smile);
    add("cheekSquint_L", 0.5 * smile);
    add("cheekSquint_R", 0.5 * smile);
    track.AppendFrame(w);
  }
  return track;
}
} // namespace reductionstudy
