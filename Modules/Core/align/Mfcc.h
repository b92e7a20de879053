// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Mfcc.h
/// @brief Mel-frequency cepstral coefficients, the spectral features the alignment compares.
/// The FFT is FFTW3's (Debian libfftw3-dev: the reference FFT library, packaged, fast on
/// any size; only its planner needs a lock, which this file holds).

#include "audio/AudioBuffer.h"

#include <cstddef>
#include <vector>

namespace morphnode
{
struct MfccOptions
{
  int SampleRate = 16000;        ///< audio is resampled to this rate first
  double FrameLength = 0.025;    ///< seconds of the analysis window (Hamming)
  double FrameStep = 0.010;      ///< seconds between frames
  int Filters = 26;              ///< mel filters
  int Coefficients = 13;         ///< cepstral coefficients c0..c12
  double LowFrequency = 60.0;    ///< Hz
  double HighFrequency = 7600.0; ///< Hz (clamped below the Nyquist frequency)
  double PreEmphasis = 0.97;
};

/// Frames x coefficients, plus the log energy of every frame.
struct MfccFeatures
{
  size_t Frames = 0;
  int Dimension = 0;
  std::vector<float> Values;    ///< Frames * Dimension, row-major
  std::vector<float> LogEnergy; ///< natural log of the frame's mean power (floor 1e-10)
  double FrameStep = 0.010;     ///< seconds
  double FrameLength = 0.025;   ///< seconds
  /// Time of the centre of frame i, seconds.
  double FrameTime(double i) const { return i * this->FrameStep + 0.5 * this->FrameLength; }
  const float* Row(size_t i) const
  {
    return this->Values.data() + i * static_cast<size_t>(this->Dimension);
  }
};

/// MFCCs of the mono mix of `audio`, resampled to options.SampleRate. A buffer shorter than
/// one frame gives 0 frames. InputError for bad options.
MfccFeatures ComputeMfcc(const AudioBuffer& audio, const MfccOptions& options = {});
} // namespace morphnode
