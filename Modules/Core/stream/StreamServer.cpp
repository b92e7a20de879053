// SPDX-License-Identifier: BSD-3-Clause
// The avatar's server (StreamServer.h) on Boost.Beast: an acceptor, one HTTP connection
// object per TCP connection that either serves files or hands the socket to a WebSocket
// session, and the sessions, each on its own strand with a frame timer.
#include "stream/StreamServer.h"

#include "base/Error.h"
#include "dialog/DialogServer.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <deque>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

namespace morphnode
{
namespace stream
{
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using SteadyClock = std::chrono::steady_clock;

namespace
{
/// Longest HTTP request head (bytes); requests have no body.
constexpr size_t MaxRequestBytes = 8192;
/// Largest file served from a folder.
constexpr size_t MaxFolderFileBytes = 16 * 1024 * 1024;

std::string ContentTypeOf(const std::string& path)
{
  auto ends = [&](const char* e)
  {
    const std::string s(e);
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".js") || ends(".mjs"))
  {
    return "text/javascript";
  }
  if (ends(".json"))
  {
    return "application/json";
  }
  if (ends(".wasm"))
  {
    return "application/wasm";
  }
  if (ends(".html"))
  {
    return "text/html; charset=utf-8";
  }
  if (ends(".css"))
  {
    return "text/css";
  }
  if (ends(".glb"))
  {
    return "model/gltf-binary";
  }
  return std::string();
}

/// A path below a folder: only [A-Za-z0-9._-/], no empty, "." or ".." component, a known
/// file type. Empty when the path is not acceptable.
std::string SafeRelativePath(const std::string& rest)
{
  if (rest.empty() || rest.size() > 256 || ContentTypeOf(rest).empty())
  {
    return std::string();
  }
  for (char c : rest)
  {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ||
          c == '/'))
    {
      return std::string();
    }
  }
  std::stringstream parts(rest);
  std::string part;
  while (std::getline(parts, part, '/'))
  {
    if (part.empty() || part == "." || part == "..")
    {
      return std::string();
    }
  }
  return rest.back() == '/' ? std::string() : rest;
}

std::map<std::string, std::string> ParseQuery(const std::string& query)
{
  std::map<std::string, std::string> out;
  std::stringstream s(query);
  std::string item;
  while (std::getline(s, item, '&'))
  {
    const size_t eq = item.find('=');
    if (eq != std::string::npos && out.size() < 16)
    {
      out[item.substr(0, eq)] = item.substr(eq + 1);
    }
  }
  return out;
}

bool IsLoopbackHostHeader(const std::string& host)
{
  // "127.0.0.1:8080", "localhost:8080", "[::1]:8080", with or without the port.
  std::string name = host;
  if (!name.empty() && name[0] == '[')
  {
    const size_t close = name.find(']');
    name = close == std::string::npos ? std::string() : name.substr(1, close - 1);
  }
  else
  {
    const size_t colon = name.rfind(':');
    if (colon != std::string::npos)
    {
      name = name.substr(0, colon);
    }
  }
  return name == "localhost" || name == "::1" || name.rfind("127.", 0) == 0;
}

/// Constant-time comparison of the token.
bool SameToken(const std::string& a, const std::string& b)
{
  if (a.size() != b.size())
  {
    return false;
  }
  unsigned char d = 0;
  for (size_t i = 0; i < a.size(); ++i)
  {
    d = static_cast<unsigned char>(d | (a[i] ^ b[i]));
  }
  return d == 0;
}
} // namespace

class WsSession;

struct StreamServer::Impl
{
  StreamServerSettings S;
  net::io_context Io;
  std::unique_ptr<tcp::acceptor> Acceptor;
  std::vector<std::thread> Threads;
  mutable std::mutex Mutex;
  std::vector<std::weak_ptr<WsSession>> Sessions;
  std::string Bound;
  std::atomic<size_t> SessionsStarted{ 0 }, SessionsRefused{ 0 }, ClientErrors{ 0 };
  std::atomic<uint64_t> FramesSent{ 0 }, FramesLate{ 0 }, FramesSkipped{ 0 }, BytesSent{ 0 };
  std::atomic<uint64_t> NextSession{ 1 };
  bool Running = false;

