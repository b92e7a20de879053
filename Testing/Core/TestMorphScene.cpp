// SPDX-License-Identifier: BSD-3-Clause
// The morph scene: parts with their own targets matched by name, one optimizer decision for
// the whole model, and the same result as one mesh holding every part.
#include "base/Error.h"
#include "morph/MorphNode.h"
#include "morph/MorphScene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
/// A whole model: points, and per target (neutral excluded) deltas; target t moves a patch
/// of points of its own, so that targets differ in size and place.
struct Model
{
  size_t NumPoints = 0;
  std::vector<std::string> Names; // neutral first
  std::vector<float> Points;
  std::vector<float> Normals;
  std::vector<std::vector<float>> PointDeltas, NormalDeltas;
};

Model MakeModel(size_t numPoints, size_t numTargets, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  Model m;
  m.NumPoints = numPoints;
  m.Names.push_back("Neutral");
  for (size_t t = 0; t < numTargets; ++t)
  {
    m.Names.push_back("shape" + std::to_string(t));
  }
  m.Points.resize(3 * numPoints);
  m.Normals.resize(3 * numPoints);
  for (auto& v : m.Points)
  {
    v = u(rng);
  }
  for (auto& v : m.Normals)
  {
    v = u(rng);
  }
  for (size_t t = 0; t < numTargets; ++t)
  {
    std::vector<float> d(3 * numPoints, 0.f), n(3 * numPoints, 0.f);
    const size_t begin = (t * 37) % numPoints;
    const size_t length = numPoints / (t + 2);
    const float size = 0.02f * float(t + 1);
    for (size_t k = 0; k < length; ++k)
    {
      const size_t i = (begin + k) % numPoints;
      for (int c = 0; c < 3; ++c)
      {
        d[3 * i + c] = size * u(rng);
        n[3 * i + c] = 0.1f * u(rng);
      }
    }
    m.PointDeltas.push_back(d);
    m.NormalDeltas.push_back(n);
  }
  return m;
}

/// Points [begin, end) of the model with the targets `targets` (indices into the model's
/// targets, neutral excluded, in the order given) as a mesh.
std::shared_ptr<const MorphMesh> Piece(
  const Model& m, size_t begin, size_t end, const std::vector<size_t>& targets)
{
  auto mesh = std::make_shared<MorphMesh>(end - begin);
  std::vector<std::string> names{ m.Names[0] };
  for (size_t t : targets)
  {
    names.push_back(m.Names[t + 1]);
  }
  mesh->SetTargetNames(names);
  auto& points = mesh->AddAttribute<float>("Points", AttributeRole::Position, 3);
  points.SetNeutral(m.Points.data() + 3 * begin);
  for (size_t t : targets)
  {
    points.AddRelativeTarget(m.PointDeltas[t].data() + 3 * begin, 0.3);
  }
  auto& normals = mesh->AddAttribute<float>("Normals", AttributeRole::Normal, 3);
  normals.SetNeutral(m.Normals.data() + 3 * begin);
  for (size_t t : targets)
  {
    normals.AddRelativeTarget(m.NormalDeltas[t].data() + 3 * begin, 0.3);
  }
  mesh->Validate();
  return mesh;
}

std::vector<size_t> AllTargets(const Model& m)
{
  std::vector<size_t> all(m.Names.size() - 1);
  for (size_t t = 0; t < all.size(); ++t)
  {
    all[t] = t;
  }
  return all;
}

/// Blends every part of the scene into one buffer per attribute in the whole model's order
/// (parts are consecutive ranges of points).
std::vector<std::vector<float>> BlendScene(const MorphScene& scene)
{
  std::vector<std::vector<float>> result(2);
  for (size_t p = 0; p < scene.GetNumberOfParts(); ++p)
  {
    const size_t n = scene.GetPart(p).GetNumberOfPoints();
    std::vector<float> points(3 * n), normals(3 * n);
    scene.Blend(p, { points.data(), normals.data() }, 0, n);
    result[0].insert(result[0].end(), points.begin(), points.end());
    result[1].insert(result[1].end(), normals.begin(), normals.end());
  }
  return result;
}

