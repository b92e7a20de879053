// SPDX-License-Identifier: BSD-3-Clause
// MorphMesh: the one mesh-with-named-targets type (its optional triangles, its attributes).
#include "base/Error.h"
#include "morph/MorphMesh.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace morphnode;

namespace
{
/// A unit square of 4 points with one target lifting point 2.
MorphMesh Square()
{
  MorphMesh mesh(4);
  mesh.SetTargetNames({ "Neutral", "lift" });
  const std::vector<float> neutral = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
  const std::vector<float> lift = { 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0 };
  auto& positions = mesh.AddAttribute<float>("Position", AttributeRole::Position, 3);
  positions.SetNeutral(neutral.data());
  positions.AddRelativeTarget(lift.data(), 0.3);
  return mesh;
}

std::string ValidateMessage(const MorphMesh& mesh)
{
  try
  {
    mesh.Validate();
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "valid";
}
} // namespace

TEST(MorphMesh, TrianglesAreOptionalAndChecked)
{
  MorphMesh mesh = Square();
  EXPECT_FALSE(mesh.HasTriangles());
  EXPECT_EQ(ValidateMessage(mesh), "valid");
  const size_t pointsOnly = mesh.GetMemorySize();

  mesh.SetTriangles({ 0, 1, 2, 0, 2, 3 });
  EXPECT_TRUE(mesh.HasTriangles());
  EXPECT_EQ(mesh.GetNumberOfTriangles(), 2u);
  EXPECT_EQ(ValidateMessage(mesh), "valid");
  EXPECT_EQ(mesh.GetMemorySize(), pointsOnly + 6 * sizeof(uint32_t));

  mesh.SetTriangles({ 0, 1, 2, 0, 2 });
  EXPECT_NE(ValidateMessage(mesh).find("5 point ids, not a multiple of 3"), std::string::npos);
  mesh.SetTriangles({ 0, 1, 2, 0, 2, 4 });
  EXPECT_NE(ValidateMessage(mesh).find("triangle 1 uses point id 4, but the mesh has 4 points"),
    std::string::npos);

  // A copy is a whole mesh: targets, attributes and triangles.
  mesh.SetTriangles({ 0, 1, 2 });
  const MorphMesh copy = mesh;
  EXPECT_EQ(copy.GetTriangles(), mesh.GetTriangles());
  EXPECT_EQ(copy.GetTargetNames(), mesh.GetTargetNames());
  EXPECT_NEAR(copy.ComputeDistances().DistMorph[1], 1.0, 1e-12);
}

TEST(MorphMesh, AttributeReferencesOutliveLaterAttributes)
{
  MorphMesh mesh(2);
  mesh.SetTargetNames({ "Neutral", "a" });
  auto& first = mesh.AddAttribute<double>("Position", AttributeRole::Position, 3);
  for (int i = 0; i < 40; ++i) // enough to make a vector reallocate
  {
    mesh.AddAttribute<float>("extra" + std::to_string(i), AttributeRole::Generic, 1);
  }
  const std::vector<double> neutral = { 0, 0, 0, 1, 0, 0 }, delta = { 0, 0, 0, 0, 2, 0 };
  first.SetNeutral(neutral.data());
  first.AddRelativeTarget(delta.data(), 0.5);
  EXPECT_EQ(&std::get<MorphAttribute<double>>(mesh.GetAttribute(0)), &first);
  EXPECT_EQ(mesh.GetPositionAttribute(), 0);
  EXPECT_EQ(mesh.ComputePointDistances(1), (std::vector<double>{ 0.0, 2.0 }));
}
