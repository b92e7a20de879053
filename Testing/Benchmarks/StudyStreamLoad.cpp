// SPDX-License-Identifier: BSD-3-Clause
// The avatar stream's server under load (docs/streaming.md): one StreamServer on one thread
// (one core's worth) serves N WebSocket clients on loopback for a few seconds each; every
// client asks for a sentence once, at a time spread over the run, so about half of the
// sessions speak at any time. Reported per N: the share of frames that missed their
// deadline (a tick more than one frame late; the server skips rather than bursts), the
// frames and bytes the clients received, the says spoken (a `started` event came) and
// those the server reported as overloaded, and the CPU the server used (process CPU minus
// the clients' thread, in cores). Speech three ways: the same sentences synthesized once
// beforehand (a phrase cache); eSpeak NG for every sentence on the session's own thread
// (inline); eSpeak NG for every sentence through a SynthesisPool (--pool-workers, the
// sessions never wait). The clients run in this process on another thread (they share
// the machine). Not a test.
//
//   StudyStreamLoad [--seconds 8] [--sessions 25,50,100,200,400] [--threads 1] [--pool-workers 1]
//                   [--modes cache,inline,pool] [--continuous] [--quick] [--out FILE.md]
//   StudyStreamLoad --first-motion N
// --first-motion: instead, one session on loopback, N short says, and the time from a say
// to the first frame with an open mouth on the stream's clock, with speech started when the
// synthesis pool has it and at the next frame (in turns).
// --continuous: every session speaks all the time (a new sentence as soon as its say ended),
// instead of one sentence each.
#include "gltf/GltfScene.h"
#include "morph/OptimizerPresets.h"
#include "speech/Speech.h"
#include "speech/SynthesisPool.h"
#include "stream/StreamServer.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#include <sys/resource.h>
#include <time.h>

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
  std::atomic<uint64_t> Frames{ 0 }, Bytes{ 0 }, Connected{ 0 }, Errors{ 0 }, Started{ 0 },
    Overloaded{ 0 };
};

