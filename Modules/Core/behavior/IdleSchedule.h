// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file IdleSchedule.h
/// @brief Unconscious behaviour, precomputed per seed: blinks, saccades, occasional smiles
/// and head micro-motion. Generated once, then sampled at any time without simulation.

#include "behavior/BehaviorTypes.h"
#include "behavior/Random.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace morphnode
{
struct BlinkEvent
{
  double Start = 0.0;     ///< seconds
  double Amplitude = 1.0; ///< peak lid closure
};

/// One saccade of the idle gaze offset (degrees, added to the gaze target).
struct SaccadeEvent
{
  double Start = 0.0;
  double Duration = 0.0;
  double Amplitude = 0.0; ///< degrees actually travelled
  double FromYaw = 0.0, FromPitch = 0.0, ToYaw = 0.0, ToPitch = 0.0;
};

struct IdleSmileEvent
{
  double Start = 0.0;
  double Duration = 0.0;
  double Intensity = 0.0;
};

/// Head micro-motion: per axis (yaw, pitch, roll) three sines with random incommensurate
/// frequencies and phases: smooth, bounded by the axis amplitude, never periodic.
struct HeadMicroMotion
{
  std::array<double, 9> Amplitude{}; ///< degrees, axis-major
  std::array<double, 9> Frequency{}; ///< radians per second
  std::array<double, 9> Phase{};
  void Evaluate(double t, double* yawPitchRoll) const;
};

/// Lee et al. 2002: amplitude in degrees from P uniform in (0, 15): -6.9 ln(P / 15.7).
double SaccadeAmplitudeLaw(double p);
/// Lee et al. 2002: 25 ms + 2.4 ms/deg x amplitude (with the parameters' figures).
double SaccadeDuration(const BehaviorParameters& parameters, double amplitude);
/// The lid curve of one blink at `t` seconds after its start, 0..1: fast smoothstep
/// closing, a short closed hold, slower ease-out opening.
double BlinkLidCurve(const BehaviorParameters& parameters, double t);
/// Seconds from a blink's start to the lids fully open again.
double BlinkLength(const BehaviorParameters& parameters);

/// The idle generators, one event at a time: IdleSchedule::Generate runs them to a
/// horizon, LiveBehavior runs them for ever, a little ahead of the sampled time. Each draws
/// from its own random stream of the seed, so the same seed gives the same events in both.

/// Blinks: log-normal intervals (mean 60 / BlinkRateRest s, shape BlinkIntervalSigma, at
/// least max(BlinkMinInterval, BlinkLength)) on a clock that runs BlinkRateSpeaking /
/// BlinkRateRest times faster inside the `speaking` intervals; the first blink at a random
/// phase of one mean interval.
class BlinkTrain
{
public:
  BlinkTrain(const BehaviorParameters& parameters, uint64_t seed,
    const std::vector<std::pair<double, double>>& speaking = {});
  /// The next blink (its start is Peek()).
  BlinkEvent Next();
  double Peek() const { return this->Time; }

private:
  BehaviorParameters Parameters;
  BehaviorRandom Random;
  std::vector<std::pair<double, double>> Speaking; // merged, sorted
  size_t Interval = 0;
  double Time = 0.0;
};

/// Saccades: Lee et al.'s amplitude law, kept within SaccadeRange of the gaze target
/// (vertical range 60 % of the horizontal one), separated by log-normal fixations. Next()
/// takes the parameters so that a mood can change range and fixations as it goes.
class SaccadeTrain
{
public:
  SaccadeTrain(const BehaviorParameters& parameters, uint64_t seed);
  SaccadeEvent Next(const BehaviorParameters& parameters);
  double Peek() const { return this->Time; }

private:
  BehaviorRandom Random;
  double Yaw = 0.0, Pitch = 0.0, Time = 0.0;
};

/// Occasional smiles: Poisson events of IdleSmileInterval mean spacing (none when the
/// interval or the intensity is <= 0: Peek() is infinite).
class SmileTrain
{
public:
  SmileTrain(const BehaviorParameters& parameters, uint64_t seed);
  IdleSmileEvent Next();
  double Peek() const { return this->Time; }

private:
  BehaviorParameters Parameters;
  BehaviorRandom Random;
  double Time = 0.0;
};

/// The head micro-motion of a seed.
HeadMicroMotion MakeHeadMicroMotion(const BehaviorParameters& parameters, uint64_t seed);

struct IdleSchedule
{
  std::vector<BlinkEvent> Blinks;     ///< sorted by start
  std::vector<SaccadeEvent> Saccades; ///< sorted, non-overlapping
  std::vector<IdleSmileEvent> Smiles; ///< sorted by start
  HeadMicroMotion Head;

  /// Generates the schedule over [0, horizon]. `speaking` lists the (start, end) intervals
  /// of speech: the blink clock runs BlinkRateSpeaking / BlinkRateRest times faster there,
  /// so the rate follows speech immediately. Each behaviour draws from its own random
  /// stream of `seed`. Throws InputError for a horizon < 0 or non-finite.
  static IdleSchedule Generate(const BehaviorParameters& parameters, uint64_t seed, double horizon,
    const std::vector<std::pair<double, double>>& speaking);

  /// The idle gaze offset (degrees) at t.
  void GazeOffset(double t, double& yaw, double& pitch) const;
};
} // namespace morphnode
