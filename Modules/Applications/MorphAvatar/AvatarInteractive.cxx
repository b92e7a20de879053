// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar's interactive mode: a window where time runs in real time; keys switch the
// optimizer (0-4 method, +/- threshold or error bound), pause, restart, hide the overlay.
#include "Avatar.h"
#include "StopSignal.h"

#include "vtkCallbackCommand.h"
#include "vtkInteractorStyleTrackballCamera.h"
#include "vtkObjectFactory.h"
#include "vtkRenderWindowInteractor.h"

#include <algorithm>
#include <iomanip>
#include <iostream>

namespace morphavatar
{
namespace
{
class AvatarStyle : public vtkInteractorStyleTrackballCamera
{
public:
  static AvatarStyle* New();
  vtkTypeMacro(AvatarStyle, vtkInteractorStyleTrackballCamera);
  Avatar* Scene = nullptr;

  void OnChar() override
  {
    // Our keys must not reach the default handling ('3' is stereo, 'r' resets the camera).
    const char key = this->Interactor->GetKeyCode();
    if (std::string("01234+-=r o").find(key) != std::string::npos && key != '\0')
    {
      return;
    }
    this->Superclass::OnChar();
  }

  void OnKeyPress() override
  {
    Avatar& a = *this->Scene;
    const std::string sym = this->Interactor->GetKeySym() ? this->Interactor->GetKeySym() : "";
    const char key = this->Interactor->GetKeyCode();
    const bool bounded = a.Method == morphnode::OptimizerPreset::ErrorBounded;
    if (key >= '0' && key <= '4')
    {
      a.Method = static_cast<morphnode::OptimizerPreset>(key - '0');
    }
    else if (key == '+' || key == '=' || sym == "plus" || sym == "KP_Add" || sym == "equal")
    {
      if (bounded)
        a.MaxError *= 1.25;
      else
        a.Threshold = std::min(1.0, a.Threshold + 0.025);
    }
    else if (key == '-' || sym == "minus" || sym == "KP_Subtract")
    {
      if (bounded)
        a.MaxError /= 1.25;
      else
        a.Threshold = std::max(0.0, a.Threshold - 0.025);
    }
    else if (key == ' ' || sym == "space")
    {
      a.SetClockPaused(!a.Paused);
    }
    else if (key == 'r')
    {
      a.SeekClock(0.0);
    }
    else if (key == 'o')
    {
      a.Overlay->SetVisibility(!a.Overlay->GetVisibility());
    }
    else
    {
      this->Superclass::OnKeyPress();
      return;
    }
    a.ApplyMethod();
  }
};
vtkStandardNewMacro(AvatarStyle);

void OnTimer(vtkObject* caller, unsigned long, void* clientData, void*)
{
  auto* a = static_cast<Avatar*>(clientData);
  auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
  const auto now = Clock::now();
  // The clock (AvatarClock.cxx): the sound's where it plays, so the picture follows it.
  double t = a->ClockNow();
  if (!a->Paused && t > a->Duration && !a->LiveFrame) // loop (live: time runs on)
  {
    a->SeekClock(0.0);
    a->Morph->ResetHysteresis();
    t = 0.0;
  }
  if ((a->LiveFrame && !a->LiveFrame(t, false)) ||
    morphnode::appkit::StopRequested()) // quit, SIGTERM/SIGINT
  {
    interactor->TerminateApp();
    return;
  }
  a->Update(t);
  ++a->FramesSinceMeasure;
  const double since = std::chrono::duration<double>(now - a->MeasureStart).count();
  if (since >= 0.5)
  {
    a->MeasuredFps = a->FramesSinceMeasure / since;
    a->FramesSinceMeasure = 0;
    a->MeasureStart = now;
  }
  a->Overlay->SetInput(a->OverlayText(false, 0, 0).c_str());
  interactor->Render();
  ++a->FramesRendered;
  if (a->LiveFrame)
  {
    a->LiveFrame(t, true);
  }
  if (a->Opt.ExitAfter >= 0.0 &&
    std::chrono::duration<double>(now - a->Launched).count() >= a->Opt.ExitAfter)
  {
    const double seconds = std::chrono::duration<double>(Clock::now() - a->Launched).count();
    // (with commands on stdin, stdout carries only their events)
    std::ostream& out = a->Opt.CommandsStdin ? std::cerr : std::cout;
    out << "rendered " << a->FramesRendered << " frames in " << std::fixed << std::setprecision(2)
        << seconds << " s (" << std::setprecision(1) << a->FramesRendered / seconds << " fps)\n"
        << a->Overlay->GetInput() << "\n";
    interactor->TerminateApp();
  }
}
} // namespace

int RunInteractive(Avatar& a)
{
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(a.Window);
  vtkNew<AvatarStyle> style;
  style->Scene = &a;
  interactor->SetInteractorStyle(style);
  interactor->Initialize();
  vtkNew<vtkCallbackCommand> timer;
  timer->SetCallback(OnTimer);
  timer->SetClientData(&a);
  interactor->AddObserver(vtkCommand::TimerEvent, timer);
  interactor->CreateRepeatingTimer(5);
  a.StartClock(true); // live runs started it already, with nothing scheduled yet
  for (char key : a.Opt.Keys)
  {
    const char sym[2] = { key, '\0' };
    interactor->SetKeyEventInformation(0, 0, key, 1,
      key == '+'     ? "plus"
        : key == '-' ? "minus"
                     : sym);
    interactor->InvokeEvent(vtkCommand::KeyPressEvent);
    interactor->InvokeEvent(vtkCommand::CharEvent);
  }
  a.MeasureStart = Clock::now();
  a.Window->Render();
  interactor->Start();
  return 0;
}
} // namespace morphavatar
