// SPDX-License-Identifier: BSD-3-Clause
#include "dialog/DialogProtocol.h"

#include "base/Base64.h"
#include "base/Error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <set>
#include <vector>

namespace morphnode
{
namespace dialog
{
using json = nlohmann::json;

namespace
{
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

/// A field's problem: thrown inside ParseCommand only, turned into an error event there.
struct FieldError
{
  const char* Reason;
  std::string Message;
};

/// Rejects every key the command does not take (a misspelt field must not be ignored).
void CheckKeys(const json& object, const char* cmd, std::initializer_list<const char*> allowed)
{
  for (auto it = object.begin(); it != object.end(); ++it)
  {
    const std::string& key = it.key();
    if (key == "cmd" || key == "id" || key == "session")
    {
      continue;
    }
    bool known = false;
    for (const char* a : allowed)
    {
      known = known || key == a;
    }
    if (!known)
    {
      std::string list;
      for (const char* a : allowed)
      {
        list += std::string(list.empty() ? "" : ", ") + a;
      }
      throw FieldError{ reason::UnknownField,
        std::string(cmd) + " takes no field '" + key.substr(0, 64) + "'" +
          (list.empty() ? std::string(" (it takes only cmd and id)")
                        : " (it takes " + list + ", and cmd and id)") };
    }
  }
}

std::string GetString(const json& object, const char* key, bool required, bool nonEmpty)
{
  auto it = object.find(key);
  if (it == object.end())
  {
    if (required)
    {
      throw FieldError{ reason::BadField, std::string("missing field '") + key + "'" };
    }
    return std::string();
  }
  if (!it->is_string())
  {
    throw FieldError{ reason::BadField, std::string("'") + key + "' must be a string" };
  }
  std::string value = it->get<std::string>();
  if (nonEmpty && value.find_first_not_of(" \t\r\n") == std::string::npos)
  {
    throw FieldError{ reason::BadField, std::string("'") + key + "' must not be empty" };
  }
  return value;
}

/// A finite number in [lo, hi]; `fallback` when absent and not required.
double GetNumber(
  const json& object, const char* key, bool required, double fallback, double lo, double hi)
{
  auto it = object.find(key);
  if (it == object.end())
  {
    if (required)
    {
      throw FieldError{ reason::BadField, std::string("missing field '") + key + "'" };
    }
    return fallback;
  }
  if (!it->is_number())
  {
    throw FieldError{ reason::BadField, std::string("'") + key + "' must be a number" };
  }
  const double value = it->get<double>();
  if (!std::isfinite(value) || value < lo || value > hi)
  {
    throw FieldError{ reason::BadField,
      std::string("'") + key + "' must be in [" + json(lo).dump() + ", " + json(hi).dump() + "]" };
  }
  return value;
}

/// A duration: 0 (the default) or in [MinDuration, MaxDuration] (a shorter one would
/// leave a gesture's envelope without a shape: see DialogProtocol.h).
double GetDuration(const json& object, const char* key)
{
  const double value = GetNumber(object, key, false, 0.0, 0.0, MaxDuration);
  if (value != 0.0 && value < MinDuration)
  {
    throw FieldError{ reason::BadField,
      std::string("'") + key + "' must be 0 (the default) or in [" + json(MinDuration).dump() +
        ", " + json(MaxDuration).dump() + "] seconds" };
  }
  return value;
}

/// `timings_inline`: the timing file's text as a string (TSV, TextGrid, .pho, speech-mark
/// lines, any JSON format as text), or a JSON format as JSON: an object (Rhubarb JSON, Azure
/// visemes, character alignments) or an array (Azure viseme events; speech marks, which
/// become the one-object-per-line text Polly writes).
std::string InlineTimings(const json& value)
{
  if (value.is_string())
  {
    const std::string& text = value.get_ref<const std::string&>();
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    {
      throw FieldError{ reason::BadField, "'timings_inline' must not be empty" };
    }
    return text;
  }
  if (value.is_array() && !value.empty())
  {
    const bool marks = std::all_of(value.begin(), value.end(),
      [](const json& m) { return m.is_object() && m.contains("time") && m.contains("type"); });
    if (!marks)
    {
      return value.dump(-1, ' ', false, json::error_handler_t::replace);
    }
    std::string lines;
    for (const json& mark : value)
    {
      lines += mark.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
    }
    return lines;
  }
  if (value.is_object() && !value.empty())
  {
    return value.dump(-1, ' ', false, json::error_handler_t::replace);
  }
  throw FieldError{ reason::BadField,
    "'timings_inline' must be the timings' text (a string) or their JSON (a non-empty object "
    "or array)" };
}

CommandBody ParseBody(const std::string& cmd, const json& o)
{
  if (cmd == "say")
  {
    CheckKeys(o, "say",
      { "text", "voice", "audio", "timings", "timings_format", "audio_base64", "timings_inline" });
    SayCommand c;
    // External speech: a recording (and its timings) instead of synthesis; text optional.
    // By name (files in the avatar's speech folder) or inline (base64 bytes, timing text).
    c.Audio = GetString(o, "audio", false, true);
    if (o.contains("audio_base64"))
    {
      if (o.contains("audio"))
      {
        throw FieldError{ reason::BadField, "give 'audio' (a file) or 'audio_base64', not both" };
      }
      const std::string encoded = GetString(o, "audio_base64", true, true);
      try
      {
        c.AudioData = base64::Decode(encoded, "'audio_base64'");
      }
      catch (const InputError& e)
      {
        throw FieldError{ reason::BadField, e.what() };
      }
      if (c.AudioData.empty())
      {
        throw FieldError{ reason::BadField, "'audio_base64' holds no bytes" };
      }
    }
    c.Timings = GetString(o, "timings", false, true);
    c.TimingsFormat = GetString(o, "timings_format", false, true);
    auto inlineTimings = o.find("timings_inline");
    if (inlineTimings != o.end())
    {
      if (o.contains("timings"))
      {
        throw FieldError{ reason::BadField,
          "give 'timings' (a file) or 'timings_inline', not both" };
      }
      c.TimingsData = InlineTimings(*inlineTimings);
    }
    if (!c.HasRecording() &&
      (o.contains("timings") || o.contains("timings_inline") || o.contains("timings_format")))
    {
      throw FieldError{ reason::BadField,
        "'timings', 'timings_inline' and 'timings_format' go with 'audio' or 'audio_base64'" };
    }
    c.Text = GetString(o, "text", !c.HasRecording(), !c.HasRecording());
    c.Voice = GetString(o, "voice", false, false);
    if (o.contains("voice") && c.Voice.find_first_not_of(" \t") == std::string::npos)
    {
      throw FieldError{ reason::BadField,
        "'voice' must not be empty (leave it out for the avatar's voice)" };
    }
    return c;
  }
  if (cmd == "gesture")
  {
    CheckKeys(o, "gesture", { "name", "duration", "intensity" });
    GestureCommand c;
    c.Name = GetString(o, "name", true, true);
    c.Duration = GetDuration(o, "duration");
    c.Intensity = GetNumber(o, "intensity", false, 1.0, 0.0, 1.0);
    return c;
  }
  if (cmd == "mood")
  {
    CheckKeys(o, "mood", { "name", "intensity" });
    MoodCommand c;
    c.Name = GetString(o, "name", true, true);
    c.Intensity = GetNumber(o, "intensity", false, 1.0, 0.0, 1.0);
    return c;
  }
  if (cmd == "look_at")
  {
    CheckKeys(o, "look_at", { "yaw", "pitch", "duration" });
    LookAtCommand c;
    c.Yaw = GetNumber(o, "yaw", true, 0.0, -90.0, 90.0);
    c.Pitch = GetNumber(o, "pitch", true, 0.0, -90.0, 90.0);
    c.Duration = GetDuration(o, "duration");
    return c;
  }
  if (cmd == "stop")
  {
    CheckKeys(o, "stop", {});
    return StopCommand{};
  }
  if (cmd == "quit")
  {
    CheckKeys(o, "quit", {});
    return QuitCommand{};
  }
  throw FieldError{ reason::UnknownCmd,
    "unknown command '" + cmd.substr(0, 64) + "' (say, gesture, mood, look_at, stop, quit)" };
}
} // namespace

const char* CommandName(const CommandBody& body)
{
  static const char* const names[] = { "say", "gesture", "mood", "look_at", "stop", "quit" };
  return names[body.index()];
}

const char* EventName(EventKind kind)
{
  switch (kind)
  {
    case EventKind::Accepted:
      return "accepted";
    case EventKind::Started:
      return "started";
    case EventKind::Ended:
      return "ended";
    case EventKind::Error:
      break;
  }
  return "error";
}

Event::Event()
  : Time(NaN)
  , Start(NaN)
  , End(NaN)
  , Sound(NaN)
  , LatencyMs(NaN)
{
}

std::string FormatEvent(const Event& e)
{
  // In insertion order: "event" first, for people reading the stream.
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  j["event"] = EventName(e.Kind);
  if (!e.Id.empty())
  {
    // The id was validated and serialized by ParseCommand; parse it back to embed it.
    json id = json::parse(e.Id, nullptr, false);
    if (!id.is_discarded())
    {
      j["id"] = id;
    }
  }
  if (!e.Session.empty())
  {
    j["session"] = e.Session;
  }
  if (!e.Cmd.empty())
  {
    j["cmd"] = e.Cmd;
  }
  const auto number = [&j](const char* key, double value, double scale = 1e6)
  {
    if (std::isfinite(value))
    {
      j[key] = std::round(value * scale) / scale; // microseconds: short lines
    }
  };
  number("time", e.Time);
  number("start", e.Start);
  number("end", e.End);
  number("sound", e.Sound);
  number("latency_ms", e.LatencyMs, 1e3);
  if (e.Kind == EventKind::Ended)
  {
    j["interrupted"] = e.Interrupted;
  }
  if (!e.Reason.empty())
  {
    j["reason"] = e.Reason;
  }
  if (!e.Message.empty())
  {
    j["message"] = e.Message;
  }
  // Invalid UTF-8 (only possible in a message quoting input) is replaced, never thrown.
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

Event MakeError(const std::string& reasonCode, const std::string& message, const std::string& id,
  const std::string& cmd)
{
  Event e;
  e.Kind = EventKind::Error;
  e.Reason = reasonCode;
  e.Message = message;
  e.Id = id;
  e.Cmd = cmd;
  return e;
}

bool IsBlankLine(std::string_view line)
{
  for (char c : line)
  {
    if (c != ' ' && c != '\t' && c != '\r')
    {
      return false;
    }
  }
  return true;
}

ParsedLine ParseCommand(std::string_view line, size_t maxLineBytes)
{
  ParsedLine out;
  const auto fail = [&out](const char* code, const std::string& message)
  {
    out.Error = MakeError(code, message, out.Cmd.Id, out.Error.Cmd);
    return out;
  };
  if (!line.empty() && line.back() == '\r')
  {
    line.remove_suffix(1);
  }
  if (line.size() > maxLineBytes)
  {
    return fail(reason::TooLong,
      "the line has " + std::to_string(line.size()) + " bytes; the limit is " +
        std::to_string(maxLineBytes));
  }
  if (std::memchr(line.data(), '\0', line.size()) != nullptr)
  {
    return fail(reason::Malformed, "the line contains a NUL byte");
  }
  // Duplicate keys are refused, not resolved to the last one (a command must mean one
  // thing to every reader of the line).
  std::vector<std::set<std::string>> keys;
  std::string duplicate;
  const json::parser_callback_t noteKeys = [&keys, &duplicate](
                                             int, json::parse_event_t event, json& parsed)
  {
    if (event == json::parse_event_t::object_start)
    {
      keys.emplace_back();
    }
    else if (event == json::parse_event_t::object_end && !keys.empty())
    {
      keys.pop_back();
    }
    else if (event == json::parse_event_t::key && !keys.empty() && parsed.is_string() &&
      !keys.back().insert(parsed.get_ref<const std::string&>()).second && duplicate.empty())
    {
      duplicate = parsed.get<std::string>();
    }
    return true;
  };
  json j = json::parse(line.begin(), line.end(), noteKeys, false);
  if (j.is_discarded())
  {
    return fail(reason::Malformed, "not a JSON value (one JSON object per line)");
  }
  if (!duplicate.empty())
  {
    return fail(
      reason::Malformed, "the key '" + duplicate.substr(0, 64) + "' appears twice in one object");
  }
  if (!j.is_object())
  {
    return fail(reason::NotObject, std::string("a command is a JSON object, not ") + j.type_name());
  }
  // The id first, so that every later error echoes it.
  auto id = j.find("id");
  if (id != j.end())
  {
    const bool isInteger = id->is_number_integer() || id->is_number_unsigned();
    if (id->is_string() && id->get_ref<const std::string&>().size() <= MaxIdBytes)
    {
      out.Cmd.Id = id->dump(-1, ' ', false, json::error_handler_t::replace);
    }
    else if (isInteger)
    {
      out.Cmd.Id = id->dump();
    }
    else
    {
      return fail(reason::BadField,
        "'id' must be a string (at most " + std::to_string(MaxIdBytes) + " bytes) or an integer");
    }
  }
  auto session = j.find("session");
  if (session != j.end())
  {
    // MorphAvatar --serve: the stream session the command is for (StreamServer's ids).
    if (!session->is_string() || session->get_ref<const std::string&>().empty() ||
      session->get_ref<const std::string&>().size() > MaxSessionBytes)
    {
      return fail(reason::BadField,
        "'session' must be a non-empty string of at most " + std::to_string(MaxSessionBytes) +
          " bytes");
    }
    out.Cmd.Session = session->get<std::string>();
  }
  auto cmd = j.find("cmd");
  if (cmd == j.end())
  {
    return fail(reason::MissingCmd, "no 'cmd' field (say, gesture, mood, look_at, stop, quit)");
  }
  if (!cmd->is_string())
  {
    return fail(reason::BadField, "'cmd' must be a string");
  }
  const std::string& name = cmd->get_ref<const std::string&>();
  try
  {
    out.Cmd.Body = ParseBody(name, j);
  }
  catch (const FieldError& e)
  {
    if (std::string(e.Reason) != reason::UnknownCmd)
    {
      out.Error.Cmd = name;
    }
    return fail(e.Reason, e.Message);
  }
  return out;
}

LineFramer::LineFramer(size_t maxLineBytes)
  : MaxLineBytes(maxLineBytes)
{
}

void LineFramer::Reset()
{
  this->Buffer.clear();
  this->Pending = 0;
  this->Discarding = false;
}

std::vector<LineFramer::Item> LineFramer::Feed(const char* data, size_t size)
{
  std::vector<Item> items;
  size_t pos = 0;
  while (pos < size)
  {
    const void* found = std::memchr(data + pos, '\n', size - pos);
    const size_t end = found ? static_cast<size_t>(static_cast<const char*>(found) - data) : size;
    const size_t chunk = end - pos;
    this->Pending += chunk;
    // The limit counts the line without its newline; one byte of slack for a '\r'.
    if (!this->Discarding && this->Pending > this->MaxLineBytes + 1)
    {
      this->Discarding = true;
      this->Buffer.clear();
      this->Buffer.shrink_to_fit();
    }
    if (!this->Discarding)
    {
      this->Buffer.append(data + pos, chunk);
    }
    if (!found)
    {
      break;
    }
    Item item;
    item.Length = this->Pending;
    if (this->Discarding)
    {
      item.TooLong = true;
    }
    else
    {
      item.Line.swap(this->Buffer);
      if (item.Line.size() > this->MaxLineBytes &&
        !(item.Line.size() == this->MaxLineBytes + 1 && item.Line.back() == '\r'))
      {
        item.TooLong = true;
        item.Line.clear();
      }
    }
    items.push_back(std::move(item));
    this->Buffer.clear();
    this->Pending = 0;
    this->Discarding = false;
    pos = end + 1;
  }
  return items;
}
} // namespace dialog
} // namespace morphnode
