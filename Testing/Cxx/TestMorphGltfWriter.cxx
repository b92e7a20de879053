// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphGltfWriter, round trip against an implementation MorphNode did not write: the
// default head and the ICT head (whole scenes read by vtkMorphTargetReader) exported with a
// random performance (weights of every target, head pose, eye turns) and read back by VTK
// 9.1's vtkGLTFReader (ApplyDeformationsToGeometry, the animation at several times) give
// the geometry of the pipeline that wrote them (vtkMorphNodeFilter with the weights at that
// time, the eyes turned about their NodeOrigin, the head about HeadPivot), to 1e-6 of the
// head's size. The optimizer's weights written equal vtkMorphNodeFilter's effective
// weights frame by frame; bad input is an error and leaves no file.
#include "vtkEyeGazeFilter.h"
#include "vtkMorphGltfWriter.h"
#include "vtkMorphNodeFilter.h"
#include "vtkMorphSkinFilter.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeMergeParts.h"

#include "behavior/HeadPose.h"
#include "gltf/GltfAnimation.h"
#include "gltf/GltfScene.h"

#include "vtkCompositeDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkGLTFReader.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include <nlohmann/json.hpp>

#include "MorphNodeTestData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <set>

namespace
{
const std::string DefaultHead =
  std::string(MORPHNODE_SOURCE_DIR) + "/Data/DefaultFace/default_head.glb";
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";
const std::string Avatar = morphnode_test::AvatarFile();

/// The validator test's folder (MORPHNODE_GLTF_EXPORT_DIR) when it runs this program, else
/// the test output folder.
std::string OutputPath(const std::string& name)
{
  const char* env = std::getenv("MORPHNODE_GLTF_EXPORT_DIR");
  const std::string dir =
    env && *env ? std::string(env) : std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/gltf-vtk";
  std::filesystem::create_directories(dir);
  return dir + "/" + name;
}

std::vector<std::string> SceneTargets(vtkDataObject* head)
{
  std::vector<std::string> names;
  for (vtkPolyData* leaf : morphnode_test::PolyDataLeaves(head))
  {
    auto* a = vtkStringArray::SafeDownCast(leaf->GetFieldData()->GetAbstractArray("TargetNames"));
    for (vtkIdType i = 1; a && i < a->GetNumberOfValues(); ++i)
    {
      if (std::find(names.begin(), names.end(), a->GetValue(i)) == names.end())
      {
        names.push_back(a->GetValue(i));
      }
    }
  }
  return names;
}

vtkSmartPointer<vtkTable> RandomPerformance(
  const std::vector<std::string>& targets, int frames, unsigned seed, bool pose)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto table = vtkSmartPointer<vtkTable>::New();
  std::vector<std::string> columns{ "Time" };
  columns.insert(columns.end(), targets.begin(), targets.end());
  if (pose)
  {
    for (const char* c : { "HeadYaw", "HeadPitch", "HeadRoll", "EyeYaw", "EyePitch" })
    {
      columns.emplace_back(c);
    }
  }
  columns.emplace_back("NotATarget"); // ignored
  for (const auto& name : columns)
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfTuples(frames);
    for (int f = 0; f < frames; ++f)
    {
      double v = u(rng) < 0.35 ? u(rng) : 0.0;
      if (name == "Time")
      {
        v = f / 30.0;
      }
      else if (name == "HeadYaw" || name == "HeadPitch" || name == "HeadRoll")
      {
        v = 30.0 * (u(rng) - 0.5); // degrees
      }
      else if (name == "EyeYaw" || name == "EyePitch")
      {
        v = 100.0 * (u(rng) - 0.5); // degrees, often beyond the eyes' limits
      }
      a->SetValue(f, v);
    }
    table->AddColumn(a);
  }
  return table;
}

double Column(vtkTable* t, const std::string& name, double time)
{
  auto* a = vtkDataArray::SafeDownCast(t->GetColumnByName(name.c_str()));
  auto* times = vtkDataArray::SafeDownCast(t->GetColumnByName("Time"));
  if (!a)
  {
    return 0.0;
  }
  const vtkIdType n = t->GetNumberOfRows();
  if (time <= times->GetComponent(0, 0))
  {
    return a->GetComponent(0, 0);
  }
  for (vtkIdType k = 0; k + 1 < n; ++k)
  {
    const double t0 = times->GetComponent(k, 0);
    const double t1 = times->GetComponent(k + 1, 0);
    if (time <= t1)
    {
      const double s = (time - t0) / (t1 - t0);
      return (1 - s) * a->GetComponent(k, 0) + s * a->GetComponent(k + 1, 0);
    }
  }
  return a->GetComponent(n - 1, 0);
}

