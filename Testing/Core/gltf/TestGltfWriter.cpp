// SPDX-License-Identifier: BSD-3-Clause
// The glTF exporter (gltf/GltfWriter.h): a scene written and read back by the project's
// loader is the same scene (points, triangles, normals, colours, materials, targets and
// their names, node tree and transforms), sparse targets stay sparse, the performance's
// samplers hold the weights by name and the rotations about their pivots, and every bad
// input is an InputError naming it. The files written here are also checked by the
// Khronos glTF validator (test GltfValidatorExport, fixture GltfExportFiles).
#include "gltf/GltfAnimation.h"
#include "gltf/GltfScene.h"
#include "gltf/GltfWriter.h"

#include "base/Error.h"

#include "MorphNodeTestData.h"
#include <gtest/gtest-spi.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

using namespace morphnode;

namespace
{
const std::string DefaultHead =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";

/// Where the files go: the validator test's folder (MORPHNODE_GLTF_EXPORT_DIR) when it runs
/// this program, else the test output folder.
std::string OutputDir()
{
  const char* env = std::getenv("MORPHNODE_GLTF_EXPORT_DIR");
  const std::string dir =
    env && *env ? std::string(env) : std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/gltf-export";
  std::filesystem::create_directories(dir);
  return dir;
}

/// The JSON chunk of a GLB.
nlohmann::json GlbJson(const std::vector<unsigned char>& glb)
{
  uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  return nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + length);
}

std::vector<std::string> AllTargetNames(const GltfScene& scene)
{
  std::vector<std::string> names;
  for (const auto& part : scene.Parts)
  {
    for (const auto& t : part.Targets)
    {
      if (std::find(names.begin(), names.end(), t.Name) == names.end())
      {
        names.push_back(t.Name);
      }
    }
  }
  return names;
}

/// A random performance over every target of the scene, with a head turn and eye turns.
GltfPerformance RandomPerformance(const GltfScene& scene, size_t frames, unsigned seed, bool eyes)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  GltfPerformance p;
  p.TargetNames = AllTargetNames(scene);
  for (size_t f = 0; f < frames; ++f)
  {
    p.Times.push_back(static_cast<double>(f) / 30.0);
    for (size_t t = 0; t < p.TargetNames.size(); ++t)
    {
      p.Weights.push_back(u(rng) < 0.3 ? u(rng) : 0.0);
    }
  }
  auto turns = [&](double amplitude)
  {
    std::vector<double> q;
    for (size_t f = 0; f < frames; ++f)
    {
      const double a = amplitude * (u(rng) - 0.5);
      const double axis[3] = { u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5 };
      const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
      for (double c : axis)
      {
        q.push_back(std::sin(a / 2) * c / len);
      }
      q.push_back(std::cos(a / 2));
    }
    return q;
  };
  p.Rotations.push_back({ "", { 0.0, -0.05, 0.0 }, turns(0.4) });
  if (eyes)
  {
    p.Rotations.push_back({ "EyeLeft", { 0.03, 0.016, 0.06 }, turns(0.3) });
    p.Rotations.push_back({ "EyeRight", { -0.03, 0.016, 0.06 }, turns(0.3) });
  }
  return p;
}

void ExpectSameScene(const GltfScene& a, const GltfScene& b)
{
  ASSERT_EQ(a.Parts.size(), b.Parts.size());
  for (size_t i = 0; i < a.Parts.size(); ++i)
  {
    const GltfPart& p = a.Parts[i];
    const GltfPart& q = b.Parts[i];
    SCOPED_TRACE(p.Name);
    EXPECT_EQ(p.Name, q.Name);
    EXPECT_EQ(p.Positions, q.Positions);
    EXPECT_EQ(p.Triangles, q.Triangles);
    ASSERT_EQ(p.Normals.size(), q.Normals.size());
    for (size_t k = 0; k < p.Normals.size(); ++k)
    {
      ASSERT_NEAR(p.Normals[k], q.Normals[k], 1e-3f); // normalized on writing
    }
    ASSERT_EQ(p.Colors.size(), q.Colors.size());
    for (size_t k = 0; k < p.Colors.size(); ++k)
    {
      ASSERT_EQ(std::min(1.0f, std::max(0.0f, p.Colors[k])), q.Colors[k]);
    }
    EXPECT_EQ(p.MaterialName, q.MaterialName);
    for (int c = 0; c < 4; ++c)
    {
      EXPECT_DOUBLE_EQ(p.BaseColor[c], q.BaseColor[c]);
    }
    ASSERT_EQ(p.Targets.size(), q.Targets.size());
    for (size_t t = 0; t < p.Targets.size(); ++t)
    {
      EXPECT_EQ(p.Targets[t].Name, q.Targets[t].Name);
      EXPECT_EQ(p.Targets[t].PositionDeltas, q.Targets[t].PositionDeltas);
      // Normal deltas: the loader turns them with the normals (world space) and the
      // writer normalizes the normals, so they agree to float rounding.
      ASSERT_EQ(p.Targets[t].NormalDeltas.size(), q.Targets[t].NormalDeltas.size());
      for (size_t k = 0; k < p.Targets[t].NormalDeltas.size(); ++k)
      {
        ASSERT_NEAR(p.Targets[t].NormalDeltas[k], q.Targets[t].NormalDeltas[k], 1e-5f) << k;
      }
    }
    if (!p.TransformApplied) // world-space parts are written on untransformed nodes
    {
      for (int k = 0; k < 16; ++k)
      {
        EXPECT_NEAR(p.World[k], q.World[k], 1e-12);
      }
    }
  }
}

