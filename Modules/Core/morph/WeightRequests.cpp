// SPDX-License-Identifier: BSD-3-Clause
#include "morph/WeightRequests.h"

#include "base/Error.h"

#include <algorithm>
#include <sstream>

namespace morphnode
{
void WeightRequests::SetByIndex(size_t index, double weight)
{
  if (index >= this->ByIndex.size())
  {
    this->ByIndex.resize(index + 1);
  }
  this->ByIndex[index] = { weight, ++this->Orders };
}

void WeightRequests::SetByName(const std::string& name, double weight)
{
  for (NamedRequest& n : this->ByName)
  {
    if (n.Name == name)
    {
      n.Value = { weight, ++this->Orders };
      return;
    }
  }
  this->ByName.push_back({ name, { weight, ++this->Orders }, this->FindTarget(name) });
}

bool WeightRequests::Clear()
{
  if (this->Empty())
  {
    return false;
  }
  this->ByIndex.clear();
  this->ByName.clear();
  return true;
}

void WeightRequests::SetTargets(const std::vector<std::string>& names)
{
  this->Names = names;
  this->Lookup.clear();
  for (size_t i = 0; i < names.size(); ++i)
  {
    this->Lookup.emplace(names[i], static_cast<int>(i)); // the first of a name, as MorphMesh
  }
  for (NamedRequest& n : this->ByName)
  {
    n.Index = this->FindTarget(n.Name);
  }
}

int WeightRequests::FindTarget(const std::string& name) const
{
  const auto found = this->Lookup.find(name);
  return found == this->Lookup.end() ? -1 : found->second;
}

double WeightRequests::Get(size_t index) const
{
  Request r{ index == 0 ? 1.0 : 0.0, 0 };
  if (index < this->ByIndex.size() && this->ByIndex[index].Order)
  {
    r = this->ByIndex[index];
  }
  for (const NamedRequest& n : this->ByName)
  {
    if (n.Index >= 0 && static_cast<size_t>(n.Index) == index && n.Value.Order > r.Order)
    {
      r = n.Value;
    }
  }
  return r.Weight;
}

double WeightRequests::GetByName(const std::string& name) const
{
  const int index = this->FindTarget(name);
  if (index >= 0)
  {
    return this->Get(static_cast<size_t>(index));
  }
  for (const NamedRequest& n : this->ByName) // not resolvable: the value set
  {
    if (n.Name == name)
    {
      return n.Value.Weight;
    }
  }
  return 0.0;
}

void WeightRequests::Resolve(std::vector<double>& requested) const
{
  const size_t n = this->Names.size();
  requested.assign(n, 0.0);
  if (n > 0)
  {
    requested[0] = 1.0;
  }
  // Which request set a weight, only needed when names may override indices: no allocation
  // on the usual step (every weight set by index).
  std::vector<uint64_t> order(this->ByName.empty() ? 0 : n, 0);
  // The first error in the order the weights were set, as a user would read them.
  size_t outOfRange = 0;
  uint64_t outOfRangeOrder = 0, unknownOrder = 0;
  const NamedRequest* unknown = nullptr;
  for (size_t i = 0; i < this->ByIndex.size(); ++i)
  {
    const Request& r = this->ByIndex[i];
    if (r.Order && i >= n && (!outOfRangeOrder || r.Order < outOfRangeOrder))
    {
      outOfRange = i;
      outOfRangeOrder = r.Order;
    }
    else if (r.Order && i < n)
    {
      requested[i] = r.Weight;
      if (!order.empty())
      {
        order[i] = r.Order;
      }
    }
  }
  for (const NamedRequest& named : this->ByName)
  {
    if (named.Index < 0)
    {
      if (!unknown || named.Value.Order < unknownOrder)
      {
        unknown = &named;
        unknownOrder = named.Value.Order;
      }
      continue;
    }
    const size_t i = static_cast<size_t>(named.Index);
    if (named.Value.Order > order[i])
    {
      requested[i] = named.Value.Weight;
      order[i] = named.Value.Order;
    }
  }
  if (outOfRangeOrder && (!unknown || outOfRangeOrder < unknownOrder))
  {
    std::ostringstream msg; // made only for an error: a stream costs more than the rest
    msg << "a weight is set for target " << outOfRange << ", but the input has " << n
        << " targets (0.." << (n > 0 ? n - 1 : 0) << ", neutral first)";
    throw InputError(msg.str());
  }
  if (unknown)
  {
    std::ostringstream msg;
    msg << "a weight is set for target '" << unknown->Name
        << "', but no target has that name; targets:";
    for (const std::string& name : this->Names)
    {
      msg << " " << name;
    }
    throw InputError(msg.str());
  }
}

std::string WeightRequests::Describe() const
{
  std::ostringstream out;
  const char* separator = "";
  for (size_t i = 0; i < this->ByIndex.size(); ++i)
  {
    if (this->ByIndex[i].Order)
    {
      out << separator << i << "=" << this->ByIndex[i].Weight;
      separator = " ";
    }
  }
  for (const NamedRequest& named : this->ByName)
  {
    out << separator << named.Name << "=" << named.Value.Weight;
    separator = " ";
  }
  return out.str();
}

double ImplicitNeutralWeight(const std::vector<double>& weights)
{
  double others = 0.0;
  for (size_t i = 1; i < weights.size(); ++i)
  {
    others += weights[i];
  }
  return std::max(0.0, 1.0 - others);
}
} // namespace morphnode
