// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Wav.h
/// @brief RIFF WAVE output: 16-bit PCM, mono.

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
/// Writes a 44-byte header and the samples (little endian). InputError for a sample rate
/// <= 0 or more samples than a WAV file can hold.
void WriteWav(std::ostream& out, const std::vector<int16_t>& samples, int sampleRate);
void WriteWavFile(const std::string& path, const std::vector<int16_t>& samples, int sampleRate);
} // namespace morphnode
