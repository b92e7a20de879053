// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Random.h
/// @brief A small seeded generator (SplitMix64) with its own distributions, so that a seed
/// gives the same behaviour with every standard library (std::normal_distribution and
/// friends are implementation-defined). Never seeded from std::random_device.

#include <cmath>
#include <cstdint>

namespace morphnode
{
class BehaviorRandom
{
public:
  /// `stream` separates independent sequences of one seed (blinks, saccades, ...), so that
  /// changing how many numbers one behaviour draws leaves the others untouched.
  explicit BehaviorRandom(uint64_t seed, uint64_t stream = 0)
    : State(seed ^ Mix(stream + 0x632BE59BD9B4E019ull))
  {
  }

  uint64_t Next() { return Mix(this->State += 0x9E3779B97F4A7C15ull); }
  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(this->Next() >> 11) * 0x1.0p-53; }
  /// Uniform in (0, 1): safe under a logarithm.
  double UniformOpen() { return (static_cast<double>(this->Next() >> 12) + 0.5) * 0x1.0p-52; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * this->Uniform(); }
  /// Standard normal (Box-Muller; one of the pair is dropped to keep the state simple).
  double Normal()
  {
    const double u1 = this->UniformOpen();
    const double u2 = this->Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  /// Log-normal with the given mean and shape sigma (of the underlying normal).
  double LogNormalWithMean(double mean, double sigma)
  {
    const double mu = std::log(mean) - 0.5 * sigma * sigma;
    return std::exp(mu + sigma * this->Normal());
  }
  /// Exponential with the given mean.
  double Exponential(double mean) { return -mean * std::log(this->UniformOpen()); }

private:
  static uint64_t Mix(uint64_t z)
  {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t State;
};
} // namespace morphnode
