// SPDX-License-Identifier: BSD-3-Clause
#include "align/Mfcc.h"

#include "audio/Resample.h"
#include "base/Error.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

namespace morphnode
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

/// FFTW's planner is not thread-safe; executing a plan is.
std::mutex PlannerMutex;

struct FftwFree
{
  void operator()(void* p) const { fftwf_free(p); }
};

double HzToMel(double hz)
{
  return 1127.0 * std::log(1.0 + hz / 700.0);
}

double MelToHz(double mel)
{
  return 700.0 * (std::exp(mel / 1127.0) - 1.0);
}
} // namespace

MfccFeatures ComputeMfcc(const AudioBuffer& audio, const MfccOptions& options)
{
  if (options.SampleRate < 4000 || !(options.FrameLength > 0.0) || !(options.FrameStep > 0.0) ||
    options.Filters < 2 || options.Coefficients < 1 || options.Coefficients > options.Filters ||
    !(options.HighFrequency > options.LowFrequency) || options.LowFrequency < 0.0)
  {
    throw InputError("MFCC: bad options (rate >= 4000, frame length and step > 0, "
                     "1 <= coefficients <= filters, low < high frequency)");
  }
  const AudioBuffer mono = Resample(MixToMono(audio), options.SampleRate, ResampleQuality::Medium);
  const int rate = options.SampleRate;
  const size_t frameLength = static_cast<size_t>(std::lround(options.FrameLength * rate));
  const size_t frameStep =
    std::max<size_t>(1, static_cast<size_t>(std::lround(options.FrameStep * rate)));
  size_t fftSize = 1;
  while (fftSize < frameLength)
  {
    fftSize *= 2;
  }
  MfccFeatures features;
  features.Dimension = options.Coefficients;
  features.FrameStep = static_cast<double>(frameStep) / rate;
  features.FrameLength = static_cast<double>(frameLength) / rate;
  const std::vector<float>& x = mono.Samples;
  if (x.size() < frameLength || frameLength < 2)
  {
    return features;
  }
  features.Frames = 1 + (x.size() - frameLength) / frameStep;

  // Hamming window, mel filterbank (triangles on the power spectrum), DCT-II matrix.
  std::vector<float> window(frameLength);
  for (size_t n = 0; n < frameLength; ++n)
  {
    window[n] = static_cast<float>(0.54 - 0.46 * std::cos(2.0 * Pi * n / (frameLength - 1)));
  }
  const size_t bins = fftSize / 2 + 1;
  const double high = std::min(options.HighFrequency, 0.5 * rate);
  const double melLow = HzToMel(options.LowFrequency), melHigh = HzToMel(high);
  const int filters = options.Filters;
  std::vector<double> edges(static_cast<size_t>(filters) + 2);
  for (size_t k = 0; k < edges.size(); ++k)
  {
    edges[k] = MelToHz(melLow + (melHigh - melLow) * static_cast<double>(k) / (filters + 1)) *
      fftSize / rate;
  }
  std::vector<std::vector<std::pair<size_t, float>>> bank(static_cast<size_t>(filters));
  for (int m = 0; m < filters; ++m)
  {
    const double left = edges[static_cast<size_t>(m)], centre = edges[static_cast<size_t>(m) + 1],
                 right = edges[static_cast<size_t>(m) + 2];
    for (size_t b = static_cast<size_t>(std::max(0.0, std::floor(left))); b < bins && b <= right;
         ++b)
    {
      const double w = b < centre ? (b - left) / (centre - left) : (right - b) / (right - centre);
      if (w > 0.0)
      {
        bank[static_cast<size_t>(m)].emplace_back(b, static_cast<float>(w));
      }
    }
  }
  const int coefficients = options.Coefficients;
  std::vector<float> dct(static_cast<size_t>(coefficients * filters));
  for (int c = 0; c < coefficients; ++c)
  {
    for (int m = 0; m < filters; ++m)
    {
      dct[static_cast<size_t>(c * filters + m)] =
        static_cast<float>(std::sqrt(2.0 / filters) * std::cos(Pi * c * (m + 0.5) / filters));
    }
  }

  std::unique_ptr<float, FftwFree> in(static_cast<float*>(fftwf_malloc(sizeof(float) * fftSize)));
  std::unique_ptr<fftwf_complex, FftwFree> out(
    static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * bins)));
  if (!in || !out)
  {
    throw InputError("MFCC: out of memory");
  }
  fftwf_plan plan;
  {
    std::lock_guard<std::mutex> lock(PlannerMutex);
    plan = fftwf_plan_dft_r2c_1d(static_cast<int>(fftSize), in.get(), out.get(), FFTW_ESTIMATE);
  }
  features.Values.resize(features.Frames * static_cast<size_t>(coefficients));
  features.LogEnergy.resize(features.Frames);
  std::vector<float> power(bins), logMel(static_cast<size_t>(filters));
  for (size_t f = 0; f < features.Frames; ++f)
  {
    const float* frame = x.data() + f * frameStep;
    float* buffer = in.get();
    double energy = 0.0;
    for (size_t n = 0; n < frameLength; ++n)
    {
      const float previous = n > 0 ? frame[n - 1] : (f * frameStep > 0 ? frame[-1] : frame[0]);
      const float s = frame[n] - static_cast<float>(options.PreEmphasis) * previous;
      buffer[n] = s * window[n];
      energy += static_cast<double>(frame[n]) * frame[n];
    }
    std::fill(buffer + frameLength, buffer + fftSize, 0.0f);
    fftwf_execute(plan);
    for (size_t b = 0; b < bins; ++b)
    {
      power[b] = out.get()[b][0] * out.get()[b][0] + out.get()[b][1] * out.get()[b][1];
    }
    for (size_t m = 0; m < bank.size(); ++m)
    {
      double sum = 0.0;
      for (const auto& [b, w] : bank[m])
      {
        sum += static_cast<double>(w) * power[b];
      }
      logMel[m] = static_cast<float>(std::log(std::max(sum, 1e-10)));
    }
    float* row = features.Values.data() + f * static_cast<size_t>(coefficients);
    for (int c = 0; c < coefficients; ++c)
    {
      double sum = 0.0;
      for (int m = 0; m < filters; ++m)
      {
        sum += static_cast<double>(dct[static_cast<size_t>(c * filters + m)]) *
          logMel[static_cast<size_t>(m)];
      }
      row[c] = static_cast<float>(sum);
    }
    features.LogEnergy[f] = static_cast<float>(std::log(std::max(energy / frameLength, 1e-10)));
  }
  {
    std::lock_guard<std::mutex> lock(PlannerMutex);
    fftwf_destroy_plan(plan);
  }
  return features;
}
} // namespace morphnode
