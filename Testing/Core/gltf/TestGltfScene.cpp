// SPDX-License-Identifier: BSD-3-Clause
// The glTF scene loader: real faces (ICT-FaceKit's whole head, the default face), small
// generated scenes for transforms, sparse accessors, topology and animations, and damaged
// files that must give an InputError naming the JSON pointer, never a crash (run under
// ASan + UBSan in CI).
#include "gltf/GltfScene.h"

#include "GltfTestFiles.h"
#include "base/Error.h"
#include "gltf/GltfMorphMesh.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

using gltftest::Builder;
using gltftest::json;
using morphnode::GltfLoadOptions;
using morphnode::GltfPart;
using morphnode::GltfScene;
using morphnode::InputError;
using morphnode::LoadGltfScene;

namespace
{
const std::string FaceKit = MORPHNODE_FACEKIT_DIR;

GltfScene Load(const std::string& bytes, const GltfLoadOptions& options = {})
{
  return morphnode::LoadGltfSceneFromMemory(bytes.data(), bytes.size(), "", options, "test.glb");
}

/// The message of the InputError that loading `bytes` gives ("" when it loads).
std::string ErrorOf(const std::string& bytes, const GltfLoadOptions& options = {})
{
  try
  {
    Load(bytes, options);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return std::string();
}

std::vector<double> ReadObjVertices(const std::string& path)
{
  std::ifstream in(path);
  std::vector<double> v;
  std::string line;
  while (std::getline(in, line))
  {
    if (line.size() > 2 && line[0] == 'v' && line[1] == ' ')
    {
      std::istringstream s(line.substr(2));
      s.imbue(std::locale::classic());
      double x, y, z;
      s >> x >> y >> z;
      v.insert(v.end(), { x, y, z });
    }
  }
  return v;
}

void ExpectNear3(const float* v, double x, double y, double z, double tolerance = 1e-6)
{
  EXPECT_NEAR(v[0], x, tolerance);
  EXPECT_NEAR(v[1], y, tolerance);
  EXPECT_NEAR(v[2], z, tolerance);
}

uint32_t ViewOffset(const Builder& b, int view)
{
  return b.Doc["bufferViews"][view]["byteOffset"].get<uint32_t>();
}

template <typename T>
void Poke(Builder& b, size_t offset, T value)
{
  std::memcpy(b.Bin.data() + offset, &value, sizeof(T));
}
} // namespace

// --- real files ---------------------------------------------------------------------------

TEST(GltfScene, IctHeadFullReadsEveryPartInMetres)
{
  const std::string file = FaceKit + "/ict_head_full53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit not found at " << FaceKit << " (set MORPHNODE_FACEKIT_DIR)";
  }
  const GltfScene scene = LoadGltfScene(file);
  ASSERT_EQ(scene.Parts.size(), 11u);
  EXPECT_EQ(scene.GetNumberOfPoints(), 26041u);
  EXPECT_EQ(scene.SceneName, "ICTFaceKit");
  const std::vector<std::string> names = { "Head/M_Face", "Head/M_BackHead", "Head/M_MouthSocket",
    "Head/M_EyeSocket", "MouthInterior", "Teeth", "EyeLeft/M_ScleraLeft", "EyeLeft/M_IrisLeft",
    "EyeRight/M_ScleraRight", "EyeRight/M_IrisRight", "Eyelashes" };
  size_t withTargets = 0;
  for (size_t i = 0; i < scene.Parts.size(); ++i)
  {
    const GltfPart& part = scene.Parts[i];
    EXPECT_EQ(part.Name, names[i]);
    EXPECT_TRUE(part.TransformApplied);
    EXPECT_EQ(part.Normals.size(), part.Positions.size()) << part.Name;
    const bool eye = part.Name.rfind("Eye", 0) == 0 && part.Name.rfind("Eyelashes", 0) != 0;
    EXPECT_EQ(part.Targets.size(), eye ? 0u : 53u) << part.Name;
    withTargets += part.Targets.empty() ? 0 : 1;
    // Metres: the head is about 25 cm across, every point within 0.3 m of the origin.
    for (size_t p = 0; p < part.Positions.size(); ++p)
    {
      ASSERT_LT(std::abs(part.Positions[p]), 0.3f) << part.Name;
    }
    // Deltas are the targets', not garbage: none moves a point more than 5 cm.
    for (const auto& target : part.Targets)
    {
      for (float d : target.PositionDeltas)
      {
        ASSERT_LT(std::abs(d), 0.05f) << part.Name << " " << target.Name;
      }
      EXPECT_EQ(target.NormalDeltas.size(), part.Positions.size());
    }
    if (!part.Targets.empty())
    {
      EXPECT_EQ(part.Targets[0].Name, "browDown_L");
      EXPECT_EQ(part.Targets[52].Name, "noseSneer_R");
      EXPECT_EQ(part.DefaultWeights, std::vector<double>(53, 0.0));
    }
  }
  EXPECT_EQ(withTargets, 7u);
  // Colours: the iris has COLOR_0 (black pupil), every part a base colour.
  const GltfPart& iris = scene.Parts[static_cast<size_t>(scene.FindPart("EyeLeft/M_IrisLeft"))];
  EXPECT_EQ(iris.Colors.size(), 4 * iris.GetNumberOfPoints());
  EXPECT_NEAR(iris.BaseColor[0], 0.2, 1e-12);
  EXPECT_EQ(scene.Parts[0].MaterialName, "M_Face");
  EXPECT_NEAR(scene.Parts[0].BaseColor[1], 0.62, 1e-12);

