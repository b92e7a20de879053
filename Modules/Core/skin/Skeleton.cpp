// SPDX-License-Identifier: BSD-3-Clause
#include "skin/Skeleton.h"

#include "base/Error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace morphnode
{
namespace
{
bool Finite(const glm::dmat4& m)
{
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 4; ++r)
    {
      if (!std::isfinite(m[c][r]))
      {
        return false;
      }
    }
  }
  return true;
}
} // namespace

glm::dmat4 Joint::Local() const
{
  if (this->HasMatrix)
  {
    return this->Matrix;
  }
  glm::dmat4 m = glm::mat4_cast(this->Rotation);
  for (int c = 0; c < 3; ++c)
  {
    m[c] *= this->Scale[c];
  }
  m[3] = glm::dvec4(this->Translation, 1.0);
  return m;
}

int Skeleton::AddJoint(const Joint& joint)
{
  this->Joints.push_back(joint);
  this->Valid = false;
  return static_cast<int>(this->Joints.size() - 1);
}

int Skeleton::FindJoint(const std::string& name) const
{
  for (size_t i = 0; i < this->Joints.size(); ++i)
  {
    if (this->Joints[i].Name == name)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

void Skeleton::Validate()
{
  if (this->Valid)
  {
    return;
  }
  const size_t n = this->Joints.size();
  for (size_t i = 0; i < n; ++i)
  {
    const Joint& j = this->Joints[i];
    const std::string what = "skeleton: joint " + std::to_string(i) + " (" + j.Name + ")";
    if (j.Parent < -1 || j.Parent >= static_cast<int>(n) || j.Parent == static_cast<int>(i))
    {
      throw InputError(what + ": parent " + std::to_string(j.Parent) + " is not another joint");
    }
    if (!Finite(j.Local()))
    {
      throw InputError(what + ": its transform is not finite");
    }
    if (!j.HasMatrix && std::abs(glm::length(j.Rotation) - 1.0) > 1e-3)
    {
      throw InputError(what + ": its rotation is not a unit quaternion");
    }
  }
  // Parents first: depth by walking up, a walk longer than n is a cycle.
  std::vector<size_t> depth(n, 0);
  for (size_t i = 0; i < n; ++i)
  {
    size_t d = 0;
    for (int p = this->Joints[i].Parent; p >= 0; p = this->Joints[static_cast<size_t>(p)].Parent)
    {
      if (++d > n)
      {
        throw InputError("skeleton: joint " + std::to_string(i) + " (" + this->Joints[i].Name +
          ") is its own ancestor (the parents form a cycle)");
      }
    }
    depth[i] = d;
  }
  this->Order.clear();
  for (size_t d = 0; this->Order.size() < n; ++d)
  {
    for (size_t i = 0; i < n; ++i)
    {
      if (depth[i] == d)
      {
        this->Order.push_back(static_cast<int>(i));
      }
    }
  }
  this->Valid = true;
}

std::vector<glm::dmat4> Skeleton::RestLocals() const
{
  std::vector<glm::dmat4> out;
  out.reserve(this->Joints.size());
  for (const auto& j : this->Joints)
  {
    out.push_back(j.Local());
  }
  return out;
}

std::vector<glm::dmat4> Skeleton::World(const std::vector<glm::dmat4>& locals) const
{
  if (!this->Valid)
  {
    throw InputError("skeleton: not validated (internal check)");
  }
  if (locals.size() != this->Joints.size())
  {
    throw InputError("skeleton: " + std::to_string(locals.size()) + " local transforms for " +
      std::to_string(this->Joints.size()) + " joints");
  }
  std::vector<glm::dmat4> world(locals.size());
  for (int i : this->Order)
  {
    const int p = this->Joints[static_cast<size_t>(i)].Parent;
    world[static_cast<size_t>(i)] = p < 0
      ? locals[static_cast<size_t>(i)]
      : world[static_cast<size_t>(p)] * locals[static_cast<size_t>(i)];
  }
  return world;
}

glm::dmat4 Skeleton::WorldOf(const std::vector<glm::dmat4>& locals, int joint) const
{
  glm::dmat4 m(1.0);
  for (int j = joint; j >= 0; j = this->Joints.at(static_cast<size_t>(j)).Parent)
  {
    m = locals.at(static_cast<size_t>(j)) * m;
  }
  return m;
}

bool Skeleton::IsAncestor(int ancestor, int joint) const
{
  for (int j = joint; j >= 0; j = this->Joints.at(static_cast<size_t>(j)).Parent)
  {
    if (j == ancestor)
    {
      return true;
    }
  }
  return false;
}

SkeletonPose::SkeletonPose(const Skeleton& skeleton)
  : Bones(&skeleton)
  , Locals(skeleton.RestLocals())
{
}

void SkeletonPose::SetLocal(int joint, const glm::dmat4& local)
{
  this->Locals.at(static_cast<size_t>(joint)) = local;
}

void SkeletonPose::Reset()
{
  this->Locals = this->Bones->RestLocals();
}

void SkeletonPose::TurnJoint(int joint, const glm::dquat& rotation)
{
  const size_t j = static_cast<size_t>(joint);
  if (j >= this->Locals.size())
  {
    throw InputError("skeleton: no joint " + std::to_string(joint) + " to turn");
  }
  if (rotation == glm::dquat(1.0, 0.0, 0.0, 0.0))
  {
    return; // no turn: the pose stays exactly as it is
  }
  const int parent = this->Bones->GetJoint(j).Parent;
  const glm::dmat4 parentWorld =
    parent < 0 ? glm::dmat4(1.0) : this->Bones->WorldOf(this->Locals, parent);
  const glm::dmat4 world = parentWorld * this->Locals[j];
  const glm::dvec3 pivot(world[3]);
  const glm::dmat4 turn = glm::translate(glm::dmat4(1.0), pivot) *
    glm::mat4_cast(glm::normalize(rotation)) * glm::translate(glm::dmat4(1.0), -pivot);
  this->Locals[j] = glm::inverse(parentWorld) * turn * world;
}
} // namespace morphnode
