// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar --serve (AvatarServe.h).
#include "AvatarServe.h"

#include "AvatarNaming.h"

#include "DataPaths.h"

#include "base/Error.h"
#include "base/Text.h"
#include "budget/DeviceProfile.h"
#include "dialog/DialogServer.h"
#include "gltf/GltfScene.h"
#include "morph/OptimizerPresets.h"
#include "speech/Speech.h"
#include "speech/SpeechSynthesizer.h"
#include "speech/SynthesisPool.h"
#include "stream/StreamAvatar.h"
#include "stream/StreamSession.h"
#ifdef MORPHNODE_HAVE_STREAM_SERVER
#include "stream/StreamServer.h"
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

namespace morphavatar
{
namespace stream = morphnode::stream;
namespace dialog = morphnode::dialog;

namespace
{
std::atomic<bool> Interrupted{ false };
void OnSignal(int)
{
  Interrupted = true;
}

/// 128 random bits as hex, for a remote session token.
std::string MakeToken()
{
  std::random_device device;
  std::ostringstream s;
  for (int i = 0; i < 4; ++i)
  {
    s << std::hex << static_cast<uint32_t>(device());
  }
  return s.str();
}

/// Where three.js is: MORPHNODE_THREE_DIR in the environment, else the npm tools folder
/// CMake configured (.ci/npm-tools/node_modules/three).
std::string ThreeDir()
{
  const char* env = std::getenv("MORPHNODE_THREE_DIR");
  return env && *env ? std::string(env) : std::string(MORPHNODE_THREE_DIR);
}
} // namespace

int RunServe(const Options& o)
{
#ifndef MORPHNODE_HAVE_STREAM_SERVER
  (void)o;
  std::cerr
    << "MorphAvatar: this build has no stream server (Boost.Beast, libboost-dev, was missing)\n";
  return 1;
#else
  std::signal(SIGPIPE, SIG_IGN);
  try
  {
    const std::string faceFile = o.Face.empty() ? morphnode::appkit::DefaultFace() : o.Face;
    const morphnode::GltfScene face = morphnode::LoadGltfScene(faceFile);
    morphnode::SpeechOptions speech;
    speech.Voice = o.Voice;
    // The rig and viseme set chosen from the face's names as the window chooses them
    // (AvatarNaming.h), unless --rig / --visemes.
    Options chosen = o;
    const std::string rigJson = ChooseServeNaming(face, faceFile, chosen);
    if (chosen.Visemes == "paper6")
    {
      speech.Visemes = morphnode::VisemeSet::Paper6;
    }
    else if (chosen.Visemes == "oculus15")
    {
      speech.Visemes = morphnode::VisemeSet::Oculus15;
    }
    else if (chosen.Visemes == "german16")
    {
      speech.Visemes = morphnode::VisemeSet::German16;
    }
    else
    {
      FailUsage("--visemes expects paper6, oculus15 or german16; got '" + chosen.Visemes + "'");
    }
    const std::vector<std::string> visemes = morphnode::SelectVisemeMap(speech).GetVisemes();
    const std::vector<std::string> channels = morphnode::LiveBehavior(visemes).GetChannelNames();
    std::unique_ptr<morphnode::Rig> rig;
    if (!rigJson.empty())
    {
      rig = std::make_unique<morphnode::Rig>(
        morphnode::Rig::LoadString(rigJson, o.Rig.empty() ? std::string("the chosen rig") : o.Rig));
    }
    const auto started = std::chrono::steady_clock::now();
    auto avatar = std::make_shared<const stream::StreamAvatar>(face, channels, rig.get());
    // The optimizer: the method and threshold of the command line; the error bound by
    // default 0.5 % of the face's diagonal, as in the window.
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
    const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
      (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double maxError = o.MaxError >= 0.0 ? o.MaxError : 0.005 * diagonal;
    stream::StreamSettings base;
    base.Optimizer = morphnode::MakeOptimizerSettings(o.Method, o.Threshold, maxError);
    base.Optimizer.Hysteresis = o.Hysteresis;
    base.FrameRate = o.Fps > 0.0 ? o.Fps : 30.0;
    base.Seed = o.Seed;

    stream::StreamServerSettings settings;
    settings.Address = o.Serve;
    settings.AllowRemote = o.ServeRemote;
    settings.Token = o.ServeToken;
    if (o.ServeRemote && settings.Token.empty())
    {
      settings.Token = MakeToken();
    }
    settings.AllowedOrigins = o.ServeOrigins;
    settings.Threads = o.ServeThreads > 0
      ? o.ServeThreads
      : static_cast<int>(std::max(2u, std::thread::hardware_concurrency()));
    settings.MaxSessions = static_cast<size_t>(o.ServeMaxSessions);
    const std::string web = morphnode::appkit::DataPath("web");
    for (const char* file : { "index.html", "avatar-stream.js", "stream-worklet.js",
           "opus-worker.js", "stream-socket.js" })
    {
      const std::string path = web + "/" + file;
      stream::StaticFile f;
      f.Body = morphnode::text::ReadFile(path, "page file");
      f.ContentType = std::string(file).find(".html") != std::string::npos
        ? "text/html; charset=utf-8"
        : "text/javascript";
      settings.Files[std::string("/") + (std::string(file) == "index.html" ? "" : file)] = f;
    }
    settings.Files["/avatar.glb"] = { "model/gltf-binary",
      std::string(avatar->GetFile().begin(), avatar->GetFile().end()) };
    // The avatar prepared for each device profile a page may ask for (?device=phone): the
    // profile's pixel bound prunes targets it would not show, and its finest level of detail
    // reduces the mesh (phone: the level-of-detail ladder's level 1, when built in).
    std::map<std::string, std::shared_ptr<const stream::StreamAvatar>> devices;
    for (const morphnode::DeviceProfile& profile : morphnode::DeviceProfiles())
    {
      auto prepared = std::make_shared<const stream::StreamAvatar>(
        face, channels, rig.get(), stream::DeviceAvatarOptions(profile));
      settings.Files["/avatar-" + profile.Name + ".glb"] = { "model/gltf-binary",
        std::string(prepared->GetFile().begin(), prepared->GetFile().end()) };
      if (!o.Quiet)
      {
        std::cerr << "MorphAvatar: for a " << profile.Name << ": "
                  << prepared->GetTargetNames().size() << " targets ("
                  << prepared->GetPrunedTargets().size() << " below " << profile.TargetPixelBound
                  << " px left out), " << prepared->GetNumberOfTriangles() << " triangles (level "
                  << prepared->GetLevel() << "), " << prepared->GetFile().size() / 1024 << " KiB"
                  << std::endl;
      }
      devices[profile.Name] = std::move(prepared);
    }
    settings.Folders["/three/"] = ThreeDir();
    // Speech is synthesized off the sessions' threads, by a pool all sessions share: a say
    // never holds up a session's frames (eSpeak NG itself is one engine per process, so
    // two workers: one in eSpeak, one estimating pitch and building the viseme track).
    morphnode::SynthesisPoolSettings poolSettings;
    poolSettings.Workers = 2;
    auto pool = std::make_shared<morphnode::SynthesisPool>(poolSettings);
    // A say's `voice`: one of eSpeak NG's voices, checked against its list (not by
    // synthesizing, which would block the session).
    auto voices =
      std::make_shared<const std::vector<std::string>>(morphnode::SpeechSynthesizer::ListVoices());
    stream::StreamSession::VoiceSynthesizers makeVoice =
      [speech, voices](const std::string& voice) -> morphnode::LiveBehavior::Synthesizer
    {
      if (std::find(voices->begin(), voices->end(), voice) == voices->end())
      {
        throw morphnode::InputError(
          "unknown voice '" + voice + "' (eSpeak NG's voices: espeak-ng --voices)");
      }
      morphnode::SpeechOptions options = speech;
      options.Voice = voice;
      return [options](const std::string& text) { return morphnode::SpeakText(text, options); };
    };
    settings.MakeSession = [avatar, devices, visemes, speech, base, pool, makeVoice](
                             const stream::SessionRequest& want)
    {
      stream::StreamSettings s = base;
      s.Codec = want.Codec;
      s.Seed = want.Seed;
      std::shared_ptr<const stream::StreamAvatar> face = avatar;
      std::string url;
      if (!want.Device.empty())
      {
        const morphnode::DeviceProfile& profile =
          morphnode::FindDeviceProfile(want.Device); // InputError: refused
        face = devices.at(profile.Name);
        url = "/avatar-" + profile.Name + ".glb";
      }
      morphnode::LiveBehavior::Synthesizer synth = [speech](const std::string& text)
      { return morphnode::SpeakText(text, speech); };
      auto session = std::make_unique<stream::StreamSession>(*face, visemes, synth, s);
      session->SetAvatarUrl(url);
      session->SetSynthesisPool(pool);
      session->SetVoiceSynthesizers(makeVoice);
      return session;
    };
    // The command socket's events come from the sessions' threads: queued here, sent by the
    // loop below (DialogServer is the loop's).
    auto eventMutex = std::make_shared<std::mutex>();
    auto events = std::make_shared<std::vector<std::pair<int, dialog::Event>>>();
    settings.CommandEvents = [eventMutex, events](int client, const dialog::Event& e)
    {
      std::lock_guard<std::mutex> lock(*eventMutex);
      if (events->size() < 100000) // a loop that stopped draining must not grow this for ever
      {
        events->emplace_back(client, e);
      }
    };
    stream::StreamServer server(settings);
    const std::string bound = server.Start();
    const double prepare =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::cerr << "MorphAvatar: serving " << faceFile << " (" << avatar->GetTargetNames().size()
              << " of " << avatar->GetNumberOfFaceTargets() << " targets driven, avatar file "
              << avatar->GetFile().size() / 1024 << " KiB, prepared in " << prepare
              << " s) on http://" << bound << "/"
              << (settings.Token.empty() ? "" : "?token=" + settings.Token) << std::endl;

    // The command socket: a command goes to the session its `session` names, or to every
    // session; its events (accepted, started, ended, error, each naming the session) come
    // back to the client that sent it.
    dialog::DialogServer::Settings commandSettings;
    commandSettings.AllowRemote = o.ListenRemote;
    dialog::DialogServer commands(commandSettings);
    for (const std::string& address : o.Listen)
    {
      std::cerr << "MorphAvatar: listening on " << commands.Listen(address) << std::endl;
    }
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    const auto start = std::chrono::steady_clock::now();
    while (!Interrupted)
    {
      const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (o.ExitAfter >= 0.0 && t >= o.ExitAfter)
      {
        break;
      }
      bool quit = false;
      for (const auto& in : commands.Poll(o.Listen.empty() ? 0 : 10))
      {
        if (std::holds_alternative<dialog::QuitCommand>(in.Cmd.Body))
        {
          quit = true;
          continue;
        }
        if (server.Send(in.Cmd, in.Client) == 0)
        {
          dialog::Event e = dialog::MakeError(dialog::reason::Rejected,
            in.Cmd.Session.empty() ? "no browser session is open"
                                   : "no open session '" + in.Cmd.Session + "'",
            in.Cmd.Id, dialog::CommandName(in.Cmd.Body));
          e.Time = t;
          e.Session = in.Cmd.Session;
          commands.Send(in.Client, e);
        }
      }
      std::vector<std::pair<int, dialog::Event>> ready;
      {
        std::lock_guard<std::mutex> lock(*eventMutex);
        ready.swap(*events);
      }
      for (const auto& [client, e] : ready)
      {
        commands.Send(client, e);
      }
      if (quit)
      {
        break;
      }
      if (o.Listen.empty())
      {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    const stream::StreamServerStats stats = server.GetStats();
    server.Stop();
    if (!o.Quiet)
    {
      std::cerr << "MorphAvatar: served " << stats.SessionsStarted << " session(s), "
                << stats.FramesSent << " frames (" << stats.FramesLate << " late), "
                << stats.BytesSent << " bytes, " << stats.ClientErrors << " client error(s), "
                << stats.SessionsRefused << " refused\n";
    }
    return 0;
  }
  catch (const morphnode::InputError& e)
  {
    std::cerr << "MorphAvatar: " << e.what() << "\n";
    return 1;
  }
#endif
}
} // namespace morphavatar
