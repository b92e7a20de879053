// SPDX-License-Identifier: BSD-3-Clause
// How far the avatar's picture and sound drift apart over a long run (issue 17, "Its
// voice"; figures in docs/avatar.md). The avatar draws every frame at the time of the
// sample being heard (playback/AudioPlayer::GetTime), so the mouth leads the sound by the
// viseme track's own lead whatever the clocks do. This program plays sound for N seconds
// in the avatar's loop (frames of 16 ms plus a random render cost) and reports, per frame:
//  - the picture clock against the wall clock: its drift (the sound device's crystal against
//    the system's; with SDL's dummy driver, as in CI, both are the system clock) and the
//    jitter of its steps;
//  - the picture clock's smoothness: residuals around its own straight line (95th
//    percentile), which a viewer would see as uneven motion;
//  - what a wall-clock picture (the avatar before) would have shown: its offset to the
//    sound at the end of the run (the device clock's drift, accumulated).
// Picture minus sound is within [0, one device buffer] by construction: the picture's time is
// the device's position less its buffer, interpolated between its requests.
//
//   StudyAudioVideoSync [--seconds 300] [--quick]
#include "playback/AudioPlayer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

int main(int argc, char* argv[])
{
  double seconds = 300.0;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--quick"))
    {
      seconds = 2.0;
    }
    else if (!std::strcmp(argv[i], "--seconds") && i + 1 < argc)
    {
      seconds = std::atof(argv[++i]);
    }
    else
    {
      std::fprintf(stderr, "usage: StudyAudioVideoSync [--seconds S] [--quick]\n");
      return 2;
    }
  }
  morphnode::AudioPlayer player;
  morphnode::AudioPlayer::Options options;
  options.Clock = morphnode::AudioPlayer::Options::ClockSource::Device; // also on the dummy driver
  player.Open(options);
  // A long clip of quiet noise: the device mixes something every request, as when speaking.
  morphnode::AudioBuffer clip;
  clip.SampleRate = player.GetSampleRate();
  clip.Channels = 1;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> noise(-0.01f, 0.01f);
  clip.Samples.resize(static_cast<size_t>((seconds + 1.0) * clip.SampleRate));
  for (float& s : clip.Samples)
  {
    s = noise(random);
  }
  player.Schedule(clip, 0.0);
  std::printf("device: %s, %d Hz, buffer %.1f ms; %.0f s\n", player.GetDriverName().c_str(),
    player.GetSampleRate(), player.GetLatency() * 1e3, seconds);

  using Clock = std::chrono::steady_clock;
  std::uniform_real_distribution<double> renderCost(0.002, 0.012);
  std::vector<double> wall, picture;
  player.SetPaused(false);
  const auto start = Clock::now();
  for (;;)
  {
    const double w = std::chrono::duration<double>(Clock::now() - start).count();
    if (w >= seconds)
    {
      break;
    }
    wall.push_back(w);
    picture.push_back(player.GetTime());
    std::this_thread::sleep_for(std::chrono::duration<double>(0.016 + renderCost(random)));
  }
  const size_t n = wall.size();
  if (n < 10)
  {
    std::fprintf(stderr, "too few frames (%zu)\n", n);
    return 1;
  }
  // Least-squares line picture = a + b * wall: b - 1 is the drift.
  double mw = 0, mp = 0;
  for (size_t i = 0; i < n; ++i)
  {
    mw += wall[i];
    mp += picture[i];
  }
  mw /= n;
  mp /= n;
  double sww = 0, swp = 0;
  for (size_t i = 0; i < n; ++i)
  {
    sww += (wall[i] - mw) * (wall[i] - mw);
    swp += (wall[i] - mw) * (picture[i] - mp);
  }
  const double slope = swp / sww;
  const double intercept = mp - slope * mw;
  std::vector<double> jitter, residual;
  for (size_t i = 1; i < n; ++i)
  {
    jitter.push_back(std::abs((picture[i] - picture[i - 1]) - (wall[i] - wall[i - 1])));
  }
  for (size_t i = 0; i < n; ++i)
  {
    residual.push_back(std::abs(picture[i] - (intercept + slope * wall[i])));
  }
  auto p95 = [](std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(0.95 * (v.size() - 1))];
  };
  std::printf("frames: %zu\n", n);
  std::printf("sound device clock vs wall clock: drift %+.0f ppm\n", (slope - 1.0) * 1e6);
  std::printf("picture clock: residual around its line p95 %.2f ms, step jitter p95 %.2f ms\n",
    p95(residual) * 1e3, p95(jitter) * 1e3);
  std::printf("picture - sound: within [0, %.1f ms] by construction\n", player.GetLatency() * 1e3);
  std::printf("a wall-clock picture would be %+.0f ms ahead of the sound at the end\n",
    (wall.back() - picture.back()) * 1e3);
  return 0;
}
