// SPDX-License-Identifier: BSD-3-Clause
#include "rig/RigOptimizer.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <unordered_map>
#include <variant>

namespace morphnode
{
NamedTargetDistances ComputeShapeDistances(const Rig& rig, const MorphMesh& part)
{
  const int position = part.GetPositionAttribute();
  if (position < 0)
  {
    throw InputError("rig '" + rig.GetName() + "': the part has no positions to measure shapes on");
  }
  const auto& names = part.GetTargetNames();
  std::unordered_map<std::string, size_t> index; // face target name -> target index (>= 1)
  for (size_t t = 1; t < names.size(); ++t)
  {
    index.emplace(names[t], t); // first occurrence wins, as in MorphMesh::FindTarget
  }
  const size_t numShapes = rig.GetNumberOfShapes();
  NamedTargetDistances result;
  result.Names.push_back(names.empty() ? std::string("Neutral") : names[0]);
  result.Names.insert(result.Names.end(), rig.GetShapeNames().begin(), rig.GetShapeNames().end());
  result.DistMorph.assign(numShapes + 1, 0.0);
  result.MaxDisplacement.assign(numShapes + 1, 0.0);
  std::visit(
    [&](const auto& attribute)
    {
      using T = typename std::decay_t<decltype(attribute.GetNeutral())>::value_type;
      const size_t numPoints = part.GetNumberOfPoints();
      const size_t numValues = numPoints * 3;
      std::unordered_map<size_t, std::vector<T>> dense; // each target decoded once
      std::vector<double> sum(numValues);
      for (size_t s = 0; s < numShapes; ++s)
      {
        std::fill(sum.begin(), sum.end(), 0.0);
        bool moved = false;
        for (const RigTerm& term : rig.GetShapeTerms(s))
        {
          const auto found = index.find(term.Target);
          if (found == index.end() || term.Coefficient == 0.0)
          {
            continue;
          }
          auto& deltas = dense[found->second];
          if (deltas.empty())
          {
            deltas.resize(numValues);
            attribute.GetTarget(found->second).ToDense(deltas.data());
          }
          for (size_t v = 0; v < numValues; ++v)
          {
            sum[v] += term.Coefficient * static_cast<double>(deltas[v]);
          }
          moved = true;
        }
        if (!moved)
        {
          continue;
        }
        double total = 0.0, largest = 0.0;
        for (size_t p = 0; p < numPoints; ++p)
        {
          const double* d = &sum[3 * p];
          const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          total += norm;
          largest = std::max(largest, norm);
        }
        result.DistMorph[s + 1] = total;
        result.MaxDisplacement[s + 1] = largest;
      }
    },
    part.GetAttribute(static_cast<size_t>(position)));
  return result;
}

void RigOptimizer::SetShapeDistances(const TargetDistances& distances)
{
  this->Optimizer.SetTargetDistances(distances);
}

size_t RigOptimizer::GetNumberOfShapes() const
{
  const size_t n = this->Optimizer.GetTargetDistances().MaxDisplacement.size();
  return n > 0 ? n - 1 : 0;
}

void RigOptimizer::Optimize(const double* shapeWeights, double* effective)
{
  const size_t numShapes = this->GetNumberOfShapes();
  if (this->Optimizer.GetTargetDistances().MaxDisplacement.empty())
  {
    throw InputError("the rig optimizer has no shape distances (SetShapeDistances)");
  }
  this->Absolute.resize(numShapes + 1);
  double sum = 0.0;
  for (size_t s = 0; s < numShapes; ++s)
  {
    if (!std::isfinite(shapeWeights[s]))
    {
      throw InputError("a shape weight is not finite");
    }
    this->Absolute[s + 1] = shapeWeights[s];
    sum += shapeWeights[s];
  }
  this->Absolute[0] = 1.0 - sum;
  this->LastErrorBound = 0.0;
  int active = 0;
  if (this->Optimizer.GetSettings().IsActive())
  {
    const std::vector<double> e = this->Optimizer.Optimize(this->Absolute);
    this->LastErrorBound = this->Optimizer.GetLastErrorBound();
    for (size_t s = 0; s < numShapes; ++s)
    {
      effective[s] = e[s + 1];
    }
  }
  else
  {
    std::copy(shapeWeights, shapeWeights + numShapes, effective);
  }
  for (size_t s = 0; s < numShapes; ++s)
  {
    active += effective[s] != 0.0 ? 1 : 0;
  }
  this->LastActiveShapes = active;
}

std::vector<std::vector<double>> ExpandShapeFrames(const Rig& rig,
  const std::vector<ShapeWeightColumn>& columns, size_t frames, RigOptimizer* optimizer)
{
  for (const ShapeWeightColumn& column : columns)
  {
    if (column.Values.size() < frames || column.Shape >= rig.GetNumberOfShapes())
    {
      throw InputError("the weights column '" + column.Name + "' has " +
        std::to_string(column.Values.size()) + " values for " + std::to_string(frames) +
        " frames, or names no shape of the rig");
    }
  }
  std::vector<std::vector<double>> out(
    rig.GetNumberOfBoundTargets(), std::vector<double>(frames, 0.0));
  std::vector<double> shapes(rig.GetNumberOfShapes());
  std::vector<double> effective(rig.GetNumberOfShapes());
  std::vector<double> targets(rig.GetNumberOfBoundTargets());
  for (size_t f = 0; f < frames; ++f)
  {
    std::fill(shapes.begin(), shapes.end(), 0.0);
    for (const ShapeWeightColumn& column : columns)
    {
      const double w = column.Values[f];
      if (!std::isfinite(w))
      {
        std::ostringstream msg;
        msg << "row " << f << " of column '" << column.Name << "' is not finite (" << w << ")";
        throw InputError(msg.str());
      }
      shapes[column.Shape] += w;
    }
    if (optimizer)
    {
      optimizer->Optimize(shapes.data(), effective.data());
      rig.Expand(effective.data(), targets.data());
    }
    else
    {
      rig.Expand(shapes.data(), targets.data());
    }
    for (size_t t = 0; t < targets.size(); ++t)
    {
      out[t][f] = targets[t];
    }
  }
  return out;
}
} // namespace morphnode
