// SPDX-License-Identifier: BSD-3-Clause
#include "align/RecordingSpeech.h"

#include "align/PhonemeRecognizer.h"
#include "audio/AudioFile.h"
#include "audio/Resample.h"
#include "base/Error.h"
#include "base/Text.h"
#include "speech/Sampa.h"

#include <algorithm>

namespace morphnode
{
namespace
{
std::string LanguageOf(const SpeechOptions& speech)
{
  return speech.Language.empty() ? speech.Voice : speech.Language;
}

/// The recording as the utterance's sound: mono 16 bit at its own rate (at most 48 kHz).
std::vector<int16_t> SoundOf(const AudioBuffer& recording, int& rate)
{
  AudioBuffer mono = MixToMono(recording);
  if (mono.SampleRate > 48000)
  {
    mono = Resample(mono, 48000, ResampleQuality::High);
  }
  rate = mono.SampleRate;
  return ToInt16Mono(mono);
}

std::function<bool(double)> Scaled(
  const std::function<bool(double)>& progress, double from, double to)
{
  if (!progress)
  {
    return nullptr;
  }
  return [progress, from, to](double f) { return progress(from + (to - from) * f); };
}
} // namespace

const char* RecordingRouteName(RecordingRoute route)
{
  switch (route)
  {
    case RecordingRoute::Transcript:
      return "transcript";
    case RecordingRoute::TimingFile:
      return "timing-file";
    case RecordingRoute::Recognition:
      return "recognition";
    case RecordingRoute::Auto:
      break;
  }
  return "auto";
}

RecordingRoute ParseRecordingRoute(const std::string& name)
{
  const std::string n = text::ToLower(name);
  for (RecordingRoute r : { RecordingRoute::Auto, RecordingRoute::Transcript,
         RecordingRoute::TimingFile, RecordingRoute::Recognition })
  {
    if (n == RecordingRouteName(r))
    {
      return r;
    }
  }
  throw InputError(
    "unknown route " + text::Quote(name) + " (auto, transcript, timing-file, recognition)");
}

Utterance SpeakRecording(const AudioBuffer& recording, const SpeechOptions& speech,
  const RecordingOptions& options, RecordingReport* report)
{
  if (recording.IsEmpty() || recording.SampleRate <= 0)
  {
    throw InputError("the recording is empty");
  }
  RecordingRoute route = options.Route;
  if (route == RecordingRoute::Auto)
  {
    route = !options.TimingFile.empty() || !options.TimingData.empty() ? RecordingRoute::TimingFile
      : !text::Trim(options.Transcript).empty()                        ? RecordingRoute::Transcript
                                                : RecordingRoute::Recognition;
  }
  RecordingReport done;
  done.Route = route;
  std::vector<TimedPhoneme> phonemes;
  const std::string language = LanguageOf(speech);
  switch (route)
  {
    case RecordingRoute::TimingFile:
    {
      const bool inMemory = !options.TimingData.empty();
      if (options.TimingFile.empty() && !inMemory)
      {
        throw InputError("the timing-file route needs a timing file");
      }
      done.Score = 1.0;
      const std::string name = options.TimingFile.empty() ? "inline timings" : options.TimingFile;
      const std::string bytes =
        inMemory ? options.TimingData : text::ReadFile(options.TimingFile, "timing file");
      const TimingFormat format = options.Timing.Format == TimingFormat::Auto
        ? GuessTimingFormat(name, bytes)
        : options.Timing.Format;
      if (IsRhubarbFormat(format))
      {
        // Rhubarb's mouth cues (what it computes from a recording: its main use) become the
        // visemes as they are; the recording is their sound, from time 0 as the cues.
        TimingFileOptions timing = options.Timing;
        timing.Format = format;
        Utterance u = LoadTimingData(bytes, name, speech, timing);
        int rate = 0;
        u.Audio = SoundOf(recording, rate);
        u.SampleRate = rate;
        const double seconds = static_cast<double>(u.Audio.size()) / rate;
        if (u.Duration > seconds + 0.5 && speech.Warn)
        {
          speech.Warn("the mouth cues of '" + name + "' run " +
            text::FormatNumber(std::round((u.Duration - seconds) * 100) / 100) +
            " s past the end of the recording");
        }
        u.Duration = std::max(u.Duration, seconds);
        if (options.Progress)
        {
          options.Progress(1.0);
        }
        if (report)
        {
          *report = std::move(done);
        }
        return u;
      }
      TimingFileOptions timing = options.Timing;
      timing.Format = format;
      phonemes = LoadTimedPhonemesData(bytes, name, language, timing);
      const double end = phonemes.empty() ? 0.0 : phonemes.back().Start + phonemes.back().Duration;
      if (end > recording.GetDuration() + 0.5 && speech.Warn)
      {
        speech.Warn("the timings of '" + name + "' run " +
          text::FormatNumber(std::round((end - recording.GetDuration()) * 100) / 100) +
          " s past the end of the recording");
      }
      break;
    }
    case RecordingRoute::Transcript:
    {
      TranscriptAlignOptions align = options.Align;
      if (align.Voice == TranscriptAlignOptions().Voice)
      {
        align.Voice = speech.Voice;
      }
      if (align.DataPath.empty())
      {
        align.DataPath = speech.DataPath;
      }
      if (!align.Warn)
      {
        align.Warn = speech.Warn;
      }
      if (!align.Progress)
      {
        align.Progress = Scaled(options.Progress, 0.0, 0.9);
      }
      TranscriptAlignment a = AlignTranscript(recording, options.Transcript, align);
      phonemes = std::move(a.Phonemes);
      done.Score = a.Score;
      done.Reliable = a.Reliable;
      done.Words = std::move(a.Words);
      break;
    }
    case RecordingRoute::Recognition:
    {
      if (SpeechLanguageOf(language) != "en" || text::ToLower(language).rfind("en", 0) != 0)
      {
        throw InputError("without a transcript only English can be recognized (the voice is " +
          text::Quote(language) + "): give the transcript");
      }
      if (speech.Warn)
      {
        // Say which route timed it: the least precise one, without words to go by.
        speech.Warn("no transcript and no timing file: the recording is timed by English phoneme "
                    "recognition, the least precise route (give the transcript or a timing file "
                    "for better timing)");
      }
      RecognitionOptions recognize;
      recognize.Warn = speech.Warn;
      recognize.Progress = Scaled(options.Progress, 0.0, 0.9);
      PhonemeRecognition r = RecognizePhonemes(recording, recognize);
      phonemes = std::move(r.Phonemes);
      done.Score = 0.0; // PocketSphinx gives no calibrated confidence for phone paths
      done.Reliable = true;
      break;
    }
    case RecordingRoute::Auto:
      break;
  }
  int rate = 0;
  std::vector<int16_t> sound = SoundOf(recording, rate);
  Utterance u =
    BuildUtterance(std::move(phonemes), std::move(sound), rate, SelectVisemeMap(speech), speech);
  // BuildUtterance may delay everything for the mouth's lead: words follow.
  if (!u.Phonemes.empty() && !done.Words.empty())
  {
    const double shift = static_cast<double>(u.Audio.size()) / rate - recording.GetDuration();
    if (shift > 1e-9)
    {
      for (SynthesizedWord& w : done.Words)
      {
        w.Start += shift;
      }
    }
  }
  if (options.Progress)
  {
    options.Progress(1.0);
  }
  if (report)
  {
    *report = std::move(done);
  }
  return u;
}

Utterance SpeakAudioFile(const std::string& path, const SpeechOptions& speech,
  const RecordingOptions& options, RecordingReport* report)
{
  return SpeakRecording(ReadAudioFile(path), speech, options, report);
}
} // namespace morphnode
