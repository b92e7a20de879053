// SPDX-License-Identifier: BSD-3-Clause
#include "vtkLiveBehaviorSource.h"

#include "vtkBehaviorTimeSource.h"

#include "base/Error.h"
#include "behavior/BehaviorTypes.h"
#include "behavior/LiveBehavior.h"
#include "speech/Speech.h"

#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"

#include <cmath>
#include <exception>
#include <string>
#include <vector>

struct vtkLiveBehaviorSource::vtkInternals
{
  morphnode::SpeechOptions Speech;
  morphnode::BehaviorParameters Parameters;
  uint64_t Seed = 1;
  std::unique_ptr<morphnode::LiveBehavior> Live;
  /// Added to requested times so that the behaviour's time never goes back.
  double Offset = 0.0;
  std::vector<double> Row;

  vtkInternals() { this->Speech.Visemes = morphnode::VisemeSet::Paper6; }

  /// A new live behaviour of the settings (InputError when they make none).
  void Start(vtkLiveBehaviorSource* self)
  {
    // Warnings of the synthesis (unknown phonemes) go to this source; the synthesizer is
    // the behaviour's, which the source owns, so `self` outlives it.
    this->Speech.Warn = [self](const std::string& message)
    { vtkWarningWithObjectMacro(self, << message); };
    auto live = std::make_unique<morphnode::LiveBehavior>(
      morphnode::SelectVisemeMap(this->Speech).GetVisemes(), this->Parameters, this->Seed);
    const morphnode::SpeechOptions speech = this->Speech;
    live->SetSynthesizer(
      [speech](const std::string& text) { return morphnode::SpeakText(text, speech); });
    this->Live = std::move(live);
    this->Offset = 0.0;
  }
};

vtkStandardNewMacro(vtkLiveBehaviorSource);

namespace
{
/// Runs a core call; an exception becomes an error of `self` and false.
template <typename F>
bool Guarded(vtkLiveBehaviorSource* self, const char* what, F&& call)
{
  try
  {
    call();
    return true;
  }
  catch (const morphnode::InputError& e)
  {
    vtkErrorWithObjectMacro(self, << what << ": " << e.what());
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(self, << what << ": unexpected failure: " << e.what());
  }
  return false;
}
} // namespace

//------------------------------------------------------------------------------
vtkLiveBehaviorSource::vtkLiveBehaviorSource()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
  this->Internals->Start(this); // the default settings always make one
}

//------------------------------------------------------------------------------
vtkLiveBehaviorSource::~vtkLiveBehaviorSource() = default;

//------------------------------------------------------------------------------
morphnode::LiveBehavior& vtkLiveBehaviorSource::GetLiveBehavior()
{
  return *this->Internals->Live;
}

//------------------------------------------------------------------------------
bool vtkLiveBehaviorSource::CopySettings(vtkBehaviorTimeSource* settings)
{
  if (!settings)
  {
    vtkErrorMacro(<< "CopySettings: no behaviour source given");
    return false;
  }
  vtkInternals& in = *this->Internals;
  const morphnode::SpeechOptions oldSpeech = in.Speech;
  const morphnode::BehaviorParameters oldParameters = in.Parameters;
  const uint64_t oldSeed = in.Seed;
  in.Speech = settings->GetSpeechOptions();
  in.Parameters = settings->GetBehaviorParameters();
  in.Seed = settings->GetSeed();
  if (!Guarded(this, "CopySettings", [&]() { in.Start(this); }))
  {
    in.Speech = oldSpeech;
    in.Parameters = oldParameters;
    in.Seed = oldSeed;
    return false;
  }
  this->Modified();
  return true;
}

//------------------------------------------------------------------------------
void vtkLiveBehaviorSource::SetSeed(vtkTypeUInt64 seed)
{
  if (seed != this->Internals->Seed)
  {
    this->Internals->Seed = seed;
    this->Internals->Start(this);
    this->Modified();
  }
}

vtkTypeUInt64 vtkLiveBehaviorSource::GetSeed()
{
  return this->Internals->Seed;
}

//------------------------------------------------------------------------------
bool vtkLiveBehaviorSource::SetVisemeSetFromString(const char* name)
{
  vtkInternals& in = *this->Internals;
  const morphnode::VisemeSet old = in.Speech.Visemes;
  const bool ok = Guarded(this, "SetVisemeSetFromString",
    [&]()
    {
      in.Speech.Visemes = morphnode::ParseVisemeSet(name ? name : "");
      in.Start(this);
    });
  if (!ok)
  {
    in.Speech.Visemes = old;
    return false;
  }
  this->Modified();
  return true;
}

