// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfAnimatedTestFiles.h
/// @brief A small animated head made in memory (tests of the animation sampler, the VTK
/// cross-check against vtkGLTFReader, and the FuzzGltf seeds).
///
/// Nodes: 0 "Head" (translation (0, 1, 0), mesh "Face": a quad with targets jawOpen,
/// smile, eyeBlinkLeft, default weights 0.1 0 0) with children 1 "Teeth" (mesh "Teeth": a
/// triangle with target jawOpen) and 2 "EyeLeft" (mesh "Eye": a triangle, no targets).
/// Key times 0, 0.5, 1.25, 2 (uneven, so that CUBICSPLINE tangents are scaled differently
/// per interval). Animations:
///   0 "Linear": Face and Teeth weights, LINEAR (Teeth's jawOpen = Face's jawOpen);
///   1 "Step":   Face weights, STEP;
///   2 "Cubic":  Face weights, CUBICSPLINE with non-zero in- and out-tangents;
///   3 "Pose":   Head translation LINEAR, Head rotation LINEAR (about y), Head scale
///               CUBICSPLINE, EyeLeft rotation STEP.

#include "GltfTestFiles.h"

#include <cmath>
#include <vector>

namespace gltftest
{
inline const std::vector<float>& AnimatedTimes()
{
  static const std::vector<float> times{ 0.0f, 0.5f, 1.25f, 2.0f };
  return times;
}

/// Face weights per key (3 targets).
inline const std::vector<float>& AnimatedFaceWeights()
{
  static const std::vector<float> w{ 0.0f, 0.2f, 0.0f, 0.8f, 0.5f, 0.1f, 0.3f, 1.0f, 0.9f, 0.0f,
    0.0f, 0.2f };
  return w;
}

/// CUBICSPLINE output for the face: per key [in-tangents (3), values (3), out-tangents (3)].
inline std::vector<float> AnimatedFaceCubic()
{
  const std::vector<float>& v = AnimatedFaceWeights();
  const float in[4][3] = { { 0, 0, 0 }, { 1.5f, -0.5f, 0.25f }, { -0.75f, 1.0f, 2.0f },
    { -1.0f, 0.5f, 0 } };
  const float out[4][3] = { { 2.0f, 0.5f, -0.25f }, { 0.5f, 1.25f, -1.0f }, { -2.0f, 0.25f, 0.5f },
    { 0, 0, 0 } };
  std::vector<float> o;
  for (size_t k = 0; k < 4; ++k)
  {
    o.insert(o.end(), in[k], in[k] + 3);
    o.insert(
      o.end(), v.begin() + 3 * static_cast<long>(k), v.begin() + 3 * static_cast<long>(k) + 3);
    o.insert(o.end(), out[k], out[k] + 3);
  }
  return o;
}

/// Head rotation keys about y (degrees), as quaternions (x, y, z, w).
inline std::vector<float> AnimatedHeadRotations()
{
  const double degrees[4] = { 0, 40, -30, 10 };
  std::vector<float> q;
  for (double d : degrees)
  {
    const double h = 0.5 * d * 3.14159265358979323846 / 180.0;
    q.insert(
      q.end(), { 0.0f, static_cast<float>(std::sin(h)), 0.0f, static_cast<float>(std::cos(h)) });
  }
  return q;
}

inline Builder AnimatedHead()
{
  Builder b;
  const int facePoints = b.Vec3({ -0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0 });
  const int faceIndices = b.Indices({ 0, 1, 2, 0, 2, 3 });
  const int jaw = b.Vec3({ 0, -0.2f, 0, 0, -0.2f, 0, 0, 0, 0, 0, 0, 0 });
  const int smile = b.Vec3({ -0.1f, 0.05f, 0, 0.1f, 0.05f, 0, 0, 0, 0.02f, 0, 0, 0 });
  const int blink = b.Vec3({ 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -0.1f, 0.03f });
  b.Mesh({ { "name", "Face" },
    { "primitives",
      { { { "attributes", { { "POSITION", facePoints } } }, { "indices", faceIndices },
        { "targets",
          { { { "POSITION", jaw } }, { { "POSITION", smile } }, { { "POSITION", blink } } } } } } },
    { "weights", { 0.1, 0, 0 } },
    { "extras", { { "targetNames", { "jawOpen", "smile", "eyeBlinkLeft" } } } } });
  const int teethPoints = b.Vec3({ -0.2f, 0, 0, 0.2f, 0, 0, 0, -0.1f, 0.05f });
  const int teethJaw = b.Vec3({ 0, -0.15f, 0, 0, -0.15f, 0, 0, -0.2f, 0 });
  b.Mesh({ { "name", "Teeth" },
    { "primitives",
      { { { "attributes", { { "POSITION", teethPoints } } },
        { "targets", { { { "POSITION", teethJaw } } } } } } },
    { "weights", { 0.0 } }, { "extras", { { "targetNames", { "jawOpen" } } } } });
  const int eyePoints = b.Vec3({ -0.05f, 0, 0, 0.05f, 0, 0, 0, 0.05f, 0 });
  b.Mesh({ { "name", "Eye" },
    { "primitives", { { { "attributes", { { "POSITION", eyePoints } } } } } } });
  b.Node({ { "name", "Head" }, { "mesh", 0 }, { "translation", { 0, 1, 0 } },
    { "children", { 1, 2 } } });
  b.Node({ { "name", "Teeth" }, { "mesh", 1 }, { "translation", { 0, -0.5, 0.2 } } });
  b.Node({ { "name", "EyeLeft" }, { "mesh", 2 }, { "translation", { 0.3, 0.2, 0.1 } } });
  b.Doc["scenes"] = { { { "name", "Scene" }, { "nodes", { 0 } } } };
  b.Doc["scene"] = 0;

  const int times = b.Floats(AnimatedTimes(), "SCALAR", 1);
  // min and max are required on animation inputs (and VTK 9.1 refuses the file without them).
  b.Doc["accessors"][static_cast<size_t>(times)]["min"] = { AnimatedTimes().front() };
  b.Doc["accessors"][static_cast<size_t>(times)]["max"] = { AnimatedTimes().back() };
  const int face = b.Floats(AnimatedFaceWeights(), "SCALAR", 1);
  std::vector<float> teethWeights;
  for (size_t k = 0; k < 4; ++k)
  {
    teethWeights.push_back(AnimatedFaceWeights()[3 * k]);
  }
  const int teeth = b.Floats(teethWeights, "SCALAR", 1);
  const int cubic = b.Floats(AnimatedFaceCubic(), "SCALAR", 1);
  const int translations =
    b.Floats({ 0, 1, 0, 0.1f, 1.2f, 0, -0.2f, 0.9f, 0.1f, 0, 1, 0 }, "VEC3", 3);
  const int rotations = b.Floats(AnimatedHeadRotations(), "VEC4", 4);
  // Scale, CUBICSPLINE: [in, value, out] per key.
  const int scales = b.Floats({ 0, 0, 0, 1, 1, 1, 0.5f, 0, 0,             //
                                0.2f, 0.2f, 0, 1.1f, 1, 1, 0.4f, 0, 0.1f, //
                                -0.3f, 0, 0, 0.9f, 1, 1.05f, 0, 0, 0,     //
                                0, 0, 0, 1, 1, 1, 0, 0, 0 },
    "VEC3", 3);
  const float half = 0.5f * 25.0f * 3.14159265f / 180.0f;
  const int eyeRotations = b.Floats({ 0, 0, 0, 1, std::sin(half), 0, 0, std::cos(half), 0,
                                      std::sin(half), 0, std::cos(half), 0, 0, 0, 1 },
    "VEC4", 4);
  auto sampler = [&](int output, const char* interpolation) {
    return json{ { "input", times }, { "output", output }, { "interpolation", interpolation } };
  };
  auto channel = [](int s, int node, const char* path) {
    return json{ { "sampler", s }, { "target", { { "node", node }, { "path", path } } } };
  };
  b.Doc["animations"] = json::array();
  b.Doc["animations"].push_back(
    { { "name", "Linear" }, { "samplers", { sampler(face, "LINEAR"), sampler(teeth, "LINEAR") } },
      { "channels", { channel(0, 0, "weights"), channel(1, 1, "weights") } } });
  b.Doc["animations"].push_back({ { "name", "Step" }, { "samplers", { sampler(face, "STEP") } },
    { "channels", { channel(0, 0, "weights") } } });
  b.Doc["animations"].push_back(
    { { "name", "Cubic" }, { "samplers", { sampler(cubic, "CUBICSPLINE") } },
      { "channels", { channel(0, 0, "weights") } } });
  b.Doc["animations"].push_back({ { "name", "Pose" },
    { "samplers",
      { sampler(translations, "LINEAR"), sampler(rotations, "LINEAR"),
        sampler(scales, "CUBICSPLINE"), sampler(eyeRotations, "STEP") } },
    { "channels",
      { channel(0, 0, "translation"), channel(1, 0, "rotation"), channel(2, 0, "scale"),
        channel(3, 2, "rotation") } } });
  return b;
}
} // namespace gltftest
