// SPDX-License-Identifier: BSD-3-Clause
#include "Avatar.h"

#include "DataPaths.h"
#include "Framing.h"

#include "base/Text.h"
#include "budget/FrameBudgetController.h"

#include "audio/AudioFile.h"
#include "speech/Rhubarb.h"
#include "speech/Speech.h"

#include "vtkCamera.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace morphavatar
{
namespace appkit = morphnode::appkit;

Avatar::TempFile::~TempFile()
{
  if (!this->Path.empty())
  {
    std::error_code ec;
    std::filesystem::remove(this->Path, ec);
  }
}

bool Avatar::SetUpBehavior()
{
  const Options& o = this->Opt;
  vtkBehaviorTimeSource* behavior = this->Behavior;
  behavior->SetVoice(o.Voice.c_str());
  if (!behavior->SetVisemeSetFromString(o.Visemes.c_str()))
  {
    FailUsage("--visemes expects paper6, oculus15 or german16; got '" + o.Visemes + "'");
  }
  if (!o.Script.empty() && !behavior->LoadScript(o.Script.c_str()))
  {
    std::cerr << "MorphAvatar: cannot load the script " << o.Script << " (see above)\n";
    return false;
  }
  const double speechStart = o.Script.empty() ? 0.5 : -1.0;
  const bool performance = !o.Animation.empty() || !o.Capture.empty();
  if (performance && !o.Audio.empty())
  {
    // The performance's sound, from time 0 as the performance: the recording as it is,
    // the mouth at rest (the performance moves the face, not the behaviour's visemes).
    try
    {
      const morphnode::AudioBuffer sound = morphnode::MixToMono(morphnode::ReadAudioFile(o.Audio));
      morphnode::SpeechOptions speech;
      speech.Visemes = morphnode::ParseVisemeSet(behavior->GetVisemeSetAsString());
      morphnode::Utterance u = morphnode::UtteranceFromMouthCues(
        { morphnode::MouthCue{ 0.0, sound.GetDuration(), 'X' } }, speech);
      u.SampleRate = sound.SampleRate;
      u.Audio.resize(sound.Samples.size());
      for (size_t i = 0; i < sound.Samples.size(); ++i)
      {
        u.Audio[i] =
          static_cast<int16_t>(std::lround(32767.0 * std::clamp(sound.Samples[i], -1.0f, 1.0f)));
      }
      u.Duration = std::max(u.Duration, sound.GetDuration());
      if (!behavior->Speak(u, 0.0))
      {
        return false;
      }
    }
    catch (const std::exception& e)
    {
      std::cerr << "MorphAvatar: " << e.what() << "\n";
      return false;
    }
  }
  else if (!o.Audio.empty() || !o.Timings.empty())
  {
    if (!behavior->SetTimingFormat(o.TimingsFormat.c_str()))
    {
      return false;
    }
    std::string transcript = o.Text;
    if (!o.TextFile.empty())
    {
      try
      {
        transcript = morphnode::text::ReadFile(o.TextFile, "transcript");
      }
      catch (const std::exception& e)
      {
        std::cerr << "MorphAvatar: " << e.what() << "\n";
        return false;
      }
    }
    const bool spoken = o.Audio.empty() ? behavior->SpeakTimingFile(o.Timings.c_str(), speechStart)
      : !o.Timings.empty()
      ? behavior->SpeakAudioFileWithTimings(o.Audio.c_str(), o.Timings.c_str(), speechStart)
      : behavior->SpeakAudioFile(o.Audio.c_str(), transcript.c_str(), speechStart);
    if (!spoken)
    {
      std::cerr << "MorphAvatar: cannot speak "
                << (o.Audio.empty() ? "the timing file " + o.Timings : "the recording " + o.Audio)
                << " (see above)\n";
      return false;
    }
  }
  if (!o.Say.empty() && !behavior->Say(o.Say.c_str(), speechStart))
  {
    std::cerr << "MorphAvatar: cannot say '" << o.Say << "' with voice '" << o.Voice
              << "' (see above; `espeak-ng --voices` lists the voices)\n";
    return false;
  }
  if (o.SeedSet)
  {
    behavior->SetSeed(o.Seed);
  }
  if (o.Fps > 0.0)
  {
    behavior->SetFrameRate(o.Fps);
  }
  if (o.Duration >= 0.0)
  {
    behavior->SetDuration(o.Duration);
  }
  this->Fps = behavior->GetFrameRate();
  this->Duration = behavior->GetEffectiveDuration();
  return true;
}

bool Avatar::SetUpPerformance()
{
  const Options& o = this->Opt;
  double end = -1.0;
  if (!o.Animation.empty())
  {
    end = this->Reader->GetAnimationEndTime();
  }
  else if (!o.Capture.empty())
  {
    this->Capture->UpdateInformation();
    this->Capture->Update();
    vtkInformation* info = this->Capture->GetOutputInformation(0);
    if (this->Capture->GetOutput()->GetNumberOfColumns() == 0 ||
      !info->Has(vtkStreamingDemandDrivenPipeline::TIME_RANGE()))
    {
      std::cerr << "MorphAvatar: cannot play the take " << o.Capture << " (see above)\n";
      return false;
    }
    end = info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE())[1];
    if (!o.Quiet)
    {
      std::cout << this->Capture->GetMappingReport() << "\n";
    }
  }
  if (end >= 0.0 && o.Duration < 0.0)
  {
    // The performance's length (and its sound's), unless --duration says otherwise.
    for (int u = 0; u < this->Behavior->GetNumberOfUtterances(); ++u)
    {
      end = std::max(end, this->Behavior->GetUtteranceEnd(u));
    }
    this->Behavior->SetDuration(std::max(end, 1.0 / this->Fps));
    this->Duration = this->Behavior->GetEffectiveDuration();
  }
  return true;
}

