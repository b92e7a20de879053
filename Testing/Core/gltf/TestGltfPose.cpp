// SPDX-License-Identifier: BSD-3-Clause
// gltf/GltfPose.h on the animated test head (GltfAnimatedTestFiles.h): the rest pose applies
// nothing, a sample's weights blend into the points (base + w * delta) and its transforms
// move the parts, the time defaults to the animation's start and must be finite; time steps
// at the keys or on a grid with the end; the parts' target names in order of first
// appearance; one mesh's part by name or index, with errors that name what there is.

#include "gltf/GltfPose.h"

#include "GltfAnimatedTestFiles.h"
#include "base/Error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace
{
using morphnode::GltfScene;
using morphnode::InputError;

GltfScene Head(bool applyTransforms)
{
  const std::string bytes = gltftest::AnimatedHead().Glb();
  morphnode::GltfLoadOptions options;
  options.ApplyTransforms = applyTransforms;
  return morphnode::LoadGltfSceneFromMemory(
    bytes.data(), bytes.size(), std::string(), options, "head.glb");
}
} // namespace

TEST(GltfPose, RestPoseAppliesNothing)
{
  const GltfScene scene = Head(true);
  morphnode::GltfPoseOptions options;
  options.ApplyTransforms = options.ApplyWeights = true; // ignored without an animation
  const morphnode::GltfPose pose = morphnode::PoseGltfScene(scene, options);
  EXPECT_EQ(pose.Time, 0.0);
  EXPECT_TRUE(pose.AnimatedNodes.empty());
  EXPECT_FALSE(pose.Options.ApplyTransforms || pose.Options.ApplyWeights);
  ASSERT_EQ(pose.Worlds.size(), scene.Nodes.size());
  const morphnode::GltfPart posed = morphnode::PoseGltfPart(scene, pose, scene.Parts[0]);
  EXPECT_EQ(posed.Positions, scene.Parts[0].Positions);
}

TEST(GltfPose, SampleBlendsWeightsAndMovesParts)
{
  const GltfScene scene = Head(false);
  morphnode::GltfPoseOptions options;
  options.Animation = 0;
  options.Time = 0.9;
  options.ApplyWeights = true;
  const morphnode::GltfPose pose = morphnode::PoseGltfScene(scene, options);
  EXPECT_EQ(pose.Time, 0.9);
  const morphnode::GltfPart& face = scene.Parts[0];
  const morphnode::GltfPart posed = morphnode::PoseGltfPart(scene, pose, face);
  const std::vector<double>& w = pose.Sample.Nodes[static_cast<size_t>(face.Node)].Weights;
  ASSERT_EQ(w.size(), face.Targets.size());
  for (size_t i = 0; i < face.Positions.size(); ++i)
  {
    double expected = face.Positions[i];
    for (size_t k = 0; k < w.size(); ++k)
    {
      expected += w[k] * face.Targets[k].PositionDeltas[i];
    }
    EXPECT_NEAR(posed.Positions[i], expected, 1e-6) << i;
  }
  EXPECT_FALSE(posed.TransformApplied) << "weights only";

  // Transforms: the part moves by its node's sampled world transform.
  options.ApplyWeights = false;
  options.ApplyTransforms = true;
  options.Animation = 3; // "Pose": moves nodes 0 and 2
  options.Time.reset();
  const morphnode::GltfPose moved = morphnode::PoseGltfScene(scene, options);
  EXPECT_EQ(moved.Time, 0.0) << "the animation's start";
  EXPECT_EQ(moved.AnimatedNodes, (std::vector<int>{ 0, 2 }));
  const morphnode::GltfPart turned = morphnode::PoseGltfPart(scene, moved, face);
  EXPECT_TRUE(turned.TransformApplied);
  EXPECT_EQ(turned.World, moved.Worlds[static_cast<size_t>(face.Node)]);

  options.Time = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(morphnode::PoseGltfScene(scene, options), InputError);
  options.Time = 0.0;
  options.Animation = 9;
  EXPECT_THROW(morphnode::PoseGltfScene(scene, options), InputError);
}

TEST(GltfPose, TimeSteps)
{
  const GltfScene scene = Head(true);
  const morphnode::GltfAnimationPlayer player(scene, 3); // keys 0, 0.5, 1.25, 2
  EXPECT_EQ(morphnode::GltfTimeSteps(player, 0.0), (std::vector<double>{ 0, 0.5, 1.25, 2 }));
  EXPECT_EQ(morphnode::GltfTimeSteps(player, 2.0), (std::vector<double>{ 0, 0.5, 1, 1.5, 2 }));
  const std::vector<double> odd = morphnode::GltfTimeSteps(player, 1.5);
  ASSERT_FALSE(odd.empty());
  EXPECT_DOUBLE_EQ(odd.back(), 2.0) << "the end is a step";
}

TEST(GltfPose, TargetNamesAndParts)
{
  const GltfScene scene = Head(true);
  // The face's jawOpen, smile, eyeBlinkLeft; the teeth's jawOpen again.
  EXPECT_EQ(morphnode::GltfTargetNames(scene),
    (std::vector<std::string>{ "jawOpen", "smile", "eyeBlinkLeft" }));
  const morphnode::GltfPart& first = morphnode::FindGltfPart(scene, "", -1, -1, "head.glb");
  EXPECT_EQ(first.Mesh, 0);
  EXPECT_EQ(first.Primitive, 0);
  const std::string name = morphnode::GltfMeshName(scene, 1);
  EXPECT_EQ(morphnode::FindGltfPart(scene, name, -1, 0, "head.glb").Mesh, 1);
  try
  {
    morphnode::FindGltfPart(scene, "Nope", -1, 0, "head.glb");
    ADD_FAILURE() << "a mesh that is not there";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("has no mesh named 'Nope'; meshes:"), std::string::npos)
      << e.what();
  }
  EXPECT_THROW(morphnode::FindGltfPart(scene, "", 99, 0, "head.glb"), InputError);
  EXPECT_THROW(morphnode::FindGltfPart(scene, "", 0, 5, "head.glb"), InputError);
}
