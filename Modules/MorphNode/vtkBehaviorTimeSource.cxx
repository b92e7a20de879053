// SPDX-License-Identifier: BSD-3-Clause
#include "vtkBehaviorTimeSource.h"

#include "base/Error.h"
#include "behavior/BehaviorController.h"
#include "speech/Speech.h"
#include "speech/Wav.h"

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
#include <cstdint>
#include <exception>
#include <limits>
#include <string>
#include <vector>

struct vtkBehaviorTimeSource::vtkInternals
{
  morphnode::BehaviorController Controller;
  std::string Voice = "en";
  int SpeechRate = morphnode::SpeechSynthesizer::DefaultRate;
  int VisemeSet = vtkBehaviorTimeSource::PAPER6;

  /// The track of port 1, built once per preparation (null when stale).
  vtkSmartPointer<vtkTable> Track;

  morphnode::SpeechOptions Options(vtkBehaviorTimeSource* self) const
  {
    morphnode::SpeechOptions options;
    options.Voice = this->Voice;
    options.Rate = this->SpeechRate;
    options.Visemes = static_cast<morphnode::VisemeSet>(this->VisemeSet);
    // Problems that are no errors (unknown phonemes) become VTK warnings.
    options.Warn = [self](const std::string& message) { vtkWarningWithObjectMacro(self, << message); };
    return options;
  }

  /// Frames 0 .. floor(duration * fps), as morphnode::BehaviorController::GenerateTrack.
  size_t NumberOfFrames() const
  {
    return static_cast<size_t>(std::floor(
             this->Controller.GetEffectiveDuration() * this->Controller.GetFrameRate() + 1e-9)) +
      1;
  }
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
    if (!Guarded(this, [&]() { call; }, message_))                                                 \
    {                                                                                              \
      vtkErrorMacro(<< what << ": " << message_);                                                  \
      return false;                                                                                \
    }                                                                                              \
    this->Modified();                                                                              \
    return true;                                                                                   \
  } while (false)

//------------------------------------------------------------------------------
vtkBehaviorTimeSource::vtkBehaviorTimeSource()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
  // The synthesizer and the phoneme loader read the speech settings when called, so they
  // always use the current voice, rate and viseme set.
  this->Internals->Controller.SetSynthesizer(
    [this](const std::string& text) { return morphnode::SpeakText(text, this->Internals->Options(this)); });
  this->Internals->Controller.SetPhonemeFileLoader([this](const std::string& path) {
    return morphnode::LoadPhoUtterance(path, this->Internals->Options(this));
  });
}

//------------------------------------------------------------------------------
vtkBehaviorTimeSource::~vtkBehaviorTimeSource() = default;

//------------------------------------------------------------------------------
morphnode::BehaviorController& vtkBehaviorTimeSource::GetController()
{
  return this->Internals->Controller;
}

//------------------------------------------------------------------------------
int vtkBehaviorTimeSource::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
  return 1;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkBehaviorTimeSource::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // A request on port 0 (a time step) need not build the whole track of port 1: mark it
  // as not generated, so it stays out of date and executes when port 1 is asked for.
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_NOT_GENERATED()) &&
    request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) &&
    request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT()) == 0)
  {
    outputVector->GetInformationObject(1)->Set(vtkDemandDrivenPipeline::DATA_NOT_GENERATED(), 1);
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
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
  if (!Guarded(this, [&]() { this->Internals->Controller.SetFrameRate(fps); }, message))
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
  if (!Guarded(this, [&]() { this->Internals->Controller.SetDuration(seconds); }, message))
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
  if (v != this->Internals->Voice)
  {
    this->Internals->Voice = v;
    this->Modified();
  }
}

