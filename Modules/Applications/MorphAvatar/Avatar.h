// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Avatar.h
/// @brief MorphAvatar's scene: the pipeline (vtkMorphAvatarPipeline, the one place it is
/// assembled)
///
///   vtkMorphTargetReader (the whole scene: a vtkPartitionedDataSetCollection of parts, or
///   one vtkPolyData for an OBJ set) -> vtkMorphNodeFilter (weights on port 1 from
///   vtkBehaviorTimeSource [-> vtkMorphRigFilter], live from vtkLiveBehaviorSource) ->
///   vtkEyeGazeFilter (the behaviour's EyeYaw/EyePitch turn the eye parts) ->
///   vtkMorphSkinFilter (a skinned avatar: the behaviour's HeadYaw/Pitch/Roll turn its head
///   and neck joints, EyeYaw/EyePitch its eye joints; arms relaxed) -> one actor per part
///   (AppKit/HeadActors); for a head without head joints HeadYaw/Pitch/Roll -> the
///   pipeline's head pose transform shared by every part's actor
///
/// the actors (head parts, overlay, caption) and the window, and the two ways to run it.

#include "AvatarOptions.h"
#include "HeadActors.h"
#include "playback/AudioPlayer.h"

#include "vtkBehaviorTimeSource.h"
#include "vtkEyeGazeFilter.h"
#include "vtkLiveLinkFaceReader.h"
#include "vtkMorphAvatarPipeline.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphRigFilter.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTextActor.h"
#include "vtkTransform.h"

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

namespace morphavatar
{
using Clock = std::chrono::steady_clock;

struct Avatar
{
  Options Opt;
  vtkNew<vtkBehaviorTimeSource> Behavior;
  vtkNew<vtkLiveLinkFaceReader> Capture; // --capture
  /// Reader -> [rig] -> morph -> gaze -> skin and the head pose, on the weights of the
  /// behaviour, the face's animation, the take or (live) a vtkLiveBehaviorSource.
  vtkNew<vtkMorphAvatarPipeline> Pipeline;
  // The pipeline's filters, for their settings (the connections are the pipeline's).
  vtkMorphTargetReader* const Reader = Pipeline->GetReader();
  vtkMorphRigFilter* const Rig = Pipeline->GetRig();
  vtkMorphNodeFilter* const Morph = Pipeline->GetMorph();
  vtkEyeGazeFilter* const Gaze = Pipeline->GetGaze();
  vtkMorphSkinFilter* const Skin = Pipeline->GetSkin();
  /// A rig chosen from the face's names (AvatarNaming.h), removed at exit.
  struct TempFile
  {
    std::string Path;
    ~TempFile();
  } ChosenRig;
  /// The box the camera frames (--frame: the head from its joints, the bust, the body).
  double ViewBounds[6] = { 0, 1, 0, 1, 0, 1 };
  morphnode::appkit::HeadActors Head; // one actor per part
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkTextActor> Overlay;
  vtkNew<vtkTextActor> Caption;
  std::string FaceFile;
  double Bounds[6] = { 0, 1, 0, 1, 0, 1 };
  double Diagonal = 1.0;
  double Duration = 5.0;
  double Fps = 30.0;
  morphnode::OptimizerPreset Method = morphnode::OptimizerPreset::Adjusted;
  double Threshold = 0.1;
  double MaxError = 0.0;
  double Time = 0.0;

  // Interactive clock
  bool Paused = false;
  Clock::time_point Start;
  double StartTime = 0.0;
  double MeasuredFps = 0.0;
  int FramesSinceMeasure = 0;
  int FramesRendered = 0;
  Clock::time_point Launched;
  Clock::time_point MeasureStart;
  /// Live commands (AvatarLive.cxx): when set, the interactive loop lets time run on (no
  /// loop) and calls it before each frame at t (rendered false; false closes the window)
  /// and after it (rendered true).
  std::function<bool(double t, bool rendered)> LiveFrame;
  /// The voice (playback/AudioPlayer): in the window and live, unless --mute or no device
  /// opens. With it, the clock is the sound's: the picture cannot drift from it.
  std::unique_ptr<morphnode::AudioPlayer> Player;
  bool ClockStarted = false;

  /// The behaviour from the options (script, sentence, seed, timing). False with a
  /// message on stderr when it cannot be made.
  bool SetUpBehavior();
  /// The face, the rig, the morph filter and the optimizer. False with a message.
  bool SetUpFace();
  /// The actors, the overlay, the caption and the window.
  void SetUpScene();
  /// --animation, --capture: checks the animation or the take and takes its length as the
  /// duration (unless --duration). False with a message.
  bool SetUpPerformance();

  /// The optimizer of Method, Threshold and MaxError (and the option's hysteresis) on the
  /// rig filter (deciding per rig shape) or, without a rig or with a frame budget, on the
  /// morph filter.
  void ApplyMethod();
  /// Whether the optimizer decides per rig shape (a rig and no frame budget).
  bool DecidesPerShape() const;
  /// The morphed head with its eyes turned (a composite of parts, or a vtkPolyData), a
  /// skinned avatar posed.
  vtkDataObject* GetHead() const;
  /// ViewBounds from --frame: the head found by its joints and the parts they move (a
  /// skinned avatar; then also the optimizer's error bound from the head's size), else the
  /// face's bounds.
  void FrameView();
  /// Brings the face to time t: weights, blend, head pose. False on error.
  bool Update(double t);
  /// The overlay: frame rate, method, threshold or bound, active targets, time.
  std::string OverlayText(bool offscreen, int frame, int frames) const;
  /// Number of frames from 0 to the duration at the frame rate.
  int NumberOfFrames() const;

  // The real-time clock of the window and of live runs (AvatarClock.cxx).
  /// Starts the clock at 0 (once) and opens the sound device unless --mute; the prepared
  /// behaviour's speech, if any, is scheduled from 0 (live runs schedule theirs as it comes).
  void StartClock(bool scheduleBehaviorSound);
  /// Seconds on the clock: the sample heard now, or steady time (paused: standing).
  double ClockNow() const;
  void SetClockPaused(bool paused);
  /// Moves the clock to t (restart, loop); the behaviour's speech is scheduled again from 0.
  void SeekClock(double t);
  /// Plays mono 16-bit samples from `start` on the clock (nothing without a player).
  void PlaySound(const std::vector<int16_t>& samples, int sampleRate, double start);
  /// Silences the sound scheduled from t on (stop speaking).
  void CutSound(double t);

  /// A live session's sound as played (--video with --listen): every segment scheduled,
  /// cut where speech was stopped. Recorded only while RecordSound is set.
  struct SoundSegment
  {
    std::vector<int16_t> Samples;
    int SampleRate = 22050;
    double Start = 0.0;
    double End = 0.0; ///< cut here (stop), else the segment's own end
  };
  bool RecordSound = false;
  std::vector<SoundSegment> SessionSound;
  /// Mixes SessionSound into one mono 16-bit WAV at 22050 Hz. False when it cannot write.
  bool WriteSessionSound(const std::string& wav) const;
};

/// A window where time runs in real time and keys switch the optimizer.
int RunInteractive(Avatar& avatar);
/// Every frame at the frame rate to PNG frames, a video and/or a time series; or one frame
/// to a PNG and/or compared with a baseline.
int RunOffscreen(Avatar& avatar);
} // namespace morphavatar
