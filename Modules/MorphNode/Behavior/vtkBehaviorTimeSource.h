// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkBehaviorTimeSource
 * @brief   a temporal source of behaviour weights (speech, gestures, moods, looks and
 *          idle behaviour, Berner WSCG 2004 section 3) for vtkMorphNodeFilter
 *
 * A thin adapter over morphnode::BehaviorController (docs/behavior.md): configure it
 * (seed, frame rate, duration, voice, viseme set, behaviour parameters), add commands (Say,
 * SpeakPhonemeFile, SpeakRhubarbFile, Gesture, SetMood, LookAt) or a script (LoadScript),
 * and connect output port 0 to the weights port of a vtkMorphNodeFilter:
 *
 * @code
 * vtkNew<vtkBehaviorTimeSource> behavior;
 * behavior->SetSeed(7);
 * behavior->SetMood("happy", 0.6);
 * behavior->Say("Hello world", 0.5);
 * behavior->Gesture("nod", 1.0, 0.8, 0.7);
 * morph->SetWeightsConnection(behavior->GetOutputPort(0));
 * morph->UpdateTimeStep(1.25); // the face at t = 1.25 s
 * @endcode
 *
 * Outputs (no inputs):
 * - port 0: a one-row vtkTable, one vtkDoubleArray column per channel (GetChannelName),
 *   the behaviour at the requested UPDATE_TIME_STEP (0 when none is requested); the
 *   table's DATA_TIME_STEP is that time. The information advertises TIME_STEPS (the
 *   frames GetFrameTime(i) = i / FrameRate, i = 0 .. floor(EffectiveDuration * FrameRate),
 *   morphnode::NumberOfFrames; left out beyond GetMaximumNumberOfTimeSteps() frames: the
 *   time is continuous) and TIME_RANGE = [0, EffectiveDuration]; any time may be
 *   requested, between steps too.
 * - port 1: the whole track, one row per frame (the same frames as the time steps), a
 *   `Time` column first, then the channels: for plots and CSV (vtkDelimitedTextWriter).
 *   Built only when port 1 itself is updated (a request on port 0 leaves it alone), once
 *   per change of the behaviour (morphnode::BehaviorController::SampleTrack). A track of
 *   more than morphnode::MaxTrackValues values is an error: RequestData returns 0 and both
 *   outputs are empty.
 *
 * Channels: EyesClosed, BrowsUp, BrowsFright, BrowsAngry, MouthSmile, MouthSad, LookUp,
 * LookDown, LookLeft, LookRight, HeadYaw, HeadPitch, HeadRoll (degrees), EyeYaw, EyePitch
 * (degrees), then the viseme channels of the scheduled utterances. Columns that name no
 * morph target (head pose, gaze angles, `sil`) are ignored by vtkMorphNodeFilter.
 *
 * Speech: Say() synthesizes at once with eSpeak NG (morphnode::SpeakText) using the
 * current Voice, SpeechRate and VisemeSet (or VisemeTableFileName); changing those later
 * affects later commands only. Lip sync made elsewhere comes in without audio: MBROLA
 * `.pho` phonemes (SpeakPhonemeFile, SpeakPhonemes) through the same viseme table, and
 * Rhubarb Lip Sync mouth cues (SpeakRhubarbFile, SpeakRhubarbCues; TSV or JSON) through
 * the table's shape entries. The default viseme set is the paper's (PAPER6: A E O S F L
 * and sil), whose names match the default face's targets. WriteAudio() writes the
 * scheduled utterances' audio on the track's time axis (morphnode::WriteBehaviorAudio),
 * so the WAV and the track line up.
 *
 * Every setter modifies the source only on a real change; every successful command
 * modifies it. Bad values, unknown names, unreadable or malformed files, eSpeak failures
 * and malformed scripts are reported with vtkErrorMacro and the command returns false,
 * leaving the source as it was. Setters that reject a value report an error and keep the
 * previous value.
 *
 * C++ code may read the core controller (GetController(), const) and schedule a
 * morphnode::Utterance it built itself (Speak); every change goes through this class, so
 * the modification time is always right.
 *
 * @sa vtkMorphTrackSource vtkMorphNodeFilter morphnode::BehaviorController morphnode::SpeakText
 */