std::vector<std::vector<float>> BlendNode(const MorphNode& node)
{
  const size_t n = node.GetMesh()->GetNumberOfPoints();
  std::vector<std::vector<float>> result{ std::vector<float>(3 * n), std::vector<float>(3 * n) };
  node.Blend({ result[0].data(), result[1].data() }, 0, n);
  return result;
}

/// Optimizer settings of every kind, each deciding something for the weights below.
std::vector<OptimizerSettings> EverySetting()
{
  std::vector<OptimizerSettings> all;
  for (int preset = 0; preset < NumberOfOptimizerPresets; ++preset)
  {
    all.push_back(MakeOptimizerSettings(static_cast<OptimizerPreset>(preset), 0.12, 0.01));
  }
  OptimizerSettings budget = MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.12, 0.0);
  budget.MaxActiveTargets = 3;
  all.push_back(budget);
  OptimizerSettings bounded = MakeOptimizerSettings(OptimizerPreset::FixedMaximum, 0.2, 0.005);
  bounded.MaxActiveTargets = 2;
  all.push_back(bounded);
  return all;
}

std::vector<double> RandomWeights(size_t n, std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(0.0, 0.4);
  std::vector<double> w(n);
  for (double& v : w)
  {
    v = u(rng);
  }
  w[0] = 0.0;
  return w;
}
} // namespace

TEST(MorphScene, OnePartIsTheMorphNodeBitForBit)
{
  const Model m = MakeModel(500, 8, 1);
  const auto mesh = Piece(m, 0, m.NumPoints, AllTargets(m));
  MorphScene scene;
  scene.SetParts({ mesh });
  MorphNode node(mesh);
  ASSERT_EQ(scene.GetTargetNames(), mesh->GetTargetNames());
  EXPECT_EQ(scene.GetTargetDistances().DistMorph, node.GetTargetDistances().DistMorph);
  EXPECT_EQ(scene.GetTargetDistances().DistNorm, node.GetTargetDistances().DistNorm);
  EXPECT_EQ(scene.GetTargetDistances().MaxDisplacement, node.GetTargetDistances().MaxDisplacement);
  std::mt19937 rng(5);
  for (const OptimizerSettings& settings : EverySetting())
  {
    for (WeightMode mode : { WeightMode::Relative, WeightMode::Normalize })
    {
      scene.SetOptimizerSettings(settings);
      node.SetOptimizerSettings(settings);
      scene.SetWeightMode(mode);
      node.SetWeightMode(mode);
      for (int frame = 0; frame < 5; ++frame)
      {
        const auto w = RandomWeights(m.Names.size(), rng);
        scene.SetWeights(w);
        node.SetWeights(w);
        ASSERT_EQ(scene.GetEffectiveWeights(), node.GetEffectiveWeights());
        EXPECT_EQ(scene.GetErrorBound(), node.GetErrorBound());
        EXPECT_EQ(scene.GetActiveTargetCount(), node.GetActiveTargetCount());
        const auto a = BlendScene(scene), b = BlendNode(node);
        EXPECT_EQ(a[0], b[0]);
        EXPECT_EQ(a[1], b[1]);
      }
    }
  }
}

