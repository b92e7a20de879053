// SPDX-License-Identifier: BSD-3-Clause
// ReductionStudy: gltfpack's simplifier as a yardstick. The face is written to a GLB with its
// targets, gltfpack (meshoptimizer, npm 1.3) simplifies it, and its output is read back. Its
// points are matched to the face's by position (gltfpack collapses onto existing vertices
// without -sv, so every kept point has an exact twin); its targets are the ones it wrote.
#include "ReductionStudy.h"

#include "base/Error.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfWriter.h"

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

namespace reductionstudy
{
Reduced ReduceGltfpack(
  const Face& face, double ratio, const std::string& gltfpack, const std::string& workDir)
{
  const ReductionMesh& mesh = face.Mesh;
  morphnode::GltfScene scene;
  morphnode::GltfNode node;
  node.Name = "face";
  node.InScene = true;
  scene.Nodes.push_back(node);
  morphnode::GltfPart part;
  part.Name = "face";
  part.Node = 0;
  part.Positions = mesh.Positions;
  part.Triangles = mesh.Triangles;
  for (size_t k = 0; k < mesh.GetNumberOfTargets(); ++k)
  {
    morphnode::GltfTarget t;
    t.Name = face.Names[k + 1];
    t.PositionDeltas = mesh.PositionDeltas[k];
    part.Targets.push_back(std::move(t));
  }
  scene.Parts.push_back(std::move(part));
  std::filesystem::create_directories(workDir);
  const std::string in = workDir + "/face.glb";
  std::ostringstream outName;
  outName << workDir << "/face_gltfpack_" << ratio << ".glb";
  const std::string out = outName.str();
  morphnode::WriteGltfScene(in, scene, nullptr);
  // -si R: the triangle ratio; -noq: float positions and deltas (no quantization), so that
  // the points match by position exactly. gltfpack 1.3 has no switch for its regularization
  // of meshes with targets: it decides that itself.
  std::ostringstream command;
  command << "\"" << gltfpack << "\" -i \"" << in << "\" -o \"" << out << "\" -si " << ratio
          << " -noq > \"" << workDir << "/gltfpack.log\" 2>&1";
  if (std::system(command.str().c_str()) != 0)
  {
    throw morphnode::InputError("gltfpack failed: " + command.str());
  }
  const morphnode::GltfScene packed = morphnode::LoadGltfScene(out);
  if (packed.Parts.size() != 1)
  {
    throw morphnode::InputError(
      "gltfpack wrote " + std::to_string(packed.Parts.size()) + " parts, expected 1");
  }
  const morphnode::GltfPart& p = packed.Parts[0];
  // Points by position (exact float match; the nearest when none, which -noq should not give).
  std::map<std::tuple<float, float, float>, uint32_t> byPosition;
  for (size_t i = 0; i < mesh.GetNumberOfPoints(); ++i)
  {
    byPosition.emplace(
      std::make_tuple(mesh.Positions[3 * i], mesh.Positions[3 * i + 1], mesh.Positions[3 * i + 2]),
      static_cast<uint32_t>(i));
  }
  Reduced r;
  r.Mesh.Positions = p.Positions;
  r.Mesh.Triangles = p.Triangles;
  size_t unmatched = 0;
  for (size_t i = 0; i < p.GetNumberOfPoints(); ++i)
  {
    const auto key =
      std::make_tuple(p.Positions[3 * i], p.Positions[3 * i + 1], p.Positions[3 * i + 2]);
    auto it = byPosition.find(key);
    if (it == byPosition.end())
    {
      ++unmatched;
      double best = HUGE_VAL;
      uint32_t bestId = 0;
      for (size_t j = 0; j < mesh.GetNumberOfPoints(); ++j)
      {
        double d = 0.0;
        for (int c = 0; c < 3; ++c)
        {
          d += (double(p.Positions[3 * i + c]) - mesh.Positions[3 * j + c]) *
            (double(p.Positions[3 * i + c]) - mesh.Positions[3 * j + c]);
        }
        if (d < best)
        {
          best = d;
          bestId = static_cast<uint32_t>(j);
        }
      }
      r.Source.push_back(bestId);
    }
    else
    {
      r.Source.push_back(it->second);
    }
  }
  r.ExactPoints = unmatched == 0;
  // Its targets by name, in the face's order.
  for (size_t k = 0; k < mesh.GetNumberOfTargets(); ++k)
  {
    const std::string& name = face.Names[k + 1];
    auto t = std::find_if(
      p.Targets.begin(), p.Targets.end(), [&](const auto& x) { return x.Name == name; });
    if (t == p.Targets.end())
    {
      throw morphnode::InputError("gltfpack's output lost the target '" + name + "'");
    }
    r.Mesh.PositionDeltas.push_back(t->PositionDeltas);
  }
  if (unmatched > 0)
  {
    std::cerr << "gltfpack at " << ratio << ": " << unmatched
              << " points without an exact twin (nearest used)\n";
  }
  return r;
}
} // namespace reductionstudy
