// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file BehaviorScript.h
/// @brief Behaviour commands from a script: a line-based text format or JSON (both in
/// docs/behavior.md). Parsing only checks and collects; BehaviorController::Apply runs them.
///
/// Text:                                  JSON:
///   seed 42                                {"seed": 42, "fps": 30, "duration": 6,
///   fps 30                                  "commands": [
///   duration 6                                {"at": 0, "mood": "happy", "intensity": 0.6},
///   at 0 mood happy 0.6 fade 1                {"at": 0.5, "say": "Hello world"},
///   at 0.5 say "Hello world"                  {"at": 1, "gesture": "nod", "duration": 0.8},
///   at 1.0 gesture nod duration 0.8           {"at": 2, "look": [10, -5], "duration": 1},
///   at 2 look 10 -5 duration 1                {"at": 3, "phonemes": "hello.pho"}]}
///   at 3 phonemes hello.pho
///
/// Any malformed input throws InputError whose message starts with "line N: ".

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace morphnode
{
struct BehaviorCommand
{
  enum class Kind
  {
    Say,      ///< Text: what to say (through the controller's synthesizer)
    Phonemes, ///< Text: a phoneme file (through the controller's phoneme loader)
    Gesture,  ///< Text: the gesture name (checked), Duration, Intensity
    Mood,     ///< Text: the mood name (checked), Intensity, Fade
    Look      ///< Yaw, Pitch, Duration
  };
  Kind Type = Kind::Say;
  int Line = 0;       ///< 1-based line in the script
  double Start = 0.0; ///< seconds
  std::string Text;
  double Duration = 0.0;  ///< seconds; <= 0 for the default (Look: hold until the next look)
  double Intensity = 1.0; ///< [0, 1]
  double Fade = -1.0;     ///< seconds; < 0 for the default (Mood only)
  double Yaw = 0.0;       ///< degrees (Look only)
  double Pitch = 0.0;
};

struct BehaviorScript
{
  std::optional<uint64_t> Seed;
  std::optional<double> FrameRate;
  std::optional<double> Duration;
  std::vector<BehaviorCommand> Commands; ///< in script order
  /// Where relative phoneme file names are looked for ("" = the working directory).
  std::string BaseDirectory;
};

/// Largest time, duration or fade accepted anywhere (24 hours, in seconds).
constexpr double MaxBehaviorTime = 86400.0;
/// Shortest duration or fade other than 0 (10 ms): a span shorter than the clock's
/// resolution at a late start (a day in, doubles resolve ~1e-11 s) would divide by zero
/// in a gesture's envelope, so such durations are refused where they are parsed.
constexpr double MinBehaviorDuration = 0.01;
/// InputError unless `v` is 0 or in [MinBehaviorDuration, MaxBehaviorTime].
void CheckBehaviorDuration(double v, const char* what);

/// Parses a script; JSON when the first non-blank character is '{' or '['.
/// Throws InputError ("line N: ...") for anything malformed or out of range.
BehaviorScript ParseBehaviorScript(const std::string& text);
/// Reads and parses a file; BaseDirectory becomes the file's directory.
BehaviorScript LoadBehaviorScript(const std::string& path);
} // namespace morphnode