/// A copy of a GLB that VTK 9.1 reads right: sparse accessors without bufferView (zeros as
/// their base, as the glTF spec defines) get an explicit all-zero buffer view with
/// byteOffset 0 (VTK 9.1 does not zero-fill them; see TestMorphNodeGLTFCrossCheck).
std::string PatchForVtk(const std::string& file)
{
  std::ifstream in(file, std::ios::binary);
  std::vector<char> glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto u32 = [&glb](size_t at)
  {
    uint32_t v;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  const uint32_t jsonLength = u32(12);
  nlohmann::json doc = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLength);
  const size_t binAt = 20 + jsonLength + 8;
  std::vector<char> bin(glb.begin() + static_cast<long>(binAt),
    glb.begin() + static_cast<long>(binAt + u32(20 + jsonLength)));
  size_t zeroBytes = 4;
  for (const auto& a : doc["accessors"])
  {
    if (!a.contains("bufferView"))
    {
      zeroBytes = std::max(zeroBytes, 12 * a["count"].get<size_t>());
    }
  }
  const size_t zeroAt = bin.size();
  bin.resize(zeroAt + zeroBytes, 0);
  doc["bufferViews"].push_back(
    { { "buffer", 0 }, { "byteOffset", zeroAt }, { "byteLength", zeroBytes } });
  const size_t zeroView = doc["bufferViews"].size() - 1;
  for (auto& a : doc["accessors"])
  {
    if (!a.contains("bufferView"))
    {
      a["bufferView"] = zeroView;
      a["byteOffset"] = 0;
    }
  }
  doc["buffers"][0]["byteLength"] = bin.size();
  std::string json = doc.dump();
  json.append((4 - json.size() % 4) % 4, ' ');
  std::vector<char> out;
  auto put = [&out](uint32_t v)
  {
    const char* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + 4);
  };
  put(0x46546C67);
  put(2);
  put(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put(static_cast<uint32_t>(json.size()));
  put(0x4E4F534A);
  out.insert(out.end(), json.begin(), json.end());
  put(static_cast<uint32_t>(bin.size()));
  put(0x004E4942);
  out.insert(out.end(), bin.begin(), bin.end());
  // Not beside the export (the validator checks every file there, and this copy is
  // VTK's), but in a sibling folder of its own, so that this test and the validator's run
  // of it, which may run at the same time, never share a file.
  const std::filesystem::path exported(file);
  const std::filesystem::path folder = exported.parent_path().string() + "-for-vtk";
  std::filesystem::create_directories(folder);
  const std::string path = (folder / exported.filename()).string();
  std::ofstream(path, std::ios::binary).write(out.data(), static_cast<std::streamsize>(out.size()));
  return path;
}

std::array<double, 3> Apply(const std::array<double, 16>& m, const double p[3])
{
  std::array<double, 3> r{};
  for (int i = 0; i < 3; ++i)
  {
    r[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3];
  }
  return r;
}

