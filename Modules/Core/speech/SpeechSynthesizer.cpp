// SPDX-License-Identifier: BSD-3-Clause
#include "speech/SpeechSynthesizer.h"

#include "base/Error.h"
#include "speech/Sampa.h"

#if MORPHNODE_HAVE_ESPEAK_NG
#include <espeak-ng/speak_lib.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <tuple>

namespace morphnode
{
namespace
{
#if MORPHNODE_HAVE_ESPEAK_NG
/// eSpeak NG is one global engine: this lock guards it and the state below.
std::mutex EngineMutex;
bool EngineReady = false;
struct Collector;
Collector* ActiveCollector = nullptr; // set only while EngineMutex is held
std::string EngineDataPath;
int EngineSampleRate = 22050;

struct Collector
{
  std::vector<int16_t> Samples;
  std::vector<std::pair<std::string, int>> Events; // eSpeak name, audio position in ms
  // Word events: character position (1-based), length in characters, audio position in ms.
  std::vector<std::tuple<int, int, int>> Words;
};

// Not through the events' user_data: the last audio chunk may come with no event at all.
int SynthCallback(short* wav, int count, espeak_EVENT* events)
{
  Collector* collector = ActiveCollector;
  for (espeak_EVENT* e = events; collector && e && e->type != espeakEVENT_LIST_TERMINATED; ++e)
  {
    if (e->type == espeakEVENT_PHONEME)
    {
      // id.string holds up to 8 bytes, zero-terminated only when shorter.
      const size_t length = strnlen(e->id.string, sizeof(e->id.string));
      collector->Events.emplace_back(std::string(e->id.string, length), e->audio_position);
    }
    else if (e->type == espeakEVENT_WORD)
    {
      collector->Words.emplace_back(e->text_position, e->length, e->audio_position);
    }
  }
  if (collector && wav && count > 0)
  {
    collector->Samples.insert(collector->Samples.end(), wav, wav + count);
  }
  return 0; // continue
}

/// eSpeak accepts a folder holding phondata or one holding espeak-ng-data/phondata.
bool HasPhonemeData(const std::string& folder)
{
  std::error_code ignored;
  return std::filesystem::is_regular_file(std::filesystem::path(folder) / "phondata", ignored) ||
    std::filesystem::is_regular_file(
      std::filesystem::path(folder) / "espeak-ng-data" / "phondata", ignored);
}

[[noreturn]] void FailInitialization(const std::string& why)
{
  throw InputError("eSpeak NG failed to initialize: " + why +
    " (install espeak-ng-data or point the data path at the folder holding it)");
}

/// The folder holding phondata (`folder` or folder/espeak-ng-data), canonical; empty if none.
std::string PhonemeDataFolder(const std::string& folder)
{
  std::error_code ignored;
  for (const auto& candidate :
    { std::filesystem::path(folder), std::filesystem::path(folder) / "espeak-ng-data" })
  {
    if (std::filesystem::is_regular_file(candidate / "phondata", ignored))
    {
      const auto canonical = std::filesystem::weakly_canonical(candidate, ignored);
      return (ignored ? candidate : canonical).string();
    }
  }
  return std::string();
}

/// Initializes eSpeak once per process. Call with EngineMutex held.
/// eSpeak NG keeps one engine per process, and Debian's 1.51 cannot be re-initialized:
/// after espeak_Terminate and espeak_Initialize, the next espeak_Terminate (and
/// espeak_Synchronize) waits forever for its command-queue thread. So the first data path
/// stays; asking for another one is an InputError (the same folder spelled differently, or
/// an empty path meaning "whatever is loaded", is fine).
void EnsureEngine(const std::string& dataPath)
{
  // eSpeak silently falls back to its default data when a given path is wrong: check first.
  if (!dataPath.empty() && !HasPhonemeData(dataPath))
  {
    FailInitialization("no phoneme data (phondata) in '" + dataPath + "'");
  }
  if (EngineReady)
  {
    if (dataPath.empty() || dataPath == EngineDataPath ||
      PhonemeDataFolder(dataPath) == PhonemeDataFolder(EngineDataPath))
    {
      return;
    }
    throw InputError("eSpeak NG is already running on the data in '" + EngineDataPath +
      "'; it cannot switch to '" + dataPath + "' in the same process (use one data path)");
  }
  // DONT_EXIT: without it eSpeak calls exit() when its data is missing.
  const int rate =
    espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, dataPath.empty() ? nullptr : dataPath.c_str(),
      espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_DONT_EXIT);
  const char* usedPath = nullptr;
  espeak_Info(&usedPath);
  if (rate <= 0 || !usedPath || !HasPhonemeData(usedPath))
  {
    FailInitialization(
      "no usable phoneme data in '" + std::string(usedPath ? usedPath : "?") + "'");
  }
  espeak_SetSynthCallback(SynthCallback);
  EngineSampleRate = rate;
  EngineDataPath = usedPath;
  EngineReady = true;
}

#endif

/// eSpeak's word events as words: character positions -> UTF-8 byte ranges of the text; a
/// word ends at the next word's start or at the next pause, whichever comes first.
std::vector<SynthesizedWord> WordsOf(const std::string& text,
  const std::vector<std::tuple<int, int, int>>& events, const std::vector<TimedPhoneme>& phonemes,
  double duration)
{
  std::vector<size_t> characterStart; // byte offset of each character
  for (size_t i = 0; i < text.size(); ++i)
  {
    if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80)
    {
      characterStart.push_back(i);
    }
  }
  characterStart.push_back(text.size());
  std::vector<SynthesizedWord> words;
  for (size_t k = 0; k < events.size(); ++k)
  {
    const auto [position, length, ms] = events[k];
    SynthesizedWord w;
    const size_t first = position > 0 ? static_cast<size_t>(position - 1) : 0;
    const size_t last = first + static_cast<size_t>(std::max(length, 0));
    if (first < characterStart.size() && last < characterStart.size() && last > first)
    {
      w.Text = text.substr(characterStart[first], characterStart[last] - characterStart[first]);
    }
    w.Start = ms / 1000.0;
    double end = k + 1 < events.size() ? std::get<2>(events[k + 1]) / 1000.0 : duration;
    // eSpeak may announce a word before the pause that precedes it: start at its sound.
    for (const TimedPhoneme& p : phonemes)
    {
      if (IsPausePhoneme(p.Sampa) && p.Start <= w.Start + 1e-9 && p.Start + p.Duration > w.Start &&
        p.Start + p.Duration < end)
      {
        w.Start = p.Start + p.Duration;
        break;
      }
    }
    for (const TimedPhoneme& p : phonemes)
    {
      if (IsPausePhoneme(p.Sampa) && p.Start > w.Start + 1e-9 && p.Start < end)
      {
        end = p.Start;
        break;
      }
    }
    w.Duration = std::max(0.0, end - w.Start);
    words.push_back(std::move(w));
  }
  return words;
}