  void Accept();
  size_t CountSessions();
};

/// One WebSocket client: its StreamSession, a dialog session on it, the frame timer and
/// the write queue, all on one strand.
class WsSession : public std::enable_shared_from_this<WsSession>
{
public:
  WsSession(StreamServer::Impl& server, beast::tcp_stream&& stream,
    std::unique_ptr<StreamSession> session, std::string id)
    : Server(server)
    , Ws(std::move(stream))
    , Timer(Ws.get_executor())
    , Session(std::move(session))
    , Id(std::move(id))
  {
  }

  void Run(http::request<http::empty_body> request)
  {
    this->Ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    this->Ws.read_message_max(this->Server.S.MaxMessageBytes);
    this->Ws.auto_fragment(false);
    this->Ws.async_accept(
      request, beast::bind_front_handler(&WsSession::OnAccept, this->shared_from_this()));
  }

  /// The client id of the page's own commands (DialogServer's clients are >= 0).
  static constexpr int PageClient = -1;

  /// From any thread: runs the command on this session's strand; its events go to the
  /// page (PageClient) or to the server's CommandEvents (any other client).
  void Post(const dialog::Command& command, int client = PageClient)
  {
    const auto arrived = SteadyClock::now();
    net::post(this->Ws.get_executor(),
      [self = this->shared_from_this(), command, client, arrived]()
      {
        if (!self->Closed && self->Dialog)
        {
          self->Dialog->Execute(client, command, self->Now(), arrived);
          self->Flush();
        }
        else if (client != PageClient && self->Server.S.CommandEvents)
        {
          dialog::Event e = dialog::MakeError(dialog::reason::Rejected, "the session has ended",
            command.Id, dialog::CommandName(command.Body));
          e.Session = self->Id;
          self->Server.S.CommandEvents(client, e);
        }
      });
  }

  const std::string& GetId() const { return this->Id; }

  void Close()
  {
    net::post(this->Ws.get_executor(), [self = this->shared_from_this()]() { self->Shutdown(); });
  }

private:
  double Now() const
  {
    return std::chrono::duration<double>(SteadyClock::now() - this->Start).count();
  }

  void OnAccept(beast::error_code ec)
  {
    if (ec)
    {
      return;
    }
    this->Start = SteadyClock::now();
    // The token bucket starts full: a page's first commands right after connecting pass.
    this->Tokens = this->Server.S.MaxCommandsPerSecond;
    this->LastCommand = 0.0;
    this->Dialog = std::make_unique<dialog::DialogSession>(
      [this](dialog::DialogSession::ClientId client, const dialog::Event& e)
      {
        if (client != PageClient)
        {
          // A command socket's command: its events go back there, named by session.
          if (this->Server.S.CommandEvents)
          {
            dialog::Event routed = e;
            routed.Session = this->Id;
            this->Server.S.CommandEvents(client, routed);
          }
          return;
        }
        if (e.Kind == dialog::EventKind::Error)
        {
          ++this->Server.ClientErrors;
        }
        std::string line = dialog::FormatEvent(e);
        if (!line.empty() && line.back() == '\n')
        {
          line.pop_back();
        }
        this->Queue(true, std::move(line));
      },
      *this->Session);
    // Speech the pool finished is taken at once (on this strand), not at the next frame:
    // that frame then shows it under way, and its sound leaves now (OnSynthesized).
    if (this->Server.S.PickUpWhenSynthesized)
    {
      this->Session->SetSynthesizedCallback(
        [weak = this->weak_from_this(), executor = this->Ws.get_executor()]()
        {
          net::post(executor,
            [weak]()
            {
              if (auto self = weak.lock())
              {
                self->OnSynthesized();
              }
            });
        });
    }
    this->Queue(true,
      this->Session->Header(this->Id,
        this->Session->GetAvatarUrl().empty() ? this->Server.S.AvatarPath
                                              : this->Session->GetAvatarUrl()));
    this->Tick();
    this->Read();
  }