/// Exports `file` with a random performance and compares VTK's reading of the export at
/// `times` with the pipeline: the morph filter, the eyes' and the head's turns.
void RoundTrip(
  const std::string& file, const std::string& out, bool pose, const std::vector<double>& times)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkDataObject* head = reader->GetOutputDataObject(0);
  const auto leaves = morphnode_test::PolyDataLeaves(head);
  const std::vector<std::string> targets = SceneTargets(head);
  ASSERT_GT(targets.size(), 5u);
  vtkSmartPointer<vtkTable> performance = RandomPerformance(targets, 12, 7, pose);

  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetPerformanceData(performance);
  writer->SetFileName(OutputPath(out).c_str());
  ASSERT_EQ(writer->Write(), 1);
  ASSERT_EQ(writer->GetErrorCode(), vtkErrorCode::NoError);
  EXPECT_EQ(writer->GetNumberOfFrames(), 12);
  EXPECT_EQ(writer->GetNumberOfWeightColumns(), static_cast<int>(targets.size()));
  EXPECT_EQ(writer->GetNumberOfParts(), static_cast<int>(leaves.size()));

  double bounds[6] = { 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 };
  for (vtkPolyData* leaf : leaves)
  {
    double b[6];
    leaf->GetBounds(b);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
    }
  }
  const double size = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const std::array<double, 3> pivot = morphnode::HeadPivot(bounds);

  {
    // Head pose and both eyes as rotation channels, weights on every mesh with targets.
    const morphnode::GltfScene written = morphnode::LoadGltfScene(OutputPath(out));
    int rotations = 0;
    for (const auto& c : written.Animations.at(0).Channels)
    {
      rotations += c.Path == morphnode::GltfAnimationPath::Rotation ? 1 : 0;
    }
    EXPECT_EQ(rotations, pose ? 3 : 0);
  }
  const std::string forVtk = PatchForVtk(OutputPath(out));

  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  vtkNew<vtkEyeGazeFilter> gaze;
  gaze->SetInputConnection(morph->GetOutputPort());
  for (double t : times)
  {
    SCOPED_TRACE("t = " + std::to_string(t));
    // A reader per time: VTK 9.1's vtkGLTFReader builds the leaves of a mesh with several
    // primitives wrongly when an animated file is updated a second time (every primitive
    // gets the last one's geometry).
    vtkNew<vtkGLTFReader> gltf;
    gltf->SetFileName(forVtk.c_str());
    gltf->SetApplyDeformationsToGeometry(true);
    gltf->UpdateInformation();
    ASSERT_EQ(gltf->GetNumberOfAnimations(), 1);
    gltf->EnableAnimation(0);
    gltf->UpdateTimeStep(t);
    const auto back = morphnode_test::PolyDataLeaves(gltf->GetOutput());
    ASSERT_EQ(back.size(), leaves.size());
    for (const auto& name : targets)
    {
      morph->SetWeightByName(name.c_str(), Column(performance, name, t));
    }
    // The eyes as the gaze filter turns them (then the head, as the avatar's actor does).
    gaze->SetEyeYaw(pose ? Column(performance, "EyeYaw", t) : 0.0);
    gaze->SetEyePitch(pose ? Column(performance, "EyePitch", t) : 0.0);
    gaze->Update();
    const auto morphed = morphnode_test::PolyDataLeaves(gaze->GetOutputDataObject(0));
    ASSERT_EQ(morphed.size(), leaves.size());
    morphnode::HeadAngles headAngles;
    if (pose)
    {
      headAngles = { Column(performance, "HeadYaw", t), Column(performance, "HeadPitch", t),
        Column(performance, "HeadRoll", t) };
    }
    const auto headPose = morphnode::HeadPoseMatrix(headAngles, pivot);
    double largest = 0.0;
    for (size_t i = 0; i < leaves.size(); ++i)
    {
      vtkPolyData* expected = morphed[i];
      vtkPolyData* actual = back[i];
      ASSERT_EQ(expected->GetNumberOfPoints(), actual->GetNumberOfPoints()) << i;
      for (vtkIdType p = 0; p < expected->GetNumberOfPoints(); ++p)
      {
        double x[3];
        expected->GetPoint(p, x);
        const auto w = Apply(headPose, x);
        double y[3];
        actual->GetPoint(p, y);
        const double d = std::sqrt((w[0] - y[0]) * (w[0] - y[0]) + (w[1] - y[1]) * (w[1] - y[1]) +
          (w[2] - y[2]) * (w[2] - y[2]));
        largest = std::max(largest, d);
      }
    }
    EXPECT_LT(largest, 1e-6 * size)
      << "largest difference " << largest << " of a head of size " << size;
    std::cout << out << " t = " << t << ": largest difference " << largest << " (head size " << size
              << ")\n";
  }
}
} // namespace

TEST(MorphGltfWriter, DefaultHeadRoundTripThroughVtkGltfReader)
{
  // Between keys only weights (glTF interpolates rotations by slerp, the behaviour its
  // angles linearly): with pose, the keys; without, keys and between them.
  RoundTrip(DefaultHead, "default_head_pose.glb", true, { 0.0, 1.0 / 30, 5.0 / 30, 11.0 / 30 });
  RoundTrip(DefaultHead, "default_head_weights.glb", false,
    { 0.0, 0.5 / 30, 3.7 / 30, 10.2 / 30, 11.0 / 30 });
}

TEST(MorphGltfWriter, IctHeadRoundTripThroughVtkGltfReader)
{
  if (!std::filesystem::exists(IctHead))
  {
    GTEST_SKIP() << "ICT-FaceKit not found: " << IctHead;
  }
  RoundTrip(IctHead, "ict_head_pose.glb", true, { 0.0, 2.0 / 30, 7.0 / 30 });
  RoundTrip(IctHead, "ict_head_weights.glb", false, { 1.5 / 30, 6.25 / 30 });
}