/// Weight value of target `name` on node `node` at key `key` in the written animation.
double WrittenWeight(const GltfScene& s, int node, const std::string& name, size_t key)
{
  const GltfMesh& mesh = s.Meshes[static_cast<size_t>(s.Nodes[static_cast<size_t>(node)].Mesh)];
  const auto it = std::find(mesh.TargetNames.begin(), mesh.TargetNames.end(), name);
  if (it == mesh.TargetNames.end())
  {
    return std::nan("");
  }
  for (const auto& c : s.Animations.at(0).Channels)
  {
    if (c.Node == node && c.Path == GltfAnimationPath::Weights)
    {
      const auto& sampler = s.Animations[0].Samplers[static_cast<size_t>(c.Sampler)];
      return sampler.Values.at(
        key * mesh.TargetNames.size() + static_cast<size_t>(it - mesh.TargetNames.begin()));
    }
  }
  return std::nan("");
}

int FindNode(const GltfScene& s, const std::string& name)
{
  for (size_t n = 0; n < s.Nodes.size(); ++n)
  {
    if (s.Nodes[n].Name == name)
    {
      return static_cast<int>(n);
    }
  }
  return -1;
}
} // namespace

TEST(GltfWriter, DefaultHeadRoundTripInNodeFrames)
{
  GltfLoadOptions options;
  options.ApplyTransforms = false;
  const GltfScene head = LoadGltfScene(DefaultHead, options);
  const GltfPerformance p = RandomPerformance(head, 31, 1, true);
  const std::string file = OutputDir() + "/default_head_nodes.glb";
  WriteGltfScene(file, head, &p);
  const GltfScene back = LoadGltfScene(file, options);
  ExpectSameScene(head, back);
  // Node tree: the original nodes keep their names and transforms, under the inserted
  // rotation nodes.
  for (const auto& node : head.Nodes)
  {
    const int n = FindNode(back, node.Name);
    ASSERT_GE(n, 0) << node.Name;
    EXPECT_EQ(back.Nodes[static_cast<size_t>(n)].Translation, node.Translation);
  }
  const int headRotation = FindNode(back, "HeadRotation");
  const int eyeRotation = FindNode(back, "EyeLeftRotation");
  ASSERT_GE(headRotation, 0);
  ASSERT_GE(eyeRotation, 0);
  EXPECT_EQ(back.Nodes[static_cast<size_t>(headRotation)].Parent, -1);
  EXPECT_EQ(back.Nodes[static_cast<size_t>(FindNode(back, "EyeLeftPivot"))].Children,
    std::vector<int>{ FindNode(back, "EyeLeft") });

  // The animation: weights by name on every node with targets, rotations as given.
  ASSERT_EQ(back.Animations.size(), 1u);
  const auto& anim = back.Animations[0];
  EXPECT_EQ(anim.Name, "performance");
  for (size_t k = 0; k < p.Times.size(); k += 7)
  {
    for (size_t t = 0; t < p.TargetNames.size(); ++t)
    {
      const std::string& name = p.TargetNames[t];
      for (size_t n = 0; n < back.Nodes.size(); ++n)
      {
        const int mesh = back.Nodes[n].Mesh;
        if (mesh < 0)
        {
          continue;
        }
        const auto& names = back.Meshes[static_cast<size_t>(mesh)].TargetNames;
        if (std::find(names.begin(), names.end(), name) != names.end())
        {
          EXPECT_EQ(WrittenWeight(back, static_cast<int>(n), name, k),
            static_cast<float>(p.Weights[k * p.TargetNames.size() + t]))
            << name << " at key " << k;
        }
      }
    }
  }
  size_t rotations = 0;
  for (const auto& c : anim.Channels)
  {
    if (c.Path != GltfAnimationPath::Rotation)
    {
      continue;
    }
    ++rotations;
    const auto& sampler = anim.Samplers[static_cast<size_t>(c.Sampler)];
    EXPECT_EQ(sampler.Interpolation, GltfInterpolation::Linear);
    ASSERT_EQ(sampler.Times.size(), p.Times.size());
    const std::string& name = back.Nodes[static_cast<size_t>(c.Node)].Name;
    const GltfRotationTrack& r = p.Rotations[name == "HeadRotation" ? 0
        : name == "EyeLeftRotation"                                 ? 1
                                                                    : 2];
    for (size_t k = 0; k < p.Times.size(); ++k)
    {
      double dot = 0;
      for (int i = 0; i < 4; ++i)
      {
        dot += sampler.Values[4 * k + i] * r.Rotations[4 * k + i];
      }
      EXPECT_NEAR(std::abs(dot), 1.0, 1e-6) << name << " key " << k;
    }
  }
  EXPECT_EQ(rotations, 3u);
}

namespace
{
GltfMatrix Turn(const std::array<double, 3>& pivot, const double* q)
{
  const GltfMatrix to = GltfComposeTrs(pivot, { { 0, 0, 0, 1 } }, { { 1, 1, 1 } });
  const GltfMatrix r =
    GltfComposeTrs({ { 0, 0, 0 } }, { { q[0], q[1], q[2], q[3] } }, { { 1, 1, 1 } });
  const GltfMatrix back =
    GltfComposeTrs({ { -pivot[0], -pivot[1], -pivot[2] } }, { { 0, 0, 0, 1 } }, { { 1, 1, 1 } });
  return GltfMultiply(to, GltfMultiply(r, back));
}

std::array<double, 3> Transform(const GltfMatrix& m, double x, double y, double z)
{
  return { { m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
    m[2] * x + m[6] * y + m[10] * z + m[14] } };
}
} // namespace

