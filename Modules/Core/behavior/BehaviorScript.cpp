// SPDX-License-Identifier: BSD-3-Clause
#include "behavior/BehaviorScript.h"

#include "base/Error.h"
#include "base/LibraryMessage.h"
#include "base/Text.h"
#include "behavior/BehaviorTypes.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

namespace morphnode
{
namespace
{
using Json = nlohmann::json;
const char* const LineKey = "__line"; // where the JSON parser notes each object's line

[[noreturn]] void Fail(int line, const std::string& message)
{
  throw InputError("line " + std::to_string(line) + ": " + message);
}

std::string Shorten(const std::string& s)
{
  return s.size() > 64 ? s.substr(0, 64) + "..." : s;
}

double ParseNumber(const std::string& token, const char* what)
{
  double v = 0.0;
  if (!text::ParseNumber(token, v))
  {
    throw InputError(std::string(what) + ": '" + Shorten(token) + "' is not a number");
  }
  return v;
}

void CheckRange(double v, double lo, double hi, const char* what)
{
  if (!(v >= lo && v <= hi))
  {
    std::ostringstream msg;
    msg << what << " " << v << " is outside [" << lo << ", " << hi << "]";
    throw InputError(msg.str());
  }
}

/// The checks shared by both formats; names are canonicalized, ranges enforced.
void Validate(BehaviorCommand& c)
{
  CheckRange(c.Start, 0.0, MaxBehaviorTime, "start time");
  CheckBehaviorDuration(c.Duration, "duration");
  if (c.Fade >= 0.0)
  {
    CheckBehaviorDuration(c.Fade, "fade");
  }
  CheckRange(c.Intensity, 0.0, 1.0, "intensity");
  switch (c.Type)
  {
    case BehaviorCommand::Kind::Gesture:
      c.Text = GestureName(ParseGestureName(c.Text));
      break;
    case BehaviorCommand::Kind::Mood:
      c.Text = MoodName(ParseMoodName(c.Text));
      break;
    case BehaviorCommand::Kind::Look:
      CheckRange(c.Yaw, -90.0, 90.0, "look yaw");
      CheckRange(c.Pitch, -90.0, 90.0, "look pitch");
      break;
    case BehaviorCommand::Kind::Say:
    case BehaviorCommand::Kind::Phonemes:
      if (c.Text.empty())
      {
        throw InputError(
          c.Type == BehaviorCommand::Kind::Say ? "say needs a text" : "phonemes needs a file name");
      }
      break;
  }
}

void CheckSettings(BehaviorScript& s)
{
  if (s.FrameRate)
  {
    CheckRange(*s.FrameRate, 1e-3, 1000.0, "fps");
  }
  if (s.Duration)
  {
    CheckRange(*s.Duration, 0.0, MaxBehaviorTime, "duration");
  }
}

} // namespace

void CheckBehaviorDuration(double v, const char* what)
{
  if (v != 0.0)
  {
    CheckRange(v, MinBehaviorDuration, MaxBehaviorTime, what);
  }
  if (!(v >= 0.0 && v <= MaxBehaviorTime))
  {
    CheckRange(v, 0.0, MaxBehaviorTime, what);
  }
}

namespace
{
// ---------------------------------------------------------------- text format

/// Splits a line into words; "double quoted" words may hold blanks and \" \\ escapes;
/// a word starting with '#' starts a comment.
std::vector<std::string> Tokenize(const std::string& line)
{
  std::vector<std::string> words;
  size_t i = 0;
  while (i < line.size())
  {
    const char c = line[i];
    if (std::isspace(static_cast<unsigned char>(c)))
    {
      ++i;
      continue;
    }
    if (c == '#')
    {
      break;
    }
    std::string word;
    if (c == '"')
    {
      ++i;
      bool closed = false;
      while (i < line.size())
      {
        char d = line[i++];
        if (d == '"')
        {
          closed = true;
          break;
        }
        if (d == '\\' && i < line.size())
        {
          d = line[i++];
        }
        word += d;
      }
      if (!closed)
      {
        throw InputError("unterminated quoted text");
      }
    }
    else
    {
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i])))
      {
        word += line[i++];
      }
    }
    words.push_back(std::move(word));
  }
  return words;
}

