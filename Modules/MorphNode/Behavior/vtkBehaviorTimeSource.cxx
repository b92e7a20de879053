// SPDX-License-Identifier: BSD-3-Clause
#include "vtkBehaviorTimeSource.h"

#include "align/RecordingSpeech.h"
#include "base/Error.h"
#include "behavior/BehaviorAudio.h"
#include "behavior/BehaviorController.h"
#include "behavior/Frames.h"
#include "speech/Pho.h"
#include "speech/Rhubarb.h"
#include "speech/Speech.h"
#include "speech/TimingFiles.h"

#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <vector>

// The viseme sets of the VTK API are the core's, by value.
static_assert(vtkBehaviorTimeSource::OCULUS15 == static_cast<int>(morphnode::VisemeSet::Oculus15) &&
    vtkBehaviorTimeSource::GERMAN16 == static_cast<int>(morphnode::VisemeSet::German16) &&
    vtkBehaviorTimeSource::PAPER6 == static_cast<int>(morphnode::VisemeSet::Paper6),
  "vtkBehaviorTimeSource::VisemeSets must match morphnode::VisemeSet");

namespace
{
/// The speech settings of the commands. The controller's synthesizer and phoneme loader
/// share them (not the source), so a copy of the controller stays safe after the source is
/// deleted; Owner (the source, for warnings) is null then.
struct SpeechSettings
{
  std::string Voice = "en";
  int Rate = morphnode::SpeechSynthesizer::DefaultRate;
  int VisemeSet = vtkBehaviorTimeSource::PAPER6;
  std::string VisemeTable;
  vtkBehaviorTimeSource* Owner = nullptr;

  morphnode::SpeechOptions Options() const
  {
    morphnode::SpeechOptions options;
    options.Voice = this->Voice;
    options.Rate = this->Rate;
    options.Visemes = static_cast<morphnode::VisemeSet>(this->VisemeSet);
    options.VisemeTablePath = this->VisemeTable;
    // Problems that are no errors (unknown phonemes) become VTK warnings.
    vtkBehaviorTimeSource* owner = this->Owner;
    options.Warn = [owner](const std::string& message)
    {
      if (owner)
      {
        vtkWarningWithObjectMacro(owner, << message);
      }
    };
    return options;
  }
};
} // namespace

struct vtkBehaviorTimeSource::vtkInternals
{
  morphnode::BehaviorController Controller;
  std::shared_ptr<SpeechSettings> Speech = std::make_shared<SpeechSettings>();

  /// The format of timing files (SetTimingFormat).
  morphnode::TimingFileOptions Timing;

  /// The track of port 1, built once per preparation (null when stale).
  vtkSmartPointer<vtkTable> Track;

  /// The script properties, and whether they changed since they were applied.
  std::string ScriptFileName;
  std::string Script;
  bool ScriptsChanged = false;
  /// Why the script properties failed; the source fails until they change.
  std::string ScriptError;
};

vtkStandardNewMacro(vtkBehaviorTimeSource);

namespace
{
/// Runs a core call; InputError (and anything else thrown) becomes an error message.
template <typename F>
bool Guarded(vtkBehaviorTimeSource* self, F&& call, std::string& message)
{
  try
  {
    call();
    return true;
  }
  catch (const morphnode::InputError& e)
  {
    message = e.what();
  }
  catch (const std::exception& e)
  {
    message = std::string("unexpected failure: ") + e.what();
  }
  (void)self;
  return false;
}

std::string Str(const char* s)
{
  return s ? std::string(s) : std::string();
}
} // namespace

#define MORPHNODE_COMMAND(what, call)                                                              \
  do                                                                                               \
  {                                                                                                \
    std::string message_;                                                                          \
    if (!Guarded(                                                                                  \
          this, [&]() { call; }, message_))                                                        \
    {                                                                                              \
      vtkErrorMacro(<< (what) << ": " << message_);                                                \
      return false;                                                                                \
    }                                                                                              \
    this->Modified();                                                                              \
    return true;                                                                                   \
  } while (false)

