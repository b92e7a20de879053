// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the dialog protocol's line parser (ParseCommand) and line framing. Any bytes
// are either one valid command or one error event with a known reason; both format to one
// JSON line. The same bytes fed to the framer in two pieces give the same lines as in one.
#include "dialog/DialogProtocol.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

namespace
{
using namespace morphnode::dialog;

void CheckOneLine(const std::string& line)
{
  // One line, newline-terminated, and a JSON object with an "event" field.
  if (line.empty() || line.back() != '\n' || line.find('\n') != line.size() - 1 ||
    line.rfind("{\"event\":", 0) != 0)
  {
    std::abort();
  }
}

void CheckLine(std::string_view text, size_t limit)
{
  ParsedLine p = ParseCommand(text, limit);
  if (p.Ok())
  {
    Event accepted;
    accepted.Kind = EventKind::Accepted;
    accepted.Id = p.Cmd.Id;
    accepted.Cmd = CommandName(p.Cmd.Body);
    accepted.Session = p.Cmd.Session;
    if (p.Cmd.Session.size() > MaxSessionBytes)
    {
      std::abort(); // the session field is bounded
    }
    CheckOneLine(FormatEvent(accepted));
    if (std::holds_alternative<SayCommand>(p.Cmd.Body))
    {
      const SayCommand& say = std::get<SayCommand>(p.Cmd.Body);
      if (!say.HasRecording() && say.Text.find_first_not_of(" \t\r\n") == std::string::npos)
      {
        std::abort(); // a say has text, or a recording (external speech, by name or inline)
      }
      if (!say.HasRecording() &&
        (!say.Timings.empty() || !say.TimingsData.empty() || !say.TimingsFormat.empty()))
      {
        std::abort(); // timings only with a recording
      }
      if (!say.Audio.empty() && !say.AudioData.empty())
      {
        std::abort(); // a recording by name or inline, not both
      }
    }
    return;
  }
  static const char* const reasons[] = { reason::Malformed, reason::NotObject, reason::MissingCmd,
    reason::UnknownCmd, reason::BadField, reason::UnknownField, reason::TooLong };
  bool known = false;
  for (const char* r : reasons)
  {
    known = known || p.Error.Reason == r;
  }
  if (!known || p.Error.Message.empty() || p.Error.Kind != EventKind::Error)
  {
    std::abort();
  }
  CheckOneLine(FormatEvent(p.Error));
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const char* bytes = reinterpret_cast<const char*>(data);
  // The whole input as one line, with the default limit and a small one.
  CheckLine(std::string_view(bytes, size), DefaultMaxLineBytes);
  CheckLine(std::string_view(bytes, size), 64);
  // Framed: every line of the input, in one piece and split in two.
  LineFramer whole(256), split(256);
  auto a = whole.Feed(bytes, size);
  const size_t half = size / 2;
  auto b = split.Feed(bytes, half);
  auto rest = split.Feed(bytes + half, size - half);
  b.insert(b.end(), rest.begin(), rest.end());
  if (a.size() != b.size() || whole.GetPartialLength() != split.GetPartialLength())
  {
    std::abort();
  }
  for (size_t i = 0; i < a.size(); ++i)
  {
    if (a[i].Line != b[i].Line || a[i].TooLong != b[i].TooLong || a[i].Length != b[i].Length ||
      (!a[i].TooLong && a[i].Line.size() > 257) || a[i].Line.find('\n') != std::string::npos)
    {
      std::abort();
    }
    if (!a[i].TooLong)
    {
      CheckLine(a[i].Line, 256);
    }
  }
  return 0;
}
