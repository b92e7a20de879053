// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"

#include "vtkAbstractArray.h"
#include "vtkArrayDispatch.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <type_traits>
#include <variant>

namespace vtkMorphTargetArrays
{
namespace
{
using morphnode::AttributeRole;
using morphnode::InputError;

constexpr const char* Prefix = "target";
constexpr size_t PrefixLength = 6;

/// k of a name `target<k>_...`; false when the name is not of that form. Numbers too large
/// for size_t come out as SIZE_MAX (beyond any target count).
bool ParseTargetIndex(const char* name, size_t& k)
{
  if (!name || std::string(name).compare(0, PrefixLength, Prefix) != 0)
  {
    return false;
  }
  const std::string s(name);
  const size_t underscore = s.find('_', PrefixLength);
  if (underscore == std::string::npos || underscore == PrefixLength ||
    !std::all_of(s.begin() + PrefixLength, s.begin() + static_cast<long>(underscore),
      [](char c) { return c >= '0' && c <= '9'; }))
  {
    return false;
  }
  const std::string digits = s.substr(PrefixLength, underscore - PrefixLength);
  k = digits.size() > 9 ? SIZE_MAX : static_cast<size_t>(std::stoul(digits));
  return true;
}

template <typename T>
struct ToVectorWorker
{
  std::vector<T>& Out;

  template <typename ArrayT>
  void operator()(ArrayT* array)
  {
    const auto values = vtk::DataArrayValueRange(array);
    this->Out.resize(static_cast<size_t>(values.size()));
    std::transform(values.begin(), values.end(), this->Out.begin(),
      [](const auto v) { return static_cast<T>(v); });
  }
};

template <typename T>
struct CopyToArrayWorker
{
  const T* Values;

