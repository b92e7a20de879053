// SPDX-License-Identifier: BSD-3-Clause
// The dialog server over real sockets and pipes: commands arrive, bad input gets error
// events on the same connection and nothing else, a client leaving mid-line runs nothing,
// two clients each get their own events, TCP binds to loopback only unless allowed.
#include "DialogTestUtilities.h"

#include "base/Error.h"
#include "dialog/DialogServer.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace morphnode::dialog;
using namespace dialogtest;

namespace
{
Event Accepted(const Command& c)
{
  Event e;
  e.Kind = EventKind::Accepted;
  e.Id = c.Id;
  e.Cmd = CommandName(c.Body);
  return e;
}

std::string TempPath(const char* name)
{
  return (std::filesystem::temp_directory_path() /
    (std::string(name) + "-" + std::to_string(getpid()) + ".sock"))
    .string();
}
} // namespace

TEST(DialogServer, TcpCommandsAndEvents)
{
  DialogServer server;
  const std::string address = server.Listen("127.0.0.1:0");
  ASSERT_EQ(address.rfind("127.0.0.1:", 0), 0u) << address;
  EXPECT_NE(address, "127.0.0.1:0"); // the port the system picked
  const int fd = ConnectTcp(address);
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(SendAll(fd,
    "{\"cmd\":\"say\",\"text\":\"Hello\",\"id\":\"s1\"}\n"
    "{\"cmd\":\"gesture\",\"name\":\"nod\",\"id\":2}\n"
    "{\"cmd\":\"mood\",\"name\":\"happy\",\"intensity\":0.5}\n"
    "{\"cmd\":\"look_at\",\"yaw\":10,\"pitch\":-5}\n"
    "\n"
    "{\"cmd\":\"stop\"}\n{\"cmd\":\"quit\",\"id\":\"q\"}\n"));
  auto in = PollCommands(server, 6);
  ASSERT_EQ(in.size(), 6u);
  EXPECT_EQ(server.GetNumberOfClients(), 1u);
  EXPECT_TRUE(std::holds_alternative<SayCommand>(in[0].Cmd.Body));
  EXPECT_TRUE(std::holds_alternative<GestureCommand>(in[1].Cmd.Body));
  EXPECT_TRUE(std::holds_alternative<MoodCommand>(in[2].Cmd.Body));
  EXPECT_TRUE(std::holds_alternative<LookAtCommand>(in[3].Cmd.Body));
  EXPECT_TRUE(std::holds_alternative<StopCommand>(in[4].Cmd.Body));
  EXPECT_TRUE(std::holds_alternative<QuitCommand>(in[5].Cmd.Body));
  EXPECT_NE(in[0].Client, DialogServer::StreamClient);
  EXPECT_EQ(in[0].Client, in[5].Client);
  EXPECT_EQ(server.GetNumberOfErrors(), 0u); // the blank line is skipped silently
  // Events echo the ids.
  server.Send(in[0].Client, Accepted(in[0].Cmd));
  server.Send(in[1].Client, Accepted(in[1].Cmd));
  auto events = ReadEvents(fd, 2, &server);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0]["event"], "accepted");
  EXPECT_EQ(events[0]["id"], "s1");
  EXPECT_EQ(events[0]["cmd"], "say");
  EXPECT_EQ(events[1]["id"], 2);
  close(fd);
  PollFor(server, 50);
  EXPECT_EQ(server.GetNumberOfClients(), 0u);
  // Events to a client that left are dropped without harm.
  server.Send(in[0].Client, Accepted(in[0].Cmd));
  EXPECT_FALSE(server.IsConnected(in[0].Client));
}

TEST(DialogServer, BadInputGetsErrorsAndNothingElse)
{
  DialogServer::Settings settings;
  settings.MaxLineBytes = 1000;
  DialogServer server(settings);
  const std::string address = server.Listen("127.0.0.1:0");
  const int fd = ConnectTcp(address);
  ASSERT_GE(fd, 0);
  const std::string nul("{\"cmd\":\"stop\"\0}\n", 16);
  ASSERT_TRUE(SendAll(fd,
    "not json\n"
    "[1,2,3]\n"
    "{\"text\":\"hi\"}\n"
    "{\"cmd\":\"juggle\",\"id\":\"j\"}\n"
    "{\"cmd\":\"say\",\"text\":42,\"id\":9}\n"
    "{\"cmd\":\"stop\",\"please\":1}\n" +
      nul + std::string(5000, '{') + "\n"));
  auto events = ReadEvents(fd, 8, &server);
  ASSERT_EQ(events.size(), 8u);
  const char* reasons[] = { reason::Malformed, reason::NotObject, reason::MissingCmd,
    reason::UnknownCmd, reason::BadField, reason::UnknownField, reason::Malformed,
    reason::TooLong };
  for (size_t i = 0; i < 8; ++i)
  {
    EXPECT_EQ(events[i]["event"], "error") << events[i].dump();
    EXPECT_EQ(events[i]["reason"], reasons[i]) << events[i].dump();
  }
  EXPECT_EQ(events[3]["id"], "j");
  EXPECT_EQ(events[4]["id"], 9);
  EXPECT_EQ(events[4]["cmd"], "say");
  EXPECT_EQ(server.GetNumberOfErrors(), 8u);
  // No command came through, and the connection still works.
  EXPECT_TRUE(PollFor(server, 30).empty());
  ASSERT_TRUE(SendAll(fd, "{\"cmd\":\"stop\",\"id\":\"after\"}\n"));
  auto in = PollCommands(server, 1);
  ASSERT_EQ(in.size(), 1u);
  EXPECT_EQ(in[0].Cmd.Id, "\"after\"");
  close(fd);
}