  void Read()
  {
    this->Ws.async_read(
      this->Input, beast::bind_front_handler(&WsSession::OnRead, this->shared_from_this()));
  }

  void OnRead(beast::error_code ec, size_t)
  {
    if (ec)
    {
      // Closed by the client, a protocol violation or an oversized message: this
      // session ends; nobody else notices.
      this->Shutdown();
      return;
    }
    const std::string text = beast::buffers_to_string(this->Input.data());
    this->Input.consume(this->Input.size());
    const double now = this->Now();
    if (!this->Ws.got_text())
    {
      this->Reject(
        dialog::MakeError(dialog::reason::Malformed, "commands are text messages (JSON)"));
    }
    else if (!this->Allow(now))
    {
      this->Reject(dialog::MakeError(dialog::reason::Rejected, "too many commands per second"));
    }
    else
    {
      const dialog::ParsedLine p = ParseClientMessage(text);
      if (!p.Ok())
      {
        this->Reject(p.Error);
      }
      else
      {
        this->Dialog->Execute(PageClient, p.Cmd, now, SteadyClock::now());
      }
    }
    this->Flush();
    if (!this->Closed)
    {
      this->Read();
    }
  }

  /// A token bucket of MaxCommandsPerSecond, holding a second's worth.
  bool Allow(double now)
  {
    const double rate = this->Server.S.MaxCommandsPerSecond;
    this->Tokens = std::min(rate, this->Tokens + (now - this->LastCommand) * rate);
    this->LastCommand = now;
    if (this->Tokens < 1.0)
    {
      return false;
    }
    this->Tokens -= 1.0;
    return true;
  }

  void Reject(const dialog::Event& error)
  {
    ++this->Server.ClientErrors;
    std::string line = dialog::FormatEvent(error);
    if (!line.empty() && line.back() == '\n')
    {
      line.pop_back();
    }
    this->Queue(true, std::move(line));
  }

  void Tick()
  {
    if (this->Closed)
    {
      return;
    }
    const double frame = 1.0 / this->Session->GetSettings().FrameRate;
    const double now = this->Now();
    if (now > this->Server.S.MaxSessionSeconds)
    {
      this->Shutdown();
      return;
    }
    // The frames due: a late timer (a loaded machine) sends those missed that a page can
    // still show, and skips older ones rather than bursting them.
    const DueFrames due = FramesDue(this->NextFrame, now, frame, this->Server.S.CatchUpSeconds);
    if (due.Late)
    {
      ++this->Server.FramesLate;
    }
    this->Server.FramesSkipped += due.Skipped;
    try
    {
      for (uint64_t k = due.First; k <= due.Last; ++k)
      {
        const double shown = static_cast<double>(k) * frame;
        this->Session->Tick(shown);
        for (const LiveBehavior::SpeechError& e : this->Session->TakeSpeechErrors())
        {
          // A say whose speech could not be made (the pool was busy or synthesis failed):
          // its page hears why, the say ends; the session goes on.
          this->Dialog->Fail(
            e.Id, e.Busy ? dialog::reason::Overloaded : dialog::reason::Rejected, e.Message, shown);
        }
        this->Dialog->Advance(shown);
        ++this->Server.FramesSent;
      }
      this->NextFrame = due.Last;
    }
    catch (const std::exception& e)
    {
      // A fault in one session (it should not happen) ends that session only.
      this->Reject(dialog::MakeError(
        dialog::reason::Rejected, std::string("the session failed: ") + e.what()));
      this->Flush();
      this->Shutdown();
      return;
    }
    this->Flush();
    ++this->NextFrame;
    this->Timer.expires_at(this->Start +
      std::chrono::duration_cast<SteadyClock::duration>(
        std::chrono::duration<double>(this->NextFrame * frame)));
    this->Timer.async_wait(
      [self = this->shared_from_this()](beast::error_code ec)
      {
        if (!ec)
        {
          self->Tick();
        }
      });
  }