TEST(MorphScene, ManyPartsDecideAsOneMesh)
{
  // The same points and targets, once as one mesh and once cut into five parts; two parts
  // lack some targets altogether (their deltas there are zero in the whole mesh too), one
  // lists its targets in another order, one has none.
  Model m = MakeModel(1000, 10, 2);
  const std::vector<size_t> cuts{ 0, 150, 400, 420, 700, 1000 };
  std::vector<std::vector<size_t>> targets(5, AllTargets(m));
  targets[1] = { 9, 7, 5, 3, 1 }; // shuffled subset
  targets[2] = {};                // an eye: no targets
  targets[3] = { 0, 2, 4, 6, 8, 1, 3, 5, 7, 9 };
  for (size_t p = 0; p < 5; ++p)
  {
    for (size_t t = 0; t < 10; ++t)
    {
      if (std::find(targets[p].begin(), targets[p].end(), t) == targets[p].end())
      {
        std::fill(
          m.PointDeltas[t].begin() + 3 * cuts[p], m.PointDeltas[t].begin() + 3 * cuts[p + 1], 0.f);
        std::fill(m.NormalDeltas[t].begin() + 3 * cuts[p],
          m.NormalDeltas[t].begin() + 3 * cuts[p + 1], 0.f);
      }
    }
  }
  const auto whole = Piece(m, 0, m.NumPoints, AllTargets(m));
  std::vector<std::shared_ptr<const MorphMesh>> parts;
  for (size_t p = 0; p < 5; ++p)
  {
    parts.push_back(Piece(m, cuts[p], cuts[p + 1], targets[p]));
  }
  MorphScene scene, one;
  scene.SetParts(parts);
  one.SetParts({ whole });
  ASSERT_EQ(scene.GetTargetNames(), one.GetTargetNames()) << "names by first appearance";
  for (size_t i = 0; i < scene.GetNumberOfTargets(); ++i)
  {
    EXPECT_NEAR(scene.GetTargetDistances().DistMorph[i], one.GetTargetDistances().DistMorph[i],
      1e-12 * one.GetTargetDistances().DistMorph[i]);
    EXPECT_NEAR(
      scene.GetTargetDistances().DistNorm[i], one.GetTargetDistances().DistNorm[i], 1e-14);
    EXPECT_EQ(
      scene.GetTargetDistances().MaxDisplacement[i], one.GetTargetDistances().MaxDisplacement[i]);
  }
  EXPECT_EQ(scene.GetPartTargets(1), (std::vector<size_t>{ 0, 10, 8, 6, 4, 2 }));
  EXPECT_EQ(scene.GetPartTargets(2), (std::vector<size_t>{ 0 }));

  std::mt19937 rng(9);
  int pruned = 0;
  for (const OptimizerSettings& settings : EverySetting())
  {
    scene.SetOptimizerSettings(settings);
    one.SetOptimizerSettings(settings);
    scene.SetWeightMode(WeightMode::Relative);
    one.SetWeightMode(WeightMode::Relative);
    for (int frame = 0; frame < 8; ++frame)
    {
      const auto w = RandomWeights(scene.GetNumberOfTargets(), rng);
      scene.SetWeights(w);
      one.SetWeights(w);
      ASSERT_EQ(scene.GetEffectiveWeights(), one.GetEffectiveWeights()) << "frame " << frame;
      EXPECT_EQ(scene.GetErrorBound(), one.GetErrorBound());
      EXPECT_EQ(scene.GetActiveTargetCount(), one.GetActiveTargetCount());
      pruned += static_cast<int>(scene.GetNumberOfTargets()) - 1 - scene.GetActiveTargetCount();
      // The same blend, part by part.
      const auto a = BlendScene(scene), b = BlendScene(one);
      ASSERT_EQ(a[0].size(), b[0].size());
      double worst = 0.0;
      for (size_t i = 0; i < a[0].size(); ++i)
      {
        worst = std::max(worst, double(std::abs(a[0][i] - b[0][i])));
      }
      EXPECT_LE(worst, 1e-6) << "points";
      EXPECT_FALSE(scene.IsPartMoved(2)) << "the part without targets";
    }
  }
  EXPECT_GT(pruned, 20) << "the optimizer must decide something, or the test proves nothing";
}

