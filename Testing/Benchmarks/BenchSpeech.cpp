// SPDX-License-Identifier: BSD-3-Clause
// Speech benchmarks. The figure that matters is `realtime_factor` of BM_TextToWeightTrack:
// seconds of speech produced per second of wall time, synthesis included (goal >= 50).
#include "speech/Speech.h"

#include <benchmark/benchmark.h>

namespace
{
using namespace morphnode;

const char* TextFor(const std::string& voice)
{
  return voice == "de"
    ? "Guten Tag! Ich bin ein sprechender Kopf. Meine Lippen folgen der Sprache, und wenn ich "
      "eine Pause mache, blinzle ich. Am Ende eines Satzes nicke ich leicht mit dem Kopf."
    : "Hello! I am a talking head. My lips follow the speech, and when I pause, I blink. At the "
      "end of a sentence I nod a little, and important words raise my brows.";
}

void ReportRealtime(benchmark::State& state, double audioSeconds)
{
  // kIsRate divides by the measured time: audio seconds per compute second.
  state.counters["realtime_factor"] = benchmark::Counter(audioSeconds, benchmark::Counter::kIsRate);
  state.counters["audio_s"] = audioSeconds / static_cast<double>(state.iterations());
}

/// Text -> Utterance (synthesis, SAMPA, visemes, coarticulation at 60 fps, cues).
void BM_TextToWeightTrack(benchmark::State& state, const std::string& voice, VisemeSet set)
{
  SpeechOptions options;
  options.Voice = voice;
  options.Visemes = set;
  double audioSeconds = 0.0;
  for (auto _ : state)
  {
    const Utterance u = SpeakText(TextFor(voice), options);
    benchmark::DoNotOptimize(u.Visemes.GetFrame(0));
    audioSeconds += u.Duration;
  }
  ReportRealtime(state, audioSeconds);
}
BENCHMARK_CAPTURE(BM_TextToWeightTrack, en_oculus15, std::string("en"), VisemeSet::Oculus15)
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();
BENCHMARK_CAPTURE(BM_TextToWeightTrack, de_german16, std::string("de"), VisemeSet::German16)
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();

/// Only the part after synthesis: phonemes -> weight track (+ cues).
void BM_PhonemesToWeightTrack(benchmark::State& state)
{
  SpeechOptions options;
  const SynthesisResult r = SpeechSynthesizer("en").Synthesize(TextFor("en"));
  const VisemeMap map = SelectVisemeMap(options);
  for (auto _ : state)
  {
    const Utterance u = BuildUtterance(r.Phonemes, {}, r.SampleRate, map, options);
    benchmark::DoNotOptimize(u.Visemes.GetFrame(0));
  }
  ReportRealtime(state, r.Duration * static_cast<double>(state.iterations()));
}
BENCHMARK(BM_PhonemesToWeightTrack)->Unit(benchmark::kMicrosecond)->UseRealTime();
} // namespace

BENCHMARK_MAIN();
