// SPDX-License-Identifier: BSD-3-Clause
// The avatar's voice (playback/AudioPlayer): the clock the picture follows and the clips it
// plays. The sound itself is checked through SDL's "disk" driver, which writes what the
// device would play into a file, at the device's pace.
#include "playback/AudioPlayer.h"

#include "base/Error.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

using morphnode::AudioBuffer;
using morphnode::AudioPlayer;

namespace
{
void Sleep(double seconds)
{
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

AudioBuffer Tone(double seconds, double amplitude, int rate = 22050)
{
  AudioBuffer tone;
  tone.SampleRate = rate;
  tone.Channels = 1;
  const size_t n = static_cast<size_t>(std::lround(seconds * rate));
  for (size_t i = 0; i < n; ++i)
  {
    tone.Samples.push_back(static_cast<float>(amplitude * std::sin(2.0 * M_PI * 440.0 * i / rate)));
  }
  return tone;
}

/// The runs of sound (|sample| > 1e-3, gaps under 5 ms bridged) in float samples: (first, length).
std::vector<std::pair<size_t, size_t>> Sounds(const std::vector<float>& s, int rate)
{
  std::vector<std::pair<size_t, size_t>> runs;
  const size_t bridge = static_cast<size_t>(rate / 200);
  for (size_t i = 0; i < s.size(); ++i)
  {
    if (std::abs(s[i]) <= 1e-3f)
    {
      continue;
    }
    if (!runs.empty() && i - (runs.back().first + runs.back().second) <= bridge)
    {
      runs.back().second = i + 1 - runs.back().first;
    }
    else
    {
      runs.emplace_back(i, 1);
    }
  }
  return runs;
}

float Peak(const std::vector<float>& s, size_t first, size_t length)
{
  float peak = 0.0f;
  for (size_t i = first; i < first + length && i < s.size(); ++i)
  {
    peak = std::max(peak, std::abs(s[i]));
  }
  return peak;
}
} // namespace

class AudioPlayerClock : public ::testing::TestWithParam<AudioPlayer::Options::ClockSource>
{
};

INSTANTIATE_TEST_SUITE_P(AudioPlayer, AudioPlayerClock,
  ::testing::Values(AudioPlayer::Options::ClockSource::Auto,
    AudioPlayer::Options::ClockSource::Device, AudioPlayer::Options::ClockSource::Steady),
  [](const ::testing::TestParamInfo<AudioPlayer::Options::ClockSource>& info)
  {
    return info.param == AudioPlayer::Options::ClockSource::Auto ? std::string("Auto")
      : info.param == AudioPlayer::Options::ClockSource::Device  ? std::string("Device")
                                                                 : std::string("Steady");
  });

TEST_P(AudioPlayerClock, RunsStandsAndSeeks)
{
  AudioPlayer player;
  AudioPlayer::Options options;
  options.Clock = GetParam();
  player.Open(options);
  if (GetParam() == AudioPlayer::Options::ClockSource::Steady)
  {
    EXPECT_FALSE(player.IsDeviceClock());
  }
  std::cout << "driver: " << player.GetDriverName() << ", " << player.GetSampleRate() << " Hz, "
            << player.GetLatency() * 1e3 << " ms buffer\n";
  EXPECT_TRUE(player.IsOpen());
  EXPECT_TRUE(player.GetPaused());
  Sleep(0.1);
  EXPECT_LT(player.GetTime(), 1e-9) << "a paused clock stands at 0";
  player.SetPaused(false);
  Sleep(0.4);
  const double running = player.GetTime();
  EXPECT_GT(running, 0.15);
  EXPECT_LT(running, 3.0); // a loaded machine sleeps longer, never shorter
  player.SetPaused(true);
  const double stood = player.GetTime();
  Sleep(0.15);
  EXPECT_EQ(player.GetTime(), stood);
  player.Seek(5.0);
  EXPECT_NEAR(player.GetTime(), 5.0, 1e-9);
  player.SetPaused(false);
  Sleep(0.1);
  EXPECT_GE(player.GetTime(), 5.0);
  EXPECT_THROW(player.Seek(-1.0), morphnode::InputError);
  EXPECT_THROW(player.Schedule(Tone(0.1, 0.5), std::nan("")), morphnode::InputError);
}

TEST(AudioPlayer, ClipsArePendingUntilHeardAndCutStopsThem)
{
  AudioPlayer player;
  player.Open();
  player.Schedule(Tone(1.0, 0.5), 0.0);
  player.Schedule(Tone(0.5, 0.5, 44100), 2.0); // another rate, resampled
  EXPECT_NEAR(player.GetPendingSeconds(), 2.5, 0.01);
  player.CutFrom(0.25);
  EXPECT_NEAR(player.GetPendingSeconds(), 0.25, 0.01) << "the cut removes the later clip too";
  player.Clear();
  EXPECT_EQ(player.GetPendingSeconds(), 0.0);
}

TEST(AudioPlayer, TheDevicePlaysTheClipsMixedAtTheirTimes)
{
  const std::filesystem::path file =
    std::filesystem::temp_directory_path() / "morphnode-audio-player-disk.raw";
  std::filesystem::remove(file);
  setenv("SDL_DISKAUDIOFILE", file.c_str(), 1);
  AudioPlayer player;
  AudioPlayer::Options options;
  options.Driver = "disk";
  try
  {
    player.Open(options);
  }
  catch (const morphnode::InputError& e)
  {
    GTEST_SKIP() << "no SDL disk driver: " << e.what();
  }
  if (player.GetDriverName() != "disk")
  {
    GTEST_SKIP() << "built without SDL2: the player is a silent clock (" << player.GetDriverName()
                 << ")";
  }
  const int rate = player.GetSampleRate();
  // A: 0.20 s at 0.3 from 0.10 s; B: 0.20 s at 0.3 from 0.20 s (overlapping A by 0.10 s:
  // 0.6 there: 440 Hz is in phase after 0.10 s); C: 0.30 s at 0.2 from 0.50 s, cut at 0.60 s.
  player.Schedule(Tone(0.2, 0.3, rate), 0.10);
  player.Schedule(Tone(0.2, 0.3, rate), 0.20);
  player.Schedule(Tone(0.3, 0.2, rate), 0.50);
  player.CutFrom(0.60);
  player.SetPaused(false);
  Sleep(1.0);
  player.Close();

  std::ifstream in(file, std::ios::binary);
  std::vector<float> samples((std::filesystem::file_size(file)) / sizeof(float));
  in.read(reinterpret_cast<char*>(samples.data()),
    static_cast<std::streamsize>(samples.size() * sizeof(float)));
  std::filesystem::remove(file);
  const auto sounds = Sounds(samples, rate);
  ASSERT_EQ(sounds.size(), 2u) << "A and B as one sound, then C";
  const double ab = static_cast<double>(sounds[0].second) / rate;
  const double c = static_cast<double>(sounds[1].second) / rate;
  const double gap = static_cast<double>(sounds[1].first - sounds[0].first) / rate;
  EXPECT_NEAR(ab, 0.30, 0.003) << "A and B from 0.10 to 0.40 s";
  EXPECT_NEAR(c, 0.10, 0.003) << "C from 0.50 s, cut at 0.60 s";
  EXPECT_NEAR(gap, 0.40, 0.002) << "C starts 0.40 s after A";
  const size_t a0 = sounds[0].first;
  const auto at = [&](double t) { return a0 + static_cast<size_t>(t * rate); };
  EXPECT_NEAR(Peak(samples, at(0.01), at(0.09) - at(0.01)), 0.3f, 0.01f) << "A alone";
  EXPECT_NEAR(Peak(samples, at(0.11), at(0.19) - at(0.11)), 0.6f, 0.02f) << "A and B add";
  EXPECT_NEAR(Peak(samples, sounds[1].first, sounds[1].second), 0.2f, 0.01f) << "C";
}
