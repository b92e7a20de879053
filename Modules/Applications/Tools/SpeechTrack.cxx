// SPDX-License-Identifier: BSD-3-Clause
#include "SpeechTrack.h"

#include "base/Error.h"
#include "behavior/BehaviorController.h"

#include <algorithm>
#include <random>

namespace morphnode
{
namespace study
{
WeightTrack MakeBehaviorTrack(const SpeechTrackOptions& options)
{
  SpeechOptions speech;
  speech.Voice = options.Voice;
  speech.Rate = options.Rate;
  std::string text = options.Text;
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');

  BehaviorController behavior;
  behavior.SetSeed(options.Seed);
  behavior.SetFrameRate(options.FrameRate);
  behavior.SetSynthesizer([&](const std::string& t) { return SpeakText(t, speech); });

  // The speech, after a short pause, then the gestures of a lively speaker around it.
  const double start = 0.6;
  behavior.SetMood("happy", 0.3, 0.0);
  behavior.Say(text, start);
  if (behavior.GetUtterances().empty())
  {
    throw InputError("nothing to say");
  }
  const double end = behavior.GetUtterances().back().End;
  std::mt19937_64 random(options.Seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto between = [&](double a, double b) { return a + (b - a) * unit(random); };
  for (double t = start + between(0.5, 2.0); t < end - 1.0; t += between(1.5, 4.0))
  {
    const double pick = unit(random);
    if (pick < 0.3)
      behavior.Gesture("raise_brows", t, between(0.6, 1.2), between(0.4, 0.9));
    else if (pick < 0.5)
      behavior.Gesture("smile", t, between(1.0, 2.5), between(0.3, 0.8));
    else if (pick < 0.7)
      behavior.Gesture("nod", t, between(0.5, 1.0), between(0.4, 0.8));
    else if (pick < 0.8)
      behavior.Gesture("frown", t, between(0.6, 1.2), between(0.3, 0.6));
    else
      behavior.LookAt(between(-20.0, 20.0), between(-10.0, 10.0), t, between(0.6, 1.5));
  }
  behavior.SetMood("happy", 0.6, std::max(0.0, end - 2.0), 1.5); // a warm ending (short texts too)
  behavior.SetDuration(end + 1.0);
  return behavior.GenerateTrack();
}

WeightTrack ExpandThroughRig(const WeightTrack& semantic, const Rig& rig,
  const std::vector<std::string>& targetNames, std::vector<std::string>* dropped)
{
  if (targetNames.size() != rig.GetNumberOfBoundTargets())
  {
    throw InputError("the rig is bound to " + std::to_string(rig.GetNumberOfBoundTargets()) +
      " targets, not the " + std::to_string(targetNames.size()) + " named");
  }
  // Semantic channels -> rig shapes (channels without a shape, e.g. HeadYaw, are dropped).
  std::vector<int> shapeOf(semantic.GetNumberOfChannels(), -1);
  for (size_t c = 0; c < semantic.GetNumberOfChannels(); ++c)
  {
    shapeOf[c] = rig.FindShape(semantic.GetChannels()[c]);
    if (shapeOf[c] < 0 && dropped)
    {
      dropped->push_back(semantic.GetChannels()[c]);
    }
  }
  WeightTrack track(targetNames, semantic.GetFrameRate());
  std::vector<double> shapes(rig.GetNumberOfShapes()), weights(targetNames.size());
  for (size_t f = 0; f < semantic.GetNumberOfFrames(); ++f)
  {
    std::fill(shapes.begin(), shapes.end(), 0.0);
    for (size_t c = 0; c < semantic.GetNumberOfChannels(); ++c)
    {
      if (shapeOf[c] >= 0)
      {
        shapes[static_cast<size_t>(shapeOf[c])] += semantic.GetValue(f, c);
      }
    }
    rig.Expand(shapes.data(), weights.data());
    track.AppendFrame(weights);
  }
  return track;
}
} // namespace study
} // namespace morphnode
