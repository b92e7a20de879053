// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file FrameRecorder.h
/// @brief Records the frames a render window shows: as PNG files FOLDER/frame_00000.png
/// ..., and/or as a video: FILE.ogv (Theora, silent) and the sound as FILE.wav, muxed by
/// ffmpeg into FILE.mp4 (or FILE.mkv when FILE ends so) when ffmpeg is on PATH.

#include "vtkNew.h"

#include <functional>
#include <iostream>
#include <string>

class vtkBehaviorTimeSource;
class vtkOggTheoraWriter;
class vtkPNGWriter;
class vtkRenderWindow;
class vtkWindowToImageFilter;

namespace morphnode
{
namespace appkit
{
class FrameRecorder
{
public:
  /// Frames of `window`, `fps` frames a second (the video's rate).
  FrameRecorder(vtkRenderWindow* window, double fps);
  ~FrameRecorder();

  /// PNG frames into `folder` (created). Throws std::runtime_error.
  void SetFramesFolder(const std::string& folder);
  /// A video: FILE.ogv and FILE.wav, FILE.mp4 or FILE.mkv; the extension of `file` chooses
  /// the muxed container (.mkv, else .mp4). Creates the folder. Throws std::runtime_error.
  void SetVideo(const std::string& file);

  /// Records the frame just rendered as frame number `frame`. Throws std::runtime_error.
  void Capture(int frame);

  /// Ends the video, writes the sound of `sound` beside it and muxes both with ffmpeg.
  /// Prints what it wrote to stdout. Throws std::runtime_error.
  void Finish(vtkBehaviorTimeSource* sound);
  /// Same, the sound written by `writeSound(wavFile)` (false: it could not), e.g. the
  /// sound of a live session.
  void Finish(const std::function<bool(const std::string&)>& writeSound);

  const std::string& GetFramesFolder() const { return this->Folder; }
  /// Where Finish says what it wrote (default stdout; stderr when stdout carries events).
  void SetLog(std::ostream& log) { this->Log = &log; }
  const std::string& GetVideoFile() const { return this->Ogv; }

private:
  FrameRecorder(const FrameRecorder&) = delete;
  void operator=(const FrameRecorder&) = delete;

  double Fps;
  std::ostream* Log = &std::cout;
  std::string Folder;
  std::string Ogv, Wav, Muxed;
  bool VideoStarted = false;
  int Frames = 0;
  vtkNew<vtkWindowToImageFilter> Grab;
  vtkNew<vtkPNGWriter> Png;
  vtkNew<vtkOggTheoraWriter> Video;
};
} // namespace appkit
} // namespace morphnode
