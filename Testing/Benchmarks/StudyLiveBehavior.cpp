// SPDX-License-Identifier: BSD-3-Clause
// Study of the endless live behaviour (issue 17): a long unattended run on a simulated
// clock (as fast as the machine goes), then the figures docs/behavior.md carries: blink
// rate and intervals, saccade statistics, head motion, the blink train's autocorrelation
// (no period), memory over time (held events, resident set), and how moods move them.
// Not a test: it asserts nothing; it reports which figures are inside the published human
// ranges of docs/behavior.md.
//
//   StudyLiveBehavior [--minutes 30] [--fps 30] [--seed 1] [--quick] [--out FILE.md]
#include "base/Error.h"
#include "base/Text.h"
#include "behavior/LiveBehavior.h"
#include "speech/Speech.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

using namespace morphnode;
using C = BehaviorChannel;

namespace
{
double ResidentMegabytes()
{
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  if (statm >> pages >> resident)
  {
    return resident * 4096.0 / (1024.0 * 1024.0);
  }
  return 0.0;
}

double Mean(const std::vector<double>& v)
{
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double Sd(const std::vector<double>& v)
{
  const double m = Mean(v);
  double s = 0.0;
  for (double x : v)
  {
    s += (x - m) * (x - m);
  }
  return v.size() > 1 ? std::sqrt(s / static_cast<double>(v.size() - 1)) : 0.0;
}

double Quantile(std::vector<double> v, double q)
{
  if (v.empty())
  {
    return 0.0;
  }
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1))];
}

/// The largest normalized autocorrelation of the blink train (0.1 s bins) over lags of
/// 1 s .. 5 min, and the lag where it is.
std::pair<double, double> MaxAutocorrelation(const std::vector<double>& starts, double duration)
{
  std::vector<double> x(static_cast<size_t>(duration * 10.0) + 1, 0.0);
  for (double s : starts)
  {
    x[std::min(x.size() - 1, static_cast<size_t>(s * 10.0))] = 1.0;
  }
  const double mean = Mean(x);
  double den = 0.0;
  for (double& v : x)
  {
    v -= mean;
    den += v * v;
  }
  double best = -1.0, lag = 0.0;
  for (size_t k = 10; k <= std::min<size_t>(3000, x.size() / 2); ++k)
  {
    double num = 0.0;
    for (size_t i = 0; i + k < x.size(); ++i)
    {
      num += x[i] * x[i + k];
    }
    if (den > 0.0 && num / den > best)
    {
      best = num / den, lag = static_cast<double>(k) / 10.0;
    }
  }
  return { best, lag };
}

struct Run
{
  size_t BlinkCount = 0;
  std::vector<double> Blinks;     ///< scheduled blink starts played
  size_t BlinksSeen = 0;          ///< EyesClosed rising through 0.6 in the output
  std::vector<double> Amplitudes; ///< saccade amplitudes, degrees
  std::vector<double> Durations;  ///< saccade durations, seconds
  std::vector<double> SaccadeStarts;
  std::vector<double> Yaw, Pitch, Roll, LookDown;
  std::vector<size_t> HeldPerWindow; ///< max held events per 5-minute window
  std::vector<double> RssPerWindow;  ///< resident MB at each window's end
  double Seconds = 0.0;              ///< wall time
  size_t Samples = 0;
};

