// SPDX-License-Identifier: BSD-3-Clause
#include "dialog/DialogServer.h"

#include "base/Error.h"

#include <arpa/inet.h>
#include <cerrno>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>

namespace morphnode
{
namespace dialog
{
struct DialogServer::Client
{
  ClientId Id = 0;
  int InFd = -1;
  int OutFd = -1;
  bool Socket = true; ///< a socket (closed by the server) or the stream (never closed)
  bool Open = true;   ///< input still read
  bool Dead = false;  ///< to be removed (gone, or dropped)
  bool Ended = false; ///< a socket whose input ended: kept for its events (ReleaseEnded)
  LineFramer Framer;
  std::string Output; ///< events not yet written
  explicit Client(size_t maxLine)
    : Framer(maxLine)
  {
  }
};

namespace
{
std::string ErrnoText(int error)
{
  return std::strerror(error);
}

/// "HOST:PORT", "[V6]:PORT", "PORT" -> host and port texts.
void SplitHostPort(const std::string& address, std::string& host, std::string& port)
{
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos)
  {
    host = "127.0.0.1";
    port = address;
  }
  else
  {
    host = address.substr(0, colon);
    port = address.substr(colon + 1);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    {
      host = host.substr(1, host.size() - 2);
    }
    else if (host.find(':') != std::string::npos)
    {
      throw InputError(
        "address '" + address + "': write IPv6 addresses in brackets, e.g. [::1]:5555");
    }
    if (host.empty())
    {
      host = "127.0.0.1";
    }
  }
  const bool digits =
    !port.empty() && port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoi(port) > 65535)
  {
    throw InputError(
      "address '" + address + "': expected HOST:PORT (e.g. 127.0.0.1:5555), PORT, or unix:PATH");
  }
}

bool IsLoopback(const sockaddr* sa)
{
  if (sa->sa_family == AF_INET)
  {
    const auto* in = reinterpret_cast<const sockaddr_in*>(sa);
    return (ntohl(in->sin_addr.s_addr) >> 24) == 127;
  }
  if (sa->sa_family == AF_INET6)
  {
    const auto* in6 = reinterpret_cast<const sockaddr_in6*>(sa);
    if (IN6_IS_ADDR_LOOPBACK(&in6->sin6_addr))
    {
      return true;
    }
    if (IN6_IS_ADDR_V4MAPPED(&in6->sin6_addr))
    {
      return in6->sin6_addr.s6_addr[12] == 127;
    }
  }
  return false;
}

std::string FormatAddress(const sockaddr* sa)
{
  char host[INET6_ADDRSTRLEN] = "";
  if (sa->sa_family == AF_INET)
  {
    const auto* in = reinterpret_cast<const sockaddr_in*>(sa);
    inet_ntop(AF_INET, &in->sin_addr, host, sizeof(host));
    return std::string(host) + ":" + std::to_string(ntohs(in->sin_port));
  }
  const auto* in6 = reinterpret_cast<const sockaddr_in6*>(sa);
  inet_ntop(AF_INET6, &in6->sin6_addr, host, sizeof(host));
  return "[" + std::string(host) + "]:" + std::to_string(ntohs(in6->sin6_port));
}

struct AddrInfo
{
  addrinfo* List = nullptr;
  ~AddrInfo()
  {
    if (this->List)
    {
      freeaddrinfo(this->List);
    }
  }
};

void Resolve(const std::string& host, const std::string& port, AddrInfo& out)
{
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  const int rc = getaddrinfo(host.c_str(), port.c_str(), &hints, &out.List);
  if (rc != 0 || !out.List)
  {
    throw InputError("cannot resolve the host '" + host + "': " + gai_strerror(rc));
  }
}
} // namespace

DialogServer::DialogServer()
  : DialogServer(Settings())
{
}

DialogServer::DialogServer(const Settings& settings)
  : Config(settings)
{
  if (this->Config.MaxLineBytes == 0)
  {
    throw InputError("the dialog server's line limit must be at least one byte");
  }
}

DialogServer::~DialogServer()
{
  for (auto& client : this->Clients)
  {
    this->Close(*client);
  }
  for (const Listener& l : this->Listeners)
  {
    ::close(l.Fd);
    if (!l.UnixPath.empty())
    {
      ::unlink(l.UnixPath.c_str());
    }
  }
}

bool DialogServer::IsLoopbackHost(const std::string& host)
{
  AddrInfo info;
  Resolve(host, "0", info);
  for (addrinfo* a = info.List; a; a = a->ai_next)
  {
    if (!IsLoopback(a->ai_addr))
    {
      return false;
    }
  }
  return true;
}

