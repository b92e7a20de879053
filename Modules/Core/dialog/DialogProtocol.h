// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DialogProtocol.h
/// @brief The dialog protocol (docs/dialog.md): commands from a dialog system as JSON
/// lines, one object per line with a `cmd` field and an optional `id`; events back as JSON
/// lines, one object per line with an `event` field (accepted, started, ended, error) that
/// echo the command's `id`.
///
///   morphnode::dialog::ParsedLine p =
///   morphnode::dialog::ParseCommand(R"({"cmd":"say","text":"Hi"})"); if (p.Ok()) { const auto& say
///   = std::get<morphnode::dialog::SayCommand>(p.Cmd.Body); } else        {
///   send(morphnode::dialog::FormatEvent(p.Error)); }
///
/// ParseCommand never throws: every input (any bytes) is either one valid command or one
/// error event with a reason (Reason below) and a message for people.

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace morphnode
{
namespace dialog
{
/// Protocol version (the `protocol` field of docs/dialog.md).
constexpr int ProtocolVersion = 1;
/// Longest line accepted by default, newline excluded (bytes): room for a recording inline
/// (`audio_base64`: about 750 KB of sound, 24 s of 16-bit 16 kHz WAV, minutes of OGG).
constexpr size_t DefaultMaxLineBytes = 1024 * 1024;
/// Longest id string (bytes).
constexpr size_t MaxIdBytes = 256;
/// A command's duration is 0 (its default) or in [MinDuration, MaxDuration] seconds: every
/// number a command carries has a range that keeps what the avatar derives from it finite
/// (a gesture of 1e-320 s would divide its envelope by zero).
constexpr double MinDuration = 0.01;
constexpr double MaxDuration = 600.0;

// ---- commands ----------------------------------------------------------------------------
struct SayCommand
{
  std::string Text;  ///< non-empty, unless Audio is given (then the recording's transcript)
  std::string Voice; ///< empty: the avatar's voice
  /// External speech (docs/dialog.md): a recording on the server (WAV, FLAC, OGG) that the
  /// avatar speaks, timed by `Timings` (a timing file on the server in any format the
  /// project reads: speech marks, Rhubarb, TextGrid, .pho, Azure viseme IDs, character
  /// alignments; `TimingsFormat` where the extension does not tell), else by aligning
  /// `Text`, else by recognition. Empty: the avatar synthesizes `Text`.
  std::string Audio;
  std::string Timings;
  std::string TimingsFormat;
  /// External speech inline: the recording's bytes (`audio_base64`, decoded: a WAV, FLAC or
  /// OGG file as it would be on disk) instead of `Audio`, and the timing file's text
  /// (`timings_inline`) instead of `Timings`.
  std::string AudioData;
  std::string TimingsData;
  /// True for external speech (a recording by name or inline).
  bool HasRecording() const { return !this->Audio.empty() || !this->AudioData.empty(); }
};
struct GestureCommand
{
  std::string Name;
  double Duration = 0.0;  ///< seconds; 0: the gesture's default, else [MinDuration, MaxDuration]
  double Intensity = 1.0; ///< [0, 1]
};
struct MoodCommand
{
  std::string Name;       ///< e.g. happy, sad, neutral (the avatar validates the name)
  double Intensity = 1.0; ///< [0, 1]
};
struct LookAtCommand
{
  double Yaw = 0.0;      ///< degrees, [-90, 90], positive to the character's left
  double Pitch = 0.0;    ///< degrees, [-90, 90], positive up
  double Duration = 0.0; ///< seconds; 0: held until the next look, else [MinDuration, MaxDuration]
};
struct StopCommand
{
};
struct QuitCommand
{
};
using CommandBody =
  std::variant<SayCommand, GestureCommand, MoodCommand, LookAtCommand, StopCommand, QuitCommand>;

struct Command
{
  /// The command's id as its JSON text (a string or an integer, e.g. `"a1"` or `42`);
  /// empty when the command has none. Events echo it unchanged.
  std::string Id;
  CommandBody Body;
  /// The stream session it is for (`session`, MorphAvatar --serve; docs/streaming.md);
  /// empty: every session (and the only avatar without --serve, which ignores it).
  std::string Session;
};
/// The longest `session` value accepted (bytes).
constexpr size_t MaxSessionBytes = 64;

/// The protocol name of a command: say, gesture, mood, look_at, stop, quit.
const char* CommandName(const CommandBody& body);

// ---- events ------------------------------------------------------------------------------
enum class EventKind
{
  Accepted, ///< the command is valid and scheduled (start, end)
  Started,  ///< the avatar's clock reached the command's start
  Ended,    ///< the avatar's clock reached its end, or it was stopped (interrupted)
  Error     ///< nothing was done (reason, message)
};
const char* EventName(EventKind kind);

/// Machine-readable reasons of error events (docs/dialog.md lists them).
namespace reason
{
constexpr const char* Malformed = "malformed";             ///< not JSON (or a NUL byte)
constexpr const char* NotObject = "not_object";            ///< JSON, but not an object
constexpr const char* MissingCmd = "missing_cmd";          ///< no `cmd` field
constexpr const char* UnknownCmd = "unknown_cmd";          ///< `cmd` is not a command
constexpr const char* BadField = "bad_field";              ///< a field of the wrong type or range
constexpr const char* UnknownField = "unknown_field";      ///< a field the command does not take
constexpr const char* TooLong = "too_long";                ///< the line exceeds the limit
constexpr const char* Incomplete = "incomplete";           ///< the client left mid-line
constexpr const char* TooManyClients = "too_many_clients"; ///< connection refused
constexpr const char* Rejected =
  "rejected"; ///< valid, but the avatar cannot do it (e.g. unknown gesture)
/// An accepted say that could not be spoken after all: the server was too busy to
/// synthesize it in time (it ends, interrupted).
constexpr const char* Overloaded = "overloaded";
} // namespace reason

struct Event
{
  EventKind Kind = EventKind::Error;
  std::string Id;      ///< the command's id as JSON text; empty: none
  std::string Cmd;     ///< the command's name; empty when unknown
  std::string Session; ///< the stream session it came from (MorphAvatar --serve); empty: none
  /// Times in seconds on the avatar's clock; NaN: absent from the JSON.
  double Time;              ///< when the event was made
  double Start;             ///< accepted, started, ended: the command's start
  double End;               ///< accepted, ended: its (expected or actual) end
  double Sound;             ///< say: when its sound starts
  double LatencyMs;         ///< started: wall-clock milliseconds from the command's arrival
  bool Interrupted = false; ///< ended: cut short by stop (or by a later command)
  std::string Reason;       ///< error: one of reason::...
  std::string Message;      ///< error: for people

  Event();
};

/// One JSON object and a newline: {"event":"accepted","id":..,"cmd":"say","time":..,...}.
/// Absent (NaN) times and empty strings are left out.
std::string FormatEvent(const Event& event);

/// An error event (no id, no command unless given).
Event MakeError(const std::string& reasonCode, const std::string& message,
  const std::string& id = std::string(), const std::string& cmd = std::string());

// ---- parsing -----------------------------------------------------------------------------
struct ParsedLine
{
  Command Cmd; ///< valid when Error.Reason is empty
  Event Error; ///< an error event (with the id and cmd when they could be read)
  bool Ok() const { return this->Error.Reason.empty(); }
};

/// One line (without its newline; a trailing '\r' is ignored) -> a command or an error.
/// Never throws. Lines longer than maxLineBytes are errors (too_long).
ParsedLine ParseCommand(std::string_view line, size_t maxLineBytes = DefaultMaxLineBytes);

/// True for lines that hold only spaces and tabs (and a '\r'): they are skipped, no event.
bool IsBlankLine(std::string_view line);

// ---- framing -----------------------------------------------------------------------------
/// Splits a byte stream into lines at '\n'. A line longer than the limit is not kept: it
/// comes out as one TooLong item when its newline arrives (or at Finish), and its bytes
/// are dropped as they come, so memory stays bounded by the limit.
class LineFramer
{
public:
  struct Item
  {
    std::string Line;
    bool TooLong = false; ///< the line exceeded the limit (Line is empty)
    size_t Length = 0;    ///< its length in bytes (newline excluded)
  };
  explicit LineFramer(size_t maxLineBytes = DefaultMaxLineBytes);
  /// Appends bytes; returns the lines completed by them.
  std::vector<Item> Feed(const char* data, size_t size);
  /// True when a partial line is buffered (bytes after the last newline).
  bool HasPartialLine() const { return this->Pending > 0; }
  /// Bytes of the partial line so far.
  size_t GetPartialLength() const { return this->Pending; }
  /// Forgets the partial line.
  void Reset();
  size_t GetMaxLineBytes() const { return this->MaxLineBytes; }

private:
  size_t MaxLineBytes;
  std::string Buffer; ///< the partial line (empty while discarding an oversized one)
  size_t Pending = 0; ///< bytes of the partial line (counted even when discarded)
  bool Discarding = false;
};
} // namespace dialog
} // namespace morphnode