  template <typename ArrayT>
  void operator()(ArrayT* array)
  {
    using V = vtk::GetAPIType<ArrayT>;
    auto values = vtk::DataArrayValueRange(array);
    std::transform(this->Values, this->Values + values.size(), values.begin(),
      [](const T v)
      {
        if constexpr (std::is_integral_v<V>)
        {
          return static_cast<V>(std::round(static_cast<double>(v)));
        }
        else
        {
          return static_cast<V>(v);
        }
      });
  }
};

bool IsIntegerType(int vtkType)
{
  return vtkType != VTK_FLOAT && vtkType != VTK_DOUBLE;
}

vtkDataArray* NormalsOf(vtkPointSet* input)
{
  vtkPointData* pd = input->GetPointData();
  if (vtkDataArray* n = pd->GetNormals())
  {
    return n;
  }
  for (const char* name : { "Normal", "Normals", "NORMAL" })
  {
    vtkDataArray* n = pd->GetArray(name);
    if (n && n->GetNumberOfComponents() == 3)
    {
      return n;
    }
  }
  return nullptr;
}

/// The dense deltas of every target of an attribute, one array each, of `vtkType` (-1: the
/// attribute's own type).
template <typename T>
void AddDeltaArrays(
  const morphnode::MorphAttribute<T>& attribute, Kind kind, int vtkType, vtkPointData* pd)
{
  const size_t numPoints = attribute.GetNumberOfPoints();
  const int c = attribute.GetNumberOfComponents();
  const int type = vtkType >= 0 ? vtkType : (std::is_same_v<T, float> ? VTK_FLOAT : VTK_DOUBLE);
  std::vector<T> deltas(numPoints * static_cast<size_t>(c));
  for (size_t k = 1; k < attribute.GetNumberOfTargets(); ++k)
  {
    attribute.GetTarget(k).ToDense(deltas.data());
    const std::string name = ArrayName(k - 1, kind);
    pd->RemoveArray(name.c_str());
    pd->AddArray(NewArray(type, name.c_str(), c, static_cast<vtkIdType>(numPoints), deltas.data()));
  }
}

/// A new array holding an attribute's neutral values in the attribute's type.
vtkSmartPointer<vtkDataArray> NeutralArray(
  const morphnode::AnyMorphAttribute& any, const char* name)
{
  return std::visit(
    [&](const auto& attribute)
    {
      using T = typename std::decay_t<decltype(attribute.GetNeutral())>::value_type;
      return NewArray(std::is_same_v<T, float> ? VTK_FLOAT : VTK_DOUBLE, name,
        attribute.GetNumberOfComponents(), static_cast<vtkIdType>(attribute.GetNumberOfPoints()),
        attribute.GetNeutral().data());
    },
    any);
}
} // namespace

std::string ArrayName(size_t k, Kind kind)
{
  return Prefix + std::to_string(k) + (kind == Kind::Position ? "_position" : "_normal");
}

bool IsTargetArrayName(const char* name)
{
  size_t k = 0;
  return ParseTargetIndex(name, k);
}

bool HasTargets(vtkPointData* pd)
{
  // The name made once: asked of every partition twice an update in the Java3D form in one
  // data set, building it each time cost more than the lookup.
  static const std::string first = ArrayName(0, Kind::Position);
  return pd && pd->GetAbstractArray(first.c_str()) != nullptr;
}

bool HasTargets(vtkPointSet* input)
{
  return input && HasTargets(input->GetPointData());
}

vtkDataArray* GetDeltas(vtkPointData* pd, size_t k, Kind kind, vtkIdType numPoints)
{
  const std::string name = ArrayName(k, kind);
  vtkAbstractArray* abstract = pd->GetAbstractArray(name.c_str());
  if (!abstract)
  {
    return nullptr;
  }
  vtkDataArray* array = vtkDataArray::SafeDownCast(abstract);
  if (!array || array->GetNumberOfComponents() != 3 || array->GetNumberOfTuples() != numPoints)
  {
    std::ostringstream msg;
    msg << "target array '" << name << "' must be numeric with 3 components and " << numPoints
        << " tuples (one per point); it has " << abstract->GetNumberOfComponents()
        << " components and " << abstract->GetNumberOfTuples() << " tuples";
    throw InputError(msg.str());
  }
  return array;
}

size_t CountTargets(vtkPointData* pd, vtkIdType numPoints)
{
  size_t n = 0;
  while (pd->GetAbstractArray(ArrayName(n, Kind::Position).c_str()))
  {
    GetDeltas(pd, n, Kind::Position, numPoints);
    ++n;
  }
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    size_t k = 0;
    const char* name = pd->GetArrayName(a);
    if (ParseTargetIndex(name, k) && k >= n)
    {
      std::ostringstream msg;
      msg << "target array '" << name << "' is target " << k << ", but ";
      if (n == 0)
      {
        msg << "there is no " << ArrayName(0, Kind::Position);
      }
      else
      {
        msg << "only targets 0 to " << n - 1 << " have a " << Prefix << "<k>_position";
      }
      msg << " (target arrays must be numbered from 0 without gaps)";
      throw InputError(msg.str());
    }
  }
  return n;
}

void RemoveTargetArrays(vtkPointData* pd)
{
  for (int a = pd->GetNumberOfArrays() - 1; a >= 0; --a)
  {
    if (IsTargetArrayName(pd->GetArrayName(a)))
    {
      pd->RemoveArray(a);
    }
  }
}

bool AssignTargetNames(vtkSmartPointer<vtkStringArray>& slot, vtkStringArray* names)
{
  if (!names && !slot)
  {
    return false;
  }
  if (names)
  {
    auto copy = vtkSmartPointer<vtkStringArray>::New();
    copy->DeepCopy(names);
    copy->SetName(TargetNamesArray);
    slot = copy;
  }
  else
  {
    slot = nullptr;
  }
  return true;
}

bool GetFaceTargetNames(vtkDataObject* face, std::vector<std::string>& targets)
{
  targets.clear();
  bool found = false;
  auto add = [&](vtkDataObject* leaf)
  {
    auto* names = leaf && leaf->GetFieldData()
      ? vtkStringArray::SafeDownCast(leaf->GetFieldData()->GetAbstractArray(TargetNamesArray))
      : nullptr;
    if (!names)
    {
      return;
    }
    found = true;
    for (vtkIdType i = 1; i < names->GetNumberOfValues(); ++i)
    {
      const std::string& name = names->GetValue(i);
      if (std::find(targets.begin(), targets.end(), name) == targets.end())
      {
        targets.push_back(name);
      }
    }
  };
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(face))
  {
    for (vtkDataObject* leaf : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      add(leaf);
    }
  }
  else
  {
    add(face);
  }
  return found;
}

