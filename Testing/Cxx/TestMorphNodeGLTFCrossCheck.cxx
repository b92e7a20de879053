// SPDX-License-Identifier: BSD-3-Clause
// Cross-check against an implementation MorphNode did not write: VTK 9.1's own glTF
// morphing (vtkGLTFReader with ApplyDeformationsToGeometry on) must give the same points
// as vtkMorphNodeFilter in Relative mode for the same weights, on the ICT face and on the
// whole ICT head (11 parts on their nodes, world space, read by vtkMorphTargetReader).
#include "vtkMorphNodeFilter.h"
#include "vtkMorphPartData.h"
#include "vtkMorphTargetReader.h"

#include "MorphNodeGltfReaderParts.h"
#include "MorphNodeTestUtilities.h"

#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkFieldData.h"
#include "vtkGLTFReader.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <random>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";
const std::string IctHead = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_head_full53.glb";

uint32_t ReadU32(const std::vector<char>& b, size_t at)
{
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

void AppendU32(std::vector<char>& b, uint32_t v)
{
  const char* p = reinterpret_cast<const char*>(&v);
  b.insert(b.end(), p, p + 4);
}

/// Copies a GLB with the first mesh's default weights replaced, so that VTK's reader
/// applies exactly these weights.
std::string WriteGlbWithWeights(
  const std::string& source, const std::vector<double>& weights, const std::string& name)
{
  std::ifstream in(source, std::ios::binary);
  std::vector<char> glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_GE(glb.size(), 20u);
  const uint32_t jsonLength = ReadU32(glb, 12);
  nlohmann::json doc = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLength);
  doc["meshes"][0]["weights"] = weights;
  std::string json = doc.dump();
  json.append((4 - json.size() % 4) % 4, ' ');
  const std::vector<char> rest(glb.begin() + 20 + jsonLength, glb.end()); // the BIN chunk

  std::vector<char> out;
  AppendU32(out, 0x46546C67); // "glTF"
  AppendU32(out, 2);
  AppendU32(out, static_cast<uint32_t>(12 + 8 + json.size() + rest.size()));
  AppendU32(out, static_cast<uint32_t>(json.size()));
  AppendU32(out, 0x4E4F534A); // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), rest.begin(), rest.end());
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/" + name;
  std::ofstream(path, std::ios::binary).write(out.data(), static_cast<std::streamsize>(out.size()));
  return path;
}

vtkSmartPointer<vtkPolyData> FirstMesh(const std::string& file, bool deform)
{
  vtkNew<vtkGLTFReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetApplyDeformationsToGeometry(deform);
  reader->Update();
  const auto polys = vtkCompositeDataSet::GetDataSets<vtkPolyData>(reader->GetOutput());
  return polys.empty() ? nullptr : polys.front();
}

/// Every leaf of VTK's output, in its order (the scene's nodes depth first, primitives in
/// order: the order of MorphNode's parts, see TestGltfSceneCrossCheck).
std::vector<vtkSmartPointer<vtkPolyData>> AllParts(const std::string& file, bool deform)
{
  return morphnode_test::VtkGltfReaderParts(file, deform);
}