TEST(MorphScene, ATargetOnSomePartsMovesOnlyThose)
{
  const Model m = MakeModel(300, 4, 3);
  const auto skin = Piece(m, 0, 100, { 0, 1, 2, 3 });
  const auto teeth = Piece(m, 100, 200, { 2 });
  const auto eye = Piece(m, 200, 300, {});
  MorphScene scene;
  scene.SetParts({ skin, teeth, eye });
  scene.SetWeightMode(WeightMode::Relative);
  std::vector<double> w(scene.GetNumberOfTargets(), 0.0);
  w[static_cast<size_t>(scene.FindTarget("shape0"))] = 0.5; // the skin only
  scene.SetWeights(w);
  EXPECT_TRUE(scene.IsPartMoved(0));
  EXPECT_FALSE(scene.IsPartMoved(1));
  EXPECT_FALSE(scene.IsPartMoved(2));
  EXPECT_EQ(scene.GetPartWeights(1), (std::vector<double>{ 1.0, 0.0 }));
  const auto blended = BlendScene(scene);
  for (size_t i = 300; i < 900; ++i)
  {
    ASSERT_EQ(blended[0][i], m.Points[i]) << "teeth and eye keep their neutral";
  }
  w[static_cast<size_t>(scene.FindTarget("shape2"))] = 0.25; // skin and teeth
  scene.SetWeights(w);
  EXPECT_TRUE(scene.IsPartMoved(1));
  EXPECT_EQ(scene.GetPartWeights(1), (std::vector<double>{ 0.75, 0.25 }));
  EXPECT_EQ(scene.GetPartWeights(0)[3], 0.25);
  EXPECT_EQ(scene.GetPartWeights(2), (std::vector<double>{ 1.0 }));
}

TEST(MorphScene, TargetsOffByPartNameMatchTheNameOrTheMeshOfAPartition)
{
  // Parts named as vtkMorphNodeFilter names a composite's leaves: "Name/i" is partition i of
  // the mesh "Name". A part takes the entry of its own name, else of its mesh's.
  const Model m = MakeModel(400, 3, 5);
  MorphScene scene;
  scene.SetParts({ Piece(m, 0, 100, { 0, 1, 2 }), Piece(m, 100, 200, { 0, 1 }),
    Piece(m, 200, 300, { 0, 1 }), Piece(m, 300, 400, { 0, 1 }) });
  scene.SetWeightMode(WeightMode::Relative);
  const std::vector<std::string> names{ "head", "eye/0", "eye/1", "lash" };
  std::vector<double> w(scene.GetNumberOfTargets(), 0.0);
  w[static_cast<size_t>(scene.FindTarget("shape0"))] = 0.5;
  w[static_cast<size_t>(scene.FindTarget("shape1"))] = 0.25;
  const auto partWeights = [&](size_t part)
  {
    scene.SetWeights(w);
    return scene.GetPartWeights(part);
  };

  std::map<std::string, std::vector<std::string>> off{ { "eye", { "shape0", "nosuch" } },
    { "eye/1", { "shape1" } } };
  EXPECT_TRUE(scene.SetTargetsOffByPartName(names, off));
  EXPECT_EQ(partWeights(0), (std::vector<double>{ 0.25, 0.5, 0.25, 0.0 })) << "head: no entry";
  EXPECT_EQ(partWeights(1), (std::vector<double>{ 0.75, 0.0, 0.25 })) << "eye/0 takes 'eye'";
  EXPECT_EQ(partWeights(2), (std::vector<double>{ 0.5, 0.5, 0.0 })) << "eye/1: its own entry";
  EXPECT_EQ(partWeights(3), (std::vector<double>{ 0.25, 0.5, 0.25 })) << "lash: no entry";

  off.clear(); // no entries: every part moves again
  EXPECT_FALSE(scene.SetTargetsOffByPartName(names, off));
  EXPECT_EQ(partWeights(1), (std::vector<double>{ 0.25, 0.5, 0.25 }));
  EXPECT_EQ(partWeights(2), (std::vector<double>{ 0.25, 0.5, 0.25 }));

  EXPECT_THROW(scene.SetTargetsOffByPartName({ "head" }, off), InputError)
    << "every part needs a name";
}

