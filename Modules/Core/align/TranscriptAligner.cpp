// SPDX-License-Identifier: BSD-3-Clause
#include "align/TranscriptAligner.h"

#include "align/PhonemeRecognizer.h"
#include "base/Error.h"
#include "base/Text.h"
#include "speech/Sampa.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace morphnode
{
namespace
{
/// Natural-log power ratio of `decibels`.
double LogPower(double decibels)
{
  return decibels * std::log(10.0) / 10.0;
}

double Percentile(std::vector<float> values, double q)
{
  if (values.empty())
  {
    return 0.0;
  }
  const size_t k =
    static_cast<size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

struct Prepared
{
  MfccFeatures Mfcc;
  std::vector<bool> Silent;
  bool HasSpeech = false;
  size_t First = 0, Last = 0; ///< first and last frame of speech (inclusive)
  double Loud = 0.0;          ///< 95th percentile of the log energy
};

Prepared Prepare(const AudioBuffer& audio, const TranscriptAlignOptions& options)
{
  Prepared p;
  p.Mfcc = ComputeMfcc(audio, options.Mfcc);
  p.Silent = FindSilentFrames(p.Mfcc, options.SilenceDecibels);
  p.Loud = Percentile(p.Mfcc.LogEnergy, 0.95);
  // Speech starts at the first run of 3 non-silent frames (a click is not speech).
  const size_t n = p.Mfcc.Frames;
  auto speechRun = [&](size_t i)
  { return i + 2 < n && !p.Silent[i] && !p.Silent[i + 1] && !p.Silent[i + 2]; };
  for (size_t i = 0; i < n; ++i)
  {
    if (speechRun(i))
    {
      p.First = i;
      p.HasSpeech = true;
      break;
    }
  }
  for (size_t i = n; p.HasSpeech && i-- > 2;)
  {
    if (speechRun(i - 2))
    {
      p.Last = i;
      break;
    }
  }
  return p;
}

/// Normalized features of frames [from, to]: cepstra c1.. with mean and variance of the
/// speech frames removed, plus the weighted log energy under the loud level; silent frames
/// all get one canonical vector, so pauses match whatever their noise.
FeatureMatrix Features(
  const Prepared& p, size_t from, size_t to, const TranscriptAlignOptions& options)
{
  const MfccFeatures& m = p.Mfcc;
  const int cepstra = m.Dimension - 1;
  FeatureMatrix f;
  f.Rows = to - from + 1;
  f.Dimension = cepstra + 1;
  f.Values.assign(f.Rows * static_cast<size_t>(f.Dimension), 0.0f);
  std::vector<double> mean(static_cast<size_t>(cepstra), 0.0),
    var(static_cast<size_t>(cepstra), 0.0);
  size_t count = 0;
  for (size_t i = from; i <= to; ++i)
  {
    if (p.Silent[i])
    {
      continue;
    }
    ++count;
    for (int k = 0; k < cepstra; ++k)
    {
      mean[static_cast<size_t>(k)] += m.Row(i)[k + 1];
    }
  }
  for (double& v : mean)
  {
    v /= std::max<size_t>(count, 1);
  }
  for (size_t i = from; i <= to; ++i)
  {
    if (p.Silent[i])
    {
      continue;
    }
    for (int k = 0; k < cepstra; ++k)
    {
      const double d = m.Row(i)[k + 1] - mean[static_cast<size_t>(k)];
      var[static_cast<size_t>(k)] += d * d;
    }
  }
  const double floorLog = LogPower(options.SilenceDecibels);
  const double energyScale = options.EnergyWeight * 3.0 / floorLog;
  for (size_t i = from; i <= to; ++i)
  {
    float* row = f.Values.data() + (i - from) * static_cast<size_t>(f.Dimension);
    if (p.Silent[i])
    {
      row[cepstra] = static_cast<float>(-floorLog * energyScale);
      continue;
    }
    for (int k = 0; k < cepstra; ++k)
    {
      const double sd = std::sqrt(var[static_cast<size_t>(k)] / std::max<size_t>(count, 1)) + 1e-6;
      row[k] = static_cast<float>((m.Row(i)[k + 1] - mean[static_cast<size_t>(k)]) / sd);
    }
    const double e = std::clamp(m.LogEnergy[i] - p.Loud, -floorLog, 0.0);
    row[cepstra] = static_cast<float>(e * energyScale);
  }
  return f;
}

/// The mean distance between random non-silent frames of a and b: the scale of "unrelated".
double RandomPairDistance(const FeatureMatrix& a, const std::vector<bool>& silentA,
  const FeatureMatrix& b, const std::vector<bool>& silentB)
{
  std::vector<size_t> ia, ib;
  for (size_t i = 0; i < a.Rows; ++i)
  {
    if (!silentA[i])
    {
      ia.push_back(i);
    }
  }
  for (size_t j = 0; j < b.Rows; ++j)
  {
    if (!silentB[j])
    {
      ib.push_back(j);
    }
  }
  if (ia.empty() || ib.empty())
  {
    return 0.0;
  }
  uint64_t state = 0x9E3779B97F4A7C15ull; // fixed seed: the same input gives the same score
  auto next = [&state]()
  {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  double sum = 0.0;
  const int samples = 4000;
  for (int s = 0; s < samples; ++s)
  {
    const float* x = a.Row(ia[next() % ia.size()]);
    const float* y = b.Row(ib[next() % ib.size()]);
    double d2 = 0.0;
    for (int k = 0; k < a.Dimension; ++k)
    {
      d2 += (x[k] - y[k]) * (x[k] - y[k]);
    }
    sum += std::sqrt(d2);
  }
  return sum / samples;
}

/// Piecewise-linear map from synthetic to recorded time through the warping path.
class TimeMap
{
public:
  TimeMap(const DtwResult& dtw, size_t aFrom, size_t bFrom, size_t aRows, const MfccFeatures& m,
    double durationA, double durationB)
  {
    std::vector<double> first(aRows, -1.0), last(aRows, -1.0);
    for (const auto& [i, j] : dtw.Path)
    {
      if (first[i] < 0.0)
      {
        first[i] = static_cast<double>(j);
      }
      last[i] = static_cast<double>(j);
    }
    // Anchors in seconds: per aligned frame its centre and its boundary to the next.
    std::vector<std::pair<double, double>> anchors;
    auto time = [&m](double frame) { return m.FrameTime(frame); };
    for (size_t i = 0; i < aRows; ++i)
    {
      const double centre = 0.5 * (first[i] + last[i]);
      anchors.emplace_back(
        time(static_cast<double>(i + aFrom)), time(centre + static_cast<double>(bFrom)));
      if (i + 1 < aRows)
      {
        const double boundary = 0.5 * (last[i] + first[i + 1]);
        anchors.emplace_back(
          time(static_cast<double>(i + aFrom) + 0.5), time(boundary + static_cast<double>(bFrom)));
      }
    }
    // Outside the aligned speech time runs at the synthesis' pace (slope 1; the synthesis
    // is already at the recording's rate): a quiet onset such as /h/ keeps its length
    // before the first loud frame instead of stretching over the leading silence.
    const auto [a0, b0] = anchors.front();
    this->From.push_back(0.0);
    this->To.push_back(0.0);
    if (a0 > b0)
    {
      this->Add(a0 - b0, 0.0);
    }
    else
    {
      this->To.back() = b0 - a0;
    }
    for (const auto& [a, b] : anchors)
    {
      this->Add(a, b);
    }
    const auto [a1, b1] = anchors.back();
    const double restA = durationA - a1, restB = durationB - b1;
    if (restA > restB)
    {
      this->Add(a1 + std::max(0.0, restB), durationB);
    }
    this->Add(durationA, std::min(durationB, b1 + std::max(0.0, restA)));
    this->EndB = durationB;
  }

  double operator()(double t) const
  {
    if (t <= this->From.front())
    {
      return this->To.front();
    }
    const auto it = std::upper_bound(this->From.begin(), this->From.end(), t);
    if (it == this->From.end())
    {
      return this->EndB;
    }
    const size_t k = static_cast<size_t>(it - this->From.begin());
    const double x0 = this->From[k - 1], x1 = this->From[k];
    const double y0 = this->To[k - 1], y1 = this->To[k];
    const double s = x1 > x0 ? (t - x0) / (x1 - x0) : 0.0;
    return std::clamp(y0 + s * (y1 - y0), 0.0, this->EndB);
  }

private:
  void Add(double a, double b)
  {
    // Keep both sequences non-decreasing (clamping at the ends may bend the last anchors).
    if (a <= this->From.back())
    {
      this->To.back() = std::max(this->To.back(), b);
      return;
    }
    this->From.push_back(a);
    this->To.push_back(std::max(b, this->To.back()));
  }

  std::vector<double> From, To;
  double EndB = 0.0;
};

SynthesisResult Synthesize(
  const std::string& transcript, int rate, const TranscriptAlignOptions& options)
{
  SpeechSynthesizer synthesizer(options.Voice, rate);
  synthesizer.SetDataPath(options.DataPath);
  synthesizer.SetEstimatePitch(false);
  return synthesizer.Synthesize(transcript);
}

bool Report(const TranscriptAlignOptions& options, double fraction)
{
  return !options.Progress || options.Progress(fraction);
}

void Cancelled()
{
  throw InputError("alignment cancelled");
}
} // namespace

std::vector<bool> FindSilentFrames(const MfccFeatures& features, double silenceDecibels)
{
  const std::vector<float>& e = features.LogEnergy;
  std::vector<bool> silent(e.size(), true);
  if (e.empty())
  {
    return silent;
  }
  const double loud = Percentile(e, 0.95);
  const double floor = Percentile(e, 0.10);
  // Under the loud level by silenceDecibels, or within the lower third between a noisy
  // recording's floor and its loud level.
  const double threshold =
    std::max(loud - LogPower(silenceDecibels), floor + 0.35 * (loud - floor));
  for (size_t i = 0; i < e.size(); ++i)
  {
    silent[i] = e[i] < threshold || e[i] < std::log(1e-9); // -90 dB full scale is silence
  }
  return silent;
}

bool IsTranscriptAlignmentAvailable()
{
  return SpeechSynthesizer::IsAvailable();
}

TranscriptAlignment AlignTranscript(const AudioBuffer& recording, const std::string& transcript,
  const TranscriptAlignOptions& options)
{
  if (!IsTranscriptAlignmentAvailable())
  {
    throw InputError("aligning a transcript needs eSpeak NG, and this MorphNode was built "
                     "without it (MORPHNODE_ENABLE_ESPEAK=OFF): use timings from a file instead");
  }
  if (recording.IsEmpty() || recording.SampleRate <= 0)
  {
    throw InputError("the recording is empty");
  }
  if (text::Trim(transcript).empty())
  {
    throw InputError("the transcript is empty");
  }
  if (!Report(options, 0.0))
  {
    Cancelled();
  }
  const Prepared rec = Prepare(recording, options);
  const double recordingDuration = recording.GetDuration();
  const double loudDecibels = rec.Loud * 10.0 / std::log(10.0);
  // Speech rises well above its pauses; steady noise (or silence) does not.
  const double rangeDecibels =
    (rec.Loud - Percentile(rec.Mfcc.LogEnergy, 0.10)) * 10.0 / std::log(10.0);
  if (!rec.HasSpeech || loudDecibels < -75.0 || rangeDecibels < 10.0)
  {
    throw InputError("the recording holds no speech (silence or steady noise only)");
  }
  const double recSpan = rec.Mfcc.FrameStep * static_cast<double>(rec.Last - rec.First + 1);

  int rate = options.Rate > 0 ? options.Rate : SpeechSynthesizer::DefaultRate;
  SynthesisResult synth = Synthesize(transcript, rate, options);
  if (!Report(options, 0.1))
  {
    Cancelled();
  }
  Prepared syn = Prepare(FromInt16Mono(synth.Audio, synth.SampleRate), options);
  const bool anyPhoneme = std::any_of(synth.Phonemes.begin(), synth.Phonemes.end(),
    [](const TimedPhoneme& p) { return !IsPausePhoneme(p.Sampa); });
  if (!syn.HasSpeech || !anyPhoneme)
  {
    throw InputError("eSpeak NG finds nothing to say in the transcript " + text::Quote(transcript));
  }
  const double synSpan = syn.Mfcc.FrameStep * static_cast<double>(syn.Last - syn.First + 1);
  TranscriptAlignment result;
  result.TempoRatio = recSpan / synSpan;
  if (result.TempoRatio > 3.0 || result.TempoRatio < 1.0 / 3.0)
  {
    throw InputError("the transcript does not match the recording: its speech lasts " +
      text::FormatNumber(std::round(recSpan * 100) / 100) + " s, the transcript's " +
      text::FormatNumber(std::round(synSpan * 100) / 100) + " s at " + std::to_string(rate) +
      " words per minute (more than 3:1)");
  }
  if (options.AdaptRate && std::abs(std::log(result.TempoRatio)) > std::log(1.1))
  {
    const int adapted = std::clamp(static_cast<int>(std::lround(rate / result.TempoRatio)),
      SpeechSynthesizer::MinimumRate, SpeechSynthesizer::MaximumRate);
    if (adapted != rate)
    {
      rate = adapted;
      synth = Synthesize(transcript, rate, options);
      syn = Prepare(FromInt16Mono(synth.Audio, synth.SampleRate), options);
      if (!syn.HasSpeech)
      {
        throw InputError(
          "eSpeak NG finds nothing to say in the transcript " + text::Quote(transcript));
      }
    }
  }
  result.SynthesisRate = rate;
  if (!Report(options, 0.2))
  {
    Cancelled();
  }

  // Align the speech spans (with a few frames of their silence on either side).
  const size_t margin = 3;
  const size_t aFrom = syn.First >= margin ? syn.First - margin : 0;
  const size_t aTo = std::min(syn.Mfcc.Frames - 1, syn.Last + margin);
  const size_t bFrom = rec.First >= margin ? rec.First - margin : 0;
  const size_t bTo = std::min(rec.Mfcc.Frames - 1, rec.Last + margin);
  const FeatureMatrix a = Features(syn, aFrom, aTo, options);
  const FeatureMatrix b = Features(rec, bFrom, bTo, options);
  const std::vector<bool> silentA(syn.Silent.begin() + static_cast<std::ptrdiff_t>(aFrom),
    syn.Silent.begin() + static_cast<std::ptrdiff_t>(aTo) + 1);
  const std::vector<bool> silentB(rec.Silent.begin() + static_cast<std::ptrdiff_t>(bFrom),
    rec.Silent.begin() + static_cast<std::ptrdiff_t>(bTo) + 1);
  DtwOptions dtwOptions = options.Dtw;
  if (options.Progress)
  {
    dtwOptions.Progress = [&options](double f) { return options.Progress(0.2 + 0.75 * f); };
  }
  DtwResult dtw;
  try
  {
    dtw = AlignFeatures(a, b, silentA, silentB, dtwOptions);
  }
  catch (const InputError& e)
  {
    if (std::string(e.what()) == "alignment cancelled" || !dtwOptions.SlopeConstraint)
    {
      throw;
    }
    dtwOptions.SlopeConstraint = false; // tempo differences beyond 2:1: align without it
    dtw = AlignFeatures(a, b, silentA, silentB, dtwOptions);
  }
  result.CellsEvaluated = dtw.CellsEvaluated;

  // Score: the path's distance where speech meets speech, against unrelated frames.
  double pathSum = 0.0;
  size_t pathCount = 0;
  for (const auto& [i, j] : dtw.Path)
  {
    if (silentA[i] && silentB[j])
    {
      continue;
    }
    double d2 = 0.0;
    for (int k = 0; k < a.Dimension; ++k)
    {
      d2 += (a.Row(i)[k] - b.Row(j)[k]) * (a.Row(i)[k] - b.Row(j)[k]);
    }
    pathSum += std::sqrt(d2);
    ++pathCount;
  }
  const double random = RandomPairDistance(a, silentA, b, silentB);
  result.Score = (random > 0.0 && pathCount > 0) ? 1.0 - (pathSum / pathCount) / random : 0.0;
  // Does the transcript match? The alignment's score alone does not tell on short
  // recordings of natural speech (a speaker far from eSpeak's voice scores low with the
  // right words, and as low with a similar sentence); where it can, an acoustic model
  // judges the words relative to what the audio supports (FitTranscript). The transcript
  // is doubted only when neither the score nor the acoustic check supports it.
  std::string why;
  const std::string language = text::ToLower(options.Voice);
  if (options.AcousticCheck && IsPhonemeRecognitionAvailable() &&
    SpeechLanguageOf(options.Voice) == "en" && language.rfind("en", 0) == 0 &&
    recordingDuration <= options.MaximumCheckSeconds)
  {
    try
    {
      const TranscriptFit fit = FitTranscript(recording, transcript);
      result.FitRatio = fit.Completed ? fit.Ratio : std::numeric_limits<double>::infinity();
      if (!fit.Completed)
      {
        why = "its words cannot be forced through the audio (acoustic check)";
      }
      else if (fit.Ratio > options.MaximumFitRatio)
      {
        why = "its words, forced through the audio, cost " +
          text::FormatNumber(std::round(fit.Ratio * 100) / 100) +
          " times as much as a free phone decode of it (at most " +
          text::FormatNumber(options.MaximumFitRatio) + " for a recording of them; acoustic check)";
      }
    }
    catch (const InputError&)
    {
      // A word the dictionary lacks, no model: the score decides (FitRatio stays NaN).
    }
  }
  if (result.Score < options.MinimumScore)
  {
    why = "alignment score " + text::FormatNumber(std::round(result.Score * 1000) / 1000) + " < " +
      text::FormatNumber(options.MinimumScore) + (why.empty() ? "" : ", and " + why);
  }
  else
  {
    // A score above the bound is evidence enough: synthetic speech (eSpeak's voices, which
    // it compares well with) fits PocketSphinx's model of natural speech poorly even with
    // its own words.
    why.clear();
  }
  if (std::isfinite(result.FitRatio) && result.FitRatio <= options.MaximumFitRatio)
  {
    why.clear(); // the words fit the audio better than a free decode does
  }
  result.Reliable = why.empty();
  if (!result.Reliable && options.Warn)
  {
    // Say which route timed the recording: this transcript, aligned all the same.
    options.Warn("the transcript may not match the recording: " + why +
      "; the recording is timed by aligning this transcript all the same (check the "
      "transcript, or give a timing file)");
  }

  // Carry every boundary across.
  const double synthDuration = synth.Duration;
  const TimeMap map(dtw, aFrom, bFrom, a.Rows, syn.Mfcc, synthDuration, recordingDuration);
  result.Duration = recordingDuration;
  result.SpeechStart =
    rec.Mfcc.FrameTime(static_cast<double>(rec.First)) - 0.5 * rec.Mfcc.FrameStep;
  result.SpeechEnd = rec.Mfcc.FrameTime(static_cast<double>(rec.Last)) + 0.5 * rec.Mfcc.FrameStep;
  for (const TimedPhoneme& p : synth.Phonemes)
  {
    TimedPhoneme q = p;
    q.Start = map(p.Start);
    q.Pitch.clear();
    result.Phonemes.push_back(std::move(q));
  }
  if (!result.Phonemes.empty())
  {
    result.Phonemes.front().Start = 0.0;
  }
  for (size_t k = 0; k < result.Phonemes.size(); ++k)
  {
    const double end =
      k + 1 < result.Phonemes.size() ? result.Phonemes[k + 1].Start : recordingDuration;
    result.Phonemes[k].Duration = std::max(0.0, end - result.Phonemes[k].Start);
  }
  for (const SynthesizedWord& w : synth.Words)
  {
    SynthesizedWord v = w;
    v.Start = map(w.Start);
    v.Duration = std::max(0.0, map(w.Start + w.Duration) - v.Start);
    result.Words.push_back(std::move(v));
  }
  Report(options, 1.0);
  return result;
}
} // namespace morphnode
