// SPDX-License-Identifier: BSD-3-Clause
// The stream server's command routing (MorphAvatar --serve --listen): a command naming a
// session goes to that session only and its events (accepted, started, ended) come back to
// the client that sent it, naming the session; a command naming no session goes to every
// session; an unknown session reaches none; a page cannot address another session.
// Two WebSocket clients (Boost.Beast) on loopback; speech from a stand-in synthesizer.
#include "stream/StreamServer.h"

#include "gltf/GltfScene.h"
#include "speech/Speech.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

using namespace morphnode;
using namespace morphnode::stream;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace
{
/// A page: connects, reads the header and then counts what comes (on its own thread).
class Page
{
public:
  explicit Page(const std::string& port)
    : Ws(Io)
  {
    tcp::resolver resolver(this->Io);
    beast::get_lowest_layer(this->Ws).connect(resolver.resolve("127.0.0.1", port));
    this->Ws.handshake("127.0.0.1:" + port, "/stream");
    beast::flat_buffer b;
    this->Ws.read(b);
    this->Header = nlohmann::json::parse(beast::buffers_to_string(b.data()));
    this->Reader = std::thread(
      [this]()
      {
        for (;;)
        {
          beast::flat_buffer m;
          beast::error_code ec;
          this->Ws.read(m, ec);
          if (ec)
          {
            return;
          }
          std::lock_guard<std::mutex> lock(this->M);
          if (this->Ws.got_text())
          {
            this->Texts.push_back(beast::buffers_to_string(m.data()));
          }
          else if (m.size() > 0 && static_cast<const uint8_t*>(m.data().data())[0] == 2)
          {
            ++this->AudioChunks;
          }
        }
      });
  }
  ~Page()
  {
    beast::error_code ec;
    beast::get_lowest_layer(this->Ws).socket().shutdown(tcp::socket::shutdown_both, ec);
    beast::get_lowest_layer(this->Ws).socket().close(ec);
    this->Reader.join();
  }
  std::string Id() const { return this->Header.at("session").get<std::string>(); }
  size_t Audio()
  {
    std::lock_guard<std::mutex> lock(this->M);
    return this->AudioChunks;
  }
  std::vector<std::string> Events()
  {
    std::lock_guard<std::mutex> lock(this->M);
    return this->Texts;
  }

private:
  net::io_context Io;
  websocket::stream<beast::tcp_stream> Ws;
  nlohmann::json Header;
  std::thread Reader;
  std::mutex M;
  std::vector<std::string> Texts;
  size_t AudioChunks = 0;
};

/// A third page that sends `message` and returns the first text reply after its header.
std::string FirstReply(const std::string& port, const std::string& message)
{
  net::io_context io;
  websocket::stream<beast::tcp_stream> ws(io);
  tcp::resolver resolver(io);
  beast::get_lowest_layer(ws).connect(resolver.resolve("127.0.0.1", port));
  ws.handshake("127.0.0.1:" + port, "/stream");
  beast::flat_buffer header;
  ws.read(header);
  ws.text(true);
  ws.write(net::buffer(message));
  for (int i = 0; i < 1000; ++i)
  {
    beast::flat_buffer m;
    ws.read(m);
    if (ws.got_text())
    {
      return beast::buffers_to_string(m.data());
    }
  }
  return std::string();
}

Utterance StandIn(const std::string&)
{
  Utterance u;
  u.Visemes = WeightTrack({ "A" }, 100.0);
  for (int f = 0; f <= 30; ++f)
  {
    u.Visemes.AppendFrame(std::vector<double>{ 0.8 });
  }
  u.Duration = 0.3;
  u.SampleRate = 24000;
  u.Audio.assign(7200, 1000);
  return u;
}

dialog::Command Say(const std::string& id, const std::string& session)
{
  dialog::Command c;
  c.Id = "\"" + id + "\"";
  c.Session = session;
  dialog::SayCommand say;
  say.Text = "Hello.";
  c.Body = say;
  return c;
}

/// Waits (bounded) until `done` holds.
template <typename F>
bool WaitFor(F done, double seconds = 10.0)
{
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done())
  {
    if (std::chrono::steady_clock::now() > end)
    {
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}
} // namespace

TEST(StreamServer, CommandsReachTheirSessionAndTheirEventsComeBack)
{
  SpeechOptions speech;
  speech.Visemes = VisemeSet::Paper6;
  const std::vector<std::string> visemes = SelectVisemeMap(speech).GetVisemes();
  const GltfScene head =
    LoadGltfScene(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb");
  const StreamAvatar avatar(head, LiveBehavior(visemes).GetChannelNames());
  auto pool = std::make_shared<SynthesisPool>();
  std::mutex m;
  std::vector<std::pair<int, dialog::Event>> events;
  StreamServerSettings settings;
  settings.Threads = 2;
  settings.MakeSession = [&](const SessionRequest&)
  {
    auto s = std::make_unique<StreamSession>(avatar, visemes, StandIn, StreamSettings());
    s->SetSynthesisPool(pool);
    return s;
  };
  settings.CommandEvents = [&](int client, const dialog::Event& e)
  {
    std::lock_guard<std::mutex> lock(m);
    events.emplace_back(client, e);
  };
  StreamServer server(settings);
  const std::string bound = server.Start();
  const std::string port = bound.substr(bound.rfind(':') + 1);
  Page one(port), two(port);
  ASSERT_NE(one.Id(), two.Id());
  ASSERT_TRUE(WaitFor([&] { return server.GetSessionIds().size() == 2; }));

  // Addressed to the first session: only it speaks; client 7 hears accepted, started,
  // ended, each naming the session; the pages hear none of these events.
  EXPECT_EQ(server.Send(Say("a", one.Id()), 7), 1u);
  const auto saw = [&](const std::string& id, dialog::EventKind kind)
  {
    std::lock_guard<std::mutex> lock(m);
    return std::count_if(events.begin(), events.end(),
      [&](const auto& e) { return e.second.Id == "\"" + id + "\"" && e.second.Kind == kind; });
  };
  ASSERT_TRUE(WaitFor([&] { return saw("a", dialog::EventKind::Ended) == 1; }));
  {
    std::lock_guard<std::mutex> lock(m);
    ASSERT_EQ(events.size(), 3u);
    EXPECT_EQ(events[0].second.Kind, dialog::EventKind::Accepted);
    EXPECT_EQ(events[1].second.Kind, dialog::EventKind::Started);
    for (const auto& e : events)
    {
      EXPECT_EQ(e.first, 7);
      EXPECT_EQ(e.second.Session, one.Id());
      EXPECT_EQ(e.second.Cmd, "say");
    }
    EXPECT_NE(dialog::FormatEvent(events[0].second).find("\"session\":\"" + one.Id() + "\""),
      std::string::npos)
      << dialog::FormatEvent(events[0].second);
  }
  EXPECT_GT(one.Audio(), 0u);
  EXPECT_EQ(two.Audio(), 0u) << "the other session did not speak";

  // No session named: every session; an unknown session: none.
  EXPECT_EQ(server.Send(Say("b", ""), 8), 2u);
  ASSERT_TRUE(WaitFor([&] { return saw("b", dialog::EventKind::Ended) == 2; }));
  EXPECT_TRUE(WaitFor([&] { return two.Audio() > 0; }));
  EXPECT_EQ(server.Send(Say("c", "nobody"), 8), 0u);

  // A page cannot address another session.
  const std::string reply =
    FirstReply(port, "{\"cmd\":\"say\",\"text\":\"Hi\",\"session\":\"" + one.Id() + "\"}");
  EXPECT_NE(reply.find("unknown_field"), std::string::npos) << reply;
  for (const std::string& t : one.Events())
  {
    EXPECT_EQ(t.find("\"say\""), std::string::npos) << "no event reached the first page: " << t;
  }
  server.Stop();
}
