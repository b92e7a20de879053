// SPDX-License-Identifier: BSD-3-Clause
// MorphAvatar --gltf: the behaviour's whole track (port 1 of vtkBehaviorTimeSource, through
// the rig when there is one) and the head the avatar reads, written by vtkMorphGltfWriter;
// the sound beside it as WAV (docs/gltf.md says how to mux it with a render).
#include "AvatarGltf.h"

#include "Avatar.h"

#include "vtkErrorCode.h"
#include "vtkMorphGltfWriter.h"

#include <chrono>
#include <filesystem>
#include <iostream>

namespace morphavatar
{
bool ExportGltf(Avatar& a)
{
  const Options& o = a.Opt;
  const auto start = std::chrono::steady_clock::now();
  vtkNew<vtkMorphRigFilter> rig; // its own: the avatar's rig reads the behaviour per frame
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(a.Reader->GetOutputPort());
  if (!o.Rig.empty())
  {
    rig->SetRigFileName(o.Rig.c_str());
    rig->SetInputConnection(a.Behavior->GetOutputPort(1)); // the whole track
    rig->SetFaceConnection(a.Reader->GetOutputPort());
    writer->SetPerformanceConnection(rig->GetOutputPort());
  }
  else
  {
    writer->SetPerformanceConnection(a.Behavior->GetOutputPort(1));
  }
  // With a rig the shapes are decided (rig/RigOptimizer.h) before the expansion; the writer
  // then writes the expanded weights as they are.
  const bool perShape = a.DecidesPerShape();
  rig->SetOptimizerPreset(perShape && o.GltfOptimized ? static_cast<int>(a.Method) : 0);
  rig->SetThreshold(a.Threshold);
  rig->SetMaxVertexError(a.MaxError);
  rig->SetHysteresis(o.Hysteresis);
  writer->SetApplyOptimizer(o.GltfOptimized && !perShape);
  writer->SetOptimizerPreset(static_cast<int>(a.Method));
  writer->SetThreshold(a.Threshold);
  writer->SetMaxVertexError(a.MaxError);
  writer->SetHysteresis(o.Hysteresis);
  // One way of moving the eyes, as on screen (--gaze): with eyeLook* targets the eye joints
  // stay (eye nodes of an unskinned head turn as vtkEyeGazeFilter turns them on screen).
  writer->SetWriteEyeRotations(o.Gaze != "targets" || !a.Skin->GetHasEyeBones());
  // The arms as on screen (--pose): a T- or A-pose body relaxed unless asked otherwise.
  writer->SetRelaxArms(a.Skin->GetRelaxArms());
  writer->SetArmAngle(a.Skin->GetArmAngle());
  // The sound first: it is the cheaper of the two to refuse (a timeline whose sound passes
  // the memory budget, docs/limits.md), and a refusal then leaves no glTF file behind.
  const std::string wav = std::filesystem::path(o.Gltf).replace_extension(".wav").string();
  if (!a.Behavior->WriteAudio(wav.c_str()))
  {
    std::cerr << "MorphAvatar: cannot write the sound " << wav << " (see above)\n";
    return false;
  }
  writer->SetFileName(o.Gltf.c_str());
  if (!writer->Write() || writer->GetErrorCode() != vtkErrorCode::NoError)
  {
    std::cerr << "MorphAvatar: cannot write " << o.Gltf << " (see above)\n";
    return false;
  }
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!o.Quiet)
  {
    std::cout << "wrote " << o.Gltf << " (" << writer->GetNumberOfParts() << " parts, "
              << writer->GetNumberOfFrames() << " frames, " << writer->GetNumberOfWeightColumns()
              << " animated targets, weights " << (o.GltfOptimized ? "optimized" : "raw")
              << (writer->GetTurnsBones() ? ", head and eyes turned by the skeleton's joints" : "")
              << (writer->GetNumberOfRelaxedArms() > 0 ? ", arms relaxed" : "") << ", " << seconds
              << " s) and " << wav << "\n";
  }
  return true;
}
} // namespace morphavatar