bool Avatar::SetUpFace()
{
  const Options& o = this->Opt;
  this->FaceFile = o.Face.empty() ? appkit::DefaultFace() : o.Face;
  // The whole scene: every part (skin, mouth, teeth, tongue, eyes, ...) as a
  // vtkPartitionedDataSetCollection in world space (docs/scene.md); an OBJ set is one
  // vtkPolyData. The pipeline (vtkMorphAvatarPipeline) gives the same structure back.
  this->Pipeline->SetFileName(this->FaceFile.c_str());
  // For ParaView: colour by AnimatedRegion or Distance_<target>.
  this->Morph->SetGenerateDistanceArrays(!o.Pvd.empty());
  // The weights: the behaviour's (through the rig), or a recorded performance: the face
  // file's own glTF animation (the reader's port 1, weights by target name) or a Live Link
  // Face take (its ARKit shapes mapped onto the face's targets by name, its angles). The
  // rig's "eyes" section names the eye parts in every case.
  this->Pipeline->SetRigFileName(o.Rig.c_str());
  this->Pipeline->SetWeightsConnection(this->Behavior->GetOutputPort(0));
  if (!o.Animation.empty())
  {
    // The file's animations (names, else animation<i>), checked before the reader reads
    // the chosen one: a name or index it lacks is told with the ones it has.
    this->Reader->UpdateInformation();
    int index = -1;
    if (!morphnode::text::ParseNumber(o.Animation, index))
    {
      index = -1;
      for (int i = 0; i < this->Reader->GetNumberOfAnimations(); ++i)
      {
        index = o.Animation == this->Reader->GetAnimationNameByIndex(i) ? i : index;
      }
    }
    if (index < 0 || index >= this->Reader->GetNumberOfAnimations())
    {
      std::ostringstream names;
      for (int i = 0; i < this->Reader->GetNumberOfAnimations(); ++i)
      {
        names << (i ? ", " : "") << i << " '" << this->Reader->GetAnimationNameByIndex(i) << "'";
      }
      std::cerr << "MorphAvatar: " << this->FaceFile << ": no animation '" << o.Animation << "' ("
                << (names.str().empty() ? std::string("the file has none")
                                        : "it has " + names.str())
                << ")\n";
      return false;
    }
    this->Reader->SetAnimationIndex(index);
    // (Its weights carry no gaze or head angles: the eyes stay as the file has them, a
    // skinned avatar takes the behaviour's idle pose.)
    this->Pipeline->SetUseFaceAnimation(true);
  }
  else if (!o.Capture.empty())
  {
    this->Capture->SetFileName(o.Capture.c_str());
    this->Capture->SetFaceConnection(this->Reader->GetOutputPort());
    this->Pipeline->SetWeightsConnection(this->Capture->GetOutputPort(0));
    this->Pipeline->SetRigMapsWeights(false); // the take names the face's targets
  }
  // A skinned avatar: its bones follow the head pose and gaze (docs/avatars.md).
  this->Skin->SetTurnEyes(o.Gaze != "targets");
  this->Skin->SetRelaxArms(o.Pose == "relaxed");
  // Drawn skinned in the vertex shader: the skin filter poses only (the points stay), unless
  // asked otherwise or the points are written (--pvd; --gltf writes its own skin).
  this->Skin->SetSkinPoints(o.CpuSkin || !o.Pvd.empty());
  this->Head.SetSkinOnGpu(!this->Skin->GetSkinPoints());
  this->Reader->Update();
  if (!appkit::HeadBounds(this->Reader->GetOutputDataObject(0), this->Bounds))
  {
    std::cerr << "MorphAvatar: cannot read a face from " << this->FaceFile << " (see above)\n";
    return false;
  }
  if (!this->SetUpPerformance())
  {
    return false;
  }
  const double* b = this->Bounds;
  this->Diagonal = std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  if (!(this->Diagonal > 0.0))
  {
    this->Diagonal = 1.0;
  }
  this->Method = o.Method;
  this->Threshold = o.Threshold;
  this->MaxError = o.MaxError >= 0.0 ? o.MaxError : 0.005 * this->Diagonal;
  this->ApplyMethod();
  if (!this->Update(0.0))
  {
    std::cerr << "MorphAvatar: the face could not be morphed (see the errors above)\n";
    return false;
  }
  this->FrameView();
  if (!o.Quiet && this->Skin->GetNumberOfSkinnedParts() > 0 && (o.Gltf.empty() || o.Offscreen))
  {
    // Where the skin is computed (docs/avatars.md, "Skinned on the GPU"); not said for
    // --gltf alone, which draws nothing. With commands on stdin, stdout carries only their
    // events.
    std::ostream& log = o.CommandsStdin ? std::cerr : std::cout;
    log << "MorphAvatar: skin: " << this->Skin->GetNumberOfSkinnedParts() << " parts, ";
    if (this->Skin->GetSkinPoints())
    {
      log << "re-skinned on the CPU" << (o.CpuSkin ? "" : " (--pvd writes posed points)");
    }
    else
    {
      log << this->Skin->GetNumberOfPosedOnlyParts()
          << " skinned in the vertex shader (--cpu-skin re-skins on the CPU)";
      for (int i = 0; i < this->Skin->GetNumberOfCPUSkinnedParts(); ++i)
      {
        log << (i ? ", " : "; on the CPU: ") << this->Skin->GetCPUSkinnedPart(i);
      }
    }
    log << "\n";
  }
  if (o.Rig.empty() && o.Animation.empty() && o.Capture.empty())
  {
    // Without a rig the channels must name the face's targets.
    int matched = 0;
    for (int c = 0; c < this->Behavior->GetNumberOfChannels(); ++c)
    {
      matched += this->Morph->GetTargetIndex(this->Behavior->GetChannelName(c)) >= 0 ? 1 : 0;
    }
    if (matched == 0)
    {
      std::cerr << "MorphAvatar: no behaviour channel names a target of " << this->FaceFile
                << "; give a rig with --rig (e.g. Data/rigs/arkit.json)\n";
      return false;
    }
  }
  return true;
}

