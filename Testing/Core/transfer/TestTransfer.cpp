// SPDX-License-Identifier: BSD-3-Clause
// The transfer, step by step, on a synthetic face with analytic targets (SyntheticFace.h)
// and, when present, on ICT-FaceKit (identity and the decimated vertex subset).

#include "SyntheticFace.h"

#include "base/Error.h"
#include "gltf/GltfMorphMesh.h"
#include "gltf/GltfScene.h"
#include "transfer/Transfer.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

using namespace morphnode;

namespace
{
glm::dvec3 At(const std::vector<float>& d, size_t i)
{
  return { d[3 * i], d[3 * i + 1], d[3 * i + 2] };
}

struct Similarity
{
  double Scale = 1.0;
  glm::dmat3 R{ 1.0 };
  glm::dvec3 T{ 0.0 };
  glm::dvec3 operator()(const glm::dvec3& p) const { return Scale * (R * p) + T; }
};

Similarity SomeSimilarity()
{
  Similarity s;
  s.Scale = 1.3;
  s.R = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.6, glm::normalize(glm::dvec3(0.3, 1.0, 0.2))));
  s.T = { 0.4, -0.2, 1.5 };
  return s;
}

TransferSurface Transformed(const TransferSurface& s, const Similarity& t)
{
  TransferSurface out = s;
  for (auto& p : out.Points)
    p = t(p);
  return out;
}

/// Max over targets and points of |transferred - s R truth|, and the largest truth.
double MaxError(const TransferResult& r, const std::vector<std::vector<glm::dvec3>>& truth,
  const Similarity& t, double& largest, const std::vector<std::vector<float>>* deltas = nullptr)
{
  const auto& d = deltas ? *deltas : r.Deltas;
  double e = 0;
  largest = 0;
  for (size_t k = 0; k < truth.size(); ++k)
    for (size_t i = 0; i < truth[k].size(); ++i)
    {
      const glm::dvec3 want = t.Scale * (t.R * truth[k][i]);
      largest = std::max(largest, glm::length(want));
      e = std::max(e, glm::length(At(d[k], i) - want));
    }
  return e;
}
} // namespace

TEST(TransferAlignment, AutomaticRecoversASimilarity)
{
  const auto face = synthetic::MakeFace(0.05);
  const Similarity t = SomeSimilarity();
  TransferOptions options;
  options.Stiffness.clear(); // alignment only
  const TransferResult r =
    TransferTargets(synthetic::ToSource(face), Transformed(face.Surface, t), options);
  EXPECT_NEAR(r.Scale, t.Scale, 1e-6);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(r.Rotation[c][k], t.R[c][k], 1e-6);
  EXPECT_NEAR(glm::length(r.Translation - t.T), 0.0, 1e-6);
}

TEST(TransferAlignment, LandmarksWithNoiseThenIcp)
{
  const auto face = synthetic::MakeFace(0.05);
  const Similarity t = SomeSimilarity();
  TransferOptions probe;
  probe.Stiffness.clear();
  const TransferResult found = TransferTargets(synthetic::ToSource(face), face.Surface, probe);
  ASSERT_GE(found.SourceLandmarks.size(), 6u);
  TransferOptions options;
  int k = 0;
  for (const auto& l : found.SourceLandmarks)
  {
    // 2 % of the eye distance off, in alternating directions.
    const glm::dvec3 noise =
      0.016 * glm::dvec3((k & 1) ? 1 : -1, (k & 2) ? 1 : -1, (k & 4) ? 1 : -1);
    options.TargetLandmarks.push_back({ l.Name, t(l.Position + noise) });
    ++k;
  }
  const TransferResult r =
    TransferTargets(synthetic::ToSource(face), Transformed(face.Surface, t), options);
  // The landmarks' alignment is off by about their noise; the registration takes it up.
  EXPECT_NEAR(r.Scale, t.Scale, 0.03 * t.Scale);
  EXPECT_LT(glm::length(r.Translation - t.T), 0.05);
  EXPECT_LT(r.ResidualP95, 1e-3);
  double largest = 0;
  EXPECT_LT(MaxError(r, face.Deltas, t, largest), 0.2 * 0.2 * t.Scale);
}

TEST(TransferAlignment, LandmarkFile)
{
  const auto l =
    ParseTransferLandmarks("# face\neye_L 1 2 3\n  chin -1 0.5 1e-2 # tip\n\nnoseTip 0 0 0");
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[1].Name, "chin");
  EXPECT_DOUBLE_EQ(l[1].Position.z, 0.01);
  EXPECT_THROW(ParseTransferLandmarks("ear 1 2 3"), InputError);
  EXPECT_THROW(ParseTransferLandmarks("chin 1 2"), InputError);
  EXPECT_THROW(ParseTransferLandmarks("chin 1 2 nan"), InputError);
  EXPECT_THROW(ParseTransferLandmarks("chin 1 2 3\nchin 1 2 3"), InputError);
}

