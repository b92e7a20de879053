// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: gestures and moods as data (BehaviorLibrary::FromJson, docs/behavior.md), then
// every gesture and mood it accepted played by a live behaviour: weights stay finite.
#include "base/Error.h"
#include "behavior/BehaviorLibrary.h"
#include "behavior/LiveBehavior.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const morphnode::BehaviorLibrary library =
      morphnode::BehaviorLibrary::FromJson(text, "fuzz", &morphnode::BehaviorLibrary::Default());
    if (library.FindMoodIndex("neutral") < 0)
    {
      std::abort();
    }
    morphnode::LiveBehavior live(
      { "sil", "aa", "ou" }, morphnode::BehaviorParameters(), 1, library);
    std::vector<double> w(live.GetNumberOfChannels());
    double t = 0.0;
    for (const auto& g : library.GetGestures())
    {
      live.Gesture(g.Name, t, 1.0);
    }
    for (const auto& m : library.GetMoods())
    {
      live.SetMood(m.Name, 1.0, t);
      for (int i = 0; i < 8; ++i, t += 0.25)
      {
        live.Sample(t, w.data());
        for (double v : w)
        {
          if (!std::isfinite(v))
          {
            std::abort();
          }
        }
      }
    }
  }
  catch (const morphnode::InputError&)
  {
  }
  return 0;
}