#ifndef vtkBehaviorTimeSource_h
#define vtkBehaviorTimeSource_h

#include "vtkMorphNodeBehaviorModule.h" // For export macro
#include "vtkMorphTrackSource.h"

#include <memory> // For std::unique_ptr

#ifndef __VTK_WRAP__
namespace morphnode
{
class BehaviorController;
struct BehaviorParameters;
struct SpeechOptions;
struct Utterance;
}
#endif

class VTKMORPHNODEBEHAVIOR_EXPORT vtkBehaviorTimeSource : public vtkMorphTrackSource
{
public:
  static vtkBehaviorTimeSource* New();
  vtkTypeMacro(vtkBehaviorTimeSource, vtkMorphTrackSource);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Viseme sets of Say(); values match morphnode::VisemeSet.
  enum VisemeSets
  {
    OCULUS15 = 0,
    GERMAN16 = 1,
    PAPER6 = 2
  };

  ///@{
  /**
   * The random seed of the idle behaviour (default 1): the same seed gives a
   * bit-identical track, another seed a different one.
   */
  void SetSeed(vtkTypeUInt64 seed);
  vtkTypeUInt64 GetSeed();
  ///@}

  ///@{
  /**
   * Frame rate of the time steps and of the track on port 1, in (0, 1000]; default 30.
   */
  void SetFrameRate(double fps);
  double GetFrameRate();
  ///@}

  ///@{
  /**
   * Length of the track in seconds; 0 (default) = the end of the last command + 1 s, at
   * least 5 s. GetEffectiveDuration() gives the length actually used.
   */
  void SetDuration(double seconds);
  double GetDuration();
  double GetEffectiveDuration();
  ///@}

  ///@{
  /**
   * eSpeak NG voice of Say(), e.g. "en" (default), "de", "en-us".
   */
  void SetVoice(const char* voice);
  const char* GetVoice();
  ///@}

  ///@{
  /**
   * Speech rate of Say() in words per minute (eSpeak clamps to [80, 450]); default
   * eSpeak's 175.
   */
  void SetSpeechRate(int wordsPerMinute);
  int GetSpeechRate();
  ///@}

  ///@{
  /**
   * Viseme set of the speech commands; default PAPER6, the paper's A E O S F L.
   * The string form takes "paper6", "oculus15", "german16" (case-insensitive) and
   * reports an error for others.
   */
  void SetVisemeSet(int set);
  int GetVisemeSet();
  void SetVisemeSetToPaper() { this->SetVisemeSet(PAPER6); }
  void SetVisemeSetToOculus() { this->SetVisemeSet(OCULUS15); }
  void SetVisemeSetToGerman() { this->SetVisemeSet(GERMAN16); }
  bool SetVisemeSetFromString(const char* name);
  const char* GetVisemeSetAsString();
  ///@}

  ///@{
  /**
   * A viseme table file (docs/speech.md, e.g. one of Modules/Core/speech/data/visemes_*.json
   * adapted to a face) used by the speech commands instead of the built-in table of VisemeSet;
   * nullptr or "" (default) = the built-in one. The file is checked when set: one that
   * cannot be read is an error, returns false and keeps the previous table.
   */
  bool SetVisemeTableFileName(const char* path);
  const char* GetVisemeTableFileName();
  ///@}

  ///@{
  /**
   * The format of the timing files of SpeakTimingFile and SpeakAudioFileWithTimings where
   * the extension does not tell (morphnode::TimingFormat names: auto (default), pho,
   * rhubarb-tsv, rhubarb-json, rhubarb-xml, textgrid, speech-marks). An unknown name is an
   * error: returns false and keeps the previous format.
   */
  bool SetTimingFormat(const char* name);
  const char* GetTimingFormat();
  ///@}