void Avatar::SetUpScene()
{
  const Options& o = this->Opt;
  // Every part in its own colour; the head pose moves them all (one transform).
  this->Head.Build(this->GetHead(), this->Renderer, this->Pipeline->GetHeadPose());

  vtkTextProperty* text = this->Overlay->GetTextProperty();
  text->SetFontFamilyToCourier();
  text->SetFontSize(std::max(10, o.Height / 40));
  text->SetColor(0.95, 0.95, 0.85);
  text->SetBackgroundColor(0.0, 0.0, 0.0);
  text->SetBackgroundOpacity(0.45);
  text->SetVerticalJustificationToTop();
  this->Overlay->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->Overlay->SetPosition(0.012, 0.988);
  this->Overlay->SetVisibility(o.Overlay);
  this->Renderer->AddActor2D(this->Overlay);

  // The sentence (or the script's name) at the bottom, like the paper's sentence choice.
  std::string caption =
    !o.Script.empty() ? std::filesystem::path(o.Script).filename().string() : "";
  if (!o.Audio.empty() || !o.Timings.empty())
  {
    const std::string recording =
      std::filesystem::path(o.Audio.empty() ? o.Timings : o.Audio).filename().string();
    caption += (caption.empty() ? "" : " + ") +
      (o.Text.empty() ? recording : recording + ": \"" + o.Text + "\"");
  }
  if (!o.Say.empty())
  {
    caption += (caption.empty() ? "\"" : " + \"") + o.Say + "\"";
  }
  if (!o.Capture.empty())
  {
    caption = std::filesystem::path(o.Capture).filename().string();
  }
  if (!o.Animation.empty())
  {
    caption = std::string("animation '") +
      this->Reader->GetAnimationNameByIndex(this->Reader->GetChosenAnimation()) + "'";
  }
  this->Caption->SetInput(caption.c_str());
  vtkTextProperty* captionText = this->Caption->GetTextProperty();
  captionText->SetFontSize(std::max(10, o.Height / 36));
  captionText->SetColor(1.0, 1.0, 1.0);
  captionText->SetJustificationToCentered();
  captionText->SetItalic(true);
  this->Caption->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  this->Caption->SetPosition(0.5, 0.02);
  this->Caption->SetVisibility(o.Overlay);
  this->Renderer->AddActor2D(this->Caption);

  this->Window->SetSize(o.Width, o.Height);
  this->Window->SetMultiSamples(0);
  this->Window->AddRenderer(this->Renderer);
  this->Window->SetWindowName("MorphAvatar");
  appkit::HeadActors::SetUpView(this->Renderer, this->ViewBounds);
}