TEST(MorphScene, TheBudgetCountsEveryPart)
{
  // shape0 barely moves the skin but moves the teeth a lot: the whole model's largest
  // displacement, not the skin's, decides which target the budget keeps.
  Model m = MakeModel(200, 2, 4);
  for (size_t i = 0; i < 3 * 100; ++i)
  {
    m.PointDeltas[0][i] *= 0.01f;               // skin: shape0 tiny
    m.PointDeltas[1][i] = 0.05f * (i % 3 == 0); // skin: shape1 moderate
  }
  for (size_t i = 3 * 100; i < 3 * 200; ++i)
  {
    m.PointDeltas[0][i] = 0.5f * (i % 3 == 1); // teeth: shape0 large
    m.PointDeltas[1][i] = 0.f;
  }
  MorphScene scene, skinOnly;
  scene.SetParts({ Piece(m, 0, 100, { 0, 1 }), Piece(m, 100, 200, { 0, 1 }) });
  skinOnly.SetParts({ Piece(m, 0, 100, { 0, 1 }) });
  OptimizerSettings budget;
  budget.MaxActiveTargets = 1;
  for (MorphScene* s : { &scene, &skinOnly })
  {
    s->SetOptimizerSettings(budget);
    s->SetWeightMode(WeightMode::Relative);
    s->SetWeights({ 0.0, 0.3, 0.3 });
  }
  EXPECT_GT(scene.GetEffectiveWeights()[1], 0.0) << "shape0 moves the teeth most";
  EXPECT_EQ(scene.GetEffectiveWeights()[2], 0.0);
  EXPECT_EQ(skinOnly.GetEffectiveWeights()[1], 0.0) << "on the skin alone shape1 wins";
  EXPECT_GT(skinOnly.GetEffectiveWeights()[2], 0.0);
}

TEST(MorphScene, PiecesWithDuplicatedPointsAndSeveralProcessesDecideAsOne)
{
  // A mesh cut into two pieces that share 20 boundary points (as VTK's redistribution
  // duplicates them): flagged once, the sums equal the whole mesh's. Then the pieces as two
  // "processes": each scene holds one piece, combines both pieces' figures (in the same
  // order), and decides as the whole.
  const Model m = MakeModel(400, 6, 6);
  const auto whole = Piece(m, 0, 400, AllTargets(m));
  const auto a = Piece(m, 0, 220, AllTargets(m));
  const auto b = Piece(m, 200, 400, AllTargets(m));
  std::vector<uint8_t> aFlags(220, 0), bFlags(200, 0);
  std::fill(bFlags.begin(), bFlags.begin() + 20, uint8_t(1)); // b's copies of a's points
  MorphScene one, both, unflagged;
  one.SetParts({ whole });
  both.SetParts({ a, b }, { aFlags, bFlags });
  unflagged.SetParts({ a, b });
  for (size_t i = 1; i < one.GetNumberOfTargets(); ++i)
  {
    const double expected = one.GetTargetDistances().DistMorph[i];
    EXPECT_NEAR(both.GetTargetDistances().DistMorph[i], expected, 1e-12 * expected) << i;
  }
  // shape5 moves points 185..241, the duplicated ones among them.
  EXPECT_GT(
    unflagged.GetTargetDistances().DistMorph[6], one.GetTargetDistances().DistMorph[6] * (1 + 1e-9))
    << "counted twice without flags";

  MorphScene rank0, rank1;
  rank0.SetParts({ a }, { aFlags });
  rank1.SetParts({ b }, { bFlags });
  const NamedTargetDistances model =
    CombineTargetDistances({ rank0.GetPartsDistances(), rank1.GetPartsDistances() });
  rank0.SetModel(model);
  rank1.SetModel(model);
  EXPECT_EQ(rank0.GetTargetDistances().DistNorm, rank1.GetTargetDistances().DistNorm);
  std::mt19937 rng(11);
  for (const OptimizerSettings& settings : EverySetting())
  {
    for (MorphScene* s : { &one, &rank0, &rank1 })
    {
      s->SetOptimizerSettings(settings);
      s->SetWeightMode(WeightMode::Relative);
    }
    for (int frame = 0; frame < 5; ++frame)
    {
      const auto w = RandomWeights(one.GetNumberOfTargets(), rng);
      one.SetWeights(w);
      rank0.SetWeights(w);
      rank1.SetWeights(w);
      EXPECT_EQ(rank0.GetEffectiveWeights(), rank1.GetEffectiveWeights());
      EXPECT_EQ(rank0.GetEffectiveWeights(), one.GetEffectiveWeights());
      EXPECT_EQ(rank0.GetErrorBound(), one.GetErrorBound());
    }
  }
}