// The project's own sampler (GltfAnimationPlayer, written independently of the writer)
// plays the export back: the weights by name at any time are the performance's, linearly
// interpolated, and at the keys every part's world geometry is the original part morphed
// by the key's weights, its eye turned about its pivot and the head about its pivot.
TEST(GltfWriter, PlaysBackThroughGltfAnimationPlayer)
{
  GltfLoadOptions options;
  options.ApplyTransforms = false;
  const GltfScene head = LoadGltfScene(DefaultHead, options);
  const GltfPerformance p = RandomPerformance(head, 31, 5, true);
  const std::vector<unsigned char> glb = WriteGltfSceneToMemory(head, &p);
  const GltfScene back = LoadGltfSceneFromMemory(glb.data(), glb.size(), std::string(), options);
  const GltfAnimationPlayer player(back, 0);
  EXPECT_DOUBLE_EQ(player.GetEndTime(), static_cast<float>(p.Times.back()));
  const size_t n = p.TargetNames.size();
  for (double t : { 0.0, 0.4 / 30, 7.0 / 30, 7.3 / 30, 29.9 / 30, 1.0, 2.0 })
  {
    SCOPED_TRACE("t = " + std::to_string(t));
    const GltfSceneSample s = player.Sample(t);
    const GltfNamedWeights named = GltfWeightsByTargetName(back, s);
    EXPECT_TRUE(named.Disagreements.empty());
    const double frame = std::min(30.0, t * 30.0);
    const size_t k = static_cast<size_t>(std::floor(frame));
    const size_t k1 = std::min<size_t>(k + 1, 30);
    const double u = frame - static_cast<double>(k);
    for (size_t i = 0; i < n; ++i)
    {
      const auto it = std::find(named.Names.begin(), named.Names.end(), p.TargetNames[i]);
      ASSERT_NE(it, named.Names.end()) << p.TargetNames[i];
      const double expected = (1 - u) * static_cast<float>(p.Weights[k * n + i]) +
        u * static_cast<float>(p.Weights[k1 * n + i]);
      EXPECT_NEAR(named.Values[static_cast<size_t>(it - named.Names.begin())], expected, 1e-6)
        << p.TargetNames[i];
    }
    if (u > 1e-9)
    {
      continue; // geometry at the keys (rotations between keys are slerped)
    }
    double largest = 0.0;
    for (size_t pi = 0; pi < head.Parts.size(); ++pi)
    {
      const GltfPart& part = head.Parts[pi];
      const GltfPart& written = back.Parts[pi];
      const GltfNode& node = head.Nodes[static_cast<size_t>(part.Node)];
      GltfMatrix world = node.World;
      for (size_t r = 1; r < p.Rotations.size(); ++r)
      {
        if (p.Rotations[r].Node == node.Name)
        {
          const GltfMatrix parent =
            node.Parent >= 0 ? head.Nodes[static_cast<size_t>(node.Parent)].World : GltfIdentity();
          world = GltfMultiply(parent,
            GltfMultiply(Turn(p.Rotations[r].Pivot, &p.Rotations[r].Rotations[4 * k]), node.Local));
        }
      }
      world = GltfMultiply(Turn(p.Rotations[0].Pivot, &p.Rotations[0].Rotations[4 * k]), world);
      const GltfMatrix& actualWorld = s.Nodes[static_cast<size_t>(written.Node)].World;
      const auto& w = s.Nodes[static_cast<size_t>(written.Node)].Weights;
      for (size_t v = 0; v < part.GetNumberOfPoints(); v += 7)
      {
        double x[3] = { part.Positions[3 * v], part.Positions[3 * v + 1],
          part.Positions[3 * v + 2] };
        double y[3] = { x[0], x[1], x[2] };
        for (size_t t2 = 0; t2 < part.Targets.size(); ++t2)
        {
          const auto ti =
            std::find(p.TargetNames.begin(), p.TargetNames.end(), part.Targets[t2].Name) -
            p.TargetNames.begin();
          const double weight = static_cast<float>(p.Weights[k * n + static_cast<size_t>(ti)]);
          for (int c = 0; c < 3; ++c)
          {
            x[c] += weight * part.Targets[t2].PositionDeltas[3 * v + c];
            y[c] += w[t2] * written.Targets[t2].PositionDeltas[3 * v + c];
          }
        }
        const auto e = Transform(world, x[0], x[1], x[2]);
        const auto a = Transform(actualWorld, y[0], y[1], y[2]);
        largest = std::max(largest, std::hypot(e[0] - a[0], e[1] - a[1], e[2] - a[2]));
      }
    }
    EXPECT_LT(largest, 1e-6 * 0.38) << "largest " << largest; // the default head is 0.38 m across
  }
}