/// Reads "key value" pairs from words[from...] into the command.
void ParseOptions(const std::vector<std::string>& w, size_t from, BehaviorCommand& c,
  std::initializer_list<const char*> allowed)
{
  for (size_t i = from; i < w.size(); i += 2)
  {
    const std::string key = text::ToLower(w[i]);
    bool ok = false;
    for (const char* a : allowed)
    {
      ok = ok || key == a;
    }
    if (!ok)
    {
      throw InputError("unexpected '" + Shorten(w[i]) + "'");
    }
    if (i + 1 >= w.size())
    {
      throw InputError("'" + key + "' needs a value");
    }
    const double v = ParseNumber(w[i + 1], key.c_str());
    if (key == "duration")
    {
      c.Duration = v;
    }
    else if (key == "intensity")
    {
      c.Intensity = v;
    }
    else
    {
      CheckRange(v, 0.0, MaxBehaviorTime, "fade");
      c.Fade = v;
    }
  }
}

BehaviorCommand ParseTextCommand(const std::vector<std::string>& w)
{
  // w[0] is "at"
  if (w.size() < 3)
  {
    throw InputError("expected 'at <time> <command> ...'");
  }
  BehaviorCommand c;
  c.Start = ParseNumber(w[1], "time");
  const std::string verb = text::ToLower(w[2]);
  if (verb == "say")
  {
    c.Type = BehaviorCommand::Kind::Say;
    for (size_t i = 3; i < w.size(); ++i)
    {
      c.Text += (i > 3 ? " " : "") + w[i];
    }
  }
  else if (verb == "phonemes")
  {
    c.Type = BehaviorCommand::Kind::Phonemes;
    if (w.size() != 4)
    {
      throw InputError("expected 'phonemes <file>'");
    }
    c.Text = w[3];
  }
  else if (verb == "gesture")
  {
    c.Type = BehaviorCommand::Kind::Gesture;
    if (w.size() < 4)
    {
      throw InputError("expected 'gesture <name> [duration <s>] [intensity <0..1>]'");
    }
    c.Text = w[3];
    ParseOptions(w, 4, c, { "duration", "intensity" });
  }
  else if (verb == "mood")
  {
    c.Type = BehaviorCommand::Kind::Mood;
    if (w.size() < 4)
    {
      throw InputError("expected 'mood <name> [<intensity>] [fade <s>]'");
    }
    c.Text = w[3];
    size_t next = 4;
    if (w.size() > 4 && text::ToLower(w[4]) != "fade")
    {
      c.Intensity = ParseNumber(w[4], "mood intensity");
      next = 5;
    }
    ParseOptions(w, next, c, { "fade" });
  }
  else if (verb == "look")
  {
    c.Type = BehaviorCommand::Kind::Look;
    if (w.size() < 5)
    {
      throw InputError("expected 'look <yaw> <pitch> [duration <s>]'");
    }
    c.Yaw = ParseNumber(w[3], "look yaw");
    c.Pitch = ParseNumber(w[4], "look pitch");
    ParseOptions(w, 5, c, { "duration" });
  }
  else
  {
    throw InputError(
      "unknown command '" + Shorten(w[2]) + "' (known: say, phonemes, gesture, mood, look)");
  }
  Validate(c);
  return c;
}

