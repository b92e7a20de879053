// SPDX-License-Identifier: BSD-3-Clause
// A skinned avatar per frame (issue 23's goals): the shared MakeHuman avatar (7 skinned
// parts, 20,945 points, 67 targets, 76 joints) animated as a speaker is, with weights that
// change every frame (jawOpen, viseme_O, eyeBlinkLeft, mouthSmileLeft/Right) and bones that
// move every frame (head pose shared by head and neck, gaze by the eye joints):
// - MorphAndSkin: vtkMorphNodeFilter (relative weights, no optimizer) then
//   vtkMorphSkinFilter, one Update per frame: what MorphAvatar does for the avatar;
// - MorphAndSkinHeadStill: the same with the head held turned (the eyes and weights move):
//   vtkMorphSkinFilter re-skins only points whose input or joints changed since last frame;
// - MorphOnly: the same weights without the skin filter (the yardstick for the skin's cost:
//   goal MorphAndSkin <= 1.5 x MorphOnly);
// - VtkGltfReader: VTK 9.1's vtkGLTFReader on a copy of the avatar with the same frame as
//   a glTF animation (the mesh weights and the Head/Neck/eye rotations), ApplyDeformations
//   on (its CPU morph and skin), UpdateTimeStep per frame (goal: MorphAndSkin >= 20x faster).
// - MorphAndPoseOnly: MorphAndSkin with the skin filter posing only (SkinPoints off): the
//   CPU's share of a frame skinned in the vertex shader (vtkMorphSkinMapper);
// - PoseOnlyPass: the skin filter's pass alone in MorphAndPoseOnly (the morph node updated
//   outside the timing);
// - MorphAndPoseInPass, MorphAndSkinInPass (and ...Held): MorphAndPoseOnly and MorphAndSkin
//   with the skin filter as the morph node's pose filter (vtkMorphNodeFilter::SetPoseFilter):
//   posed in the morph node's own pass, one pass instead of two (what MorphAvatar runs);
// - MorphOnlyHeld, MorphAndSkinHeld, MorphAndPoseOnlyHeld: the same three with each frame's
//   parts shallow-copied into kept data sets, as a renderer's inputs hold them: the morph
//   node (and the skin filter) then write new arrays instead of the last frame's in place;
//   what a drawn frame's pipeline costs the CPU;
// - DrawnMorphOnlyAtRest, DrawnMorphAndCpuSkin, DrawnMorphAndGpuSkin: a drawn frame (Update
//   and an offscreen Render of every part, 640 x 640, framed on the face, GL finished) of
//   (a) the morph alone at rest, (b) morph + CPU re-skin, (c) morph + pose only + the skin
//   mapper; (b) and (c) posed in the morph node's pass, as MorphAvatar runs them. They need
//   an X display (xvfb-run -a); the renderer string goes to stderr.
// Times are per frame (real time, and CPU time of the whole process). The avatar is required;
// without it the benchmarks skip.
#include "vtkMorphNodeFilter.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"

#include "vtkMorphSkinMapper.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataSet.h"
#include "vtkGLTFReader.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkSmartPointer.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using json = nlohmann::json;
const std::string Avatar = std::string(MORPHNODE_AVATAR_DIR) + "/makehuman_avatar.glb";
/// Without the avatar: the benchmark skipped, saying why.
bool SkippedWithoutAvatar(benchmark::State& state)
{
  if (std::filesystem::exists(Avatar))
  {
    return false;
  }
  state.SkipWithError(("MakeHuman avatar not found: " + Avatar).c_str());
  return true;
}
constexpr double Fps = 30.0;
constexpr int Keys = 61; // 2 s of animation

/// Speech-like weight of a target at frame f.
double Weight(int which, int f)
{
  const double t = f / Fps;
  return 0.5 + 0.5 * std::sin(2.0 * t * (1.0 + 0.37 * which) + which);
}
double HeadYaw(int f)
{
  return 15.0 * std::sin(0.9 * f / Fps);
}
double EyeYaw(int f)
{
  return 20.0 * std::sin(1.7 * f / Fps);
}

const char* const Animated[] = { "jawOpen", "viseme_O", "eyeBlinkLeft", "mouthSmileLeft",
  "mouthSmileRight" };