// The pitch range searched (speech F0 lies well inside).
constexpr double MinimumPitchHz = 60.0;
constexpr double MaximumPitchHz = 500.0;
} // namespace

SpeechSynthesizer::SpeechSynthesizer(const std::string& voice, int rate)
  : Voice(voice)
{
  this->SetRate(rate);
}

void SpeechSynthesizer::SetRate(int wordsPerMinute)
{
  this->Rate = std::clamp(wordsPerMinute, MinimumRate, MaximumRate);
}

void SpeechSynthesizer::SetPitch(int pitch)
{
  this->Pitch = std::clamp(pitch, 0, 100);
}

bool SpeechSynthesizer::IsAvailable()
{
  return MORPHNODE_HAVE_ESPEAK_NG != 0;
}

std::vector<std::string> SpeechSynthesizer::ListVoices(const std::string& dataPath)
{
  std::vector<std::string> voices;
#if MORPHNODE_HAVE_ESPEAK_NG
  std::lock_guard<std::mutex> lock(EngineMutex);
  EnsureEngine(dataPath);
  for (const espeak_VOICE** v = espeak_ListVoices(nullptr); v && *v; ++v)
  {
    // `languages` is a list of (priority byte, zero-terminated name), ended by a zero byte;
    // the first name is the language `espeak-ng --voices` shows.
    const char* languages = (*v)->languages;
    if (languages && languages[0] && languages[1])
    {
      voices.emplace_back(languages + 1);
    }
  }
#else
  (void)dataPath;
#endif
  return voices;
}

