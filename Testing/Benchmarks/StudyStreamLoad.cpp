// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream's server under load (docs/streaming.md): one StreamServer on one thread
// (one core's worth) serves N WebSocket clients on loopback for a few seconds each; every
// client asks for a sentence once, at a time spread over the run, so about half of the
// sessions speak at any time. Reported per N: the share of frames that missed their
// deadline (a tick more than one frame late; the server skips rather than bursts), the
// frames and bytes the clients received. With synthesis: eSpeak NG for every sentence;
// without: the same sentences synthesized once beforehand (a phrase cache). The clients run
// in this process on another thread (they share the machine). Not a test.
//
//   StudyStreamLoad [--seconds 8] [--sessions 25,50,100,200,400] [--threads 1] [--quick] [--out FILE.md]
#include "gltf/GltfScene.h"
#include "morph/OptimizerPresets.h"
#include "speech/Speech.h"
#include "stream/StreamServer.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

using namespace morphnode;
using namespace morphnode::stream;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace
{
const char* const Sentences[] = {
  "Hello! I am an avatar made of morph targets, and your browser draws my face.",
  "The server decides which targets matter in every frame, and sends only those.",
  "A few bytes per frame are enough to make me talk, blink and look around.",
};

struct Counters
{
  std::atomic<uint64_t> Frames{ 0 }, Bytes{ 0 }, Connected{ 0 }, Errors{ 0 };
};

class Client : public std::enable_shared_from_this<Client>
{
public:
  Client(net::io_context& io, Counters& c, std::string port, double sayAt, int sentence)
    : Ws(net::make_strand(io))
    , Timer(Ws.get_executor())
    , C(c)
    , Port(std::move(port))
    , SayAt(sayAt)
    , Sentence(sentence)
  {
  }
  void Start(tcp::resolver::results_type endpoints)
  {
    beast::get_lowest_layer(this->Ws).async_connect(endpoints,
      [self = this->shared_from_this()](beast::error_code ec, tcp::endpoint) {
        if (ec)
        {
          ++self->C.Errors;
          return;
        }
        self->Ws.async_handshake("127.0.0.1:" + self->Port, "/stream", [self](beast::error_code ec2) {
          if (ec2)
          {
            ++self->C.Errors;
            return;
          }
          ++self->C.Connected;
          self->Read();
          self->Timer.expires_after(std::chrono::milliseconds(static_cast<int>(1000 * self->SayAt)));
          self->Timer.async_wait([self](beast::error_code ec3) {
            if (!ec3)
            {
              self->Say();
            }
          });
        });
      });
  }
  void Close()
  {
    net::post(this->Ws.get_executor(), [self = this->shared_from_this()]() {
      self->Timer.cancel();
      beast::error_code ignored;
      beast::get_lowest_layer(self->Ws).socket().close(ignored);
    });
  }

private:
  void Say()
  {
    this->Out = std::string("{\"cmd\":\"say\",\"text\":\"") + Sentences[this->Sentence] + "\"}";
    this->Ws.text(true);
    this->Ws.async_write(net::buffer(this->Out), [self = this->shared_from_this()](beast::error_code, size_t) {});
  }
  void Read()
  {
    this->Ws.async_read(this->Buffer, [self = this->shared_from_this()](beast::error_code ec, size_t bytes) {
      if (ec)
      {
        return;
      }
      self->C.Bytes += bytes;
      if (!self->Ws.got_text() && self->Buffer.size() > 0 &&
        static_cast<const uint8_t*>(self->Buffer.data().data())[0] == 1)
      {
        ++self->C.Frames;
      }
      self->Buffer.consume(self->Buffer.size());
      self->Read();
    });
  }
  websocket::stream<beast::tcp_stream> Ws;
  net::steady_timer Timer;
  Counters& C;
  std::string Port;
  double SayAt;
  int Sentence;
  beast::flat_buffer Buffer;
  std::string Out;
};

struct Result
{
  size_t Sessions = 0, Connected = 0;
  uint64_t Sent = 0, Late = 0, Received = 0, Bytes = 0;
};

Result Run(const StreamAvatar& avatar, const std::vector<std::string>& visemes, LiveBehavior::Synthesizer synth,
  size_t n, double seconds, int threads)
{
  StreamServerSettings settings;
  settings.Threads = threads;
  settings.MaxSessions = n + 1;
  settings.MaxCommandsPerSecond = 5;
  settings.MakeSession = [&avatar, &visemes, synth](const SessionRequest& want) {
    StreamSettings s;
    s.Optimizer = MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.1, 0.0);
    s.Seed = want.Seed;
    return std::make_unique<StreamSession>(avatar, visemes, synth, s);
  };
  StreamServer server(settings);
  const std::string bound = server.Start();
  const std::string port = bound.substr(bound.rfind(':') + 1);
  net::io_context io;
  Counters counters;
  std::vector<std::shared_ptr<Client>> clients;
  tcp::resolver resolver(io);
  const auto endpoints = resolver.resolve("127.0.0.1", port);
  for (size_t i = 0; i < n; ++i)
  {
    const double sayAt = 0.5 + (seconds - 1.0) * static_cast<double>(i) / static_cast<double>(n);
    clients.push_back(std::make_shared<Client>(io, counters, port, sayAt, static_cast<int>(i % 3)));
    clients.back()->Start(endpoints);
  }
  std::thread thread([&io]() { io.run(); });
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const StreamServerStats stats = server.GetStats();
  for (auto& c : clients)
  {
    c->Close();
  }
  server.Stop();
  io.stop();
  thread.join();
  Result r;
  r.Sessions = n;
  r.Connected = counters.Connected;
  r.Sent = stats.FramesSent;
  r.Late = stats.FramesLate;
  r.Received = counters.Frames;
  r.Bytes = counters.Bytes;
  return r;
}
} // namespace

