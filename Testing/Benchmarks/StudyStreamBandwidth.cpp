// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream's figures (docs/streaming.md), measured in one run:
//  1. Bandwidth: the same 60 s of behaviour (idle, a mood, three sentences) at 30 fps as
//     dense float32 weights, dense 8-bit weights, and the stream's sparse frames after each
//     optimizer method, with the vertex error each costs (largest distance of any vertex from
//     the blend of the unquantized, unoptimized weights; mean over frames of the per-frame
//     maximum, and the maximum), for the default head and the ICT head through the ARKit rig.
//  2. Sessions per core: the CPU time one session costs per second of stream (behaviour,
//     rig, optimizer, quantization, encoding, sound resampling), without speech synthesis
//     (utterances synthesized once beforehand and replayed) and with it (eSpeak NG for every
//     sentence), and from it the sessions one core keeps at 30 fps.
// Not a test: it asserts nothing.
//
//   StudyStreamBandwidth [--seconds 60] [--quick] [--out FILE.md]
#include "base/Error.h"
#include "gltf/GltfMorphMesh.h"
#include "gltf/GltfScene.h"
#include "morph/OptimizerPresets.h"
#include "speech/Speech.h"
#include "stream/StreamSession.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace morphnode;
using namespace morphnode::stream;