TEST(MorphGltfWriter, OptimizedWeightsAreTheFiltersEffectiveWeights)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultHead.c_str());
  reader->Update();
  const std::vector<std::string> targets = SceneTargets(reader->GetOutputDataObject(0));
  vtkSmartPointer<vtkTable> performance = RandomPerformance(targets, 20, 11, false);
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetPerformanceData(performance);
  writer->ApplyOptimizerOn();
  writer->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_ADJUSTED);
  writer->SetThreshold(0.3);
  writer->SetHysteresis(0.2);
  writer->SetInterpolationToStep();
  const std::string file = OutputPath("default_head_optimized.glb");
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);

  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  morph->SetThreshold(0.3);
  morph->SetHysteresis(0.2);
  morph->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_ADJUSTED);
  const morphnode::GltfScene back = morphnode::LoadGltfScene(file);
  ASSERT_EQ(back.Animations.size(), 1u);
  int pruned = 0;
  for (vtkIdType f = 0; f < performance->GetNumberOfRows(); ++f)
  {
    for (const auto& name : targets)
    {
      morph->SetWeightByName(name.c_str(), Column(performance, name, f / 30.0));
    }
    morph->Update();
    for (const auto& c : back.Animations[0].Channels)
    {
      const auto& mesh =
        back.Meshes[static_cast<size_t>(back.Nodes[static_cast<size_t>(c.Node)].Mesh)];
      const auto& sampler = back.Animations[0].Samplers[static_cast<size_t>(c.Sampler)];
      EXPECT_EQ(sampler.Interpolation, morphnode::GltfInterpolation::Step);
      for (size_t t = 0; t < mesh.TargetNames.size(); ++t)
      {
        const double effective =
          morph->GetEffectiveWeight(morph->GetTargetIndex(mesh.TargetNames[t].c_str()));
        const double written = sampler.Values[static_cast<size_t>(f) * mesh.TargetNames.size() + t];
        EXPECT_NEAR(written, effective, 1e-6) << mesh.TargetNames[t] << " frame " << f;
        pruned +=
          (effective == 0.0 && Column(performance, mesh.TargetNames[t], f / 30.0) != 0.0) ? 1 : 0;
      }
    }
  }
  EXPECT_GT(pruned, 0) << "the optimizer must have pruned something for this test to say anything";
}

TEST(MorphGltfWriter, GltfJsonAndStaticHead)
{
  // A .gltf is JSON (the buffer embedded); without a performance, no animation.
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultHead.c_str());
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  const std::string file = OutputPath("default_head_static.gltf");
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_FALSE(j.contains("animations"));
  EXPECT_EQ(j["meshes"].size(), 11u); // the default head's nodes with meshes
  const morphnode::GltfScene back = morphnode::LoadGltfScene(file);
  EXPECT_EQ(back.Parts.size(), 15u);
  EXPECT_EQ(writer->GetNumberOfFrames(), 0);
}

TEST(MorphGltfWriter, BadInput)
{
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(DefaultHead.c_str());
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->GlobalWarningDisplayOff();
  // No file name.
  writer->Write();
  EXPECT_NE(writer->GetErrorCode(), vtkErrorCode::NoError);

  // Times that do not increase: an error, no file.
  reader->Update();
  vtkSmartPointer<vtkTable> performance =
    RandomPerformance(SceneTargets(reader->GetOutputDataObject(0)), 5, 3, true);
  vtkDataArray::SafeDownCast(performance->GetColumnByName("Time"))->SetComponent(3, 0, 0.0);
  const std::string file = OutputPath("bad.glb");
  std::filesystem::remove(file);
  writer->SetFileName(file.c_str());
  writer->SetPerformanceData(performance);
  writer->Write();
  EXPECT_EQ(writer->GetErrorCode(), vtkErrorCode::UserError);
  EXPECT_FALSE(std::filesystem::exists(file));
  EXPECT_FALSE(std::filesystem::exists(file + ".part"));

  // NaN weight.
  performance = RandomPerformance(SceneTargets(reader->GetOutputDataObject(0)), 5, 3, false);
  vtkDataArray::SafeDownCast(performance->GetColumn(1))->SetComponent(2, 0, std::nan(""));
  writer->SetPerformanceData(performance);
  writer->Write();
  EXPECT_EQ(writer->GetErrorCode(), vtkErrorCode::UserError);
  EXPECT_FALSE(std::filesystem::exists(file));

  // No time column.
  performance->RemoveColumnByName("Time");
  writer->Write();
  EXPECT_EQ(writer->GetErrorCode(), vtkErrorCode::UserError);

  // A leaf that is not poly data.
  vtkNew<vtkMultiBlockDataSet> blocks;
  vtkNew<vtkUnstructuredGrid> grid;
  blocks->SetBlock(0, grid);
  vtkNew<vtkMorphGltfWriter> other;
  other->GlobalWarningDisplayOff();
  other->SetInputData(blocks);
  other->SetFileName(file.c_str());
  other->Write();
  EXPECT_EQ(other->GetErrorCode(), vtkErrorCode::UserError);
  EXPECT_FALSE(std::filesystem::exists(file));

  // Unwritable folder.
  vtkNew<vtkMorphGltfWriter> nowhere;
  nowhere->GlobalWarningDisplayOff();
  nowhere->SetInputConnection(reader->GetOutputPort());
  nowhere->SetFileName("/nonexistent-folder/x.glb");
  nowhere->Write();
  EXPECT_EQ(nowhere->GetErrorCode(), vtkErrorCode::UserError);
}