class Client : public std::enable_shared_from_this<Client>
{
public:
  Client(
    net::io_context& io, Counters& c, std::string port, double sayAt, int sentence, bool continuous)
    : Ws(net::make_strand(io))
    , Timer(Ws.get_executor())
    , C(c)
    , Port(std::move(port))
    , SayAt(sayAt)
    , Sentence(sentence)
    , Continuous(continuous)
  {
  }
  void Start(tcp::resolver::results_type endpoints)
  {
    beast::get_lowest_layer(this->Ws).async_connect(endpoints,
      [self = this->shared_from_this()](beast::error_code ec, tcp::endpoint)
      {
        if (ec)
        {
          ++self->C.Errors;
          return;
        }
        self->Ws.async_handshake("127.0.0.1:" + self->Port, "/stream",
          [self](beast::error_code ec2)
          {
            if (ec2)
            {
              ++self->C.Errors;
              return;
            }
            ++self->C.Connected;
            self->Read();
            self->Timer.expires_after(
              std::chrono::milliseconds(static_cast<int>(1000 * self->SayAt)));
            self->Timer.async_wait(
              [self](beast::error_code ec3)
              {
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
    net::post(this->Ws.get_executor(),
      [self = this->shared_from_this()]()
      {
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
    this->Ws.async_write(
      net::buffer(this->Out), [self = this->shared_from_this()](beast::error_code, size_t) {});
  }
  void Read()
  {
    this->Ws.async_read(this->Buffer,
      [self = this->shared_from_this()](beast::error_code ec, size_t bytes)
      {
        if (ec)
        {
          return;
        }
        self->C.Bytes += bytes;
        if (self->Ws.got_text())
        {
          const std::string line = beast::buffers_to_string(self->Buffer.data());
          if (line.find("\"started\"") != std::string::npos &&
            line.find("\"say\"") != std::string::npos)
          {
            ++self->C.Started;
          }
          if (line.find("\"overloaded\"") != std::string::npos)
          {
            ++self->C.Overloaded;
          }
          if (self->Continuous && line.find("\"ended\"") != std::string::npos &&
            line.find("\"say\"") != std::string::npos)
          {
            self->Sentence = (self->Sentence + 1) % 3;
            self->Say(); // speaks again at once
          }
        }
        else if (self->Buffer.size() > 0 &&
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
  bool Continuous;
  beast::flat_buffer Buffer;
  std::string Out;
};

struct Result
{
  size_t Sessions = 0, Connected = 0;
  uint64_t Sent = 0, Late = 0, Received = 0, Bytes = 0, Started = 0, Overloaded = 0;
  double ServerCores = 0.0;
  SynthesisPoolStats Pool;
};

double ThreadCpuSeconds()
{
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double ProcessCpuSeconds()
{
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
    1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// The server's sessions of the study: the avatar with the paper's adjusted threshold, the
/// client's seed, and the synthesis pool when there is one.
std::function<std::unique_ptr<StreamSession>(const SessionRequest&)> SessionMaker(
  const StreamAvatar& avatar, const std::vector<std::string>& visemes,
  LiveBehavior::Synthesizer synth, std::shared_ptr<SynthesisPool> pool)
{
  return [&avatar, &visemes, synth, pool](const SessionRequest& want)
  {
    StreamSettings s;
    s.Optimizer = MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.1, 0.0);
    s.Seed = want.Seed;
    auto session = std::make_unique<StreamSession>(avatar, visemes, synth, s);
    if (pool)
    {
      session->SetSynthesisPool(pool);
    }
    return session;
  };
}

Result Run(const StreamAvatar& avatar, const std::vector<std::string>& visemes,
  LiveBehavior::Synthesizer synth, size_t n, double seconds, int threads, int poolWorkers,
  bool continuous)
{
  std::shared_ptr<SynthesisPool> pool;
  if (poolWorkers > 0)
  {
    SynthesisPoolSettings ps;
    ps.Workers = poolWorkers;
    pool = std::make_shared<SynthesisPool>(ps);
  }
  const double cpuBefore = ProcessCpuSeconds();
  StreamServerSettings settings;
  settings.Threads = threads;
  settings.MaxSessions = n + 1;
  settings.MaxCommandsPerSecond = 5;
  settings.MakeSession = SessionMaker(avatar, visemes, synth, pool);
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
    const double spread = continuous ? 1.0 : seconds - 1.0;
    const double sayAt = 0.5 + spread * static_cast<double>(i) / static_cast<double>(n);
    clients.push_back(
      std::make_shared<Client>(io, counters, port, sayAt, static_cast<int>(i % 3), continuous));
    clients.back()->Start(endpoints);
  }
  double clientCpu = 0.0;
  std::thread thread(
    [&io, &clientCpu]()
    {
      io.run();
      clientCpu = ThreadCpuSeconds();
    });
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const StreamServerStats stats = server.GetStats();
  for (auto& c : clients)
  {
    c->Close();
  }
  server.Stop();
  io.stop();
  thread.join();
  const double cpu = ProcessCpuSeconds() - cpuBefore - clientCpu;
  Result r;
  r.Sessions = n;
  r.Connected = counters.Connected;
  r.Sent = stats.FramesSent;
  r.Late = stats.FramesLate;
  r.Received = counters.Frames;
  r.Bytes = counters.Bytes;
  r.Started = counters.Started;
  r.Overloaded = counters.Overloaded;
  r.ServerCores = cpu / seconds;
  if (pool)
  {
    r.Pool = pool->GetStats();
  }
  return r;
}
/// One session, one client on loopback: says a short sentence every 0.8 s (sent at a random
/// moment between two frames) and measures, on the stream's clock, from the say leaving the
/// client to the first frame with an open mouth (a mouth weight above 10/255): what a page
/// adds to it is its jitter buffer and its drawing. Per say also the server's `started`
/// latency_ms. Returns the latencies in ms (first) and latency_ms (second).
std::pair<std::vector<double>, std::vector<double>> FirstMotion(const StreamAvatar& avatar,
  const std::vector<std::string>& visemes, LiveBehavior::Synthesizer synth, int says, bool pickUp,
  std::mt19937& random)
{
  SynthesisPoolSettings ps;
  ps.Workers = 2;
  auto pool = std::make_shared<SynthesisPool>(ps);
  StreamServerSettings settings;
  settings.Threads = 1;
  settings.PickUpWhenSynthesized = pickUp;
  settings.MakeSession = SessionMaker(avatar, visemes, synth, pool);
  StreamServer server(settings);
  const std::string bound = server.Start();
  const std::string port = bound.substr(bound.rfind(':') + 1);
  net::io_context io;
  tcp::resolver resolver(io);
  websocket::stream<tcp::socket> ws(io);
  net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", port));
  ws.handshake("127.0.0.1:" + port, "/stream");
  beast::flat_buffer buffer;
  ws.read(buffer);
  const StreamHeader header = ParseHeader(beast::buffers_to_string(buffer.data()));
  buffer.consume(buffer.size());
  std::vector<bool> mouth(header.Targets.size(), false);
  for (size_t k = 0; k < header.Targets.size(); ++k)
  {
    for (const char* m : { "A", "E", "O", "S", "F", "L" })
    {
      mouth[k] = mouth[k] || header.Targets[k] == m;
    }
  }
  using Clock = std::chrono::steady_clock;
  const double rate = header.SampleRate;
  double newest = -1.0;
  Clock::time_point newestAt;
  std::vector<double> latencies, serverPart;
  std::uniform_real_distribution<double> between(0.0, 1.0 / header.FrameRate);
  const char* const texts[] = { "Hello there.", "How are you?", "Fine, thanks." };
  for (int i = 0; i < says; ++i)
  {
    // Past the previous speech, then a random moment after a frame.
    const auto until = Clock::now() + std::chrono::milliseconds(800);
    bool opened = false, started = false;
    double sentSample = 0.0;
    bool sent = false;
    while (Clock::now() < until ||
      (sent && (!opened || !started) && Clock::now() < until + std::chrono::seconds(3)))
    {
      ws.read(buffer);
      const auto at = Clock::now();
      const std::string bytes = beast::buffers_to_string(buffer.data());
      buffer.consume(buffer.size());
      if (ws.got_text())
      {
        const size_t p = bytes.find("\"latency_ms\":");
        if (sent && !started && bytes.find("\"started\"") != std::string::npos &&
          p != std::string::npos)
        {
          serverPart.push_back(std::atof(bytes.c_str() + p + 13));
          started = true;
        }
        continue;
      }
      if (bytes.empty() || bytes[0] != 1)
      {
        continue;
      }
      const ServerMessage message =
        DecodeServerMessage(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), &header);
      const Frame& f = std::get<Frame>(message);
      newest = f.Sample;
      newestAt = at;
      if (sent && !opened && f.Sample > sentSample)
      {
        for (const auto& [k, w] : f.Targets)
        {
          if (k < mouth.size() && mouth[k] && w > 10)
          {
            opened = true;
          }
        }
        if (opened)
        {
          latencies.push_back(1000.0 * (f.Sample - sentSample) / rate);
        }
      }
      if (!sent && i >= 0 && Clock::now() + std::chrono::milliseconds(400) > until)
      {
        std::this_thread::sleep_for(std::chrono::duration<double>(between(random)));
        const std::string say = std::string("{\"cmd\":\"say\",\"text\":\"") + texts[i % 3] + "\"}";
        sentSample = newest + rate * std::chrono::duration<double>(Clock::now() - newestAt).count();
        ws.text(true);
        ws.write(net::buffer(say));
        ws.binary(true);
        sent = true;
      }
    }
  }
  beast::error_code ignored;
  ws.next_layer().close(ignored);
  server.Stop();
  return { latencies, serverPart };
}

double Quantile(std::vector<double> v, double q)
{
  if (v.empty())
  {
    return std::nan("");
  }
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}
} // namespace

int main(int argc, char* argv[])
{
  double seconds = 8.0;
  int threads = 1;
  int poolWorkers = 1;
  bool continuous = false;
  std::vector<std::string> modes = { "cache", "inline", "pool" };
  std::vector<size_t> counts = { 25, 50, 100, 200, 400 };
  std::string out;
  int firstMotion = 0;
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
    else if (a == "--pool-workers" && i + 1 < argc)
    {
      poolWorkers = std::max(1, std::atoi(argv[++i]));
    }
    else if (a == "--modes" && i + 1 < argc)
    {
      modes.clear();
      std::stringstream s(argv[++i]);
      std::string item;
      while (std::getline(s, item, ','))
      {
        modes.push_back(item);
      }
    }
    else if (a == "--continuous")
    {
      continuous = true;
    }
    else if (a == "--first-motion" && i + 1 < argc)
    {
      firstMotion = std::max(1, std::atoi(argv[++i]));
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
      std::cerr << "usage: StudyStreamLoad [--seconds 8] [--sessions 25,50,...] [--threads 1] "
                   "[--pool-workers 1] "
                   "[--modes cache,inline,pool] [--quick] [--out FILE.md]\n";
      return 2;
    }
  }
  try
  {
    SpeechOptions speech;
    speech.Visemes = VisemeSet::Paper6;
    const std::vector<std::string> visemes = SelectVisemeMap(speech).GetVisemes();
    const GltfScene head =
      LoadGltfScene(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb");
    const StreamAvatar avatar(head, LiveBehavior(visemes).GetChannelNames());
    // The phrase cache: each chunk synthesized once (the chunks a Say splits a text into).
    auto cache = std::make_shared<std::map<std::string, Utterance>>();
    auto mutex = std::make_shared<std::mutex>();
    LiveBehavior::Synthesizer cached = [speech, cache, mutex](const std::string& text)
    {
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
    LiveBehavior::Synthesizer synthesize = [speech](const std::string& text)
    { return SpeakText(text, speech); };
    if (firstMotion > 0)
    {
      // Speech picked up when the pool has it, against the next frame, in blocks of 5 says
      // taking turns (the machine's load drifts alike for both).
      std::mt19937 random(7);
      std::vector<double> motion[2], started[2];
      for (int done = 0; done < firstMotion; done += 5)
      {
        for (int mode = 0; mode < 2; ++mode)
        {
          auto r = FirstMotion(
            avatar, visemes, synthesize, std::min(5, firstMotion - done), mode == 0, random);
          motion[mode].insert(motion[mode].end(), r.first.begin(), r.first.end());
          started[mode].insert(started[mode].end(), r.second.begin(), r.second.end());
          std::cerr << "." << std::flush;
        }
      }
      std::cerr << "\n";
      std::ostringstream md;
      md << "| speech starts | says | say to the first open-mouth frame, stream clock: median / "
            "p95 / max (ms) | started latency_ms: median / p95 (ms) |\n|---|---:|---|---|\n";
      md << std::fixed;
      md.precision(0);
      for (int mode = 0; mode < 2; ++mode)
      {
        md << "| " << (mode == 0 ? "when the pool has it (PickUp)" : "at the next frame") << " | "
           << motion[mode].size() << " | " << Quantile(motion[mode], 0.5) << " / "
           << Quantile(motion[mode], 0.95) << " / " << Quantile(motion[mode], 1.0) << " | "
           << Quantile(started[mode], 0.5) << " / " << Quantile(started[mode], 0.95) << " |\n";
      }
      std::cout << md.str();
      if (!out.empty())
      {
        std::ofstream(out) << md.str();
      }
      return 0;
    }
    std::ostringstream md;
    md << "Server threads: " << threads << ", synthesis pool workers (pool rows): " << poolWorkers
       << ", " << seconds << " s per row, "
       << (continuous ? "every session speaks all the time (a new sentence when its say ended)"
                      : "every session says one sentence")
       << "\n\n";
    md << "| speech | sessions | late (missed deadline) | says started / sessions | overloaded | "
          "server CPU (cores) | sessions per core | "
          "synthesis wait mean / max (ms) | frames received | received kB/s per session |\n"
       << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const std::string& mode : modes)
    {
      if (mode != "cache" && mode != "inline" && mode != "pool")
      {
        std::cerr << "StudyStreamLoad: --modes takes cache, inline, pool\n";
        return 2;
      }
      for (size_t n : counts)
      {
        const Result r = Run(avatar, visemes, mode == "cache" ? cached : synthesize, n, seconds,
          threads, mode == "pool" ? poolWorkers : 0, continuous);
        const char* name = mode == "cache" ? "phrase cache"
          : mode == "inline"               ? "eSpeak NG on the session's thread"
                                           : "eSpeak NG through the pool";
        md << "| " << name << " | " << n << " | " << r.Late << " (" << std::fixed;
        md.precision(1);
        md << 100.0 * r.Late / std::max<uint64_t>(1, r.Sent + r.Late) << " %) | " << r.Started
           << " / " << n << " | " << r.Overloaded << " | ";
        md.precision(2);
        md << r.ServerCores << " | ";
        md.precision(0);
        md << n / std::max(0.01, r.ServerCores) << " | ";
        if (mode == "pool")
        {
          md << 1000.0 * r.Pool.MeanWaitSeconds << " / " << 1000.0 * r.Pool.MaxWaitSeconds;
        }
        else
        {
          md << "-";
        }
        md << " | " << r.Received << " | ";
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
