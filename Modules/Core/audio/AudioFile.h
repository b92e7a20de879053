// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AudioFile.h
/// @brief Audio files through libsndfile: read WAV, FLAC, OGG/Vorbis (and every other format
/// libsndfile knows: AIFF, AU, CAF, ...) at any sample rate and channel count; write WAV.

#include "audio/AudioBuffer.h"

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace morphnode
{
/// Reads a sound file as float samples at its own rate and channel count. InputError naming
/// the file for a file that cannot be opened, is not a sound file libsndfile reads, holds no
/// frames, or fails while decoding.
AudioBuffer ReadAudioFile(const std::string& path);

/// Same from bytes in memory; `origin` names them in error messages.
AudioBuffer ReadAudioMemory(const std::string& bytes, const std::string& origin = "audio data");

/// Writes 16-bit PCM WAV (samples clipped to [-1, 1]). InputError for a rate <= 0, no
/// channels, a sample count that is not a multiple of the channels, or a write failure.
void WriteWavFile(const std::string& path, const AudioBuffer& audio);
void WriteWav(std::ostream& out, const AudioBuffer& audio);

/// Mono 16-bit samples as WAV (what eSpeak NG synthesizes).
void WriteWavFile(const std::string& path, const std::vector<int16_t>& samples, int sampleRate);
void WriteWav(std::ostream& out, const std::vector<int16_t>& samples, int sampleRate);
} // namespace morphnode
