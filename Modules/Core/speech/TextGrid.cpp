// SPDX-License-Identifier: BSD-3-Clause
#include "speech/TextGrid.h"

#include "base/Error.h"
#include "base/Text.h"
#include "speech/Utf8.h"

#include <algorithm>
#include <cmath>

namespace morphnode
{
namespace
{
[[noreturn]] void Fail(const std::string& why)
{
  throw InputError("textgrid: " + why);
}

/// UTF-16 with a byte-order mark -> UTF-8; UTF-8 (with or without its mark) as it is.
std::string ToUtf8(const std::string& bytes)
{
  const auto b = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
  if (bytes.size() >= 3 && b(0) == 0xEF && b(1) == 0xBB && b(2) == 0xBF)
  {
    return bytes.substr(3);
  }
  const bool le = bytes.size() >= 2 && b(0) == 0xFF && b(1) == 0xFE;
  const bool be = bytes.size() >= 2 && b(0) == 0xFE && b(1) == 0xFF;
  if (!le && !be)
  {
    return bytes;
  }
  if (bytes.size() % 2 != 0)
  {
    Fail("UTF-16 text with an odd number of bytes");
  }
  std::u16string units;
  units.reserve(bytes.size() / 2);
  for (size_t i = 2; i + 1 < bytes.size(); i += 2)
  {
    units.push_back(
      static_cast<char16_t>(le ? (b(i) | (b(i + 1) << 8)) : ((b(i) << 8) | b(i + 1))));
  }
  try
  {
    return Utf16ToUtf8(units);
  }
  catch (const InputError& e)
  {
    Fail(std::string("UTF-16 text: ") + e.what());
  }
}

/// Praat's text formats as one stream of values: quoted strings ("" inside is a quote),
/// numbers and <flags>. The long format's labels (`xmin =`, `item [1]:`, `intervals: size
/// =`) are skipped: words, `=`, `:`, bracketed indices; `!` starts a comment.
class Tokens
{
public:
  explicit Tokens(std::string text)
    : Text(std::move(text))
  {
  }

  std::string String(const char* what)
  {
    const Token t = this->Next(what);
    if (!t.IsString)
    {
      Fail("expected a quoted text for " + std::string(what) + ", found " + text::Quote(t.Value) +
        this->Where());
    }
    return t.Value;
  }

  double Number(const char* what)
  {
    const Token t = this->Next(what);
    double v = 0.0;
    if (t.IsString || !text::ParseNumber(t.Value, v))
    {
      Fail("expected a number for " + std::string(what) + ", found " + text::Quote(t.Value) +
        this->Where());
    }
    return v;
  }

  size_t Count(const char* what, size_t limit)
  {
    const double v = this->Number(what);
    if (v < 0 || v != std::floor(v) || v > static_cast<double>(limit))
    {
      Fail(std::string(what) + " is not a plausible count (" + text::FormatNumber(v) + ")" +
        this->Where());
    }
    return static_cast<size_t>(v);
  }

  std::string Flag(const char* what)
  {
    const Token t = this->Next(what);
    if (t.IsString || t.Value.empty() || t.Value.front() != '<')
    {
      Fail("expected <exists> or <absent> for " + std::string(what) + this->Where());
    }
    return t.Value;
  }

  /// Bytes left: an upper bound for any count still to read.
  size_t Remaining() const { return this->Text.size() - this->Pos; }

private:
  struct Token
  {
    std::string Value;
    bool IsString = false;
  };

  std::string Where() const { return " (line " + std::to_string(this->Line) + ")"; }