int main(int argc, char* argv[])
{
  double seconds = 8.0;
  int threads = 1;
  std::vector<size_t> counts = { 25, 50, 100, 200, 400 };
  std::string out;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc)
    {
      seconds = std::atof(argv[++i]);
    }
    else if (a == "--sessions" && i + 1 < argc)
    {
      counts.clear();
      std::stringstream s(argv[++i]);
      std::string item;
      while (std::getline(s, item, ','))
      {
        counts.push_back(std::stoul(item));
      }
    }
    else if (a == "--threads" && i + 1 < argc)
    {
      threads = std::atoi(argv[++i]);
    }
    else if (a == "--quick")
    {
      seconds = 2.0;
      counts = { 4 };
    }
    else if (a == "--out" && i + 1 < argc)
    {
      out = argv[++i];
    }
    else
    {
      std::cerr << "usage: StudyStreamLoad [--seconds 8] [--sessions 25,50,...] [--threads 1] [--quick] [--out FILE.md]\n";
      return 2;
    }
  }
  try
  {
    SpeechOptions speech;
    speech.Visemes = VisemeSet::Paper6;
    const std::vector<std::string> visemes = SelectVisemeMap(speech).GetVisemes();
    const GltfScene head = LoadGltfScene(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb");
    const StreamAvatar avatar(head, LiveBehavior(visemes).GetChannelNames());
    // The phrase cache: each chunk synthesized once (the chunks a Say splits a text into).
    auto cache = std::make_shared<std::map<std::string, Utterance>>();
    auto mutex = std::make_shared<std::mutex>();
    LiveBehavior::Synthesizer cached = [speech, cache, mutex](const std::string& text) {
      std::lock_guard<std::mutex> lock(*mutex);
      auto it = cache->find(text);
      if (it == cache->end())
      {
        it = cache->emplace(text, SpeakText(text, speech)).first;
      }
      return it->second;
    };
    for (const char* s : Sentences)
    {
      for (const std::string& chunk : SplitSpeechChunks(s))
      {
        cached(chunk);
      }
    }
    LiveBehavior::Synthesizer synthesize = [speech](const std::string& text) { return SpeakText(text, speech); };
    std::ostringstream md;
    md << "Server threads: " << threads << "\n\n";
    md << "| speech | sessions | connected | frames sent | late (missed deadline) | frames received | received kB/s per session |\n"
       << "|---|---:|---:|---:|---:|---:|---:|\n";
    for (int mode = 0; mode < 2; ++mode)
    {
      for (size_t n : counts)
      {
        const Result r = Run(avatar, visemes, mode == 0 ? cached : synthesize, n, seconds, threads);
        md << "| " << (mode == 0 ? "phrase cache" : "eSpeak NG per sentence") << " | " << n << " | " << r.Connected
           << " | " << r.Sent << " | " << r.Late << " (" << std::fixed;
        md.precision(1);
        md << 100.0 * r.Late / std::max<uint64_t>(1, r.Sent + r.Late) << " %) | " << r.Received << " | ";
        md.precision(1);
        md << r.Bytes / 1024.0 / seconds / std::max<size_t>(1, r.Connected) << " |\n";
        md.unsetf(std::ios::fixed);
        std::cerr << "." << std::flush;
      }
    }
    std::cerr << "\n";
    std::cout << md.str();
    if (!out.empty())
    {
      std::ofstream(out) << md.str();
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "StudyStreamLoad: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
