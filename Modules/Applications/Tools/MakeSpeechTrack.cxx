// SPDX-License-Identifier: BSD-3-Clause
// MakeSpeechTrack: a long, speech-driven weight track for the optimizer study.
//
//   MakeSpeechTrack --face face.glb --out track.csv
//                   [--text Data/scripts/long-text.txt] [--rig Data/rigs/arkit.json]
//                   [--seed 2004] [--fps 30] [--voice en] [--rate 175]
//                   [--livelink-csv take.csv]
//
// Speaks the text with eSpeak NG (Oculus visemes), lets the behaviour controller add what
// a speaker does besides talking (SpeechTrack.h; all seeded, so the same seed gives the
// same track), expands the semantic channels through the rig onto the face's own targets
// and writes their relative (glTF) weights as the CSV OptimizerStudy reads:
// `time,<target>,...`, one column per face target, in the face's order. Head and eye
// angles have no morph target and are left out.
//
// The target names come from the GLB's meshes[0].extras.targetNames (no VTK needed).
//
// --livelink-csv also writes the performance as a Live Link Face CSV take (docs/capture.md):
// the face's ARKit-named targets as the 52 ARKit blendshapes, the behaviour's head and gaze
// angles (degrees) as radians, 60 fps timecodes from 00:00:00:00; what maps to nothing
// (targets that are no ARKit shape, shapes the face lacks) is listed.
#include "CommandLine.h"
#include "DataPaths.h"
#include "SpeechTrack.h"
#include "StopSignal.h"

#include "base/Error.h"
#include "base/File.h"
#include "base/Text.h"
#include "capture/ArkitNames.h"
#include "capture/LiveLinkCsv.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
/// meshes[0].extras.targetNames of a .glb (or .gltf) file.
std::vector<std::string> ReadTargetNames(const std::string& path)
{
  const std::string bytes = morphnode::text::ReadFile(path, "face");
  std::string json = bytes;
  if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0)
  {
    auto u32 = [&](size_t at)
    {
      return static_cast<uint32_t>(static_cast<unsigned char>(bytes[at])) |
        static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 8 |
        static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 16 |
        static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + 3])) << 24;
    };
    const uint32_t length = u32(12);
    if (u32(16) != 0x4E4F534Au || 20 + static_cast<size_t>(length) > bytes.size())
    {
      throw morphnode::InputError(path + ": the first GLB chunk is not a JSON chunk");
    }
    json = bytes.substr(20, length);
  }
  const auto doc = nlohmann::json::parse(json, nullptr, false);
  if (doc.is_discarded() || !doc.contains("meshes") || doc["meshes"].empty())
  {
    throw morphnode::InputError(path + ": no glTF meshes");
  }
  const auto& mesh = doc["meshes"][0];
  if (!mesh.contains("extras") || !mesh["extras"].contains("targetNames"))
  {
    throw morphnode::InputError(path + ": meshes[0] has no extras.targetNames");
  }
  return mesh["extras"]["targetNames"].get<std::vector<std::string>>();
}
} // namespace

