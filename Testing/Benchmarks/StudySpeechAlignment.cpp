// SPDX-License-Identifier: BSD-3-Clause
// Study of the speech-from-a-recording routes (issue 15): accuracy against known truth and
// speed, written as the markdown tables of docs/speech.md, plus data for its plots.
//
// Truth: recordings made with eSpeak NG voices other than the aligner's (variants, pitch,
// rate 130-220 words per minute, added noise, other sample rates), whose phoneme events give
// the exact phoneme times. Each route times the same sentence on that recording; the study
// compares per 10 ms frame which viseme is shown (the phoneme's viseme, no coarticulation,
// so the figure measures timing, not blending) and how far each phoneme boundary is off.
// A negative control aligns each recording to a shuffled transcript. Real speech: the
// LibriVox and other recordings of pocketsphinx-testdata (read from /usr/share, never
// copied), whose word boundaries are written out for the plot.
//
//   StudySpeechAlignment [--quick] [--out DIR]
// writes DIR/speech-study.md (tables), DIR/boundary-errors.csv, DIR/human-*.csv.
#include "align/PhonemeRecognizer.h"
#include "align/TranscriptAligner.h"
#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"
#include "speech/Sampa.h"
#include "speech/SpeechSynthesizer.h"
#include "speech/VisemeMap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
struct Sentence
{
  std::string Language;
  std::string Text;
};

const std::vector<Sentence>& Sentences()
{
  static const std::vector<Sentence> sentences = {
    { "en", "The quick brown fox jumps over the lazy dog, and then it runs far away." },
    { "de", "Die alten Bäume im Park verlieren im Herbst ihre bunten Blätter." },
    { "fr", "Bonjour, je voudrais un café au lait et un croissant, s'il vous plaît." },
    { "es", "El perro de mi vecino ladra todas las mañanas a las siete en punto." },
    { "it", "Buongiorno, vorrei prenotare una camera per due notti, per favore." },
    { "pt", "O menino comprou um bolo de chocolate na padaria ao lado da escola." },
    { "nl", "De fiets van mijn broer staat al drie dagen voor de deur van het huis." },
    { "pl", "Mój młodszy brat mieszka w małym domu nad szeroką rzeką." },
  };
  return sentences;
}

struct Condition
{
  std::string Variant; ///< eSpeak variant appended as voice+variant
  int Rate;
  int Pitch;
  double NoiseSnr; ///< dB; infinity: clean
  int SampleRate;  ///< the recording's rate
};

std::vector<Condition> Conditions(bool quick)
{
  if (quick)
  {
    return { { "m3", 150, 40, 30.0, 16000 } };
  }
  std::vector<Condition> all;
  for (const char* variant : { "m3", "f2", "klatt" })
  {
    for (int rate : { 130, 175, 220 })
    {
      for (double snr : { double(INFINITY), 20.0 })
      {
        const int pitch = rate == 175 ? 70 : 30;
        const int sampleRate = snr > 100 ? 44100 : 16000;
        all.push_back({ variant, rate, pitch, snr, sampleRate });
      }
    }
  }
  return all;
}

std::string Shuffled(const std::string& text, uint32_t seed)
{
  std::istringstream in(text);
  std::vector<std::string> words;
  std::string w;
  while (in >> w)
  {
    words.push_back(w);
  }
  std::mt19937 random(seed);
  std::string original = text;
  for (int tries = 0; tries < 10; ++tries)
  {
    std::shuffle(words.begin(), words.end(), random);
    std::string out;
    for (const std::string& x : words)
    {
      out += (out.empty() ? "" : " ") + x;
    }
    if (out != original)
    {
      return out;
    }
  }
  return text;
}