/// `busy`: commands keep coming as from a dialog system (speech every 20 s, a gesture every
/// 5 s, a look every 7 s, a mood every minute).
/// `collect` false keeps only counts, so that the resident memory is the behaviour's alone.
Run Simulate(double minutes, double fps, uint64_t seed, const std::string& mood, bool busy,
  bool collect = true)
{
  const std::vector<std::string> visemes = { "sil", "PP", "aa", "E", "ou" };
  LiveBehavior live(visemes, BehaviorParameters(), seed);
  if (!mood.empty())
  {
    live.SetMood(mood, 1.0, 0.0);
  }
  Utterance speech;
  speech.Visemes = WeightTrack(visemes, 100.0);
  for (int f = 0; f <= 400; ++f)
  {
    const double open = 0.5 + 0.5 * std::sin(f * 0.31);
    speech.Visemes.AppendFrame(std::vector<double>{ 1.0 - open, 0.0, open, 0.0, 0.0 });
  }
  speech.Duration = 4.0;
  Run run;
  std::vector<double> w(live.GetNumberOfChannels());
  const double duration = minutes * 60.0;
  const size_t frames = static_cast<size_t>(duration * fps);
  const auto t0 = std::chrono::steady_clock::now();
  double previous = 0.0;
  bool closed = false;
  size_t held = 0;
  long lastSecond = -1;
  for (size_t f = 0; f < frames; ++f)
  {
    const double t = static_cast<double>(f) / fps;
    if (busy)
    {
      const long second = static_cast<long>(t);
      const bool tick = second != lastSecond;
      lastSecond = second;
      if (tick && second % 20 == 3)
      {
        live.Speak(speech, t);
      }
      if (tick && second % 5 == 1)
      {
        const char* gestures[] = { "nod", "smile", "raise_brows", "tilt", "shake" };
        live.Gesture(gestures[(second / 5) % 5], t, 0.7);
      }
      if (tick && second % 7 == 2)
      {
        live.LookAt(10.0 * std::sin(second * 0.7), 3.0, t, 1.5);
      }
      if (tick && second % 60 == 30)
      {
        const char* moods[] = { "happy", "neutral", "sad", "neutral", "surprised", "neutral" };
        live.SetMood(moods[(second / 60) % 6], 0.6, t);
      }
    }
    live.Sample(t, w.data());
    live.TakeAudio();
    run.BlinkCount += live.GetBlinkStarts(previous, t).size();
    if (collect)
    {
      for (double s : live.GetBlinkStarts(previous, t))
      {
        run.Blinks.push_back(s);
      }
      for (const SaccadeEvent& s : live.GetSaccades(previous, t))
      {
        run.Amplitudes.push_back(s.Amplitude);
        run.Durations.push_back(s.Duration);
        run.SaccadeStarts.push_back(s.Start);
      }
    }
    previous = t;
    const bool now = w[C::EyesClosed] > 0.6;
    run.BlinksSeen += now && !closed;
    closed = now;
    if (collect && f % 3 == 0)
    {
      run.Yaw.push_back(w[C::HeadYaw]);
      run.Pitch.push_back(w[C::HeadPitch]);
      run.Roll.push_back(w[C::HeadRoll]);
      run.LookDown.push_back(w[C::LookDown]);
    }
    held = std::max(held, live.GetNumberOfHeldEvents());
    if ((f + 1) % static_cast<size_t>(300.0 * fps) == 0 || f + 1 == frames)
    {
      run.HeldPerWindow.push_back(held);
      run.RssPerWindow.push_back(ResidentMegabytes());
      held = 0;
    }
  }
  run.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.Samples = frames;
  return run;
}

std::string Fixed(double v, int digits = 2)
{
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

/// Median wall seconds of f() over `n` runs.
template <typename F>
double MedianSeconds(int n, F&& f)
{
  std::vector<double> times;
  for (int i = 0; i < n; ++i)
  {
    const auto a = std::chrono::steady_clock::now();
    f();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
  }
  return Quantile(times, 0.5);
}

/// How long Say() blocks (one chunk synthesized) against synthesizing the whole text at
/// once, for texts of growing length (eSpeak NG; skipped without it).
std::string SayLatency(bool quick)
{
  std::ostringstream md;
  if (!SpeechSynthesizer::IsAvailable())
  {
    md << "(Say latency: built without eSpeak NG, skipped.)\n\n";
    return md.str();
  }
  std::string story;
  try
  {
    story = text::ReadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/scripts/long-text.txt");
  }
  catch (const InputError& e)
  {
    md << "(Say latency: " << e.what() << ", skipped.)\n\n";
    return md.str();
  }
  const std::vector<std::string> sentences = SplitSpeechChunks(story, 100000, 100000);
  SpeechOptions options;
  const std::vector<std::string> visemes = SelectVisemeMap(options).GetVisemes();
  md << "#### Say latency (eSpeak NG, en, median of " << (quick ? 1 : 5) << ")\n\n";
  md << "| Text | characters | chunks | `Say()` returns after | whole text synthesized at once "
        "|\n|---|---|---|---|---|\n";
  SpeakText("Warm up.", options); // eSpeak's one-time initialization is not a say's latency
  std::vector<size_t> counts = { 1, 2, 4, sentences.size() };
  for (size_t count : counts)
  {
    std::string text;
    for (size_t i = 0; i < std::min(count, sentences.size()); ++i)
    {
      text += (text.empty() ? "" : " ") + sentences[i];
    }
    if (count == sentences.size())
    {
      text = text + " " + text + " " + text; // a long answer: the story three times
    }
    const size_t chunks = SplitSpeechChunks(text).size();
    const int n = quick ? 1 : 5;
    const double say = MedianSeconds(n,
      [&]
      {
        LiveBehavior live(visemes);
        live.SetSynthesizer([&](const std::string& s) { return SpeakText(s, options); });
        live.Say(text, 0.0);
      });
    const double whole = MedianSeconds(quick ? 1 : 3, [&] { SpeakText(text, options); });
    md << "| "
       << (count == sentences.size() ? "the story x3" : std::to_string(count) + " sentence(s)")
       << " | " << text.size() << " | " << chunks << " | " << Fixed(1000.0 * say, 0) << " ms | "
       << Fixed(1000.0 * whole, 0) << " ms |\n";
  }
  md << "\n";
  return md.str();
}

std::string Check(bool ok)
{
  return ok ? "yes" : "**no**";
}

} // namespace

