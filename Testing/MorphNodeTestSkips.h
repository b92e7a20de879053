// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Skips of tests whose prerequisite an optional build leaves out, with the reason shown.

#include "speech/SpeechSynthesizer.h"

#include <gtest/gtest.h>

/// At the start of a test that synthesizes speech: skips it in a build without eSpeak NG.
#define MORPHNODE_SKIP_WITHOUT_ESPEAK()                                                            \
  if (!morphnode::SpeechSynthesizer::IsAvailable())                                                \
  GTEST_SKIP() << "built without eSpeak NG (MORPHNODE_ENABLE_ESPEAK=OFF)"