/// A copy of the ICT head that VTK 9.1 reads right, with `weights` (by target name) as every
/// mesh's default weights (`mesh.weights`, which VTK applies with
/// ApplyDeformationsToGeometry on).
///
/// The head's targets are sparse accessors WITHOUT a bufferView, whose base the glTF spec
/// defines as zeros; VTK 9.1 does not zero-fill them (its targets come out as garbage). The
/// spec's equivalent that VTK does read: the same sparse accessors over an explicit all-zero
/// buffer view. So the copy appends one block of zeros (as long as the largest such
/// accessor) to the GLB's BIN chunk, adds a buffer view over it, and points every sparse
/// accessor without a bufferView at it, with an explicit byteOffset 0 (VTK 9.1 needs one).
/// The JSON is edited with nlohmann/json; nothing else of the file changes.
std::string WriteHeadForVtk(const std::map<std::string, double>& weights, const std::string& name)
{
  std::ifstream in(IctHead, std::ios::binary);
  std::vector<char> glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_GE(glb.size(), 28u);
  const uint32_t jsonLength = ReadU32(glb, 12);
  nlohmann::json doc = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLength);
  const size_t binAt = 20 + jsonLength;
  EXPECT_EQ(ReadU32(glb, binAt + 4), 0x004E4942u) << "the BIN chunk";
  std::vector<char> bin(glb.begin() + static_cast<long>(binAt + 8),
    glb.begin() + static_cast<long>(binAt + 8 + ReadU32(glb, binAt)));

  size_t zeroBytes = 0;
  int patched = 0;
  for (const auto& accessor : doc["accessors"])
  {
    if (accessor.contains("sparse") && !accessor.contains("bufferView"))
    {
      EXPECT_EQ(accessor["type"], "VEC3");
      EXPECT_EQ(accessor["componentType"], 5126);
      zeroBytes = std::max(zeroBytes, 12 * accessor["count"].get<size_t>());
    }
  }
  const size_t zeroAt = bin.size(); // a multiple of 4, as GLB chunks are
  bin.resize(zeroAt + zeroBytes, 0);
  doc["bufferViews"].push_back(
    { { "buffer", 0 }, { "byteOffset", zeroAt }, { "byteLength", zeroBytes } });
  const size_t zeroView = doc["bufferViews"].size() - 1;
  for (auto& accessor : doc["accessors"])
  {
    if (accessor.contains("sparse") && !accessor.contains("bufferView"))
    {
      accessor["bufferView"] = zeroView;
      accessor["byteOffset"] = 0;
      ++patched;
    }
  }
  EXPECT_GT(patched, 100) << "the head's targets are sparse without bufferView";
  doc["buffers"][0]["byteLength"] = bin.size();
  for (auto& mesh : doc["meshes"])
  {
    if (mesh.contains("extras") && mesh["extras"].contains("targetNames"))
    {
      std::vector<double> w;
      for (const auto& target : mesh["extras"]["targetNames"])
      {
        w.push_back(weights.at(target.get<std::string>()));
      }
      mesh["weights"] = w;
    }
  }
  for (const auto& node : doc["nodes"])
  {
    EXPECT_FALSE(node.contains("weights")) << "node weights would override the mesh's";
  }

  std::string json = doc.dump();
  json.append((4 - json.size() % 4) % 4, ' ');
  std::vector<char> out;
  AppendU32(out, 0x46546C67); // "glTF"
  AppendU32(out, 2);
  AppendU32(out, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  AppendU32(out, static_cast<uint32_t>(json.size()));
  AppendU32(out, 0x4E4F534A); // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  AppendU32(out, static_cast<uint32_t>(bin.size()));
  AppendU32(out, 0x004E4942); // "BIN"
  out.insert(out.end(), bin.begin(), bin.end());
  const std::string path = std::string(MORPHNODE_TEST_OUTPUT_DIR) + "/" + name;
  std::ofstream(path, std::ios::binary).write(out.data(), static_cast<std::streamsize>(out.size()));
  return path;
}

/// The whole head: vtkMorphTargetReader (every part, world space) and vtkMorphNodeFilter
/// with `weights` by name, against VTK's deformed parts of the patched copy.
void CrossCheckHead(const std::map<std::string, double>& weights, const std::string& name)
{
  const std::string file = WriteHeadForVtk(weights, name);
  const auto reference = AllParts(file, true);
  ASSERT_EQ(reference.size(), 11u);

  vtkNew<vtkMorphTargetReader> reader;
  reader->SetFileName(IctHead.c_str()); // the original, sparse accessors without bufferView
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputConnection(reader->GetOutputPort());
  morph->SetWeightModeToRelative();
  for (const auto& [target, w] : weights)
  {
    morph->SetWeightByName(target.c_str(), w);
  }
  morph->Update();
  EXPECT_EQ(morph->GetNumberOfTargets(), 54);
  auto* head = vtkCompositeDataSet::SafeDownCast(morph->GetOutputDataObject(0));
  auto* neutral = vtkCompositeDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  ASSERT_TRUE(head && neutral);
  std::vector<vtkPolyData*> ours, rest;
  for (const auto& [data, list] : { std::pair{ head, &ours }, std::pair{ neutral, &rest } })
  {
    for (vtkDataObject* leaf : vtk::Range(data, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      list->push_back(vtkPolyData::SafeDownCast(leaf));
    }
  }
  ASSERT_EQ(ours.size(), reference.size());

  double bounds[6] = { VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX,
    VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (vtkPolyData* part : rest)
  {
    double b[6];
    part->GetBounds(b);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], b[2 * k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], b[2 * k + 1]);
    }
  }
  const double size = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  EXPECT_GT(size, 0.2) << "metres";
  double moved = 0.0, largest = 0.0;
  for (size_t p = 0; p < ours.size(); ++p)
  {
    ASSERT_TRUE(ours[p] && rest[p]);
    ASSERT_EQ(ours[p]->GetNumberOfPoints(), reference[p]->GetNumberOfPoints()) << p;
    double worst = 0.0;
    for (vtkIdType i = 0; i < ours[p]->GetNumberOfPoints(); ++i)
    {
      double a[3], b[3], n[3];
      ours[p]->GetPoint(i, a);
      reference[p]->GetPoint(i, b);
      rest[p]->GetPoint(i, n);
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(a[c] - b[c]));
        moved = std::max(moved, std::abs(b[c] - n[c]));
      }
    }
    EXPECT_LE(worst, 1e-6 * size)
      << vtkMorphPartData::GetPartName(rest[p]->GetFieldData(), std::to_string(p))
      << ": largest coordinate difference to VTK's glTF morphing, world space";
    largest = std::max(largest, worst);
  }
  EXPECT_GT(moved, 5e-3) << "the weights hardly move the head (metres)";
  std::cout << name << ": 11 parts, head size " << size << " m, weights move points up to " << moved
            << " m, largest difference to VTK " << largest << " m\n";
}