TEST(DialogServer, OversizedLineInPieces)
{
  DialogServer::Settings settings;
  settings.MaxLineBytes = 4096;
  DialogServer server(settings);
  const int fd = ConnectTcp(server.Listen("127.0.0.1:0"));
  ASSERT_GE(fd, 0);
  // A valid command far over the limit, sent in pieces while the server reads: it is not
  // run, not even its start.
  const std::string line = "{\"cmd\":\"say\",\"text\":\"" + std::string(300000, 'a') + "\"}\n";
  std::vector<DialogServer::Incoming> got;
  for (size_t i = 0; i < line.size(); i += 65536)
  {
    ASSERT_TRUE(SendAll(fd, line.substr(i, 65536)));
    for (auto& in : server.Poll(5))
    {
      got.push_back(in);
    }
  }
  ASSERT_TRUE(SendAll(fd, "{\"cmd\":\"stop\"}\n"));
  for (auto& in : PollCommands(server, 1))
  {
    got.push_back(in);
  }
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<StopCommand>(got[0].Cmd.Body));
  auto events = ReadEvents(fd, 1, &server);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]["reason"], reason::TooLong);
  close(fd);
}

TEST(DialogServer, ClientLeavingMidLineRunsNothing)
{
  DialogServer server;
  const std::string address = server.Listen("127.0.0.1:0");
  // Half-closed: a full line, then half of one; it can still read its events.
  int fd = ConnectTcp(address);
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(
    SendAll(fd, "{\"cmd\":\"gesture\",\"name\":\"nod\"}\n{\"cmd\":\"say\",\"text\":\"Hel"));
  shutdown(fd, SHUT_WR);
  auto in = PollCommands(server, 2, 300);
  ASSERT_EQ(in.size(), 1u); // the complete line only
  EXPECT_TRUE(std::holds_alternative<GestureCommand>(in[0].Cmd.Body));
  auto events = ReadEvents(fd, 1, &server);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]["event"], "error");
  EXPECT_EQ(events[0]["reason"], reason::Incomplete);
  close(fd);
  // Gone altogether (closed with the partial line): nothing runs, nothing breaks.
  fd = ConnectTcp(address);
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(SendAll(fd, "{\"cmd\":\"quit\""));
  PollFor(server, 30);
  close(fd);
  EXPECT_TRUE(PollFor(server, 100).empty());
  EXPECT_EQ(server.GetNumberOfClients(), 0u);
  EXPECT_EQ(server.GetNumberOfErrors(), 2u);
  // A reset connection (RST: SO_LINGER 0) mid-line: the same.
  fd = ConnectTcp(address);
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(SendAll(fd, "{\"cmd\":\"stop\""));
  PollFor(server, 30);
  linger lin{ 1, 0 };
  setsockopt(fd, SOL_SOCKET, SO_LINGER, &lin, sizeof(lin));
  close(fd);
  EXPECT_TRUE(PollFor(server, 100).empty());
  EXPECT_EQ(server.GetNumberOfClients(), 0u);
}