std::string DialogServer::Listen(const std::string& address)
{
  Listener listener;
  std::string bound;
  if (address.rfind("unix:", 0) == 0)
  {
    const std::string path = address.substr(5);
    sockaddr_un sun{};
    sun.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(sun.sun_path) || path.find('\0') != std::string::npos)
    {
      throw InputError("address '" + address + "': a Unix socket needs a path of 1 to " +
        std::to_string(sizeof(sun.sun_path) - 1) + " bytes");
    }
    std::memcpy(sun.sun_path, path.data(), path.size());
    struct stat st
    {
    };
    if (::lstat(path.c_str(), &st) == 0)
    {
      if (!S_ISSOCK(st.st_mode))
      {
        throw InputError("cannot listen on '" + path + "': it exists and is not a socket");
      }
      // A socket file: in use if someone answers, else left over by a dead process.
      const int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
      const bool alive =
        probe >= 0 && ::connect(probe, reinterpret_cast<const sockaddr*>(&sun), sizeof(sun)) == 0;
      if (probe >= 0)
      {
        ::close(probe);
      }
      if (alive)
      {
        throw InputError("cannot listen on '" + path + "': another program listens there");
      }
      ::unlink(path.c_str());
    }
    listener.Fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (listener.Fd < 0)
    {
      throw InputError("cannot create a Unix socket: " + ErrnoText(errno));
    }
    if (::bind(listener.Fd, reinterpret_cast<const sockaddr*>(&sun), sizeof(sun)) != 0)
    {
      const int error = errno;
      ::close(listener.Fd);
      throw InputError("cannot listen on '" + path + "': " + ErrnoText(error));
    }
    // Only this user may connect; set before listen(), so nobody connects earlier.
    if (::chmod(path.c_str(), S_IRUSR | S_IWUSR) != 0 || ::listen(listener.Fd, 16) != 0)
    {
      const int error = errno;
      ::close(listener.Fd);
      ::unlink(path.c_str());
      throw InputError("cannot listen on '" + path + "': " + ErrnoText(error));
    }
    listener.UnixPath = path;
    bound = "unix:" + path;
  }
  else
  {
    std::string host, port;
    SplitHostPort(address, host, port);
    AddrInfo info;
    Resolve(host, port, info);
    if (!this->Config.AllowRemote)
    {
      for (addrinfo* a = info.List; a; a = a->ai_next)
      {
        if (!IsLoopback(a->ai_addr))
        {
          throw InputError("refusing to listen on '" + address + "' (" + FormatAddress(a->ai_addr) +
            "): it is not a loopback address, so other machines could command the avatar; "
            "use 127.0.0.1, ::1 or localhost, or allow remote clients explicitly");
        }
      }
    }
    int lastError = 0;
    for (addrinfo* a = info.List; a && listener.Fd < 0; a = a->ai_next)
    {
      const int fd =
        ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
      if (fd < 0)
      {
        lastError = errno;
        continue;
      }
      const int one = 1;
      ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
      if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd, 16) != 0)
      {
        lastError = errno;
        ::close(fd);
        continue;
      }
      listener.Fd = fd;
    }
    if (listener.Fd < 0)
    {
      throw InputError("cannot listen on '" + address + "': " + ErrnoText(lastError));
    }
    sockaddr_storage ss{};
    socklen_t len = sizeof(ss);
    ::getsockname(listener.Fd, reinterpret_cast<sockaddr*>(&ss), &len);
    bound = FormatAddress(reinterpret_cast<const sockaddr*>(&ss));
  }
  this->Listeners.push_back(listener);
  this->Addresses.push_back(bound);
  return bound;
}

void DialogServer::AddStream(int inFd, int outFd)
{
  if (this->Find(StreamClient))
  {
    throw InputError("the dialog server already reads a stream");
  }
  auto client = std::make_unique<Client>(this->Config.MaxLineBytes);
  client->Id = StreamClient;
  client->InFd = inFd;
  client->OutFd = outFd;
  client->Socket = false;
  this->Clients.insert(this->Clients.begin(), std::move(client));
}

DialogServer::Client* DialogServer::Find(ClientId id)
{
  for (auto& c : this->Clients)
  {
    if (c->Id == id && !c->Dead)
    {
      return c.get();
    }
  }
  return nullptr;
}

const DialogServer::Client* DialogServer::Find(ClientId id) const
{
  return const_cast<DialogServer*>(this)->Find(id);
}

bool DialogServer::IsConnected(ClientId id) const
{
  const Client* c = this->Find(id);
  return c && c->Open;
}

