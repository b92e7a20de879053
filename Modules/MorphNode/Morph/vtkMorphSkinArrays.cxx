// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphSkinArrays.h"

#include "base/Error.h"
#include "gltf/GltfSkin.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedShortArray.h"

#include <cmath>

namespace vtkMorphSkinArrays
{
namespace
{
void AddMatrices(vtkFieldData* fd, const char* name,
  const std::vector<morphnode::GltfMatrix>& matrices, double scale)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfComponents(16);
  array->SetNumberOfTuples(static_cast<vtkIdType>(matrices.size()));
  for (size_t i = 0; i < matrices.size(); ++i)
  {
    for (int k = 0; k < 16; ++k)
    {
      array->SetTypedComponent(static_cast<vtkIdType>(i), k,
        k >= 12 && k < 15 ? scale * matrices[i][static_cast<size_t>(k)]
                          : matrices[i][static_cast<size_t>(k)]);
    }
  }
  fd->AddArray(array);
}

std::vector<glm::dmat4> MatricesOf(
  vtkFieldData* fd, const char* name, vtkIdType count, const std::string& what)
{
  vtkDataArray* array = fd->GetArray(name);
  if (!array || array->GetNumberOfComponents() != 16 || array->GetNumberOfTuples() != count)
  {
    throw morphnode::InputError(what + ": field data " + name + " is missing or does not hold " +
      std::to_string(count) + " 4x4 matrices");
  }
  std::vector<glm::dmat4> out(static_cast<size_t>(count));
  for (vtkIdType i = 0; i < count; ++i)
  {
    for (int k = 0; k < 16; ++k)
    {
      const double v = array->GetComponent(i, k);
      if (!std::isfinite(v))
      {
        throw morphnode::InputError(what + ": field data " + name + " is not finite");
      }
      out[static_cast<size_t>(i)][k / 4][k % 4] = v;
    }
  }
  return out;
}
} // namespace

bool IsSkinned(vtkDataSet* data)
{
  return data && data->GetPointData()->GetArray(WeightsArray) != nullptr;
}

void AddSkin(vtkPolyData* poly, const morphnode::GltfScene& scene, const morphnode::GltfPart& part,
  const std::vector<morphnode::GltfMatrix>& locals, double scale)
{
  const morphnode::GltfSkin& skin = scene.Skins.at(static_cast<size_t>(part.Skin));
  const morphnode::SkinInfluences& inf = part.Influences;
  const vtkIdType n = static_cast<vtkIdType>(inf.GetNumberOfPoints());
  const int per = static_cast<int>(inf.PerPoint);
  vtkNew<vtkUnsignedShortArray> joints;
  joints->SetName(JointsArray);
  joints->SetNumberOfComponents(per);
  joints->SetNumberOfTuples(n);
  std::copy(inf.Joints.begin(), inf.Joints.end(), joints->GetPointer(0));
  vtkNew<vtkFloatArray> weights;
  weights->SetName(WeightsArray);
  weights->SetNumberOfComponents(per);
  weights->SetNumberOfTuples(n);
  std::copy(inf.Weights.begin(), inf.Weights.end(), weights->GetPointer(0));
  poly->GetPointData()->AddArray(joints);
  poly->GetPointData()->AddArray(weights);

  vtkFieldData* fd = poly->GetFieldData();
  vtkNew<vtkIntArray> indices;
  indices->SetName(JointIndicesArray);
  for (int j : skin.Joints)
  {
    indices->InsertNextValue(j);
  }
  fd->AddArray(indices);
  AddMatrices(fd, InverseBindArray, skin.InverseBind, scale);
  vtkNew<vtkStringArray> names;
  names->SetName(SkeletonNamesArray);
  vtkNew<vtkIntArray> parents;
  parents->SetName(SkeletonParentsArray);
  for (size_t i = 0; i < scene.Nodes.size(); ++i)
  {
    names->InsertNextValue(morphnode::GltfNodeName(scene, static_cast<int>(i)));
    parents->InsertNextValue(scene.Nodes[i].Parent);
  }
  fd->AddArray(names);
  fd->AddArray(parents);
  AddMatrices(fd, SkeletonRestArray, locals, scale);
}

void AddVrm(vtkPolyData* poly, const morphnode::GltfVrm& vrm)
{
  vtkFieldData* fd = poly->GetFieldData();
  if (!vrm.HumanBoneNodeNames.empty())
  {
    vtkNew<vtkStringArray> bones;
    bones->SetName(HumanoidBonesArray);
    for (const auto& [bone, node] : vrm.HumanBoneNodeNames)
    {
      std::string entry = bone;
      entry += '=';
      entry += node;
      bones->InsertNextValue(entry);
    }
    fd->AddArray(bones);
  }
  if (vrm.LookAtType == "bone")
  {
    vtkNew<vtkDoubleArray> maps;
    maps->SetName(LookAtRangeMapsArray);
    for (const morphnode::GltfVrmRangeMap* m :
      { &vrm.HorizontalInner, &vrm.HorizontalOuter, &vrm.VerticalDown, &vrm.VerticalUp })
    {
      maps->InsertNextValue(m->InputMax);
      maps->InsertNextValue(m->OutputScale);
    }
    fd->AddArray(maps);
  }
}

