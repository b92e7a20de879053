// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file WeightRequests.h
/// @brief The weights a user asks for, by target index or by name, before and across
/// models: what a node's SetWeight/SetWeightByName calls add up to.
///
/// Requests outlive models: a name may be set before the model that has it is built, and
/// an index beyond the model's targets is kept (the next model may have it). For one
/// target, the request set last wins, whether it came by index or by name. Against a
/// model's target names (SetTargets), Resolve gives the requested weights, neutral first:
/// the neutral 1 and every other target 0 unless a request says otherwise.
///
/// @code
/// morphnode::WeightRequests requests;
/// requests.SetByName("jawOpen", 0.7);           // before the face is known
/// requests.SetTargets(scene.GetTargetNames());  // once per model
/// std::vector<double> requested;
/// requests.Resolve(requested);                  // throws for unknown names, indices out of range
/// scene.SetWeights(requested);
/// @endcode

#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace morphnode
{
class WeightRequests
{
public:
  /// A request for target `index` (0: the neutral).
  void SetByIndex(size_t index, double weight);
  /// A request for the target named `name` (resolved against every model set later).
  void SetByName(const std::string& name, double weight);
  /// Forgets every request. False when there was none.
  bool Clear();
  bool Empty() const { return this->ByIndex.empty() && this->ByName.empty(); }

  /// The model's target names, neutral first (a new model: names resolve again). An empty
  /// list: no model.
  void SetTargets(const std::vector<std::string>& names);
  const std::vector<std::string>& GetTargets() const { return this->Names; }
  /// Index of the model's target of that name, -1 when none has it.
  int FindTarget(const std::string& name) const;

  /// The requested weight of target `index` of the model (the last request for it, by
  /// index or by its name; else 1 for the neutral, 0 for the others).
  double Get(size_t index) const;
  /// The requested weight of the target named `name`: Get of its index when the model has
  /// it, else the value set by that name (0 when none was).
  double GetByName(const std::string& name) const;

  /// The requested weights of the model's targets, neutral first (resized to the model's
  /// target count). Throws InputError for the request set first of those the model cannot
  /// take: an index beyond its targets, or a name none of its targets has (the message
  /// lists the targets).
  void Resolve(std::vector<double>& requested) const;

  /// Each request as "index=weight" or "name=weight", in index order then name order
  /// (for PrintSelf).
  std::string Describe() const;

private:
  struct Request
  {
    double Weight = 0.0;
    uint64_t Order = 0; ///< when it was set; 0: not set
  };
  struct NamedRequest
  {
    std::string Name;
    Request Value;
    int Index = -1; ///< in the current model, -1: none
  };
  std::vector<Request> ByIndex;
  std::vector<NamedRequest> ByName;
  uint64_t Orders = 0;
  std::vector<std::string> Names;
  std::unordered_map<std::string, int> Lookup;
};

/// The neutral's weight when a request names only other targets (a weights table without
/// a neutral column): max(0, 1 - the sum of the others). `weights` neutral first; its entry
/// 0 is not read.
double ImplicitNeutralWeight(const std::vector<double>& weights);
} // namespace morphnode