AudioBuffer Record(const SynthesisResult& truth, const Condition& c, uint32_t seed)
{
  AudioBuffer audio =
    Resample(FromInt16Mono(truth.Audio, truth.SampleRate), c.SampleRate, ResampleQuality::High);
  if (std::isfinite(c.NoiseSnr))
  {
    // Noise relative to the speech's power (frames louder than -40 dB of the peak).
    double sum = 0.0;
    size_t count = 0;
    float peak = 0.0f;
    for (float s : audio.Samples)
    {
      peak = std::max(peak, std::abs(s));
    }
    for (float s : audio.Samples)
    {
      if (std::abs(s) > peak * 0.01f)
      {
        sum += static_cast<double>(s) * s;
        ++count;
      }
    }
    const double noiseRms =
      std::sqrt(sum / std::max<size_t>(count, 1)) * std::pow(10.0, -c.NoiseSnr / 20.0);
    std::mt19937 random(seed);
    std::normal_distribution<double> gauss(0.0, noiseRms);
    for (float& s : audio.Samples)
    {
      s = static_cast<float>(s + gauss(random));
    }
  }
  return audio;
}

/// Phoneme index covering time t (the last one starting at or before t).
size_t Covering(const std::vector<TimedPhoneme>& p, double t)
{
  size_t k = 0;
  while (k + 1 < p.size() && p[k + 1].Start <= t)
  {
    ++k;
  }
  return k;
}

double FrameAgreement(const std::vector<TimedPhoneme>& truth, const std::vector<TimedPhoneme>& test,
  const VisemeMap& map, double duration)
{
  size_t same = 0, total = 0;
  for (double t = 0.005; t < duration; t += 0.01)
  {
    const int a = map.MapPhoneme(truth[Covering(truth, t)].Sampa);
    const int b = map.MapPhoneme(test[Covering(test, t)].Sampa);
    same += a == b ? 1 : 0;
    ++total;
  }
  return total ? static_cast<double>(same) / total : 0.0;
}

/// Boundary errors (seconds) of phonemes matched by name in order (longest common
/// subsequence), the first phoneme (start 0) excluded.
std::vector<double> BoundaryErrors(
  const std::vector<TimedPhoneme>& truth, const std::vector<TimedPhoneme>& test)
{
  const size_t n = truth.size(), m = test.size();
  std::vector<std::vector<int>> l(n + 1, std::vector<int>(m + 1, 0));
  for (size_t i = n; i-- > 0;)
  {
    for (size_t j = m; j-- > 0;)
    {
      l[i][j] =
        truth[i].Sampa == test[j].Sampa ? l[i + 1][j + 1] + 1 : std::max(l[i + 1][j], l[i][j + 1]);
    }
  }
  std::vector<double> errors;
  for (size_t i = 0, j = 0; i < n && j < m;)
  {
    if (truth[i].Sampa == test[j].Sampa)
    {
      if (i > 0 && j > 0)
      {
        errors.push_back(std::abs(truth[i].Start - test[j].Start));
      }
      ++i;
      ++j;
    }
    else if (l[i + 1][j] >= l[i][j + 1])
    {
      ++i;
    }
    else
    {
      ++j;
    }
  }
  return errors;
}

double Quantile(std::vector<double> v, double q)
{
  if (v.empty())
  {
    return NAN;
  }
  std::sort(v.begin(), v.end());
  const double x = q * static_cast<double>(v.size() - 1);
  const size_t k = static_cast<size_t>(x);
  return k + 1 < v.size() ? v[k] + (x - k) * (v[k + 1] - v[k]) : v[k];
}

/// The synthetic timings stretched linearly onto the recording's speech: the baseline a
/// route must beat (what aligning without warping gives).
std::vector<TimedPhoneme> LinearBaseline(
  const std::string& text, const std::string& voice, const TranscriptAlignment& aligned)
{
  const SynthesisResult s = SpeechSynthesizer(voice).Synthesize(text);
  double first = 0.0, last = s.Duration;
  for (const TimedPhoneme& p : s.Phonemes)
  {
    if (!IsPausePhoneme(p.Sampa))
    {
      first = p.Start;
      break;
    }
  }
  for (size_t k = s.Phonemes.size(); k-- > 0;)
  {
    if (!IsPausePhoneme(s.Phonemes[k].Sampa))
    {
      last = s.Phonemes[k].Start + s.Phonemes[k].Duration;
      break;
    }
  }
  std::vector<TimedPhoneme> out = s.Phonemes;
  const double scale = (aligned.SpeechEnd - aligned.SpeechStart) / std::max(1e-3, last - first);
  for (TimedPhoneme& p : out)
  {
    p.Start = std::clamp(aligned.SpeechStart + (p.Start - first) * scale, 0.0, aligned.Duration);
  }
  out.front().Start = 0.0;
  return out;
}

