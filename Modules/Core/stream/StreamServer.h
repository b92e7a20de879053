// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file StreamServer.h
/// @brief The avatar's server for remote faces (docs/streaming.md): plain HTTP for the
/// page and its files (exact paths registered in memory, or files under registered
/// folders, never outside them) and one WebSocket per browser session on /stream, each with
/// its own StreamSession (behaviour, optimizer, sound) ticking at the frame rate.
///
/// Why Boost.Beast (Debian libboost-dev) and not libwebsockets: Beast is header-only C++
/// on Boost.Asio, so sessions are plain C++ objects with strands and timers in the same
/// io_context (no C callback table, no global context, no separate event loop to marry to
/// ours); it enforces message size limits itself (read_message_max) and does the
/// WebSocket handshake, masking and fragmentation RFC 6455 asks. libwebsockets would add a
/// C library with its own loop and protocol tables for the same work.
///
/// Security: loopback only unless AllowRemote; remote sessions need the Token (the
/// `token` query parameter of /stream); a browser's Origin must be the server's own (or one
/// of AllowedOrigins); HTTP requests, client messages and each session's unsent output
/// are bounded; a malformed command gets an error event and the session goes on; a
/// WebSocket protocol violation or an oversized message closes that session only.
///
///   morphnode::stream::StreamServer server(settings);
///   std::cout << server.Start() << "\n";  // "127.0.0.1:8080": runs on its own threads
///   ... server.Broadcast(command) ...      // e.g. from the dialog command socket
///   server.Stop();

#include "dialog/DialogProtocol.h"
#include "stream/StreamSession.h"

#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
namespace stream
{
struct StaticFile
{
  std::string ContentType;
  std::string Body;
};

/// What a connecting client asked for (the /stream URL's query parameters).
struct SessionRequest
{
  AudioCodec Codec = AudioCodec::Pcm16;
  uint64_t Seed = 1;
  /// The device profile the page asks for (`device`: letters only, at most 16; empty: none).
  /// MakeSession checks it (budget/DeviceProfile.h) and picks the avatar prepared for it.
  std::string Device;
};

struct StreamServerSettings
{
  /// "HOST:PORT" or "PORT" (127.0.0.1); PORT 0 picks a free one.
  std::string Address = "127.0.0.1:0";
  /// Accept non-loopback addresses; then Token must be set.
  bool AllowRemote = false;
  /// Required as ?token= on /stream when non-empty (always when AllowRemote).
  std::string Token;
  /// Origins allowed besides the server's own ("http://HOST:PORT" of the request's Host).
  std::vector<std::string> AllowedOrigins;
  size_t MaxSessions = 64;
  /// Longest client message (bytes); longer ones close that session (1009).
  size_t MaxMessageBytes = MaxClientMessageBytes;
  /// Commands per second a session may send (more get a rejected error event).
  double MaxCommandsPerSecond = 20.0;
  /// Unsent output a session may hold (bytes) before the slow client is dropped.
  size_t MaxPendingBytes = 2 * 1024 * 1024;
  /// Threads running the sessions (each session is on one strand).
  int Threads = 1;
  /// Exact paths ("/", "/avatar.glb") served from memory.
  std::map<std::string, StaticFile> Files;
  /// URL prefix ("/three/") -> folder: files below it (.js, .json, .wasm), read on request.
  std::map<std::string, std::string> Folders;
  /// Makes a session (the application's avatar, voice, optimizer). Throwing InputError
  /// refuses the connection with the message.
  std::function<std::unique_ptr<StreamSession>(const SessionRequest&)> MakeSession;
  /// Where the avatar file is (the header's `avatar`).
  std::string AvatarPath = "/avatar.glb";
  /// Events of the commands given to Send() with a client (e.g. the command socket's):
  /// accepted, started, ended, error, each with the session's id in Event::Session. Called
  /// on the sessions' threads: it must be thread-safe (e.g. queue them for the caller's loop).
  std::function<void(int client, const dialog::Event& event)> CommandEvents;
  /// Sessions end after this many seconds (the u32 sample clock wraps after a day at 48 kHz).
  double MaxSessionSeconds = 12 * 3600.0;
  /// A frame timer that fires late still sends the frames missed up to this old (seconds;
  /// stream::FramesDue): a page's jitter buffer shows them instead of a gap. Older ones are
  /// skipped (StreamServerStats::FramesSkipped).
  double CatchUpSeconds = 0.1;
  /// Speech the synthesis pool finished starts when it is ready (StreamSession::PickUp on
  /// the pool's signal), not at the next frame. Off: at the next frame (the studies compare).
  bool PickUpWhenSynthesized = true;
};

struct StreamServerStats
{
  size_t Sessions = 0;        ///< open now
  size_t SessionsStarted = 0; ///< since Start
  size_t SessionsRefused = 0;
  size_t ClientErrors = 0; ///< error events sent for bad client input
  uint64_t FramesSent = 0;
  uint64_t FramesLate = 0;    ///< ticks that ran more than one frame late
  uint64_t FramesSkipped = 0; ///< frames not sent: older than CatchUpSeconds when due
  uint64_t BytesSent = 0;
};

class StreamServer
{
public:
  explicit StreamServer(StreamServerSettings settings);
  ~StreamServer();
  StreamServer(const StreamServer&) = delete;
  StreamServer& operator=(const StreamServer&) = delete;

  /// Binds and starts serving on Threads threads. Returns the bound "HOST:PORT".
  /// InputError for a bad address, a remote one without AllowRemote or without a Token,
  /// a port in use, no MakeSession.
  std::string Start();
  /// Closes every session and stops the threads (also on destruction).
  void Stop();
  /// Runs a command on every open session (e.g. from the command socket). Returns how
  /// many sessions it went to; their events go to their own pages.
  size_t Broadcast(const dialog::Command& command);
  /// Runs a command from `client` (>= 0, e.g. a DialogServer client) on the session its
  /// Session names, or on every open session when it names none; the command's events go
  /// to CommandEvents with that client (not to the pages). Returns how many sessions it
  /// went to (0: no such session, or none open).
  size_t Send(const dialog::Command& command, int client);
  /// The ids of the open sessions (as in their headers and in CommandEvents).
  std::vector<std::string> GetSessionIds() const;
  StreamServerStats GetStats() const;

  /// The implementation (StreamServer.cpp; its connections and sessions use it).
  struct Impl;

private:
  std::unique_ptr<Impl> P;
};
} // namespace stream
} // namespace morphnode
