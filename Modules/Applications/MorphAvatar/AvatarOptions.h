// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarOptions.h
/// @brief MorphAvatar's command line (docs/avatar.md lists the options).

#include "morph/OptimizerPresets.h"

#include <string>
#include <vector>

namespace morphavatar
{
struct Options
{
  std::string Face; // empty: the project's default face
  std::string Rig;
  std::string Say;
  std::string Voice = "en";
  std::string Visemes; // empty: chosen from the face (oculus15 when it has its own, else paper6)
  std::string Gaze = "auto";    // eyes by: auto, bones (eye joints), targets (eyeLook*/eye nodes)
  std::string Framing = "face"; // face, bust, body
  std::string Pose = "relaxed"; // a skinned body's arms: relaxed (down) or stored
  std::string Script;
  std::string Audio;    // a recording to speak (WAV, FLAC, OGG)
  std::string Text;     // its transcript
  std::string TextFile; // its transcript, from a file
  std::string Timings;  // a timing file (of the recording, or alone: speech without sound)
  std::string TimingsFormat = "auto"; // its format where the extension does not tell
  std::string Animation;  // play the face file's own glTF animation (a name or an index)
  std::string Capture;    // play a Live Link Face take (CSV)
  double Duration = -1.0; // < 0: the script's, else automatic
  double Fps = -1.0;      // < 0: the script's, else 30
  int Width = 640;
  int Height = 640;
  morphnode::OptimizerPreset Method = morphnode::OptimizerPreset::Adjusted;
  double Threshold = 0.1;
  double MaxError = -1.0; // < 0: 0.5 % of the face's diagonal
  double Hysteresis = 0.0;
  double FrameBudget = 0.0;   // ms for the morph; 0: off (AvatarFrameBudget.h)
  std::string FrameBudgetLog; // CSV of every frame's choice
  std::string Profile;        // a device profile (morphnode::DeviceProfiles); empty: none
  bool Lod = false;           // target level of detail from the camera (docs/lod.md)
  bool SeedSet = false;
  unsigned long long Seed = 1;
  bool Offscreen = false;
  std::string FramesDir;
  std::string Video;
  bool CpuSkin = false;      // skinned parts re-skinned on the CPU, not in the vertex shader
  std::string Pvd;           // a ParaView time series: FILE.pvd + FILE/face_*.vtp
  std::string Gltf;          // the performance as glTF: FILE.glb/.gltf and FILE.wav
  bool GltfOptimized = true; // --gltf-weights optimized (else raw)
  std::string Png;
  std::string Compare;
  double CompareThreshold = 10.0;
  double At = -1.0;
  bool Overlay = true;
  bool Quiet = false;
  double ExitAfter = -1.0;         // interactive: close after this many seconds (smoke tests)
  std::string Keys;                // interactive: keys pressed at the start (smoke tests)
  std::vector<std::string> Listen; // live: command addresses (AvatarLive.h)
  bool CommandsStdin = false;      // live: commands on stdin, events on stdout
  bool ListenRemote = false;       // live: allow non-loopback --listen addresses
  std::string SpeechDir;           // live: the folder `say` may name recordings and timings in
  bool Mute = false;               // window and live: no sound (the steady clock)
  std::string Serve;               // serve: the page and the stream on HOST:PORT (AvatarServe.h)
  bool ServeRemote = false;        // serve: allow non-loopback addresses (needs a token)
  std::string ServeToken;          // serve: the session token (made up when remote and empty)
  std::vector<std::string> ServeOrigins; // serve: origins allowed besides the server's own
  int ServeThreads = 0;      // serve: threads running the sessions (0: cores, at least 2)
  int ServeMaxSessions = 64; // serve: sessions at once
};

/// Reads the command line; --help and usage errors exit (0 and 2).
Options ParseOptions(int argc, char* argv[]);

/// A usage error found later (e.g. an unknown viseme set): prints it and exits with 2.
[[noreturn]] void FailUsage(const std::string& message);
} // namespace morphavatar