const char* vtkLiveBehaviorSource::GetVisemeSetAsString()
{
  return morphnode::VisemeSetName(this->Internals->Speech.Visemes);
}

//------------------------------------------------------------------------------
int vtkLiveBehaviorSource::GetNumberOfChannels()
{
  return static_cast<int>(this->Internals->Live->GetNumberOfChannels());
}

const char* vtkLiveBehaviorSource::GetChannelName(int index)
{
  const auto& names = this->Internals->Live->GetChannelNames();
  return index >= 0 && static_cast<size_t>(index) < names.size()
    ? names[static_cast<size_t>(index)].c_str()
    : nullptr;
}

//------------------------------------------------------------------------------
bool vtkLiveBehaviorSource::Say(const char* text, double now)
{
  const bool ok =
    Guarded(this, "Say", [&]() { this->Internals->Live->Say(text ? text : "", now); });
  this->Modified();
  return ok;
}

bool vtkLiveBehaviorSource::Gesture(const char* name, double now, double intensity, double duration)
{
  const bool ok = Guarded(this, "Gesture",
    [&]() { this->Internals->Live->Gesture(name ? name : "", now, intensity, duration); });
  this->Modified();
  return ok;
}

bool vtkLiveBehaviorSource::SetMood(const char* name, double intensity, double now)
{
  const bool ok = Guarded(
    this, "SetMood", [&]() { this->Internals->Live->SetMood(name ? name : "", intensity, now); });
  this->Modified();
  return ok;
}

bool vtkLiveBehaviorSource::LookAt(double yaw, double pitch, double now, double duration)
{
  const bool ok =
    Guarded(this, "LookAt", [&]() { this->Internals->Live->LookAt(yaw, pitch, now, duration); });
  this->Modified();
  return ok;
}

void vtkLiveBehaviorSource::StopSpeaking(double now)
{
  this->Internals->Live->StopSpeaking(now);
  this->Modified();
}

//------------------------------------------------------------------------------
double vtkLiveBehaviorSource::GetBehaviorTime(double t)
{
  // The window's clock goes back when restarted ('r'); the behaviour goes on from where it
  // was (LiveBehavior samples only forward).
  const double last = this->Internals->Live->GetLastSampleTime();
  if (t + this->Internals->Offset < last)
  {
    this->Internals->Offset = last - t;
  }
  return t + this->Internals->Offset;
}

//------------------------------------------------------------------------------
int vtkLiveBehaviorSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  const double range[2] = { 0.0, morphnode::LiveBehavior::MaxLiveTime };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

//------------------------------------------------------------------------------
int vtkLiveBehaviorSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  output->Initialize();
  const double requested = vtkMorphTrackSource::RequestedTime(outputVector);
  if (!std::isfinite(requested))
  {
    vtkErrorMacro(<< "cannot sample the live behaviour at t = " << requested);
    return 0;
  }
  morphnode::LiveBehavior& live = *this->Internals->Live;
  std::vector<double>& row = this->Internals->Row;
  row.assign(live.GetNumberOfChannels(), 0.0);
  const double t = this->GetBehaviorTime(requested);
  if (!Guarded(this, "RequestData", [&]() { live.Sample(t, row.data()); }))
  {
    return 0;
  }
  const auto& names = live.GetChannelNames();
  for (size_t c = 0; c < names.size(); ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(names[c].c_str());
    column->SetNumberOfValues(1);
    column->SetValue(0, row[c]);
    output->AddColumn(column);
  }
  output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), requested);
  return 1;
}

//------------------------------------------------------------------------------
void vtkLiveBehaviorSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const vtkInternals& in = *this->Internals;
  os << indent << "Seed: " << in.Seed << "\n";
  os << indent << "Voice: " << in.Speech.Voice << "\n";
  os << indent << "SpeechRate: " << in.Speech.Rate << "\n";
  os << indent << "VisemeSet: " << morphnode::VisemeSetName(in.Speech.Visemes) << "\n";
  os << indent << "VisemeTable: "
     << (in.Speech.VisemeTablePath.empty() ? "(built-in)" : in.Speech.VisemeTablePath) << "\n";
  os << indent << "NumberOfChannels: " << in.Live->GetNumberOfChannels() << "\n";
  os << indent << "LastSampleTime: " << in.Live->GetLastSampleTime() << "\n";
  os << indent << "TimeOffset: " << in.Offset << "\n";
}
