// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkLiveBehaviorSource
 * @brief   a temporal source of live behaviour weights: endless idle behaviour with
 *          commands (say, gesture, mood, look, stop) merged in as they come
 *
 * A thin adapter over morphnode::LiveBehavior (behavior/LiveBehavior.h, docs/dialog.md):
 * where vtkBehaviorTimeSource plays a finite, prepared behaviour, this source runs for ever
 * and takes commands while it runs, so a live avatar is the same pipeline with another
 * weights source (vtkMorphAvatarPipeline::SetWeightsConnection):
 *
 * @code
 * vtkNew<vtkLiveBehaviorSource> live;
 * live->CopySettings(behavior);          // seed, parameters, voice, viseme set
 * pipeline->SetWeightsConnection(live->GetOutputPort());
 * live->Say("Hello there.", clockNow);   // or commands on GetLiveBehavior() from C++
 * pipeline->UpdateTimeStep(clockNow);    // the face at the clock's time
 * @endcode
 *
 * Output (no inputs): port 0, a one-row vtkTable with one vtkDoubleArray column per
 * channel (GetChannelName: the base channels, then the viseme channels), the behaviour at
 * the requested UPDATE_TIME_STEP (0 when none is requested). The live behaviour's time only
 * moves forward: a request before the last sampled time (a clock restarted) goes on from
 * where the behaviour was (GetBehaviorTime); the table's DATA_TIME_STEP is the requested
 * time. The information advertises TIME_RANGE = [0, morphnode::LiveBehavior::MaxLiveTime]
 * (the executive re-executes a source for another time only when it has a time range) and
 * no TIME_STEPS: the behaviour has no frames.
 * There is no whole-track port (the track is not known in advance).
 *
 * Commands take `now`, the time they take effect on the caller's clock (the same clock as
 * the requested times); each modifies the source. C++ code that drives the core directly
 * (GetLiveBehavior: speech with its own synthesizer, timings, TakeAudio) calls Modified()
 * after its commands. The sound of synthesized speech is the caller's to play
 * (GetLiveBehavior().TakeAudio()); this source only moves the face.
 *
 * Bad values, unknown names and synthesis failures are reported with vtkErrorMacro and the
 * command returns false. Settings apply when the behaviour is made: at the first command
 * or update after CopySettings, SetSeed or SetVisemeSetFromString (which start it anew).
 *
 * @sa vtkMorphTrackSource vtkBehaviorTimeSource vtkMorphAvatarPipeline morphnode::LiveBehavior
 */

#ifndef vtkLiveBehaviorSource_h
#define vtkLiveBehaviorSource_h

#include "vtkMorphNodeBehaviorModule.h" // For export macro
#include "vtkMorphTrackSource.h"

#include <memory> // For std::unique_ptr

class vtkBehaviorTimeSource;
#ifndef __VTK_WRAP__
namespace morphnode
{
class LiveBehavior;
}
#endif

class VTKMORPHNODEBEHAVIOR_EXPORT vtkLiveBehaviorSource : public vtkMorphTrackSource
{
public:
  static vtkLiveBehaviorSource* New();
  vtkTypeMacro(vtkLiveBehaviorSource, vtkMorphTrackSource);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Takes a prepared behaviour's settings: its seed, behaviour parameters and speech
   * settings (voice, rate, viseme set or table), and starts the live behaviour anew with
   * them. False with an error when they make no live behaviour.
   */
  bool CopySettings(vtkBehaviorTimeSource* settings);

  ///@{
  /**
   * The random seed of the idle behaviour (default 1), and the viseme set of the speech
   * (paper6 by default, oculus15, german16). Each starts the live behaviour anew.
   */
  void SetSeed(vtkTypeUInt64 seed);
  vtkTypeUInt64 GetSeed();
  bool SetVisemeSetFromString(const char* name);
  const char* GetVisemeSetAsString();
  ///@}

  ///@{
  /// The output's channels: the base channels, then the viseme set's channels.
  int GetNumberOfChannels();
  const char* GetChannelName(int index);
  ///@}

  ///@{
  /**
   * Commands at `now` (seconds on the caller's clock), merged into what is scheduled;
   * behavior/LiveBehavior.h has their rules. False with an error for an unknown name, a
   * value out of range or a synthesis failure.
   */
  bool Say(const char* text, double now);
  bool Gesture(const char* name, double now, double intensity = 1.0, double duration = 0.0);
  bool SetMood(const char* name, double intensity, double now);
  bool LookAt(double yaw, double pitch, double now, double duration = 0.0);
  void StopSpeaking(double now);
  ///@}

  /**
   * The behaviour's time for a requested time t: t shifted so that it never goes back
   * before the last sampled time (a clock restarted goes on from there). Commands for the
   * frame at t are given at this time.
   */
  double GetBehaviorTime(double t);

#ifndef __VTK_WRAP__
  /// The core behaviour, for C++ code that commands it directly (call Modified() after its
  /// commands) and takes its sound (TakeAudio) and errors. The reference holds until the
  /// settings change (CopySettings, SetSeed, SetVisemeSetFromString start a new one).
  morphnode::LiveBehavior& GetLiveBehavior();
#endif

protected:
  vtkLiveBehaviorSource();
  ~vtkLiveBehaviorSource() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkLiveBehaviorSource(const vtkLiveBehaviorSource&) = delete;
  void operator=(const vtkLiveBehaviorSource&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