  // The eyes sit at their node's translation (centimetres in the file, times the root's
  // 0.01), and their points around it.
  for (const char* eyeName : { "EyeLeft/M_ScleraLeft", "EyeRight/M_ScleraRight" })
  {
    const GltfPart& eye = scene.Parts[static_cast<size_t>(scene.FindPart(eyeName))];
    const auto& node = scene.Nodes[static_cast<size_t>(eye.Node)];
    EXPECT_EQ(node.Parent, 0);
    const double sx = eyeName[3] == 'L' ? 1 : -1;
    EXPECT_NEAR(eye.World[12], sx * 0.031370726543482075, 1e-12);
    EXPECT_NEAR(eye.World[13], 0.03609134390913293, 1e-12);
    EXPECT_NEAR(eye.World[14], 0.07987609150576895, 1e-12);
    EXPECT_NEAR(node.Translation[0], sx * 3.1370726543482075, 1e-12);
    double radius = 0;
    for (size_t p = 0; p < eye.GetNumberOfPoints(); ++p)
    {
      const double dx = eye.Positions[3 * p] - eye.World[12],
                   dy = eye.Positions[3 * p + 1] - eye.World[13],
                   dz = eye.Positions[3 * p + 2] - eye.World[14];
      radius = std::max(radius, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
    EXPECT_GT(radius, 0.008); // an eyeball is about 12 mm in radius, its cornea bulges
    EXPECT_LT(radius, 0.018);
  }

  // Against the FaceKit's own OBJ originals (same vertex order, centimetres): the face
  // skin's neutral and its jawOpen target, read from a sparse accessor without bufferView.
  const std::vector<double> neutral = ReadObjVertices(FaceKit + "/obj/generic_neutral_mesh.obj");
  const std::vector<double> jawOpen = ReadObjVertices(FaceKit + "/obj/jawOpen.obj");
  const GltfPart& face = scene.Parts[0];
  ASSERT_EQ(face.GetNumberOfPoints(), 9409u);
  ASSERT_GE(neutral.size(), 3 * 9409u);
  ASSERT_EQ(jawOpen.size(), neutral.size());
  size_t jaw = 0;
  while (face.Targets[jaw].Name != "jawOpen")
  {
    ++jaw;
  }
  double worstPoint = 0, worstDelta = 0;
  for (size_t i = 0; i < 3 * 9409; ++i)
  {
    worstPoint = std::max(worstPoint, std::abs(face.Positions[i] - 0.01 * neutral[i]));
    worstDelta = std::max(
      worstDelta, std::abs(face.Targets[jaw].PositionDeltas[i] - 0.01 * (jawOpen[i] - neutral[i])));
  }
  EXPECT_LT(worstPoint, 1e-6);
  EXPECT_LT(worstDelta, 1e-6);
}

TEST(GltfScene, IctHeadInTheFileFrame)
{
  const std::string file = FaceKit + "/ict_head_full53.glb";
  if (!std::filesystem::exists(file))
  {
    GTEST_SKIP() << "ICT-FaceKit not found at " << FaceKit;
  }
  GltfLoadOptions options;
  options.ApplyTransforms = false;
  const GltfScene scene = LoadGltfScene(file, options);
  const GltfPart& eye = scene.Parts[6];
  EXPECT_FALSE(eye.TransformApplied);
  // The eye's points are relative to its centre, in centimetres.
  double radius = 0;
  for (float v : eye.Positions)
  {
    radius = std::max(radius, double(std::abs(v)));
  }
  EXPECT_GT(radius, 0.8);
  EXPECT_LT(radius, 1.8);
  EXPECT_EQ(scene.Nodes[0].Name, "ICTFaceKit");
  EXPECT_EQ(scene.Nodes[0].Children.size(), 6u);
  EXPECT_DOUBLE_EQ(scene.Nodes[0].Scale[0], 0.01);
}

TEST(GltfScene, DefaultHeadLoadsEveryPart)
{
  // The project's own multi-part head (Data/DefaultFace/default_head.glb, docs/default-face.md).
  const GltfScene scene =
    LoadGltfScene(std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb");
  size_t primitives = 0;
  for (const auto& node : scene.Nodes)
  {
    if (node.InScene && node.Mesh >= 0)
    {
      primitives += scene.Meshes[static_cast<size_t>(node.Mesh)].NumberOfPrimitives;
    }
  }
  EXPECT_GE(scene.Parts.size(), 10u);
  EXPECT_EQ(scene.Parts.size(), primitives);
  for (const GltfPart& part : scene.Parts)
  {
    EXPECT_FALSE(part.Name.empty());
    EXPECT_EQ(part.DefaultWeights.size(), part.Targets.size()) << part.Name;
    const auto& node = scene.Nodes[static_cast<size_t>(part.Node)];
    // Parts sit at their node: the world matrix's translation is the node's, composed.
    EXPECT_EQ(part.World, node.World) << part.Name;
  }
}

// --- generated scenes ---------------------------------------------------------------------

TEST(GltfScene, QuadReadsEverything)
{
  const Builder b = gltftest::Quad();
  for (const std::string& bytes : { b.Glb(), b.GltfWithDataUri() })
  {
    const GltfScene scene = Load(bytes);
    ASSERT_EQ(scene.Parts.size(), 1u);
    const GltfPart& part = scene.Parts[0];
    EXPECT_EQ(part.Name, "Quad");
    EXPECT_EQ(part.MaterialName, "Skin");
    EXPECT_EQ(part.BaseColor, (std::array<double, 4>{ { 0.8, 0.6, 0.5, 1 } }));
    EXPECT_EQ(part.Triangles, (std::vector<uint32_t>{ 0, 1, 2, 0, 2, 3 }));
    // World = scale 0.5 * (translate (1, 2, 3) * rotate 90 degrees about z).
    ExpectNear3(&part.Positions[0], 0.5, 1.0, 1.5);
    ExpectNear3(&part.Positions[3], 0.5, 1.5, 1.5);
    ExpectNear3(&part.Normals[0], 0, 0, 1);
    EXPECT_EQ(part.Colors, (std::vector<float>{ 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1 }));
    ASSERT_EQ(part.Targets.size(), 2u);
    EXPECT_EQ(part.Targets[0].Name, "Lift");
    EXPECT_EQ(part.Targets[1].Name, "Raise");
    ExpectNear3(&part.Targets[0].PositionDeltas[0], 0, 0, 0.05);
    // Normal deltas turn with the normals and keep their scale relative to them.
    ExpectNear3(&part.Targets[0].NormalDeltas[0], 0, 0.1, 0);
    // The sparse target without bufferView: zeros but point 2's (0, 0.5, 0), turned.
    EXPECT_TRUE(part.Targets[1].NormalDeltas.empty());
    ExpectNear3(&part.Targets[1].PositionDeltas[0], 0, 0, 0);
    ExpectNear3(&part.Targets[1].PositionDeltas[6], -0.25, 0, 0);
    ExpectNear3(&part.Targets[1].PositionDeltas[9], 0, 0, 0);
    EXPECT_EQ(part.DefaultWeights, (std::vector<double>{ 0.25, 0 }));

    ASSERT_EQ(scene.Nodes.size(), 2u);
    EXPECT_EQ(scene.Nodes[1].Parent, 0);
    EXPECT_TRUE(scene.Nodes[1].InScene);
    EXPECT_NEAR(scene.Nodes[1].World[12], 0.5, 1e-12);

    ASSERT_EQ(scene.Animations.size(), 1u);
    const auto& animation = scene.Animations[0];
    EXPECT_EQ(animation.Name, "Nod");
    ASSERT_EQ(animation.Samplers.size(), 2u);
    EXPECT_EQ(animation.Samplers[0].Times, (std::vector<float>{ 0, 0.5f, 1 }));
    EXPECT_EQ(animation.Samplers[0].Components, 4);
    EXPECT_EQ(animation.Samplers[1].Interpolation, morphnode::GltfInterpolation::Step);
    ASSERT_EQ(animation.Channels.size(), 2u);
    EXPECT_EQ(animation.Channels[0].Path, morphnode::GltfAnimationPath::Rotation);
    EXPECT_EQ(animation.Channels[1].Path, morphnode::GltfAnimationPath::Weights);
    EXPECT_EQ(animation.Channels[1].ValuesPerElement, 2);
    EXPECT_EQ(animation.Channels[1].Node, 1);
  }
}

TEST(GltfScene, TransformsNotAppliedKeepTheFileFrame)
{
  GltfLoadOptions options;
  options.ApplyTransforms = false;
  const GltfScene scene = Load(gltftest::Quad().Glb(), options);
  const GltfPart& part = scene.Parts[0];
  EXPECT_FALSE(part.TransformApplied);
  ExpectNear3(&part.Positions[3], 1, 0, 0);
  ExpectNear3(&part.Targets[1].PositionDeltas[6], 0, 0.5, 0);
  // The world matrix maps them as the applied version does.
  const auto& m = part.World;
  EXPECT_NEAR(m[0] * 1 + m[12], 0.5, 1e-12);
  EXPECT_NEAR(m[1] * 1 + m[13], 1.5, 1e-12);
}

TEST(GltfScene, NestedTrsAndMatrixAgree)
{
  // Three levels: TRS, matrix, TRS with a non-uniform scale. The same chain once with
  // matrices only must give the same points.
  const std::array<double, 4> q1{ { 0.2, -0.3, 0.1, 0.927 } };
  const double n1 = std::sqrt(q1[0] * q1[0] + q1[1] * q1[1] + q1[2] * q1[2] + q1[3] * q1[3]);
  const std::array<double, 4> r1{ { q1[0] / n1, q1[1] / n1, q1[2] / n1, q1[3] / n1 } };
  const auto m1 = morphnode::GltfComposeTrs({ { 1, -2, 0.5 } }, r1, { { 2, 2, 2 } });
  const auto m2 =
    morphnode::GltfComposeTrs({ { 0, 3, 0 } }, { { 0, 0.6, 0, 0.8 } }, { { 1, 1, 1 } });
  const auto m3 =
    morphnode::GltfComposeTrs({ { -1, 0, 0.25 } }, { { 0, 0, 0, 1 } }, { { 1, 3, 0.5 } });

  auto make = [&](bool matrices)
  {
    Builder b = gltftest::Quad();
    b.Doc["nodes"] = json::array();
    b.Doc.erase("animations");
    auto node = [&](const std::array<double, 16>& m, json trs) {
      return matrices ? json{ { "matrix", m } } : trs;
    };
    b.Node(node(
      m1, { { "translation", { 1, -2, 0.5 } }, { "rotation", q1 }, { "scale", { 2, 2, 2 } } }));
    b.Node({ { "matrix", m2 } });
    b.Node(node(m3, { { "translation", { -1, 0, 0.25 } }, { "scale", { 1, 3, 0.5 } } }));
    b.Doc["nodes"][0]["children"] = { 1 };
    b.Doc["nodes"][1]["children"] = { 2 };
    b.Doc["nodes"][2]["mesh"] = 0;
    return Load(b.Glb());
  };
  const GltfScene trs = make(false);
  const GltfScene matrix = make(true);
  const auto world = morphnode::GltfMultiply(morphnode::GltfMultiply(m1, m2), m3);
  ASSERT_EQ(trs.Parts.size(), 1u);
  for (size_t i = 0; i < 16; ++i)
  {
    EXPECT_NEAR(trs.Parts[0].World[i], world[i], 1e-12);
    EXPECT_NEAR(matrix.Parts[0].World[i], world[i], 1e-12);
  }
  // Point 1 = (1, 0, 0) goes to world * (1, 0, 0, 1).
  ExpectNear3(&trs.Parts[0].Positions[3], world[0] + world[12], world[1] + world[13],
    world[2] + world[14], 1e-5);
  for (size_t i = 0; i < trs.Parts[0].Positions.size(); ++i)
  {
    EXPECT_NEAR(trs.Parts[0].Positions[i], matrix.Parts[0].Positions[i], 1e-5);
    EXPECT_NEAR(trs.Parts[0].Normals[i], matrix.Parts[0].Normals[i], 1e-5);
  }
  // Normals stay unit length and perpendicular to the transformed quad.
  const float* n = &trs.Parts[0].Normals[0];
  EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
  const float* p = trs.Parts[0].Positions.data();
  const double e1[3] = { p[3] - p[0], p[4] - p[1], p[5] - p[2] };
  const double e2[3] = { p[9] - p[0], p[10] - p[1], p[11] - p[2] };
  EXPECT_NEAR(n[0] * e1[0] + n[1] * e1[1] + n[2] * e1[2], 0, 1e-5);
  EXPECT_NEAR(n[0] * e2[0] + n[1] * e2[1] + n[2] * e2[2], 0, 1e-5);
}

TEST(GltfScene, MirroringTurnsTriangles)
{
  Builder b = gltftest::Quad();
  b.Doc["nodes"][0]["scale"] = { -1, 1, 1 };
  const GltfScene scene = Load(b.Glb());
  EXPECT_EQ(scene.Parts[0].Triangles, (std::vector<uint32_t>{ 0, 2, 1, 0, 3, 2 }));
  // The normal still points to the side the (turned) triangles face: +z stays +z.
  ExpectNear3(&scene.Parts[0].Normals[0], 0, 0, 1);
}

TEST(GltfScene, SparseWithAndWithoutBufferView)
{
  Builder b = gltftest::Quad();
  // A sparse POSITION target on a dense base: point 1 replaced, the others kept.
  const int onBase =
    b.SparseVec3(4, { 1, 3 }, { 0, 0, 7, 0, 0, 9 }, { 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4 });
  b.Doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = onBase;
  GltfLoadOptions options;
  options.ApplyTransforms = false;
  const GltfScene scene = Load(b.Glb(), options);
  EXPECT_EQ(scene.Parts[0].Targets[1].PositionDeltas,
    (std::vector<float>{ 1, 1, 1, 0, 0, 7, 3, 3, 3, 0, 0, 9 }));
  // Without bufferView (the Quad's own), the base is zeros.
  const GltfScene quad = Load(gltftest::Quad().Glb(), options);
  EXPECT_EQ(quad.Parts[0].Targets[1].PositionDeltas,
    (std::vector<float>{ 0, 0, 0, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0 }));
}

TEST(GltfScene, StripsFansAndUnindexed)
{
  Builder b = gltftest::Quad();
  auto& prim = b.Doc["meshes"][0]["primitives"][0];
  prim["indices"] = b.Indices({ 0, 1, 3, 2 });
  prim["mode"] = 5; // strip
  GltfScene scene = Load(b.Glb());
  EXPECT_EQ(scene.Parts[0].Triangles, (std::vector<uint32_t>{ 0, 1, 3, 1, 2, 3 }));
  prim["indices"] = b.Indices({ 0, 1, 2, 3 });
  prim["mode"] = 6; // fan
  scene = Load(b.Glb());
  EXPECT_EQ(scene.Parts[0].Triangles, (std::vector<uint32_t>{ 1, 2, 0, 2, 3, 0 }));
  // Strips joined by degenerate triangles lose those.
  prim["indices"] = b.Indices({ 0, 1, 2, 2, 3, 3, 0, 1 });
  prim["mode"] = 5;
  scene = Load(b.Glb());
  for (size_t t = 0; t < scene.Parts[0].Triangles.size(); t += 3)
  {
    const auto& tri = scene.Parts[0].Triangles;
    EXPECT_TRUE(tri[t] != tri[t + 1] && tri[t + 1] != tri[t + 2] && tri[t] != tri[t + 2]);
  }
  // No indices: the points in order, three per triangle.
  prim.erase("indices");
  prim["mode"] = 4;
  const int position = b.Vec3({ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0 });
  prim["attributes"] = { { "POSITION", position } };
  prim.erase("targets");
  b.Doc["meshes"][0].erase("weights");
  b.Doc["meshes"][0].erase("extras");
  b.Doc.erase("animations");
  scene = Load(b.Glb());
  EXPECT_EQ(scene.Parts[0].Triangles, (std::vector<uint32_t>{ 0, 1, 2, 3, 4, 5 }));
  EXPECT_TRUE(scene.Parts[0].Normals.empty());
  EXPECT_TRUE(scene.Parts[0].Targets.empty());
}

TEST(GltfScene, InstancedMeshesAndNodeWeights)
{
  Builder b = gltftest::Quad();
  b.Doc["nodes"][0]["children"] = { 1, 2 };
  b.Node({ { "name", "Quad" }, { "mesh", 0 }, { "weights", { 0.5, 0.75 } } });
  const GltfScene scene = Load(b.Glb());
  ASSERT_EQ(scene.Parts.size(), 2u);
  EXPECT_EQ(scene.Parts[0].Name, "Quad");
  EXPECT_EQ(scene.Parts[1].Name, "Quad#2");
  EXPECT_EQ(scene.Parts[0].DefaultWeights, (std::vector<double>{ 0.25, 0 }));
  EXPECT_EQ(scene.Parts[1].DefaultWeights, (std::vector<double>{ 0.5, 0.75 }));
}

TEST(GltfScene, ExternalBufferBesideTheFile)
{
  const std::filesystem::path folder =
    std::filesystem::path(MORPHNODE_TEST_OUTPUT_DIR) / "gltf-external";
  std::filesystem::create_directories(folder / "inner");
  const Builder b = gltftest::Quad();
  json doc = b.Finished();
  doc["buffers"][0]["uri"] = "quad%20data.bin";
  const std::vector<unsigned char> bin = b.PaddedBin();
  std::ofstream(folder / "quad data.bin", std::ios::binary)
    .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
  std::ofstream(folder / "quad.gltf") << doc.dump();
  const GltfScene scene = LoadGltfScene((folder / "quad.gltf").string());
  EXPECT_EQ(scene.Parts.size(), 1u);

  // Only files in the same folder: a path out of it is refused before anything is read.
  for (const char* uri :
    { "../quad%20data.bin", "inner/quad.bin", "/etc/passwd", "file:///etc/passwd", "..%2Fx.bin" })
  {
    doc["buffers"][0]["uri"] = uri;
    std::ofstream(folder / "inner" / "bad.gltf") << doc.dump();
    try
    {
      LoadGltfScene((folder / "inner" / "bad.gltf").string());
      ADD_FAILURE() << uri << " was followed";
    }
    catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find("/buffers/0/uri: "), std::string::npos) << e.what();
    }
  }
  // Issue 29: a link in the folder that leads out of it is refused too (the folder is
  // checked after resolving links); a FIFO named like the buffer is refused, not waited for.
  std::error_code ec;
  std::filesystem::remove(folder / "inner" / "link.bin", ec);
  std::filesystem::create_symlink(folder / "quad data.bin", folder / "inner" / "link.bin");
  std::filesystem::remove(folder / "inner" / "fifo.bin", ec);
  ASSERT_EQ(::mkfifo((folder / "inner" / "fifo.bin").c_str(), 0600), 0);
  for (const char* uri : { "link.bin", "fifo.bin" })
  {
    doc["buffers"][0]["uri"] = uri;
    std::ofstream(folder / "inner" / "bad.gltf") << doc.dump();
    try
    {
      LoadGltfScene((folder / "inner" / "bad.gltf").string());
      ADD_FAILURE() << uri << " was followed";
    }
    catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find("/buffers/0/uri: "), std::string::npos) << e.what();
    }
  }
  // From memory, external buffers cannot be found.
  doc["buffers"][0]["uri"] = "quad%20data.bin";
  EXPECT_NE(ErrorOf(doc.dump()).find("/buffers/0/uri: "), std::string::npos);
  // A .bin of the wrong size.
  doc["buffers"][0]["byteLength"] = bin.size() + 4;
  std::ofstream(folder / "short.gltf") << doc.dump();
  EXPECT_THROW(LoadGltfScene((folder / "short.gltf").string()), InputError);
}