struct Tally
{
  std::vector<double> Agreement, Errors, Scores;
  double AudioSeconds = 0.0, ComputeSeconds = 0.0;
  size_t Runs = 0, Failures = 0;
};

std::string Percent(double x)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << 100.0 * x << " %";
  return s.str();
}

std::string Ms(double seconds)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(0) << 1000.0 * seconds;
  return s.str();
}

std::string Fixed(double x, int digits)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

double Mean(const std::vector<double>& v)
{
  double s = 0.0;
  for (double x : v)
  {
    s += x;
  }
  return v.empty() ? NAN : s / static_cast<double>(v.size());
}

struct HumanFile
{
  std::string Path;
  std::string Transcript;
  std::string Name;
};

std::vector<HumanFile> HumanFiles()
{
  std::vector<HumanFile> files;
  const std::string dir = "/usr/share/pocketsphinx/test/data/librivox/";
  std::ifstream in(dir + "transcription");
  std::string line;
  while (std::getline(in, line))
  {
    const size_t open = line.rfind('('), close = line.rfind(')');
    if (open == std::string::npos || close == std::string::npos)
    {
      continue;
    }
    const std::string id = line.substr(open + 1, close - open - 1);
    std::string text = line.substr(0, open);
    for (const char* tag : { "<s>", "</s>" })
    {
      const size_t at = text.find(tag);
      if (at != std::string::npos)
      {
        text.erase(at, std::string(tag).size());
      }
    }
    files.push_back({ dir + id + ".wav", std::string(text), id });
  }
  return files;
}
} // namespace

