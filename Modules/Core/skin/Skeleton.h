// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Skeleton.h
/// @brief A hierarchy of joints with their rest transforms, and poses of it.
///
/// A joint's local transform is T * R * S (translation, unit rotation, scale) as glTF
/// composes a node's, or a matrix given as is. Its world transform is its parents' world
/// transforms times its local one, root first. A pose overrides local transforms; the
/// typical change is a turn of a joint about its own pivot (TurnJoint), which moves the
/// joint's children with it, as a neck carries the head and the head the eyes.

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <string>
#include <vector>

namespace morphnode
{
struct Joint
{
  std::string Name;
  int Parent = -1; ///< another joint's index, -1 for a root
  glm::dvec3 Translation{ 0.0 };
  glm::dquat Rotation{ 1.0, 0.0, 0.0, 0.0 }; ///< w, x, y, z (GLM's order)
  glm::dvec3 Scale{ 1.0 };
  /// When true, Matrix is the local transform and the TRS fields are unused.
  bool HasMatrix = false;
  glm::dmat4 Matrix{ 1.0 };

  glm::dmat4 Local() const;
};

class Skeleton
{
public:
  /// Adds a joint; parents may be added before or after their children (the order is
  /// checked by Validate()). Returns its index.
  int AddJoint(const Joint& joint);
  size_t GetNumberOfJoints() const { return this->Joints.size(); }
  const Joint& GetJoint(size_t index) const { return this->Joints.at(index); }
  /// The first joint with exactly this name, -1 if none.
  int FindJoint(const std::string& name) const;

  /// Checks parents (in range, no cycle), finite transforms and unit rotations, and orders
  /// the joints parents first. Throws InputError. Called by every function below that needs it.
  void Validate();

  /// The rest (as stored) local transforms.
  std::vector<glm::dmat4> RestLocals() const;
  /// World transforms from local ones (one per joint).
  std::vector<glm::dmat4> World(const std::vector<glm::dmat4>& locals) const;
  /// The world transform of one joint.
  glm::dmat4 WorldOf(const std::vector<glm::dmat4>& locals, int joint) const;
  /// True when `ancestor` is `joint` or one of its parents.
  bool IsAncestor(int ancestor, int joint) const;

private:
  std::vector<Joint> Joints;
  std::vector<int> Order; ///< parents first
  bool Valid = false;
};

/// Local transforms of a skeleton's joints, starting at rest.
class SkeletonPose
{
public:
  explicit SkeletonPose(const Skeleton& skeleton);

  const Skeleton& GetSkeleton() const { return *this->Bones; }
  const std::vector<glm::dmat4>& GetLocals() const { return this->Locals; }
  void SetLocal(int joint, const glm::dmat4& local);
  /// Back to rest.
  void Reset();

  /// Turns `joint` by `rotation`, a rotation in WORLD axes, about the joint's own world
  /// origin (its pivot) as the pose has it now: the joint's world transform W becomes
  /// T(c) R T(-c) W, c = W's origin, and its children follow. Turning a neck first and then
  /// the head composes as a body does.
  void TurnJoint(int joint, const glm::dquat& rotation);

  /// World transforms of every joint.
  std::vector<glm::dmat4> World() const { return this->Bones->World(this->Locals); }

private:
  const Skeleton* Bones;
  std::vector<glm::dmat4> Locals;
};
} // namespace morphnode