void Append(std::vector<unsigned char>& bin, json& doc, const std::vector<float>& values,
  const char* type, size_t count, bool minmax)
{
  while (bin.size() % 4)
  {
    bin.push_back(0);
  }
  const size_t offset = bin.size();
  bin.resize(offset + 4 * values.size());
  std::memcpy(bin.data() + offset, values.data(), 4 * values.size());
  doc["bufferViews"].push_back(
    { { "buffer", 0 }, { "byteOffset", offset }, { "byteLength", 4 * values.size() } });
  json accessor = { { "bufferView", doc["bufferViews"].size() - 1 }, { "componentType", 5126 },
    { "count", count }, { "type", type } };
  if (minmax)
  {
    accessor["min"] = { *std::min_element(values.begin(), values.end()) };
    accessor["max"] = { *std::max_element(values.begin(), values.end()) };
  }
  doc["accessors"].push_back(accessor);
}

/// The avatar with the benchmark's frames as a glTF animation, for vtkGLTFReader.
std::string AnimatedCopy()
{
  const std::string out =
    (std::filesystem::temp_directory_path() / "morphnode_bench_skin_avatar.glb").string();
  std::ifstream in(Avatar, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string glb = ss.str();
  uint32_t jsonLength, binLength;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  json doc = json::parse(glb.substr(20, jsonLength));
  std::memcpy(&binLength, glb.data() + 20 + jsonLength, 4);
  std::vector<unsigned char> bin(
    glb.begin() + 28 + jsonLength, glb.begin() + 28 + jsonLength + binLength);

  std::vector<float> times;
  for (int k = 0; k < Keys; ++k)
  {
    times.push_back(static_cast<float>(k / Fps));
  }
  Append(bin, doc, times, "SCALAR", Keys, true);
  const size_t input = doc["accessors"].size() - 1;
  json animation = { { "name", "bench" }, { "samplers", json::array() },
    { "channels", json::array() } };
  const auto names = doc["meshes"][0]["extras"]["targetNames"].get<std::vector<std::string>>();
  std::vector<float> weights;
  for (int k = 0; k < Keys; ++k)
  {
    for (const auto& name : names)
    {
      float w = 0.0f;
      for (int a = 0; a < 5; ++a)
      {
        w = name == Animated[a] ? static_cast<float>(Weight(a, k)) : w;
      }
      weights.push_back(w);
    }
  }
  Append(bin, doc, weights, "SCALAR", weights.size(), false);
  const size_t weightsOutput = doc["accessors"].size() - 1;
  for (size_t n = 0; n < doc["nodes"].size(); ++n)
  {
    if (doc["nodes"][n].contains("mesh"))
    {
      animation["samplers"].push_back({ { "input", input }, { "output", weightsOutput } });
      animation["channels"].push_back({ { "sampler", animation["samplers"].size() - 1 },
        { "target", { { "node", n }, { "path", "weights" } } } });
    }
    const std::string name = doc["nodes"][n].value("name", "");
    if (name == "Head" || name == "LeftEye" || name == "RightEye")
    {
      std::vector<float> rotations;
      const auto r = doc["nodes"][n]["rotation"].get<std::vector<double>>();
      for (int k = 0; k < Keys; ++k)
      {
        // A turn about the joint's own axis, as large as the frame's angle (the exact axis
        // does not change the cost).
        const double a = (name == "Head" ? HeadYaw(k) : EyeYaw(k)) * M_PI / 360.0;
        const double q[4] = { 0, 0, std::sin(a), std::cos(a) }; // about local Z
        const double x = r[3] * q[0] + r[0] * q[3] + r[1] * q[2] - r[2] * q[1];
        const double y = r[3] * q[1] - r[0] * q[2] + r[1] * q[3] + r[2] * q[0];
        const double z = r[3] * q[2] + r[0] * q[1] - r[1] * q[0] + r[2] * q[3];
        const double w = r[3] * q[3] - r[0] * q[0] - r[1] * q[1] - r[2] * q[2];
        for (double v : { x, y, z, w })
        {
          rotations.push_back(static_cast<float>(v));
        }
      }
      Append(bin, doc, rotations, "VEC4", Keys, false);
      animation["samplers"].push_back(
        { { "input", input }, { "output", doc["accessors"].size() - 1 } });
      animation["channels"].push_back({ { "sampler", animation["samplers"].size() - 1 },
        { "target", { { "node", n }, { "path", "rotation" } } } });
    }
  }
  doc["animations"] = json::array({ animation });
  while (bin.size() % 4)
  {
    bin.push_back(0);
  }
  doc["buffers"][0]["byteLength"] = bin.size();
  std::string text = doc.dump();
  while (text.size() % 4)
  {
    text += ' ';
  }
  std::string file;
  auto u32 = [&file](uint32_t v) { file.append(reinterpret_cast<const char*>(&v), 4); };
  u32(0x46546C67);
  u32(2);
  u32(static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  u32(static_cast<uint32_t>(text.size()));
  u32(0x4E4F534A);
  file += text;
  u32(static_cast<uint32_t>(bin.size()));
  u32(0x004E4942);
  file.append(reinterpret_cast<const char*>(bin.data()), bin.size());
  std::ofstream(out, std::ios::binary) << file;
  return out;
}

/// The avatar's pipeline: the reader, the morph node (relative weights) and the skin filter,
/// re-skinning the points (`skinPoints`) or posing only, downstream of the morph node (a
/// second pass) or as its pose filter (`inPass`: in the morph node's pass, as MorphAvatar
/// runs it).
struct AvatarPipeline
{
  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkMorphSkinFilter> Skin;

  explicit AvatarPipeline(bool skinPoints, bool inPass = false)
  {
    this->Reader->SetFileName(Avatar.c_str());
    this->Reader->Update();
    this->Morph->SetInputConnection(this->Reader->GetOutputPort());
    this->Morph->SetWeightModeToRelative();
    if (inPass)
    {
      this->Morph->SetPoseFilter(this->Skin);
    }
    else
    {
      this->Skin->SetInputConnection(this->Morph->GetOutputPort());
    }
    this->Skin->SetSkinPoints(skinPoints);
  }

  /// Frame f's weights and bones (the head held turned when it does not move).
  void Animate(int f, bool headMoves = true)
  {
    for (int a = 0; a < 5; ++a)
    {
      this->Morph->SetWeightByName(Animated[a], Weight(a, f % Keys));
    }
    this->Skin->SetHeadYaw(headMoves ? HeadYaw(f % Keys) : 10.0);
    this->Skin->SetEyeYaw(EyeYaw(f % Keys));
  }
};

void Ours(benchmark::State& state, bool skin, bool headMoves = true, bool poseOnly = false,
  bool held = false, bool inPass = false)
{
  if (SkippedWithoutAvatar(state))
  {
    return;
  }
  AvatarPipeline p(!poseOnly, skin && inPass);
  vtkAlgorithm* last =
    skin && !inPass ? static_cast<vtkAlgorithm*>(p.Skin) : static_cast<vtkAlgorithm*>(p.Morph);
  // held: each frame's parts shallow-copied into kept data sets, as a renderer's inputs
  // hold them (MorphAvatar's HeadActors): the filters then cannot write the last frame's
  // arrays in place.
  std::vector<vtkSmartPointer<vtkPolyData>> kept;
  int f = 0;
  for (auto _ : state)
  {
    p.Animate(f, headMoves);
    last->Update();
    if (held)
    {
      const auto parts = vtkCompositeDataSet::GetDataSets<vtkPolyData>(
        vtkCompositeDataSet::SafeDownCast(last->GetOutputDataObject(0)));
      kept.resize(parts.size());
      for (size_t i = 0; i < parts.size(); ++i)
      {
        if (!kept[i])
        {
          kept[i] = vtkSmartPointer<vtkPolyData>::New();
        }
        kept[i]->ShallowCopy(parts[i]);
      }
    }
    ++f;
  }
  state.SetLabel(std::string(skin ? (poseOnly ? "morph + pose only (GPU skin)" : "morph + skin")
                                  : "morph only") +
    (skin && inPass ? ", in the morph node's pass" : "") + (held ? ", output held" : ""));
}

void MorphAndSkin(benchmark::State& state)
{
  Ours(state, true);
}
void MorphAndSkinHeadStill(benchmark::State& state)
{
  Ours(state, true, false); // the head held turned: only the eyes and the morphed points re-skin
}
void MorphOnly(benchmark::State& state)
{
  Ours(state, false);
}
void MorphAndPoseOnly(benchmark::State& state)
{
  Ours(state, true, true, true); // the skin filter poses only: a GPU-skinned frame's CPU cost
}
// The same three with the output held as a renderer holds it (a drawn frame's CPU share).
void MorphOnlyHeld(benchmark::State& state)
{
  Ours(state, false, true, false, true);
}
void MorphAndSkinHeld(benchmark::State& state)
{
  Ours(state, true, true, false, true);
}
void MorphAndPoseOnlyHeld(benchmark::State& state)
{
  Ours(state, true, true, true, true);
}
// The same with the skin filter as the morph node's pose filter: one pass (MorphAvatar's).
void MorphAndPoseInPass(benchmark::State& state)
{
  Ours(state, true, true, true, false, true);
}
void MorphAndPoseInPassHeld(benchmark::State& state)
{
  Ours(state, true, true, true, true, true);
}
void MorphAndSkinInPass(benchmark::State& state)
{
  Ours(state, true, true, false, false, true);
}
void MorphAndSkinInPassHeld(benchmark::State& state)
{
  Ours(state, true, true, false, true, true);
}
// The skin filter's pass alone when it poses only (the morph node updated outside the
// timing): what MorphAndPoseOnly adds to a frame.
void PoseOnlyPass(benchmark::State& state)
{
  if (SkippedWithoutAvatar(state))
  {
    return;
  }
  AvatarPipeline p(false);
  int f = 0;
  for (auto _ : state)
  {
    state.PauseTiming();
    p.Animate(f++, true);
    p.Morph->Update();
    state.ResumeTiming();
    p.Skin->Update();
  }
  state.SetLabel("pose only (GPU skin), the skin filter's pass");
}

enum class Drawn
{
  MorphOnlyAtRest, ///< (a) the morph alone, the skeleton at rest, plain mappers
  CpuSkin,         ///< (b) morph + vtkMorphSkinFilter re-skinning, plain mappers
  GpuSkin          ///< (c) morph + pose only + vtkMorphSkinMapper
};

/// A drawn frame: the pipeline's Update and an offscreen Render of every part (one actor
/// each, as MorphAvatar), framed on the face, 640 x 640, waiting for the GL to finish.
void DrawnFrame(benchmark::State& state, Drawn mode)
{
  if (SkippedWithoutAvatar(state))
  {
    return;
  }
  if (!std::getenv("DISPLAY"))
  {
    state.SkipWithError("no X display: run under xvfb-run -a");
    return;
  }
  // (b) and (c) posed in the morph node's pass, as MorphAvatar runs them.
  AvatarPipeline p(mode == Drawn::CpuSkin, mode != Drawn::MorphOnlyAtRest);
  // One window for every drawn benchmark of the run (VTK 9.1 opens an X connection per
  // window; opening many in a row now and then fails), a renderer of its own for each.
  static vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(640, 640);
  while (window->GetRenderers()->GetNumberOfItems() > 0)
  {
    window->RemoveRenderer(window->GetRenderers()->GetFirstRenderer());
  }
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  // One actor per part; each frame the part's new data set is shallow-copied into the
  // mapper's own (as MorphAvatar's HeadActors).
  std::vector<vtkSmartPointer<vtkPolyData>> shown;
  auto frame = [&](int f)
  {
    p.Animate(f);
    p.Morph->Update();
    auto* composite = vtkCompositeDataSet::SafeDownCast(p.Morph->GetOutputDataObject(0));
    const auto parts = vtkCompositeDataSet::GetDataSets<vtkPolyData>(composite);
    for (size_t i = 0; i < parts.size(); ++i)
    {
      if (shown.size() <= i)
      {
        shown.push_back(vtkSmartPointer<vtkPolyData>::New());
        vtkSmartPointer<vtkPolyDataMapper> mapper;
        if (mode == Drawn::GpuSkin)
        {
          mapper = vtkSmartPointer<vtkMorphSkinMapper>::New();
        }
        else
        {
          mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
        }
        mapper->ScalarVisibilityOff();
        mapper->SetInputData(shown.back());
        vtkNew<vtkActor> actor;
        actor->SetMapper(mapper);
        actor->GetProperty()->SetColor(0.86, 0.72, 0.62);
        renderer->AddActor(actor);
      }
      shown[i]->ShallowCopy(parts[i]);
    }
    window->Render();
    window->WaitForCompletion();
  };
  frame(0);
  double b[6];
  if (mode != Drawn::MorphOnlyAtRest)
  {
    p.Skin->GetHeadBounds(b);
  }
  else
  {
    vtkNew<vtkMorphSkinFilter> bounds; // the head's bounds only
    bounds->SetInputConnection(p.Reader->GetOutputPort());
    bounds->Update();
    bounds->GetHeadBounds(b);
  }
  vtkCamera* camera = renderer->GetActiveCamera();
  const double h = b[3] - b[2];
  camera->SetFocalPoint((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2);
  camera->SetPosition((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2 + 2.6 * h);
  camera->SetViewAngle(30);
  renderer->ResetCameraClippingRange();
  frame(1);
  static bool said = false;
  if (!said)
  {
    // The renderer string: llvmpipe is Mesa's software rasterizer, its "GPU" the CPU.
    const std::string caps = window->ReportCapabilities();
    const size_t at = caps.find("OpenGL renderer string:");
    std::cerr << "BenchSkin: "
              << caps.substr(at,
                   caps.find('\n', at) == std::string::npos ? std::string::npos
                                                            : caps.find('\n', at) - at)
              << "\n";
    said = true;
  }
  int f = 2;
  for (auto _ : state)
  {
    frame(f++);
  }
  state.SetLabel(mode == Drawn::MorphOnlyAtRest ? "drawn: morph only, at rest"
      : mode == Drawn::CpuSkin                  ? "drawn: morph + CPU skin"
                                                : "drawn: morph + pose only + GPU skin");
}
void DrawnMorphOnlyAtRest(benchmark::State& state)
{
  DrawnFrame(state, Drawn::MorphOnlyAtRest);
}
void DrawnMorphAndCpuSkin(benchmark::State& state)
{
  DrawnFrame(state, Drawn::CpuSkin);
}
void DrawnMorphAndGpuSkin(benchmark::State& state)
{
  DrawnFrame(state, Drawn::GpuSkin);
}

void VtkGltfReader(benchmark::State& state)
{
  if (SkippedWithoutAvatar(state))
  {
    return;
  }
  static const std::string file = AnimatedCopy();
  vtkNew<vtkGLTFReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetApplyDeformationsToGeometry(true);
  reader->SetFrameRate(Fps);
  reader->UpdateInformation();
  reader->EnableAnimation(0);
  reader->UpdateInformation();
  reader->UpdateTimeStep(0.0);
  int f = 1;
  for (auto _ : state)
  {
    reader->UpdateTimeStep((f % Keys) / Fps);
    ++f;
  }
  state.SetLabel("vtkGLTFReader animation, CPU morph + skin");
}
/// A frame's settings: milliseconds, wall time, and the CPU time of the whole process
/// (vtkSMPTools' worker threads included).
void PerFrame(benchmark::internal::Benchmark* b)
{
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}
} // namespace

BENCHMARK(MorphAndSkin)->Apply(PerFrame);
BENCHMARK(MorphAndSkinHeadStill)->Apply(PerFrame);
BENCHMARK(MorphOnly)->Apply(PerFrame);
BENCHMARK(MorphAndPoseOnly)->Apply(PerFrame);
BENCHMARK(PoseOnlyPass)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(MorphAndPoseInPass)->Apply(PerFrame);
BENCHMARK(MorphAndSkinInPass)->Apply(PerFrame);
BENCHMARK(MorphOnlyHeld)->Apply(PerFrame);
BENCHMARK(MorphAndSkinHeld)->Apply(PerFrame);
BENCHMARK(MorphAndPoseOnlyHeld)->Apply(PerFrame);
BENCHMARK(MorphAndPoseInPassHeld)->Apply(PerFrame);
BENCHMARK(MorphAndSkinInPassHeld)->Apply(PerFrame);
BENCHMARK(DrawnMorphOnlyAtRest)->Apply(PerFrame);
BENCHMARK(DrawnMorphAndCpuSkin)->Apply(PerFrame);
BENCHMARK(DrawnMorphAndGpuSkin)->Apply(PerFrame);
BENCHMARK(VtkGltfReader)->Apply(PerFrame);
BENCHMARK_MAIN();
