// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphModelAdapter.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"

#include "vtkAbstractArray.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiProcessStream.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVariant.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

namespace vtkMorphModelAdapter
{
namespace
{
using morphnode::AttributeRole;
using morphnode::InputError;

namespace arrays = vtkMorphTargetArrays;

bool IsIntegerType(int vtkType)
{
  return vtkType != VTK_FLOAT && vtkType != VTK_DOUBLE;
}

/// A leaf's name for messages: its metadata NAME, else its flat index.
std::string LeafName(vtkInformation* meta, unsigned int flatIndex)
{
  if (meta && meta->Has(vtkCompositeDataSet::NAME()) && meta->Get(vtkCompositeDataSet::NAME()))
  {
    return meta->Get(vtkCompositeDataSet::NAME());
  }
  return "#" + std::to_string(flatIndex);
}

/// Adds an attribute from the neutral's array and every other input's array of that name
/// (absolute targets).
template <typename GetTarget>
void AddAttribute(BuiltModel& built, const std::string& name, AttributeRole role,
  vtkDataArray* neutral, size_t numTargets, double sparseCoverage, GetTarget targetArray)
{
  std::vector<vtkDataArray*> targets;
  for (size_t i = 1; i < numTargets; ++i)
  {
    targets.push_back(targetArray(i));
  }
  arrays::AddAttribute(built.Model, name, role, neutral, targets, false, sparseCoverage);
}

AttributeRole RoleOf(vtkPointSet* neutral, vtkDataArray* array)
{
  if (array == neutral->GetPointData()->GetNormals())
  {
    return AttributeRole::Normal;
  }
  // Colours and any other integer array: clamped to the type's range, so that the
  // conversion back to the array's type is always defined.
  return IsIntegerType(array->GetDataType()) ? AttributeRole::Color : AttributeRole::Generic;
}

std::vector<std::string> NamesFrom(
  vtkPointSet* neutral, const std::vector<vtkPointSet*>& all, size_t numTargets)
{
  if (neutral->GetFieldData()->GetAbstractArray(TargetNamesArray))
  {
    return arrays::GetTargetNames(neutral->GetFieldData(), numTargets);
  }
  std::vector<std::string> result = morphnode::DefaultTargetNames(numTargets);
  for (size_t i = 0; i < all.size() && i < numTargets; ++i)
  {
    auto* name =
      vtkStringArray::SafeDownCast(all[i]->GetFieldData()->GetAbstractArray(TargetNameArray));
    if (name && name->GetNumberOfValues() > 0 && !name->GetValue(0).empty())
    {
      result[i] = name->GetValue(0);
    }
  }
  return result;
}

void CheckNeutral(vtkPointSet* neutral)
{
  if (!neutral)
  {
    throw InputError("no input: connect the neutral (and the targets) to port 0");
  }
  if (neutral->GetNumberOfPoints() == 0 || !neutral->GetPoints())
  {
    throw InputError("the neutral target has no points");
  }
}

/// Works out BuiltModel::PointArrays from the neutral's point data.
void PlanPointArrays(vtkPointData* pd, BuiltModel& built)
{
  built.PointArrays.clear();
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    vtkAbstractArray* array = pd->GetAbstractArray(i);
    const char* name = array ? array->GetName() : nullptr;
    if (!array ||
      (name &&
        std::find(built.ConsumedArrays.begin(), built.ConsumedArrays.end(), name) !=
          built.ConsumedArrays.end()))
    {
      continue;
    }
    OutputArraySource source{ i, -1, pd->IsArrayAnAttribute(i) };
    for (size_t a = 1; name && a < built.Bindings.size(); ++a)
    {
      if (built.Bindings[a].ArrayName == name)
      {
        source.Blended = static_cast<int>(a - 1);
        if (built.Bindings[a].IsNormals)
        {
          source.Attribute = vtkDataSetAttributes::NORMALS;
        }
      }
    }
    built.PointArrays.push_back(source);
  }
}
} // namespace