//------------------------------------------------------------------------------
vtkBehaviorTimeSource::vtkBehaviorTimeSource()
  : Internals(new vtkInternals)
{
  // The synthesizer and the phoneme loader (of Say, SpeakPhonemeFile and the scripts) read
  // the speech settings when called, so they always use the current voice, rate and table.
  // The loader reads every timing file (.pho, Rhubarb, TextGrid, speech marks), so a script's
  // `phonemes <file>` takes any of them.
  auto& speech = this->Internals->Speech;
  speech->Owner = this;
  this->Internals->Controller.SetSynthesizer(
    [speech](const std::string& text) { return morphnode::SpeakText(text, speech->Options()); });
  this->Internals->Controller.SetPhonemeFileLoader([speech](const std::string& path)
    { return morphnode::LoadTimingFile(path, speech->Options()); });
}

//------------------------------------------------------------------------------
vtkBehaviorTimeSource::~vtkBehaviorTimeSource()
{
  this->Internals->Speech->Owner = nullptr;
}

//------------------------------------------------------------------------------
const morphnode::BehaviorController& vtkBehaviorTimeSource::GetController()
{
  this->EnsurePrepared();
  return this->Internals->Controller;
}

//------------------------------------------------------------------------------
morphnode::SpeechOptions vtkBehaviorTimeSource::GetSpeechOptions()
{
  return this->Internals->Speech->Options();
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetSeed(vtkTypeUInt64 seed)
{
  if (this->Internals->Controller.GetSeed() != seed)
  {
    this->Internals->Controller.SetSeed(seed);
    this->Modified();
  }
}

vtkTypeUInt64 vtkBehaviorTimeSource::GetSeed()
{
  return this->Internals->Controller.GetSeed();
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetFrameRate(double fps)
{
  if (this->Internals->Controller.GetFrameRate() == fps)
  {
    return;
  }
  std::string message;
  if (!Guarded(
        this, [&]() { this->Internals->Controller.SetFrameRate(fps); }, message))
  {
    vtkErrorMacro(<< "SetFrameRate: " << message);
    return;
  }
  this->Modified();
}

double vtkBehaviorTimeSource::GetFrameRate()
{
  return this->Internals->Controller.GetFrameRate();
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetDuration(double seconds)
{
  if (this->Internals->Controller.GetDuration() == seconds)
  {
    return;
  }
  std::string message;
  if (!Guarded(
        this, [&]() { this->Internals->Controller.SetDuration(seconds); }, message))
  {
    vtkErrorMacro(<< "SetDuration: " << message);
    return;
  }
  this->Modified();
}

double vtkBehaviorTimeSource::GetDuration()
{
  return this->Internals->Controller.GetDuration();
}

double vtkBehaviorTimeSource::GetEffectiveDuration()
{
  return this->EnsurePrepared() ? this->Internals->Controller.GetEffectiveDuration() : 0.0;
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetVoice(const char* voice)
{
  const std::string v = Str(voice);
  if (v.empty())
  {
    vtkErrorMacro(<< "SetVoice: an eSpeak voice name is needed, e.g. \"en\" or \"de\"");
    return;
  }
  if (v != this->Internals->Speech->Voice)
  {
    this->Internals->Speech->Voice = v;
    this->Modified();
  }
}

const char* vtkBehaviorTimeSource::GetVoice()
{
  return this->Internals->Speech->Voice.c_str();
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetSpeechRate(int wordsPerMinute)
{
  const int rate = std::min(std::max(wordsPerMinute, morphnode::SpeechSynthesizer::MinimumRate),
    morphnode::SpeechSynthesizer::MaximumRate);
  if (rate != this->Internals->Speech->Rate)
  {
    this->Internals->Speech->Rate = rate;
    this->Modified();
  }
}

int vtkBehaviorTimeSource::GetSpeechRate()
{
  return this->Internals->Speech->Rate;
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetVisemeSet(int set)
{
  if (set < OCULUS15 || set > PAPER6)
  {
    vtkErrorMacro(<< "SetVisemeSet: " << set
                  << " is no viseme set (OCULUS15 = 0, GERMAN16 = 1, PAPER6 = 2)");
    return;
  }
  if (set != this->Internals->Speech->VisemeSet)
  {
    this->Internals->Speech->VisemeSet = set;
    this->Modified();
  }
}

int vtkBehaviorTimeSource::GetVisemeSet()
{
  return this->Internals->Speech->VisemeSet;
}

bool vtkBehaviorTimeSource::SetVisemeSetFromString(const char* name)
{
  morphnode::VisemeSet set = morphnode::VisemeSet::Paper6;
  std::string message;
  if (!Guarded(
        this, [&]() { set = morphnode::ParseVisemeSet(Str(name)); }, message))
  {
    vtkErrorMacro(<< "SetVisemeSetFromString: " << message);
    return false;
  }
  this->SetVisemeSet(static_cast<int>(set));
  return true;
}

const char* vtkBehaviorTimeSource::GetVisemeSetAsString()
{
  return morphnode::VisemeSetName(
    static_cast<morphnode::VisemeSet>(this->Internals->Speech->VisemeSet));
}

//------------------------------------------------------------------------------
bool vtkBehaviorTimeSource::SetVisemeTableFileName(const char* path)
{
  const std::string p = Str(path);
  if (p == this->Internals->Speech->VisemeTable)
  {
    return true;
  }
  std::string message;
  if (!p.empty() &&
    !Guarded(
      this, [&]() { morphnode::VisemeMap::Load(p); }, message))
  {
    vtkErrorMacro(<< "SetVisemeTableFileName: " << message);
    return false;
  }
  this->Internals->Speech->VisemeTable = p;
  this->Modified();
  return true;
}

const char* vtkBehaviorTimeSource::GetVisemeTableFileName()
{
  return this->Internals->Speech->VisemeTable.c_str();
}

//------------------------------------------------------------------------------
int vtkBehaviorTimeSource::GetNumberOfBehaviorParameters()
{
  return static_cast<int>(morphnode::BehaviorParameterNames().size());
}

const char* vtkBehaviorTimeSource::GetBehaviorParameterName(int index)
{
  const auto& names = morphnode::BehaviorParameterNames();
  if (index < 0 || index >= static_cast<int>(names.size()))
  {
    vtkErrorMacro(<< "GetBehaviorParameterName: no parameter " << index << " (there are "
                  << names.size() << ")");
    return nullptr;
  }
  return names[static_cast<size_t>(index)].c_str();
}

bool vtkBehaviorTimeSource::SetBehaviorParameter(const char* name, double value)
{
  morphnode::BehaviorParameters parameters = this->Internals->Controller.GetParameters();
  std::string message;
  if (!Guarded(
        this, [&]() { morphnode::SetBehaviorParameter(parameters, Str(name), value); }, message))
  {
    vtkErrorMacro(<< "SetBehaviorParameter: " << message);
    return false;
  }
  return this->SetBehaviorParameters(parameters);
}

double vtkBehaviorTimeSource::GetBehaviorParameter(const char* name)
{
  double value = std::numeric_limits<double>::quiet_NaN();
  std::string message;
  if (!Guarded(
        this,
        [&]()
        {
          value =
            morphnode::GetBehaviorParameter(this->Internals->Controller.GetParameters(), Str(name));
        },
        message))
  {
    vtkErrorMacro(<< "GetBehaviorParameter: " << message);
  }
  return value;
}

bool vtkBehaviorTimeSource::SetBehaviorParameters(const morphnode::BehaviorParameters& parameters)
{
  const auto& current = this->Internals->Controller.GetParameters();
  bool same = true;
  for (const auto& name : morphnode::BehaviorParameterNames())
  {
    // Compared bit for bit as the setters compare (NaN is rejected by the range checks).
    same = same &&
      morphnode::GetBehaviorParameter(current, name) ==
        morphnode::GetBehaviorParameter(parameters, name);
  }
  if (same)
  {
    return true;
  }
  MORPHNODE_COMMAND("SetBehaviorParameters", this->Internals->Controller.SetParameters(parameters));
}

const morphnode::BehaviorParameters& vtkBehaviorTimeSource::GetBehaviorParameters()
{
  return this->Internals->Controller.GetParameters();
}

void vtkBehaviorTimeSource::ResetBehaviorParameters()
{
  this->SetBehaviorParameters(morphnode::BehaviorParameters());
}

//------------------------------------------------------------------------------
bool vtkBehaviorTimeSource::Say(const char* text, double start)
{
  MORPHNODE_COMMAND("Say", this->Internals->Controller.Say(Str(text), start));
}

bool vtkBehaviorTimeSource::SpeakPhonemeFile(const char* path, double start)
{
  MORPHNODE_COMMAND(
    "SpeakPhonemeFile", this->Internals->Controller.SpeakPhonemeFile(Str(path), start));
}

bool vtkBehaviorTimeSource::SpeakPhonemes(const char* pho, double start)
{
  MORPHNODE_COMMAND("SpeakPhonemes",
    this->Internals->Controller.Speak(
      morphnode::UtteranceFromPhonemes(
        morphnode::ParsePho(Str(pho)), this->Internals->Speech->Options()),
      start));
}

bool vtkBehaviorTimeSource::SpeakRhubarbFile(const char* path, double start)
{
  MORPHNODE_COMMAND("SpeakRhubarbFile",
    this->Internals->Controller.Speak(
      morphnode::UtteranceFromMouthCues(
        morphnode::ReadRhubarbFile(Str(path)), this->Internals->Speech->Options()),
      start));
}

bool vtkBehaviorTimeSource::SpeakRhubarbCues(const char* cues, double start)
{
  MORPHNODE_COMMAND("SpeakRhubarbCues",
    this->Internals->Controller.Speak(
      morphnode::UtteranceFromMouthCues(
        morphnode::ParseRhubarb(Str(cues)), this->Internals->Speech->Options()),
      start));
}

bool vtkBehaviorTimeSource::SetTimingFormat(const char* name)
{
  try
  {
    this->Internals->Timing.Format =
      morphnode::ParseTimingFormat(Str(name).empty() ? "auto" : Str(name));
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "SetTimingFormat: " << e.what());
    return false;
  }
  return true;
}

const char* vtkBehaviorTimeSource::GetTimingFormat()
{
  return morphnode::TimingFormatName(this->Internals->Timing.Format);
}

bool vtkBehaviorTimeSource::SpeakTimingFile(const char* path, double start)
{
  MORPHNODE_COMMAND("SpeakTimingFile",
    this->Internals->Controller.Speak(
      morphnode::LoadTimingFile(
        Str(path), this->Internals->Speech->Options(), this->Internals->Timing),
      start));
}

bool vtkBehaviorTimeSource::SpeakAudioFile(const char* path, const char* transcript, double start)
{
  morphnode::RecordingOptions recording;
  recording.Transcript = Str(transcript);
  MORPHNODE_COMMAND("SpeakAudioFile",
    this->Internals->Controller.Speak(
      morphnode::SpeakAudioFile(Str(path), this->Internals->Speech->Options(), recording), start));
}

bool vtkBehaviorTimeSource::SpeakAudioFileWithTimings(
  const char* path, const char* timingFile, double start)
{
  morphnode::RecordingOptions recording;
  recording.TimingFile = Str(timingFile);
  recording.Timing = this->Internals->Timing;
  if (recording.TimingFile.empty())
  {
    vtkErrorMacro(<< "SpeakAudioFileWithTimings: a timing file is needed (.TextGrid, .marks, .pho, "
                     ".tsv, .json)");
    return false;
  }
  MORPHNODE_COMMAND("SpeakAudioFileWithTimings",
    this->Internals->Controller.Speak(
      morphnode::SpeakAudioFile(Str(path), this->Internals->Speech->Options(), recording), start));
}

bool vtkBehaviorTimeSource::Speak(const morphnode::Utterance& utterance, double start)
{
  MORPHNODE_COMMAND("Speak", this->Internals->Controller.Speak(utterance, start));
}

bool vtkBehaviorTimeSource::Gesture(
  const char* name, double start, double duration, double intensity)
{
  MORPHNODE_COMMAND(
    "Gesture", this->Internals->Controller.Gesture(Str(name), start, duration, intensity));
}

bool vtkBehaviorTimeSource::SetMood(const char* name, double intensity, double start, double fade)
{
  MORPHNODE_COMMAND(
    "SetMood", this->Internals->Controller.SetMood(Str(name), intensity, start, fade));
}

bool vtkBehaviorTimeSource::LookAt(double yaw, double pitch, double start, double duration)
{
  MORPHNODE_COMMAND("LookAt", this->Internals->Controller.LookAt(yaw, pitch, start, duration));
}

bool vtkBehaviorTimeSource::LoadScript(const char* path)
{
  MORPHNODE_COMMAND("LoadScript", this->Internals->Controller.LoadScript(Str(path)));
}

bool vtkBehaviorTimeSource::ParseScript(const char* text)
{
  MORPHNODE_COMMAND("ParseScript", this->Internals->Controller.ParseScript(Str(text)));
}

void vtkBehaviorTimeSource::ClearCommands()
{
  this->Internals->Controller.ClearCommands();
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetScriptFileName(const char* path)
{
  if (this->Internals->ScriptFileName != Str(path))
  {
    this->Internals->ScriptFileName = Str(path);
    this->Internals->ScriptsChanged = true;
    this->Modified();
  }
}

const char* vtkBehaviorTimeSource::GetScriptFileName()
{
  return this->Internals->ScriptFileName.c_str();
}

void vtkBehaviorTimeSource::SetScript(const char* text)
{
  if (this->Internals->Script != Str(text))
  {
    this->Internals->Script = Str(text);
    this->Internals->ScriptsChanged = true;
    this->Modified();
  }
}

const char* vtkBehaviorTimeSource::GetScript()
{
  return this->Internals->Script.c_str();
}

//------------------------------------------------------------------------------
bool vtkBehaviorTimeSource::EnsurePrepared()
{
  auto& controller = this->Internals->Controller;
  if (this->Internals->ScriptsChanged)
  {
    // The script properties replace every command, all or nothing.
    this->Internals->ScriptsChanged = false;
    this->Internals->ScriptError.clear();
    controller.ClearCommands();
    std::string message;
    const bool ok = Guarded(
      this,
      [&]()
      {
        if (!this->Internals->ScriptFileName.empty())
        {
          controller.LoadScript(this->Internals->ScriptFileName);
        }
        if (!this->Internals->Script.empty())
        {
          controller.ParseScript(this->Internals->Script);
        }
      },
      message);
    if (!ok)
    {
      controller.ClearCommands();
      this->Internals->Track = nullptr;
      this->Internals->ScriptError = message;
    }
  }
  if (!this->Internals->ScriptError.empty())
  {
    vtkErrorMacro(<< "the behaviour script: " << this->Internals->ScriptError);
    return false;
  }
  if (controller.IsPrepared())
  {
    return true;
  }
  this->Internals->Track = nullptr;
  std::string message;
  if (!Guarded(
        this, [&]() { controller.Prepare(); }, message))
  {
    vtkErrorMacro(<< "cannot prepare the behaviour: " << message);
    return false;
  }
  return true;
}

int vtkBehaviorTimeSource::GetNumberOfChannels()
{
  return this->EnsurePrepared()
    ? static_cast<int>(this->Internals->Controller.GetNumberOfChannels())
    : 0;
}

const char* vtkBehaviorTimeSource::GetChannelName(int index)
{
  if (index < 0 || index >= this->GetNumberOfChannels())
  {
    vtkErrorMacro(<< "GetChannelName: no channel " << index << " (there are "
                  << this->GetNumberOfChannels() << ")");
    return nullptr;
  }
  return this->Internals->Controller.GetChannelNames()[static_cast<size_t>(index)].c_str();
}

int vtkBehaviorTimeSource::GetChannelIndex(const char* name)
{
  return this->EnsurePrepared() ? this->Internals->Controller.FindChannel(Str(name)) : -1;
}

vtkIdType vtkBehaviorTimeSource::GetNumberOfFrames()
{
  if (!this->EnsurePrepared())
  {
    return 0;
  }
  return static_cast<vtkIdType>(this->Internals->Controller.GetNumberOfFrames());
}

double vtkBehaviorTimeSource::GetFrameTime(vtkIdType frame)
{
  const vtkIdType frames = this->GetNumberOfFrames();
  if (frame < 0 || frame >= frames)
  {
    vtkErrorMacro(<< "GetFrameTime: no frame " << frame << " (there are " << frames << ")");
    return -1.0;
  }
  return this->Internals->Controller.GetFrameTime(static_cast<size_t>(frame));
}

vtkIdType vtkBehaviorTimeSource::GetMaximumNumberOfTimeSteps()
{
  return vtkIdType(1) << 22;
}

int vtkBehaviorTimeSource::GetNumberOfUtterances()
{
  return static_cast<int>(this->Internals->Controller.GetUtterances().size());
}

double vtkBehaviorTimeSource::GetUtteranceStart(int index)
{
  const auto& utterances = this->Internals->Controller.GetUtterances();
  if (index < 0 || index >= static_cast<int>(utterances.size()))
  {
    vtkErrorMacro(<< "GetUtteranceStart: no utterance " << index << " (there are "
                  << utterances.size() << ")");
    return -1.0;
  }
  return utterances[static_cast<size_t>(index)].Start;
}

double vtkBehaviorTimeSource::GetUtteranceEnd(int index)
{
  const auto& utterances = this->Internals->Controller.GetUtterances();
  if (index < 0 || index >= static_cast<int>(utterances.size()))
  {
    vtkErrorMacro(<< "GetUtteranceEnd: no utterance " << index << " (there are "
                  << utterances.size() << ")");
    return -1.0;
  }
  return utterances[static_cast<size_t>(index)].End;
}

bool vtkBehaviorTimeSource::HasAudio()
{
  for (const auto& u : this->Internals->Controller.GetUtterances())
  {
    if (!u.Speech.Audio.empty())
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
bool vtkBehaviorTimeSource::WriteAudio(const char* path)
{
  if (!this->EnsurePrepared())
  {
    return false;
  }
  std::string message;
  if (!Guarded(
        this, [&]() { morphnode::WriteBehaviorAudio(Str(path), this->Internals->Controller); },
        message))
  {
    vtkErrorMacro(<< "WriteAudio: " << message);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkBehaviorTimeSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkMorphTrackSource::ClearTimeInformation(outputVector);
  if (!this->EnsurePrepared())
  {
    return 0;
  }
  const auto& controller = this->Internals->Controller;
  const size_t frames = controller.GetNumberOfFrames();
  std::vector<double> steps;
  if (frames <= static_cast<size_t>(GetMaximumNumberOfTimeSteps()))
  {
    steps.resize(frames);
    for (size_t f = 0; f < frames; ++f)
    {
      steps[f] = controller.GetFrameTime(f);
    }
  }
  vtkMorphTrackSource::SetTimeInformation(
    outputVector, steps.data(), static_cast<int>(steps.size()), controller.GetEffectiveDuration());
  return 1;
}

//------------------------------------------------------------------------------
int vtkBehaviorTimeSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkTable* frame = vtkTable::GetData(outputVector, 0);
  vtkTable* track = vtkTable::GetData(outputVector, 1);
  if (!frame || !track)
  {
    vtkErrorMacro(<< "the outputs are not vtkTables");
    return 0;
  }
  frame->Initialize();
  const bool trackWanted = vtkMorphTrackSource::IsTrackWanted(outputVector);
  if (trackWanted)
  {
    track->Initialize();
  }
  if (!this->EnsurePrepared())
  {
    return 0;
  }
  const auto& controller = this->Internals->Controller;
  const auto& names = controller.GetChannelNames();

  // Port 0: the behaviour at the requested time.
  const double t = vtkMorphTrackSource::RequestedTime(outputVector);
  std::vector<double> row(names.size());
  std::string message;
  if (!Guarded(
        this, [&]() { controller.Sample(t, row.data()); }, message))
  {
    vtkErrorMacro(<< "cannot sample the behaviour at t = " << t << ": " << message);
    return 0;
  }
  for (size_t c = 0; c < names.size(); ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(names[c].c_str());
    column->SetNumberOfValues(1);
    column->SetValue(0, row[c]);
    frame->AddColumn(column);
  }
  frame->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), t);

  // Port 1: the whole track (the core samples it), built once per preparation, when asked for.
  if (!trackWanted)
  {
    this->UpdateProgress(1.0);
    return 1;
  }
  this->UpdateProgress(0.1);
  if (!this->Internals->Track)
  {
    morphnode::WeightTrack sampled;
    if (!Guarded(
          this, [&]() { sampled = controller.SampleTrack(); }, message))
    {
      vtkErrorMacro(<< "cannot build the track: " << message);
      frame->Initialize();
      return 0;
    }
    const vtkIdType frames = static_cast<vtkIdType>(sampled.GetNumberOfFrames());
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> time;
    time->SetName("Time");
    time->SetNumberOfValues(frames);
    for (vtkIdType f = 0; f < frames; ++f)
    {
      time->SetValue(f, sampled.GetTime(static_cast<size_t>(f)));
    }
    table->AddColumn(time);
    for (size_t c = 0; c < names.size(); ++c)
    {
      vtkNew<vtkDoubleArray> column;
      column->SetName(names[c].c_str());
      column->SetNumberOfValues(frames);
      for (vtkIdType f = 0; f < frames; ++f)
      {
        column->SetValue(f, sampled.GetValue(static_cast<size_t>(f), c));
      }
      table->AddColumn(column);
    }
    this->Internals->Track = table;
  }
  track->ShallowCopy(this->Internals->Track);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const auto& controller = this->Internals->Controller;
  os << indent << "Seed: " << controller.GetSeed() << "\n";
  os << indent << "FrameRate: " << controller.GetFrameRate() << "\n";
  os << indent << "Duration: " << controller.GetDuration() << "\n";
  os << indent << "Voice: " << this->Internals->Speech->Voice << "\n";
  os << indent << "SpeechRate: " << this->Internals->Speech->Rate << "\n";
  os << indent << "VisemeSet: " << this->GetVisemeSetAsString() << "\n";
  os << indent << "ScriptFileName: "
     << (this->Internals->ScriptFileName.empty() ? "(none)" : this->Internals->ScriptFileName)
     << "\n";
  os << indent << "Script: " << this->Internals->Script.size() << " characters\n";
  os << indent << "VisemeTableFileName: "
     << (this->Internals->Speech->VisemeTable.empty() ? "(none)"
                                                      : this->Internals->Speech->VisemeTable)
     << "\n";
  os << indent << "BehaviorParameters:";
  const morphnode::BehaviorParameters defaults;
  int changed = 0;
  for (const auto& name : morphnode::BehaviorParameterNames())
  {
    const double value = morphnode::GetBehaviorParameter(controller.GetParameters(), name);
    if (value != morphnode::GetBehaviorParameter(defaults, name))
    {
      os << " " << name << "=" << value;
      ++changed;
    }
  }
  os << (changed ? "\n" : " (defaults)\n");
  os << indent << "Utterances: " << controller.GetUtterances().size() << "\n";
  for (const auto& u : controller.GetUtterances())
  {
    os << indent.GetNextIndent() << "[" << u.Start << ", " << u.End << "] s"
       << (u.Speech.Audio.empty() ? "" : ", with audio") << "\n";
  }
  os << indent << "Gestures: " << controller.GetGestures().size() << "\n";
  if (controller.IsPrepared())
  {
    os << indent << "EffectiveDuration: " << controller.GetEffectiveDuration() << "\n";
    os << indent << "NumberOfFrames: " << controller.GetNumberOfFrames() << "\n";
    os << indent << "Channels:";
    for (const auto& name : controller.GetChannelNames())
    {
      os << " " << name;
    }
    os << "\n";
  }
}