TEST(MorphScene, AModelWithTargetsThisProcessLacks)
{
  const Model m = MakeModel(100, 3, 7);
  MorphScene scene;
  scene.SetParts({ Piece(m, 0, 100, { 1 }) });
  ASSERT_EQ(scene.GetNumberOfTargets(), 2u);
  NamedTargetDistances other{ { "Neutral", "shape0", "shape2" }, { 0, 5, 1 }, { 0, 0.2, 0.1 } };
  scene.SetModel(CombineTargetDistances({ other, scene.GetPartsDistances() }));
  EXPECT_EQ(
    scene.GetTargetNames(), (std::vector<std::string>{ "Neutral", "shape0", "shape2", "shape1" }));
  EXPECT_EQ(scene.GetPartTargets(0), (std::vector<size_t>{ 0, 3 }));
  EXPECT_DOUBLE_EQ(scene.GetTargetDistances().DistNorm[1], 1.0);
  scene.SetWeightMode(WeightMode::Relative);
  scene.SetWeights({ 0.0, 0.5, 0.0, 0.25 });
  EXPECT_EQ(scene.GetPartWeights(0), (std::vector<double>{ 0.75, 0.25 }));
  EXPECT_EQ(scene.GetActiveTargetCount(), 2);
}

TEST(MorphScene, BadInputIsAnInputError)
{
  const Model m = MakeModel(50, 2, 8);
  const auto good = Piece(m, 0, 50, { 0, 1 });
  MorphScene scene;
  EXPECT_THROW(scene.SetParts({}), InputError);
  EXPECT_THROW(scene.SetParts({ good, nullptr }), InputError);
  EXPECT_THROW(scene.SetParts({ good }, { std::vector<uint8_t>(49, 0) }), InputError);
  EXPECT_THROW(scene.SetParts({ good }, { {}, {} }), InputError);
  auto twice = std::make_shared<MorphMesh>(*good);
  twice->SetTargetNames({ "Neutral", "shape0", "shape0" });
  EXPECT_THROW(scene.SetParts({ twice }), InputError);
  auto likeNeutral = std::make_shared<MorphMesh>(*good);
  likeNeutral->SetTargetNames({ "Base", "Neutral", "shape1" });
  EXPECT_THROW(scene.SetParts({ good, likeNeutral }), InputError);
  try
  {
    scene.SetParts({ good, likeNeutral });
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("'Neutral', the name of the neutral"), std::string::npos)
      << e.what();
  }
  auto broken = std::make_shared<MorphMesh>(*good);
  broken->SetTargetNames({ "Neutral", "shape0" }); // two targets' deltas, one name
  EXPECT_THROW(scene.SetParts({ good, broken }), InputError);

  scene.SetParts({ good });
  EXPECT_THROW(scene.SetModel({ { "Neutral", "shape0" }, { 0, 1 }, { 0, 1 } }), InputError)
    << "shape1 of the part is missing from the model";
  EXPECT_THROW(
    scene.SetModel({ { "Neutral", "shape0", "shape1" }, { 0, 1 }, { 0, 1, 1 } }), InputError);
  EXPECT_THROW(scene.SetWeights({ 1.0, 0.0 }), InputError) << "two weights for three targets";
  EXPECT_FALSE(scene.HasEffectiveWeights());
  EXPECT_THROW(scene.SetWeights({ 1.0, NAN, 0.0 }), InputError);
  EXPECT_THROW(scene.GetPartNode(1), InputError);
  EXPECT_THROW(CombineTargetDistances({}), InputError);
  EXPECT_THROW(CombineTargetDistances({ { {}, {}, {} } }), InputError);
}