bool HasRelativeTargets(vtkPointSet* input)
{
  return arrays::HasTargets(input);
}

BuiltModel BuildFromAbsoluteTargets(const std::vector<vtkPointSet*>& inputs, double sparseCoverage)
{
  vtkPointSet* neutral = inputs.empty() ? nullptr : inputs[0];
  CheckNeutral(neutral);
  const vtkIdType numPoints = neutral->GetNumberOfPoints();
  for (size_t i = 1; i < inputs.size(); ++i)
  {
    if (!inputs[i])
    {
      std::ostringstream msg;
      msg << "target " << i << " (connection " << i << " of port 0) is not a vtkPointSet";
      throw InputError(msg.str());
    }
    if (inputs[i]->GetNumberOfPoints() != numPoints)
    {
      std::ostringstream msg;
      msg << "target " << i << " has " << inputs[i]->GetNumberOfPoints()
          << " points, the neutral has " << numPoints << "; all targets need the same points";
      throw InputError(msg.str());
    }
    if (HasRelativeTargets(inputs[i]))
    {
      throw InputError("target arrays (target<k>_position) on a Java3D-style target: use either "
                       "several absolute targets or one input with relative target arrays");
    }
  }
  if (HasRelativeTargets(neutral) && inputs.size() > 1)
  {
    throw InputError(
      "the neutral carries target<k>_position arrays but more targets are connected; "
      "use one form of targets only");
  }

  const size_t n = inputs.size();
  BuiltModel built{ morphnode::MorphMesh(static_cast<size_t>(numPoints)), {}, {}, {} };
  built.Model.SetTargetNames(NamesFrom(neutral, inputs, n));
  arrays::CheckUniqueNames(built.Model.GetTargetNames());

  AddAttribute(built, arrays::PointsAttributeName, AttributeRole::Position,
    neutral->GetPoints()->GetData(), n, sparseCoverage,
    [&](size_t i) { return inputs[i]->GetPoints()->GetData(); });
  built.Bindings.push_back({ "", neutral->GetPoints()->GetData(), false });

  vtkPointData* pd = neutral->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = pd->GetArray(a);
    if (!array || !array->GetName())
    {
      continue;
    }
    const std::string name = array->GetName();
    bool onAll = true;
    for (size_t i = 1; i < n && onAll; ++i)
    {
      vtkDataArray* other = inputs[i]->GetPointData()->GetArray(name.c_str());
      onAll = other && other->GetNumberOfComponents() == array->GetNumberOfComponents() &&
        other->GetNumberOfTuples() == numPoints;
    }
    if (!onAll || array->GetNumberOfTuples() != numPoints)
    {
      continue; // passed through from the neutral
    }
    const AttributeRole role = RoleOf(neutral, array);
    AddAttribute(built, name, role, array, n, sparseCoverage,
      [&](size_t i) { return inputs[i]->GetPointData()->GetArray(name.c_str()); });
    built.Bindings.push_back({ name, array, role == AttributeRole::Normal });
  }
  built.Model.Validate();
  PlanPointArrays(pd, built);
  return built;
}

BuiltModel BuildFromRelativeTargets(vtkPointSet* input, double sparseCoverage)
{
  CheckNeutral(input);
  arrays::ReadOptions options;
  options.SparseCoverage = sparseCoverage;
  arrays::MeshFromVTK read = arrays::ToMorphMesh(input, options);
  BuiltModel built{ std::move(read.Mesh), {}, std::move(read.TargetArrays), {} };
  built.Bindings.push_back({ "", input->GetPoints()->GetData(), false });
  if (read.Normals)
  {
    built.Bindings.push_back(
      { read.Normals->GetName() ? read.Normals->GetName() : "", read.Normals, true });
  }
  PlanPointArrays(input->GetPointData(), built);
  return built;
}