  Token Next(const char* what)
  {
    const std::string& s = this->Text;
    while (this->Pos < s.size())
    {
      const char c = s[this->Pos];
      if (c == '\n')
      {
        ++this->Line;
        ++this->Pos;
      }
      else if (c == ' ' || c == '\t' || c == '\r' || c == '=' || c == ':' || c == ',')
      {
        ++this->Pos;
      }
      else if (c == '!')
      {
        while (this->Pos < s.size() && s[this->Pos] != '\n')
        {
          ++this->Pos;
        }
      }
      else if (c == '[')
      {
        const size_t close = s.find(']', this->Pos);
        if (close == std::string::npos)
        {
          Fail("unclosed '['" + this->Where());
        }
        this->Pos = close + 1;
      }
      else if (c == '"')
      {
        Token t;
        t.IsString = true;
        ++this->Pos;
        for (;;)
        {
          if (this->Pos >= s.size())
          {
            Fail("a quoted text is not closed" + this->Where());
          }
          const char d = s[this->Pos++];
          if (d == '"')
          {
            if (this->Pos < s.size() && s[this->Pos] == '"')
            {
              t.Value += '"';
              ++this->Pos;
              continue;
            }
            break;
          }
          if (d == '\n')
          {
            ++this->Line;
          }
          t.Value += d;
        }
        return t;
      }
      else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_')
      {
        // A label word of the long format (xmin, item, class, intervals, size, text, ...).
        while (this->Pos < s.size() &&
          (std::isalnum(static_cast<unsigned char>(s[this->Pos])) || s[this->Pos] == '_' ||
            s[this->Pos] == '?'))
        {
          ++this->Pos;
        }
      }
      else
      {
        Token t;
        while (this->Pos < s.size() && s[this->Pos] != ' ' && s[this->Pos] != '\t' &&
          s[this->Pos] != '\r' && s[this->Pos] != '\n' && s[this->Pos] != '"')
        {
          t.Value += s[this->Pos++];
        }
        return t;
      }
    }
    Fail("the file ends before " + std::string(what));
  }

