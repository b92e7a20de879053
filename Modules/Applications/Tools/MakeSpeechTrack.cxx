// SPDX-License-Identifier: BSD-3-Clause
// MakeSpeechTrack: a long, speech-driven weight track for the optimizer study.
//
//   MakeSpeechTrack --face face.glb --out track.csv
//                   [--text Data/scripts/long-text.txt] [--rig Data/rigs/arkit.json]
//                   [--seed 2004] [--fps 30] [--voice en] [--rate 175]
//
// Speaks the text with eSpeak NG (Oculus visemes), lets the behaviour controller add what
// a speaker does besides talking (SpeechTrack.h; all seeded, so the same seed gives the
// same track), expands the semantic channels through the rig onto the face's own targets
// and writes their relative (glTF) weights as the CSV OptimizerStudy reads:
// `time,<target>,...`, one column per face target, in the face's order. Head and eye
// angles have no morph target and are left out.
//
// The target names come from the GLB's meshes[0].extras.targetNames (no VTK needed).
#include "CommandLine.h"
#include "DataPaths.h"
#include "SpeechTrack.h"

#include "base/Error.h"
#include "base/Text.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <fstream>
#include <iostream>
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
    auto u32 = [&](size_t at) {
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
  std::string face, out, textFile = appkit::DataPath("scripts/long-text.txt"),
                         rigFile = appkit::DataPath("rigs/arkit.json");
  morphnode::study::SpeechTrackOptions options;
  CLI::App app("MakeSpeechTrack: a long speech-driven weight track of a face's targets, for "
               "OptimizerStudy (docs/optimizer-study.md).",
    "MakeSpeechTrack");
  app.add_option("--face", face, "a glTF/GLB face with extras.targetNames")
    ->required()
    ->check(CLI::ExistingFile);
  app.add_option("--out", out, "the CSV to write")->required();
  app.add_option("--text", textFile, "what is said")->check(CLI::ExistingFile)->capture_default_str();
  app.add_option("--rig", rigFile, "the rig onto the face's targets")
    ->check(CLI::ExistingFile)
    ->capture_default_str();
  app.add_option("--seed", options.Seed, "seed of the behaviour")
    ->check(appkit::UnsignedInteger())
    ->capture_default_str();
  appkit::AddNumberOption(app, "--fps", options.FrameRate, 1.0, 240.0, "frame rate, in [1, 240]");
  app.add_option("--voice", options.Voice, "eSpeak NG voice")->capture_default_str();
  app.add_option("--rate", options.Rate, "words per minute")
    ->check(CLI::Range(morphnode::SpeechSynthesizer::MinimumRate, morphnode::SpeechSynthesizer::MaximumRate))
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
    std::ofstream csv(out);
    if (!csv)
    {
      throw morphnode::InputError("cannot write " + out);
    }
    track.WriteCsv(csv);
    std::cout << "wrote " << out << ": " << track.GetNumberOfFrames() << " frames at " << track.GetFrameRate()
              << " fps (" << track.GetNumberOfFrames() / track.GetFrameRate() << " s), " << targets.size()
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
  }
  catch (const std::exception& e)
  {
    std::cerr << "MakeSpeechTrack: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