size_t CountFaceTargets(vtkDataObject* face)
{
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(face))
  {
    // Not GetFaceTargetNames: this counts the leaves' target arrays, naming unnamed ones
    // target<k> as the model does, and skips leaves whose names do not match their arrays.
    std::set<std::string> targets;
    for (vtkDataObject* node : vtk::Range(composite, vtk::CompositeDataSetOptions::SkipEmptyNodes))
    {
      auto* leaf = vtkPointSet::SafeDownCast(node);
      try
      {
        const size_t n = leaf ? CountTargets(leaf->GetPointData(), leaf->GetNumberOfPoints()) : 0;
        const std::vector<std::string> names =
          GetTargetNames(leaf ? leaf->GetFieldData() : nullptr, n + 1);
        targets.insert(names.begin() + 1, names.end());
      }
      catch (const std::exception&)
      {
        // Reported when the face is read.
      }
    }
    return targets.size();
  }
  auto* points = vtkPointSet::SafeDownCast(face);
  size_t n = 0;
  while (points && points->GetPointData()->GetAbstractArray(ArrayName(n, Kind::Position).c_str()))
  {
    ++n;
  }
  return n;
}

std::vector<std::string> GetTargetNames(vtkFieldData* fd, size_t numTargets)
{
  vtkAbstractArray* abstract = fd ? fd->GetAbstractArray(TargetNamesArray) : nullptr;
  if (!abstract)
  {
    return morphnode::DefaultTargetNames(numTargets);
  }
  auto* names = vtkStringArray::SafeDownCast(abstract);
  if (!names)
  {
    throw InputError(std::string("field data '") + TargetNamesArray + "' must be a string array");
  }
  if (static_cast<size_t>(names->GetNumberOfValues()) != numTargets)
  {
    std::ostringstream msg;
    msg << "field data '" << TargetNamesArray << "' has " << names->GetNumberOfValues()
        << " names for " << numTargets << " targets (neutral first)";
    throw InputError(msg.str());
  }
  std::vector<std::string> result;
  result.reserve(numTargets);
  for (vtkIdType i = 0; i < names->GetNumberOfValues(); ++i)
  {
    result.push_back(names->GetValue(i));
  }
  return result;
}

void CheckUniqueNames(const std::vector<std::string>& names)
{
  for (size_t i = 0; i < names.size(); ++i)
  {
    for (size_t j = i + 1; j < names.size(); ++j)
    {
      if (names[i] == names[j])
      {
        throw InputError("two targets are named '" + names[i] + "'; target names must be unique");
      }
    }
  }
}

void SetTargetNames(vtkFieldData* fd, const std::vector<std::string>& names)
{
  fd->RemoveArray(TargetNamesArray);
  fd->AddArray(MakeNamesArray(TargetNamesArray, names));
}

vtkSmartPointer<vtkStringArray> MakeNamesArray(
  const char* arrayName, const std::vector<std::string>& names)
{
  auto array = vtkSmartPointer<vtkStringArray>::New();
  array->SetName(arrayName);
  array->SetNumberOfValues(static_cast<vtkIdType>(names.size()));
  for (size_t i = 0; i < names.size(); ++i)
  {
    array->SetValue(static_cast<vtkIdType>(i), names[i]);
  }
  return array;
}

template <typename T>
std::vector<T> ToVector(vtkDataArray* array)
{
  std::vector<T> values;
  ToVectorWorker<T> worker{ values };
  if (!vtkArrayDispatch::Dispatch::Execute(array, worker))
  {
    worker(array); // any other array type, through the generic range
  }
  return values;
}

template <typename T>
void CopyToArray(const T* values, vtkDataArray* array)
{
  CopyToArrayWorker<T> worker{ values };
  if (!vtkArrayDispatch::Dispatch::Execute(array, worker))
  {
    worker(array);
  }
}