// On a similarity copy of the source every step must be exact: all three methods.
TEST(TransferExact, SimilarityCopyOfTheSource)
{
  const auto face = synthetic::MakeFace(0.05, 0.0, true, true);
  const Similarity t = SomeSimilarity();
  TransferOptions options;
  options.ComputeAllMethods = true;
  const TransferResult r =
    TransferTargets(synthetic::ToSource(face), Transformed(face.Surface, t), options);
  double largest = 0;
  const double dt = MaxError(r, face.Deltas, t, largest);
  EXPECT_LT(dt, 1e-6 * largest);
  EXPECT_LT(MaxError(r, face.Deltas, t, largest, &r.BarycentricDeltas), 1e-6 * largest);
  EXPECT_LT(MaxError(r, face.Deltas, t, largest, &r.NearestDeltas), 1e-6 * largest);
  EXPECT_LT(r.ResidualP95, 1e-9);
  for (size_t i = 0; i < r.Confidence.size(); ++i)
    EXPECT_GT(r.Confidence[i], 0.99f) << "point " << i;
}

// A face of another shape: the registration must pull the source onto it.
TEST(TransferRegistration, ResidualFallsOnAnotherShape)
{
  const auto face = synthetic::MakeFace(0.05);
  auto other = face.Surface;
  for (auto& p : other.Points)
    p.z += 0.08 * p.x * p.x + 0.04 * std::sin(3 * p.y);
  // Landmarks where the source's are, on the other shape (the alignment has its own tests).
  TransferOptions options, probe;
  probe.Stiffness.clear();
  for (const auto& l :
    TransferTargets(synthetic::ToSource(face), face.Surface, probe).SourceLandmarks)
    options.TargetLandmarks.push_back({ l.Name,
      l.Position +
        glm::dvec3(0, 0, 0.08 * l.Position.x * l.Position.x + 0.04 * std::sin(3 * l.Position.y)) });
  const TransferResult r = TransferTargets(synthetic::ToSource(face), other, options);
  EXPECT_GT(r.AlignedResidualP95, 0.02);
  EXPECT_LT(r.ResidualP95, 0.15 * r.AlignedResidualP95);
  EXPECT_LT(r.ResidualP95, 0.01);
  // Without registration the residual stays.
  options.Stiffness.clear();
  options.MaxResidual = 1.0;
  const TransferResult rigid = TransferTargets(synthetic::ToSource(face), other, options);
  EXPECT_GT(rigid.ResidualP95, 0.01);
}

// A finer remesh with touching lips: every lower-lip point opens with the jaw, no upper-lip
// point does, and the lids keep their sides.
TEST(TransferSeams, LipsAndLidsKeepTheirSides)
{
  const auto source = synthetic::MakeFace(0.025);
  const auto target = synthetic::MakeFace(0.035);
  const TransferResult r = TransferTargets(synthetic::ToSource(source), target.Surface);
  size_t lower = 0, upper = 0;
  for (size_t i = 0; i < target.Surface.GetNumberOfPoints(); ++i)
  {
    // Inside both meshes' slits (their corners differ by construction).
    if (std::abs(target.Uv[i].x) > 0.3)
      continue;
    const double truth = glm::length(target.Deltas[0][i]);
    const double got = glm::length(At(r.Deltas[0], i));
    if (target.Side[i] < 0)
    {
      ++lower;
      EXPECT_EQ(r.TargetSide[i], -1) << "point " << i;
      EXPECT_NEAR(got, truth, 0.1 * truth) << "lower lip point " << i;
    }
    if (target.Side[i] > 0)
    {
      ++upper;
      EXPECT_EQ(r.TargetSide[i], 1) << "point " << i;
      EXPECT_LT(got, 0.02 * 0.2) << "upper lip point " << i;
    }
  }
  EXPECT_GT(lower, 10u);
  EXPECT_EQ(lower, upper);
  // Lids: eyeBlink_L moves nothing below the eye's centre line.
  double maxError = 0, largest = 0;
  for (size_t i = 0; i < target.Surface.GetNumberOfPoints(); ++i)
  {
    maxError = std::max(maxError, glm::length(At(r.Deltas[1], i) - target.Deltas[1][i]));
    largest = std::max(largest, glm::length(target.Deltas[1][i]));
  }
  EXPECT_LT(maxError, 0.2 * largest);
}