  /// A synthesis job of this session finished: start it now, with a frame of its own,
  /// unless a frame is due within a millisecond (that frame's Tick takes it).
  void OnSynthesized()
  {
    if (this->Closed)
    {
      return;
    }
    const double frame = 1.0 / this->Session->GetSettings().FrameRate;
    const double now = this->Now();
    if (static_cast<double>(this->NextFrame) * frame - now < 0.001)
    {
      return;
    }
    try
    {
      if (this->Session->PickUp(now))
      {
        // A frame now, off the frame clock: the speech's first picture need not wait for
        // the next frame (frames carry their own sample; a page shows the nearest).
        this->Dialog->Advance(now);
        ++this->Server.FramesSent;
        this->Flush();
      }
    }
    catch (const std::exception&)
    {
      // (The next Tick meets the same fault and ends the session with its message.)
    }
  }

  /// The session's binary messages into the write queue.
  void Flush()
  {
    for (auto& m : this->Session->TakeMessages())
    {
      this->Queue(false, std::string(m.begin(), m.end()));
    }
  }

  void Queue(bool text, std::string bytes)
  {
    if (this->Closed)
    {
      return;
    }
    this->Pending += bytes.size();
    if (this->Pending > this->Server.S.MaxPendingBytes)
    {
      this->Shutdown(); // a client that does not read is dropped, not buffered for
      return;
    }
    this->Out.emplace_back(text, std::move(bytes));
    if (this->Out.size() == 1)
    {
      this->Write();
    }
  }

  void Write()
  {
    this->Ws.text(this->Out.front().first);
    this->Ws.async_write(net::buffer(this->Out.front().second),
      beast::bind_front_handler(&WsSession::OnWrite, this->shared_from_this()));
  }

  void OnWrite(beast::error_code ec, size_t bytes)
  {
    if (ec)
    {
      this->Shutdown();
      return;
    }
    this->Server.BytesSent += bytes;
    this->Pending -= this->Out.front().second.size();
    this->Out.pop_front();
    if (!this->Out.empty() && !this->Closed)
    {
      this->Write();
    }
  }

  void Shutdown()
  {
    if (this->Closed)
    {
      return;
    }
    this->Closed = true;
    this->Timer.cancel();
    if (this->Dialog)
    {
      // What still runs ends, interrupted: a command socket client hears it (the page is gone).
      this->Dialog->Shutdown(this->Now(), 0);
    }
    beast::error_code ignored;
    beast::get_lowest_layer(this->Ws).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(this->Ws).socket().close(ignored);
  }

  StreamServer::Impl& Server;
  websocket::stream<beast::tcp_stream> Ws;
  net::steady_timer Timer;
  std::unique_ptr<StreamSession> Session;
  std::unique_ptr<dialog::DialogSession> Dialog;
  std::string Id;
  beast::flat_buffer Input;
  std::deque<std::pair<bool, std::string>> Out;
  size_t Pending = 0;
  SteadyClock::time_point Start;
  uint64_t NextFrame = 0;
  double Tokens = 0.0;
  double LastCommand = 0.0;
  bool Closed = false;
};

/// One HTTP connection: files, or the handshake of a WebSocket session.
class HttpConnection : public std::enable_shared_from_this<HttpConnection>
{
public:
  HttpConnection(StreamServer::Impl& server, tcp::socket&& socket)
    : Server(server)
    , Stream(std::move(socket))
  {
  }

