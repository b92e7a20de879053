// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Rig.h
/// @brief Semantic shapes (visemes, expressions, gaze) as weighted combinations of a face's
/// own morph targets, read from a JSON rig file (format in docs/rigs.md).
///
/// A face scanned with ARKit-style action units (jawOpen, mouthFunnel, eyeBlink_L, ...)
/// has no "A" or "BrowsAngry" target; the paper's control layer speaks in those terms.
/// A rig bridges the two in either direction:
/// - Expand: semantic weights -> the face's target weights, per frame (a sparse
///   matrix-vector product into a caller's buffer, no allocation);
/// - Bake: the face's target deltas -> one delta set per semantic shape, once, so that the
///   morph node runs the paper's own target set (13 targets) on the real face.

#include "gaze/EyeRig.h"
#include "morph/MorphMesh.h"

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace morphnode
{
/// One coefficient of a shape: `Coefficient` times the face target `Target`.
struct RigTerm
{
  std::string Target;
  double Coefficient = 0.0;
};

class Rig
{
public:
  /// Reads a rig file. Throws InputError naming the file and the field at fault.
  static Rig LoadFile(const std::string& path);
  /// Parses rig JSON; `sourceName` only appears in error messages.
  static Rig LoadString(const std::string& json, const std::string& sourceName = "<string>");

  const std::string& GetName() const { return this->Name; }
  const std::string& GetDescription() const { return this->Description; }
  /// The face target names the rig was written for ("targets" field; may be empty).
  const std::vector<std::string>& GetDeclaredTargets() const { return this->DeclaredTargets; }

  /// Shapes in file order.
  size_t GetNumberOfShapes() const { return this->ShapeNames.size(); }
  const std::vector<std::string>& GetShapeNames() const { return this->ShapeNames; }
  /// -1 when the rig has no shape of that name.
  int FindShape(const std::string& name) const;
  /// Coefficients of one shape, in file order; throws std::out_of_range for a bad index.
  const std::vector<RigTerm>& GetShapeTerms(size_t shape) const { return this->Terms.at(shape); }

  /// The shape a shape is an alias of ("FF": "F" in the file), empty for a shape with
  /// coefficients of its own. An alias has a copy of its original's terms.
  const std::string& GetAliasOf(size_t shape) const { return this->Aliases.at(shape); }

  /// Named lists of shapes ("sets" field), e.g. "paper" = the 12 non-neutral shapes of
  /// Berner's Table 1 in table order. Throws InputError for an unknown set.
  const std::vector<std::string>& GetSet(const std::string& setName) const;
  std::vector<std::string> GetSetNames() const;

  /// The eyes (the "eyes" section, docs/rigs.md): named eye parts, their rest and up
  /// directions, their limits. A rig without the section gives the default EyeRig (the
  /// convention for common eye names); HasEyes() tells whether the file had one.
  bool HasEyes() const { return this->HasEyeSection; }
  const EyeRig& GetEyes() const { return this->Eyes; }

  /// Throws InputError, naming the shape and the target, when a shape refers to a target
  /// that `faceTargetNames` (the face's relative targets, no neutral) does not have.
  void Validate(const std::vector<std::string>& faceTargetNames) const;

  /// Validates, then resolves target names to indices into `faceTargetNames`: Expand and
  /// Bake work on that order from then on.
  void Bind(const std::vector<std::string>& faceTargetNames);
  /// Binds to a MorphMesh's targets: its target 0 is the neutral and is skipped, so
  /// index k of Expand's output is the model's target k + 1.
  void Bind(const MorphMesh& model);
  bool IsBound() const { return this->Bound; }
  /// Length of Expand's output and of Bake's input: the bound face's target count.
  size_t GetNumberOfBoundTargets() const { return this->BoundTargetNames.size(); }
  const std::vector<std::string>& GetBoundTargetNames() const { return this->BoundTargetNames; }

  /// Relative (glTF-style) target weights from semantic shape weights:
  ///   target[t] = clamp(sum over shapes s of shapeWeights[s] * coefficient(s, t), 0, 1).
  /// `shapeWeights` has GetNumberOfShapes() values, `targetWeights` receives
  /// GetNumberOfBoundTargets() values. Shapes with weight 0 cost nothing; no allocation.
  /// Throws InputError when the rig is not bound or a weight is not finite.
  void Expand(const double* shapeWeights, double* targetWeights) const;
  std::vector<double> Expand(const std::vector<double>& shapeWeights) const;
  /// By shape name; shapes not named weigh 0, unknown names are an error.
  std::vector<double> Expand(const std::map<std::string, double>& namedWeights) const;

  /// Semantic shapes as delta sets of their own: delta_shape = sum coef * delta_target.
  /// `targetDeltas[t]` points at the bound target t's deltas, `numValues` values each
  /// (numPoints * 3 for positions). Returns one vector of numValues per shape, in shape
  /// order. No clamping: the baked shape at weight 1 equals Expand at weight 1 as long as
  /// no coefficient exceeds [0, 1].
  template <typename T>
  std::vector<std::vector<T>> Bake(
    const std::vector<const T*>& targetDeltas, size_t numValues) const;

  /// Bakes every attribute of a model (positions, normals, ...) into a new model whose
  /// targets are "Neutral" followed by `shapeNames` (all shapes when empty). Binds the rig
  /// to the model first. The triangles are carried over; colour clamp ranges are not.
  MorphMesh BakeModel(const MorphMesh& model, const std::vector<std::string>& shapeNames = {});

private:
  void RequireBound(const char* what) const;
  /// out = sum over the shape's terms of coefficient * targetDeltas[target].
  template <typename T>
  void BakeShape(size_t shape, const T* const* targetDeltas, size_t numValues, T* out) const;
  std::vector<size_t> ResolveShapes(const std::vector<std::string>& shapeNames) const;

  std::string Name;
  std::string Description;
  std::vector<std::string> DeclaredTargets;
  std::vector<std::string> ShapeNames;
  std::vector<std::vector<RigTerm>> Terms;
  std::vector<std::string> Aliases; // per shape, empty when not an alias
  std::map<std::string, std::vector<std::string>> Sets;
  bool HasEyeSection = false;
  EyeRig Eyes;

  // Bound form: a CSR matrix, row per shape, columns = indices into BoundTargetNames.
  bool Bound = false;
  std::vector<std::string> BoundTargetNames;
  std::vector<size_t> RowStart; // GetNumberOfShapes() + 1 entries
  std::vector<size_t> Columns;
  std::vector<double> Values;
};

extern template std::vector<std::vector<float>> Rig::Bake<float>(
  const std::vector<const float*>&, size_t) const;
extern template std::vector<std::vector<double>> Rig::Bake<double>(
  const std::vector<const double*>&, size_t) const;
} // namespace morphnode
