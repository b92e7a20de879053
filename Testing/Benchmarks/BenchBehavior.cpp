// SPDX-License-Identifier: BSD-3-Clause
// The behaviour control's speed: sampling every channel at one time t (the VTK adapter's
// per-time-step work), building the schedules (Prepare), and a whole track.
// Target: >= 100,000 samples ("frames") per second on one core; the counter frames/s says.
#include "behavior/BehaviorController.h"
#include "speech/SpeechTypes.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

namespace
{
/// A synthetic utterance with the 15 Oculus visemes at 100 fps, one viseme after another.
morphnode::Utterance MakeUtterance(double seconds)
{
  const std::vector<std::string> names = { "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn",
    "RR", "aa", "E", "ih", "oh", "ou" };
  morphnode::Utterance u;
  u.Visemes = morphnode::WeightTrack(names, 100.0);
  const int frames = static_cast<int>(seconds * 100.0) + 1;
  std::vector<double> row(names.size());
  for (int f = 0; f < frames; ++f)
  {
    std::fill(row.begin(), row.end(), 0.0);
    const double phase = f / 8.0; // a viseme every 80 ms, cross-faded
    const int v = 1 + static_cast<int>(phase) % 14;
    const double a = phase - std::floor(phase);
    row[v] = 1.0 - a;
    row[1 + (v % 14)] = a;
    u.Visemes.AppendFrame(row);
  }
  u.Duration = seconds;
  for (double t = 0.5; t < seconds; t += 1.5)
  {
    u.Cues.push_back({ morphnode::NonverbalCue::Kind::BrowRaise, t, 0.3, 0.8 });
    u.Cues.push_back({ morphnode::NonverbalCue::Kind::Nod, t + 0.7, 0.4, 0.6 });
  }
  return u;
}

/// A busy minute: speech most of the time, moods, gestures, looks, all idle behaviour.
morphnode::BehaviorController MakeScene()
{
  morphnode::BehaviorController b;
  b.SetSeed(2004);
  b.SetDuration(60.0);
  b.SetFrameRate(60.0);
  b.SetMood("happy", 0.5, 0.0);
  b.SetMood("surprised", 0.7, 20.0);
  b.SetMood("neutral", 0.0, 40.0);
  for (int i = 0; i < 6; ++i)
  {
    b.Speak(MakeUtterance(8.0), 2.0 + 10.0 * i);
    b.Gesture("nod", 3.0 + 10.0 * i, 0.8, 0.7);
    b.Gesture("smile", 5.0 + 10.0 * i, 2.0, 0.6);
    b.Gesture("raise_brows", 7.0 + 10.0 * i, 1.0, 0.8);
    b.LookAt(10.0, -5.0, 9.0 + 10.0 * i, 1.5);
  }
  b.Gesture("close_eyes", 30.0, 2.0, 1.0);
  return b;
}

void BM_BehaviorSample(benchmark::State& state)
{
  morphnode::BehaviorController b = MakeScene();
  b.Prepare();
  std::vector<double> weights(b.GetNumberOfChannels());
  double t = 0.0;
  for (auto _ : state)
  {
    b.Sample(t, weights.data());
    benchmark::DoNotOptimize(weights.data());
    benchmark::ClobberMemory();
    t += 1.0 / 60.0;
    t = t > 60.0 ? 0.0 : t;
  }
  state.counters["frames/s"] =
    benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["channels"] = static_cast<double>(b.GetNumberOfChannels());
}
BENCHMARK(BM_BehaviorSample);

void BM_BehaviorPrepare(benchmark::State& state)
{
  morphnode::BehaviorController b = MakeScene();
  b.SetDuration(static_cast<double>(state.range(0)));
  for (auto _ : state)
  {
    b.SetSeed(b.GetSeed() + 1); // a change, so the schedules are built again
    b.Prepare();
    benchmark::DoNotOptimize(b.GetIdleSchedule().Blinks.data());
  }
}
BENCHMARK(BM_BehaviorPrepare)->Arg(60)->Arg(3600)->Unit(benchmark::kMicrosecond);

void BM_BehaviorGenerateTrack(benchmark::State& state)
{
  morphnode::BehaviorController b = MakeScene();
  size_t frames = 0;
  for (auto _ : state)
  {
    const morphnode::WeightTrack track = b.GenerateTrack();
    frames += track.GetNumberOfFrames();
    benchmark::DoNotOptimize(track.GetFrame(0));
  }
  state.counters["frames/s"] =
    benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BehaviorGenerateTrack)->Unit(benchmark::kMillisecond);
} // namespace

BENCHMARK_MAIN();
