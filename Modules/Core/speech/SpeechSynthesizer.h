// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SpeechSynthesizer.h
/// @brief Live text-to-speech with eSpeak NG: audio plus timed phonemes.
///
/// eSpeak NG keeps global state, so every synthesizer shares one engine and calls are
/// serialized by a process-wide lock: instances may be used from any thread, but
/// synthesis never runs in parallel. Phoneme events only exist in eSpeak's legacy API
/// (espeak_Initialize with espeakINITIALIZE_PHONEME_EVENTS), which is what this uses.

#include "speech/SpeechTypes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace morphnode
{
/// A word of the text with the time eSpeak starts speaking it.
struct SynthesizedWord
{
  std::string Text;      ///< UTF-8, as in the input text
  double Start = 0.0;    ///< seconds
  double Duration = 0.0; ///< until the next word or the next pause, whichever comes first
};

struct SynthesisResult
{
  /// eSpeak's phoneme events as they came: eSpeak's mnemonics, start = audio_position, each
  /// lasting until the next event (the last one until the end of the audio).
  std::vector<TimedPhoneme> EspeakPhonemes;
  /// The same in SAMPA (NormalizeVoicePhonemes: German and English by table, X-SAMPA for
  /// other languages), a leading `_` covering the silence before the first event; with
  /// pitch targets when pitch estimation is on.
  std::vector<TimedPhoneme> Phonemes;
  std::vector<int16_t> Audio; ///< mono, 16 bit
  int SampleRate = 22050;
  double Duration = 0.0;              ///< seconds of audio
  std::vector<SynthesizedWord> Words; ///< eSpeak's word events, in order
};

class SpeechSynthesizer
{
public:
  static constexpr int MinimumRate = 80;  ///< words per minute (eSpeak's lower limit)
  static constexpr int MaximumRate = 450; ///< eSpeak distorts above this
  static constexpr int DefaultRate = 175;

  /// False when MorphNode was built without eSpeak NG (MORPHNODE_ENABLE_ESPEAK=OFF): then
  /// Synthesize throws InputError saying so.
  static bool IsAvailable();

  /// The languages of every voice eSpeak NG has (as `espeak-ng --voices` lists them: "af",
  /// "en-gb", "fr-fr", "cmn", ...); each works as a voice name. Empty without eSpeak NG.
  static std::vector<std::string> ListVoices(const std::string& dataPath = std::string());

  SpeechSynthesizer() = default;
  explicit SpeechSynthesizer(const std::string& voice, int rate = DefaultRate);

  /// An eSpeak voice name ("de", "en", "en-us", ...). Checked when synthesizing.
  void SetVoice(const std::string& voice) { this->Voice = voice; }
  const std::string& GetVoice() const { return this->Voice; }
  /// Words per minute, clamped to [MinimumRate, MaximumRate].
  void SetRate(int wordsPerMinute);
  int GetRate() const { return this->Rate; }
  /// eSpeak's base pitch, 0..100 (default 50), clamped.
  void SetPitch(int pitch);
  int GetPitch() const { return this->Pitch; }
  /// The folder holding espeak-ng-data; empty uses eSpeak's compiled-in default.
  void SetDataPath(const std::string& path) { this->DataPath = path; }
  const std::string& GetDataPath() const { return this->DataPath; }
  /// Estimate F0 from the audio and attach it to every voiced phoneme (on by default).
  void SetEstimatePitch(bool on) { this->EstimatePitch = on; }
  bool GetEstimatePitch() const { return this->EstimatePitch; }

  /// Synthesizes UTF-8 text. Throws InputError when eSpeak cannot be initialized (e.g. no
  /// espeak-ng-data), the voice is unknown or synthesis fails.
  SynthesisResult Synthesize(const std::string& text) const;

private:
  std::string Voice = "en";
  int Rate = DefaultRate;
  int Pitch = 50;
  std::string DataPath;
  bool EstimatePitch = true;
};

/// F0 in Hz of samples [begin, end) by normalized autocorrelation over 60..500 Hz; 0 when
/// the stretch is unvoiced (peak correlation below `voicingThreshold`) or too short. 0.45
/// keeps eSpeak's r-coloured vowels, whose jitter lowers the correlation, and still rejects
/// noise.
double EstimatePitchHz(
  const int16_t* samples, size_t begin, size_t end, int sampleRate, double voicingThreshold = 0.45);

/// Sets one pitch target (position 0.5) on every non-pause phoneme that is voiced at its
/// centre (a 42 ms window); other phonemes get an empty pitch list.
void AttachPitch(
  std::vector<TimedPhoneme>& phonemes, const std::vector<int16_t>& audio, int sampleRate);
} // namespace morphnode
