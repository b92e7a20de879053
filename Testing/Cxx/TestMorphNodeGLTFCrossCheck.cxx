// SPDX-License-Identifier: BSD-3-Clause
// Cross-check against an implementation MorphNode did not write: VTK 9.1's own glTF
// morphing (vtkGLTFReader with ApplyDeformationsToGeometry on) must give the same points
// as vtkMorphNodeFilter in Relative mode for the same weights, on the ICT face.
#include "vtkMorphNodeFilter.h"

#include "MorphNodeTestUtilities.h"

#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkGLTFReader.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

namespace
{
const std::string IctGlb = std::string(MORPHNODE_FACEKIT_DIR) + "/ict_face11248_sparse53.glb";

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
std::string WriteGlbWithWeights(const std::string& source, const std::vector<double>& weights,
  const std::string& name)
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
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(reader->GetOutput()->NewIterator());
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    if (auto* pd = vtkPolyData::SafeDownCast(it->GetCurrentDataObject()))
    {
      return pd;
    }
  }
  return nullptr;
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