size_t DialogServer::GetNumberOfClients() const
{
  return static_cast<size_t>(std::count_if(this->Clients.begin(), this->Clients.end(),
    [](const std::unique_ptr<Client>& c) { return c->Socket && !c->Dead && !c->Ended; }));
}

void DialogServer::Accept(const Listener& listener)
{
  for (;;)
  {
    const int fd = ::accept4(listener.Fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0)
    {
      return; // EAGAIN (no more), or the client left already
    }
    // Held half-closed clients count too: each still holds a socket.
    const size_t held = static_cast<size_t>(std::count_if(this->Clients.begin(),
      this->Clients.end(), [](const std::unique_ptr<Client>& c) { return c->Socket && !c->Dead; }));
    if (held >= this->Config.MaxClients)
    {
      const std::string line = FormatEvent(MakeError(reason::TooManyClients,
        "the avatar serves at most " + std::to_string(this->Config.MaxClients) +
          " clients at once"));
      [[maybe_unused]] const ssize_t sent =
        ::send(fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      ::close(fd);
      ++this->Errors;
      continue;
    }
    auto client = std::make_unique<Client>(this->Config.MaxLineBytes);
    client->Id = this->NextClient++;
    client->InFd = client->OutFd = fd;
    this->Clients.push_back(std::move(client));
  }
}

void DialogServer::Enqueue(Client& client, const std::string& bytes)
{
  if (client.Dead || client.OutFd < 0)
  {
    return;
  }
  client.Output += bytes;
  this->FlushClient(client);
  if (client.Socket && client.Output.size() > this->Config.MaxPendingOutput)
  {
    this->Close(client); // it does not read its events
  }
}

void DialogServer::FlushClient(Client& client)
{
  while (!client.Output.empty() && client.OutFd >= 0)
  {
    const ssize_t n = client.Socket
      ? ::send(
          client.OutFd, client.Output.data(), client.Output.size(), MSG_NOSIGNAL | MSG_DONTWAIT)
      : ::write(client.OutFd, client.Output.data(), client.Output.size());
    if (n > 0)
    {
      client.Output.erase(0, static_cast<size_t>(n));
    }
    else if (n < 0 && errno == EINTR)
    {
      continue;
    }
    else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
    {
      return; // later, when poll says it is writable
    }
    else
    {
      // The reader is gone (EPIPE, ECONNRESET): nobody to tell.
      client.Output.clear();
      if (client.Socket)
      {
        this->Close(client);
      }
      else
      {
        client.OutFd = -1;
      }
      return;
    }
  }
}

void DialogServer::Close(Client& client)
{
  if (client.Socket && client.InFd >= 0)
  {
    ::close(client.InFd);
  }
  client.InFd = client.OutFd = -1;
  client.Open = false;
  client.Dead = true;
}

void DialogServer::SendError(Client& client, const Event& error)
{
  ++this->Errors;
  this->Enqueue(client, FormatEvent(error));
}

void DialogServer::HandleLines(Client& client, const std::vector<LineFramer::Item>& items,
  TimePoint arrived, std::vector<Incoming>& out)
{
  for (const LineFramer::Item& item : items)
  {
    if (item.TooLong)
    {
      this->SendError(client,
        MakeError(reason::TooLong,
          "the line has " + std::to_string(item.Length) + " bytes; the limit is " +
            std::to_string(this->Config.MaxLineBytes)));
      continue;
    }
    if (IsBlankLine(item.Line))
    {
      continue;
    }
    ParsedLine parsed = ParseCommand(item.Line, this->Config.MaxLineBytes);
    if (!parsed.Ok())
    {
      this->SendError(client, parsed.Error);
      continue;
    }
    Incoming in;
    in.Client = client.Id;
    in.Cmd = std::move(parsed.Cmd);
    in.Arrived = arrived;
    out.push_back(std::move(in));
  }
}

void DialogServer::ReadClient(Client& client, std::vector<Incoming>& out)
{
  // At most this much per client and poll, so that one busy client cannot hold the frame.
  constexpr size_t budget = 256 * 1024;
  char buffer[16384];
  size_t total = 0;
  while (client.Open && total < budget)
  {
    const ssize_t n = ::read(client.InFd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR)
    {
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
    {
      return;
    }
    if (n <= 0)
    {
      // End of input (or a reset): complete lines were handled; a partial one is not run.
      if (client.Framer.HasPartialLine())
      {
        this->SendError(client,
          MakeError(reason::Incomplete,
            "the input ended in the middle of a line (" +
              std::to_string(client.Framer.GetPartialLength()) +
              " bytes after the last newline); that line was not executed"));
        client.Framer.Reset();
      }
      client.Open = false;
      if (client.Socket)
      {
        // A half-closed client still reads its events: the socket stays until the commands
        // it sent have ended (ReleaseEnded), or until writing to it fails.
        this->FlushClient(client);
        client.Ended = n == 0 && !client.Dead && this->HoldEnded;
        if (!client.Ended)
        {
          this->Close(client);
        }
      }
      return;
    }
    total += static_cast<size_t>(n);
    const TimePoint arrived = std::chrono::steady_clock::now();
    this->HandleLines(client, client.Framer.Feed(buffer, static_cast<size_t>(n)), arrived, out);
    if (!client.Socket)
    {
      return; // the stream may be blocking: one read per poll
    }
  }
}

void DialogServer::RemoveClosed()
{
  this->Clients.erase(std::remove_if(this->Clients.begin(), this->Clients.end(),
                        [](const std::unique_ptr<Client>& c) { return c->Dead; }),
    this->Clients.end());
}

std::vector<DialogServer::Incoming> DialogServer::Poll(int timeoutMs)
{
  std::vector<Incoming> out;
  std::vector<pollfd> fds;
  for (const Listener& l : this->Listeners)
  {
    fds.push_back(pollfd{ l.Fd, POLLIN, 0 });
  }
  std::vector<Client*> polled;
  for (auto& c : this->Clients)
  {
    if (c->Dead)
    {
      continue;
    }
    short events = c->Open && c->InFd >= 0 ? POLLIN : 0;
    if (c->Socket && !c->Output.empty())
    {
      events |= POLLOUT;
    }
    if (events == 0)
    {
      continue;
    }
    fds.push_back(pollfd{ c->InFd, events, 0 });
    polled.push_back(c.get());
  }
  if (fds.empty())
  {
    return out;
  }
  // A signal ends the wait (EINTR: nothing read): a stop request (SIGTERM) is seen at once.
  const int ready = ::poll(fds.data(), fds.size(), timeoutMs);
  if (ready <= 0)
  {
    return out;
  }
  const size_t nl = this->Listeners.size();
  for (size_t i = 0; i < polled.size(); ++i)
  {
    Client& c = *polled[i];
    const short r = fds[nl + i].revents;
    if (r & POLLNVAL)
    {
      c.Open = false;
      if (c.Socket)
      {
        this->Close(c);
      }
      continue;
    }
    if (r & POLLOUT)
    {
      this->FlushClient(c);
    }
    if (!c.Dead && (r & (POLLIN | POLLHUP | POLLERR)))
    {
      this->ReadClient(c, out);
    }
  }
  for (size_t i = 0; i < nl; ++i)
  {
    if (fds[i].revents & POLLIN)
    {
      this->Accept(this->Listeners[i]);
    }
  }
  this->RemoveClosed();
  return out;
}

void DialogServer::ReleaseEnded(const std::function<bool(ClientId)>& busy)
{
  for (auto& c : this->Clients)
  {
    if (c->Ended && !c->Dead && !busy(c->Id))
    {
      this->FlushClient(*c);
      if (c->Output.empty() && !c->Dead)
      {
        this->Close(*c);
      }
    }
  }
  this->RemoveClosed();
}

void DialogServer::Send(ClientId id, const Event& event)
{
  if (Client* c = this->Find(id))
  {
    this->Enqueue(*c, FormatEvent(event));
  }
}

void DialogServer::Broadcast(const Event& event)
{
  const std::string line = FormatEvent(event);
  for (auto& c : this->Clients)
  {
    this->Enqueue(*c, line);
  }
}

void DialogServer::Flush(int timeoutMs)
{
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  for (;;)
  {
    std::vector<pollfd> fds;
    std::vector<Client*> waiting;
    for (auto& c : this->Clients)
    {
      if (!c->Dead && c->OutFd >= 0 && !c->Output.empty())
      {
        fds.push_back(pollfd{ c->OutFd, POLLOUT, 0 });
        waiting.push_back(c.get());
      }
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      until - std::chrono::steady_clock::now())
                        .count();
    if (fds.empty() || left <= 0)
    {
      return;
    }
    if (::poll(fds.data(), fds.size(), static_cast<int>(left)) <= 0)
    {
      continue;
    }
    for (size_t i = 0; i < waiting.size(); ++i)
    {
      if (fds[i].revents & (POLLOUT | POLLERR | POLLHUP))
      {
        this->FlushClient(*waiting[i]);
      }
    }
  }
}
} // namespace dialog
} // namespace morphnode