// The skinned MakeHuman avatar (vtkMorphTargetReader: skinned parts at rest with the skin
// arrays) written with a performance: the file keeps the avatar's skeleton (the same nodes,
// none inserted), its skin (joints and inverse bind matrices), every part's joints and
// weights, its materials and images; the head pose and gaze are rotation channels on the
// Neck, Head and eye joints. Read back by VTK 9.1's vtkGLTFReader (which skins on the CPU)
// at a key, it equals the pipeline that plays the same frame: vtkMorphNodeFilter with the
// weights, then vtkMorphSkinFilter with the angles. GltfValidatorVtkExport validates it.
TEST(MorphGltfWriter, EyeLookWeightsMoveTheLidsNotTheEyeballsTheJointsTurn)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(Avatar.c_str());
  // Eyes looking down by their joints, and the rig's eyeLookDown* weights for the lids.
  vtkNew<vtkTable> performance;
  for (const char* name : { "Time", "eyeLookDownLeft", "eyeLookDownRight", "EyePitch" })
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->InsertNextValue(0.0);
    a->InsertNextValue(std::string(name) == "Time" ? 1.0
        : std::string(name) == "EyePitch"          ? -15.0
                                                   : 0.8);
    performance->AddColumn(a);
  }
  const std::string out = OutputPath("makehuman_avatar_eyelook_export.glb");
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetPerformanceData(performance);
  writer->SetFileName(out.c_str());
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_TRUE(writer->GetTurnsBones());
  const morphnode::GltfScene back = morphnode::LoadGltfScene(out);
  ASSERT_EQ(back.Animations.size(), 1u);
  std::map<std::string, float> lastLookDown; // node -> eyeLookDownLeft at the last key
  for (const auto& c : back.Animations[0].Channels)
  {
    if (c.Path != morphnode::GltfAnimationPath::Weights)
    {
      continue;
    }
    const auto& node = back.Nodes[static_cast<size_t>(c.Node)];
    const morphnode::GltfPart* part = nullptr;
    for (const auto& p : back.Parts)
    {
      part = p.Node == c.Node ? &p : part;
    }
    ASSERT_NE(part, nullptr);
    const auto& values = back.Animations[0].Samplers[static_cast<size_t>(c.Sampler)].Values;
    for (size_t t = 0; t < part->Targets.size(); ++t)
    {
      if (part->Targets[t].Name == "eyeLookDownLeft")
      {
        lastLookDown[node.Name] = values[values.size() - part->Targets.size() + t];
      }
    }
  }
  ASSERT_EQ(
    lastLookDown.count("Body") + lastLookDown.count("EyeLeft") + lastLookDown.count("EyeRight"),
    3u);
  EXPECT_FLOAT_EQ(lastLookDown["Body"], 0.8f) << "the lids do not follow";
  EXPECT_EQ(lastLookDown["EyeLeft"], 0.0f) << "the left eyeball turns twice";
  EXPECT_EQ(lastLookDown["EyeRight"], 0.0f) << "the right eyeball turns twice";
}