bool Avatar::DecidesPerShape() const
{
  // With a rig the optimizer decides per rig shape (vtkMorphRigFilter, rig/RigOptimizer.h):
  // a viseme's targets are kept or pruned together, so closures and roundings survive every
  // method. The frame budget steers the morph filter's own threshold, per target.
  return !this->Opt.Rig.empty() && this->Opt.FrameBudget <= 0.0;
}

void Avatar::ApplyMethod()
{
  // The preset (morph/OptimizerPresets.h) reads the threshold and the error bound.
  const bool perShape = this->DecidesPerShape();
  this->Rig->SetThreshold(this->Threshold);
  this->Rig->SetMaxVertexError(this->MaxError);
  this->Rig->SetHysteresis(this->Opt.Hysteresis);
  this->Rig->SetOptimizerPreset(perShape ? static_cast<int>(this->Method) : 0);
  this->Rig->ResetHysteresis();
  this->Morph->SetThreshold(this->Threshold);
  this->Morph->SetMaxVertexError(this->MaxError);
  this->Morph->SetHysteresis(this->Opt.Hysteresis);
  this->Morph->SetOptimizerPreset(
    perShape ? vtkMorphNodeFilter::OPTIMIZER_NONE : static_cast<int>(this->Method));
  this->Morph->ResetHysteresis();
}