  ///@{
  /**
   * The figures of the idle behaviour, gestures and gaze (morphnode::BehaviorParameters,
   * docs/behavior.md) by name, e.g. "BlinkRateRest" (blinks per minute), "HeadShareOfGaze".
   * Names are matched as gestures are (case, '_' and '-' do not matter). An unknown name
   * or a value out of the parameter's range is an error: Set returns false and changes
   * nothing, Get returns NaN.
   */
  int GetNumberOfBehaviorParameters();
  const char* GetBehaviorParameterName(int index);
  bool SetBehaviorParameter(const char* name, double value);
  double GetBehaviorParameter(const char* name);
  /// Back to the published and chosen defaults.
  void ResetBehaviorParameters();
  ///@}

  ///@{
  /**
   * Commands; times in seconds, angles in degrees (yaw > 0 to the face's left, pitch > 0
   * up). Each returns false and reports an error for bad input, leaving the source
   * unchanged. A start below 0 for the speech commands queues after the previous
   * utterance. Say: text through eSpeak NG, with audio. SpeakPhonemeFile / SpeakPhonemes:
   * an MBROLA .pho file / .pho text (SAMPA phonemes with durations), no audio.
   * SpeakRhubarbFile / SpeakRhubarbCues: Rhubarb Lip Sync's mouth cues as a file / text,
   * TSV (`start<TAB>shape` lines) or JSON (`{"mouthCues": [...]}`), told apart by the first
   * character; no audio (play the recording Rhubarb analysed alongside). SpeakTimingFile:
   * any timing file other tools write (morphnode::LoadTimingFile: .pho, Rhubarb TSV/JSON,
   * Praat TextGrid, Amazon Polly speech marks; by extension, then content), no audio.
   * SpeakAudioFile: a recording (WAV, FLAC, OGG) with its transcript in the language of
   * Voice, timed by aligning eSpeak NG's rendering of the transcript (an empty transcript:
   * English phoneme recognition); the recording is the utterance's audio, so WriteAudio
   * plays it. SpeakAudioFileWithTimings: a recording timed by a timing file of it
   * (morphnode::SpeakAudioFile, align/RecordingSpeech.h). Gesture: smile,
   * sad, raise_brows, frown, fright, close_eyes, blink, nod, shake, tilt; duration <= 0
   * takes the gesture's default; intensity in [0, 1]. Mood: neutral, happy, sad, angry,
   * afraid, surprised; fade < 0 takes the default (0.8 s). LookAt: back to the front after
   * `duration`, held until the next look when <= 0.
   */
  bool Say(const char* text, double start = -1.0);
  bool SpeakPhonemeFile(const char* path, double start = -1.0);
  bool SpeakPhonemes(const char* pho, double start = -1.0);
  bool SpeakRhubarbFile(const char* path, double start = -1.0);
  bool SpeakRhubarbCues(const char* cues, double start = -1.0);
  bool SpeakTimingFile(const char* path, double start = -1.0);
  bool SpeakAudioFile(const char* path, const char* transcript, double start = -1.0);
  bool SpeakAudioFileWithTimings(const char* path, const char* timingFile, double start = -1.0);
  bool Gesture(const char* name, double start, double duration = 0.0, double intensity = 1.0);
  bool SetMood(const char* name, double intensity, double start = 0.0, double fade = -1.0);
  bool LookAt(double yaw, double pitch, double start, double duration = 0.0);
  /// Removes every command; keeps seed, frame rate, duration and the speech settings.
  void ClearCommands();
  ///@}