const char* vtkBehaviorTimeSource::GetVoice()
{
  return this->Internals->Voice.c_str();
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetSpeechRate(int wordsPerMinute)
{
  const int rate = std::min(std::max(wordsPerMinute, morphnode::SpeechSynthesizer::MinimumRate),
    morphnode::SpeechSynthesizer::MaximumRate);
  if (rate != this->Internals->SpeechRate)
  {
    this->Internals->SpeechRate = rate;
    this->Modified();
  }
}

int vtkBehaviorTimeSource::GetSpeechRate()
{
  return this->Internals->SpeechRate;
}

//------------------------------------------------------------------------------
void vtkBehaviorTimeSource::SetVisemeSet(int set)
{
  if (set < OCULUS15 || set > PAPER6)
  {
    vtkErrorMacro(<< "SetVisemeSet: " << set << " is no viseme set (OCULUS15 = 0, GERMAN16 = 1, PAPER6 = 2)");
    return;
  }
  if (set != this->Internals->VisemeSet)
  {
    this->Internals->VisemeSet = set;
    this->Modified();
  }
}

int vtkBehaviorTimeSource::GetVisemeSet()
{
  return this->Internals->VisemeSet;
}

bool vtkBehaviorTimeSource::SetVisemeSetFromString(const char* name)
{
  morphnode::VisemeSet set = morphnode::VisemeSet::Paper6;
  std::string message;
  if (!Guarded(this, [&]() { set = morphnode::ParseVisemeSet(Str(name)); }, message))
  {
    vtkErrorMacro(<< "SetVisemeSetFromString: " << message);
    return false;
  }
  this->SetVisemeSet(static_cast<int>(set));
  return true;
}

const char* vtkBehaviorTimeSource::GetVisemeSetAsString()
{
  return morphnode::VisemeSetName(static_cast<morphnode::VisemeSet>(this->Internals->VisemeSet));
}

//------------------------------------------------------------------------------
bool vtkBehaviorTimeSource::Say(const char* text, double start)
{
  MORPHNODE_COMMAND("Say", this->Internals->Controller.Say(Str(text), start));
}

bool vtkBehaviorTimeSource::SpeakPhonemeFile(const char* path, double start)
{
  MORPHNODE_COMMAND("SpeakPhonemeFile", this->Internals->Controller.SpeakPhonemeFile(Str(path), start));
}

bool vtkBehaviorTimeSource::Gesture(const char* name, double start, double duration, double intensity)
{
  MORPHNODE_COMMAND(
    "Gesture", this->Internals->Controller.Gesture(Str(name), start, duration, intensity));
}

bool vtkBehaviorTimeSource::SetMood(const char* name, double intensity, double start, double fade)
{
  MORPHNODE_COMMAND("SetMood", this->Internals->Controller.SetMood(Str(name), intensity, start, fade));
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
bool vtkBehaviorTimeSource::EnsurePrepared()
{
  auto& controller = this->Internals->Controller;
  if (controller.IsPrepared())
  {
    return true;
  }
  this->Internals->Track = nullptr;
  std::string message;
  if (!Guarded(this, [&]() { controller.Prepare(); }, message))
  {
    vtkErrorMacro(<< "cannot prepare the behaviour: " << message);
    return false;
  }
  return true;
}

int vtkBehaviorTimeSource::GetNumberOfChannels()
{
  return this->EnsurePrepared() ? static_cast<int>(this->Internals->Controller.GetNumberOfChannels())
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

int vtkBehaviorTimeSource::GetNumberOfUtterances()
{
  return static_cast<int>(this->Internals->Controller.GetUtterances().size());
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
  const auto& utterances = this->Internals->Controller.GetUtterances();
  int rate = 0;
  double end = this->Internals->Controller.GetEffectiveDuration();
  for (const auto& u : utterances)
  {
    if (!u.Speech.Audio.empty() && u.Speech.SampleRate > 0)
    {
      rate = std::max(rate, u.Speech.SampleRate);
      end = std::max(end, u.Start + static_cast<double>(u.Speech.Audio.size()) / u.Speech.SampleRate);
    }
  }
  if (rate == 0)
  {
    rate = 22050; // eSpeak NG's rate
  }
  if (!(end * rate < static_cast<double>(std::numeric_limits<int32_t>::max())))
  {
    vtkErrorMacro(<< "WriteAudio: " << end << " s of audio is too long for a WAV file");
    return false;
  }
  const size_t n = static_cast<size_t>(std::ceil(end * rate - 1e-9));
  std::vector<int32_t> mix(n, 0);
  for (const auto& u : utterances)
  {
    const auto& audio = u.Speech.Audio;
    if (audio.empty() || u.Speech.SampleRate <= 0)
    {
      continue;
    }
    // Sample i of the output is at time i / rate; resample (nearest) if the rates differ.
    const double ratio = static_cast<double>(u.Speech.SampleRate) / rate;
    const double first = std::round(u.Start * rate);
    const size_t count = static_cast<size_t>(std::floor(audio.size() / ratio));
    for (size_t j = 0; j < count; ++j)
    {
      const double i = first + static_cast<double>(j);
      if (i < 0 || i >= static_cast<double>(n))
      {
        continue;
      }
      const size_t source = std::min(audio.size() - 1, static_cast<size_t>(std::lround(j * ratio)));
      mix[static_cast<size_t>(i)] += audio[source];
    }
  }
  std::vector<int16_t> samples(n);
  for (size_t i = 0; i < n; ++i)
  {
    samples[i] = static_cast<int16_t>(std::min(32767, std::max(-32768, mix[i])));
  }
  std::string message;
  if (!Guarded(this, [&]() { morphnode::WriteWavFile(Str(path), samples, rate); }, message))
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
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  if (!this->EnsurePrepared())
  {
    return 0;
  }
  const auto& controller = this->Internals->Controller;
  const size_t frames = this->Internals->NumberOfFrames();
  std::vector<double> steps(frames);
  for (size_t f = 0; f < frames; ++f)
  {
    steps[f] = static_cast<double>(f) / controller.GetFrameRate();
  }
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps.data(), static_cast<int>(frames));
  double range[2] = { 0.0, controller.GetEffectiveDuration() };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

//------------------------------------------------------------------------------
int vtkBehaviorTimeSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* frameInfo = outputVector->GetInformationObject(0);
  vtkTable* frame = vtkTable::GetData(outputVector, 0);
  vtkTable* track = vtkTable::GetData(outputVector, 1);
  if (!frame || !track || !this->EnsurePrepared())
  {
    return 0;
  }
  const auto& controller = this->Internals->Controller;
  const auto& names = controller.GetChannelNames();
  std::vector<double> row(names.size());

  // Port 0: the behaviour at the requested time.
  const double t = frameInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    ? frameInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
    : 0.0;
  std::string message;
  if (!Guarded(this, [&]() { controller.Sample(t, row.data()); }, message))
  {
    vtkErrorMacro(<< "cannot sample the behaviour at t = " << t << ": " << message);
    return 0;
  }
  frame->Initialize();
  for (size_t c = 0; c < names.size(); ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(names[c].c_str());
    column->SetNumberOfValues(1);
    column->SetValue(0, row[c]);
    frame->AddColumn(column);
  }
  frame->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), t);

  // Port 1: the whole track, built once per preparation, when asked for.
  if (outputVector->GetInformationObject(1)->Get(vtkDemandDrivenPipeline::DATA_NOT_GENERATED()))
  {
    return 1;
  }
  if (!this->Internals->Track)
  {
    const size_t frames = this->Internals->NumberOfFrames();
    vtkNew<vtkTable> table;
    std::vector<vtkDoubleArray*> columns;
    vtkNew<vtkDoubleArray> time;
    time->SetName("Time");
    time->SetNumberOfValues(static_cast<vtkIdType>(frames));
    table->AddColumn(time);
    for (const auto& name : names)
    {
      vtkNew<vtkDoubleArray> column;
      column->SetName(name.c_str());
      column->SetNumberOfValues(static_cast<vtkIdType>(frames));
      table->AddColumn(column);
      columns.push_back(column);
    }
    for (size_t f = 0; f < frames; ++f)
    {
      const double tf = static_cast<double>(f) / controller.GetFrameRate();
      controller.Sample(tf, row.data());
      time->SetValue(static_cast<vtkIdType>(f), tf);
      for (size_t c = 0; c < names.size(); ++c)
      {
        columns[c]->SetValue(static_cast<vtkIdType>(f), row[c]);
      }
    }
    this->Internals->Track = table;
  }
  track->ShallowCopy(this->Internals->Track);
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
  os << indent << "Voice: " << this->Internals->Voice << "\n";
  os << indent << "SpeechRate: " << this->Internals->SpeechRate << "\n";
  os << indent << "VisemeSet: " << this->GetVisemeSetAsString() << "\n";
  os << indent << "Utterances: " << controller.GetUtterances().size() << "\n";
  os << indent << "Gestures: " << controller.GetGestures().size() << "\n";
  if (controller.IsPrepared())
  {
    os << indent << "EffectiveDuration: " << controller.GetEffectiveDuration() << "\n";
    os << indent << "Channels:";
    for (const auto& name : controller.GetChannelNames())
    {
      os << " " << name;
    }
    os << "\n";
  }
}
