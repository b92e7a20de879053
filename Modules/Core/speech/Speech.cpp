// SPDX-License-Identifier: BSD-3-Clause
#include "speech/Speech.h"

#include "base/Error.h"
#include "base/Text.h"
#include "speech/Pho.h"
#include "speech/Sampa.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace morphnode
{
VisemeMap SelectVisemeMap(const SpeechOptions& options)
{
  if (!options.VisemeTablePath.empty())
  {
    return VisemeMap::Load(options.VisemeTablePath);
  }
  const std::string& language = options.Language.empty() ? options.Voice : options.Language;
  return VisemeMap::Builtin(options.Visemes, language); // the voice, named in warnings
}

Utterance BuildUtterance(std::vector<TimedPhoneme> phonemes, std::vector<int16_t> audio,
  int sampleRate, const VisemeMap& map, const SpeechOptions& options)
{
  if (sampleRate <= 0)
  {
    throw InputError("an utterance needs a sample rate > 0");
  }
  // The mouth leads the sound; if speech starts sooner than the lead, delay the sound.
  const double lead = options.Coarticulation.Lead;
  auto firstSpoken = std::find_if(phonemes.begin(), phonemes.end(),
    [](const TimedPhoneme& p) { return !IsPausePhoneme(p.Sampa); });
  if (firstSpoken != phonemes.end() && std::isfinite(firstSpoken->Start) &&
    lead > firstSpoken->Start)
  {
    const double padSamples = std::ceil((lead - firstSpoken->Start) * sampleRate);
    const double pad = padSamples / sampleRate;
    for (TimedPhoneme& p : phonemes)
    {
      p.Start += pad;
    }
    if (phonemes.front().Sampa == "_")
    {
      phonemes.front().Start -= pad;
      phonemes.front().Duration += pad;
    }
    else
    {
      TimedPhoneme pause;
      pause.Sampa = "_";
      pause.Duration = pad;
      phonemes.insert(phonemes.begin(), pause);
    }
    if (!audio.empty())
    {
      audio.insert(audio.begin(), static_cast<size_t>(padSamples), int16_t(0));
    }
  }

  Utterance u;
  u.SampleRate = sampleRate;
  u.Duration = static_cast<double>(audio.size()) / sampleRate;
  for (const TimedPhoneme& p : phonemes)
  {
    u.Duration = std::max(u.Duration, p.Start + p.Duration);
  }
  u.Visemes = CoarticulatePhonemes(phonemes, map, u.Duration, options.Coarticulation, options.Warn);
  u.Cues = DeriveNonverbalCues(phonemes, options.Nonverbal);
  u.Phonemes = std::move(phonemes);
  u.Audio = std::move(audio);
  return u;
}

Utterance SpeakText(const std::string& text, const SpeechOptions& options)
{
  SpeechSynthesizer synthesizer(options.Voice, options.Rate);
  synthesizer.SetDataPath(options.DataPath);
  synthesizer.SetEstimatePitch(options.EstimatePitch);
  SynthesisResult result = synthesizer.Synthesize(text);
  const std::vector<std::string> switches =
    EspeakLanguageSwitches(result.EspeakPhonemes, options.Voice);
  if (!switches.empty() && options.Warn)
  {
    // Once per text: where the voice has no rules, eSpeak NG reads in another language.
    std::string languages;
    for (const std::string& l : switches)
    {
      languages += (languages.empty() ? "" : ", ") + text::Quote(l);
    }
    options.Warn("eSpeak NG has no rules for part of this text in voice " +
      text::Quote(options.Voice) + " and reads it as " + languages +
      " (e.g. tone numbers or characters the voice does not know): "
      "sound and mouth follow that reading");
  }
  return BuildUtterance(std::move(result.Phonemes), std::move(result.Audio), result.SampleRate,
    SelectVisemeMap(options), options);
}

Utterance UtteranceFromPhonemes(std::vector<TimedPhoneme> phonemes, const SpeechOptions& options)
{
  if (phonemes.empty())
  {
    throw InputError("no phonemes to speak");
  }
  return BuildUtterance(std::move(phonemes), {}, 22050, SelectVisemeMap(options), options);
}

Utterance LoadPhoUtterance(const std::string& path, const SpeechOptions& options)
{
  return UtteranceFromPhonemes(ReadPhoFile(path), options);
}

Utterance UtteranceFromMouthCues(const std::vector<MouthCue>& cues, const SpeechOptions& options)
{
  if (cues.empty())
  {
    throw InputError("no mouth cues to speak");
  }
  const VisemeMap map = SelectVisemeMap(options);
  Utterance u;
  u.Duration = cues.empty() ? 0.0 : cues.back().End;
  u.Visemes =
    Coarticulate(MouthCuesToVisemeSegments(cues, map), map, u.Duration, options.Coarticulation);
  return u;
}
} // namespace morphnode