// --- damaged files ------------------------------------------------------------------------

struct Damage
{
  const char* Name;
  std::function<std::string(Builder&)> Make; ///< damages the quad, returns the bytes
  const char* Expected;                      ///< the JSON pointer (or text) the message names
};

std::string Json(Builder& b, const std::function<void(json&)>& edit)
{
  json doc = b.Finished();
  edit(doc);
  return Builder::MakeGlb(doc.dump(), b.PaddedBin());
}

class GltfDamage : public ::testing::TestWithParam<Damage>
{
};

TEST_P(GltfDamage, IsAnInputErrorNamingThePointer)
{
  Builder b = gltftest::Quad();
  const std::string bytes = GetParam().Make(b);
  const std::string message = ErrorOf(bytes);
  ASSERT_FALSE(message.empty()) << GetParam().Name << " was accepted";
  EXPECT_NE(message.find(GetParam().Expected), std::string::npos) << message;
  EXPECT_EQ(message.rfind("test.glb: ", 0), 0u) << message;
  std::printf("  %s -> %s\n", GetParam().Name, message.c_str());
}

const Damage Damages[] = {
  // The cases.
  { "accessor count past the buffer",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["count"] = 400; }); },
    "/accessors/0/count: 400 elements" },
  { "bufferView offset past the buffer",
    [](Builder& b) { return Json(b, [](json& d) { d["bufferViews"][0]["byteOffset"] = 100000; }); },
    "/bufferViews/0: " },
  { "bufferView length past the buffer",
    [](Builder& b) { return Json(b, [](json& d) { d["bufferViews"][3]["byteLength"] = 4000; }); },
    "/bufferViews/3: " },
  { "missing accessor",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99; });
    },
    "/meshes/0/primitives/0/attributes/POSITION: there is no accessor 99" },
  { "missing accessor in a target",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = 10; });
    },
    "/meshes/0/primitives/0/targets/1/POSITION: there is no accessor 10" },
  { "sparse count larger than the accessor",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][6]["sparse"]["count"] = 400; }); },
    "/accessors/6/sparse/count: 400 exceeds the accessor's count 4" },
  { "sparse count larger than its data",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][6]["sparse"]["count"] = 3; }); },
    "/accessors/6/sparse/count: 3 indices" },
  { "sparse index out of range",
    [](Builder& b)
    {
      Poke<uint32_t>(b, ViewOffset(b, 6), 7);
      return b.Glb();
    },
    "/accessors/6/sparse/indices: index 0 is 7" },
  { "sparse indices not increasing",
    [](Builder& b)
    {
      b.Doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] =
        b.SparseVec3(4, { 2, 1 }, { 0, 1, 0, 0, 1, 0 });
      return b.Glb();
    },
    "/accessors/10/sparse/indices: index 1 (1) does not follow" },
  { "index referencing a point past the count",
    [](Builder& b)
    {
      Poke<uint16_t>(b, ViewOffset(b, 3) + 4, 9);
      return b.Glb();
    },
    "/accessors/3: element 2 (indices of /meshes/0/primitives/0) is 9, but there are only 4 "
    "points" },
  { "wrong component type for POSITION",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["componentType"] = 5123; }); },
    "/meshes/0/primitives/0/attributes/POSITION: accessor 0 is VEC3 of UNSIGNED_SHORT; POSITION "
    "must be VEC3 of FLOAT" },
  { "wrong type for POSITION",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["type"] = "VEC2"; }); },
    "/meshes/0/primitives/0/attributes/POSITION: accessor 0 is VEC2" },
  { "target with a mismatching count",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][4]["count"] = 3; }); },
    "/meshes/0/primitives/0/targets/0/POSITION: accessor 4 has 3 elements, but the primitive has 4 "
    "points" },
  { "NaN (null) in a matrix",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        {
          d["nodes"][1] = { { "mesh", 0 },
            { "matrix", { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 } } };
          d["nodes"][1]["matrix"][5] = std::nan("");
        });
    },
    "/nodes/1/matrix/5: must be a number, got null" },
  { "NaN literal in the JSON",
    [](Builder& b)
    {
      std::string text = b.Finished().dump();
      text.replace(text.find("\"scale\":[0.5,0.5,0.5]"), 21, "\"scale\":[NaN,0.5,0.5]");
      return Builder::MakeGlb(text, b.PaddedBin());
    },
    "is not valid glTF JSON" },
  { "NaN in the positions",
    [](Builder& b)
    {
      Poke<float>(b, ViewOffset(b, 0) + 16, std::nanf(""));
      return b.Glb();
    },
    "/accessors/0: element 1 (POSITION of /meshes/0/primitives/0) is NaN" },
  { "infinity in a target",
    [](Builder& b)
    {
      Poke<float>(b, ViewOffset(b, 7) + 4, HUGE_VALF);
      return b.Glb();
    },
    "/accessors/6: element 2 (POSITION of /meshes/0/primitives/0/targets/1) is infinite" },
  { "non-affine matrix",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        {
          d["nodes"][1] = { { "mesh", 0 },
            { "matrix", { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2 } } };
        });
    },
    "/nodes/1/matrix: is not an affine transform" },
  { "matrix taking points beyond float (found by FuzzGltf)",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        {
          d["nodes"][1] = { { "mesh", 0 },
            { "matrix", { 0, 1, 1e300, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 } } };
        });
    },
    "/nodes/1/matrix/2: 1e+300 is beyond the range of float" }, // (refused where it is, issue 29)
  { "matrix taking points past the blend limit (issue 29)",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        {
          d["nodes"][1] = { { "mesh", 0 },
            { "matrix", { 0, 1, 3e38, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 } } };
        });
    },
    "/meshes/0/primitives/0: its positions, deltas and default weights reach a coordinate of 1.5" },
  { "default weight beyond float (issue 29)",
    [](Builder& b) {
      return Json(b, [](json& d) { d["meshes"][0]["weights"] = { 1e39, 0 }; });
    },
    "/meshes/0/weights/0: 1e+39 is beyond the range of float" },
  { "default weight whose blend passes the coordinate limit (issue 29)",
    [](Builder& b) {
      return Json(b, [](json& d) { d["meshes"][0]["weights"] = { 3e38, 0 }; });
    },
    "/meshes/0/primitives/0: its positions, deltas and default weights reach a coordinate of" },
  { "asset.minVersion above 2.0 (issue 29)",
    [](Builder& b) { return Json(b, [](json& d) { d["asset"]["minVersion"] = "2.5"; }); },
    "/asset/minVersion: glTF '2.5' is required; this reader reads 2.0" },
  { "matrix and TRS",
    [](Builder& b)
    {
      return Json(b,
        [](json& d) {
          d["nodes"][1]["matrix"] = json::array({ 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 });
        });
    },
    "/nodes/1/translation: a node with a 'matrix'" },
  { "zero quaternion",
    [](Builder& b) {
      return Json(b, [](json& d) { d["nodes"][1]["rotation"] = { 0, 0, 0, 0 }; });
    },
    "/nodes/1/rotation: is not a rotation quaternion" },
  { "negative count",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["count"] = -1; }); },
    "/accessors/0/count: must not be negative, got -1" },
  { "zero count",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["count"] = 0; }); },
    "/accessors/0/count: must be at least 1" },
  { "huge count",
    [](Builder& b)
    { return Json(b, [](json& d) { d["accessors"][0]["count"] = 1099511627776ull; }); },
    "/accessors/0/count: 1099511627776 is too large" },
  { "count as a float",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["count"] = 4.0; }); },
    "/accessors/0/count: must be an integer, got 4" },
  { "index 2^32 (tinygltf would read accessor 0)",
    [](Builder& b)
    {
      return Json(b,
        [](json& d) { d["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 4294967296ull; });
    },
    "/meshes/0/primitives/0/attributes/NORMAL: 4294967296 is too large" },
  { "huge sparse byteOffset",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["accessors"][6]["sparse"]["values"]["byteOffset"] = 4294967292ull; });
    },
    "/accessors/6/sparse/values/byteOffset: 4294967292 is too large" },
  { "misaligned accessor",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["byteOffset"] = 2; }); },
    "/accessors/0/byteOffset: the accessor's data do not start on a multiple of 4 bytes" },
  { "stride shorter than an element",
    [](Builder& b) { return Json(b, [](json& d) { d["bufferViews"][0]["byteStride"] = 8; }); },
    "/accessors/0: bufferView 0's byteStride 8 is less than an element" },
  { "stride not a multiple of 4",
    [](Builder& b) { return Json(b, [](json& d) { d["bufferViews"][0]["byteStride"] = 14; }); },
    "/bufferViews/0/byteStride: must be a multiple of 4" },
  { "buffer longer than the BIN chunk",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        { d["buffers"][0]["byteLength"] = d["buffers"][0]["byteLength"].get<int>() + 4; });
    },
    "/buffers/0/byteLength: " },
  { "second buffer without uri",
    [](Builder& b) {
      return Json(b, [](json& d) { d["buffers"].push_back({ { "byteLength", 4 } }); });
    },
    "/buffers/1: has no 'uri'" },
  { "index count not a multiple of 3",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][3]["count"] = 5; }); },
    "/meshes/0/primitives/0/indices: 5 corners do not make whole triangles" },
  { "lines",
    [](Builder& b)
    { return Json(b, [](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 1; }); },
    "/meshes/0/primitives/0/mode: LINES is not supported" },
  { "unknown mode",
    [](Builder& b)
    { return Json(b, [](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 7; }); },
    "/meshes/0/primitives/0/mode: 7 is not a glTF primitive mode" },
  { "no POSITION",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["meshes"][0]["primitives"][0]["attributes"].erase("POSITION"); });
    },
    "/meshes/0/primitives/0/attributes: has no POSITION" },
  { "indices without bufferView",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][3].erase("bufferView"); }); },
    "/meshes/0/primitives/0/indices: accessor 3 has no bufferView" },
  { "signed byte indices",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][3]["componentType"] = 5120; }); },
    "/meshes/0/primitives/0/indices: accessor 3 is SCALAR of BYTE" },
  { "primitives with different target counts",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        {
          json second = d["meshes"][0]["primitives"][0];
          second["targets"].erase(1);
          d["meshes"][0]["primitives"].push_back(second);
        });
    },
    "/meshes/0/primitives/1/targets: the primitive has 1 morph targets, but primitive 0 of the "
    "mesh has 2" },
  { "mesh weights of the wrong number",
    [](Builder& b) { return Json(b, [](json& d) { d["meshes"][0]["weights"] = { 0.5 }; }); },
    "/meshes/0/weights: 1 weights for 2 morph targets" },
  { "node weights of the wrong number",
    [](Builder& b) {
      return Json(b, [](json& d) { d["nodes"][1]["weights"] = { 0.5, 0, 0 }; });
    },
    "/nodes/1/weights: 3 weights for 2 morph targets" },
  { "too few target names",
    [](Builder& b)
    { return Json(b, [](json& d) { d["meshes"][0]["extras"]["targetNames"] = { "Lift" }; }); },
    "/meshes/0/extras/targetNames: 1 names for 2 morph targets" },
  { "a target name that is a number",
    [](Builder& b)
    { return Json(b, [](json& d) { d["meshes"][0]["extras"]["targetNames"][1] = 7; }); },
    "/meshes/0/extras/targetNames/1: must be a string, got 7" },
  { "duplicate target names",
    [](Builder& b)
    { return Json(b, [](json& d) { d["meshes"][0]["extras"]["targetNames"][1] = "Lift"; }); },
    "/meshes/0/extras/targetNames/1: 'Lift' names target 0 already" },
  { "node cycle",
    [](Builder& b) { return Json(b, [](json& d) { d["nodes"][1]["children"] = { 0 }; }); },
    "is its own ancestor (the node hierarchy has a cycle)" },
  { "node with two parents",
    [](Builder& b) {
      return Json(b, [](json& d) { d["nodes"].push_back({ { "children", { 1 } } }); });
    },
    "/nodes/2/children/0: node 1 is already a child of node 0" },
  { "node its own child",
    [](Builder& b) { return Json(b, [](json& d) { d["nodes"][1]["children"] = { 1 }; }); },
    "/nodes/1/children/0: node 1 cannot be its own child" },
  { "scene root that is a child",
    [](Builder& b) { return Json(b, [](json& d) { d["scenes"][0]["nodes"] = { 1 }; }); },
    "/scenes/0/nodes/0: node 1 is a child of node 0, not a root" },
  { "missing scene", [](Builder& b) { return Json(b, [](json& d) { d["scene"] = 3; }); },
    "/scene: there is no scene 3" },
  { "base colour out of range",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][0] = 2; });
    },
    "/materials/0/pbrMetallicRoughness/baseColorFactor/0: must lie in [0, 1]" },
  { "missing material",
    [](Builder& b)
    { return Json(b, [](json& d) { d["meshes"][0]["primitives"][0]["material"] = 1; }); },
    "/meshes/0/primitives/0/material: there is no material 1" },
  // Animations.
  { "key times going back",
    [](Builder& b)
    {
      Poke<float>(b, ViewOffset(b, 8) + 8, 0.25f);
      return b.Glb();
    },
    "/accessors/7: key time 2 (0.25 s, input of /animations/0/samplers/0) is earlier than the key "
    "before it" },
  { "negative key time",
    [](Builder& b)
    {
      Poke<float>(b, ViewOffset(b, 8), -1.0f);
      return b.Glb();
    },
    "/accessors/7: key time 0 (-1 s, input of /animations/0/samplers/0) is negative" },
  { "weights output of the wrong count",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][9]["count"] = 3; }); },
    "/animations/0/samplers/1/output: 3 output elements, but 3 keys of weights (2 morph targets) "
    "need 6" },
  { "CUBICSPLINE without tangents",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["animations"][0]["samplers"][0]["interpolation"] = "CUBICSPLINE"; });
    },
    "/animations/0/samplers/0/output: accessor 8 has 3 elements, not a multiple of 9" },
  { "unknown interpolation",
    [](Builder& b) {
      return Json(
        b, [](json& d) { d["animations"][0]["samplers"][0]["interpolation"] = "SMOOTH"; });
    },
    "/animations/0/samplers/0/interpolation: 'SMOOTH' is not LINEAR, STEP or CUBICSPLINE" },
  { "channel to a missing node",
    [](Builder& b)
    { return Json(b, [](json& d) { d["animations"][0]["channels"][0]["target"]["node"] = 5; }); },
    "/animations/0/channels/0/target/node: there is no node 5" },
  { "channel to a missing sampler",
    [](Builder& b)
    { return Json(b, [](json& d) { d["animations"][0]["channels"][0]["sampler"] = 2; }); },
    "/animations/0/channels/0/sampler: there is no sampler 2 (the animation has 2)" },
  { "rotation from a VEC3",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["animations"][0]["channels"][0]["target"]["path"] = "translation"; });
    },
    "/animations/0/samplers/0/output: is VEC4 of FLOAT, but channel 0 animates translation" },
  { "weights of a node without targets",
    [](Builder& b)
    { return Json(b, [](json& d) { d["animations"][0]["channels"][1]["target"]["node"] = 0; }); },
    "/animations/0/channels/1/target/node: node 0 has no mesh with morph targets" },
  { "two channels on one path",
    [](Builder& b)
    {
      return Json(
        b, [](json& d) { d["animations"][0]["channels"][1] = d["animations"][0]["channels"][0]; });
    },
    "/animations/0/channels/1/target: node 1's rotation is animated by an earlier channel too" },
  { "key times as integers",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][7]["componentType"] = 5123; }); },
    "/animations/0/samplers/0/input: accessor 7 is SCALAR of UNSIGNED_SHORT; key times must be "
    "SCALAR of FLOAT" },
  // The container.
  { "truncated GLB",
    [](Builder& b)
    {
      std::string g = b.Glb();
      return g.substr(0, g.size() - 10);
    },
    "GLB: the header gives a length of" },
  { "truncated GLB, length patched",
    [](Builder& b)
    {
      std::string g = b.Glb();
      g.resize(g.size() - 12);
      const uint32_t n = static_cast<uint32_t>(g.size());
      std::memcpy(&g[8], &n, 4);
      return g;
    },
    "GLB: chunk 1 at byte" },
  { "BIN chunk and buffer claiming the chunk header's 8 bytes more (tinygltf reads past the input)",
    [](Builder& b)
    {
      std::string g = Json(b,
        [](json& d)
        { d["buffers"][0]["byteLength"] = d["buffers"][0]["byteLength"].get<int>() + 8; });
      uint32_t jsonLength;
      std::memcpy(&jsonLength, &g[12], 4);
      uint32_t binLength;
      std::memcpy(&binLength, &g[20 + jsonLength], 4);
      binLength += 8;
      std::memcpy(&g[20 + jsonLength], &binLength, 4);
      return g;
    },
    "runs past the end of the file" },
  { "GLB header only", [](Builder&) { return std::string("glTF\x02\0\0\0\x0c\0\0\0", 12); },
    "GLB: the file has no JSON chunk" },
  { "GLB version 1",
    [](Builder& b)
    {
      std::string g = b.Glb();
      g[4] = 1;
      return g;
    },
    "GLB: version 1 is not supported" },
  { "JSON chunk of another type",
    [](Builder& b)
    {
      std::string g = b.Glb();
      g[16] = 'X';
      return g;
    },
    "GLB: the first chunk must be JSON" },
  { "BIN chunk length not a multiple of 4",
    [](Builder& b)
    {
      b.Bin.push_back(1);
      b.Doc["buffers"] = json::array({ { { "byteLength", b.Bin.size() } } });
      json doc = b.Finished();
      return Builder::MakeGlb(doc.dump(), b.Bin);
    },
    "GLB: the BIN chunk's length" },
  { "empty input", [](Builder&) { return std::string(); }, "is neither a GLB nor glTF JSON" },
  { "not JSON", [](Builder&) { return std::string("solid cube\nfacet normal 0 0 1\n"); },
    "is not valid glTF JSON" },
  { "deep nesting",
    [](Builder&)
    {
      return "{\"asset\":{\"version\":\"2.0\"},\"extras\":" + std::string(5000, '[') +
        std::string(5000, ']') + "}";
    },
    "nests deeper than 64 levels" },
  // JSON of the wrong types.
  { "accessors as an object",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"] = json::object(); }); },
    "/accessors: must be an array, got an object" },
  { "an accessor that is a number",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][2] = 5; }); },
    "/accessors/2: must be an object, got 5" },
  { "attributes as an array",
    [](Builder& b) {
      return Json(
        b, [](json& d) { d["meshes"][0]["primitives"][0]["attributes"] = json::array(); });
    },
    "/meshes/0/primitives/0/attributes: must be an object, got an array" },
  { "a name that is a number",
    [](Builder& b) { return Json(b, [](json& d) { d["nodes"][0]["name"] = 5; }); },
    "/nodes/0/name: must be a string, got 5" },
  { "scene as a string", [](Builder& b) { return Json(b, [](json& d) { d["scene"] = "0"; }); },
    "/scene: must be an integer, got the string '0'" },
  { "type as a number",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][0]["type"] = 3; }); },
    "/accessors/0/type: must be a string, got 3" },
  { "normalized as a string",
    [](Builder& b) { return Json(b, [](json& d) { d["accessors"][2]["normalized"] = "yes"; }); },
    "/accessors/2/normalized: must be true or false" },
  { "translation of two numbers",
    [](Builder& b) {
      return Json(b, [](json& d) { d["nodes"][1]["translation"] = { 1, 2 }; });
    },
    "/nodes/1/translation: must have 3 numbers, got 2" },
  { "children as a number",
    [](Builder& b) { return Json(b, [](json& d) { d["nodes"][0]["children"] = 1; }); },
    "/nodes/0/children: must be an array, got 1" },
  { "asset missing", [](Builder& b) { return Json(b, [](json& d) { d.erase("asset"); }); },
    "/: 'asset' is missing" },
  { "glTF 1.0", [](Builder& b) { return Json(b, [](json& d) { d["asset"]["version"] = "1.0"; }); },
    "/asset/version: glTF '1.0' is not supported" },
  { "root is an array", [](Builder&) { return std::string("[1, 2, 3]"); },
    "/: the glTF document must be a JSON object" },
  { "Draco required",
    [](Builder& b)
    {
      return Json(b,
        [](json& d)
        {
          d["extensionsUsed"] = { "KHR_draco_mesh_compression" };
          d["extensionsRequired"] = { "KHR_draco_mesh_compression" };
        });
    },
    "/extensionsRequired/0: the file requires the extension 'KHR_draco_mesh_compression'" },
  { "bad base64",
    [](Builder& b)
    {
      json doc = json::parse(b.GltfWithDataUri());
      std::string uri = doc["buffers"][0]["uri"];
      uri[50] = '*';
      doc["buffers"][0]["uri"] = uri;
      return doc.dump();
    },
    "/buffers/0/uri: the data URI is not valid base64" },
  { "data URI shorter than byteLength",
    [](Builder& b)
    {
      json doc = json::parse(b.GltfWithDataUri());
      doc["buffers"][0]["byteLength"] = doc["buffers"][0]["byteLength"].get<int>() + 1;
      return doc.dump();
    },
    "/buffers/0/uri: the data URI holds" },
  { "image with a missing buffer view",
    [](Builder& b)
    {
      return Json(b,
        [](json& d) {
          d["images"] = { { { "bufferView", 40 }, { "mimeType", "image/png" } } };
        });
    },
    "/images/0/bufferView: there is no bufferView 40" },
};