TEST(DialogServer, TwoClientsGetTheirOwnEvents)
{
  DialogServer server;
  const std::string address = server.Listen("127.0.0.1:0");
  const int a = ConnectTcp(address);
  const int b = ConnectTcp(address);
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  ASSERT_TRUE(SendAll(a, "{\"cmd\":\"say\",\"text\":\"from a\",\"id\":\"a\"}\n"));
  ASSERT_TRUE(SendAll(b, "{\"cmd\":\"say\",\"text\":\"from b\",\"id\":\"b\"}\n"));
  auto in = PollCommands(server, 2);
  ASSERT_EQ(in.size(), 2u);
  EXPECT_EQ(server.GetNumberOfClients(), 2u);
  EXPECT_NE(in[0].Client, in[1].Client);
  for (const auto& i : in)
  {
    server.Send(i.Client, Accepted(i.Cmd));
  }
  auto ea = ReadEvents(a, 2, &server, 300);
  auto eb = ReadEvents(b, 2, &server, 300);
  ASSERT_EQ(ea.size(), 1u); // only its own
  ASSERT_EQ(eb.size(), 1u);
  EXPECT_EQ(ea[0]["id"], "a");
  EXPECT_EQ(eb[0]["id"], "b");
  // A bad line of one client does not touch the other.
  ASSERT_TRUE(SendAll(a, "oops\n"));
  ea = ReadEvents(a, 1, &server);
  ASSERT_EQ(ea.size(), 1u);
  EXPECT_EQ(ea[0]["reason"], reason::Malformed);
  EXPECT_TRUE(ReadEvents(b, 1, &server, 100).empty());
  // Broadcast reaches both.
  server.Broadcast(MakeError(reason::Rejected, "to everyone"));
  EXPECT_EQ(ReadEvents(a, 1, &server).size(), 1u);
  EXPECT_EQ(ReadEvents(b, 1, &server).size(), 1u);
  close(a);
  close(b);
}

TEST(DialogServer, TooManyClients)
{
  DialogServer::Settings settings;
  settings.MaxClients = 1;
  DialogServer server(settings);
  const std::string address = server.Listen("127.0.0.1:0");
  const int a = ConnectTcp(address);
  ASSERT_GE(a, 0);
  PollFor(server, 30);
  const int b = ConnectTcp(address);
  ASSERT_GE(b, 0);
  auto events = ReadEvents(b, 1, &server);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]["reason"], reason::TooManyClients);
  EXPECT_EQ(server.GetNumberOfClients(), 1u);
  close(a);
  close(b);
}

TEST(DialogServer, LoopbackOnlyUnlessAllowed)
{
  EXPECT_TRUE(DialogServer::IsLoopbackHost("127.0.0.1"));
  EXPECT_TRUE(DialogServer::IsLoopbackHost("127.4.5.6"));
  EXPECT_TRUE(DialogServer::IsLoopbackHost("::1"));
  EXPECT_FALSE(DialogServer::IsLoopbackHost("0.0.0.0"));
  EXPECT_FALSE(DialogServer::IsLoopbackHost("::"));
  EXPECT_FALSE(DialogServer::IsLoopbackHost("192.168.1.1"));
  EXPECT_FALSE(DialogServer::IsLoopbackHost("8.8.8.8"));

  DialogServer server;
  EXPECT_THROW(server.Listen("0.0.0.0:0"), morphnode::InputError);
  EXPECT_THROW(server.Listen("[::]:0"), morphnode::InputError);
  EXPECT_THROW(server.Listen("10.1.2.3:0"), morphnode::InputError);
  try
  {
    server.Listen("0.0.0.0:5555");
    FAIL() << "0.0.0.0 accepted";
  }
  catch (const morphnode::InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("loopback"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(server.GetAddresses().empty());
  // A port alone is loopback; so is localhost.
  const std::string portOnly = server.Listen("0");
  EXPECT_EQ(portOnly.rfind("127.0.0.1:", 0), 0u) << portOnly;
  const std::string named = server.Listen("localhost:0");
  EXPECT_TRUE(named.rfind("127.", 0) == 0 || named.rfind("[::1]", 0) == 0) << named;

  DialogServer::Settings open;
  open.AllowRemote = true;
  DialogServer remote(open);
  const std::string any = remote.Listen("0.0.0.0:0");
  EXPECT_EQ(any.rfind("0.0.0.0:", 0), 0u) << any;
}

TEST(DialogServer, BadAddresses)
{
  DialogServer server;
  const char* bad[] = { "", "abc", "127.0.0.1:", "127.0.0.1:99999", "127.0.0.1:12x", "::1:5555",
    "unix:" };
  for (const char* address : bad)
  {
    EXPECT_THROW(server.Listen(address), morphnode::InputError) << address;
  }
  // A port in use.
  const std::string taken = server.Listen("127.0.0.1:0");
  EXPECT_THROW(server.Listen(taken), morphnode::InputError);
  EXPECT_THROW(server.Listen("unix:" + std::string(200, 'x')), morphnode::InputError);
}

TEST(DialogServer, UnixSocket)
{
  const std::string path = TempPath("morphnode-dialog-test");
  {
    // A regular file in the way is not replaced.
    std::ofstream(path) << "keep";
    DialogServer server;
    EXPECT_THROW(server.Listen("unix:" + path), morphnode::InputError);
    std::filesystem::remove(path);
  }
  {
    DialogServer server;
    EXPECT_EQ(server.Listen("unix:" + path), "unix:" + path);
    struct stat st
    {
    };
    ASSERT_EQ(stat(path.c_str(), &st), 0);
    EXPECT_TRUE(S_ISSOCK(st.st_mode));
    EXPECT_EQ(st.st_mode & 0777, 0600u); // this user only
    // A second server may not steal a live socket.
    DialogServer other;
    EXPECT_THROW(other.Listen("unix:" + path), morphnode::InputError);
    const int fd = ConnectUnix(path);
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(SendAll(fd, "{\"cmd\":\"look_at\",\"yaw\":1,\"pitch\":2,\"id\":\"u\"}\n"));
    auto in = PollCommands(server, 1);
    ASSERT_EQ(in.size(), 1u);
    server.Send(in[0].Client, Accepted(in[0].Cmd));
    auto events = ReadEvents(fd, 1, &server);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0]["id"], "u");
    close(fd);
  }
  EXPECT_FALSE(std::filesystem::exists(path)); // removed with the server
  {
    // A stale socket (its server died without removing it) is replaced.
    const int stale = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un sun{};
    sun.sun_family = AF_UNIX;
    std::strncpy(sun.sun_path, path.c_str(), sizeof(sun.sun_path) - 1);
    ASSERT_EQ(bind(stale, reinterpret_cast<sockaddr*>(&sun), sizeof(sun)), 0);
    close(stale);
    ASSERT_TRUE(std::filesystem::exists(path));
    DialogServer server;
    EXPECT_NO_THROW(server.Listen("unix:" + path));
  }
}

