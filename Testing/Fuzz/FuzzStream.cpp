// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the avatar stream (docs/streaming.md). The first byte picks the reader:
// even: a client's text message (stream::ParseClientMessage, the dialog parser with the
// stream's limit and quit refused): one valid command (never quit) or one error event with
// a known reason; odd: a server's binary message (DecodeServerMessage, with and without a
// header bounding the indices): a message that re-encodes to the same bytes, or
// StreamError. Never a crash, never a read outside the input.
#include "stream/StreamProtocol.h"

#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace
{
using namespace morphnode;
using namespace morphnode::stream;

void CheckClient(std::string_view text)
{
  const dialog::ParsedLine p = ParseClientMessage(text);
  if (p.Ok())
  {
    if (std::holds_alternative<dialog::QuitCommand>(p.Cmd.Body))
    {
      std::abort(); // a page never quits the server
    }
    if (!p.Cmd.Session.empty())
    {
      std::abort(); // a page commands its own session only
    }
    return;
  }
  static const char* const reasons[] = { dialog::reason::Malformed, dialog::reason::NotObject,
    dialog::reason::MissingCmd, dialog::reason::UnknownCmd, dialog::reason::BadField,
    dialog::reason::UnknownField, dialog::reason::TooLong, dialog::reason::Rejected };
  bool known = false;
  for (const char* r : reasons)
  {
    known = known || p.Error.Reason == r;
  }
  const std::string line = dialog::FormatEvent(p.Error);
  if (!known || p.Error.Message.empty() || line.rfind("{\"event\":", 0) != 0)
  {
    std::abort();
  }
}

void CheckServer(const uint8_t* data, size_t size, const StreamHeader* header)
{
  ServerMessage m;
  try
  {
    m = DecodeServerMessage(data, size, header);
  }
  catch (const StreamError&)
  {
    return;
  }
  std::vector<uint8_t> again;
  if (auto* f = std::get_if<Frame>(&m))
  {
    again = EncodeFrame(*f);
  }
  else if (auto* a = std::get_if<AudioChunk>(&m))
  {
    again = EncodeAudio(*a);
  }
  else
  {
    again = EncodeStop(std::get<StopMessage>(m));
  }
  if (again.size() != size || !std::equal(again.begin(), again.end(), data))
  {
    std::abort();
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size == 0)
  {
    return 0;
  }
  if (data[0] % 2 == 0)
  {
    CheckClient(std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
    return 0;
  }
  StreamHeader header;
  header.Targets = { "A", "E", "O", "S" };
  header.Rotations = { "HeadRotation", "EyeLeftRotation" };
  CheckServer(data + 1, size - 1, nullptr);
  CheckServer(data + 1, size - 1, &header);
  return 0;
}