template <typename T>
vtkSmartPointer<vtkDataArray> NewArray(
  int vtkType, const char* name, int components, vtkIdType numTuples, const T* values)
{
  vtkSmartPointer<vtkDataArray> array;
  array.TakeReference(vtkDataArray::CreateDataArray(vtkType));
  if (!array)
  {
    throw InputError("VTK type " + std::to_string(vtkType) + " is not a numeric array type");
  }
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(numTuples);
  CopyToArray(values, array.GetPointer());
  return array;
}

void AddAttribute(morphnode::MorphMesh& mesh, const std::string& name, AttributeRole role,
  vtkDataArray* neutral, const std::vector<vtkDataArray*>& targets, bool relative,
  double sparseCoverage)
{
  const vtkIdType numPoints = static_cast<vtkIdType>(mesh.GetNumberOfPoints());
  const int c = neutral ? neutral->GetNumberOfComponents() : 0;
  auto check = [&](vtkDataArray* array, size_t target)
  {
    if (!array || array->GetNumberOfComponents() != c || array->GetNumberOfTuples() != numPoints)
    {
      std::ostringstream msg;
      msg << "attribute '" << name << "': ";
      if (target == 0)
      {
        msg << "the neutral's";
      }
      else
      {
        msg << "target " << target << "'s";
      }
      if (!array)
      {
        msg << " array is missing";
      }
      else
      {
        msg << " array '" << (array->GetName() ? array->GetName() : "") << "' has "
            << array->GetNumberOfTuples() << " tuples of " << array->GetNumberOfComponents()
            << " components, expected " << numPoints << " of " << c;
      }
      throw InputError(msg.str());
    }
  };
  check(neutral, 0);
  for (size_t i = 0; i < targets.size(); ++i)
  {
    check(targets[i], i + 1);
  }
  auto fill = [&](auto& attribute)
  {
    using T = typename std::decay_t<decltype(attribute.GetNeutral())>::value_type;
    attribute.SetNeutral(ToVector<T>(neutral).data());
    if (IsIntegerType(neutral->GetDataType()))
    {
      attribute.SetClampRange(neutral->GetDataTypeMin(), neutral->GetDataTypeMax());
    }
    for (vtkDataArray* target : targets)
    {
      const std::vector<T> values = ToVector<T>(target);
      if (relative)
      {
        attribute.AddRelativeTarget(values.data(), sparseCoverage);
      }
      else
      {
        attribute.AddAbsoluteTarget(values.data(), sparseCoverage);
      }
    }
  };
  if (neutral->GetDataType() == VTK_FLOAT)
  {
    fill(mesh.AddAttribute<float>(name, role, c));
  }
  else
  {
    fill(mesh.AddAttribute<double>(name, role, c));
  }
}

std::vector<uint32_t> GetTriangles(vtkPolyData* mesh, bool fan)
{
  if (mesh->GetNumberOfStrips() > 0)
  {
    throw InputError("the input has triangle strips; convert them with vtkTriangleFilter first");
  }
  std::vector<uint32_t> triangles;
  vtkCellArray* polys = mesh->GetPolys();
  if (!polys)
  {
    return triangles;
  }
  triangles.reserve(3 * static_cast<size_t>(polys->GetNumberOfCells()));
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType size;
    const vtkIdType* ids;
    it->GetCurrentCell(size, ids);
    if (size != 3 && !fan)
    {
      throw InputError("polygon " + std::to_string(it->GetCurrentCellId()) + " has " +
        std::to_string(size) + " points; the input must be triangles (use vtkTriangleFilter)");
    }
    for (vtkIdType k = 1; k + 1 < size; ++k)
    {
      triangles.push_back(static_cast<uint32_t>(ids[0]));
      triangles.push_back(static_cast<uint32_t>(ids[k]));
      triangles.push_back(static_cast<uint32_t>(ids[k + 1]));
    }
  }
  return triangles;
}