INSTANTIATE_TEST_SUITE_P(Cases, GltfDamage, ::testing::ValuesIn(Damages),
  [](const ::testing::TestParamInfo<Damage>& info)
  {
    std::string name;
    for (const char* c = info.param.Name; *c; ++c)
    {
      name += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
    }
    return name;
  });

TEST(GltfScene, DecodedSizeIsBoundedBeforeDecoding)
{
  // A 1 kB file declaring a 100-million-point POSITION (sparse without bufferView: zeros).
  Builder b = gltftest::Quad();
  b.Doc.erase("animations");
  const int huge = b.SparseVec3(99999999, { 5 }, { 1, 2, 3 });
  auto& prim = b.Doc["meshes"][0]["primitives"][0];
  prim["attributes"] = { { "POSITION", huge } };
  prim.erase("indices");
  prim.erase("targets");
  b.Doc["meshes"][0].erase("weights");
  b.Doc["meshes"][0].erase("extras");
  GltfLoadOptions options;
  options.MaxDecodedBytes = 64 << 20;
  const std::string message = ErrorOf(b.Glb(), options);
  EXPECT_NE(message.find("the scene would take 16"), std::string::npos) << message;
  EXPECT_NE(message.find("MaxDecodedBytes"), std::string::npos) << message;
  // And a mesh instanced on many nodes counts once per node.
  Builder many = gltftest::Quad();
  many.Doc.erase("animations");
  for (int i = 0; i < 100; ++i)
  {
    many.Doc["nodes"][0]["children"].push_back(many.Node({ { "mesh", 0 } }));
  }
  options.MaxDecodedBytes = 20000;
  EXPECT_NE(ErrorOf(many.Glb(), options).find("MaxDecodedBytes"), std::string::npos);
  options.MaxDecodedBytes = 1 << 20;
  EXPECT_EQ(Load(many.Glb(), options).Parts.size(), 101u);
}