  std::string Text;
  size_t Pos = 0;
  size_t Line = 1;
};

void CheckTime(double t, const TextGrid& grid, const std::string& where)
{
  // Praat writes times with 15+ digits; allow rounding at the grid's edges.
  const double slack = 1e-6 * std::max(1.0, std::abs(grid.End));
  if (t < grid.Start - slack || t > grid.End + slack)
  {
    Fail(where + ": time " + text::FormatNumber(t) + " outside the grid [" +
      text::FormatNumber(grid.Start) + ", " + text::FormatNumber(grid.End) + "]");
  }
}
} // namespace

const TextGridTier* TextGrid::FindTier(const std::string& name) const
{
  const std::string wanted = text::ToLower(name);
  for (const TextGridTier& tier : this->Tiers)
  {
    if (text::ToLower(tier.Name) == wanted)
    {
      return &tier;
    }
  }
  return nullptr;
}

TextGrid ParseTextGrid(const std::string& bytes)
{
  if (bytes.compare(0, 12, "ooBinaryFile") == 0)
  {
    Fail("binary TextGrids are not read; save it from Praat as a text file");
  }
  Tokens tokens(ToUtf8(bytes));
  if (tokens.String("the file type") != "ooTextFile")
  {
    Fail("not a Praat text file (File type = \"ooTextFile\" expected)");
  }
  const std::string objectClass = tokens.String("the object class");
  if (objectClass != "TextGrid")
  {
    Fail("the file holds a " + text::Quote(objectClass) + ", not a TextGrid");
  }
  TextGrid grid;
  grid.Start = tokens.Number("xmin");
  grid.End = tokens.Number("xmax");
  if (!(grid.End >= grid.Start))
  {
    Fail("the grid ends before it starts");
  }
  if (tokens.Flag("tiers?") != "<exists>")
  {
    return grid; // a grid without tiers
  }
  // Every tier and item takes several bytes: counts larger than the file are lies.
  const size_t tierCount = tokens.Count("the tier count", tokens.Remaining());
  for (size_t t = 0; t < tierCount; ++t)
  {
    TextGridTier tier;
    const std::string where = "tier " + std::to_string(t + 1);
    const std::string tierClass = tokens.String("the tier class");
    if (tierClass == "IntervalTier")
    {
      tier.IsInterval = true;
    }
    else if (tierClass == "TextTier")
    {
      tier.IsInterval = false;
    }
    else
    {
      Fail(where + ": unknown tier class " + text::Quote(tierClass));
    }
    tier.Name = tokens.String("the tier name");
    const double tierStart = tokens.Number("the tier's xmin");
    const double tierEnd = tokens.Number("the tier's xmax");
    if (!(tierEnd >= tierStart))
    {
      Fail(where + " (" + text::Quote(tier.Name) + ") ends before it starts");
    }
    const size_t count = tokens.Count("the interval count", tokens.Remaining() / 2);
    double previousEnd = -INFINITY;
    for (size_t i = 0; i < count; ++i)
    {
      TextGridInterval item;
      const std::string itemWhere =
        where + " (" + text::Quote(tier.Name) + ") item " + std::to_string(i + 1);
      item.Start = tokens.Number("a time");
      item.End = tier.IsInterval ? tokens.Number("an interval end") : item.Start;
      item.Text = tokens.String("a label");
      if (item.End < item.Start)
      {
        Fail(itemWhere + " ends (" + text::FormatNumber(item.End) + ") before it starts (" +
          text::FormatNumber(item.Start) + ")");
      }
      const double slack = 1e-9 * std::max(1.0, std::abs(item.Start));
      if (item.Start < previousEnd - slack ||
        (!tier.IsInterval && item.Start <= previousEnd && i > 0))
      {
        Fail(itemWhere + " starts at " + text::FormatNumber(item.Start) +
          ", before the previous one ends: times out of order or overlapping");
      }
      CheckTime(item.Start, grid, itemWhere);
      CheckTime(item.End, grid, itemWhere);
      previousEnd = item.End;
      tier.Items.push_back(std::move(item));
    }
    grid.Tiers.push_back(std::move(tier));
  }
  return grid;
}

TextGrid ReadTextGridFile(const std::string& path)
{
  const std::string bytes = text::ReadFile(path, "TextGrid file");
  try
  {
    return ParseTextGrid(bytes);
  }
  catch (const InputError& e)
  {
    throw InputError("'" + path + "': " + e.what());
  }
}

std::vector<TimedPhoneme> TextGridPhonemes(
  const TextGrid& grid, const TextGridPhoneOptions& options)
{
  const TextGridTier* tier = nullptr;
  if (!options.TierName.empty())
  {
    tier = grid.FindTier(options.TierName);
  }
  else
  {
    for (const char* name :
      { "phones", "phone", "phonemes", "phoneme", "segments", "MAU", "PhoneTier" })
    {
      const TextGridTier* candidate = grid.FindTier(name);
      if (candidate && candidate->IsInterval)
      {
        tier = candidate;
        break;
      }
    }
  }
  if (!tier || !tier->IsInterval)
  {
    std::string names;
    for (const TextGridTier& t : grid.Tiers)
    {
      names +=
        (names.empty() ? "" : ", ") + text::Quote(t.Name) + (t.IsInterval ? "" : " (points)");
    }
    const std::string wanted = options.TierName.empty()
      ? std::string("no phone tier (looked for phones, phone, phonemes, segments, MAU)")
      : (tier ? "tier " + text::Quote(options.TierName) + " is a point tier, not intervals"
              : "no tier " + text::Quote(options.TierName));
    Fail(wanted + "; the file has " + (names.empty() ? std::string("no tiers") : names));
  }
  std::vector<std::string> labels;
  for (const TextGridInterval& item : tier->Items)
  {
    labels.push_back(item.Text);
  }
  const PhoneAlphabet alphabet =
    options.Alphabet == PhoneAlphabet::Auto ? GuessPhoneAlphabet(labels) : options.Alphabet;

  std::vector<TimedPhoneme> phonemes;
  auto add = [&](const std::string& name, double start, double end)
  {
    if (!(end > start))
    {
      return;
    }
    if (name == "_" && !phonemes.empty() && phonemes.back().Sampa == "_")
    {
      phonemes.back().Duration = end - phonemes.back().Start; // merge pauses
      return;
    }
    TimedPhoneme p;
    p.Sampa = name;
    p.Start = start;
    p.Duration = end - start;
    phonemes.push_back(std::move(p));
  };
  double cursor =
    std::min(grid.Start, tier->Items.empty() ? grid.Start : tier->Items.front().Start);
  for (const TextGridInterval& item : tier->Items)
  {
    add("_", cursor, item.Start);
    add(PhoneLabelToSampa(item.Text, alphabet, options.Language), item.Start, item.End);
    cursor = std::max(cursor, item.End);
  }
  add("_", cursor, grid.End);
  if (phonemes.empty() ||
    std::all_of(
      phonemes.begin(), phonemes.end(), [](const TimedPhoneme& p) { return p.Sampa == "_"; }))
  {
    Fail("the phone tier " + text::Quote(tier->Name) + " holds no phones");
  }
  return phonemes;
}
} // namespace morphnode