void CrossCheck(const std::vector<double>& gltfWeights, const std::string& name)
{
  const std::string file = WriteGlbWithWeights(IctGlb, gltfWeights, name);
  auto reference = FirstMesh(file, true);
  auto targets = FirstMesh(file, false);
  ASSERT_TRUE(reference && targets);
  ASSERT_EQ(reference->GetNumberOfPoints(), 11248);

  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputData(targets);
  morph->SetWeightModeToRelative();
  for (size_t k = 0; k < gltfWeights.size(); ++k)
  {
    morph->SetWeight(static_cast<int>(k + 1), gltfWeights[k]);
  }
  morph->Update();
  auto* ours = vtkPolyData::SafeDownCast(morph->GetOutput());
  ASSERT_EQ(ours->GetNumberOfPoints(), reference->GetNumberOfPoints());
  EXPECT_EQ(morph->GetNumberOfTargets(), 54);

  // The weights must make a difference, or the comparison proves nothing.
  double moved = 0.0, worst = 0.0;
  for (vtkIdType i = 0; i < ours->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3], n[3];
    ours->GetPoint(i, a);
    reference->GetPoint(i, b);
    targets->GetPoint(i, n);
    for (int c = 0; c < 3; ++c)
    {
      worst = std::max(worst, std::abs(a[c] - b[c]));
      moved = std::max(moved, std::abs(b[c] - n[c]));
    }
  }
  EXPECT_GT(moved, 1e-3) << "the weights hardly move the face (metres)";
  EXPECT_LT(worst, 1e-6) << "largest coordinate difference to VTK's glTF morphing (metres)";
}
} // namespace

TEST(MorphNodeGLTFCrossCheck, SpeechLikeFrame)
{
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  std::vector<double> w(53, 0.0);
  w[26] = 0.6;  // jawOpen
  w[33] = 0.3;  // mouthFunnel
  w[10] = 1.0;  // eyeBlink_L
  w[45] = 0.4;  // mouthSmile_L
  w[2] = 0.7;   // browInnerUp_L
  w[35] = 0.25; // mouthLowerDown_L
  CrossCheck(w, "ict_speech_frame.glb");
}

TEST(MorphNodeGLTFCrossCheck, AllTargetsActive)
{
  if (!std::ifstream(IctGlb))
  {
    GTEST_SKIP() << "ICT-FaceKit data not found at " << IctGlb;
  }
  std::mt19937 rng(2004);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> w(53);
  for (auto& v : w)
  {
    v = u(rng);
  }
  CrossCheck(w, "ict_all_targets.glb");
}

TEST(MorphNodeGLTFCrossCheck, WholeHeadRandomWeights)
{
  if (!std::ifstream(IctHead))
  {
    GTEST_SKIP() << "ICT-FaceKit head not found at " << IctHead;
  }
  vtkNew<vtkMorphTargetReader> names;
  names->SetFileName(IctHead.c_str());
  names->Update();
  ASSERT_EQ(names->GetNumberOfTargets(), 54);
  for (unsigned seed : { 14u, 2004u })
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::map<std::string, double> weights;
    for (int k = 1; k < names->GetNumberOfTargets(); ++k)
    {
      weights[names->GetTargetName(k)] = u(rng);
    }
    CrossCheckHead(weights, "ict_head_random_" + std::to_string(seed) + ".glb");
  }
}
