// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file BehaviorAudio.h
/// @brief The sound of a behaviour: the audio of its scheduled utterances mixed on the
/// track's time axis (sample 0 at t = 0), so that a WAV file and the frames line up.
///
///   morphnode::BehaviorController behavior;  // ... Say(...), Prepare()
///   morphnode::WriteBehaviorAudio("speech.wav", behavior);

#include "audio/AudioBuffer.h"
#include "behavior/BehaviorController.h"

#include <string>
#include <vector>

namespace morphnode
{
/// The rate of a mix without any audio: eSpeak NG's.
constexpr int DefaultMixSampleRate = 22050;

/// Mixes the utterances' audio into one mono buffer at the highest sample rate among them
/// (DefaultMixSampleRate when none has audio), each utterance from sample
/// round(Start * rate) on; an utterance at another rate is resampled first (audio/Resample.h).
/// The samples are summed, not clipped (ToInt16Mono clips). The mix lasts until the end of
/// the last sound and at least `minimumDuration` seconds (silence after the sound):
/// ceil(end * rate) samples. InputError for a minimum duration that is negative or not
/// finite, or more samples than a 16-bit WAV file holds.
AudioBuffer MixUtteranceAudio(
  const std::vector<BehaviorController::ScheduledUtterance>& utterances, double minimumDuration);

/// The mix of a prepared behaviour's utterances, at least its effective duration long.
/// InputError if it is not prepared since the last change.
AudioBuffer MixBehaviorAudio(const BehaviorController& behavior);

/// Writes MixBehaviorAudio() as a 16-bit mono WAV file (clipped, audio/AudioFile.h): the one
/// place where a behaviour's sound goes to a file. InputError when it cannot be written.
void WriteBehaviorAudio(const std::string& path, const BehaviorController& behavior);
} // namespace morphnode