  void Read()
  {
    this->Parser.emplace();
    this->Parser->header_limit(MaxRequestBytes);
    this->Parser->body_limit(0);
    this->Stream.expires_after(std::chrono::seconds(15));
    http::async_read(this->Stream, this->Buffer, *this->Parser,
      beast::bind_front_handler(&HttpConnection::OnRead, this->shared_from_this()));
  }

private:
  void OnRead(beast::error_code ec, size_t)
  {
    if (ec)
    {
      beast::error_code ignored;
      this->Stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
      return;
    }
    http::request<http::empty_body> request = this->Parser->release();
    const std::string target(request.target());
    const size_t q = target.find('?');
    const std::string path = target.substr(0, q);
    const std::string query = q == std::string::npos ? std::string() : target.substr(q + 1);
    const std::string host(request[http::field::host]);
    if (!this->Server.S.AllowRemote && !IsLoopbackHostHeader(host))
    {
      // A loopback server answers loopback names only (no DNS rebinding).
      return this->Respond(request, http::status::forbidden, "text/plain", "host not allowed\n");
    }
    if (websocket::is_upgrade(request))
    {
      return this->Upgrade(std::move(request), path, query, host);
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head)
    {
      return this->Respond(request, http::status::method_not_allowed, "text/plain", "GET only\n");
    }
    if (path == "/status")
    {
      // The server's figures (sessions, frames, bytes) as JSON, for tests and monitors.
      const size_t sessions = this->Server.CountSessions();
      std::ostringstream j;
      j << "{\"sessions\":" << sessions << ",\"started\":" << this->Server.SessionsStarted
        << ",\"refused\":" << this->Server.SessionsRefused
        << ",\"clientErrors\":" << this->Server.ClientErrors
        << ",\"frames\":" << this->Server.FramesSent << ",\"late\":" << this->Server.FramesLate
        << ",\"skipped\":" << this->Server.FramesSkipped << ",\"bytes\":" << this->Server.BytesSent
        << "}\n";
      return this->Respond(request, http::status::ok, "application/json", j.str());
    }
    const auto file = this->Server.S.Files.find(path);
    if (file != this->Server.S.Files.end())
    {
      return this->Respond(request, http::status::ok, file->second.ContentType, file->second.Body);
    }
    for (const auto& [prefix, folder] : this->Server.S.Folders)
    {
      if (path.rfind(prefix, 0) == 0)
      {
        const std::string rest = SafeRelativePath(path.substr(prefix.size()));
        if (rest.empty())
        {
          break;
        }
        std::ifstream in(folder + "/" + rest, std::ios::binary);
        std::string body;
        if (in)
        {
          std::ostringstream s;
          s << in.rdbuf();
          body = s.str();
        }
        if (!in || body.size() > MaxFolderFileBytes)
        {
          break;
        }
        return this->Respond(request, http::status::ok, ContentTypeOf(rest), body);
      }
    }
    this->Respond(request, http::status::not_found, "text/plain", "not found\n");
  }

  void Upgrade(http::request<http::empty_body> request, const std::string& path,
    const std::string& query, const std::string& host)
  {
    const StreamServerSettings& s = this->Server.S;
    const auto refuse = [&](http::status status, const std::string& why)
    {
      ++this->Server.SessionsRefused;
      this->Respond(request, status, "text/plain", why + "\n");
    };
    if (path != "/stream")
    {
      return refuse(http::status::not_found, "the stream is at /stream");
    }
    const std::string origin(request[http::field::origin]);
    if (!origin.empty() && origin != "http://" + host &&
      std::find(s.AllowedOrigins.begin(), s.AllowedOrigins.end(), origin) == s.AllowedOrigins.end())
    {
      return refuse(http::status::forbidden, "origin not allowed");
    }
    const auto params = ParseQuery(query);
    if (!s.Token.empty())
    {
      const auto token = params.find("token");
      if (token == params.end() || !SameToken(token->second, s.Token))
      {
        return refuse(http::status::unauthorized, "a session token is required");
      }
    }
    if (this->Server.CountSessions() >= s.MaxSessions)
    {
      return refuse(http::status::service_unavailable, "too many sessions");
    }
    SessionRequest want;
    try
    {
      const auto codec = params.find("audio");
      if (codec != params.end())
      {
        want.Codec = ParseAudioCodec(codec->second);
      }
      const auto seed = params.find("seed");
      if (seed != params.end())
      {
        want.Seed = std::stoull(seed->second.substr(0, 19));
      }
      const auto device = params.find("device");
      if (device != params.end())
      {
        if (device->second.empty() || device->second.size() > 16 ||
          !std::all_of(device->second.begin(), device->second.end(),
            [](char c) { return std::isalpha(static_cast<unsigned char>(c)); }))
        {
          throw InputError("bad device");
        }
        want.Device = device->second;
      }
    }
    catch (const std::exception&)
    {
      return refuse(http::status::bad_request, "bad audio, seed or device parameter");
    }
    std::unique_ptr<StreamSession> session;
    try
    {
      session = s.MakeSession(want);
    }
    catch (const std::exception& e)
    {
      return refuse(http::status::bad_request, e.what());
    }
    this->Stream.expires_never();
    const std::string id = "s" + std::to_string(this->Server.NextSession++);
    auto ws =
      std::make_shared<WsSession>(this->Server, std::move(this->Stream), std::move(session), id);
    {
      std::lock_guard<std::mutex> lock(this->Server.Mutex);
      this->Server.Sessions.push_back(ws);
    }
    ++this->Server.SessionsStarted;
    ws->Run(std::move(request));
  }

