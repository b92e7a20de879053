// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Nonverbal.h"

#include "speech/Sampa.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace
{
/// Mean of a phoneme's pitch targets; 0 when it has none.
double PhonemePitch(const TimedPhoneme& p)
{
  double sum = 0.0;
  int count = 0;
  for (const auto& target : p.Pitch)
  {
    if (std::isfinite(target.second) && target.second > 0.0)
    {
      sum += target.second;
      ++count;
    }
  }
  return count ? sum / count : 0.0;
}

NonverbalCue MakeCue(NonverbalCue::Kind kind, double start, double duration, double intensity)
{
  NonverbalCue cue;
  cue.Type = kind;
  cue.Start = std::max(0.0, start);
  cue.Duration = std::max(0.0, duration);
  cue.Intensity = std::clamp(intensity, 0.0, 1.0);
  return cue;
}
} // namespace

std::vector<NonverbalCue> DeriveNonverbalCues(
  const std::vector<TimedPhoneme>& phonemes, const NonverbalOptions& options)
{
  std::vector<NonverbalCue> cues;
  const size_t n = phonemes.size();
  std::vector<double> pitch(n, 0.0);
  double weightedSum = 0.0, weight = 0.0;
  for (size_t i = 0; i < n; ++i)
  {
    if (IsPausePhoneme(phonemes[i].Sampa) || !std::isfinite(phonemes[i].Duration))
    {
      continue;
    }
    pitch[i] = PhonemePitch(phonemes[i]);
    if (pitch[i] > 0.0)
    {
      // Duration weighting keeps many short voiced consonants from skewing the mean.
      const double w = std::max(phonemes[i].Duration, 1e-3);
      weightedSum += w * pitch[i];
      weight += w;
    }
  }
  const double meanPitch = weight > 0.0 ? weightedSum / weight : 0.0;
  auto centre = [&](size_t i) { return phonemes[i].Start + 0.5 * phonemes[i].Duration; };

  // Pitch accents: local peaks well above the mean raise the brows.
  if (meanPitch > 0.0)
  {
    std::vector<std::pair<double, size_t>> accents; // (pitch ratio, phoneme)
    for (size_t i = 0; i < n; ++i)
    {
      if (pitch[i] < options.AccentRatio * meanPitch)
      {
        continue;
      }
      bool peak = true;
      for (size_t j = 0; j < n && peak; ++j)
      {
        const bool near = j != i && std::fabs(centre(j) - centre(i)) <= options.AccentNeighbourhood;
        peak = !(near && (pitch[j] > pitch[i] || (pitch[j] == pitch[i] && j < i)));
      }
      if (peak)
      {
        accents.emplace_back(pitch[i] / meanPitch, i);
      }
    }
    std::sort(accents.begin(), accents.end(),
      [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<double> taken;
    for (const auto& [ratio, i] : accents)
    {
      const double t = centre(i);
      if (std::any_of(taken.begin(), taken.end(),
            [&](double u) { return std::fabs(u - t) < options.AccentMinimumSpacing; }))
      {
        continue; // a stronger accent close by already raises the brows
      }
      taken.push_back(t);
      const double excess = (ratio - 1.0) / (2.0 * std::max(options.AccentRatio - 1.0, 1e-6));
      cues.push_back(MakeCue(NonverbalCue::Kind::BrowRaise, phonemes[i].Start - options.BrowLead,
        options.BrowDuration, excess));
    }
  }

  // Pauses and sentence ends. `lastSpoken` is the last non-pause phoneme so far.
  auto sentenceEnd = [&](size_t lastSpoken, double intensity)
  {
    // The last voiced phoneme of the sentence tells a question (rising pitch) apart.
    double finalPitch = 0.0;
    for (size_t j = lastSpoken + 1; j-- > 0 && !IsPausePhoneme(phonemes[j].Sampa);)
    {
      if (pitch[j] > 0.0)
      {
        finalPitch = pitch[j];
        break;
      }
    }
    const TimedPhoneme& last = phonemes[lastSpoken];
    if (meanPitch > 0.0 && finalPitch >= options.QuestionRise * meanPitch)
    {
      cues.push_back(MakeCue(
        NonverbalCue::Kind::BrowRaise, last.Start - options.BrowLead, options.BrowDuration, 0.6));
    }
    else
    {
      cues.push_back(MakeCue(NonverbalCue::Kind::Nod, last.Start, options.NodDuration, intensity));
    }
  };
  bool spoken = false;
  size_t lastSpoken = 0;
  for (size_t i = 0; i < n;)
  {
    if (!IsPausePhoneme(phonemes[i].Sampa))
    {
      spoken = true;
      lastSpoken = i++;
      continue;
    }
    const double start = phonemes[i].Start;
    double end = start;
    while (i < n && IsPausePhoneme(phonemes[i].Sampa))
    {
      end = std::max(end, phonemes[i].Start + phonemes[i].Duration);
      ++i;
    }
    const bool interior = spoken && i < n; // speech on both sides
    const double length = end - start;
    if (!interior || !std::isfinite(length))
    {
      continue;
    }
    if (length >= options.RelaxPause)
    {
      cues.push_back(
        MakeCue(NonverbalCue::Kind::Relax, start, length, length / (2.0 * options.BlinkPause)));
    }
    if (length >= options.BlinkPause)
    {
      cues.push_back(MakeCue(NonverbalCue::Kind::Blink, start, options.BlinkDuration, 1.0));
    }
    if (length >= options.SentencePause)
    {
      sentenceEnd(lastSpoken, 0.7);
    }
  }
  if (spoken)
  {
    sentenceEnd(lastSpoken, 1.0);
  }
  std::stable_sort(cues.begin(), cues.end(),
    [](const NonverbalCue& a, const NonverbalCue& b) { return a.Start < b.Start; });
  return cues;
}
} // namespace morphnode