std::vector<vtkPointSet*> AbsoluteShapes(vtkDataObject* input)
{
  std::vector<vtkPointSet*> shapes;
  auto* set = vtkPartitionedDataSet::SafeDownCast(input);
  for (unsigned int i = 0; set && i < set->GetNumberOfPartitions(); ++i)
  {
    auto* shape = vtkPointSet::SafeDownCast(set->GetPartitionAsDataObject(i));
    if (!shape || HasRelativeTargets(shape))
    {
      return {};
    }
    shapes.push_back(shape);
  }
  return shapes;
}

BuiltModel BuildModel(const std::vector<vtkPointSet*>& inputs, double sparseCoverage)
{
  return inputs.size() == 1 && HasRelativeTargets(inputs[0])
    ? BuildFromRelativeTargets(inputs[0], sparseCoverage)
    : BuildFromAbsoluteTargets(inputs, sparseCoverage);
}

std::vector<double> WeightsFromTable(
  vtkTable* table, const morphnode::WeightRequests& model, int& matched)
{
  const size_t n = model.GetTargets().size();
  std::vector<double> weights(n, 0.0);
  matched = 0;
  if (table->GetNumberOfRows() < 1)
  {
    throw InputError("the weights table on port 1 has no rows");
  }
  bool neutralGiven = false;
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
  {
    const char* name = table->GetColumnName(c);
    const int target = name ? model.FindTarget(name) : -1;
    if (target < 0)
    {
      continue;
    }
    bool ok = false;
    const double w = table->GetValue(0, c).ToDouble(&ok);
    if (!ok)
    {
      throw InputError(std::string("the weights table's column '") + name + "' is not numeric");
    }
    weights[static_cast<size_t>(target)] = w;
    neutralGiven = neutralGiven || target == 0;
    ++matched;
  }
  if (!neutralGiven)
  {
    weights[0] = morphnode::ImplicitNeutralWeight(weights);
  }
  return weights;
}

vtkSmartPointer<vtkStringArray> MakeNamesArray(
  const char* arrayName, const std::vector<std::string>& names)
{
  return arrays::MakeNamesArray(arrayName, names);
}

vtkSmartPointer<vtkDataArray> MakeDoubleArray(
  const char* arrayName, const std::vector<double>& values)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(arrayName);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

vtkDataArray* ReuseOrNew(vtkSmartPointer<vtkDataArray>& slot, vtkDataArray* prototype,
  vtkIdType numTuples, int holders, vtkSmartPointer<vtkDataArray>* spare)
{
  auto fits = [&](vtkDataArray* a, int refs)
  {
    return a && a->GetReferenceCount() == refs && a->GetDataType() == prototype->GetDataType() &&
      a->GetNumberOfComponents() == prototype->GetNumberOfComponents() &&
      a->GetNumberOfTuples() == numTuples;
  };
  if (fits(slot, holders))
  {
    return slot;
  }
  if (spare && fits(*spare, 1) && holders == 1)
  {
    std::swap(slot, *spare);
    return slot;
  }
  if (spare && slot)
  {
    *spare = slot; // held downstream: the spare once let go
  }
  slot.TakeReference(prototype->NewInstance());
  slot->SetName(prototype->GetName());
  slot->SetNumberOfComponents(prototype->GetNumberOfComponents());
  slot->SetNumberOfTuples(numTuples);
  return slot;
}

void AssemblePointData(
  vtkPointData* neutral, const BuiltModel& built, const BlendOutputs& outputs, vtkPointData* out)
{
  for (const OutputArraySource& source : built.PointArrays)
  {
    vtkAbstractArray* array = source.Blended >= 0
      ? outputs.Arrays[static_cast<size_t>(source.Blended)].GetPointer()
      : neutral->GetAbstractArray(source.NeutralIndex);
    if (!array)
    {
      continue;
    }
    const int index = out->AddArray(array);
    if (source.Attribute >= 0)
    {
      out->SetActiveAttribute(index, source.Attribute);
    }
  }
}