namespace
{
double CpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

/// Positions-only model of the avatar file, for the vertex error.
struct Blender
{
  MorphScene Scene;
  std::vector<std::vector<float>> A, B;
  size_t Points = 0;
  explicit Blender(const StreamAvatar& avatar)
  {
    const GltfScene file =
      LoadGltfSceneFromMemory(avatar.GetFile().data(), avatar.GetFile().size());
    std::vector<std::shared_ptr<const MorphMesh>> meshes;
    for (GltfPart part : file.Parts)
    {
      part.Normals.clear();
      for (auto& t : part.Targets)
      {
        t.NormalDeltas.clear();
      }
      meshes.push_back(std::make_shared<MorphMesh>(GltfPartToMorphMesh(part)));
      this->A.emplace_back(part.Positions.size());
      this->B.emplace_back(part.Positions.size());
      this->Points += part.GetNumberOfPoints();
    }
    this->Scene.SetParts(meshes);
    this->Scene.SetWeightMode(WeightMode::Relative);
  }
  /// Largest vertex distance between the blends of two weight vectors (stream order).
  double Error(const std::vector<double>& reference, const std::vector<double>& sent)
  {
    auto blend = [&](const std::vector<double>& w, std::vector<std::vector<float>>& out)
    {
      std::vector<double> requested(w.size() + 1, 0.0);
      std::copy(w.begin(), w.end(), requested.begin() + 1);
      this->Scene.SetWeights(requested);
      for (size_t p = 0; p < this->Scene.GetNumberOfParts(); ++p)
      {
        this->Scene.Blend(p, { out[p].data() }, 0, out[p].size() / 3);
      }
    };
    blend(reference, this->A);
    blend(sent, this->B);
    double worst = 0.0;
    for (size_t p = 0; p < this->A.size(); ++p)
    {
      for (size_t i = 0; i < this->A[p].size(); i += 3)
      {
        const double dx = this->A[p][i] - this->B[p][i], dy = this->A[p][i + 1] - this->B[p][i + 1],
                     dz = this->A[p][i + 2] - this->B[p][i + 2];
        worst = std::max(worst, dx * dx + dy * dy + dz * dz);
      }
    }
    return std::sqrt(worst);
  }
};

double Diagonal(const GltfScene& face)
{
  double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
  for (const auto& part : face.Parts)
  {
    for (size_t p = 0; p + 2 < part.Positions.size(); p += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        lo[k] = std::min(lo[k], static_cast<double>(part.Positions[p + k]));
        hi[k] = std::max(hi[k], static_cast<double>(part.Positions[p + k]));
      }
    }
  }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
    (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

const char* const Sentences[] = {
  "Hello! I am an avatar made of morph targets, and my face is drawn by your browser.",
  "The server decides which targets matter in every frame, and sends only those.",
  "A few bytes per frame are enough to make me talk, blink and look around.",
};

/// The 60 s script: a mood at 2 s, sentences at 1 s, 20 s, 40 s (and every 20 s after).
void Script(StreamSession& s, double t, double frame, const LiveBehavior::Synthesizer* replay,
  const std::vector<Utterance>* cached)
{
  auto due = [&](double at) { return t <= at && at < t + frame; };
  if (due(2.0))
  {
    dialog::MoodCommand mood;
    mood.Name = "happy";
    mood.Intensity = 0.6;
    s.Mood(mood, t);
  }
  for (int k = 0; k < 100; ++k)
  {
    if (due(1.0 + 20.0 * k))
    {
      if (cached)
      {
        s.GetBehavior().Speak((*cached)[static_cast<size_t>(k) % cached->size()], t);
      }
      else
      {
        dialog::SayCommand say;
        say.Text = Sentences[k % 3];
        s.Say(say, t);
      }
    }
  }
  (void)replay;
}

struct Row
{
  std::string Name;
  double WeightBytesPerSecond = 0.0; ///< the weights alone
  double FrameBytesPerSecond = 0.0;  ///< whole frames (sample, weights, rotations)
  double MeanTargets = 0.0;
  double MeanError = 0.0, MaxError = 0.0;
};

std::string Fixed(double v, int digits)
{
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

void Bandwidth(std::ostream& md, const std::string& title, const GltfScene& face, const Rig* rig,
  const SpeechOptions& speech, double seconds, int errorStride)
{
  const std::vector<std::string> visemes = SelectVisemeMap(speech).GetVisemes();
  // (float deltas: the loader reads them back; the file the page gets has 16-bit deltas,
  // a step of 1/32767 model units, not counted here)
  const StreamAvatar avatar(face, LiveBehavior(visemes).GetChannelNames(), rig, false);
  Blender blender(avatar);
  const double diagonal = Diagonal(face);
  const size_t n = avatar.GetTargetNames().size();
  const double fps = 30.0, frame = 1.0 / fps;
  const int frames = static_cast<int>(std::lround(seconds * fps));
  LiveBehavior::Synthesizer synth = [speech](const std::string& text)
  { return SpeakText(text, speech); };

  struct Method
  {
    const char* Name;
    OptimizerPreset Preset;
    double Threshold;
  };
  const Method methods[] = {
    { "sparse, no optimizer (non-zero after 8-bit)", OptimizerPreset::None, 0.0 },
    { "sparse, fixed threshold 0.1, pruned to the largest", OptimizerPreset::FixedMaximum, 0.1 },
    { "sparse, fixed threshold 0.1, pruned to the remaining", OptimizerPreset::FixedRemaining,
      0.1 },
    { "sparse, adjusted threshold 0.1 (the paper's th_adj)", OptimizerPreset::Adjusted, 0.1 },
    { "sparse, adjusted threshold 0.2", OptimizerPreset::Adjusted, 0.2 },
    { "sparse, error bound 0.5 % of the diagonal", OptimizerPreset::ErrorBounded, 0.0 },
  };
  std::vector<Row> rows;
  Row dense32{ "dense float32", 0, 0, static_cast<double>(n), 0, 0 };
  Row dense8{ "dense 8-bit", 0, 0, static_cast<double>(n), 0, 0 };
  const size_t rotations = avatar.GetRotationNames().size();
  dense32.WeightBytesPerSecond = 4.0 * n * fps;
  dense32.FrameBytesPerSecond = (4.0 + 4.0 * n + 16.0 * rotations) * fps;
  dense8.WeightBytesPerSecond = 1.0 * n * fps;
  dense8.FrameBytesPerSecond = (4.0 + 1.0 * n + 6.0 * rotations) * fps;
  bool first = true;
  for (const Method& m : methods)
  {
    StreamSettings settings;
    settings.Optimizer = MakeOptimizerSettings(m.Preset, m.Threshold, 0.005 * diagonal);
    StreamSession s(avatar, visemes, synth, settings);
    Row row;
    row.Name = m.Name;
    double targets = 0.0, errors = 0.0, dense8Errors = 0.0;
    int measured = 0;
    uint64_t weightBytes = 0;
    for (int f = 0; f < frames; ++f)
    {
      const double t = f * frame;
      Script(s, t, frame, nullptr, nullptr);
      s.Tick(t);
      s.TakeMessages();
      const Frame& sent = s.GetLastFrame();
      weightBytes += 2 * sent.Targets.size();
      targets += sent.Targets.size();
      if (f % errorStride == 0)
      {
        const std::vector<double> reference = s.GetLastWeights();
        std::vector<double> got(n, 0.0);
        for (const auto& [k, w] : sent.Targets)
        {
          got[k] = DequantizeWeight(w);
        }
        const double e = blender.Error(reference, got);
        errors += e;
        row.MaxError = std::max(row.MaxError, e);
        if (first)
        {
          std::vector<double> q(n);
          for (size_t k = 0; k < n; ++k)
          {
            q[k] = DequantizeWeight(QuantizeWeight(reference[k]));
          }
          const double e8 = blender.Error(reference, q);
          dense8Errors += e8;
          dense8.MaxError = std::max(dense8.MaxError, e8);
        }
        ++measured;
      }
    }
    row.WeightBytesPerSecond = weightBytes / seconds;
    row.FrameBytesPerSecond = s.GetFrameBytes() / seconds;
    row.MeanTargets = targets / frames;
    row.MeanError = errors / std::max(1, measured);
    if (first)
    {
      dense8.MeanError = dense8Errors / std::max(1, measured);
    }
    first = false;
    rows.push_back(row);
  }
  rows.insert(rows.begin(), dense8);
  rows.insert(rows.begin(), dense32);
  md << "### " << title << "\n\n"
     << n << " targets streamed (of " << avatar.GetNumberOfFaceTargets() << " in the face), "
     << rotations << " rotations, " << blender.Points << " vertices, diagonal "
     << Fixed(diagonal, 4) << "; " << seconds
     << " s at 30 fps (idle, a mood, a sentence at 1 s, 20 s, 40 s). Vertex error: the largest "
        "distance of any vertex "
        "from the blend of the exact weights, per frame (every "
     << errorStride << " frames), in % of the diagonal.\n\n"
     << "| encoding | weights B/s | frames B/s (with sample and rotations) | targets per frame | "
        "mean error % | max error % |\n"
     << "|---|---:|---:|---:|---:|---:|\n";
  for (const Row& r : rows)
  {
    md << "| " << r.Name << " | " << Fixed(r.WeightBytesPerSecond, 0) << " | "
       << Fixed(r.FrameBytesPerSecond, 0) << " | " << Fixed(r.MeanTargets, 2) << " | "
       << Fixed(100.0 * r.MeanError / diagonal, 4) << " | "
       << Fixed(100.0 * r.MaxError / diagonal, 4) << " |\n";
  }
  md << "\n";
}

void Sessions(std::ostream& md, const GltfScene& face, const SpeechOptions& speech, double seconds)
{
  const std::vector<std::string> visemes = SelectVisemeMap(speech).GetVisemes();
  const StreamAvatar avatar(face, LiveBehavior(visemes).GetChannelNames(), nullptr);
  LiveBehavior::Synthesizer synth = [speech](const std::string& text)
  { return SpeakText(text, speech); };
  std::vector<Utterance> cached;
  for (const char* sentence : Sentences)
  {
    cached.push_back(SpeakText(sentence, speech));
  }
  const double fps = 30.0, frame = 1.0 / fps;
  const int frames = static_cast<int>(std::lround(seconds * fps));
  md
    << "### Sessions per core\n\nOne thread ticks " << 8 << " sessions through " << seconds
    << " s of stream each (a sentence every 20 s, speaking about a third of the time; the adjusted "
       "threshold 0.1); CPU time of the process per session and second of stream, and the sessions "
       "one "
       "core keeps at 30 fps (1 / that). Sending is not included (see the loopback figures).\n\n"
    << "| speech | CPU ms per session-second | sessions per core | bytes per session-second "
       "(frames + PCM) |\n"
    << "|---|---:|---:|---:|\n";
  for (int withSynthesis = 0; withSynthesis < 2; ++withSynthesis)
  {
    StreamSettings settings;
    settings.Optimizer = MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.1, 0.0);
    std::vector<std::unique_ptr<StreamSession>> sessions;
    for (int i = 0; i < 8; ++i)
    {
      settings.Seed = static_cast<uint64_t>(i + 1);
      sessions.push_back(std::make_unique<StreamSession>(avatar, visemes, synth, settings));
    }
    uint64_t bytes = 0;
    const double cpu0 = CpuSeconds();
    for (int f = 0; f < frames; ++f)
    {
      const double t = f * frame;
      for (auto& s : sessions)
      {
        Script(*s, t, frame, nullptr, withSynthesis ? nullptr : &cached);
        s->Tick(t);
        for (const auto& m : s->TakeMessages())
        {
          bytes += m.size();
        }
      }
    }
    const double cpu = CpuSeconds() - cpu0;
    const double perSessionSecond = cpu / (sessions.size() * seconds);
    md << "| "
       << (withSynthesis ? "synthesized (eSpeak NG) for every sentence"
                         : "replayed (synthesized once)")
       << " | " << Fixed(1000.0 * perSessionSecond, 3) << " | " << Fixed(1.0 / perSessionSecond, 0)
       << " | " << Fixed(bytes / (sessions.size() * seconds), 0) << " |\n";
  }
  md << "\n";
}
} // namespace

int main(int argc, char* argv[])
{
  double seconds = 60.0;
  std::string out;
  bool quick = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc)
    {
      seconds = std::atof(argv[++i]);
    }
    else if (a == "--out" && i + 1 < argc)
    {
      out = argv[++i];
    }
    else if (a == "--quick")
    {
      quick = true;
    }
    else
    {
      std::cerr << "usage: StudyStreamBandwidth [--seconds 60] [--quick] [--out FILE.md]\n";
      return 2;
    }
  }
  if (quick)
  {
    seconds = 3.0;
  }
  try
  {
    std::ostringstream md;
    SpeechOptions speech;
    speech.Visemes = VisemeSet::Paper6;
    const GltfScene head =
      LoadGltfScene(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb");
    Bandwidth(md, "The default head", head, nullptr, speech, seconds, quick ? 10 : 3);
    const std::string ict = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
    if (std::filesystem::exists(ict))
    {
      const Rig rig = Rig::LoadFile(std::string(MORPHNODE_SOURCE_DIR) + "/Data/rigs/arkit.json");
      Bandwidth(md, "The ICT head through the ARKit rig", LoadGltfScene(ict), &rig, speech, seconds,
        quick ? 10 : 6);
    }
    else
    {
      md << "(The ICT head is missing: " << ict << ")\n\n";
    }
    Sessions(md, head, speech, quick ? 2.0 : std::min(seconds, 60.0));
    std::cout << md.str();
    if (!out.empty())
    {
      std::ofstream(out) << md.str();
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "StudyStreamBandwidth: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
