// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Helpers of the dialog tests: a client socket, reading event lines with a timeout, and
// polling a server until something arrives.
#include "dialog/DialogServer.h"

#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <string>
#include <vector>

namespace dialogtest
{
using json = nlohmann::json;
using morphnode::dialog::DialogServer;

/// A connected TCP client of "HOST:PORT" (IPv4), or -1.
inline int ConnectTcp(const std::string& address)
{
  const size_t colon = address.rfind(':');
  sockaddr_in sin{};
  sin.sin_family = AF_INET;
  sin.sin_port = htons(static_cast<uint16_t>(std::stoi(address.substr(colon + 1))));
  if (inet_pton(AF_INET, address.substr(0, colon).c_str(), &sin.sin_addr) != 1)
  {
    return -1;
  }
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd >= 0 && connect(fd, reinterpret_cast<sockaddr*>(&sin), sizeof(sin)) != 0)
  {
    close(fd);
    return -1;
  }
  return fd;
}

inline int ConnectUnix(const std::string& path)
{
  sockaddr_un sun{};
  sun.sun_family = AF_UNIX;
  std::strncpy(sun.sun_path, path.c_str(), sizeof(sun.sun_path) - 1);
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd >= 0 && connect(fd, reinterpret_cast<sockaddr*>(&sun), sizeof(sun)) != 0)
  {
    close(fd);
    return -1;
  }
  return fd;
}

inline bool SendAll(int fd, const std::string& bytes)
{
  size_t done = 0;
  while (done < bytes.size())
  {
    const ssize_t n = send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n <= 0)
    {
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

/// Reads from fd, keeping partial lines in `pending`, until `count` lines arrived or the
/// timeout passed; while waiting it polls the server (so that it reads and answers).
/// Each line is parsed as JSON (a discarded value if it is not JSON).
inline std::vector<json> ReadEvents(
  int fd, size_t count, DialogServer* server, std::string& pending, int timeoutMs = 3000)
{
  std::vector<json> events;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (events.size() < count && std::chrono::steady_clock::now() < until)
  {
    size_t nl;
    while (events.size() < count && (nl = pending.find('\n')) != std::string::npos)
    {
      events.push_back(json::parse(pending.substr(0, nl), nullptr, false));
      pending.erase(0, nl + 1);
    }
    if (events.size() >= count)
    {
      break;
    }
    if (server)
    {
      server->Poll(5);
    }
    pollfd p{ fd, POLLIN, 0 };
    if (poll(&p, 1, server ? 5 : 20) > 0)
    {
      char buffer[4096];
      const ssize_t n = read(fd, buffer, sizeof(buffer));
      if (n <= 0)
      {
        break;
      }
      pending.append(buffer, static_cast<size_t>(n));
    }
  }
  return events;
}

inline std::vector<json> ReadEvents(
  int fd, size_t count, DialogServer* server, int timeoutMs = 3000)
{
  std::string pending;
  return ReadEvents(fd, count, server, pending, timeoutMs);
}

/// Polls until at least `count` commands arrived (or the timeout).
inline std::vector<DialogServer::Incoming> PollCommands(
  DialogServer& server, size_t count, int timeoutMs = 3000)
{
  std::vector<DialogServer::Incoming> all;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (all.size() < count && std::chrono::steady_clock::now() < until)
  {
    for (auto& in : server.Poll(10))
    {
      all.push_back(std::move(in));
    }
  }
  return all;
}

/// Polls for a while and returns everything (to show that nothing arrives).
inline std::vector<DialogServer::Incoming> PollFor(DialogServer& server, int ms)
{
  std::vector<DialogServer::Incoming> all;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  while (std::chrono::steady_clock::now() < until)
  {
    for (auto& in : server.Poll(5))
    {
      all.push_back(std::move(in));
    }
  }
  return all;
}
} // namespace dialogtest