int main(int argc, char* argv[])
{
  namespace appkit = morphnode::appkit;
  std::string face, out, livelinkFile, textFile = appkit::DataPath("scripts/long-text.txt"),
                                       rigFile = appkit::DataPath("rigs/arkit.json");
  morphnode::study::SpeechTrackOptions options;
  CLI::App app("MakeSpeechTrack: a long speech-driven weight track of a face's targets, for "
               "OptimizerStudy (docs/optimizer-study.md).",
    "MakeSpeechTrack");
  app.add_option("--face", face, "a glTF/GLB face with extras.targetNames")
    ->required()
    ->check(CLI::ExistingFile);
  app.add_option("--out", out, "the CSV to write")->required();
  app.add_option("--livelink-csv", livelinkFile,
    "also write the performance as a Live Link Face CSV take (ARKit blendshapes, head and eye "
    "angles)");
  // Defaults shown as the project's paths, not this machine's.
  app.add_option("--text", textFile, "what is said")
    ->check(CLI::ExistingFile)
    ->default_str("Data/scripts/long-text.txt");
  app.add_option("--rig", rigFile, "the rig onto the face's targets")
    ->check(CLI::ExistingFile)
    ->default_str("Data/rigs/arkit.json");
  app.add_option("--seed", options.Seed, "seed of the behaviour")
    ->check(appkit::UnsignedInteger())
    ->capture_default_str();
  appkit::AddNumberOption(app, "--fps", options.FrameRate, 1.0, 240.0, "frame rate, in [1, 240]");
  app.add_option("--voice", options.Voice, "eSpeak NG voice")->capture_default_str();
  app.add_option("--rate", options.Rate, "words per minute")
    ->check(CLI::Range(
      morphnode::SpeechSynthesizer::MinimumRate, morphnode::SpeechSynthesizer::MaximumRate))
    ->capture_default_str();
  appkit::ParseCommandLine(app, argc, argv);
  try
  {
    const std::vector<std::string> targets = ReadTargetNames(face);
    morphnode::Rig rig = morphnode::Rig::LoadFile(rigFile);
    rig.Bind(targets);
    options.Text = morphnode::text::ReadFile(textFile, "text");
    const morphnode::WeightTrack semantic = morphnode::study::MakeBehaviorTrack(options);
    std::vector<std::string> dropped;
    const morphnode::WeightTrack track =
      morphnode::study::ExpandThroughRig(semantic, rig, targets, &dropped);
    morphnode::file::CheckOutputPath(out, "--out");
    {
      std::ostringstream csv;
      track.WriteCsv(csv);
      const appkit::DeferStopSignals whole; // a SIGTERM now: the whole file or none
      morphnode::file::WriteFileSafely(out, csv.str(), "--out"); // every write checked
    }
    std::cout << "wrote " << out << ": " << track.GetNumberOfFrames() << " frames at "
              << track.GetFrameRate() << " fps ("
              << track.GetNumberOfFrames() / track.GetFrameRate() << " s), " << targets.size()
              << " targets, from " << semantic.GetNumberOfChannels() << " behaviour channels";
    if (!dropped.empty())
    {
      std::cout << " (no shape, left out:";
      for (const auto& d : dropped)
      {
        std::cout << " " << d;
      }
      std::cout << ")";
    }
    std::cout << "\n";
    if (!livelinkFile.empty())
    {
      // The face's targets and the behaviour's angles (degrees), frame by frame.
      std::vector<std::string> channels = track.GetChannels();
      std::vector<int> angles;
      for (const char* name : { "HeadYaw", "HeadPitch", "HeadRoll", "EyeYaw", "EyePitch" })
      {
        const int c = semantic.FindChannel(name);
        if (c >= 0)
        {
          channels.emplace_back(name);
          angles.push_back(c);
        }
      }
      morphnode::WeightTrack performance(channels, track.GetFrameRate());
      std::vector<double> row(channels.size());
      for (size_t f = 0; f < track.GetNumberOfFrames(); ++f)
      {
        std::copy(track.GetFrame(f), track.GetFrame(f) + track.GetNumberOfChannels(), row.begin());
        for (size_t a = 0; a < angles.size(); ++a)
        {
          row[track.GetNumberOfChannels() + a] =
            semantic.GetValue(f, static_cast<size_t>(angles[a]));
        }
        performance.AppendFrame(row);
      }
      std::vector<std::string> unmapped;
      const morphnode::LiveLinkCapture take =
        morphnode::CaptureFromTrack(performance, {}, &unmapped);
      {
        std::ostringstream livelink;
        morphnode::WriteLiveLinkCsv(livelink, take);
        const appkit::DeferStopSignals whole;
        morphnode::file::WriteFileSafely(livelinkFile, livelink.str(), "--livelink");
      }
      std::cout << "wrote " << livelinkFile << ": Live Link Face CSV, " << take.GetNumberOfRows()
                << " rows at " << take.TimecodeRate << " fps timecode, "
                << morphnode::ArkitShapeCount - take.MissingShapes.size() << " of "
                << morphnode::ArkitShapeCount << " ARKit shapes";
      if (!take.MissingShapes.empty())
      {
        std::cout << " (no face target, written as 0:";
        for (const auto& name : take.MissingShapes)
        {
          std::cout << " " << name;
        }
        std::cout << ")";
      }
      if (!unmapped.empty())
      {
        std::cout << "; no ARKit shape, left out:";
        for (const auto& name : unmapped)
        {
          std::cout << " " << name;
        }
      }
      // What was written must read as a take again (and says how many rows it holds).
      const morphnode::LiveLinkCapture back = morphnode::ReadLiveLinkCsvFile(livelinkFile);
      std::cout << "; read back: " << back.GetNumberOfRows() << " rows\n";
    }
  }
  catch (const std::bad_alloc&)
  {
    std::cerr << "MakeSpeechTrack: out of memory (the input is too long for this machine; see "
                 "docs/limits.md)\n";
    return 1;
  }
  catch (const std::exception& e)
  {
    std::cerr << "MakeSpeechTrack: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