  void Respond(const http::request<http::empty_body>& request, http::status status,
    const std::string& type, const std::string& body)
  {
    auto response = std::make_shared<http::response<http::string_body>>(status, request.version());
    response->set(http::field::server, "MorphNode");
    response->set(http::field::content_type, type);
    response->set(http::field::cache_control, "no-store");
    response->set("X-Content-Type-Options", "nosniff");
    response->keep_alive(request.keep_alive() && status == http::status::ok);
    if (request.method() != http::verb::head)
    {
      response->body() = body;
    }
    response->prepare_payload();
    http::async_write(this->Stream, *response,
      [self = this->shared_from_this(), response](beast::error_code ec, size_t)
      {
        if (!ec && response->keep_alive())
        {
          self->Read();
          return;
        }
        beast::error_code ignored;
        self->Stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
      });
  }

  StreamServer::Impl& Server;
  beast::tcp_stream Stream;
  beast::flat_buffer Buffer;
  std::optional<http::request_parser<http::empty_body>> Parser;
};

void StreamServer::Impl::Accept()
{
  this->Acceptor->async_accept(net::make_strand(this->Io),
    [this](beast::error_code ec, tcp::socket socket)
    {
      if (ec == net::error::operation_aborted || !this->Acceptor->is_open())
      {
        return;
      }
      if (!ec)
      {
        std::make_shared<HttpConnection>(*this, std::move(socket))->Read();
      }
      this->Accept();
    });
}

size_t StreamServer::Impl::CountSessions()
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Sessions.erase(std::remove_if(this->Sessions.begin(), this->Sessions.end(),
                         [](const std::weak_ptr<WsSession>& w) { return w.expired(); }),
    this->Sessions.end());
  return this->Sessions.size();
}

StreamServer::StreamServer(StreamServerSettings settings)
  : P(std::make_unique<Impl>())
{
  this->P->S = std::move(settings);
}

StreamServer::~StreamServer()
{
  this->Stop();
}