BehaviorScript ParseText(const std::string& text)
{
  BehaviorScript script;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line))
  {
    ++number;
    try
    {
      const std::vector<std::string> w = Tokenize(line);
      if (w.empty())
      {
        continue;
      }
      const std::string head = text::ToLower(w[0]);
      if (head == "at")
      {
        BehaviorCommand c = ParseTextCommand(w);
        c.Line = number;
        script.Commands.push_back(std::move(c));
        continue;
      }
      if (w.size() != 2)
      {
        throw InputError("expected 'at <time> <command> ...', 'seed <n>', 'fps <rate>' or "
                         "'duration <s>', got '" +
          Shorten(w[0]) + "'");
      }
      if (head == "seed")
      {
        uint64_t seed = 0;
        const auto r = std::from_chars(w[1].data(), w[1].data() + w[1].size(), seed);
        if (r.ec != std::errc() || r.ptr != w[1].data() + w[1].size())
        {
          throw InputError("seed: '" + Shorten(w[1]) + "' is not an unsigned integer");
        }
        script.Seed = seed;
      }
      else if (head == "fps" || head == "framerate")
      {
        script.FrameRate = ParseNumber(w[1], "fps");
      }
      else if (head == "duration")
      {
        script.Duration = ParseNumber(w[1], "duration");
      }
      else
      {
        throw InputError("unknown setting '" + Shorten(w[0]) + "' (known: seed, fps, duration)");
      }
      CheckSettings(script);
    }
    catch (const InputError& e)
    {
      Fail(number, e.what());
    }
  }
  return script;
}

// ---------------------------------------------------------------- JSON

/// A char iterator that counts the newlines it passes, so that the JSON parser's callback
/// knows the line it is on.
struct LineCountingIterator
{
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  const char* Position = nullptr;
  int* Line = nullptr;

  reference operator*() const { return *this->Position; }
  LineCountingIterator& operator++()
  {
    if (*this->Position == '\n')
    {
      ++*this->Line;
    }
    ++this->Position;
    return *this;
  }
  LineCountingIterator operator++(int)
  {
    LineCountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const LineCountingIterator& o) const { return this->Position == o.Position; }
  bool operator!=(const LineCountingIterator& o) const { return this->Position != o.Position; }
};

int LineOf(const Json& object, int fallback)
{
  if (object.is_object())
  {
    auto it = object.find(LineKey);
    if (it != object.end() && it->is_number_integer())
    {
      return it->get<int>();
    }
  }
  return fallback;
}

double JsonNumber(const Json& v, const char* what)
{
  if (!v.is_number())
  {
    throw InputError(std::string("'") + what + "' must be a number");
  }
  const double d = v.get<double>();
  if (!std::isfinite(d))
  {
    throw InputError(std::string("'") + what + "' must be finite");
  }
  return d;
}

std::string JsonString(const Json& v, const char* what)
{
  if (!v.is_string())
  {
    throw InputError(std::string("'") + what + "' must be a string");
  }
  return v.get<std::string>();
}

BehaviorCommand ParseJsonCommand(const Json& j)
{
  if (!j.is_object())
  {
    throw InputError("a command must be an object like {\"at\": 0, \"gesture\": \"nod\"}");
  }
  BehaviorCommand c;
  bool hasAt = false;
  int kinds = 0;
  for (auto it = j.begin(); it != j.end(); ++it)
  {
    const std::string& key = it.key();
    const Json& v = it.value();
    if (key == LineKey)
    {
      continue;
    }
    if (key == "at")
    {
      c.Start = JsonNumber(v, "at");
      hasAt = true;
    }
    else if (key == "duration")
    {
      c.Duration = JsonNumber(v, "duration");
    }
    else if (key == "intensity")
    {
      c.Intensity = JsonNumber(v, "intensity");
    }
    else if (key == "fade")
    {
      c.Fade = JsonNumber(v, "fade");
      CheckRange(c.Fade, 0.0, MaxBehaviorTime, "fade");
    }
    else if (key == "say" || key == "phonemes" || key == "gesture" || key == "mood")
    {
      ++kinds;
      c.Type = key == "say" ? BehaviorCommand::Kind::Say
        : key == "phonemes" ? BehaviorCommand::Kind::Phonemes
        : key == "gesture"  ? BehaviorCommand::Kind::Gesture
                            : BehaviorCommand::Kind::Mood;
      c.Text = JsonString(v, key.c_str());
    }
    else if (key == "look")
    {
      ++kinds;
      c.Type = BehaviorCommand::Kind::Look;
      if (v.is_array() && v.size() == 2)
      {
        c.Yaw = JsonNumber(v[0], "look yaw");
        c.Pitch = JsonNumber(v[1], "look pitch");
      }
      else if (v.is_object() && v.size() == 2 && v.contains("yaw") && v.contains("pitch"))
      {
        c.Yaw = JsonNumber(v["yaw"], "look yaw");
        c.Pitch = JsonNumber(v["pitch"], "look pitch");
      }
      else
      {
        throw InputError("'look' must be [yaw, pitch] or {\"yaw\": .., \"pitch\": ..}");
      }
    }
    else
    {
      throw InputError("unknown key '" + Shorten(key) +
        "' (known: at, say, phonemes, gesture, mood, look, duration, intensity, fade)");
    }
  }
  if (!hasAt)
  {
    throw InputError("a command needs \"at\" (its start time in seconds)");
  }
  if (kinds != 1)
  {
    throw InputError("a command needs exactly one of say, phonemes, gesture, mood, look");
  }
  Validate(c);
  return c;
}