MeshFromVTK ToMorphMesh(vtkPointSet* input, const ReadOptions& options)
{
  if (!input)
  {
    throw InputError("no input");
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numPoints == 0 || !input->GetPoints())
  {
    throw InputError("the input has no points");
  }
  vtkPointData* pd = input->GetPointData();
  const size_t numDeltas = CountTargets(pd, numPoints);

  MeshFromVTK result{ morphnode::MorphMesh(static_cast<size_t>(numPoints)), nullptr, {} };
  morphnode::MorphMesh& mesh = result.Mesh;
  mesh.SetTargetNames(GetTargetNames(input->GetFieldData(), numDeltas + 1));
  CheckUniqueNames(mesh.GetTargetNames());

  auto deltas = [&](Kind kind)
  {
    std::vector<vtkDataArray*> arrays;
    for (size_t k = 0; k < numDeltas; ++k)
    {
      arrays.push_back(GetDeltas(pd, k, kind, numPoints));
    }
    return arrays;
  };
  AddAttribute(mesh, PointsAttributeName, AttributeRole::Position, input->GetPoints()->GetData(),
    deltas(Kind::Position), true, options.SparseCoverage);

  vtkDataArray* normals = options.Normals && numDeltas > 0 ? NormalsOf(input) : nullptr;
  if (normals)
  {
    const std::vector<vtkDataArray*> normalDeltas = deltas(Kind::Normal);
    if (std::find(normalDeltas.begin(), normalDeltas.end(), nullptr) == normalDeltas.end())
    {
      AddAttribute(mesh, normals->GetName() ? normals->GetName() : "Normals", AttributeRole::Normal,
        normals, normalDeltas, true, options.SparseCoverage);
      result.Normals = normals;
    }
  }

  if (options.Triangles)
  {
    auto* poly = vtkPolyData::SafeDownCast(input);
    if (!poly)
    {
      throw InputError("the input must be a vtkPolyData of triangles");
    }
    std::vector<uint32_t> triangles = GetTriangles(poly, false);
    if (triangles.empty())
    {
      throw InputError("the input has no triangles");
    }
    mesh.SetTriangles(std::move(triangles));
  }

  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    if (IsTargetArrayName(pd->GetArrayName(a)))
    {
      result.TargetArrays.emplace_back(pd->GetArrayName(a));
    }
  }
  mesh.Validate();
  return result;
}

void AddTargetArrays(
  const morphnode::MorphMesh& mesh, vtkPointData* pd, int positionType, int normalType)
{
  bool position = false, normal = false;
  for (size_t a = 0; a < mesh.GetNumberOfAttributes(); ++a)
  {
    std::visit(
      [&](const auto& attribute)
      {
        if (attribute.GetRole() == AttributeRole::Position && !position)
        {
          AddDeltaArrays(attribute, Kind::Position, positionType, pd);
          position = true;
        }
        else if (attribute.GetRole() == AttributeRole::Normal && !normal)
        {
          AddDeltaArrays(attribute, Kind::Normal, normalType, pd);
          normal = true;
        }
      },
      mesh.GetAttribute(a));
  }
}

vtkSmartPointer<vtkPolyData> ToPolyData(const morphnode::MorphMesh& mesh)
{
  mesh.Validate();
  const int position = mesh.GetPositionAttribute();
  if (position < 0 ||
    std::visit([](const auto& a) { return a.GetNumberOfComponents(); },
      mesh.GetAttribute(static_cast<size_t>(position))) != 3)
  {
    throw InputError("the mesh has no Position attribute of 3 components");
  }
  auto output = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetData(NeutralArray(mesh.GetAttribute(static_cast<size_t>(position)), nullptr));
  output->SetPoints(points);

  const std::vector<uint32_t>& triangles = mesh.GetTriangles();
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(
    static_cast<vtkIdType>(mesh.GetNumberOfTriangles()), static_cast<vtkIdType>(triangles.size()));
  for (size_t t = 0; t < mesh.GetNumberOfTriangles(); ++t)
  {
    const vtkIdType ids[3] = { triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2] };
    polys->InsertNextCell(3, ids);
  }
  output->SetPolys(polys);

  vtkPointData* pd = output->GetPointData();
  bool normals = false;
  for (size_t a = 0; a < mesh.GetNumberOfAttributes(); ++a)
  {
    const morphnode::AnyMorphAttribute& any = mesh.GetAttribute(a);
    const AttributeRole role = std::visit([](const auto& x) { return x.GetRole(); }, any);
    const std::string name = std::visit([](const auto& x) { return x.GetName(); }, any);
    if (static_cast<int>(a) == position)
    {
      continue;
    }
    if (role == AttributeRole::Normal && !normals)
    {
      pd->SetNormals(NeutralArray(any, name.c_str()));
      normals = true;
      continue;
    }
    std::visit(
      [&](const auto& attribute)
      {
        for (size_t k = 1; k < attribute.GetNumberOfTargets(); ++k)
        {
          if (attribute.GetTarget(k).GetNumberOfMovedPoints() > 0)
          {
            throw InputError("attribute '" + name + "' is morphed by target '" +
              mesh.GetTargetNames()[k] +
              "'; the target<k>_* arrays hold only positions and normals");
          }
        }
      },
      any);
    pd->AddArray(NeutralArray(any, name.c_str()));
  }
  AddTargetArrays(mesh, pd);
  SetTargetNames(output->GetFieldData(), mesh.GetTargetNames());
  return output;
}