SynthesisResult SpeechSynthesizer::Synthesize(const std::string& text) const
{
  SynthesisResult result;
#if MORPHNODE_HAVE_ESPEAK_NG
  Collector collector;
  {
    std::lock_guard<std::mutex> lock(EngineMutex);
    EnsureEngine(this->DataPath);
    // By name ("fr", "en+f2", "Afrikaans"), else by language ("en-gb", "fr-fr"), as the
    // espeak-ng program does.
    bool voiceSet = !this->Voice.empty() && espeak_SetVoiceByName(this->Voice.c_str()) == EE_OK;
    if (!voiceSet && !this->Voice.empty())
    {
      // A language `espeak-ng --voices` lists, with an optional +variant: the voice's name.
      const size_t plus = this->Voice.find('+');
      const std::string language = this->Voice.substr(0, plus);
      for (const espeak_VOICE** v = espeak_ListVoices(nullptr); v && *v && !voiceSet; ++v)
      {
        const char* languages = (*v)->languages;
        if (languages && languages[0] && language == languages + 1 && (*v)->name)
        {
          const std::string name = std::string((*v)->name) +
            (plus == std::string::npos ? std::string() : this->Voice.substr(plus));
          voiceSet = espeak_SetVoiceByName(name.c_str()) == EE_OK;
        }
      }
    }
    if (!voiceSet)
    {
      throw InputError("eSpeak NG has no voice '" + this->Voice + "'");
    }
    espeak_SetParameter(espeakRATE, this->Rate, 0);
    espeak_SetParameter(espeakPITCH, this->Pitch, 0);
    ActiveCollector = &collector;
    const espeak_ERROR status = espeak_Synth(
      text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, nullptr);
    // AUDIO_OUTPUT_SYNCHRONOUS: espeak_Synth returns when the text is done; there is
    // nothing to wait for with espeak_Synchronize.
    ActiveCollector = nullptr;
    if (status != EE_OK)
    {
      throw InputError("eSpeak NG failed to synthesize the text");
    }
    result.SampleRate = EngineSampleRate;
  }
  result.Audio = std::move(collector.Samples);
  auto& events = collector.Events;
  const auto& words = collector.Words;
#else
  (void)text;
  std::vector<std::pair<std::string, int>> events;
  std::vector<std::tuple<int, int, int>> words;
  throw InputError("this MorphNode was built without eSpeak NG (MORPHNODE_ENABLE_ESPEAK=OFF): "
                   "speech synthesis is not available; use .pho, Rhubarb or timed phonemes");
#endif
  result.Duration = static_cast<double>(result.Audio.size()) / result.SampleRate;

  std::stable_sort(
    events.begin(), events.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  for (size_t i = 0; i < events.size(); ++i)
  {
    TimedPhoneme p;
    p.Sampa = events[i].first;
    p.Start = events[i].second / 1000.0;
    const double end = i + 1 < events.size() ? events[i + 1].second / 1000.0 : result.Duration;
    p.Duration = std::max(0.0, end - p.Start);
    result.EspeakPhonemes.push_back(std::move(p));
  }

  // German and English through their SAMPA tables; every other language's mnemonics
  // become X-SAMPA, which the viseme tables read by articulation.
  result.Phonemes = NormalizeVoicePhonemes(result.EspeakPhonemes, this->Voice);
  // eSpeak starts a few ms into the audio: a pause covers that, so starts match the audio.
  if (!result.Phonemes.empty() && result.Phonemes.front().Start > 0.0)
  {
    TimedPhoneme& first = result.Phonemes.front();
    if (IsPausePhoneme(first.Sampa))
    {
      first.Duration += first.Start;
      first.Start = 0.0;
    }
    else
    {
      TimedPhoneme pause;
      pause.Sampa = "_";
      pause.Duration = first.Start;
      result.Phonemes.insert(result.Phonemes.begin(), pause);
    }
  }
  if (this->EstimatePitch)
  {
    AttachPitch(result.Phonemes, result.Audio, result.SampleRate);
  }
  result.Words = WordsOf(text, words, result.Phonemes, result.Duration);
  return result;
}

double EstimatePitchHz(
  const int16_t* samples, size_t begin, size_t end, int sampleRate, double voicingThreshold)
{
  if (!samples || sampleRate <= 0 || end <= begin)
  {
    return 0.0;
  }
  const size_t minLag = static_cast<size_t>(std::floor(sampleRate / MaximumPitchHz));
  const size_t maxLag = static_cast<size_t>(std::ceil(sampleRate / MinimumPitchHz));
  const size_t length = end - begin;
  if (length < maxLag + maxLag / 2 || minLag < 2)
  {
    return 0.0;
  }
  const int16_t* x = samples + begin;
  double energy = 0.0;
  for (size_t i = 0; i < length; ++i)
  {
    energy += static_cast<double>(x[i]) * x[i];
  }
  if (energy / length < 100.0 * 100.0)
  {
    return 0.0; // near silence: rms below ~0.3 % of full scale
  }
  std::vector<double> correlation(maxLag + 2, 0.0);
  double best = 0.0;
  for (size_t lag = minLag; lag <= maxLag + 1; ++lag)
  {
    double sum = 0.0, e0 = 0.0, e1 = 0.0;
    for (size_t i = 0; i + lag < length; ++i)
    {
      sum += static_cast<double>(x[i]) * x[i + lag];
      e0 += static_cast<double>(x[i]) * x[i];
      e1 += static_cast<double>(x[i + lag]) * x[i + lag];
    }
    correlation[lag] = (e0 > 0.0 && e1 > 0.0) ? sum / std::sqrt(e0 * e1) : 0.0;
    if (lag <= maxLag)
    {
      best = std::max(best, correlation[lag]);
    }
  }
  if (best < voicingThreshold)
  {
    return 0.0;
  }
  // The first local peak close to the best one: avoids picking twice the period.
  for (size_t lag = minLag + 1; lag <= maxLag; ++lag)
  {
    const double c = correlation[lag];
    if (c >= 0.9 * best && c >= correlation[lag - 1] && c >= correlation[lag + 1])
    {
      const double left = correlation[lag - 1], right = correlation[lag + 1];
      const double curvature = left - 2.0 * c + right;
      const double shift = curvature < 0.0 ? 0.5 * (left - right) / curvature : 0.0;
      return sampleRate / (static_cast<double>(lag) + std::clamp(shift, -0.5, 0.5));
    }
  }
  return 0.0;
}

void AttachPitch(
  std::vector<TimedPhoneme>& phonemes, const std::vector<int16_t>& audio, int sampleRate)
{
  if (audio.empty() || sampleRate <= 0)
  {
    return;
  }
  // Two and a half periods of the lowest pitch, centred on the phoneme: long enough to find
  // the period, short enough that intonation does not glide much inside it.
  const double window = 2.5 / MinimumPitchHz;
  for (TimedPhoneme& p : phonemes)
  {
    if (IsPausePhoneme(p.Sampa))
    {
      continue;
    }
    const double centre = p.Start + 0.5 * p.Duration;
    const double half = 0.5 * window;
    const double begin = std::max(0.0, (centre - half) * sampleRate);
    const double end = std::min(static_cast<double>(audio.size()), (centre + half) * sampleRate);
    if (!(end > begin))
    {
      continue;
    }
    const double f0 = EstimatePitchHz(
      audio.data(), static_cast<size_t>(begin), static_cast<size_t>(end), sampleRate);
    p.Pitch.clear();
    if (f0 > 0.0)
    {
      p.Pitch.emplace_back(0.5, f0);
    }
  }
}
} // namespace morphnode
