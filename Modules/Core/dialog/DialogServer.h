// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DialogServer.h
/// @brief Where dialog commands come from: standard input, TCP sockets bound to loopback
/// (unless remote access is allowed explicitly) and Unix sockets, any number of clients,
/// over poll(2), never blocking the caller longer than the timeout it gives.
///
///   morphnode::dialog::DialogServer server;
///   server.Listen("127.0.0.1:5555");       // or "unix:/tmp/avatar.sock", or "5555"
///   server.AddStream(0, 1);                // commands on stdin, events on stdout
///   for (;;) {                              // the render loop
///     for (auto& in : server.Poll(0)) { ...; server.Send(in.Client, event); }
///   }
///
/// Poll() answers bad input itself: a malformed line, an unknown command, a wrong field, an
/// oversized line or a client leaving mid-line gets an error event (docs/dialog.md) and
/// nothing else happens; only valid commands are returned. A client's complete lines are
/// its commands; bytes after its last newline are never executed.
///
/// Not thread-safe: one thread (the render loop) uses the server.

#include "dialog/DialogProtocol.h"

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
namespace dialog
{
class DialogServer
{
public:
  /// Identifies a client in Poll() and Send(): 0 is the stream of AddStream(), sockets'
  /// clients count from 1 and are never reused.
  using ClientId = int;
  static constexpr ClientId StreamClient = 0;
  using TimePoint = std::chrono::steady_clock::time_point;

  struct Settings
  {
    size_t MaxLineBytes = DefaultMaxLineBytes;
    /// Socket clients at once; the next one gets a too_many_clients error and is closed.
    size_t MaxClients = 16;
    /// Events not yet taken by a client (bytes); a client that stops reading beyond this
    /// is disconnected rather than letting memory grow.
    size_t MaxPendingOutput = 1024 * 1024;
    /// Accept non-loopback TCP addresses (e.g. 0.0.0.0). Off: Listen() refuses them.
    bool AllowRemote = false;
  };

  struct Incoming
  {
    ClientId Client = StreamClient;
    Command Cmd;
    TimePoint Arrived; ///< when the line's last byte was read
  };

  DialogServer();
  explicit DialogServer(const Settings& settings);
  /// Closes every socket and removes the Unix sockets it made.
  ~DialogServer();
  DialogServer(const DialogServer&) = delete;
  DialogServer& operator=(const DialogServer&) = delete;

  /// Listens on "HOST:PORT" (IPv4, "[IPv6]:PORT", "localhost:PORT"), "PORT" (127.0.0.1),
  /// or "unix:PATH". PORT 0 picks a free port. Returns the bound address with its port
  /// (e.g. "127.0.0.1:40123", "unix:/tmp/a.sock"). InputError for a bad address, a
  /// non-loopback host without AllowRemote, a port in use, a path that exists and is not
  /// a stale socket.
  std::string Listen(const std::string& address);
  /// Commands from `inFd` (e.g. 0), its events to `outFd` (e.g. 1), as client 0. The
  /// descriptors are not closed by the server; inFd is only read after poll(2) says it is
  /// readable, so it may stay blocking.
  void AddStream(int inFd, int outFd);

  /// Waits at most timeoutMs (0: does not wait; < 0: until something arrives) for input,
  /// accepts clients, reads what is there, answers bad lines, flushes pending events.
  /// Returns the valid commands in arrival order.
  std::vector<Incoming> Poll(int timeoutMs);
  /// Queues an event for a client (written at once as far as the client takes it, the rest
  /// by later Poll() calls). Events to a client that is gone are dropped.
  void Send(ClientId client, const Event& event);
  /// Sends an event to every connected client (and the stream).
  void Broadcast(const Event& event);
  /// Writes pending events, waiting at most timeoutMs in total (e.g. before quitting).
  void Flush(int timeoutMs);
  /// Keep socket clients whose input ended (a half-closed client, `nc -N`, still reads the
  /// events of what it sent) until ReleaseEnded() lets them go; off: closed at the end of
  /// their input. DialogSession turns it on.
  void HoldEndedClients(bool hold) { this->HoldEnded = hold; }
  /// Closes the held clients whose input ended once `busy(client)` is false and their
  /// events are written (DialogSession calls it when commands end).
  void ReleaseEnded(const std::function<bool(ClientId)>& busy);

  /// True while the client is connected (the stream: while its input is open).
  bool IsConnected(ClientId client) const;
  /// Socket clients connected now.
  size_t GetNumberOfClients() const;
  /// Error events sent for bad input so far.
  size_t GetNumberOfErrors() const { return this->Errors; }
  /// The bound addresses, as Listen() returned them.
  const std::vector<std::string>& GetAddresses() const { return this->Addresses; }
  const Settings& GetSettings() const { return this->Config; }

  /// True when the TCP host (a numeric address or a name) resolves only to loopback
  /// addresses (127.0.0.0/8, ::1). InputError when it does not resolve.
  static bool IsLoopbackHost(const std::string& host);

private:
  struct Client;
  struct Listener
  {
    int Fd = -1;
    std::string UnixPath; ///< removed on destruction
  };
  void Accept(const Listener& listener);
  void ReadClient(Client& client, std::vector<Incoming>& out);
  void HandleLines(Client& client, const std::vector<LineFramer::Item>& items, TimePoint arrived,
    std::vector<Incoming>& out);
  void SendError(Client& client, const Event& error);
  void Enqueue(Client& client, const std::string& bytes);
  void FlushClient(Client& client);
  void Close(Client& client);
  void RemoveClosed();
  Client* Find(ClientId id);
  const Client* Find(ClientId id) const;

  Settings Config;
  std::vector<Listener> Listeners;
  std::vector<std::unique_ptr<Client>> Clients; ///< the stream (if any) and the sockets
  std::vector<std::string> Addresses;
  ClientId NextClient = 1;
  size_t Errors = 0;
  bool HoldEnded = false;
};
} // namespace dialog
} // namespace morphnode