template std::vector<float> ToVector<float>(vtkDataArray*);
template std::vector<double> ToVector<double>(vtkDataArray*);
template void CopyToArray<float>(const float*, vtkDataArray*);
template void CopyToArray<double>(const double*, vtkDataArray*);
template vtkSmartPointer<vtkDataArray> NewArray<float>(
  int, const char*, int, vtkIdType, const float*);
template vtkSmartPointer<vtkDataArray> NewArray<double>(
  int, const char*, int, vtkIdType, const double*);
//------------------------------------------------------------------------------
void GatherTuples(vtkDataSetAttributes* in, vtkIdList* ids, vtkDataSetAttributes* out)
{
  const vtkIdType n = ids->GetNumberOfIds();
  out->CopyAllocate(in, n);
  out->SetNumberOfTuples(n);
  for (int a = 0; a < out->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* target = out->GetAbstractArray(a);
    if (vtkAbstractArray* source =
          target->GetName() ? in->GetAbstractArray(target->GetName()) : nullptr)
    {
      source->GetTuples(ids, target);
    }
  }
}

void ExtractPointSubset(vtkPolyData* input, const std::vector<uint32_t>& ids, vtkIdType numPoints,
  const std::vector<uint32_t>& triangles, vtkPolyData* output, vtkPoints* points)
{
  const vtkIdType n = std::min(numPoints, static_cast<vtkIdType>(ids.size()));
  vtkNew<vtkIdList> from;
  from->SetNumberOfIds(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    from->SetId(i, static_cast<vtkIdType>(ids[static_cast<size_t>(i)]));
  }
  vtkSmartPointer<vtkPoints> outPoints = points;
  if (!outPoints)
  {
    outPoints = vtkSmartPointer<vtkPoints>::New();
    outPoints->SetDataType(input->GetPoints()->GetDataType());
    outPoints->SetNumberOfPoints(n);
    input->GetPoints()->GetData()->GetTuples(from, outPoints->GetData());
  }
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(
    static_cast<vtkIdType>(triangles.size() / 3), static_cast<vtkIdType>(triangles.size()));
  for (size_t t = 0; t + 2 < triangles.size(); t += 3)
  {
    const vtkIdType tri[3] = { triangles[t], triangles[t + 1], triangles[t + 2] };
    polys->InsertNextCell(3, tri);
  }
  output->Initialize();
  output->SetPoints(outPoints);
  output->SetPolys(polys);
  // Every point array (normals, texture coordinates, target deltas) comes unchanged from
  // the point each output point is.
  vtkPointData* outPD = output->GetPointData();
  GatherTuples(input->GetPointData(), from, outPD);
  vtkNew<vtkIdTypeArray> original;
  original->SetName("OriginalPointId");
  original->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    original->SetValue(i, from->GetId(i));
  }
  outPD->AddArray(original);
  output->GetFieldData()->PassData(input->GetFieldData());
}

} // namespace vtkMorphTargetArrays
