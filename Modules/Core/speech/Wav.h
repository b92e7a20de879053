// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Wav.h
/// @brief Deprecated: WAV output moved to the audio concept (audio/AudioFile.h, through
/// libsndfile). This header only forwards there until its last user includes that instead.

#include "audio/AudioFile.h"