TEST(MorphGltfWriter, SkinnedAvatarKeepsItsSkeletonAndTurnsItsBones)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(Avatar.c_str());
  // The performance: 4 keys, a vowel, the head turned and the eyes looking left and down.
  const std::vector<std::string> names{ "Time", "jawOpen", "viseme_O", "eyeBlinkLeft", "HeadYaw",
    "HeadPitch", "HeadRoll", "EyeYaw", "EyePitch" };
  const std::vector<std::vector<double>> rows{ { 0.0, 0, 0, 0, 0, 0, 0, 0, 0 },
    { 0.4, 0.3, 0.5, 0.2, 10, 4, -3, 12, 5 }, { 0.8, 0.6, 1.0, 0.0, 20, -8, 5, 25, -10 },
    { 1.2, 0.0, 0.2, 0.7, -15, 6, 2, -20, 8 } };
  vtkNew<vtkTable> performance;
  for (size_t c = 0; c < names.size(); ++c)
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName(names[c].c_str());
    for (const auto& row : rows)
    {
      a->InsertNextValue(row[c]);
    }
    performance->AddColumn(a);
  }
  const std::string out = OutputPath("makehuman_avatar_vtk_export.glb");
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetPerformanceData(performance);
  writer->SetFileName(out.c_str());
  ASSERT_EQ(writer->Write(), 1);
  ASSERT_EQ(writer->GetErrorCode(), vtkErrorCode::NoError);
  EXPECT_TRUE(writer->GetTurnsBones());
  EXPECT_EQ(writer->GetNumberOfFrames(), 4);
  EXPECT_EQ(writer->GetNumberOfWeightColumns(), 3);

  // The skeleton, skin, influences, materials and images as the avatar has them.
  morphnode::GltfLoadOptions nodeFrames;
  nodeFrames.ApplyTransforms = false;
  const morphnode::GltfScene original = morphnode::LoadGltfScene(Avatar, nodeFrames);
  const morphnode::GltfScene back = morphnode::LoadGltfScene(out, nodeFrames);
  ASSERT_EQ(back.Nodes.size(), original.Nodes.size())
    << "nodes inserted into or lost from the skeleton";
  for (size_t n = 0; n < original.Nodes.size(); ++n)
  {
    EXPECT_EQ(back.Nodes[n].Name, original.Nodes[n].Name);
    EXPECT_EQ(back.Nodes[n].Parent, original.Nodes[n].Parent) << original.Nodes[n].Name;
  }
  ASSERT_EQ(back.Skins.size(), original.Skins.size());
  ASSERT_EQ(back.Skins.size(), 1u);
  ASSERT_EQ(back.Skins[0].Joints, original.Skins[0].Joints);
  for (size_t j = 0; j < original.Skins[0].Joints.size(); ++j)
  {
    for (size_t c = 0; c < 16; ++c)
    {
      EXPECT_NEAR(back.Skins[0].InverseBind[j][c], original.Skins[0].InverseBind[j][c], 1e-6)
        << "joint " << j;
    }
  }
  ASSERT_EQ(back.Parts.size(), original.Parts.size());
  double worstBind = 0.0;
  for (const auto& part : original.Parts)
  {
    const int k = back.FindPart(part.Name);
    ASSERT_GE(k, 0) << part.Name;
    const morphnode::GltfPart& other = back.Parts[static_cast<size_t>(k)];
    EXPECT_EQ(other.Skin, part.Skin) << part.Name;
    ASSERT_EQ(other.Influences.PerPoint, part.Influences.PerPoint) << part.Name;
    ASSERT_EQ(other.Influences.Weights.size(), part.Influences.Weights.size()) << part.Name;
    size_t differing = 0;
    for (size_t i = 0; i < part.Influences.Weights.size(); ++i)
    {
      differing += std::abs(other.Influences.Weights[i] - part.Influences.Weights[i]) > 1e-6 ||
        (part.Influences.Weights[i] > 0.0f &&
          other.Influences.Joints[i] != part.Influences.Joints[i]);
    }
    EXPECT_EQ(differing, 0u) << part.Name << ": joints or weights differ";
    EXPECT_EQ(other.Material, part.Material) << part.Name;
    ASSERT_EQ(other.Positions.size(), part.Positions.size());
    for (size_t i = 0; i < part.Positions.size(); ++i)
    {
      worstBind =
        std::max(worstBind, static_cast<double>(std::abs(other.Positions[i] - part.Positions[i])));
    }
  }
  EXPECT_LT(worstBind, 1e-6 * 1.666) << "bind-space points changed";
  EXPECT_EQ(back.Materials.size(), original.Materials.size());
  EXPECT_EQ(back.Images.size(), original.Images.size());

  // Rotation channels on the joints that turn, and only there.
  ASSERT_EQ(back.Animations.size(), 1u);
  std::set<std::string> turned;
  for (const auto& c : back.Animations[0].Channels)
  {
    if (c.Path == morphnode::GltfAnimationPath::Rotation)
    {
      turned.insert(back.Nodes[static_cast<size_t>(c.Node)].Name);
    }
  }
  EXPECT_EQ(turned, (std::set<std::string>{ "Neck", "Head", "LeftEye", "RightEye" }));

  // It plays: VTK's reading at the third key equals the pipeline's frame.
  const double t = rows[2][0];
  vtkNew<vtkGLTFReader> gltf;
  gltf->SetFileName(PatchForVtk(out).c_str());
  gltf->SetApplyDeformationsToGeometry(true);
  gltf->UpdateInformation();
  ASSERT_EQ(gltf->GetNumberOfAnimations(), 1);
  gltf->EnableAnimation(0);
  gltf->UpdateTimeStep(t);
  const auto theirs = morphnode_test::PolyDataLeaves(gltf->GetOutput());

  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  for (size_t c = 1; c <= 3; ++c)
  {
    morph->SetWeightByName(names[c].c_str(), rows[2][c]);
  }
  vtkNew<vtkMorphSkinFilter> skin;
  skin->SetInputConnection(morph->GetOutputPort());
  skin->SetHeadYaw(rows[2][4]);
  skin->SetHeadPitch(rows[2][5]);
  skin->SetHeadRoll(rows[2][6]);
  skin->SetEyeYaw(rows[2][7]);
  skin->SetEyePitch(rows[2][8]);
  skin->Update();
  const auto ours = morphnode_test::PolyDataLeaves(skin->GetOutputDataObject(0));
  reader->Update();
  const auto rest = morphnode_test::PolyDataLeaves(reader->GetOutputDataObject(0));
  ASSERT_EQ(theirs.size(), ours.size());
  ASSERT_EQ(rest.size(), ours.size());
  double worst = 0.0;
  double moved = 0.0;
  for (size_t i = 0; i < ours.size(); ++i)
  {
    ASSERT_EQ(theirs[i]->GetNumberOfPoints(), ours[i]->GetNumberOfPoints()) << i;
    for (vtkIdType p = 0; p < ours[i]->GetNumberOfPoints(); ++p)
    {
      double a[3], b[3], r[3];
      ours[i]->GetPoint(p, a);
      theirs[i]->GetPoint(p, b);
      rest[i]->GetPoint(p, r);
      worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
      moved = std::max(moved, std::sqrt(vtkMath::Distance2BetweenPoints(a, r)));
    }
  }
  std::cout << "skinned avatar export at t = " << t << ": largest difference to vtkGLTFReader "
            << worst * 1e3 << " mm; the frame moves points up to " << moved * 1e3
            << " mm from rest\n";
  EXPECT_GT(moved, 0.01) << "the frame does not move the avatar: the check could not fail";
  EXPECT_LT(worst, 1e-6 * 1.666);

  // Our own reader plays it too (the animation's joint rotations and weights applied).
  vtkNew<vtkMorphTargetReader> again;
  again->SetFileName(out.c_str());
  again->SetAnimationIndex(0);
  again->SetApplyAnimation(vtkMorphTargetReader::ANIMATION_TRANSFORMS_AND_WEIGHTS);
  again->UpdateTimeStep(t);
  const auto played = morphnode_test::PolyDataLeaves(again->GetOutputDataObject(0));
  ASSERT_EQ(played.size(), ours.size());
  double worstOurs = 0.0;
  for (size_t i = 0; i < ours.size(); ++i)
  {
    ASSERT_EQ(played[i]->GetNumberOfPoints(), ours[i]->GetNumberOfPoints()) << i;
    for (vtkIdType p = 0; p < ours[i]->GetNumberOfPoints(); ++p)
    {
      double a[3], b[3];
      ours[i]->GetPoint(p, a);
      played[i]->GetPoint(p, b);
      worstOurs = std::max(worstOurs, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
    }
  }
  std::cout << "vtkMorphTargetReader playing the export: largest difference " << worstOurs * 1e3
            << " mm\n";
  EXPECT_LT(worstOurs, 1e-6 * 1.666);
}