  ///@{
  /**
   * Scripts (docs/behavior.md, text or JSON): settings and commands, all or nothing.
   * On failure an error with the core's "line N: ..." message, and false.
   */
  bool LoadScript(const char* path);
  bool ParseScript(const char* text);
  ///@}

  ///@{
  /**
   * Scripts as properties (what ParaView's proxy sets): the behaviour script in a file
   * and/or as text. When either changes, the next execution replaces every command by the
   * file's then the text's (commands given by the methods above after that are added to
   * them). Empty: none. A script that does not parse is an error of the execution, with
   * the core's "line N: ..." message, and an empty output.
   */
  void SetScriptFileName(const char* path);
  const char* GetScriptFileName();
  void SetScript(const char* text);
  const char* GetScript();
  ///@}

  ///@{
  /**
   * The output channels, in column order of port 0 (port 1 has `Time` first). They
   * depend on the scheduled utterances; asking prepares the behaviour if needed.
   */
  int GetNumberOfChannels();
  const char* GetChannelName(int index);
  /// -1 when there is no such channel.
  int GetChannelIndex(const char* name);
  ///@}

  ///@{
  /**
   * The frames of the track (port 1) and of TIME_STEPS: GetNumberOfFrames() frames at
   * GetFrameTime(i) = i / FrameRate, i = 0 .. floor(EffectiveDuration * FrameRate). Use
   * them to render every frame. GetFrameTime is -1 (and an error) outside the frames.
   */
  vtkIdType GetNumberOfFrames();
  double GetFrameTime(vtkIdType frame);
  ///@}

  /// TIME_STEPS are advertised up to this many frames: 4194304 (24 h at 48 fps).
  static vtkIdType GetMaximumNumberOfTimeSteps();

  ///@{
  /**
   * The scheduled utterances in the order they were added: their start and end in seconds
   * (the end of the longer of the sound and the visemes), e.g. to place a gesture after a
   * Say() queued with start -1. -1 (and an error) for an index out of range.
   */
  int GetNumberOfUtterances();
  double GetUtteranceStart(int index);
  double GetUtteranceEnd(int index);
  ///@}
  /// True when at least one scheduled utterance carries audio (Say and SpeakAudioFile do,
  /// .pho files, Rhubarb cues and other timing files not).
  bool HasAudio();

  /**
   * Writes a 16-bit mono WAV of the scheduled utterances, mixed at their start times on
   * the track's time axis (sample 0 = time 0), at least as long as the track. Silence when
   * nothing with audio is scheduled. False and an error when the file cannot be written.
   */
  bool WriteAudio(const char* path);

#ifndef __VTK_WRAP__
  /**
   * The core controller, read-only (for C++ code that samples it directly or inspects the
   * schedules), prepared unless preparing failed (then with an error). Changes go through
   * the methods of this class, which keep the modification time right. A copy keeps this
   * source's speech settings for its own Say() calls, also after the source is deleted.
   */
  const morphnode::BehaviorController& GetController();

  /// Schedules an utterance built by C++ code (morphnode::Utterance, e.g. from
  /// morphnode::BuildUtterance with audio of its own); as the other speech commands.
  bool Speak(const morphnode::Utterance& utterance, double start = -1.0);

  ///@{
  /// All behaviour parameters at once; false and an error for a value out of range.
  bool SetBehaviorParameters(const morphnode::BehaviorParameters& parameters);
  const morphnode::BehaviorParameters& GetBehaviorParameters();
  ///@}

  /// The speech settings of Say() now (voice, rate, viseme set or table), warnings to this
  /// source: for a live behaviour with the same voice (vtkLiveBehaviorSource::CopySettings).
  morphnode::SpeechOptions GetSpeechOptions();
#endif

protected:
  vtkBehaviorTimeSource();
  ~vtkBehaviorTimeSource() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkBehaviorTimeSource(const vtkBehaviorTimeSource&) = delete;
  void operator=(const vtkBehaviorTimeSource&) = delete;

  bool EnsurePrepared();

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