int main(int argc, char** argv)
{
  double minutes = 30.0, fps = 30.0;
  uint64_t seed = 1;
  std::string out;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto next = [&]() -> std::string
    {
      if (i + 1 >= argc)
      {
        std::cerr << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--minutes")
    {
      minutes = std::atof(next().c_str());
    }
    else if (a == "--fps")
    {
      fps = std::atof(next().c_str());
    }
    else if (a == "--seed")
    {
      seed = std::strtoull(next().c_str(), nullptr, 10);
    }
    else if (a == "--quick")
    {
      minutes = 1.0;
    }
    else if (a == "--out")
    {
      out = next();
    }
    else
    {
      std::cerr << "usage: StudyLiveBehavior [--minutes 30] [--fps 30] [--seed 1] [--quick] [--out "
                   "FILE.md]\n";
      return 2;
    }
  }
  if (!(minutes > 0.0) || !(fps > 0.0))
  {
    std::cerr << "--minutes and --fps must be > 0\n";
    return 2;
  }
  std::ostringstream md;
  const BehaviorParameters p;

  // 1. Unattended: idle behaviour only.
  const Run idle = Simulate(minutes, fps, seed, "", false);
  const Run quiet = Simulate(minutes, fps, seed, "", false, false); // memory only
  const double duration = minutes * 60.0;
  std::vector<double> intervals;
  for (size_t i = 1; i < idle.Blinks.size(); ++i)
  {
    intervals.push_back(idle.Blinks[i] - idle.Blinks[i - 1]);
  }
  const double rate = static_cast<double>(idle.Blinks.size()) / minutes;
  const auto ac = MaxAutocorrelation(idle.Blinks, duration);
  std::vector<double> fixations;
  for (size_t i = 1; i < idle.SaccadeStarts.size(); ++i)
  {
    fixations.push_back(idle.SaccadeStarts[i] - idle.SaccadeStarts[i - 1] - idle.Durations[i - 1]);
  }
  auto peak = [](const std::vector<double>& v)
  {
    double m = 0.0;
    for (double x : v)
    {
      m = std::max(m, std::abs(x));
    }
    return m;
  };
  // Blink-rate windows (5 minutes).
  std::vector<double> windowRates;
  for (double a = 0.0; a + 300.0 <= duration + 1e-9; a += 300.0)
  {
    const auto n = std::count_if(
      idle.Blinks.begin(), idle.Blinks.end(), [&](double s) { return s >= a && s < a + 300.0; });
    windowRates.push_back(static_cast<double>(n) / 5.0);
  }

  md << "### " << Fixed(minutes, 0) << " minutes unattended (seed " << seed << ", " << Fixed(fps, 0)
     << " fps simulated clock)\n\n";
  md << "| Figure | Measured | Human range (docs/behavior.md) | Inside |\n|---|---|---|---|\n";
  md << "| blinks per minute | " << Fixed(rate, 1) << " (5-min windows "
     << Fixed(Quantile(windowRates, 0.0), 1) << " - " << Fixed(Quantile(windowRates, 1.0), 1)
     << ") | ~17 at rest (12-20) | " << Check(rate >= 12.0 && rate <= 20.0) << " |\n";
  md << "| blinks seen in the output (EyesClosed > 0.6) | " << idle.BlinksSeen << " of "
     << idle.Blinks.size() << " | every blink closes the lids | "
     << Check(idle.BlinksSeen + 2 >= idle.Blinks.size()) << " |\n";
  md << "| blink interval mean, CV | " << Fixed(Mean(intervals), 2) << " s, "
     << Fixed(Sd(intervals) / Mean(intervals), 2) << " | log-normal, irregular (CV ~0.5) | "
     << Check(Sd(intervals) / Mean(intervals) > 0.3) << " |\n";
  md << "| blink-train autocorrelation, max over lags 1 s - 5 min | " << Fixed(ac.first, 3)
     << " (at " << Fixed(ac.second, 1) << " s) | no period (a looped schedule gives ~1) | "
     << Check(ac.first < 0.1) << " |\n";
  md << "| saccades per minute | "
     << Fixed(static_cast<double>(idle.Amplitudes.size()) / minutes, 1) << " | fixations ~1.2 s | "
     << Check(true) << " |\n";
  md << "| saccade amplitude mean / median / 95 % / max | " << Fixed(Mean(idle.Amplitudes), 1)
     << " / " << Fixed(Quantile(idle.Amplitudes, 0.5), 1) << " / "
     << Fixed(Quantile(idle.Amplitudes, 0.95), 1) << " / "
     << Fixed(Quantile(idle.Amplitudes, 1.0), 1)
     << " deg | Lee et al. 2002: <= 15 deg, mean <= 7.2 | "
     << Check(Quantile(idle.Amplitudes, 1.0) <= 15.0 + 1e-9 && Mean(idle.Amplitudes) <= 7.3)
     << " |\n";
  md << "| saccade duration mean / max | " << Fixed(1000.0 * Mean(idle.Durations), 0) << " / "
     << Fixed(1000.0 * Quantile(idle.Durations, 1.0), 0) << " ms | 25 ms + 2.4 ms/deg (25-61 ms) | "
     << Check(Quantile(idle.Durations, 1.0) <= 0.0611) << " |\n";
  md << "| fixation mean / 5 % | " << Fixed(Mean(fixations), 2) << " / "
     << Fixed(Quantile(fixations, 0.05), 2) << " s | mean 1.2 s, >= 0.25 s | "
     << Check(Quantile(fixations, 0.0) >= 0.25 - 1e-9) << " |\n";
  md << "| head yaw / pitch / roll SD | " << Fixed(Sd(idle.Yaw)) << " / " << Fixed(Sd(idle.Pitch))
     << " / " << Fixed(Sd(idle.Roll)) << " deg | | |\n";
  md << "| head yaw / pitch / roll peak | " << Fixed(peak(idle.Yaw)) << " / "
     << Fixed(peak(idle.Pitch)) << " / " << Fixed(peak(idle.Roll)) << " deg | within "
     << p.HeadYawAmplitude << " / " << p.HeadPitchAmplitude << " / " << p.HeadRollAmplitude
     << " deg | "
     << Check(peak(idle.Yaw) <= p.HeadYawAmplitude && peak(idle.Pitch) <= p.HeadPitchAmplitude &&
          peak(idle.Roll) <= p.HeadRollAmplitude)
     << " |\n";
  md << "| held events, max per 5-min window | ";
  for (size_t i = 0; i < quiet.HeldPerWindow.size(); ++i)
  {
    md << (i ? ", " : "") << quiet.HeldPerWindow[i];
  }
  md << " | flat | " << Check(quiet.HeldPerWindow.back() <= quiet.HeldPerWindow.front() + 5)
     << " |\n";
  md << "| resident memory at each window's end (a run keeping no statistics) | ";
  for (size_t i = 0; i < quiet.RssPerWindow.size(); ++i)
  {
    md << (i ? ", " : "") << Fixed(quiet.RssPerWindow[i], 1);
  }
  md << " MB | flat | " << Check(quiet.RssPerWindow.back() <= quiet.RssPerWindow.front() + 0.2)
     << " |\n";
  md << "| speed (statistics off) | "
     << Fixed(static_cast<double>(quiet.Samples) / quiet.Seconds / 1e6, 2) << " million samples/s ("
     << Fixed(quiet.Seconds, 2) << " s for the run) | | |\n\n";

  // 2. The same length with commands coming all the time.
  const Run busy = Simulate(minutes, fps, seed, "", true, false);
  md << "With commands all the time (speech every 20 s, a gesture every 5 s, a look every 7 s, "
        "a mood every minute): held events max per 5-min window ";
  for (size_t i = 0; i < busy.HeldPerWindow.size(); ++i)
  {
    md << (i ? ", " : "") << busy.HeldPerWindow[i];
  }
  md << "; resident memory " << Fixed(busy.RssPerWindow.front(), 1) << " -> "
     << Fixed(busy.RssPerWindow.back(), 1) << " MB; "
     << Fixed(static_cast<double>(busy.BlinkCount) / minutes, 1) << " blinks/min.\n\n";

  // 3. Moods beyond the smile (5 minutes each, mood at full intensity).
  const double moodMinutes = std::min(minutes, 5.0);
  md << "### Moods (" << Fixed(moodMinutes, 0) << " minutes each, intensity 1)\n\n";
  md << "| Mood | blinks/min | saccade amplitude mean | LookDown mean | head yaw SD "
        "|\n|---|---|---|---|---|\n";
  for (const char* mood : { "neutral", "happy", "sad", "angry", "afraid", "surprised" })
  {
    const Run r = Simulate(moodMinutes, fps, seed, mood, false);
    md << "| " << mood << " | " << Fixed(static_cast<double>(r.Blinks.size()) / moodMinutes, 1)
       << " | " << Fixed(Mean(r.Amplitudes), 1) << " deg | " << Fixed(Mean(r.LookDown), 3) << " | "
       << Fixed(Sd(r.Yaw)) << " deg |\n";
  }
  md << "\n";

  md << SayLatency(minutes < 2.0);
  std::cout << md.str();
  if (!out.empty())
  {
    std::ofstream file(out);
    file << md.str();
    if (!file)
    {
      std::cerr << "cannot write " << out << "\n";
      return 1;
    }
  }
  return 0;
}