TEST(TransferRigid, ToothMovesRigidly)
{
  const auto source = synthetic::MakeFace(0.05, 0.0, true, true);
  const auto target = synthetic::MakeFace(0.035, 0.0, true, true);
  const TransferResult r = TransferTargets(synthetic::ToSource(source), target.Surface);
  size_t rigid = 0;
  for (size_t i = 0; i < target.Surface.GetNumberOfPoints(); ++i)
  {
    EXPECT_EQ(bool(r.Rigid[i]), bool(target.Tooth[i]));
    if (!target.Tooth[i])
      continue;
    ++rigid;
    // (the alignment of two meshes of one surface is exact only to about 1e-4)
    EXPECT_LT(glm::length(At(r.Deltas[0], i) - target.Deltas[0][i]), 2e-4);
    // Distances within the tooth are kept.
    for (size_t j = 0; j < target.Surface.GetNumberOfPoints(); ++j)
      if (target.Tooth[j])
      {
        const auto& p = target.Surface.Points;
        EXPECT_NEAR(glm::length(p[i] + At(r.Deltas[0], i) - p[j] - At(r.Deltas[0], j)),
          glm::length(p[i] - p[j]), 1e-6);
      }
  }
  EXPECT_EQ(rigid, 8u);
}

TEST(TransferErrors, BadInputIsRefusedClearly)
{
  const auto face = synthetic::MakeFace(0.05);
  const auto source = synthetic::ToSource(face);
  auto expectError = [](auto&& call, const std::string& words)
  {
    try
    {
      call();
      ADD_FAILURE() << "no error, expected: " << words;
    }
    catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  // Not a face: no mouth target.
  auto noMouth = source;
  noMouth.TargetNames[0] = "jawSideways";
  expectError([&] { TransferTargets(noMouth, face.Surface); }, "not a face");
  // Non-manifold: a third triangle on one edge.
  auto nonManifold = face.Surface;
  nonManifold.Points.emplace_back(0.0, 0.0, 5.0);
  nonManifold.Triangles.insert(nonManifold.Triangles.end(),
    { nonManifold.Triangles[0], nonManifold.Triangles[2],
      uint32_t(nonManifold.Points.size() - 1) });
  expectError([&] { TransferTargets(source, nonManifold); }, "non-manifold");
  // A closed mouth.
  const auto closed = synthetic::MakeFace(0.05, 0.0, false);
  expectError([&] { TransferTargets(source, closed.Surface); }, "closed mouth");
  // A residual above the limit: another shape, registered stiffly, with a tight limit.
  auto other = face.Surface;
  for (auto& p : other.Points)
    p.z += 0.08 * p.x * p.x + 0.04 * std::sin(3 * p.y);
  TransferOptions options;
  options.Stiffness = { 50.0 };
  options.MaxResidual = 1e-3;
  expectError([&] { TransferTargets(source, other, options); }, "registration residual");
  expectError([&] { TransferTargets(source, TransferSurface{}); }, "no triangles");
}

TEST(TransferFaceKit, IdentityIsExactAndSubsetIsClose)
{
  const std::string dir = MORPHNODE_FACEKIT_DIR;
  const std::string full = dir + "/ict_face11248_sparse53.glb";
  const std::string subset = dir + "/ict_face_dec70_sparse53.glb";
  if (!std::filesystem::exists(full) || !std::filesystem::exists(subset))
    GTEST_SKIP() << "ICT-FaceKit not found: " << full;
  const GltfScene a = LoadGltfScene(full);
  const TransferSource source = MakeTransferSource(GltfPartToMorphMesh(a.Parts.at(0)));
  // Identity.
  {
    const TransferResult r = TransferTargets(source, source.Surface);
    double largest = 0;
    EXPECT_LT(MaxError(r, source.Deltas, Similarity{}, largest), 1e-6);
  }
  // The decimated face: its points are the full face's, found here by position only for
  // the truth (the transfer does not see it).
  const GltfScene b = LoadGltfScene(subset);
  const TransferSource small = MakeTransferSource(GltfPartToMorphMesh(b.Parts.at(0)));
  std::map<std::tuple<float, float, float>, size_t> index;
  for (size_t i = 0; i < source.Surface.GetNumberOfPoints(); ++i)
  {
    const auto& p = source.Surface.Points[i];
    index[{ float(p.x), float(p.y), float(p.z) }] = i;
  }
  const TransferResult r = TransferTargets(source, small.Surface);
  std::vector<double> errors;
  for (size_t k = 0; k < source.Deltas.size(); ++k)
    for (size_t i = 0; i < small.Surface.GetNumberOfPoints(); ++i)
    {
      const auto& p = small.Surface.Points[i];
      const auto it = index.find({ float(p.x), float(p.y), float(p.z) });
      ASSERT_NE(it, index.end());
      const glm::dvec3 truth = source.Deltas[k][it->second];
      if (glm::length(truth) > 0 || glm::length(At(r.Deltas[k], i)) > 0)
        errors.push_back(glm::length(At(r.Deltas[k], i) - truth));
    }
  std::sort(errors.begin(), errors.end());
  const double p95 = errors[size_t(0.95 * double(errors.size() - 1))];
  EXPECT_LT(p95, 0.5e-3) << "p95 " << p95 * 1e3 << " mm, max " << errors.back() * 1e3 << " mm";
}
