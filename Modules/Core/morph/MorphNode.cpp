// SPDX-License-Identifier: BSD-3-Clause
#include "morph/MorphNode.h"

#include "base/Error.h"

#include <algorithm>
#include <sstream>

namespace morphnode
{
MorphNode::MorphNode(std::shared_ptr<const MorphMesh> mesh)
{
  this->SetMesh(std::move(mesh));
}

void MorphNode::SetMesh(std::shared_ptr<const MorphMesh> mesh)
{
  this->ClearDecision();
  if (mesh)
  {
    mesh->Validate();
    this->SetTargetDistances(mesh->ComputeDistances());
  }
  else
  {
    this->SetTargetDistances(TargetDistances{});
  }
  this->Mesh = std::move(mesh);
}

size_t MorphNode::GetNumberOfTargets() const
{
  return this->Mesh ? this->Mesh->GetNumberOfTargets() : 0;
}

const std::vector<double>& MorphNode::SetWeights(const double* requested, size_t count)
{
  this->ClearDecision();
  if (!this->Mesh)
  {
    throw InputError("the morph node has no mesh to blend");
  }
  const size_t n = this->Mesh->GetNumberOfTargets();
  if (count != n)
  {
    std::ostringstream msg;
    msg << "the morph node got " << count << " weights for " << n << " targets (neutral first)";
    throw InputError(msg.str());
  }
  return this->Decide(requested, count);
}

void MorphNode::CheckOutputs(const std::vector<AttributeOutput>& outputs) const
{
  if (!this->Mesh || !this->HasEffectiveWeights())
  {
    throw InputError("the morph node has no effective weights to blend with: set weights first");
  }
  const size_t numAttributes = this->Mesh->GetNumberOfAttributes();
  if (outputs.size() != numAttributes)
  {
    std::ostringstream msg;
    msg << "the blend got " << outputs.size() << " outputs for " << numAttributes << " attributes";
    throw InputError(msg.str());
  }
  for (size_t a = 0; a < numAttributes; ++a)
  {
    const bool storedAsFloat =
      std::holds_alternative<MorphAttribute<float>>(this->Mesh->GetAttribute(a));
    const bool outputIsFloat = std::holds_alternative<float*>(outputs[a]);
    const bool null = std::visit([](auto* p) { return p == nullptr; }, outputs[a]);
    if (storedAsFloat != outputIsFloat || null)
    {
      std::ostringstream msg;
      msg << "the blend's output " << a << " must be a non-null "
          << (storedAsFloat ? "float" : "double") << " buffer";
      throw InputError(msg.str());
    }
  }
}

void MorphNode::Blend(const std::vector<AttributeOutput>& outputs, size_t begin, size_t end) const
{
  this->CheckOutputs(outputs);
  end = std::min(end, this->Mesh->GetNumberOfPoints());
  if (begin >= end)
  {
    return;
  }
  const double* weights = this->GetEffectiveWeights().data();
  const size_t numWeights = this->GetEffectiveWeights().size();
  for (size_t a = 0; a < outputs.size(); ++a)
  {
    std::visit(
      [&](const auto& attribute)
      {
        using T = typename std::decay_t<decltype(attribute.GetNeutral())>::value_type;
        attribute.Blend(weights, numWeights, std::get<T*>(outputs[a]), begin, end);
      },
      this->Mesh->GetAttribute(a));
  }
}

template <typename T>
void MorphNode::BlendAttribute(size_t attribute, T* out, size_t begin, size_t end) const
{
  if (!this->Mesh || !this->HasEffectiveWeights())
  {
    throw InputError("the morph node has no effective weights to blend with: set weights first");
  }
  if (attribute >= this->Mesh->GetNumberOfAttributes())
  {
    std::ostringstream msg;
    msg << "the mesh has no attribute " << attribute << " (it has "
        << this->Mesh->GetNumberOfAttributes() << ")";
    throw InputError(msg.str());
  }
  const auto* stored = std::get_if<MorphAttribute<T>>(&this->Mesh->GetAttribute(attribute));
  if (!stored || !out)
  {
    std::ostringstream msg;
    msg << "attribute " << attribute << " is not stored as "
        << (sizeof(T) == 4 ? "float" : "double") << ", or its output is null";
    throw InputError(msg.str());
  }
  end = std::min(end, this->Mesh->GetNumberOfPoints());
  if (begin < end)
  {
    stored->Blend(
      this->GetEffectiveWeights().data(), this->GetEffectiveWeights().size(), out, begin, end);
  }
}

template void MorphNode::BlendAttribute<float>(size_t, float*, size_t, size_t) const;
template void MorphNode::BlendAttribute<double>(size_t, double*, size_t, size_t) const;
} // namespace morphnode