std::string StreamServer::Start()
{
  Impl& p = *this->P;
  if (p.Running)
  {
    return p.Bound;
  }
  if (!p.S.MakeSession)
  {
    throw InputError("the stream server has no way to make sessions");
  }
  if (p.S.Threads < 1 || p.S.Threads > 256)
  {
    throw InputError("the stream server needs 1 to 256 threads");
  }
  std::string host = "127.0.0.1";
  std::string port = p.S.Address;
  const size_t colon = p.S.Address.rfind(':');
  if (colon != std::string::npos)
  {
    host = p.S.Address.substr(0, colon);
    port = p.S.Address.substr(colon + 1);
    if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    {
      host = host.substr(1, host.size() - 2);
    }
  }
  if (port.empty() || port.size() > 5 ||
    port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) > 65535)
  {
    throw InputError("bad --serve address '" + p.S.Address + "' (HOST:PORT or PORT)");
  }
  const bool loopback = dialog::DialogServer::IsLoopbackHost(host);
  if (!loopback && !p.S.AllowRemote)
  {
    throw InputError(
      "'" + host + "' is not a loopback address: serving other machines needs --serve-remote");
  }
  if (!loopback && p.S.Token.empty())
  {
    throw InputError("serving other machines needs a session token");
  }
  try
  {
    tcp::resolver resolver(p.Io);
    const auto endpoints = resolver.resolve(host, port, tcp::resolver::numeric_service);
    const tcp::endpoint endpoint = *endpoints.begin();
    p.Acceptor = std::make_unique<tcp::acceptor>(p.Io);
    p.Acceptor->open(endpoint.protocol());
    p.Acceptor->set_option(net::socket_base::reuse_address(true));
    p.Acceptor->bind(endpoint);
    p.Acceptor->listen(net::socket_base::max_listen_connections);
    const tcp::endpoint bound = p.Acceptor->local_endpoint();
    const std::string address = bound.address().to_string();
    p.Bound = (bound.address().is_v6() ? "[" + address + "]" : address) + ":" +
      std::to_string(bound.port());
  }
  catch (const boost::system::system_error& e)
  {
    throw InputError("cannot serve on '" + p.S.Address + "': " + e.what());
  }
  p.Running = true;
  p.Accept();
  for (int i = 0; i < p.S.Threads; ++i)
  {
    p.Threads.emplace_back([&p]() { p.Io.run(); });
  }
  return p.Bound;
}

void StreamServer::Stop()
{
  Impl& p = *this->P;
  if (!p.Running)
  {
    return;
  }
  net::post(p.Io,
    [&p]()
    {
      beast::error_code ignored;
      p.Acceptor->close(ignored);
    });
  {
    std::lock_guard<std::mutex> lock(p.Mutex);
    for (auto& w : p.Sessions)
    {
      if (auto s = w.lock())
      {
        s->Close();
      }
    }
  }
  // Give the sessions a moment to close, then stop the loop.
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  p.Io.stop();
  for (auto& t : p.Threads)
  {
    t.join();
  }
  p.Threads.clear();
  p.Running = false;
}

size_t StreamServer::Broadcast(const dialog::Command& command)
{
  return this->Send(command, WsSession::PageClient);
}

std::vector<std::string> StreamServer::GetSessionIds() const
{
  std::vector<std::string> ids;
  std::lock_guard<std::mutex> lock(this->P->Mutex);
  for (auto& w : this->P->Sessions)
  {
    if (auto s = w.lock())
    {
      ids.push_back(s->GetId());
    }
  }
  return ids;
}

size_t StreamServer::Send(const dialog::Command& command, int client)
{
  std::vector<std::shared_ptr<WsSession>> open;
  {
    std::lock_guard<std::mutex> lock(this->P->Mutex);
    for (auto& w : this->P->Sessions)
    {
      auto s = w.lock();
      if (s && (command.Session.empty() || s->GetId() == command.Session))
      {
        open.push_back(std::move(s));
      }
    }
  }
  for (auto& s : open)
  {
    s->Post(command, client);
  }
  return open.size();
}

StreamServerStats StreamServer::GetStats() const
{
  StreamServerStats s;
  s.Sessions = this->P->CountSessions();
  s.SessionsStarted = this->P->SessionsStarted;
  s.SessionsRefused = this->P->SessionsRefused;
  s.ClientErrors = this->P->ClientErrors;
  s.FramesSent = this->P->FramesSent;
  s.FramesLate = this->P->FramesLate;
  s.FramesSkipped = this->P->FramesSkipped;
  s.BytesSent = this->P->BytesSent;
  return s;
}
} // namespace stream
} // namespace morphnode