TEST(DialogServer, StreamLikeStdin)
{
  int in[2], out[2];
  ASSERT_EQ(pipe(in), 0);
  ASSERT_EQ(pipe(out), 0);
  {
    DialogServer server;
    server.AddStream(in[0], out[1]);
    EXPECT_THROW(server.AddStream(in[0], out[1]), morphnode::InputError);
    EXPECT_TRUE(server.IsConnected(DialogServer::StreamClient));
    const std::string lines =
      "{\"cmd\":\"gesture\",\"name\":\"blink\",\"id\":1}\nbad\n{\"cmd\":\"sa";
    ASSERT_EQ(write(in[1], lines.data(), lines.size()), static_cast<ssize_t>(lines.size()));
    auto cmds = PollCommands(server, 1);
    ASSERT_EQ(cmds.size(), 1u);
    EXPECT_EQ(cmds[0].Client, DialogServer::StreamClient);
    server.Send(DialogServer::StreamClient, Accepted(cmds[0].Cmd));
    close(in[1]); // end of input mid-line
    EXPECT_TRUE(PollFor(server, 50).empty());
    EXPECT_FALSE(server.IsConnected(DialogServer::StreamClient));
    // Events still go out after the input ended (e.g. `echo ... | MorphAvatar`).
    server.Send(DialogServer::StreamClient, Accepted(cmds[0].Cmd));
    auto events = ReadEvents(out[0], 4, nullptr, 500);
    ASSERT_EQ(events.size(), 4u);
    EXPECT_EQ(events[0]["reason"], reason::Malformed);
    EXPECT_EQ(events[1]["event"], "accepted");
    EXPECT_EQ(events[1]["id"], 1);
    EXPECT_EQ(events[2]["reason"], reason::Incomplete);
    EXPECT_EQ(events[3]["event"], "accepted");
  }
  // The server does not close the stream's descriptors.
  EXPECT_NE(fcntl(in[0], F_GETFD), -1);
  EXPECT_NE(fcntl(out[1], F_GETFD), -1);
  close(in[0]);
  close(out[0]);
  close(out[1]);
}

TEST(DialogServer, ClientThatDoesNotReadIsDropped)
{
  DialogServer::Settings settings;
  settings.MaxPendingOutput = 64 * 1024;
  DialogServer server(settings);
  const int fd = ConnectTcp(server.Listen("127.0.0.1:0"));
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(SendAll(fd, "{\"cmd\":\"stop\"}\n"));
  auto in = PollCommands(server, 1);
  ASSERT_EQ(in.size(), 1u);
  Event big = MakeError(reason::Rejected, std::string(4000, 'm'));
  for (int i = 0; i < 50000 && server.IsConnected(in[0].Client); ++i) // up to 200 MB
  {
    server.Send(in[0].Client, big); // the client never reads
  }
  EXPECT_FALSE(server.IsConnected(in[0].Client));
  PollFor(server, 20);
  EXPECT_EQ(server.GetNumberOfClients(), 0u);
  close(fd);
}