TEST(GltfWriter, DefaultHeadWorldSpaceAndJson)
{
  const GltfScene head = LoadGltfScene(DefaultHead);
  GltfPerformance p = RandomPerformance(head, 10, 2, false);
  p.Interpolation = GltfInterpolation::Step;
  const std::string file = OutputDir() + "/default_head_world.gltf";
  WriteGltfScene(file, head, &p);
  const GltfScene back = LoadGltfScene(file);
  ExpectSameScene(head, back);
  EXPECT_EQ(back.Animations.at(0).Samplers.at(0).Interpolation, GltfInterpolation::Step);
  // A .gltf is JSON with the buffer embedded.
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(
    j["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0),
    0u);
}

TEST(GltfWriter, StaticSceneWithoutPerformance)
{
  const GltfScene head = LoadGltfScene(DefaultHead);
  const std::vector<unsigned char> glb = WriteGltfSceneToMemory(head, nullptr);
  const GltfScene back = LoadGltfSceneFromMemory(glb.data(), glb.size());
  ExpectSameScene(head, back);
  EXPECT_TRUE(back.Animations.empty());
}

namespace
{
/// Sparse accessors of a GLB (all of them, and those that save bytes: fewer than 3/4 of
/// their elements given).
std::pair<size_t, size_t> CountSparse(const std::vector<unsigned char>& glb, bool ours)
{
  const nlohmann::json j = GlbJson(glb);
  size_t sparse = 0;
  size_t saving = 0;
  for (const auto& a : j["accessors"])
  {
    if (a.contains("sparse"))
    {
      ++sparse;
      saving += 4 * a["sparse"]["count"].get<size_t>() < 3 * a["count"].get<size_t>() ? 1 : 0;
      if (ours) // no base data, and bounds as POSITION needs
      {
        EXPECT_FALSE(a.contains("bufferView"));
        EXPECT_TRUE(a.contains("min") && a.contains("max"));
      }
    }
  }
  return { sparse, saving };
}

std::vector<unsigned char> ReadBytes(const std::string& file)
{
  std::ifstream in(file, std::ios::binary);
  return std::vector<unsigned char>(
    std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
} // namespace

TEST(GltfWriter, SparseTargetsStaySparse)
{
  // Sparse wherever it is smaller: every target the file keeps sparse because it moves few
  // points stays sparse; a "sparse" accessor that lists every point (the default head has
  // such) is written dense, which is smaller.
  for (const std::string& file : { DefaultHead, IctHead })
  {
    if (!std::filesystem::exists(file))
    {
      continue;
    }
    SCOPED_TRACE(file);
    const std::vector<unsigned char> original = ReadBytes(file);
    const GltfScene scene = LoadGltfScene(file);
    const std::vector<unsigned char> glb = WriteGltfSceneToMemory(scene, nullptr);
    // Delta arrays that move some but fewer than 3/4 of their points: sparse is smaller.
    size_t few = 0;
    for (const auto& part : scene.Parts)
    {
      for (const auto& t : part.Targets)
      {
        for (const auto* deltas : { &t.PositionDeltas, &t.NormalDeltas })
        {
          size_t moved = 0;
          for (size_t i = 0; i + 2 < deltas->size(); i += 3)
          {
            moved += ((*deltas)[i] != 0 || (*deltas)[i + 1] != 0 || (*deltas)[i + 2] != 0) ? 1 : 0;
          }
          few += moved > 0 && 4 * moved < 3 * part.GetNumberOfPoints() ? 1 : 0;
        }
      }
    }
    const auto before = CountSparse(original, false);
    const auto after = CountSparse(glb, true);
    EXPECT_GT(before.second, 0u);
    EXPECT_GT(few, 0u);
    EXPECT_GE(after.first, few);
    EXPECT_LE(glb.size(), original.size() + original.size() / 20);
  }
}

TEST(GltfWriter, IctHeadRoundTrip)
{
  if (!std::filesystem::exists(IctHead))
  {
    GTEST_SKIP() << "ICT-FaceKit not found: " << IctHead;
  }
  GltfLoadOptions options;
  options.ApplyTransforms = false;
  const GltfScene head = LoadGltfScene(IctHead, options);
  const GltfPerformance p = RandomPerformance(head, 20, 3, true);
  const std::string file = OutputDir() + "/ict_head.glb";
  WriteGltfScene(file, head, &p);
  const GltfScene back = LoadGltfScene(file, options);
  ExpectSameScene(head, back);
  // Scale of the root kept.
  EXPECT_EQ(
    back.Nodes[static_cast<size_t>(FindNode(back, "ICTFaceKit"))].Scale, head.Nodes[0].Scale);
  std::ifstream original(IctHead, std::ios::binary | std::ios::ate);
  std::ifstream written(file, std::ios::binary | std::ios::ate);
  EXPECT_LT(static_cast<double>(written.tellg()), 1.5 * static_cast<double>(original.tellg()));
}

TEST(GltfWriter, QuaternionFromMatrix)
{
  // 90 degrees about +Y: x -> -z.
  const std::array<double, 16> m{ { 0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 0, 1 } };
  const auto q = GltfQuaternionFromRowMajor(m);
  EXPECT_NEAR(q[0], 0.0, 1e-12);
  EXPECT_NEAR(std::abs(q[1]), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(q[2], 0.0, 1e-12);
  EXPECT_NEAR(q[3] * q[1] > 0 ? 1.0 : -1.0, 1.0, 0.0);
  // 180 degrees about X (trace -1).
  const std::array<double, 16> x{ { 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1 } };
  const auto qx = GltfQuaternionFromRowMajor(x);
  EXPECT_NEAR(std::abs(qx[0]), 1.0, 1e-12);
}

namespace
{
void ExpectError(const GltfScene& scene, const GltfPerformance& p, const std::string& fragment)
{
  try
  {
    WriteGltfSceneToMemory(scene, &p);
    ADD_FAILURE() << "no error; expected one containing '" << fragment << "'";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}
} // namespace

TEST(GltfWriter, BadInput)
{
  const GltfScene head = LoadGltfScene(DefaultHead);
  const GltfPerformance good = RandomPerformance(head, 5, 4, true);
  EXPECT_NO_THROW(WriteGltfSceneToMemory(head, &good));

  GltfPerformance p = good;
  p.Weights.pop_back();
  ExpectError(head, p, "weights for 5 times");
  p = good;
  p.Weights[3] = std::nan("");
  ExpectError(head, p, "is not finite");
  p = good;
  p.Times[2] = p.Times[1];
  ExpectError(head, p, "times must increase");
  p = good;
  p.Times[2] = p.Times[1] + 1e-12; // distinct as doubles, equal as floats
  ExpectError(head, p, "as 32-bit floats");
  p = good;
  p.Times[0] = -1.0;
  ExpectError(head, p, ">= 0");
  p = good;
  p.Times.clear();
  ExpectError(head, p, "no times");
  p = good;
  p.TargetNames[0] = "noSuchTarget";
  ExpectError(head, p, "'noSuchTarget', which no part");
  p = good;
  p.TargetNames[1] = p.TargetNames[0];
  ExpectError(head, p, "appears twice");
  p = good;
  p.Rotations[1].Node = "NoSuchEye";
  ExpectError(head, p, "'NoSuchEye', which the scene does not have");
  p = good;
  p.Rotations[0].Rotations.pop_back();
  ExpectError(head, p, "4 per time");
  p = good;
  std::fill(p.Rotations[0].Rotations.begin(), p.Rotations[0].Rotations.begin() + 4, 0.0);
  ExpectError(head, p, "not a rotation");
  p = good;
  p.Interpolation = GltfInterpolation::CubicSpline;
  ExpectError(head, p, "LINEAR or STEP");

  GltfScene bad = head;
  bad.Parts[0].Triangles[5] = 1u << 30;
  ExpectError(bad, good, "beyond its");
  bad = head;
  bad.Parts[0].Positions[7] = std::nanf("");
  ExpectError(bad, good, "must be finite");
  bad = head;
  bad.Parts[0].Targets[0].PositionDeltas.pop_back();
  ExpectError(bad, good, "position delta values");
  bad = head;
  bad.Parts[0].Colors.resize(5);
  ExpectError(bad, good, "colour values");
  bad = head;
  bad.Parts[0].Node = 99;
  ExpectError(bad, good, "is not a node of the scene");
  bad = head;
  bad.Parts.clear();
  ExpectError(bad, good, "no parts");
  bad = head;
  bad.Nodes[1].Parent = 2;
  ExpectError(bad, good, "is not a node whose parent it is");
  EXPECT_THROW(WriteGltfScene("/nonexistent-folder/x.glb", head, &good), InputError);
}

namespace
{

/// The materials of `a`'s parts equal those of `b`'s parts of the same name: factors,
/// alpha, sides, and each texture's sampler, texture coordinate set, transform and image
/// (name, size, decoded pixels). Returns how many textures were compared.
size_t ExpectSameMaterials(const GltfScene& a, const GltfScene& b)
{
  size_t textures = 0;
  for (const auto& part : a.Parts)
  {
    const int j = b.FindPart(part.Name);
    EXPECT_GE(j, 0) << part.Name;
    if (j < 0 || part.Material < 0)
    {
      continue;
    }
    const GltfPart& other = b.Parts[static_cast<size_t>(j)];
    EXPECT_EQ(other.TexCoords0, part.TexCoords0) << part.Name;
    EXPECT_EQ(other.TexCoords1, part.TexCoords1) << part.Name;
    EXPECT_GE(other.Material, 0) << part.Name;
    if (other.Material < 0)
    {
      continue;
    }
    const GltfMaterial& m = a.Materials[static_cast<size_t>(part.Material)];
    const GltfMaterial& n = b.Materials[static_cast<size_t>(other.Material)];
    const std::string where = part.Name + " (" + m.Name + ")";
    EXPECT_EQ(n.Name, m.Name) << where;
    EXPECT_EQ(n.BaseColorFactor, m.BaseColorFactor) << where;
    EXPECT_EQ(n.MetallicFactor, m.MetallicFactor) << where;
    EXPECT_EQ(n.RoughnessFactor, m.RoughnessFactor) << where;
    EXPECT_EQ(n.EmissiveFactor, m.EmissiveFactor) << where;
    EXPECT_EQ(n.EmissiveStrength, m.EmissiveStrength) << where;
    EXPECT_EQ(n.AlphaMode, m.AlphaMode) << where;
    EXPECT_EQ(n.AlphaCutoff, m.AlphaCutoff) << where;
    EXPECT_EQ(n.DoubleSided, m.DoubleSided) << where;
    EXPECT_EQ(n.Unlit, m.Unlit) << where;
    const std::pair<const GltfTextureRef*, const GltfTextureRef*> refs[] = {
      { &m.BaseColorTexture, &n.BaseColorTexture },
      { &m.MetallicRoughnessTexture, &n.MetallicRoughnessTexture },
      { &m.NormalTexture, &n.NormalTexture }, { &m.OcclusionTexture, &n.OcclusionTexture },
      { &m.EmissiveTexture, &n.EmissiveTexture }
    };
    for (const auto& [r, s] : refs)
    {
      EXPECT_EQ(s->IsSet(), r->IsSet()) << where;
      if (!r->IsSet() || !s->IsSet())
      {
        continue;
      }
      ++textures;
      EXPECT_EQ(s->TexCoord, r->TexCoord) << where;
      EXPECT_EQ(s->Scale, r->Scale) << where;
      EXPECT_EQ(s->Sampler.MagFilter, r->Sampler.MagFilter) << where;
      EXPECT_EQ(s->Sampler.MinFilter, r->Sampler.MinFilter) << where;
      EXPECT_EQ(s->Sampler.WrapS, r->Sampler.WrapS) << where;
      EXPECT_EQ(s->Sampler.WrapT, r->Sampler.WrapT) << where;
      EXPECT_EQ(s->HasTransform, r->HasTransform) << where;
      EXPECT_EQ(s->UvMatrix(), r->UvMatrix()) << where;
      const GltfImage& x = a.Images[static_cast<size_t>(r->Image)];
      const GltfImage& y = b.Images[static_cast<size_t>(s->Image)];
      EXPECT_EQ(y.Name, x.Name) << where;
      EXPECT_EQ(y.Width, x.Width) << where;
      EXPECT_EQ(y.Height, x.Height) << where;
      EXPECT_TRUE(y.Pixels == x.Pixels)
        << where << ": the pixels of image '" << x.Name << "' differ";
    }
  }
  return textures;
}
} // namespace

// The shared MakeHuman avatar (skinned, 17 textures) written and read back: every part
// keeps its material (factors, alpha mode and cutoff, double-sided), its textures
// (samplers, texture coordinate sets) and their images, PNG and JPEG byte for byte.
TEST(GltfWriter, AvatarMaterialsRoundTrip)
{
  const std::string file = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(file);
  const GltfScene avatar = LoadGltfScene(file);
  ASSERT_FALSE(avatar.Materials.empty());
  ASSERT_FALSE(avatar.Images.empty());
  const std::string out = OutputDir() + "/makehuman_avatar_materials.glb";
  WriteGltfScene(out, avatar, nullptr);
  const GltfScene back = LoadGltfScene(out);
  EXPECT_EQ(back.Parts.size(), avatar.Parts.size());
  EXPECT_GT(ExpectSameMaterials(avatar, back), 0u);
  EXPECT_EQ(back.Images.size(), avatar.Images.size())
    << "every image of the avatar is used by a material";
  // PNG and JPEG go back as the file held them.
  for (const auto& image : back.Images)
  {
    const auto it = std::find_if(avatar.Images.begin(), avatar.Images.end(),
      [&image](const GltfImage& i) { return i.Name == image.Name; });
    ASSERT_NE(it, avatar.Images.end()) << image.Name;
    EXPECT_EQ(image.MimeType, it->MimeType) << image.Name;
    EXPECT_TRUE(image.Encoded == it->Encoded) << image.Name << ": not the original bytes";
  }
  // Negative control of the comparison: a material changed in the scene is seen.
  GltfScene changed = avatar;
  for (auto& m : changed.Materials)
  {
    if (m.BaseColorTexture.IsSet())
    {
      m.BaseColorTexture.TexCoord = 1 - m.BaseColorTexture.TexCoord;
      break;
    }
  }
  ::testing::TestPartResultArray failures;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
      ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &failures);
    ExpectSameMaterials(changed, back);
  }
  EXPECT_GT(failures.size(), 0) << "a changed texture coordinate set went unnoticed";
}

// The WebP variant: its images (EXT_texture_webp) are written as PNG from the decoded
// pixels, so the file needs no extension and the pixels are the same.
TEST(GltfWriter, AvatarWebpImagesAsPngRoundTrip)
{
  const std::string file = morphnode_test::AvatarFile("makehuman_avatar_webp.glb");
  MORPHNODE_SKIP_WITHOUT_AVATAR(file);
  const GltfScene avatar = LoadGltfScene(file);
  const std::vector<unsigned char> glb = WriteGltfSceneToMemory(avatar, nullptr);
  const nlohmann::json json = GlbJson(glb);
  EXPECT_FALSE(json.contains("extensionsRequired")) << json["extensionsRequired"].dump();
  for (const auto& image : json["images"])
  {
    EXPECT_EQ(image["mimeType"], "image/png");
  }
  const GltfScene back = LoadGltfSceneFromMemory(glb.data(), glb.size());
  EXPECT_GT(ExpectSameMaterials(avatar, back), 0u);
  // For the validator (GltfValidatorCoreExport).
  std::ofstream(OutputDir() + "/makehuman_avatar_webp_as_png.glb", std::ios::binary)
    .write(reinterpret_cast<const char*>(glb.data()), static_cast<std::streamsize>(glb.size()));
}

// The skinned avatar read in its nodes' frames (bind space) and written: the same skin
// (joints by name, inverse bind matrices), the same influences on every part (both weight
// sets where there are two), and, read back as the loader shows it (skinned at rest in
// world space), the same points. The performance turns the Head, Neck and eye joints
// (about their own origins); the file plays: GltfValidatorCoreExport checks it.
TEST(GltfWriter, AvatarSkinRoundTrip)
{
  const std::string file = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(file);
  GltfLoadOptions nodeFrames;
  nodeFrames.ApplyTransforms = false;
  const GltfScene avatar = LoadGltfScene(file, nodeFrames);
  ASSERT_EQ(avatar.Skins.size(), 1u);
  GltfPerformance p = RandomPerformance(avatar, 12, 5, false);
  p.Rotations.clear();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (const char* joint : { "Neck", "Head", "LeftEye", "RightEye" })
  {
    const int n = FindNode(avatar, joint);
    ASSERT_GE(n, 0) << joint;
    GltfRotationTrack track;
    track.Node = joint;
    track.Pivot = avatar.Nodes[static_cast<size_t>(n)].Translation;
    for (size_t f = 0; f < p.Times.size(); ++f)
    {
      const double a = u(rng);
      track.Rotations.insert(track.Rotations.end(), { std::sin(a / 2), 0.0, 0.0, std::cos(a / 2) });
    }
    p.Rotations.push_back(track);
  }
  const std::string out = OutputDir() + "/makehuman_avatar_skinned.glb";
  WriteGltfScene(out, avatar, &p);

  const GltfScene back = LoadGltfScene(out, nodeFrames);
  ASSERT_EQ(back.Skins.size(), 1u);
  const GltfSkin& s0 = avatar.Skins[0];
  const GltfSkin& s1 = back.Skins[0];
  ASSERT_EQ(s1.Joints.size(), s0.Joints.size());
  for (size_t j = 0; j < s0.Joints.size(); ++j)
  {
    EXPECT_EQ(back.Nodes[static_cast<size_t>(s1.Joints[j])].Name,
      avatar.Nodes[static_cast<size_t>(s0.Joints[j])].Name);
    for (size_t c = 0; c < 16; ++c)
    {
      EXPECT_NEAR(
        s1.InverseBind[j][c], s0.InverseBind[j][c], 1e-6 * (1 + std::abs(s0.InverseBind[j][c])));
    }
  }
  size_t skinnedParts = 0;
  for (const auto& part : avatar.Parts)
  {
    const int j = back.FindPart(part.Name);
    ASSERT_GE(j, 0) << part.Name;
    const GltfPart& other = back.Parts[static_cast<size_t>(j)];
    EXPECT_EQ(other.Skin >= 0, part.Skin >= 0) << part.Name;
    if (part.Skin < 0)
    {
      continue;
    }
    ++skinnedParts;
    ASSERT_EQ(other.Influences.PerPoint, part.Influences.PerPoint) << part.Name;
    ASSERT_EQ(other.Influences.Weights.size(), part.Influences.Weights.size()) << part.Name;
    for (size_t i = 0; i < part.Influences.Weights.size(); ++i)
    {
      EXPECT_NEAR(other.Influences.Weights[i], part.Influences.Weights[i], 1e-6)
        << part.Name << " " << i;
      if (part.Influences.Weights[i] > 0.0f)
      {
        EXPECT_EQ(other.Influences.Joints[i], part.Influences.Joints[i]) << part.Name << " " << i;
      }
    }
  }
  EXPECT_GT(skinnedParts, 0u);

  // The rest pose as the loader shows it: skinned, in world space.
  const GltfScene rest = LoadGltfScene(file);
  const GltfScene restBack = LoadGltfScene(out);
  ASSERT_EQ(restBack.Parts.size(), rest.Parts.size());
  double worst = 0.0;
  for (const auto& part : rest.Parts)
  {
    const int j = restBack.FindPart(part.Name);
    ASSERT_GE(j, 0) << part.Name;
    const auto& q = restBack.Parts[static_cast<size_t>(j)].Positions;
    ASSERT_EQ(q.size(), part.Positions.size()) << part.Name;
    for (size_t i = 0; i < q.size(); ++i)
    {
      worst = std::max(worst, static_cast<double>(std::abs(q[i] - part.Positions[i])));
    }
  }
  EXPECT_LT(worst, 1e-5) << "rest pose points moved by the export";
  // The joints' channels are on the joints themselves (no nodes inserted), each key the
  // turn times the joint's rest rotation.
  ASSERT_EQ(back.Animations.size(), 1u);
  EXPECT_EQ(back.Nodes.size(), avatar.Nodes.size());
  for (const char* joint : { "Neck", "Head", "LeftEye", "RightEye" })
  {
    const int n = FindNode(back, joint);
    ASSERT_GE(n, 0) << joint;
    const auto& channels = back.Animations[0].Channels;
    EXPECT_TRUE(std::any_of(channels.begin(), channels.end(),
      [n](const GltfAnimationChannel& c)
      { return c.Node == n && c.Path == GltfAnimationPath::Rotation; }))
      << joint;
  }
  // Re-read, it plays: at a key the joints hold turn * rest rotation about their own
  // origin, and the eyes ride on the turned head (their centres move).
  const GltfAnimationPlayer player(back, 0);
  const size_t key = 3;
  const GltfSceneSample sample = player.Sample(p.Times[key]);
  const GltfSceneSample restPose = GltfRestPose(back);
  for (const auto& track : p.Rotations)
  {
    const int n = FindNode(back, track.Node);
    const auto& q0 = avatar.Nodes[static_cast<size_t>(FindNode(avatar, track.Node))].Rotation;
    const double* r = track.Rotations.data() + 4 * key; // (sin, 0, 0, cos): about x
    const std::array<double, 4> expected{ { r[3] * q0[0] + r[0] * q0[3],
      r[3] * q0[1] - r[0] * q0[2], r[3] * q0[2] + r[0] * q0[1], r[3] * q0[3] - r[0] * q0[0] } };
    const auto& got = sample.Nodes[static_cast<size_t>(n)].Rotation;
    const double dot =
      got[0] * expected[0] + got[1] * expected[1] + got[2] * expected[2] + got[3] * expected[3];
    EXPECT_NEAR(std::abs(dot), 1.0, 1e-6) << track.Node;
    EXPECT_EQ(sample.Nodes[static_cast<size_t>(n)].Translation,
      avatar.Nodes[static_cast<size_t>(n)].Translation);
  }
  const int eye = FindNode(back, "LeftEye");
  const auto& w1 = sample.Nodes[static_cast<size_t>(eye)].World;
  const auto& w0 = restPose.Nodes[static_cast<size_t>(eye)].World;
  EXPECT_GT(std::abs(w1[12] - w0[12]) + std::abs(w1[13] - w0[13]) + std::abs(w1[14] - w0[14]), 1e-4)
    << "the left eye did not move with the turned neck and head";
}

// A second weight set (JOINTS_1/WEIGHTS_1) goes out and comes back: every point of the
// avatar's skinned parts has half of its first influence moved into a second set, which
// skins the same; written, read back, the part has 8 influences per point and the same
// rest pose. The avatar itself has one set.
TEST(GltfWriter, SecondWeightSetRoundTrip)
{
  const std::string file = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(file);
  GltfLoadOptions nodeFrames;
  nodeFrames.ApplyTransforms = false;
  GltfScene avatar = LoadGltfScene(file, nodeFrames);
  size_t changed = 0;
  for (auto& part : avatar.Parts)
  {
    SkinInfluences& inf = part.Influences;
    if (part.Skin < 0 || inf.PerPoint != 4)
    {
      continue;
    }
    SkinInfluences two;
    two.PerPoint = 8;
    for (size_t i = 0; i < inf.GetNumberOfPoints(); ++i)
    {
      const float half = inf.Weights[4 * i] / 2;
      for (size_t k = 0; k < 4; ++k)
      {
        two.Joints.push_back(inf.Joints[4 * i + k]);
        two.Weights.push_back(k == 0 ? half : inf.Weights[4 * i + k]);
      }
      two.Joints.insert(two.Joints.end(), { inf.Joints[4 * i], 0, 0, 0 });
      two.Weights.insert(two.Weights.end(), { half, 0.0f, 0.0f, 0.0f });
    }
    inf = two;
    ++changed;
  }
  ASSERT_GT(changed, 0u) << "the avatar has no skinned part with one weight set";
  const std::vector<unsigned char> glb = WriteGltfSceneToMemory(avatar, nullptr);
  const GltfScene back = LoadGltfSceneFromMemory(glb.data(), glb.size(), std::string(), nodeFrames);
  for (const auto& part : avatar.Parts)
  {
    const GltfPart& other = back.Parts[static_cast<size_t>(back.FindPart(part.Name))];
    EXPECT_EQ(other.Influences.PerPoint, part.Influences.PerPoint) << part.Name;
    EXPECT_EQ(other.Influences.Weights.size(), part.Influences.Weights.size()) << part.Name;
  }
  const GltfScene rest = LoadGltfScene(file);
  const GltfScene restBack = LoadGltfSceneFromMemory(glb.data(), glb.size());
  double worst = 0.0;
  for (const auto& part : rest.Parts)
  {
    const auto& q = restBack.Parts[static_cast<size_t>(restBack.FindPart(part.Name))].Positions;
    ASSERT_EQ(q.size(), part.Positions.size()) << part.Name;
    for (size_t i = 0; i < q.size(); ++i)
    {
      worst = std::max(worst, static_cast<double>(std::abs(q[i] - part.Positions[i])));
    }
  }
  EXPECT_LT(worst, 1e-5);
}

// Skins and texture coordinates that do not fit are refused with an InputError naming them.
TEST(GltfWriter, BadSkinAndTexCoords)
{
  const std::string file = morphnode_test::AvatarFile();
  MORPHNODE_SKIP_WITHOUT_AVATAR(file);
  GltfLoadOptions nodeFrames;
  nodeFrames.ApplyTransforms = false;
  const GltfScene avatar = LoadGltfScene(file, nodeFrames);
  const auto skinned = std::find_if(
    avatar.Parts.begin(), avatar.Parts.end(), [](const GltfPart& p) { return p.Skin >= 0; });
  ASSERT_NE(skinned, avatar.Parts.end());
  const size_t k = static_cast<size_t>(skinned - avatar.Parts.begin());
  auto expectError = [](const GltfScene& scene, const std::string& words)
  {
    try
    {
      WriteGltfSceneToMemory(scene, nullptr);
      ADD_FAILURE() << "no error for: " << words;
    }
    catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  GltfScene bad = avatar;
  const auto w = std::find_if(bad.Parts[k].Influences.Weights.begin(),
    bad.Parts[k].Influences.Weights.end(), [](float x) { return x > 0.0f; });
  bad.Parts[k].Influences.Joints[static_cast<size_t>(w - bad.Parts[k].Influences.Weights.begin())] =
    60000;
  expectError(bad, "beyond its skin's");
  bad = avatar;
  bad.Parts[k].Influences.Weights.pop_back();
  expectError(bad, "influences do not fit");
  bad = avatar;
  bad.Skins[0].InverseBind[0][5] = std::nan("");
  expectError(bad, "not finite");
  bad = avatar;
  bad.Parts[k].TexCoords0.resize(3);
  expectError(bad, "texture coordinates");
}
