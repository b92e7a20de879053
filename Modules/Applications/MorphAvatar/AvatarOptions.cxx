// SPDX-License-Identifier: BSD-3-Clause
#include "AvatarOptions.h"

#include "base/Text.h"
#include "budget/DeviceProfile.h"

#include "CommandLine.h"
#include "DataPaths.h"
#include "MeshFiles.h"

#include "gltf/GltfWriter.h"
#include "transfer/TransferScene.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace morphavatar
{
namespace appkit = morphnode::appkit;

namespace
{
const char* const Name = "MorphAvatar";

CLI::App& App()
{
  static CLI::App app(
    "MorphAvatar: a talking face with morph targets (Berner, WSCG 2004, Figure 6). An avatar\n"
    "speaks a sentence or plays a behaviour script with idle behaviour; the optimizer is\n"
    "switched by keys; offscreen it renders PNG frames, a video with sound, a ParaView time\n"
    "series or one frame compared with a baseline (docs/avatar.md).",
    Name);
  return app;
}
/// --targets-from: the face (a bare mesh) given the source's targets (docs/transfer.md),
/// written to a temporary GLB that becomes the face. Source targets named like ARKit's
/// get the ARKit rig unless --rig chose one.
void TransferTargetsOntoFace(Options& o, const std::string& source)
{
  if (o.Face.empty())
  {
    appkit::FailUsage(App(), "--targets-from needs --face: the mesh to give the targets to");
  }
  try
  {
    const morphnode::TransferSource s =
      morphnode::MakeTransferSource(appkit::ReadMeshScene(source));
    morphnode::GltfScene face = appkit::ReadMeshScene(o.Face);
    morphnode::TransferOntoScene(s, face, {});
    const std::string file = (std::filesystem::temp_directory_path() /
      ("morphavatar-" + std::to_string(getpid()) + "-face.glb"))
                               .string();
    morphnode::WriteGltfScene(file, face, nullptr);
    o.Face = file;
    static std::string written; // removed when the program ends
    written = file;
    std::atexit([] { std::filesystem::remove(written); });
    if (o.Rig.empty() &&
      std::find(s.TargetNames.begin(), s.TargetNames.end(), "jawOpen") != s.TargetNames.end())
    {
      o.Rig = appkit::DataPath("rigs/arkit.json");
    }
  }
  catch (const std::exception& e)
  {
    appkit::FailUsage(App(), "--targets-from " + source + ": " + e.what());
  }
}
} // namespace

void FailUsage(const std::string& message)
{
  appkit::FailUsage(App(), message);
}

Options ParseOptions(int argc, char* argv[])
{
  Options o;
  CLI::App& app = App();
  app.get_formatter()->column_width(28);
  app.footer("Keys (interactive): 0-4 method, +/- threshold (method 4: error bound), space pause,\n"
             "  r restart, o overlay on/off, q quit; mouse: rotate/zoom the camera.");

  const std::string say = "What it says and does";
  app
    .add_option("--say", o.Say,
      "speak TEXT (eSpeak NG) at 0.5 s, after the script's speech if a script is given; "
      "default: a short greeting when there is no script")
    ->type_name("TEXT")
    ->check(CLI::Validator([](std::string& s) -> std::string
      { return s.find_first_not_of(" \t\n") == std::string::npos ? "needs a non-empty text" : ""; },
      std::string()))
    ->group(say);
  app.add_option("--voice", o.Voice, "eSpeak NG voice of --say and the script")
    ->capture_default_str()
    ->group(say);
  app
    .add_option("--visemes", o.Visemes,
      "viseme set: paper6 (A E O S F L), oculus15, german16 (default: oculus15 for a face with "
      "its own viseme_* targets, else paper6)")
    ->check(CLI::IsMember({ "paper6", "oculus15", "german16" }))
    ->group(say);
  app
    .add_option(
      "--script", o.Script, "a behaviour script (docs/behavior.md), e.g. Data/scripts/greeting.txt")
    ->check(CLI::ExistingFile)
    ->group(say);
  const std::string recorded = "Recorded speech (docs/speech.md)";
  auto* audio =
    app
      .add_option("--audio", o.Audio,
        "speak a recording (WAV, FLAC, OGG) at 0.5 s (after the script's speech if a script is "
        "given), timed by aligning the transcript (--text, --text-file; in the language of "
        "--voice), by a timing file (--timings), or else by English phoneme recognition; the "
        "recording is the sound of --video")
      ->check(CLI::ExistingFile)
      ->group(recorded);
  auto* text = app.add_option("--text", o.Text, "the transcript of --audio")
                 ->type_name("TEXT")
                 ->needs(audio)
                 ->group(recorded);
  auto* textFile =
    app.add_option("--text-file", o.TextFile, "the transcript of --audio, from a file")
      ->check(CLI::ExistingFile)
      ->needs(audio)
      ->excludes(text)
      ->group(recorded);
  auto* timings =
    app
      .add_option("--timings", o.Timings,
        "a timing file (.pho, Rhubarb TSV/JSON/XML, Praat TextGrid, Polly speech marks, Azure "
        "viseme IDs, ElevenLabs character alignments): of "
        "--audio (e.g. the cues Rhubarb Lip Sync computed from it), or alone to move the mouth "
        "without sound")
      ->check(CLI::ExistingFile)
      ->excludes(text)
      ->excludes(textFile)
      ->group(recorded);
  app
    .add_option("--timings-format", o.TimingsFormat,
      "the format of --timings where its extension does not tell: auto, pho, rhubarb-tsv, "
      "rhubarb-json, rhubarb-xml, textgrid, speech-marks, azure-visemes, character-alignment")
    ->check(CLI::IsMember({ "auto", "pho", "rhubarb-tsv", "rhubarb-json", "rhubarb-xml", "textgrid",
                            "speech-marks", "azure-visemes", "character-alignment" },
      CLI::ignore_case))
    ->capture_default_str()
    ->needs(timings)
    ->group(recorded);
  const std::string played = "Recorded performances (docs/avatar.md)";
  auto* animation =
    app
      .add_option("--animation", o.Animation,
        "play the face file's own glTF animation (its name or index; e.g. a --gltf export read "
        "back with --face), with --audio as its sound")
      ->type_name("NAME|INDEX")
      ->group(played);
  auto* capture =
    app
      .add_option("--capture", o.Capture,
        "play a Live Link Face take (CSV, docs/capture.md) on the face: its ARKit shapes onto the "
        "face's targets by name, its head and eye angles; with --audio as its sound")
      ->check(CLI::ExistingFile)
      ->excludes(animation)
      ->group(played);
  for (CLI::Option* performance : { animation, capture })
  {
    performance->excludes(text)->excludes(textFile)->excludes(timings);
  }
  app.add_option("--seed", o.Seed, "seed of the idle behaviour (default 1 or the script's)")
    ->check(appkit::UnsignedInteger())
    ->group(say);
  appkit::AddNumberOption(app, "--duration", o.Duration, 0.0, 24 * 3600.0,
    "length in seconds (default: the script's, else the end of the last command + 1 s, at least 5 "
    "s)")
    ->default_str("")
    ->group(say);
  appkit::AddNumberOption(app, "--fps", o.Fps, 1.0, 240.0,
    "frame rate of the track and the offscreen frames, in [1, 240] (default 30 or the script's)")
    ->default_str("")
    ->group(say);

  const std::string face = "The face";
  app
    .add_option("--face", o.Face,
      "a face with morph targets (glTF/GLB, OBJ set); default the project's default face "
      "(its targets match the channels)")
    ->check(CLI::ExistingPath)
    ->group(face);
  app
    .add_option("--rig", o.Rig,
      "a rig (docs/rigs.md, e.g. Data/rigs/arkit.json) mapping the channels onto the face's own "
      "targets "
      "(default: chosen from the face's target names, docs/avatars.md)")
    ->check(CLI::ExistingFile)
    ->group(face);
  app
    .add_option("--gaze", o.Gaze,
      "how the eyes turn: bones (a skinned avatar's eye joints; its eyeLook* targets are then left "
      "out), targets (eyeLook* targets, or eye parts turned as nodes), auto (bones when the avatar "
      "has eye joints)")
    ->check(CLI::IsMember({ "auto", "bones", "targets" }))
    ->capture_default_str()
    ->group(face);
  app
    .add_option(
      "--frame", o.Framing, "what the camera frames: face (head and shoulders), bust, body")
    ->check(CLI::IsMember({ "face", "bust", "body" }))
    ->capture_default_str()
    ->group(face);
  app
    .add_option("--pose", o.Pose,
      "a skinned body's arms, on screen and in --gltf: relaxed (a T- or A-pose lowered) or "
      "stored (as in the file)")
    ->check(CLI::IsMember({ "relaxed", "stored" }))
    ->capture_default_str()
    ->group(face);
  std::string targetsFrom;
  app
    .add_option("--targets-from", targetsFrom,
      "give --face (a mesh without targets: glTF, OBJ, PLY, STL, VTP) the targets of this face "
      "first (docs/transfer.md); ARKit-named targets get Data/rigs/arkit.json unless --rig")
    ->check(CLI::ExistingFile)
    ->group(face);

  const std::string optimizer = "The optimizer (keys 0-4 and +/- switch them while it runs)";
  appkit::AddOptimizerPresetOption(app, "--method", o.Method, appkit::OptimizerPresetChoices())
    ->group(optimizer);
  appkit::AddNumberOption(
    app, "--threshold", o.Threshold, 0.0, 1.0, "th_fix of methods 1-3, in [0, 1]")
    ->group(optimizer);
  appkit::AddNumberOption(app, "--max-error", o.MaxError, 0.0, 1e30,
    "vertex error bound of method 4 in model units (default 0.5 % of the face's bounding-box "
    "diagonal)")
    ->default_str("")
    ->group(optimizer);
  appkit::AddNumberOption(app, "--hysteresis", o.Hysteresis, 0.0, 0.99,
    "in [0, 0.99]: keeps active targets a little longer")
    ->group(optimizer);
  appkit::AddNumberOption(app, "--frame-budget", o.FrameBudget, 0.0, 1e6,
    "milliseconds for the morph of a frame: the threshold is chosen every frame from measured "
    "times (replaces --threshold; 0: off)")
    ->group(optimizer);
  app
    .add_option("--frame-budget-log", o.FrameBudgetLog,
      "with --frame-budget or --profile: every frame's threshold, active targets and morph time as "
      "CSV")
    ->group(optimizer);
  app
    .add_flag("--lod", o.Lod,
      "target level of detail: targets whose reach projects below half a pixel (the profile's "
      "bound with --profile) on screen are left out, from the camera every frame (docs/lod.md)")
    ->group(optimizer);
  app
    .add_option("--profile", o.Profile,
      "a device profile (" + morphnode::DeviceProfileNames() +
        "): its frame budget and pixel "
        "bound (implies --lod; --frame-budget overrides its budget)")
    ->check(
      [](const std::string& name)
      {
        try
        {
          morphnode::FindDeviceProfile(name);
          return std::string();
        }
        catch (const std::exception& e)
        {
          return std::string(e.what());
        }
      })
    ->group(optimizer);

  const std::string output = "Output";
  appkit::AddSizeOption(app, "--size", o.Width, o.Height, "window / frame size")->group(output);
  app
    .add_flag("--offscreen", o.Offscreen,
      "no window: render every frame at the frame rate; needs --frames, --video, --pvd or --png")
    ->group(output);
  app
    .add_option("--frames", o.FramesDir, "write frame_00000.png ... into DIR (created if missing)")
    ->type_name("DIR")
    ->group(output);
  app
    .add_option("--video", o.Video,
      "write a video: FILE.ogv (Theora, silent) and FILE.wav; with ffmpeg on PATH also FILE.mp4 "
      "(or .mkv if FILE ends so) with sound")
    ->type_name("FILE")
    ->group(output);
  app
    .add_flag("--cpu-skin", o.CpuSkin,
      "a skinned avatar re-skinned on the CPU every frame (vtkMorphSkinFilter); by default the "
      "window and frames skin it in the vertex shader (vtkMorphSkinMapper, docs/avatars.md). "
      "--pvd always re-skins on the CPU (it writes the posed points)")
    ->group(output);
  app
    .add_option("--pvd", o.Pvd,
      "write the morphed head of every frame as a ParaView time series: FILE.pvd and "
      "FILE/face_00000.vtm ... (every part a block; one mesh: .vtp), with distance arrays "
      "(AnimatedRegion, Distance_<target>) and "
      "the weights (EffectiveWeights, the behaviour's channels) as field data")
    ->type_name("FILE.pvd")
    ->group(output);
  app
    .add_option("--gltf", o.Gltf,
      "write the head with its morph targets and the whole performance as a glTF animation "
      "(weights, head pose, eye turns) to FILE.glb or FILE.gltf, and its sound to FILE.wav "
      "(docs/gltf.md); without other output nothing is rendered")
    ->type_name("FILE.glb")
    ->group(output);
  std::string gltfWeights = "optimized";
  app
    .add_option("--gltf-weights", gltfWeights,
      "the weights --gltf writes: optimized (the optimizer's, as rendered; default) or raw")
    ->check(CLI::IsMember({ "optimized", "raw" }))
    ->group(output);
  appkit::AddNumberOption(
    app, "--at", o.At, 0.0, 24 * 3600.0, "render only the frame at time T (with --png / --compare)")
    ->default_str("")
    ->group(output);
  app.add_option("--png", o.Png, "write that single frame (default: the last frame)")
    ->type_name("FILE")
    ->group(output);
  app
    .add_option("--compare", o.Compare,
      "compare the single frame with a baseline PNG (VTK's image difference, 24 levels of "
      "tolerance a channel); exit code 1 when it differs")
    ->check(CLI::ExistingFile)
    ->group(output);
  appkit::AddNumberOption(app, "--compare-threshold", o.CompareThreshold, 0.0, 1000.0,
    "largest accepted image error (VTK's usual 10)")
    ->group(output);
  app.add_flag("--no-overlay", "no text overlay")->group(output);
  app.add_flag("--quiet", o.Quiet, "no progress bar")->group(output);
  appkit::AddNumberOption(app, "--exit-after", o.ExitAfter, 0.0, 1e6,
    "interactive: close the window after S seconds and print the frame rate and the last "
    "overlay (for smoke tests)")
    ->default_str("")
    ->group(output);
  app.add_option("--keys", o.Keys, "interactive: press these keys at the start, e.g. '4--'")
    ->group(output);
  app
    .add_flag("--mute", o.Mute,
      "window and live: no sound (by default the speech plays on the sound device, and the "
      "picture follows the sound's clock)")
    ->group(output);

  const std::string live = "Live commands from a dialog system (JSON lines, docs/dialog.md)";
  app
    .add_option("--listen", o.Listen,
      "take commands on ADDR: HOST:PORT (loopback only, e.g. 127.0.0.1:5555; PORT 0 picks a "
      "free port, printed on stderr), PORT, or unix:PATH; repeatable")
    ->type_name("ADDR")
    ->group(live);
  app
    .add_flag("--commands-stdin", o.CommandsStdin,
      "take commands on standard input; their events go to standard output")
    ->group(live);
  app
    .add_option("--speech-dir", o.SpeechDir,
      "live: the folder whose recordings and timing files `say` commands may name (external "
      "speech from a dialog system's own voice, docs/dialog.md); without it they name no files")
    ->check(CLI::ExistingDirectory)
    ->group(live);
  app
    .add_flag("--listen-remote", o.ListenRemote,
      "let --listen use addresses other machines reach (anyone who connects commands the avatar)")
    ->group(live);

  const std::string serve = "Serving browsers (the avatar stream, docs/streaming.md)";
  app
    .add_option("--serve", o.Serve,
      "serve the page, the avatar file and one WebSocket session per browser on HOST:PORT "
      "(loopback only unless --serve-remote; PORT 0 picks a free port, printed on stderr); "
      "--listen then commands every session")
    ->type_name("ADDR")
    ->group(serve);
  app
    .add_flag("--serve-remote", o.ServeRemote,
      "let --serve use addresses other machines reach; sessions then need the token")
    ->group(serve);
  app
    .add_option("--serve-token", o.ServeToken,
      "the session token browsers pass as ?token= (made up and printed when remote and not given)")
    ->group(serve);
  app
    .add_option("--serve-origin", o.ServeOrigins,
      "an origin (e.g. https://example.org) whose pages may open sessions; repeatable")
    ->group(serve);
  app
    .add_option("--serve-threads", o.ServeThreads,
      "threads running the sessions (default 0: one per core, at least 2, so that a session "
      "waiting for speech synthesis never holds up the others' frames)")
    ->check(CLI::Range(0, 256))
    ->group(serve);
  app.add_option("--serve-max-sessions", o.ServeMaxSessions, "sessions at once (default 64)")
    ->check(CLI::Range(1, 100000))
    ->group(serve);

  appkit::ParseCommandLine(app, argc, argv);
  if (!targetsFrom.empty())
  {
    TransferTargetsOntoFace(o, targetsFrom);
  }
  o.Overlay = app.count("--no-overlay") == 0;
  o.SeedSet = app.count("--seed") > 0;
  o.GltfOptimized = gltfWeights != "raw";

  const bool isLive = !o.Listen.empty() || o.CommandsStdin || !o.Serve.empty();
  if (!o.Serve.empty() &&
    (o.CommandsStdin || !o.Gltf.empty() || !o.Script.empty() || !o.Audio.empty() ||
      !o.Timings.empty() || !o.FramesDir.empty() || !o.Video.empty()))
  {
    FailUsage("--serve takes its speech as commands from the pages (or --listen) and draws nothing "
              "itself; leave out --commands-stdin, --gltf, --script, --audio, --timings, --frames "
              "and --video");
  }
  if (isLive && (!o.Pvd.empty() || !o.Png.empty() || !o.Compare.empty() || o.At >= 0.0))
  {
    FailUsage("--listen and --commands-stdin run in real time; --pvd, --png, --compare and --at "
              "render a fixed behaviour offline (--frames and --video record the live session)");
  }
  const bool performance = !o.Animation.empty() || !o.Capture.empty();
  if (performance && (isLive || !o.Say.empty() || !o.Script.empty() || !o.Gltf.empty()))
  {
    FailUsage("--animation and --capture play a recorded performance; leave out --say, --script, "
              "--gltf, --listen and --commands-stdin");
  }
  if (o.Say.empty() && o.Script.empty() && o.Audio.empty() && o.Timings.empty() && !isLive &&
    !performance)
  {
    o.Say = o.Voice.rfind("de", 0) == 0 ? "Hallo! Ich bin ein Avatar mit Morph-Targets."
                                        : "Hello! I am an avatar made of morph targets.";
  }
  if (!o.FramesDir.empty() || !o.Video.empty() || !o.Pvd.empty() || !o.Png.empty() ||
    !o.Compare.empty() || o.At >= 0.0)
  {
    o.Offscreen = true; // writing files means rendering every frame offscreen
  }
  if (o.Offscreen && o.FramesDir.empty() && o.Video.empty() && o.Pvd.empty() && o.Png.empty() &&
    o.Compare.empty() && !isLive)
  {
    FailUsage("--offscreen needs somewhere to write: --frames DIR, --video FILE, --pvd FILE or "
              "--png FILE");
  }
  if (o.At >= 0.0 && (!o.FramesDir.empty() || !o.Video.empty() || !o.Pvd.empty()))
  {
    FailUsage(
      "--at renders one frame (for --png / --compare); leave out --frames, --video and --pvd");
  }
  if (!o.Pvd.empty())
  {
    if (morphnode::text::ToLower(std::filesystem::path(o.Pvd).extension().string()) != ".pvd")
    {
      FailUsage("--pvd takes a file name ending in .pvd, not '" + o.Pvd + "'");
    }
  }
  return o;
}
} // namespace morphavatar