bool Avatar::Update(double t)
{
  this->Time = t;
  if (this->Opt.Lod || !this->Opt.Profile.empty())
  {
    // The target level of detail: how many pixels a model unit spans at the head.
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    const double* b = this->Bounds;
    const double center[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
    const double distance =
      std::sqrt(vtkMath::Distance2BetweenPoints(camera->GetPosition(), center));
    const int height =
      this->Window->GetSize()[1] > 0 ? this->Window->GetSize()[1] : this->Opt.Height;
    this->Morph->SetPixelsPerUnit(distance > 0.0 && !camera->GetParallelProjection()
        ? morphnode::ScreenPixelsPerUnit(height, camera->GetViewAngle(), distance)
        : 0.0);
  }
  if (!this->Pipeline->UpdateTimeStep(t)) // the head and its pose
  {
    return false;
  }
  double bounds[6];
  if (!appkit::HeadBounds(this->GetHead(), bounds))
  {
    return false;
  }
  if (this->Head.GetNumberOfParts() > 0 && !this->Head.Update(this->GetHead()))
  {
    std::cerr << "MorphAvatar: the head's parts changed while it ran\n";
    return false;
  }
  return true;
}

void Avatar::FrameView()
{
  std::copy(this->Bounds, this->Bounds + 6, this->ViewBounds);
  double head[6];
  if (!this->Skin->GetHeadBounds(head))
  {
    return; // a head of its own: the portrait of its bounds
  }
  // The optimizer's error bound in face units, not the whole body's.
  const double h = head[3] - head[2];
  if (this->Opt.MaxError < 0.0)
  {
    const double diagonal = std::sqrt((head[1] - head[0]) * (head[1] - head[0]) + h * h +
      (head[5] - head[4]) * (head[5] - head[4]));
    this->MaxError = 0.005 * diagonal;
    this->ApplyMethod();
  }
  appkit::FramingBox(head, this->Bounds, this->Opt.Framing, this->ViewBounds);
}

vtkDataObject* Avatar::GetHead() const
{
  return this->Pipeline->GetOutputDataObject();
}

std::string Avatar::OverlayText(bool offscreen, int frame, int frames) const
{
  using morphnode::OptimizerPreset;
  std::ostringstream os;
  os << std::fixed;
  if (offscreen)
  {
    os << std::setprecision(1) << this->Fps << " fps   frame " << frame << " / " << frames;
  }
  else
  {
    os << std::setprecision(1) << this->MeasuredFps << " fps"
       << (this->Paused ? "   (paused)" : "");
  }
  os << "\nmethod " << static_cast<int>(this->Method) << ": "
     << morphnode::OptimizerPresetLabel(this->Method) << "\n";
  switch (this->Method)
  {
    case OptimizerPreset::FixedMaximum:
    case OptimizerPreset::FixedRemaining:
    case OptimizerPreset::Adjusted:
      if (this->Morph->GetFrameBudget() > 0.0 && this->Morph->GetFrameBudgetThreshold() >= 0.0)
      {
        // --frame-budget: the threshold the controller chose for this frame.
        os << "threshold " << std::setprecision(3) << this->Morph->GetFrameBudgetThreshold()
           << " (frame budget " << this->Morph->GetFrameBudget() << " ms)\n";
      }
      else
      {
        os << "threshold " << std::setprecision(3) << this->Threshold << "\n";
      }
      break;
    case OptimizerPreset::ErrorBounded:
      os << "max vertex error " << std::setprecision(2) << 100.0 * this->MaxError / this->Diagonal
         << " % of the face\n";
      break;
    case OptimizerPreset::None:
      os << "threshold -\n";
      break;
  }
  const int targets = std::max(0, this->Morph->GetNumberOfTargets() - 1);
  const double bound =
    this->DecidesPerShape() ? this->Rig->GetLastErrorBound() : this->Morph->GetErrorBound();
  // (Short enough for a 640-pixel frame: a longer note ran past its right edge.)
  os << "active targets " << this->Morph->GetActiveTargetCount() << " / " << targets
     << (this->DecidesPerShape() ? " (per rig shape)" : "") << "   error bound "
     << std::setprecision(2) << 100.0 * bound / this->Diagonal << " %\n";
  if (this->Morph->GetPixelsPerUnit() > 0.0)
  {
    // The level of detail drawn: the level of the parts the actors took (field data
    // LevelOfDetail of the mesh levels; level 0 without them), targets by the screen.
    int level = 0;
    for (vtkPolyData* part : appkit::HeadParts(this->GetHead()))
    {
      if (vtkDataArray* lod = part->GetFieldData()->GetArray("LevelOfDetail"))
      {
        level = std::max(level, static_cast<int>(lod->GetComponent(0, 0)));
      }
    }
    os << "LOD " << (this->Opt.Profile.empty() ? "" : this->Opt.Profile + " ") << "level " << level
       << "   targets " << this->Morph->GetActiveTargetCount() << "   points "
       << this->GetHead()->GetNumberOfElements(vtkDataObject::POINT) << "   face "
       << std::setprecision(0) << this->Morph->GetPixelsPerUnit() * this->Diagonal << " px\n";
  }
  os << "t = " << std::setprecision(2) << this->Time << " s / " << this->Duration << " s";
  if (!offscreen)
  {
    os << "\nkeys: 0-4 method  +/- threshold  space pause  r restart  q quit";
  }
  return os.str();
}

int Avatar::NumberOfFrames() const
{
  return static_cast<int>(std::floor(this->Duration * this->Fps + 1e-9)) + 1;
}
} // namespace morphavatar