std::vector<glm::dmat4> Skin::RestMatrices() const
{
  return this->Joints.Matrices(this->Bones.World(this->Bones.RestLocals()));
}

Skin GetSkin(vtkDataSet* data, const std::string& what)
{
  vtkPointData* pd = data->GetPointData();
  auto* joints = vtkUnsignedShortArray::SafeDownCast(pd->GetArray(JointsArray));
  auto* weights = vtkFloatArray::SafeDownCast(pd->GetArray(WeightsArray));
  const vtkIdType n = data->GetNumberOfPoints();
  if (!joints || !weights || joints->GetNumberOfComponents() != weights->GetNumberOfComponents() ||
    joints->GetNumberOfComponents() < 1 || joints->GetNumberOfTuples() != n ||
    weights->GetNumberOfTuples() != n)
  {
    throw morphnode::InputError(what +
      ": point data SkinJoints (unsigned short) and SkinWeights (float) must have " +
      "the same components and one tuple per point");
  }
  vtkFieldData* fd = data->GetFieldData();
  auto* indices = vtkIntArray::SafeDownCast(fd->GetArray(JointIndicesArray));
  auto* names = vtkStringArray::SafeDownCast(fd->GetAbstractArray(SkeletonNamesArray));
  auto* parents = vtkIntArray::SafeDownCast(fd->GetArray(SkeletonParentsArray));
  if (!indices || !names || !parents || indices->GetNumberOfTuples() < 1 ||
    parents->GetNumberOfValues() != names->GetNumberOfValues())
  {
    throw morphnode::InputError(what +
      ": field data SkinJointIndices, SkeletonNames and SkeletonParents are missing "
      "or differ in size");
  }
  Skin skin;
  const vtkIdType numNodes = names->GetNumberOfValues();
  const std::vector<glm::dmat4> rest = MatricesOf(fd, SkeletonRestArray, numNodes, what);
  for (vtkIdType i = 0; i < numNodes; ++i)
  {
    morphnode::Joint joint;
    joint.Name = names->GetValue(i);
    joint.Parent = parents->GetValue(i);
    joint.HasMatrix = true;
    joint.Matrix = rest[static_cast<size_t>(i)];
    skin.Bones.AddJoint(joint);
  }
  skin.Bones.Validate();
  for (vtkIdType k = 0; k < indices->GetNumberOfTuples(); ++k)
  {
    skin.Joints.Joints.push_back(indices->GetValue(k));
  }
  skin.Joints.InverseBind = MatricesOf(fd, InverseBindArray, indices->GetNumberOfTuples(), what);
  skin.Joints.Validate(skin.Bones, what);
  skin.Influences.PerPoint = static_cast<size_t>(joints->GetNumberOfComponents());
  skin.Influences.Joints.assign(
    joints->GetPointer(0), joints->GetPointer(0) + joints->GetNumberOfValues());
  skin.Influences.Weights.assign(
    weights->GetPointer(0), weights->GetPointer(0) + weights->GetNumberOfValues());
  skin.Influences.Normalize(skin.Joints.Joints.size(), what);
  if (auto* bones = vtkStringArray::SafeDownCast(fd->GetAbstractArray(HumanoidBonesArray)))
  {
    for (vtkIdType i = 0; i < bones->GetNumberOfValues(); ++i)
    {
      const std::string entry = bones->GetValue(i);
      const size_t eq = entry.find('=');
      if (eq != std::string::npos)
      {
        skin.Humanoid[entry.substr(0, eq)] = entry.substr(eq + 1);
      }
    }
  }
  auto* maps = vtkDataArray::SafeDownCast(fd->GetAbstractArray(LookAtRangeMapsArray));
  if (maps && maps->GetNumberOfValues() == 8)
  {
    double v[8];
    for (int k = 0; k < 8; ++k)
    {
      v[k] =
        maps->GetComponent(k / maps->GetNumberOfComponents(), k % maps->GetNumberOfComponents());
      if (!std::isfinite(v[k]) || v[k] < 0.0)
      {
        throw morphnode::InputError(what + ": LookAtRangeMaps must be 8 finite values >= 0");
      }
    }
    morphnode::EyeRangeMaps& r = skin.RangeMaps;
    r.Enabled = true;
    r.InnerMax = v[0], r.InnerScale = v[1], r.OuterMax = v[2], r.OuterScale = v[3];
    r.DownMax = v[4], r.DownScale = v[5], r.UpMax = v[6], r.UpScale = v[7];
  }
  return skin;
}
} // namespace vtkMorphSkinArrays
