// SPDX-License-Identifier: BSD-3-Clause
// MorphLipSync: mouth cues for a recording, in Rhubarb Lip Sync's TSV or JSON, so that tools
// reading Rhubarb's output can use MorphNode's timing instead (docs/speech.md):
//
//   MorphLipSync speech.wav --text "Hello there" -o cues.tsv
//   MorphLipSync speech.flac --text-file dialog.txt --voice fr -f json -o cues.json
//   MorphLipSync speech.wav --timings speech.TextGrid        (timings of another aligner)
//   MorphLipSync speech.wav                                  (English, recognized, less precise)
//
// Times refer to the recording as it is (no silence added in front); the mouth leads the
// sound by the coarticulation's lead (50 ms), as Rhubarb's cues anticipate too.
#include "CommandLine.h"
#include "Progress.h"
#include "StopSignal.h"

#include "align/RecordingSpeech.h"
#include "audio/AudioFile.h"
#include "base/Error.h"
#include "base/File.h"
#include "base/Text.h"
#include "speech/Rhubarb.h"
#include "speech/VisemeMap.h"

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

using namespace morphnode;

int main(int argc, char** argv)
{
  CLI::App app{ "Mouth cues (Rhubarb Lip Sync TSV/JSON) for a recording: aligned to its "
                "transcript in any eSpeak NG language, from another tool's timings, or recognized "
                "(English only, less precise)." };
  std::string audioPath, text, textFile, timings, voice = "en", format = "tsv", output,
                                                  route = "auto";
  std::string visemes = "oculus15";
  double minimumCue = 0.07;
  bool quiet = false;
  app.add_option("audio", audioPath, "the recording: WAV, FLAC or OGG, any rate and channels")
    ->required()
    ->check(CLI::ExistingFile);
  auto* textOption = app.add_option("--text", text, "the transcript");
  auto* textFileOption =
    app.add_option("--text-file,-d,--dialogFile", textFile, "a UTF-8 file holding the transcript")
      ->check(CLI::ExistingFile);
  textOption->excludes(textFileOption);
  app
    .add_option("--timings", timings,
      "timings from another tool instead of aligning: .TextGrid (phone tier), .marks (speech "
      "marks), .pho")
    ->check(CLI::ExistingFile)
    ->excludes(textOption)
    ->excludes(textFileOption);
  app
    .add_option("--voice,-v", voice,
      "eSpeak NG voice of the transcript's language (en, de, "
      "fr, es, ...)")
    ->capture_default_str();
  app.add_option("--route", route, "auto, transcript, timing-file or recognition")
    ->capture_default_str();
  app.add_option("-f,--exportFormat", format, "tsv or json")
    ->check(CLI::IsMember({ "tsv", "json" }))
    ->capture_default_str();
  app.add_option("-o,--output", output, "the cue file (default: standard output)");
  app
    .add_option("--visemes", visemes,
      "viseme set the shapes are taken from: oculus15, german16, "
      "paper6")
    ->capture_default_str();
  appkit::AddNumberOption(app, "--min-cue", minimumCue, 0.0, 1.0,
    "seconds a cue lasts at least (shorter ones merge into the previous; closures are kept)");
  app.add_flag("-q,--quiet", quiet, "no progress bar");
  appkit::ParseCommandLine(app, argc, argv);

  try
  {
    if (!textFile.empty())
    {
      text = std::string(text::Trim(text::ReadFile(textFile, "transcript file")));
    }
    SpeechOptions speech;
    speech.Voice = voice;
    speech.Visemes = ParseVisemeSet(visemes);
    speech.Warn = [](const std::string& message)
    { std::cerr << "MorphLipSync: warning: " << message << "\n"; };
    RecordingOptions options;
    options.Route = ParseRecordingRoute(route);
    options.Transcript = text;
    options.TimingFile = timings;
    appkit::ProgressBar bar(100, "%", !quiet);
    options.Progress = [&bar](double f)
    {
      bar.Show(static_cast<int>(100.0 * f));
      return true;
    };
    const AudioBuffer recording = ReadAudioFile(audioPath);
    RecordingReport report;
    const Utterance u = SpeakRecording(recording, speech, options, &report);
    // BuildUtterance may have put silence in front for the mouth's lead: undo it, so the
    // cues match the file as it is.
    const double pad = static_cast<double>(u.Audio.size()) / u.SampleRate - recording.GetDuration();
    std::vector<MouthCue> cues =
      VisemeTrackToMouthCues(u.Visemes, SelectVisemeMap(speech), minimumCue);
    std::vector<MouthCue> shifted;
    for (MouthCue c : cues)
    {
      // Rhubarb writes centiseconds; so do we (a cue never starts before the previous).
      c.Start = std::round(100.0 * std::max(0.0, c.Start - std::max(pad, 0.0))) / 100.0;
      c.End =
        std::round(100.0 * std::min(recording.GetDuration(), c.End - std::max(pad, 0.0))) / 100.0;
      if (!shifted.empty())
      {
        c.Start = std::max(c.Start, shifted.back().End);
      }
      if (c.End > c.Start)
      {
        shifted.push_back(c);
      }
    }
    if (!quiet)
    {
      std::cerr << "MorphLipSync: route " << RecordingRouteName(report.Route) << ", "
                << shifted.size() << " cues over " << recording.GetDuration() << " s"
                << (report.Route == RecordingRoute::Transcript ? ", alignment score " +
                         text::FormatNumber(std::round(report.Score * 1000) / 1000)
                                                               : std::string())
                << "\n";
    }
    std::ostringstream file; // written safely below (base/File.h)
    std::ostream* out = output.empty() ? static_cast<std::ostream*>(&std::cout) : &file;
    if (format == "json")
    {
      WriteRhubarbJson(*out, shifted, audioPath, recording.GetDuration());
    }
    else
    {
      WriteRhubarbTsv(*out, shifted);
    }
    out->flush();
    if (!*out)
    {
      throw InputError("error while writing the cues");
    }
    if (!output.empty())
    {
      const appkit::DeferStopSignals whole; // a SIGTERM now: the whole file or none
      file::WriteFileSafely(output, file.str(), "output");
    }
  }
  catch (const InputError& e)
  {
    std::cerr << "MorphLipSync: " << e.what() << "\n";
    return 1;
  }
  catch (const std::bad_alloc&)
  {
    std::cerr << "MorphLipSync: out of memory (the input is too long for this machine; see "
                 "docs/limits.md)\n";
    return 1;
  }
  catch (const std::exception& e)
  {
    std::cerr << "MorphLipSync: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