int main(int argc, char** argv)
{
  bool quick = false;
  std::string out = ".";
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--quick")
    {
      quick = true;
    }
    else if (a == "--out" && i + 1 < argc)
    {
      out = argv[++i];
    }
    else
    {
      std::cerr << "usage: StudySpeechAlignment [--quick] [--out DIR]\n";
      return 2;
    }
  }
  if (!IsTranscriptAlignmentAvailable())
  {
    std::cout << "built without eSpeak NG: the transcript route is unavailable, nothing to study\n";
    return 0;
  }
  std::filesystem::create_directories(out);
  std::ofstream errorsCsv(out + "/boundary-errors.csv");
  errorsCsv << "route,language,error_ms\n";

  std::map<std::string, Tally> byLanguage, byCondition;
  Tally transcript, baseline, shuffled, recognition, other;
  const auto sentences = quick ? std::vector<Sentence>{ Sentences()[0] } : Sentences();
  uint32_t seed = 1;
  for (const Sentence& s : sentences)
  {
    const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, SpeechLanguageOf(s.Language));
    for (const Condition& c : Conditions(quick))
    {
      SpeechSynthesizer voice(s.Language + "+" + c.Variant, c.Rate);
      voice.SetPitch(c.Pitch);
      voice.SetEstimatePitch(false);
      const SynthesisResult truth = voice.Synthesize(s.Text);
      const AudioBuffer recording = Record(truth, c, ++seed);
      TranscriptAlignOptions options;
      options.Voice = s.Language;
      const std::string conditionName = std::string("rate ") + std::to_string(c.Rate) +
        (std::isfinite(c.NoiseSnr) ? ", noise 20 dB" : ", clean");
      try
      {
        const auto t0 = std::chrono::steady_clock::now();
        const TranscriptAlignment a = AlignTranscript(recording, s.Text, options);
        const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double agreement = FrameAgreement(truth.Phonemes, a.Phonemes, map, truth.Duration);
        const std::vector<double> errors = BoundaryErrors(truth.Phonemes, a.Phonemes);
        for (Tally* t : { &transcript, &byLanguage[s.Language], &byCondition[conditionName] })
        {
          t->Agreement.push_back(agreement);
          t->Errors.insert(t->Errors.end(), errors.begin(), errors.end());
          t->Scores.push_back(a.Score);
          t->AudioSeconds += recording.GetDuration();
          t->ComputeSeconds += seconds;
          ++t->Runs;
        }
        for (double e : errors)
        {
          errorsCsv << "transcript," << s.Language << "," << 1000.0 * e << "\n";
        }
        const auto linear = LinearBaseline(s.Text, s.Language, a);
        baseline.Agreement.push_back(FrameAgreement(truth.Phonemes, linear, map, truth.Duration));
        const auto baseErrors = BoundaryErrors(truth.Phonemes, linear);
        baseline.Errors.insert(baseline.Errors.end(), baseErrors.begin(), baseErrors.end());
        for (double e : baseErrors)
        {
          errorsCsv << "linear," << s.Language << "," << 1000.0 * e << "\n";
        }
        ++baseline.Runs;
        std::cerr << s.Language << " " << c.Variant << " " << conditionName << ": agreement "
                  << Percent(agreement) << ", median " << Ms(Quantile(errors, 0.5)) << " ms, p95 "
                  << Ms(Quantile(errors, 0.95)) << " ms, score " << Fixed(a.Score, 3) << ", rate "
                  << a.SynthesisRate << ", " << Fixed(recording.GetDuration() / seconds, 0)
                  << "x\n";
      }
      catch (const InputError& e)
      {
        ++transcript.Failures;
        std::cerr << s.Language << " " << c.Variant << " " << conditionName << ": FAILED "
                  << e.what() << "\n";
      }
      // The route without a transcript (English only).
      if (s.Language == "en" && IsPhonemeRecognitionAvailable())
      {
        try
        {
          const auto t0 = std::chrono::steady_clock::now();
          const PhonemeRecognition r = RecognizePhonemes(recording);
          const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          recognition.Agreement.push_back(
            FrameAgreement(truth.Phonemes, r.Phonemes, map, truth.Duration));
          const auto errors = BoundaryErrors(truth.Phonemes, r.Phonemes);
          recognition.Errors.insert(recognition.Errors.end(), errors.begin(), errors.end());
          recognition.Scores.push_back(
            static_cast<double>(errors.size()) / std::max<size_t>(1, truth.Phonemes.size() - 1));
          recognition.AudioSeconds += recording.GetDuration();
          recognition.ComputeSeconds += seconds;
          ++recognition.Runs;
          for (double e : errors)
          {
            errorsCsv << "recognition," << s.Language << "," << 1000.0 * e << "\n";
          }
        }
        catch (const InputError& e)
        {
          ++recognition.Failures;
          std::cerr << "recognition FAILED: " << e.what() << "\n";
        }
      }
      // Second control: another sentence of similar length (spoken with this voice).
      try
      {
        const auto& all = Sentences();
        const size_t index = static_cast<size_t>(&s - &sentences[0]);
        const std::string wrong = all[(index + 1) % all.size()].Text;
        const TranscriptAlignment a = AlignTranscript(recording, wrong, options);
        other.Agreement.push_back(FrameAgreement(truth.Phonemes, a.Phonemes, map, truth.Duration));
        other.Scores.push_back(a.Score);
        ++other.Runs;
      }
      catch (const InputError&)
      {
        ++other.Failures;
      }
      // Negative control: the same recording, the words shuffled.
      try
      {
        const std::string wrong = Shuffled(s.Text, seed);
        const TranscriptAlignment a = AlignTranscript(recording, wrong, options);
        shuffled.Agreement.push_back(
          FrameAgreement(truth.Phonemes, a.Phonemes, map, truth.Duration));
        shuffled.Scores.push_back(a.Score);
        ++shuffled.Runs;
      }
      catch (const InputError&)
      {
        ++shuffled.Failures; // refusing a wrong transcript is a fine outcome too
      }
    }
  }

  std::ofstream md(out + "/speech-study.md");
  md << "| route | runs | frame agreement (mean) | boundary error median | 95th percentile | score "
        "(mean) |\n";
  md << "| --- | ---: | ---: | ---: | ---: | ---: |\n";
  md << "| transcript (eSpeak + DTW) | " << transcript.Runs << " | "
     << Percent(Mean(transcript.Agreement)) << " | " << Ms(Quantile(transcript.Errors, 0.5))
     << " ms | " << Ms(Quantile(transcript.Errors, 0.95)) << " ms | "
     << Fixed(Mean(transcript.Scores), 3) << " |\n";
  md << "| linear stretch (no warping, baseline) | " << baseline.Runs << " | "
     << Percent(Mean(baseline.Agreement)) << " | " << Ms(Quantile(baseline.Errors, 0.5)) << " ms | "
     << Ms(Quantile(baseline.Errors, 0.95)) << " ms | |\n";
  if (recognition.Runs > 0)
  {
    md << "| no transcript: PocketSphinx phonemes (English only) | " << recognition.Runs << " | "
       << Percent(Mean(recognition.Agreement)) << " | " << Ms(Quantile(recognition.Errors, 0.5))
       << " ms | " << Ms(Quantile(recognition.Errors, 0.95)) << " ms | ("
       << Percent(Mean(recognition.Scores)) << " of the phonemes found) |\n";
  }
  md << "| control: another sentence | " << other.Runs << " (+" << other.Failures << " refused) | "
     << Percent(Mean(other.Agreement)) << " | | | " << Fixed(Mean(other.Scores), 3) << " |\n";
  md << "| negative control: shuffled transcript | " << shuffled.Runs << " (+" << shuffled.Failures
     << " refused) | " << Percent(Mean(shuffled.Agreement)) << " | | | "
     << Fixed(Mean(shuffled.Scores), 3) << " |\n\n";

  md << "| language | runs | frame agreement | boundary error median | 95th percentile | speed (x "
        "real time) |\n";
  md << "| --- | ---: | ---: | ---: | ---: | ---: |\n";
  for (const auto& [language, t] : byLanguage)
  {
    md << "| " << language << " | " << t.Runs << " | " << Percent(Mean(t.Agreement)) << " | "
       << Ms(Quantile(t.Errors, 0.5)) << " ms | " << Ms(Quantile(t.Errors, 0.95)) << " ms | "
       << Fixed(t.AudioSeconds / t.ComputeSeconds, 0) << " |\n";
  }
  md << "\n| condition | runs | frame agreement | boundary error median | 95th percentile |\n";
  md << "| --- | ---: | ---: | ---: | ---: |\n";
  for (const auto& [name, t] : byCondition)
  {
    md << "| " << name << " | " << t.Runs << " | " << Percent(Mean(t.Agreement)) << " | "
       << Ms(Quantile(t.Errors, 0.5)) << " ms | " << Ms(Quantile(t.Errors, 0.95)) << " ms |\n";
  }
  md << "\nScores (eSpeak recordings): right transcript 5th percentile "
     << Fixed(Quantile(transcript.Scores, 0.05), 3) << ", minimum "
     << Fixed(Quantile(transcript.Scores, 0.0), 3) << "; shuffled transcript 95th percentile "
     << Fixed(Quantile(shuffled.Scores, 0.95), 3) << ", maximum "
     << Fixed(Quantile(shuffled.Scores, 1.0), 3) << "; another sentence 95th percentile "
     << Fixed(Quantile(other.Scores, 0.95), 3) << ", maximum "
     << Fixed(Quantile(other.Scores, 1.0), 3) << ".\n";
  const double minimum = TranscriptAlignOptions().MinimumScore;
  auto below = [minimum](const std::vector<double>& v)
  {
    return v.empty() ? NAN
                     : static_cast<double>(std::count_if(
                         v.begin(), v.end(), [minimum](double x) { return x < minimum; })) /
        v.size();
  };
  md << "With the default MinimumScore " << Fixed(minimum, 2)
     << ", the warning \"may not match\" is raised for " << Percent(below(transcript.Scores))
     << " of the right transcripts, " << Percent(below(other.Scores))
     << " of the other sentences and " << Percent(below(shuffled.Scores))
     << " of the shuffled ones.\n";
  md << "\nSpeed of the transcript route, one core: "
     << Fixed(transcript.AudioSeconds / transcript.ComputeSeconds, 0) << "x real time ("
     << Fixed(transcript.AudioSeconds, 1) << " s of audio in "
     << Fixed(transcript.ComputeSeconds, 2) << " s). Failures: " << transcript.Failures << ".\n";
  if (recognition.Runs > 0)
  {
    md << "Speed of the recognition route, one core, model loading included: "
       << Fixed(recognition.AudioSeconds / recognition.ComputeSeconds, 1)
       << "x real time. Failures: " << recognition.Failures << ".\n";
  }

  // Real speech: LibriVox readings of pocketsphinx-testdata.
  md << "\n| recording (pocketsphinx-testdata) | duration | score | words | score, shuffled "
        "transcript | speed | recognition vs alignment (frames) | recognition speed |\n| --- | "
        "---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const HumanFile& h : quick ? std::vector<HumanFile>{} : HumanFiles())
  {
    try
    {
      const AudioBuffer audio = ReadAudioFile(h.Path);
      TranscriptAlignOptions options;
      options.Voice = "en-us";
      const auto t0 = std::chrono::steady_clock::now();
      const TranscriptAlignment a = AlignTranscript(audio, h.Transcript, options);
      const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      double wrongScore = NAN;
      try
      {
        wrongScore = AlignTranscript(audio, Shuffled(h.Transcript, 99), options).Score;
      }
      catch (const InputError&)
      {
      }
      std::string versus = "", speed = "";
      if (IsPhonemeRecognitionAvailable())
      {
        const auto t1 = std::chrono::steady_clock::now();
        const PhonemeRecognition r = RecognizePhonemes(audio);
        const double s1 =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        versus = Percent(FrameAgreement(a.Phonemes, r.Phonemes,
          VisemeMap::Builtin(VisemeSet::Oculus15, "en"), audio.GetDuration()));
        speed = Fixed(audio.GetDuration() / s1, 1) + "x";
      }
      md << "| " << h.Name << " | " << Fixed(audio.GetDuration(), 1) << " s | " << Fixed(a.Score, 3)
         << " | " << a.Words.size() << " | " << Fixed(wrongScore, 3) << " | "
         << Fixed(audio.GetDuration() / seconds, 0) << "x | " << versus << " | " << speed << " |\n";
      std::ofstream words(out + "/human-" + h.Name + "-words.csv");
      words << "start,end,word\n";
      for (const auto& w : a.Words)
      {
        words << w.Start << "," << w.Start + w.Duration << "," << w.Text << "\n";
      }
      std::ofstream phonemes(out + "/human-" + h.Name + "-phonemes.csv");
      const VisemeMap map = VisemeMap::Builtin(VisemeSet::Oculus15, "en");
      phonemes << "start,end,phoneme,viseme\n";
      for (const auto& p : a.Phonemes)
      {
        phonemes << p.Start << "," << p.Start + p.Duration << "," << p.Sampa << ","
                 << map.MapPhonemeName(p.Sampa) << "\n";
      }
    }
    catch (const InputError& e)
    {
      md << "| " << h.Name << " | failed: " << e.what() << " | | | |\n";
    }
  }
  md.close();
  std::cout << std::ifstream(out + "/speech-study.md").rdbuf();
  return transcript.Runs > 0 ? 0 : 1;
}