// The relaxed arms the window shows are what the export writes: the upper arm joints' node
// rotations, so that VTK's vtkGLTFReader and our reader show the avatar at rest with its
// arms down, at the points vtkMorphSkinFilter's RelaxArms gives.
TEST(MorphGltfWriter, SkinnedAvatarExportKeepsTheRelaxedArms)
{
  MORPHNODE_SKIP_WITHOUT_AVATAR(Avatar);
  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(Avatar.c_str());
  const std::string out = OutputPath("makehuman_avatar_relaxed_arms.glb");
  vtkNew<vtkMorphGltfWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetRelaxArms(true);
  writer->SetFileName(out.c_str());
  ASSERT_EQ(writer->Write(), 1);
  ASSERT_EQ(writer->GetErrorCode(), vtkErrorCode::NoError);
  EXPECT_EQ(writer->GetNumberOfRelaxedArms(), 2);

  // The display: the stored (T- or A-) pose with the arms relaxed.
  vtkNew<vtkMorphSkinFilter> skin;
  skin->SetInputConnection(reader->GetOutputPort());
  skin->SetRelaxArms(true);
  skin->Update();
  const auto shown = morphnode_test::PolyDataLeaves(skin->GetOutputDataObject(0));
  const auto stored = morphnode_test::PolyDataLeaves(reader->GetOutputDataObject(0));

  vtkNew<vtkGLTFReader> gltf;
  gltf->SetFileName(PatchForVtk(out).c_str());
  gltf->SetApplyDeformationsToGeometry(true);
  gltf->Update();
  const auto theirs = morphnode_test::PolyDataLeaves(gltf->GetOutput());
  vtkNew<vtkMorphTargetReader> again;
  again->SetFileName(out.c_str());
  again->Update();
  const auto ours = morphnode_test::PolyDataLeaves(again->GetOutputDataObject(0));
  ASSERT_EQ(theirs.size(), shown.size());
  ASSERT_EQ(ours.size(), shown.size());
  ASSERT_EQ(stored.size(), shown.size());

  // An arm vertex: the body's point farthest out to the side as stored (a fingertip).
  size_t body = 0;
  for (size_t i = 0; i < shown.size(); ++i)
  {
    body = shown[i]->GetNumberOfPoints() > shown[body]->GetNumberOfPoints() ? i : body;
  }
  vtkIdType tip = 0;
  for (vtkIdType p = 0; p < stored[body]->GetNumberOfPoints(); ++p)
  {
    tip =
      std::abs(stored[body]->GetPoint(p)[0]) > std::abs(stored[body]->GetPoint(tip)[0]) ? p : tip;
  }
  double rest[3], display[3], vtk[3], back[3];
  stored[body]->GetPoint(tip, rest);
  shown[body]->GetPoint(tip, display);
  theirs[body]->GetPoint(tip, vtk);
  ours[body]->GetPoint(tip, back);
  const double lowered = std::sqrt(vtkMath::Distance2BetweenPoints(rest, display));
  std::cout << "relaxed arms: the fingertip at x = " << rest[0] << " m moves " << lowered
            << " m; vtkGLTFReader puts it "
            << std::sqrt(vtkMath::Distance2BetweenPoints(vtk, display)) * 1e3
            << " mm from the display, our reader "
            << std::sqrt(vtkMath::Distance2BetweenPoints(back, display)) * 1e3 << " mm\n";
  // The shared avatar stands in an A-pose: its fingertip comes down by about 0.1 m and in by
  // more.
  EXPECT_GT(lowered, 0.1) << "the arms do not come down: the check could not fail";
  EXPECT_LT(display[1], rest[1] - 0.05) << "the fingertip is not lower";
  EXPECT_LT(std::sqrt(vtkMath::Distance2BetweenPoints(vtk, display)), 1e-6 * 1.666)
    << "vtkGLTFReader shows the arm elsewhere";
  EXPECT_LT(std::sqrt(vtkMath::Distance2BetweenPoints(back, display)), 1e-6 * 1.666)
    << "our reader shows the arm elsewhere";

  // Every point of every part.
  double worst = 0.0, worstOurs = 0.0;
  for (size_t i = 0; i < shown.size(); ++i)
  {
    ASSERT_EQ(theirs[i]->GetNumberOfPoints(), shown[i]->GetNumberOfPoints()) << i;
    ASSERT_EQ(ours[i]->GetNumberOfPoints(), shown[i]->GetNumberOfPoints()) << i;
    for (vtkIdType p = 0; p < shown[i]->GetNumberOfPoints(); ++p)
    {
      double a[3], b[3], c[3];
      shown[i]->GetPoint(p, a);
      theirs[i]->GetPoint(p, b);
      ours[i]->GetPoint(p, c);
      worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
      worstOurs = std::max(worstOurs, std::sqrt(vtkMath::Distance2BetweenPoints(a, c)));
    }
  }
  EXPECT_LT(worst, 1e-6 * 1.666);
  EXPECT_LT(worstOurs, 1e-6 * 1.666);
}