BehaviorScript ParseJson(const std::string& text)
{
  int line = 1;
  std::vector<int> openLines;
  Json root;
  const Json::parser_callback_t noteLines = [&](int, Json::parse_event_t event, Json& parsed)
  {
    if (event == Json::parse_event_t::object_start)
    {
      openLines.push_back(line);
    }
    else if (event == Json::parse_event_t::object_end && !openLines.empty())
    {
      parsed[LineKey] = openLines.back();
      openLines.pop_back();
    }
    return true;
  };
  try
  {
    LineCountingIterator first{ text.data(), &line }, last{ text.data() + text.size(), &line };
    root = Json::parse(first, last, noteLines);
  }
  catch (const Json::exception& e)
  {
    Fail(line, std::string("invalid JSON: ") + text::LibraryMessage(e.what()));
  }

  BehaviorScript script;
  const int rootLine = LineOf(root, 1);
  const Json* commands = &root;
  if (root.is_object())
  {
    commands = nullptr;
    for (auto it = root.begin(); it != root.end(); ++it)
    {
      const std::string& key = it.key();
      try
      {
        if (key == LineKey)
        {
          continue;
        }
        if (key == "seed")
        {
          if (!it->is_number_unsigned())
          {
            throw InputError("'seed' must be an unsigned integer");
          }
          script.Seed = it->get<uint64_t>();
        }
        else if (key == "fps")
        {
          script.FrameRate = JsonNumber(*it, "fps");
        }
        else if (key == "duration")
        {
          script.Duration = JsonNumber(*it, "duration");
        }
        else if (key == "commands")
        {
          commands = &*it;
        }
        else
        {
          throw InputError(
            "unknown key '" + Shorten(key) + "' (known: seed, fps, duration, commands)");
        }
        CheckSettings(script);
      }
      catch (const InputError& e)
      {
        Fail(rootLine, e.what());
      }
    }
    if (!commands)
    {
      return script;
    }
  }
  if (!commands->is_array())
  {
    Fail(rootLine, "expected an array of commands");
  }
  int previousLine = rootLine;
  for (const Json& j : *commands)
  {
    const int at = LineOf(j, previousLine);
    try
    {
      BehaviorCommand c = ParseJsonCommand(j);
      c.Line = at;
      script.Commands.push_back(std::move(c));
    }
    catch (const InputError& e)
    {
      Fail(at, e.what());
    }
    previousLine = at;
  }
  return script;
}
} // namespace

BehaviorScript ParseBehaviorScript(const std::string& input)
{
  std::string text = input;
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0)
  {
    text.erase(0, 3); // UTF-8 byte order mark
  }
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (text[first] == '{' || text[first] == '['))
  {
    return ParseJson(text);
  }
  return ParseText(text);
}

BehaviorScript LoadBehaviorScript(const std::string& path)
{
  const std::string content = text::ReadFile(path, "behaviour script");
  BehaviorScript script;
  try
  {
    script = ParseBehaviorScript(content);
  }
  catch (const InputError& e)
  {
    throw InputError(path + ": " + e.what());
  }
  const size_t slash = path.find_last_of('/');
  script.BaseDirectory = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  return script;
}
} // namespace morphnode