// The blend plan covers every point of the parts asked for exactly once, in tasks of about
// the grain, serial when there is too little work; its tasks blend what one Blend does.
TEST(MorphScene, BlendPlanCoversEveryPointOnce)
{
  const Model m = MakeModel(9000, 4, 7);
  MorphScene scene;
  scene.SetParts({ Piece(m, 0, 100, AllTargets(m)), Piece(m, 100, 6000, AllTargets(m)),
    Piece(m, 6000, 9000, { 1 }) });
  std::mt19937 rng(3);
  scene.SetWeightMode(WeightMode::Relative);
  scene.SetWeights(RandomWeights(scene.GetNumberOfTargets(), rng));
  BlendPlan plan;
  scene.PlanBlend({ 0, 2 }, 1, plan);
  EXPECT_TRUE(plan.Serial);
  EXPECT_EQ(plan.GetNumberOfTasks(), 1u);
  scene.PlanBlend({ 0, 1, 2 }, 4, plan);
  EXPECT_FALSE(plan.Serial);
  ASSERT_GT(plan.GetNumberOfTasks(), 1u);
  std::vector<std::vector<int>> seen(3);
  for (size_t p = 0; p < 3; ++p)
  {
    seen[p].assign(scene.GetPart(p).GetNumberOfPoints(), 0);
  }
  for (size_t t = 0; t < plan.GetNumberOfTasks(); ++t)
  {
    size_t points = 0;
    for (size_t r = plan.Tasks[t]; r < plan.Tasks[t + 1]; ++r)
    {
      for (size_t i = plan.Ranges[r].Begin; i < plan.Ranges[r].End; ++i)
      {
        ++seen[plan.Ranges[r].Part][i];
      }
      points += plan.Ranges[r].End - plan.Ranges[r].Begin;
    }
    EXPECT_GE(points, t + 1 < plan.GetNumberOfTasks() ? MinPointsPerBlendTask : 1u);
  }
  for (const auto& part : seen)
  {
    EXPECT_TRUE(std::all_of(part.begin(), part.end(), [](int n) { return n == 1; }));
  }
  // Tasks of equal size, a multiple of the threads: 9,000 points on 2 threads are 4 tasks of
  // 2,250 (not 2,048 x 4 and 808, which leaves one thread a task more than the other).
  scene.PlanBlend({ 0, 1, 2 }, 2, plan);
  ASSERT_EQ(plan.GetNumberOfTasks(), 4u);
  for (size_t t = 0; t < plan.GetNumberOfTasks(); ++t)
  {
    size_t points = 0;
    for (size_t r = plan.Tasks[t]; r < plan.Tasks[t + 1]; ++r)
    {
      points += plan.Ranges[r].End - plan.Ranges[r].Begin;
    }
    EXPECT_EQ(points, 2250u) << "task " << t;
  }
  // Too little work for two tasks: serial however many threads.
  scene.PlanBlend({ 0 }, 8, plan);
  EXPECT_TRUE(plan.Serial);
  // The tasks blend what one Blend per part does.
  const std::vector<std::vector<float>> whole = BlendScene(scene);
  std::vector<std::vector<float>> points(3), normals(3);
  std::vector<std::vector<AttributeOutput>> where(3);
  std::vector<const std::vector<AttributeOutput>*> outputs(3);
  for (size_t p = 0; p < 3; ++p)
  {
    points[p].assign(3 * scene.GetPart(p).GetNumberOfPoints(), 0.f);
    normals[p].assign(points[p].size(), 0.f);
    where[p] = { points[p].data(), normals[p].data() };
    outputs[p] = &where[p];
  }
  scene.PlanBlend({ 0, 1, 2 }, 4, plan);
  for (size_t t = plan.GetNumberOfTasks(); t-- > 0;) // any order
  {
    scene.BlendTask(plan, t, outputs);
  }
  std::vector<float> joined;
  for (const auto& part : points)
  {
    joined.insert(joined.end(), part.begin(), part.end());
  }
  EXPECT_EQ(joined, whole[0]);
}
