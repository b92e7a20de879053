// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Frames.h
/// @brief The frames of a behaviour track: one formula for every user (the controller's
/// tracks, the VTK time steps, the applications' frame loops).
///
/// A track of `duration` seconds at `frameRate` frames per second has the frames
/// t_i = i / frameRate, i = 0 .. floor(duration * frameRate): the first at 0, the last at
/// or just before the end (a product within 1e-9 of a whole number counts as that number,
/// so 0.29 s at 100 fps has 30 frames although 0.29 * 100 = 28.999999999999996).

#include <cstddef>
#include <vector>

namespace morphnode
{
/// The most values (frames x channels) a sampled track may hold (512 MiB of doubles);
/// longer behaviours are sampled one time at a time (BehaviorController::Sample).
constexpr size_t MaxTrackValues = size_t(1) << 26;

/// floor(duration * frameRate + 1e-9) + 1, at least 1. InputError for a frame rate that is
/// not > 0 and finite, a duration that is negative or not finite, or more than 2^32 frames
/// (a behaviour is at most 24 h at 1000 fps: 86.4 million).
size_t NumberOfFrames(double duration, double frameRate);

/// The time of frame `frame`: frame / frameRate.
inline double FrameTime(size_t frame, double frameRate)
{
  return static_cast<double>(frame) / frameRate;
}

/// Every frame time, t_0 .. t_{NumberOfFrames - 1}; InputError as NumberOfFrames and for
/// more than MaxTrackValues frames.
std::vector<double> FrameTimes(double duration, double frameRate);
} // namespace morphnode
