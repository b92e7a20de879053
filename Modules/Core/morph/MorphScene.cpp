// SPDX-License-Identifier: BSD-3-Clause
#include "morph/MorphScene.h"

#include "base/Error.h"

#include <algorithm>
#include <limits>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace morphnode
{
namespace
{
void CheckPiece(const NamedTargetDistances& piece, size_t index)
{
  std::ostringstream msg;
  if (piece.Names.empty())
  {
    msg << "piece " << index << " of the model has no targets (not even the neutral)";
  }
  else if (piece.DistMorph.size() != piece.Names.size() ||
    piece.MaxDisplacement.size() != piece.Names.size())
  {
    msg << "piece " << index << " of the model has " << piece.Names.size() << " target names but "
        << piece.DistMorph.size() << " dist_morph and " << piece.MaxDisplacement.size()
        << " largest displacements";
  }
  if (!msg.str().empty())
  {
    throw InputError(msg.str());
  }
}

/// The scene target index of every name of `names` (neutral first), checking that no name
/// appears twice and no target is named like `neutral`.
std::unordered_map<std::string, size_t> IndexNames(
  const std::vector<std::string>& names, const std::string& what)
{
  std::unordered_map<std::string, size_t> index;
  for (size_t i = 0; i < names.size(); ++i)
  {
    if (!index.emplace(names[i], i).second)
    {
      std::ostringstream msg;
      msg << what << " has two targets named '" << names[i] << "'"
          << (i > 0 && names[i] == names[0] ? " (a target named like the neutral)" : "");
      throw InputError(msg.str());
    }
  }
  return index;
}
} // namespace

NamedTargetDistances CombineTargetDistances(const std::vector<NamedTargetDistances>& pieces)
{
  if (pieces.empty())
  {
    throw InputError("a model needs at least one piece");
  }
  NamedTargetDistances model;
  std::unordered_map<std::string, size_t> index;
  for (size_t p = 0; p < pieces.size(); ++p)
  {
    const NamedTargetDistances& piece = pieces[p];
    CheckPiece(piece, p);
    IndexNames(piece.Names, "piece " + std::to_string(p) + " of the model");
    if (p == 0)
    {
      model.Names.push_back(piece.Names[0]);
      model.DistMorph.push_back(0.0);
      model.MaxDisplacement.push_back(0.0);
      index.emplace(piece.Names[0], 0);
    }
    for (size_t k = 1; k < piece.Names.size(); ++k)
    {
      auto [it, added] = index.emplace(piece.Names[k], model.Names.size());
      if (added)
      {
        model.Names.push_back(piece.Names[k]);
        model.DistMorph.push_back(0.0);
        model.MaxDisplacement.push_back(0.0);
      }
      else if (it->second == 0)
      {
        std::ostringstream msg;
        msg << "piece " << p << " of the model has a target named '" << piece.Names[k]
            << "', the name of the neutral";
        throw InputError(msg.str());
      }
      model.DistMorph[it->second] += piece.DistMorph[k];
      model.MaxDisplacement[it->second] =
        std::max(model.MaxDisplacement[it->second], piece.MaxDisplacement[k]);
    }
  }
  return model;
}

TargetDistances MakeTargetDistances(const NamedTargetDistances& model)
{
  CheckPiece(model, 0);
  const size_t n = model.Names.size();
  TargetDistances d;
  d.DistMorph.assign(n, 0.0);
  d.MaxDisplacement.assign(n, 0.0);
  for (size_t i = 1; i < n; ++i)
  {
    d.DistMorph[i] = model.DistMorph[i];
    d.MaxDisplacement[i] = model.MaxDisplacement[i];
  }
  NormalizeDistances(
    d); // as ComputeTargetDistances: one part gives MorphNode's figures bit for bit
  return d;
}

void MorphScene::SetParts(std::vector<std::shared_ptr<const MorphMesh>> parts,
  const std::vector<std::vector<uint8_t>>& excludedFromSums)
{
  this->ClearResult();
  this->Parts.clear();
  this->Names.clear();
  this->PartsDistances = {};
  this->SetTargetDistances(TargetDistances{});
  if (parts.empty())
  {
    throw InputError("a morph scene needs at least one part");
  }
  if (!excludedFromSums.empty() && excludedFromSums.size() != parts.size())
  {
    std::ostringstream msg;
    msg << "the morph scene got point flags for " << excludedFromSums.size() << " parts, but has "
        << parts.size() << " parts";
    throw InputError(msg.str());
  }
  std::vector<std::unique_ptr<PartState>> states;
  std::vector<NamedTargetDistances> pieces;
  for (size_t p = 0; p < parts.size(); ++p)
  {
    if (!parts[p])
    {
      throw InputError("part " + std::to_string(p) + " of the morph scene is missing");
    }
    auto state = std::make_unique<PartState>();
    state->Node.SetWeightMode(WeightMode::Relative);
    try
    {
      state->Node.SetMesh(parts[p]); // validates, computes the part's distances
    }
    catch (const InputError& e)
    {
      throw InputError("part " + std::to_string(p) + " of the morph scene: " + e.what());
    }
    const MorphMesh& mesh = *parts[p];
    if (mesh.GetNumberOfTargets() == 0)
    {
      throw InputError("part " + std::to_string(p) + " of the morph scene has no target names");
    }
    NamedTargetDistances piece;
    piece.Names = mesh.GetTargetNames();
    const TargetDistances& own = state->Node.GetTargetDistances();
    piece.DistMorph = own.DistMorph;
    piece.MaxDisplacement = own.MaxDisplacement;
    piece.DistMorph.resize(piece.Names.size(), 0.0); // a mesh without positions moves nothing
    piece.MaxDisplacement.resize(piece.Names.size(), 0.0);
    const std::vector<uint8_t>* excluded =
      excludedFromSums.empty() ? nullptr : &excludedFromSums[p];
    if (excluded && !excluded->empty())
    {
      if (excluded->size() != mesh.GetNumberOfPoints())
      {
        std::ostringstream msg;
        msg << "part " << p << " of the morph scene has " << mesh.GetNumberOfPoints()
            << " points, but " << excluded->size() << " point flags";
        throw InputError(msg.str());
      }
      if (std::any_of(excluded->begin(), excluded->end(), [](uint8_t f) { return f != 0; }))
      {
        // dist_morph over the points this part owns only.
        for (size_t k = 1; k < piece.Names.size() && mesh.GetPositionAttribute() >= 0; ++k)
        {
          const std::vector<double> perPoint = mesh.ComputePointDistances(k);
          double sum = 0.0;
          for (size_t i = 0; i < perPoint.size(); ++i)
          {
            sum += (*excluded)[i] ? 0.0 : perPoint[i];
          }
          piece.DistMorph[k] = sum;
        }
      }
    }
    pieces.push_back(std::move(piece));
    state->Mesh = std::move(parts[p]);
    states.push_back(std::move(state));
  }
  NamedTargetDistances combined = CombineTargetDistances(pieces);
  this->Parts = std::move(states);
  this->PartsDistances = std::move(combined);
  this->SetModel(this->PartsDistances);
}

void MorphScene::SetModel(const NamedTargetDistances& model)
{
  this->ClearResult();
  const TargetDistances distances = MakeTargetDistances(model);
  const auto index = IndexNames(model.Names, "the model");
  for (size_t p = 0; p < this->Parts.size(); ++p)
  {
    PartState& part = *this->Parts[p];
    const auto& names = part.Mesh->GetTargetNames();
    part.Targets.assign(names.size(), 0);
    for (size_t k = 1; k < names.size(); ++k)
    {
      const auto it = index.find(names[k]);
      if (it == index.end() || it->second == 0)
      {
        std::ostringstream msg;
        msg << "part " << p << " of the morph scene has a target '" << names[k]
            << "' that the model "
            << (it == index.end() ? "does not have" : "names like its neutral");
        throw InputError(msg.str());
      }
      part.Targets[k] = it->second;
    }
    part.Weights.assign(names.size(), 0.0);
  }
  this->Names = model.Names;
  this->SetTargetDistances(distances);
}

const MorphMesh& MorphScene::GetPart(size_t part) const
{
  this->CheckPart(part);
  return *this->Parts[part]->Mesh;
}

int MorphScene::FindTarget(const std::string& name) const
{
  const auto it = std::find(this->Names.begin(), this->Names.end(), name);
  return it == this->Names.end() ? -1 : static_cast<int>(it - this->Names.begin());
}

const std::vector<size_t>& MorphScene::GetPartTargets(size_t part) const
{
  this->CheckPart(part);
  return this->Parts[part]->Targets;
}

void MorphScene::SetPartTargetsOff(size_t part, const std::vector<std::string>& names)
{
  this->CheckPart(part);
  PartState& state = *this->Parts[part];
  const std::vector<std::string>& own = state.Mesh->GetTargetNames();
  state.Off.assign(own.size(), 0);
  for (size_t k = 1; k < own.size(); ++k)
  {
    state.Off[k] = std::find(names.begin(), names.end(), own[k]) != names.end();
  }
  if (std::find(state.Off.begin(), state.Off.end(), 1) == state.Off.end())
  {
    state.Off.clear();
  }
}

bool MorphScene::SetTargetsOffByPartName(const std::vector<std::string>& partNames,
  const std::map<std::string, std::vector<std::string>>& off)
{
  if (partNames.size() != this->Parts.size())
  {
    std::ostringstream msg;
    msg << "the morph scene got " << partNames.size() << " part names for its "
        << this->Parts.size() << " parts";
    throw InputError(msg.str());
  }
  static const std::vector<std::string> none;
  bool any = false;
  for (size_t p = 0; p < partNames.size(); ++p)
  {
    const std::string& name = partNames[p];
    auto it = off.find(name);
    if (it == off.end())
    {
      it = off.find(name.substr(0, name.rfind('/'))); // "Name/i": the mesh "Name"
    }
    this->SetPartTargetsOff(p, it == off.end() ? none : it->second);
    any = any || it != off.end();
  }
  return any;
}

void MorphScene::ClearResult()
{
  this->ClearDecision();
  for (auto& part : this->Parts)
  {
    part->Moved = false;
  }
}

void MorphScene::CheckPart(size_t part) const
{
  if (part >= this->Parts.size())
  {
    std::ostringstream msg;
    msg << "the morph scene has no part " << part << " (it has " << this->Parts.size() << ")";
    throw InputError(msg.str());
  }
}

const std::vector<double>& MorphScene::SetWeights(const double* requested, size_t count)
{
  this->ClearResult();
  if (this->Parts.empty())
  {
    throw InputError("the morph scene has no parts to blend");
  }
  const size_t n = this->Names.size();
  if (count != n)
  {
    std::ostringstream msg;
    msg << "the morph scene got " << count << " weights for " << n << " targets (neutral first)";
    throw InputError(msg.str());
  }
  // The rule and the optimizer once, for the whole model (as MorphNode::SetWeights; no
  // allocation per call without optimizer).
  const std::vector<double>& effective = this->Decide(requested, count);
  // Each part blends its own targets with their scene weights. In Relative mode the node
  // uses them as given (its neutral's weight, 1 - their sum, does not enter the blend), so a
  // part holding every target of the scene blends exactly as a MorphNode given the
  // effective weights.
  try
  {
    for (auto& partPtr : this->Parts)
    {
      PartState& part = *partPtr;
      part.Moved = false;
      for (size_t k = 1; k < part.Targets.size(); ++k)
      {
        part.Weights[k] = part.Off.empty() || !part.Off[k] ? effective[part.Targets[k]] : 0.0;
        part.Moved = part.Moved || part.Weights[k] != 0.0;
      }
      part.Weights[0] = 0.0;
      part.Node.SetWeights(part.Weights);
    }
  }
  catch (...)
  {
    this->ClearResult();
    throw;
  }
  return effective;
}

const std::vector<double>& MorphScene::GetPartWeights(size_t part) const
{
  this->CheckPart(part);
  return this->Parts[part]->Node.GetEffectiveWeights();
}

bool MorphScene::IsPartMoved(size_t part) const
{
  this->CheckPart(part);
  return this->Parts[part]->Moved;
}

const MorphNode& MorphScene::GetPartNode(size_t part) const
{
  this->CheckPart(part);
  return this->Parts[part]->Node;
}
void MorphScene::PlanBlend(const std::vector<size_t>& parts, int threads, BlendPlan& plan) const
{
  size_t total = 0;
  for (size_t p : parts)
  {
    total += this->GetPart(p).GetNumberOfPoints();
  }
  plan.Ranges.clear();
  plan.Tasks.clear();
  plan.Serial = threads <= 1 || total < 2 * MinPointsPerBlendTask;
  // Tasks of equal size (at least MinPointsPerBlendTask, at most four per thread), as many
  // as a multiple of the threads where there are more than threads: a blend bound by
  // streaming deltas takes as long as its slowest thread, and 11,248 points cut in tasks of
  // 2,048 left one thread three and the other two and a half.
  size_t grain = std::numeric_limits<size_t>::max();
  if (!plan.Serial)
  {
    const size_t workers = static_cast<size_t>(threads);
    size_t tasks = std::min(total / MinPointsPerBlendTask, 4 * workers);
    if (tasks > workers)
    {
      tasks -= tasks % workers;
    }
    grain = (total + tasks - 1) / tasks;
  }
  size_t filled = 0; // points in the current task
  for (size_t p : parts)
  {
    const size_t n = this->GetPart(p).GetNumberOfPoints();
    for (size_t begin = 0; begin < n;)
    {
      if (filled == 0)
      {
        plan.Tasks.push_back(plan.Ranges.size());
      }
      const size_t end = begin + std::min(grain - filled, n - begin);
      plan.Ranges.push_back({ p, begin, end });
      filled = (filled + end - begin) % grain;
      begin = end;
    }
  }
  plan.Tasks.push_back(plan.Ranges.size());
  plan.Serial = plan.Serial || plan.GetNumberOfTasks() <= 1;
}

void MorphScene::BlendTask(const BlendPlan& plan, size_t task,
  const std::vector<const std::vector<AttributeOutput>*>& outputs) const
{
  for (size_t r = plan.Tasks[task]; r < plan.Tasks[task + 1]; ++r)
  {
    const BlendPlan::Range& range = plan.Ranges[r];
    this->Blend(range.Part, *outputs[range.Part], range.Begin, range.End);
  }
}
} // namespace morphnode
