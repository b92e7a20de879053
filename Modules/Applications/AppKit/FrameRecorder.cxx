// SPDX-License-Identifier: BSD-3-Clause
#include "FrameRecorder.h"

#include "base/File.h"
#include "base/Text.h"

#include "ImageOutput.h"

#include "vtkBehaviorTimeSource.h"
#include "vtkOggTheoraWriter.h"
#include "vtkPNGWriter.h"
#include "vtkRenderWindow.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>

namespace morphnode
{
namespace appkit
{
namespace
{
bool HasProgram(const std::string& name)
{
  const std::string command = "command -v " + name + " >/dev/null 2>&1";
  return std::system(command.c_str()) == 0;
}

/// Quoted for a POSIX shell.
std::string ShellQuote(const std::string& s)
{
  std::string q = "'";
  for (char c : s)
  {
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return q + "'";
}
} // namespace

FrameRecorder::FrameRecorder(vtkRenderWindow* window, double fps)
  : Fps(fps)
{
  this->Grab->SetInput(window);
  this->Grab->ReadFrontBufferOff();
  this->Grab->SetInputBufferTypeToRGB();
  this->Png->SetInputConnection(this->Grab->GetOutputPort());
}

FrameRecorder::~FrameRecorder() = default;

void FrameRecorder::SetFramesFolder(const std::string& folder)
{
  MakeFolder(folder);
  this->Folder = folder;
}

void FrameRecorder::SetVideo(const std::string& file)
{
  const std::filesystem::path path(file);
  MakeFolder(path.parent_path().string());
  const std::string ext = path.extension().string();
  const std::string stem = file.substr(0, file.size() - ext.size());
  this->Ogv = stem + ".ogv";
  this->Wav = stem + ".wav";
  this->Muxed = stem + (text::ToLower(ext) == ".mkv" ? ".mkv" : ".mp4");
  this->Video->SetInputConnection(this->Grab->GetOutputPort());
  this->Video->SetFileName(this->Ogv.c_str());
  this->Video->SetRate(std::max(1, static_cast<int>(std::lround(this->Fps))));
  this->Video->SetQuality(2);
}

void FrameRecorder::Capture(int frame)
{
  this->Grab->Modified();
  if (!this->Folder.empty())
  {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%05d.png", frame);
    // Beside the frame, renamed when complete (base/File.h): a full disk is an error and
    // leaves no partial frame; a link or device at a frame's path is refused.
    morphnode::file::SafeOutput out(this->Folder + name, "frame");
    this->Png->SetFileName(out.GetTemporaryPath().c_str());
    this->Png->Write();
    if (this->Png->GetErrorCode() != 0)
    {
      throw std::runtime_error("cannot write " + this->Folder + name + " (the disk is full?)");
    }
    out.Commit();
  }
  if (!this->Ogv.empty())
  {
    if (!this->VideoStarted)
    {
      this->Grab->Update();
      this->Video->Start();
      this->VideoStarted = true;
    }
    this->Video->Write();
    if (this->Video->GetError())
    {
      throw std::runtime_error("cannot write the video " + this->Ogv);
    }
  }
  ++this->Frames;
}

void FrameRecorder::Finish(vtkBehaviorTimeSource* sound)
{
  this->Finish([sound](const std::string& wav) { return sound && sound->WriteAudio(wav.c_str()); });
}

void FrameRecorder::Finish(const std::function<bool(const std::string&)>& writeSound)
{
  if (!this->Folder.empty())
  {
    *this->Log << "wrote " << this->Frames << " frames to " << this->Folder << "/frame_*.png at "
               << this->Fps << " fps\n";
  }
  if (!this->VideoStarted)
  {
    return;
  }
  this->Video->End();
  this->VideoStarted = false;
  *this->Log << "wrote " << this->Ogv << " (silent)\n";
  if (!writeSound || !writeSound(this->Wav))
  {
    throw std::runtime_error("cannot write the audio " + this->Wav);
  }
  *this->Log << "wrote " << this->Wav << "\n";
  const std::string mux = "-i " + ShellQuote(this->Ogv) + " -i " + ShellQuote(this->Wav) +
    " -c:v libx264 -pix_fmt yuv420p -c:a aac";
  if (!HasProgram("ffmpeg"))
  {
    *this->Log << "ffmpeg is not on PATH: no video with sound; kept the silent " << this->Ogv
               << " and " << this->Wav << " (mux them with: ffmpeg " << mux << " "
               << ShellQuote(this->Muxed) << ")\n";
    return;
  }
  const std::string command =
    "ffmpeg -y -loglevel error " + mux + " -b:a 128k -shortest " + ShellQuote(this->Muxed);
  if (std::system(command.c_str()) != 0)
  {
    throw std::runtime_error(
      "ffmpeg could not mux " + this->Muxed + " (kept " + this->Ogv + " and " + this->Wav + ")");
  }
  *this->Log << "wrote " << this->Muxed << " (video with sound)\n";
}
} // namespace appkit
} // namespace morphnode
