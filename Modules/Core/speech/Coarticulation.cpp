// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Coarticulation.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace morphnode
{
namespace
{
// Dominance below exp(-DominanceCutoff) of a segment's peak is treated as zero.
constexpr double DominanceCutoff = 30.0;
// More frames than this is certainly a mistake (about 46 hours at 60 fps).
constexpr double MaximumFrames = 1e7;
// Smallest half-width of the rest segments before and after an utterance (seconds).
constexpr double RestHalfWidth = 0.1;

void CheckOptions(const CoarticulationOptions& o)
{
  auto check = [](bool ok, const char* what)
  {
    if (!ok)
    {
      throw InputError(std::string("coarticulation: ") + what);
    }
  };
  check(std::isfinite(o.FrameRate) && o.FrameRate > 0.0 && o.FrameRate <= 1000.0,
    "the frame rate must be in (0, 1000]");
  check(std::isfinite(o.Lead) && std::fabs(o.Lead) <= 1.0, "the lead must be within +-1 s");
  check(std::isfinite(o.ThetaBefore) && o.ThetaBefore > 0.0, "ThetaBefore must be > 0");
  check(std::isfinite(o.ThetaAfter) && o.ThetaAfter > 0.0, "ThetaAfter must be > 0");
  check(std::isfinite(o.Power) && o.Power >= 0.25 && o.Power <= 4.0,
    "the power c must be in [0.25, 4]");
  check(std::isfinite(o.MinimumHalfWidth) && o.MinimumHalfWidth > 0.0 && o.MinimumHalfWidth <= 1.0,
    "the minimum half width must be in (0, 1] s");
  check(std::isfinite(o.ClosureHold) && o.ClosureHold >= 0.0 && o.ClosureHold <= 1.0,
    "the closure hold must be in [0, 1]");
}

/// One segment prepared for evaluation.
struct Kernel
{
  int Viseme;
  double Centre;
  double HalfWidth; // h
  double Magnitude; // a_s
  double Reach[2];  // seconds before / after the centre with non-negligible dominance
  bool Closure;
  double Hold; // closure: half-width of full closure
};

/// exp(-theta * (distance / h)^c).
double Decay(double distance, double halfWidth, double theta, double power)
{
  return std::exp(-theta * std::pow(distance / halfWidth, power));
}
} // namespace

std::vector<VisemeSegment> PhonemesToVisemeSegments(
  const std::vector<TimedPhoneme>& phonemes, const VisemeMap& map, const WarningHandler& warn)
{
  std::set<std::string> warned; // one warning per unknown phoneme, not per occurrence
  const WarningHandler once = [&](const std::string& message)
  {
    if (warn && warned.insert(message).second)
    {
      warn(message);
    }
  };
  std::vector<VisemeSegment> segments;
  segments.reserve(phonemes.size());
  for (const TimedPhoneme& p : phonemes)
  {
    // Diphthongs (and pf) show their visemes in turn, within the phoneme's time.
    double start = p.Start;
    for (const VisemePart& part : map.MapPhonemeParts(p.Sampa, once))
    {
      VisemeSegment s;
      s.Viseme = part.Viseme;
      s.Start = start;
      s.Duration = p.Duration * part.Fraction;
      s.Closure = part.Closure;
      segments.push_back(s);
      start += s.Duration;
    }
  }
  return segments;
}

WeightTrack Coarticulate(const std::vector<VisemeSegment>& segments, const VisemeMap& map,
  double duration, const CoarticulationOptions& options)
{
  CheckOptions(options);
  if (!std::isfinite(duration) || duration < 0.0 || duration * options.FrameRate > MaximumFrames)
  {
    throw InputError("coarticulation: the duration must be >= 0 and below " +
      std::to_string(static_cast<long long>(MaximumFrames / options.FrameRate)) + " s");
  }
  const int channels = static_cast<int>(map.GetVisemes().size());
  const double frameTime = 1.0 / options.FrameRate;

  std::vector<Kernel> kernels;
  kernels.reserve(segments.size());
  for (size_t i = 0; i < segments.size(); ++i)
  {
    const VisemeSegment& s = segments[i];
    if (s.Viseme < 0 || s.Viseme >= channels || !std::isfinite(s.Start) ||
      !std::isfinite(s.Duration) || s.Duration < 0.0)
    {
      std::ostringstream msg;
      msg << "coarticulation: segment " << i << " has a bad viseme index or time";
      throw InputError(msg.str());
    }
    Kernel k;
    k.Viseme = s.Viseme;
    k.Centre = s.Start + 0.5 * s.Duration;
    k.HalfWidth = std::max(0.5 * s.Duration, options.MinimumHalfWidth);
    k.Magnitude = map.GetDominance(s.Viseme);
    k.Closure = s.Closure;
    // At least half a frame (plus rounding), so some frame always lands inside the hold.
    k.Hold =
      s.Closure ? std::max(0.5 * options.ClosureHold * s.Duration, 0.5 * frameTime + 1e-9) : 0.0;
    k.Reach[0] =
      k.Hold + k.HalfWidth * std::pow(DominanceCutoff / options.ThetaBefore, 1.0 / options.Power);
    k.Reach[1] =
      k.Hold + k.HalfWidth * std::pow(DominanceCutoff / options.ThetaAfter, 1.0 / options.Power);
    kernels.push_back(k);
  }
  // The face rests before and after the segments: without these, the long tail of a long
  // last vowel would outweigh a short final pause and reopen the mouth after the speech.
  // Each rest is as wide as the segment it borders (at least RestHalfWidth), so inside the
  // speech it weighs no more than a real neighbour would.
  if (!kernels.empty())
  {
    size_t first = 0, last = 0;
    for (size_t i = 0; i < segments.size(); ++i)
    {
      first = segments[i].Start < segments[first].Start ? i : first;
      last =
        segments[i].Start + segments[i].Duration > segments[last].Start + segments[last].Duration
        ? i
        : last;
    }
    const double firstHalf = std::max(RestHalfWidth, kernels[first].HalfWidth);
    const double lastHalf = std::max(RestHalfWidth, kernels[last].HalfWidth);
    for (const auto& [centre, half] :
      { std::make_pair(segments[first].Start - firstHalf, firstHalf),
        std::make_pair(segments[last].Start + segments[last].Duration + lastHalf, lastHalf) })
    {
      Kernel rest{ map.GetSilenceIndex(), centre, half, map.GetDominance(map.GetSilenceIndex()),
        { 0.0, 0.0 }, false, 0.0 };
      rest.Reach[0] = half * std::pow(DominanceCutoff / options.ThetaBefore, 1.0 / options.Power);
      rest.Reach[1] = half * std::pow(DominanceCutoff / options.ThetaAfter, 1.0 / options.Power);
      kernels.push_back(rest);
    }
  }
  // Sweep in time: kernels enter when their reach begins and leave when it ends.
  std::vector<size_t> byEntry(kernels.size());
  for (size_t i = 0; i < byEntry.size(); ++i)
  {
    byEntry[i] = i;
  }
  std::sort(byEntry.begin(), byEntry.end(),
    [&](size_t a, size_t b)
    { return kernels[a].Centre - kernels[a].Reach[0] < kernels[b].Centre - kernels[b].Reach[0]; });

  WeightTrack track(map.GetVisemes(), options.FrameRate);
  const size_t frames = static_cast<size_t>(std::ceil(duration * options.FrameRate - 1e-9)) + 1;
  std::vector<double> weights(channels), closure(channels);
  std::vector<size_t> active;
  size_t nextEntry = 0;
  for (size_t f = 0; f < frames; ++f)
  {
    const double t = track.GetTime(f) + options.Lead; // the mouth shows what is heard later
    while (nextEntry < byEntry.size() &&
      kernels[byEntry[nextEntry]].Centre - kernels[byEntry[nextEntry]].Reach[0] <= t)
    {
      active.push_back(byEntry[nextEntry++]);
    }
    active.erase(std::remove_if(active.begin(), active.end(),
                   [&](size_t k) { return kernels[k].Centre + kernels[k].Reach[1] < t; }),
      active.end());

    std::fill(weights.begin(), weights.end(), 0.0);
    std::fill(closure.begin(), closure.end(), 0.0);
    double total = 0.0;
    for (size_t index : active)
    {
      const Kernel& k = kernels[index];
      const double tau = t - k.Centre;
      const double theta = tau < 0.0 ? options.ThetaBefore : options.ThetaAfter;
      const double d = k.Magnitude * Decay(std::fabs(tau), k.HalfWidth, theta, options.Power);
      weights[k.Viseme] += d;
      total += d;
      if (k.Closure)
      {
        const double beyondHold = std::fabs(tau) - k.Hold;
        const double envelope =
          beyondHold <= 0.0 ? 1.0 : Decay(beyondHold, k.HalfWidth, theta, options.Power);
        closure[k.Viseme] = std::max(closure[k.Viseme], envelope);
      }
    }
    if (total > 0.0)
    {
      for (double& w : weights)
      {
        w /= total;
      }
    }
    else
    {
      weights[map.GetSilenceIndex()] = 1.0; // nothing spoken near: rest
    }
    // Closures win by maximum; the strongest is applied last so it is exact.
    std::vector<int> closing;
    for (int v = 0; v < channels; ++v)
    {
      if (closure[v] > weights[v])
      {
        closing.push_back(v);
      }
    }
    std::sort(
      closing.begin(), closing.end(), [&](int a, int b) { return closure[a] < closure[b]; });
    for (int v : closing)
    {
      const double rest = 1.0 - weights[v];
      const double scale = rest > 0.0 ? (1.0 - closure[v]) / rest : 0.0;
      for (int u = 0; u < channels; ++u)
      {
        weights[u] = u == v ? closure[v] : weights[u] * scale;
      }
    }
    track.AppendFrame(weights.data());
  }
  return track;
}

WeightTrack CoarticulatePhonemes(const std::vector<TimedPhoneme>& phonemes, const VisemeMap& map,
  double duration, const CoarticulationOptions& options, const WarningHandler& warn)
{
  return Coarticulate(PhonemesToVisemeSegments(phonemes, map, warn), map, duration, options);
}
} // namespace morphnode
