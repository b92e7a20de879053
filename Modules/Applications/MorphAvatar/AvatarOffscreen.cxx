// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar's offscreen mode: every frame at the frame rate to PNG frames, a video with
// sound and/or a ParaView time series; or one frame to a PNG and/or compared with a
// baseline (the render regression test).
#include "Avatar.h"
#include "StopSignal.h"

#include "FrameRecorder.h"
#include "ImageOutput.h"
#include "Progress.h"
#include "TimeSeriesWriter.h"

#include "vtkImageDifference.h"
#include "vtkImageExtractComponents.h"
#include "vtkPNGReader.h"
#include "vtkPNGWriter.h"
#include "vtkTable.h"
#include "vtkWindowToImageFilter.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

namespace morphavatar
{
namespace appkit = morphnode::appkit;

namespace
{
/// One frame: --at (or the last frame) to --png and/or compared with --compare.
int RunOneFrame(Avatar& a)
{
  const Options& o = a.Opt;
  const double t = o.At >= 0.0 ? o.At : a.Duration;
  const int frame = static_cast<int>(std::floor(t * a.Fps + 1e-9));
  if (!a.Update(t))
  {
    std::cerr << "MorphAvatar: the face could not be morphed (see the errors above)\n";
    return 1;
  }
  a.Overlay->SetInput(a.OverlayText(true, frame, a.NumberOfFrames()).c_str());
  a.Window->Render();
  if (!o.Png.empty())
  {
    appkit::WritePng(a.Window, o.Png);
    std::cout << "wrote " << o.Png << " (t = " << t << " s)\n";
  }
  if (!o.Compare.empty())
  {
    namespace fs = std::filesystem;
    const std::string outDir = o.Png.empty() ? fs::current_path().string()
                                             : fs::absolute(fs::path(o.Png)).parent_path().string();
    // VTK's legacy image metric (3 x 3 averaging, shifts of two pixels, the error summed
    // over the pixels that still differ) with a per-channel tolerance of 24 levels:
    // vtkTesting's fixed 105 does not see an open mouth on glTF materials drawn
    // gamma-correct (docs/materials.md).
    const std::string baseline = fs::absolute(fs::path(o.Compare)).lexically_normal().string();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(a.Window);
    grab->SetInputBufferTypeToRGB();
    grab->ReadFrontBufferOff();
    grab->Update();
    vtkNew<vtkPNGReader> reader;
    double error = -1.0;
    if (reader->CanReadFile(baseline.c_str()))
    {
      reader->SetFileName(baseline.c_str());
      vtkNew<vtkImageExtractComponents> rgb;
      rgb->SetInputConnection(reader->GetOutputPort());
      rgb->SetComponents(0, 1, 2);
      vtkNew<vtkImageDifference> difference;
      difference->SetInputConnection(grab->GetOutputPort());
      difference->SetImageConnection(rgb->GetOutputPort());
      difference->SetThreshold(24);
      difference->AllowShiftOn();
      difference->AveragingOn();
      difference->Update();
      error = difference->GetThresholdedError();
    }
    std::cout << "image error " << error << " (threshold " << o.CompareThreshold << ")\n";
    if (error < 0 || error > o.CompareThreshold)
    {
      vtkNew<vtkPNGWriter> writer;
      writer->SetInputConnection(grab->GetOutputPort());
      writer->SetFileName(
        (outDir + "/" + fs::path(baseline).stem().string() + "-test.png").c_str());
      writer->Write();
      std::cerr << "MorphAvatar: the frame differs from " << o.Compare << " (images in " << outDir
                << ")\n";
      return 1;
    }
    std::cout << "the frame matches " << o.Compare << "\n";
  }
  return 0;
}

/// Every frame at the frame rate.
int RunAllFrames(Avatar& a)
{
  const Options& o = a.Opt;
  const int frames = a.NumberOfFrames();
  appkit::FrameRecorder recorder(a.Window, a.Fps);
  if (!o.FramesDir.empty())
  {
    recorder.SetFramesFolder(o.FramesDir);
  }
  if (!o.Video.empty())
  {
    recorder.SetVideo(o.Video);
  }
  std::unique_ptr<appkit::TimeSeriesWriter> series;
  if (!o.Pvd.empty())
  {
    series = std::make_unique<appkit::TimeSeriesWriter>(o.Pvd);
  }
  appkit::ProgressBar progress(frames, "frames", !o.Quiet);
  for (int f = 0; f < frames; ++f)
  {
    if (appkit::StopRequested())
    {
      // SIGTERM/SIGINT: what was recorded so far is completed below, as at the last frame.
      std::cerr << "\nMorphAvatar: stopped by signal " << appkit::StopSignalNumber() << " after "
                << f << " frames\n";
      break;
    }
    const double t = f / a.Fps;
    if (!a.Update(t))
    {
      std::cerr << "\nMorphAvatar: the face could not be morphed at t = " << t
                << " (see the errors above)\n";
      return 1;
    }
    if (series)
    {
      series->Write(a.GetHead(), vtkTable::SafeDownCast(a.Behavior->GetOutputDataObject(0)), t);
    }
    a.Overlay->SetInput(a.OverlayText(true, f, frames).c_str());
    a.Window->Render();
    if (!o.FramesDir.empty() || !o.Video.empty())
    {
      recorder.Capture(f);
    }
    progress.Show(f + 1);
  }
  if (series)
  {
    series->Close();
  }
  recorder.Finish(a.Behavior);
  return 0;
}
} // namespace

int RunOffscreen(Avatar& a)
{
  const Options& o = a.Opt;
  a.Window->OffScreenRenderingOn();
  try
  {
    const bool oneFrame = o.At >= 0.0 || (o.FramesDir.empty() && o.Video.empty() && o.Pvd.empty());
    return oneFrame ? RunOneFrame(a) : RunAllFrames(a);
  }
  catch (const std::exception& e)
  {
    std::cerr << "\nMorphAvatar: " << e.what() << "\n";
    return 1;
  }
}
} // namespace morphavatar