TEST(GltfScene, MissingFileIsAnInputError)
{
  EXPECT_THROW(LoadGltfScene("/nonexistent/face.glb"), InputError);
}

TEST(GltfScene, FuzzSeedsLoadAndDamagedOnesAreRejected)
{
  // The seed corpus of FuzzGltf (Testing/Fuzz/tools/MakeGltfSeeds.cpp): good seeds must
  // reach the end of the loader, the damaged ones (regression inputs) must be refused.
  const std::filesystem::path folder =
    std::filesystem::path(MORPHNODE_SOURCE_DIR) / "Testing/Fuzz/corpus/gltf";
  size_t good = 0, damaged = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
  {
    const std::string name = entry.path().filename().string();
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (name.rfind("damaged-", 0) == 0 || name.rfind("crash-", 0) == 0)
    {
      EXPECT_FALSE(ErrorOf(bytes).empty()) << name;
      ++damaged;
    }
    else if (name.rfind("found-", 0) != 0)
    {
      EXPECT_FALSE(Load(bytes).Parts.empty()) << name;
      ++good;
    }
  }
  EXPECT_GE(good, 8u);
  EXPECT_GE(damaged, 4u);
}

TEST(GltfScene, PartAsMorphMesh)
{
  const GltfScene scene = Load(gltftest::Quad().Glb());
  const morphnode::MorphMesh mesh = morphnode::GltfPartToMorphMesh(scene.Parts[0]);
  EXPECT_EQ(mesh.GetNumberOfPoints(), 4u);
  EXPECT_EQ(mesh.GetTargetNames(), (std::vector<std::string>{ "Neutral", "Lift", "Raise" }));
  EXPECT_EQ(mesh.FindTarget("Raise"), 2);
  EXPECT_EQ(mesh.GetTriangles(), scene.Parts[0].Triangles);
  ASSERT_EQ(mesh.GetNumberOfAttributes(), 2u);
  const auto& positions = std::get<morphnode::MorphAttribute<float>>(mesh.GetAttribute(0));
  EXPECT_EQ(positions.GetNeutral(), scene.Parts[0].Positions);
  std::vector<float> dense(12);
  positions.GetTarget(2).ToDense(dense.data());
  EXPECT_EQ(dense, scene.Parts[0].Targets[1].PositionDeltas);
  // Blending "Raise" at 1 moves point 2 by its delta.
  std::vector<float> out(12);
  const double weights[] = { 0, 0, 1 };
  positions.Blend(weights, 3, out.data(), 0, 4);
  EXPECT_NEAR(out[6], scene.Parts[0].Positions[6] - 0.25f, 1e-6);
  const auto& normals = std::get<morphnode::MorphAttribute<float>>(mesh.GetAttribute(1));
  EXPECT_EQ(normals.GetRole(), morphnode::AttributeRole::Normal);
}

TEST(GltfScene, NamesOfNamelessNodesMeshesAndAnimations)
{
  morphnode::GltfScene scene;
  scene.Nodes.resize(3);
  scene.Nodes[2].Name = "Jaw";
  scene.Meshes.resize(2);
  scene.Meshes[0].Name = "Face";
  scene.Animations.resize(2);
  scene.Animations[1].Name = "Talk";
  EXPECT_EQ(morphnode::GltfNodeName(scene, 0), "node0");
  EXPECT_EQ(morphnode::GltfNodeName(scene, 2), "Jaw");
  EXPECT_EQ(morphnode::GltfMeshName(scene, 0), "Face");
  EXPECT_EQ(morphnode::GltfMeshName(scene, 1), "mesh1");
  EXPECT_EQ(morphnode::GltfAnimationName(scene, 0), "animation0");
  EXPECT_EQ(morphnode::GltfAnimationName(scene, 1), "Talk");
  EXPECT_THROW(morphnode::GltfNodeName(scene, 3), std::out_of_range);
}