std::vector<uint8_t> DuplicateFlags(vtkPointSet* input)
{
  std::vector<uint8_t> flags;
  vtkUnsignedCharArray* ghosts = input ? input->GetPointGhostArray() : nullptr;
  if (!ghosts || ghosts->GetNumberOfTuples() != input->GetNumberOfPoints())
  {
    return flags;
  }
  bool any = false;
  flags.resize(static_cast<size_t>(input->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    flags[static_cast<size_t>(i)] =
      (ghosts->GetValue(i) & vtkDataSetAttributes::DUPLICATEPOINT) ? 1 : 0;
    any = any || flags[static_cast<size_t>(i)];
  }
  if (!any)
  {
    flags.clear();
  }
  return flags;
}

std::vector<std::string> LeafNames(vtkCompositeDataSet* composite, size_t count)
{
  std::vector<std::string> names;
  auto* collection = vtkPartitionedDataSetCollection::SafeDownCast(composite);
  for (unsigned int d = 0; collection && d < collection->GetNumberOfPartitionedDataSets(); ++d)
  {
    vtkPartitionedDataSet* parts = collection->GetPartitionedDataSet(d);
    const char* name =
      collection->HasMetaData(d) && collection->GetMetaData(d)->Has(vtkCompositeDataSet::NAME())
      ? collection->GetMetaData(d)->Get(vtkCompositeDataSet::NAME())
      : nullptr;
    const unsigned int count = parts ? parts->GetNumberOfPartitions() : 0;
    for (unsigned int i = 0; i < count; ++i)
    {
      if (parts->GetPartitionAsDataObject(i))
      {
        const std::string part = name ? name : "#" + std::to_string(d);
        names.push_back(count > 1 ? part + "/" + std::to_string(i) : part);
      }
    }
  }
  if (!collection && composite)
  {
    for (auto node : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      names.push_back(
        LeafName(node.HasMetaData() ? node.GetMetaData() : nullptr, node.GetFlatIndex()));
    }
  }
  names.resize(std::max(names.size(), count + 1), "?");
  return names;
}

morphnode::NamedTargetDistances GatherModel(vtkMultiProcessController* controller,
  const morphnode::NamedTargetDistances* piece, const std::string& error)
{
  vtkMultiProcessStream mine;
  if (!error.empty())
  {
    mine << 'E' << error;
  }
  else if (piece)
  {
    mine << 'P' << static_cast<vtkTypeUInt64>(piece->Names.size());
    for (size_t i = 0; i < piece->Names.size(); ++i)
    {
      mine << piece->Names[i] << piece->DistMorph[i] << piece->MaxDisplacement[i];
    }
  }
  else
  {
    mine << '0';
  }
  std::vector<vtkMultiProcessStream> all;
  if (!controller->AllGather(mine, all) ||
    all.size() != static_cast<size_t>(controller->GetNumberOfProcesses()))
  {
    throw morphnode::InputError("the processes could not exchange their targets' figures");
  }
  std::vector<morphnode::NamedTargetDistances> pieces;
  for (size_t r = 0; r < all.size(); ++r)
  {
    char kind = '0';
    all[r] >> kind;
    if (kind == 'E')
    {
      std::string failure;
      all[r] >> failure;
      const bool local = static_cast<int>(r) == controller->GetLocalProcessId();
      throw morphnode::InputError((local ? "" : "process " + std::to_string(r) + ": ") + failure);
    }
    if (kind == 'P')
    {
      vtkTypeUInt64 n = 0;
      all[r] >> n;
      morphnode::NamedTargetDistances& received = pieces.emplace_back();
      received.Names.resize(n);
      received.DistMorph.resize(n);
      received.MaxDisplacement.resize(n);
      for (size_t i = 0; i < n; ++i)
      {
        all[r] >> received.Names[i] >> received.DistMorph[i] >> received.MaxDisplacement[i];
      }
    }
  }
  if (pieces.empty())
  {
    throw morphnode::InputError("no process has a point in its input");
  }
  return morphnode::CombineTargetDistances(pieces);
}

} // namespace vtkMorphModelAdapter
