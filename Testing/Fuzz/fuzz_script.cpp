// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target of the behaviour script parser (text and JSON): any input either parses
// or throws morphnode::InputError; what parses is applied, prepared and sampled, so that
// nothing the parser accepts can crash the controller either.
#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "behavior/BehaviorScript.h"
#include "speech/SpeechTypes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{
morphnode::Utterance TinyUtterance(const std::string& text)
{
  morphnode::Utterance u;
  u.Visemes = morphnode::WeightTrack({ "sil", "aa", "PP" }, 50.0);
  const size_t frames = 2 + text.size() % 50;
  for (size_t f = 0; f < frames; ++f)
  {
    const double open = 0.5 + 0.5 * std::sin(0.7 * static_cast<double>(f));
    u.Visemes.AppendFrame(std::vector<double>{ 1.0 - open, open, 0.0 });
  }
  u.Duration = static_cast<double>(frames - 1) / 50.0;
  u.Cues.push_back({ morphnode::NonverbalCue::Kind::Blink, 0.1, 0.1, 1.0 });
  u.Cues.push_back({ morphnode::NonverbalCue::Kind::Nod, 0.2, 0.3, 0.5 });
  return u;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const morphnode::BehaviorScript script = morphnode::ParseBehaviorScript(text);
    morphnode::BehaviorController behavior;
    behavior.SetSynthesizer(TinyUtterance);
    behavior.SetPhonemeFileLoader(TinyUtterance);
    behavior.Apply(script);
    // Keep each run short: the idle schedule grows with the duration.
    behavior.SetDuration(
      std::min(behavior.GetDuration() > 0.0 ? behavior.GetDuration() : 30.0, 30.0));
    behavior.Prepare();
    std::vector<double> weights;
    for (double t : { 0.0, 0.37, 1.0, 2.5, 12.0, 29.9, 1e6, -1.0 })
    {
      behavior.Sample(t, weights);
      for (double w : weights)
      {
        if (!std::isfinite(w))
        {
          std::abort(); // a script the parser accepts renders (issue 29)
        }
      }
    }
  }
  catch (const morphnode::InputError&)
  {
    // Rejected input is the expected outcome for most of the fuzzer's inputs.
  }
  return 0;
}
