// SPDX-License-Identifier: BSD-3-Clause
// MorphTransfer: a face's morph targets onto a mesh that has none (docs/transfer.md).
//
//   MorphTransfer --source FACE --target MESH --output OUT.glb [--landmarks FILE]
//
// FACE: a glTF/GLB face with named targets (every part with targets is used). MESH: glTF,
// OBJ, PLY, STL or VTP, any topology, scale and pose; its own targets, if any, are
// replaced. OUT: glTF/GLB, the target's own points with the source's target names.
#include "CommandLine.h"
#include "MeshFiles.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gltf/GltfWriter.h"
#include "transfer/TransferScene.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>

using namespace morphnode;

int main(int argc, char** argv)
{
  CLI::App app{
    "MorphTransfer: gives a mesh without morph targets the targets of a source face "
    "(similarity alignment, non-rigid ICP, deformation transfer, seam-aware resampling; "
    "docs/transfer.md)."
  };
  std::string sourceFile, targetFile, outputFile, landmarkFile, method = "deformation-transfer";
  TransferOptions options;
  app.add_option("--source", sourceFile, "the face with named morph targets (glTF/GLB)")
    ->required();
  app
    .add_option("--target", targetFile, "the mesh to give them to (glb, gltf, obj, ply, stl, vtp)")
    ->required();
  app.add_option("--output", outputFile, "the result (.glb, or .gltf with the buffer embedded)")
    ->required();
  app.add_option("--landmarks", landmarkFile,
    "landmarks on the target, one 'name x y z' per line (names: eye_L eye_R mouthCorner_L "
    "mouthCorner_R upperLip lowerLip chin noseTip); default: automatic alignment");
  app.add_option("--method", method, "deformation-transfer (default), barycentric or nearest")
    ->check(CLI::IsMember({ "deformation-transfer", "barycentric", "nearest" }));
  appkit::AddNumberOption(app, "--max-residual", options.MaxResidual, 1e-6, 10.0,
    "the largest registration residual accepted (95th percentile, in eye distances)");
  bool allowClosedMouth = false;
  app.add_flag("--allow-closed-mouth", allowClosedMouth,
    "transfer onto a target whose lips are not cut apart (the mouth will not open)");
  appkit::ParseCommandLine(app, argc, argv);
  options.RequireMouthOpening = !allowClosedMouth;
  options.Method = method == "nearest" ? TransferMethod::NearestVertex
    : method == "barycentric"          ? TransferMethod::Barycentric
                                       : TransferMethod::DeformationTransfer;
  try
  {
    const GltfScene sourceScene = appkit::ReadMeshScene(sourceFile);
    const TransferSource source = MakeTransferSource(sourceScene);
    GltfScene target = appkit::ReadMeshScene(targetFile);
    if (!landmarkFile.empty())
    {
      options.TargetLandmarks =
        ParseTransferLandmarks(text::ReadFile(landmarkFile, "landmark file"), landmarkFile);
    }
    const TransferResult r = TransferOntoScene(source, target, options);
    WriteGltfScene(outputFile, target, nullptr);
    for (const auto& w : r.Warnings)
    {
      std::cerr << "MorphTransfer: warning: " << w << "\n";
    }
    std::vector<float> confidence = r.Confidence;
    std::sort(confidence.begin(), confidence.end());
    const size_t moved = size_t(
      std::count_if(r.HitTriangle.begin(), r.HitTriangle.end(), [](int t) { return t >= 0; }));
    std::printf("MorphTransfer: %zu targets from %s onto %zu points of %s (%zu parts) -> %s\n",
      r.TargetNames.size(), sourceFile.c_str(), r.Confidence.size(), targetFile.c_str(),
      target.Parts.size(), outputFile.c_str());
    std::printf(
      "  alignment: scale %.6g; registration residual (95th percentile) %.3g before, %.3g after "
      "(%.2f %% of the eye distance %.4g)\n",
      r.Scale, r.AlignedResidualP95, r.ResidualP95, 100.0 * r.ResidualP95 / r.EyeDistance,
      r.EyeDistance);
    std::printf("  %zu of %zu points matched on the source; confidence median %.3f\n", moved,
      r.Confidence.size(), confidence.empty() ? 0.0 : double(confidence[confidence.size() / 2]));
    std::printf("  seconds: align %.2f, register %.2f, transfer %.2f, resample %.2f\n",
      r.AlignSeconds, r.RegisterSeconds, r.TransferSeconds, r.ResampleSeconds);
  }
  catch (const std::exception& e)
  {
    std::cerr << "MorphTransfer: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
