// SPDX-License-Identifier: BSD-3-Clause
#include "CommandLine.h"

#include "Messages.h"

#include "base/Error.h"
#include "base/Text.h"

#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>

namespace morphnode
{
namespace appkit
{
namespace
{
/// "640x480" -> (640, 480); false when it is not two integers joined by 'x'.
bool ParseSize(const std::string& s, int& width, int& height)
{
  const auto x = s.find_first_of("xX");
  return x != std::string::npos && text::ParseNumber(std::string_view(s).substr(0, x), width) &&
    text::ParseNumber(std::string_view(s).substr(x + 1), height);
}
/// CLI11's formatter with option descriptions wrapped to the terminal's usual 80 columns.
class WrappingFormatter : public CLI::Formatter
{
public:
  std::string make_option_desc(const CLI::Option* option) const override
  {
    const size_t width = 80 > this->get_column_width() + 20 ? 80 - this->get_column_width() : 20;
    std::string out, line, word;
    std::istringstream words(option->get_description());
    while (words >> word)
    {
      if (!line.empty() && line.size() + 1 + word.size() > width)
      {
        out += line + "\n";
        line.clear();
      }
      line += (line.empty() ? "" : " ") + word;
    }
    return out + line;
  }
};
} // namespace

void ParseCommandLine(CLI::App& app, int argc, char** argv)
{
  auto formatter = std::make_shared<WrappingFormatter>();
  formatter->column_width(app.get_formatter()->get_column_width());
  app.formatter(formatter);
  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::Success& e) // --help
  {
    std::exit(app.exit(e));
  }
  catch (const CLI::ParseError& e)
  {
    FailUsage(app, e.what());
  }
  // Content errors from here on read `Program: what: why`, not as VTK's log lines.
  UseProgramMessages(app.get_name());
}

void FailUsage(const CLI::App& app, const std::string& message)
{
  std::cerr << app.get_name() << ": " << message << "\n(see " << app.get_name() << " --help)\n";
  std::exit(2);
}

CLI::Validator NumberIn(double lo, double hi)
{
  return CLI::Validator(
    [lo, hi](std::string& value) -> std::string
    {
      double v = 0.0;
      if (!text::ParseNumber(value, v))
      {
        return "expects a number, got '" + value + "'";
      }
      if (v < lo || v > hi)
      {
        return "must be in [" + text::FormatNumber(lo) + ", " + text::FormatNumber(hi) + "], got " +
          value;
      }
      return std::string();
    },
    std::string()); // the option's help gives the range
}

CLI::Validator UnsignedInteger()
{
  return CLI::Validator(
    [](std::string& value) -> std::string
    {
      unsigned long long v = 0;
      if (!text::ParseNumber(value, v))
      {
        return "expects an unsigned integer, got '" + value + "'";
      }
      return std::string();
    },
    std::string());
}

CLI::Option* AddNumberOption(CLI::App& app, const std::string& name, double& value, double lo,
  double hi, const std::string& help)
{
  // Parsed here (locale-independent), so CLI11 sees only the validated text.
  return app
    .add_option_function<std::string>(
      name, [&value](const std::string& s) { text::ParseNumber(s, value); }, help)
    ->check(NumberIn(lo, hi))
    ->type_name("NUMBER")
    ->default_str(text::FormatNumber(value));
}

CLI::Option* AddSizeOption(CLI::App& app, const std::string& name, int& width, int& height,
  const std::string& help, int lo, int hi)
{
  CLI::Validator size(
    [lo, hi](std::string& s) -> std::string
    {
      int w = 0, h = 0;
      if (!ParseSize(s, w, h) || w < lo || h < lo || w > hi || h > hi)
      {
        return "expects WxH with " + std::to_string(lo) + " <= W, H <= " + std::to_string(hi) +
          ", e.g. 640x480; got '" + s + "'";
      }
      return std::string();
    },
    std::string());
  return app
    .add_option_function<std::string>(
      name, [&width, &height](const std::string& s) { ParseSize(s, width, height); }, help)
    ->check(size)
    ->type_name("WxH")
    ->default_str(std::to_string(width) + "x" + std::to_string(height));
}

CLI::Option* AddNumberListOption(CLI::App& app, const std::string& name,
  std::vector<double>& values, double lo, double hi, const std::string& help)
{
  std::string defaults;
  for (double v : values)
  {
    defaults += (defaults.empty() ? "" : ",") + text::FormatNumber(v);
  }
  return app
    .add_option_function<std::vector<std::string>>(
      name,
      [&values](const std::vector<std::string>& items)
      {
        values.clear();
        for (const auto& item : items)
        {
          double v = 0.0;
          text::ParseNumber(item, v);
          values.push_back(v);
        }
      },
      help)
    ->delimiter(',')
    ->check(NumberIn(lo, hi))
    ->type_name("LIST")
    ->default_str(defaults);
}

CLI::Option* AddOptimizerPresetOption(
  CLI::App& app, const std::string& name, OptimizerPreset& preset, const std::string& help)
{
  CLI::Validator known(
    [](std::string& s) -> std::string
    {
      try
      {
        ParseOptimizerPreset(s);
      }
      catch (const InputError& e)
      {
        return e.what();
      }
      return std::string();
    },
    std::string());
  return app
    .add_option_function<std::string>(
      name, [&preset](const std::string& s) { preset = ParseOptimizerPreset(s); }, help)
    ->check(known)
    ->type_name("METHOD")
    ->default_str(OptimizerPresetName(preset));
}

std::string OptimizerPresetChoices()
{
  std::string choices;
  for (int i = 0; i < NumberOfOptimizerPresets; ++i)
  {
    choices += (i ? ", " : "") + std::to_string(i) + "|" +
      OptimizerPresetName(static_cast<OptimizerPreset>(i));
  }
  return choices;
}
} // namespace appkit
} // namespace morphnode
