// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file CommandLine.h
/// @brief The command lines of the MorphNode programs, on CLI11: one way to parse and to
/// report errors (exit code 2, "<program>: <message>" and a pointer to --help), and the
/// option types the programs share: numbers in a range (read without the locale), WxH
/// sizes, lists of numbers, seeds and optimizer methods (morph/OptimizerPresets.h).

#include "morph/OptimizerPresets.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace morphnode
{
namespace appkit
{
/// Parses the command line into `app`. --help prints the help and exits with 0; an error
/// prints "<program>: <message>" and "(see <program> --help)" to stderr and exits with 2.
/// Then VTK's errors print as "<program>: <message>" too (UseProgramMessages, Messages.h).
void ParseCommandLine(CLI::App& app, int argc, char** argv);

/// A usage error found after parsing (e.g. options that do not go together): prints it as
/// ParseCommandLine does and exits with 2.
[[noreturn]] void FailUsage(const CLI::App& app, const std::string& message);

/// A finite number in [lo, hi]: "expects a number, got 'x'" or "must be in [lo, hi], got x".
CLI::Validator NumberIn(double lo, double hi);

/// An unsigned integer written in digits ("-3" is refused, not wrapped around).
CLI::Validator UnsignedInteger();

/// A number option in [lo, hi] (locale-independent; the default shown in the help).
CLI::Option* AddNumberOption(CLI::App& app, const std::string& name, double& value, double lo,
  double hi, const std::string& help);

/// A WxH option ("640x480"), both sides in [lo, hi].
CLI::Option* AddSizeOption(CLI::App& app, const std::string& name, int& width, int& height,
  const std::string& help, int lo = 16, int hi = 8192);

/// A comma-separated list of numbers in [lo, hi], e.g. "0.1,0.2,0.3".
CLI::Option* AddNumberListOption(CLI::App& app, const std::string& name,
  std::vector<double>& values, double lo, double hi, const std::string& help);

/// An optimizer method by name or number, as ParseOptimizerPreset reads it.
CLI::Option* AddOptimizerPresetOption(
  CLI::App& app, const std::string& name, OptimizerPreset& preset, const std::string& help);

/// "0|none, 1|fixed-maximum, ..." for help texts.
std::string OptimizerPresetChoices();
} // namespace appkit
} // namespace morphnode
