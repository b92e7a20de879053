// SPDX-License-Identifier: BSD-3-Clause
// MakeSpeechTrack: a long, speech-driven weight track for the optimizer study.
//
//   MakeSpeechTrack --face face.glb --out track.csv
//                   [--text Data/scripts/long-text.txt] [--rig Data/rigs/arkit.json]
//                   [--seed 2004] [--fps 30] [--voice en] [--rate 175]
//
// Speaks the text with eSpeak NG (morphnode::SpeakText, Oculus visemes), lets the
// behaviour controller add what a speaker does besides talking (idle blinks, saccades,
// smiles, a mood, brow raises, nods, glances; all seeded, so the same seed gives the same
// track), expands the semantic channels (visemes, EyesClosed, BrowsUp, LookLeft, ...)
// through the rig onto the face's own targets and writes their relative (glTF) weights
// as the CSV OptimizerStudy reads: `time,<target>,...`, one column per face target, in
// the face's order. Head and eye angles have no morph target and are left out.
//
// The target names come from the GLB's meshes[0].extras.targetNames (no VTK needed).
#include "base/Error.h"
#include "track/WeightTrack.h"
#include "behavior/BehaviorController.h"
#include "rig/Rig.h"
#include "speech/Speech.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
/// meshes[0].extras.targetNames of a .glb (or .gltf) file.
std::vector<std::string> ReadTargetNames(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    throw morphnode::InputError("cannot open " + path);
  }
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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

std::string ReadText(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
  {
    throw morphnode::InputError("cannot open " + path);
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (char& c : text)
  {
    if (c == '\n' || c == '\r')
    {
      c = ' ';
    }
  }
  return text;
}
} // namespace

int main(int argc, char* argv[])
{
#ifdef MORPHNODE_DATA_DIR
  const std::string data = MORPHNODE_DATA_DIR;
#else
  const std::string data = "Data";
#endif
  std::string face, out, textFile = data + "/scripts/long-text.txt", rigFile = data + "/rigs/arkit.json";
  std::string voice = "en";
  uint64_t seed = 2004;
  double fps = 30.0;
  int rate = morphnode::SpeechSynthesizer::DefaultRate;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string arg = argv[i], value = argv[i + 1];
    if (arg == "--face")
      face = value;
    else if (arg == "--out")
      out = value;
    else if (arg == "--text")
      textFile = value;
    else if (arg == "--rig")
      rigFile = value;
    else if (arg == "--seed")
      seed = std::stoull(value);
    else if (arg == "--fps")
      fps = std::stod(value);
    else if (arg == "--voice")
      voice = value;
    else if (arg == "--rate")
      rate = std::stoi(value);
    else
    {
      std::cerr << "unknown option " << arg << "\n";
      return 2;
    }
  }
  if (face.empty() || out.empty() || argc % 2 == 0)
  {
    std::cerr << "usage: MakeSpeechTrack --face face.glb --out track.csv [--text FILE] [--rig FILE]\n"
                 "                       [--seed N] [--fps F] [--voice V] [--rate WPM]\n";
    return 2;
  }
  try
  {
    const std::vector<std::string> targets = ReadTargetNames(face);
    morphnode::Rig rig = morphnode::Rig::LoadFile(rigFile);
    rig.Bind(targets);

    morphnode::SpeechOptions speech;
    speech.Voice = voice;
    speech.Rate = rate;

    morphnode::BehaviorController behavior;
    behavior.SetSeed(seed);
    behavior.SetFrameRate(fps);
    behavior.SetSynthesizer([&](const std::string& text) { return morphnode::SpeakText(text, speech); });

    // The speech, after a short pause, then the gestures of a lively speaker around it.
    const double start = 0.6;
    behavior.SetMood("happy", 0.3, 0.0);
    behavior.Say(ReadText(textFile), start);
    const double end = behavior.GetUtterances().back().End;
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto between = [&](double a, double b) { return a + (b - a) * unit(random); };
    for (double t = start + between(0.5, 2.0); t < end - 1.0; t += between(1.5, 4.0))
    {
      const double pick = unit(random);
      if (pick < 0.3)
        behavior.Gesture("raise_brows", t, between(0.6, 1.2), between(0.4, 0.9));
      else if (pick < 0.5)
        behavior.Gesture("smile", t, between(1.0, 2.5), between(0.3, 0.8));
      else if (pick < 0.7)
        behavior.Gesture("nod", t, between(0.5, 1.0), between(0.4, 0.8));
      else if (pick < 0.8)
        behavior.Gesture("frown", t, between(0.6, 1.2), between(0.3, 0.6));
      else
        behavior.LookAt(between(-20.0, 20.0), between(-10.0, 10.0), t, between(0.6, 1.5));
    }
    behavior.SetMood("happy", 0.6, std::max(0.0, end - 2.0), 1.5); // a warm ending (short texts too)
    behavior.SetDuration(end + 1.0);
    const morphnode::WeightTrack semantic = behavior.GenerateTrack();

    // Semantic channels -> rig shapes (channels without a shape, e.g. HeadYaw, are dropped).
    std::vector<int> shapeOf(semantic.GetNumberOfChannels(), -1);
    std::vector<std::string> dropped;
    for (size_t c = 0; c < semantic.GetNumberOfChannels(); ++c)
    {
      shapeOf[c] = rig.FindShape(semantic.GetChannels()[c]);
      if (shapeOf[c] < 0)
      {
        dropped.push_back(semantic.GetChannels()[c]);
      }
    }
    morphnode::WeightTrack track(targets, semantic.GetFrameRate());
    std::vector<double> shapes(rig.GetNumberOfShapes()), weights(targets.size());
    for (size_t f = 0; f < semantic.GetNumberOfFrames(); ++f)
    {
      std::fill(shapes.begin(), shapes.end(), 0.0);
      for (size_t c = 0; c < semantic.GetNumberOfChannels(); ++c)
      {
        if (shapeOf[c] >= 0)
        {
          shapes[static_cast<size_t>(shapeOf[c])] += semantic.GetValue(f, c);
        }
      }
      rig.Expand(shapes.data(), weights.data());
      track.AppendFrame(weights);
    }
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
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
