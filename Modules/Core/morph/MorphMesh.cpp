// SPDX-License-Identifier: BSD-3-Clause
#include "morph/MorphMesh.h"

#include "base/Error.h"

#include <sstream>

namespace morphnode
{
int MorphMesh::FindTarget(const std::string& name) const
{
  for (size_t i = 0; i < this->TargetNames.size(); ++i)
  {
    if (this->TargetNames[i] == name)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

int MorphMesh::GetPositionAttribute() const
{
  for (size_t i = 0; i < this->Attributes.size(); ++i)
  {
    const bool isPosition = std::visit(
      [](const auto& a) { return a.GetRole() == AttributeRole::Position; }, this->Attributes[i]);
    if (isPosition)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

void MorphMesh::Validate() const
{
  if (this->TargetNames.empty())
  {
    throw InputError("the morph model has no targets, not even a neutral");
  }
  for (const auto& any : this->Attributes)
  {
    std::visit(
      [&](const auto& a)
      {
        if (a.GetNumberOfTargets() != this->TargetNames.size())
        {
          std::ostringstream msg;
          msg << "attribute '" << a.GetName() << "' has " << a.GetNumberOfTargets()
              << " targets, the model has " << this->TargetNames.size();
          throw InputError(msg.str());
        }
      },
      any);
  }
  if (this->Triangles.size() % 3 != 0)
  {
    throw InputError("the mesh's triangle list has " + std::to_string(this->Triangles.size()) +
      " point ids, not a multiple of 3");
  }
  for (size_t i = 0; i < this->Triangles.size(); ++i)
  {
    if (this->Triangles[i] >= this->NumPoints)
    {
      std::ostringstream msg;
      msg << "triangle " << i / 3 << " uses point id " << this->Triangles[i]
          << ", but the mesh has " << this->NumPoints << " points";
      throw InputError(msg.str());
    }
  }
}

TargetDistances MorphMesh::ComputeDistances() const
{
  const int p = this->GetPositionAttribute();
  if (p < 0)
  {
    const size_t n = this->TargetNames.size();
    return TargetDistances{ std::vector<double>(n, 0.0), std::vector<double>(n, 0.0),
      std::vector<double>(n, 0.0) };
  }
  return std::visit([](const auto& a) { return morphnode::ComputeTargetDistances(a); },
    this->Attributes[static_cast<size_t>(p)]);
}

std::vector<double> MorphMesh::ComputePointDistances(size_t target) const
{
  const int p = this->GetPositionAttribute();
  if (p < 0 || target == 0 || target >= this->TargetNames.size())
  {
    return std::vector<double>(this->NumPoints, 0.0);
  }
  return std::visit([&](const auto& a) { return morphnode::ComputePointDistances(a, target); },
    this->Attributes[static_cast<size_t>(p)]);
}

std::vector<double> MorphMesh::ComputeAnimatedRegion() const
{
  const int p = this->GetPositionAttribute();
  if (p < 0)
  {
    return std::vector<double>(this->NumPoints, 0.0);
  }
  return std::visit([](const auto& a) { return morphnode::ComputeAnimatedRegion(a); },
    this->Attributes[static_cast<size_t>(p)]);
}

std::vector<size_t> MorphMesh::MovedPointRanges() const
{
  std::vector<char> moved(this->NumPoints, 0);
  std::vector<double> norms;
  for (const auto& any : this->Attributes)
  {
    std::visit(
      [&](const auto& a)
      {
        for (size_t t = 1; t < a.GetNumberOfTargets(); ++t)
        {
          a.GetTarget(t).PointNorms(norms);
          for (size_t p = 0; p < norms.size() && p < moved.size(); ++p)
          {
            moved[p] = moved[p] || norms[p] != 0.0;
          }
        }
      },
      any);
  }
  std::vector<size_t> ranges;
  for (size_t p = 0; p < moved.size(); ++p)
  {
    if (moved[p] && (p == 0 || !moved[p - 1]))
    {
      ranges.push_back(p);
    }
    if (moved[p] && (p + 1 == moved.size() || !moved[p + 1]))
    {
      ranges.push_back(p + 1);
    }
  }
  return ranges;
}

size_t MorphMesh::GetMemorySize() const
{
  size_t bytes = 0;
  for (const auto& any : this->Attributes)
  {
    bytes += std::visit([](const auto& a) { return a.GetMemorySize(); }, any);
  }
  return bytes + this->Triangles.size() * sizeof(uint32_t);
}

std::vector<std::string> DefaultTargetNames(size_t numTargets)
{
  std::vector<std::string> names;
  names.reserve(numTargets);
  for (size_t i = 0; i < numTargets; ++i)
  {
    names.push_back(i == 0 ? "Neutral" : "target" + std::to_string(i - 1));
  }
  return names;
}
} // namespace morphnode
