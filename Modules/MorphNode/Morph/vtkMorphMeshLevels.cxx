// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphMeshLevels.h"

#include "vtkMorphSkinArrays.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "skin/AvatarBones.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <type_traits>
#include <variant>
#include <vector>

namespace vtkMorphMeshLevels
{
namespace
{
/// Triangles only (no strips, lines or other polygons), and enough of them to reduce.
bool Reducible(vtkPointSet* part)
{
  auto* poly = vtkPolyData::SafeDownCast(part);
  return poly && poly->GetNumberOfStrips() == 0 && poly->GetNumberOfLines() == 0 &&
    poly->GetNumberOfVerts() == 0 &&
    poly->GetNumberOfPolys() >= static_cast<vtkIdType>(MinimumTriangles) &&
    poly->GetPolys()->IsHomogeneous() == 3;
}

/// The poses a skinned part takes in the avatar, for its level errors (LadderSettings::
/// SkinPoses): the head turned by 25 degrees, nodded by 15, the eyes turned by 25 (the bones
/// vtkMorphSkinFilter moves, found by name). The part's points are rest-posed
/// (vtkMorphSkinArrays), so each pose is given as J_k(pose) J_k(rest)^-1 per joint of its
/// skin: exact where a point's joints share one rest matrix, the usual case
/// (skin/Skinning.h's RestSkin). None when the skeleton has no head or eyes.
std::vector<std::vector<glm::dmat4>> AvatarSkinPoses(const vtkMorphSkinArrays::Skin& skin)
{
  const morphnode::AvatarBoneRoles roles = morphnode::FindAvatarBones(skin.Bones);
  std::vector<std::vector<glm::dmat4>> poses;
  if (roles.Head < 0 && !roles.HasEyes())
  {
    return poses;
  }
  const std::vector<glm::dmat4> rest = skin.RestMatrices();
  const double turns[3][3] = { { 25.0, 0.0, 0.0 }, { 0.0, 15.0, 0.0 }, { 0.0, 0.0, 25.0 } };
  for (const auto& turn : turns)
  {
    morphnode::AvatarBonePose angles;
    angles.HeadYaw = turn[0];
    angles.HeadPitch = turn[1];
    angles.EyeYaw = turn[2];
    morphnode::SkeletonPose pose(skin.Bones);
    morphnode::PoseAvatarBones(pose, roles, angles);
    std::vector<glm::dmat4> matrices = skin.Joints.Matrices(pose.World());
    for (size_t k = 0; k < matrices.size() && k < rest.size(); ++k)
    {
      matrices[k] = matrices[k] * glm::inverse(rest[k]);
    }
    poses.push_back(std::move(matrices));
  }
  return poses;
}

/// Blends attribute `a` of the part at the shown level into `array` (n tuples).
template <typename T>
void BlendInto(
  const morphnode::ScalableScene& scene, size_t part, size_t a, vtkDataArray* array, size_t n)
{
  const int nc = array->GetNumberOfComponents();
  if (array->GetDataType() == (std::is_same_v<T, float> ? VTK_FLOAT : VTK_DOUBLE))
  {
    scene.BlendAttribute(part, a, static_cast<T*>(array->GetVoidPointer(0)));
    return;
  }
  std::vector<T> values(n * static_cast<size_t>(nc));
  scene.BlendAttribute(part, a, values.data());
  for (size_t p = 0; p < n; ++p)
  {
    for (int c = 0; c < nc; ++c)
    {
      array->SetComponent(
        static_cast<vtkIdType>(p), c, values[p * static_cast<size_t>(nc) + static_cast<size_t>(c)]);
    }
  }
}
} // namespace

std::shared_ptr<const morphnode::MorphLadder> BuildLadder(const morphnode::MorphMesh& model,
  vtkPointSet* part, const morphnode::LadderSettings& settings, const std::string& what)
{
  try
  {
    if (!part || static_cast<size_t>(part->GetNumberOfPoints()) != model.GetNumberOfPoints())
    {
      throw morphnode::InputError("the part's data set does not fit its model");
    }
    const bool reduce = Reducible(part);
    morphnode::MorphMesh mesh = model;
    mesh.SetTriangles(reduce
        ? vtkMorphTargetArrays::GetTriangles(vtkPolyData::SafeDownCast(part), false)
        : std::vector<uint32_t>());
    morphnode::SkinInfluences influences;
    morphnode::LadderSettings s = settings;
    if (vtkMorphSkinArrays::IsSkinned(part))
    {
      const vtkMorphSkinArrays::Skin skin = vtkMorphSkinArrays::GetSkin(part, what);
      influences = skin.Influences;
      if (s.SkinPoses.empty() && reduce)
      {
        s.SkinPoses = AvatarSkinPoses(skin);
      }
    }
    if (!reduce)
    {
      s.TriangleFractions.clear(); // kept whole, in the input's numbering
    }
    return std::make_shared<const morphnode::MorphLadder>(
      morphnode::BuildMorphLadder(mesh, influences, s));
  }
  catch (const morphnode::InputError& e)
  {
    throw morphnode::InputError(what + ": " + e.what());
  }
}

std::shared_ptr<const morphnode::MorphLadder> BuildLadder(
  vtkPointSet* part, const morphnode::LadderSettings& settings, const std::string& what)
{
  try
  {
    return BuildLadder(vtkMorphTargetArrays::ToMorphMesh(part, {}).Mesh, part, settings, what);
  }
  catch (const morphnode::InputError& e)
  {
    throw morphnode::InputError(what + ": " + e.what());
  }
}

void Assembler::Reset()
{
  this->Levels.clear();
  this->Previous.clear();
}

void Assembler::Assemble(
  const morphnode::ScalableScene& scene, size_t part, vtkPointSet* input, vtkPolyData* output)
{
  const morphnode::MorphLadder& ladder = scene.GetLadder(part);
  const morphnode::SceneFrame& frame = scene.GetFrame();
  if (part >= frame.PartPoints.size() || !input ||
    static_cast<size_t>(input->GetNumberOfPoints()) != ladder.Mesh.GetNumberOfPoints())
  {
    throw morphnode::InputError("a part's level asked for before its frame, or of another input");
  }
  const size_t n = frame.PartPoints[part];
  const auto vn = static_cast<vtkIdType>(n);
  const int level = frame.PartLevels[part];
  if (this->Levels.size() < scene.GetNumberOfParts())
  {
    this->Levels.resize(scene.GetNumberOfParts());
  }
  this->Levels[part].resize(ladder.Levels.size());
  Level& made = this->Levels[part][static_cast<size_t>(level)];
  if (!made.Gathered)
  {
    // The input's arrays gathered to the level's points (the target arrays left out), and
    // the points' ids in the input.
    vtkNew<vtkIdList> from;
    from->SetNumberOfIds(vn);
    for (vtkIdType i = 0; i < vn; ++i)
    {
      from->SetId(i, static_cast<vtkIdType>(ladder.OriginalPointIds[static_cast<size_t>(i)]));
    }
    vtkPointData* inPD = input->GetPointData();
    made.Gathered = vtkSmartPointer<vtkPointData>::New();
    made.Gathered->CopyAllocate(inPD, vn);
    made.Gathered->SetNumberOfTuples(vn);
    for (int a = 0; a < made.Gathered->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* target = made.Gathered->GetAbstractArray(a);
      if (vtkAbstractArray* source =
            target->GetName() ? inPD->GetAbstractArray(target->GetName()) : nullptr)
      {
        source->GetTuples(from, target);
      }
    }
    vtkMorphTargetArrays::RemoveTargetArrays(made.Gathered);
    vtkNew<vtkIdTypeArray> original;
    original->SetName(OriginalPointIdArray);
    original->SetNumberOfTuples(vn);
    for (vtkIdType i = 0; i < vn; ++i)
    {
      original->SetValue(i, from->GetId(i));
    }
    made.Gathered->AddArray(original);
    if (ladder.Levels.size() > 1 || !vtkPolyData::SafeDownCast(input))
    {
      const std::vector<uint32_t>& triangles = ladder.Levels[static_cast<size_t>(level)].Triangles;
      made.Polys = vtkSmartPointer<vtkCellArray>::New();
      made.Polys->AllocateExact(
        static_cast<vtkIdType>(triangles.size() / 3), static_cast<vtkIdType>(triangles.size()));
      for (size_t t = 0; t + 2 < triangles.size(); t += 3)
      {
        const vtkIdType tri[3] = { triangles[t], triangles[t + 1], triangles[t + 2] };
        made.Polys->InsertNextCell(3, tri);
      }
    }
  }

  output->Initialize();
  if (this->Previous.size() < scene.GetNumberOfParts())
  {
    this->Previous.resize(scene.GetNumberOfParts());
  }
  Last& last = this->Previous[part];
  const bool reuse = !scene.IsPartChanged(part) && last.Level == level && last.Points;
  if (!reuse)
  {
    last.Level = level;
    last.Morphed.clear();
    last.Points = vtkSmartPointer<vtkPoints>::New();
    last.Points->SetDataTypeToFloat();
    last.Points->SetNumberOfPoints(vn);
    std::copy_n(scene.GetPositions(part).data(), 3 * n,
      static_cast<float*>(last.Points->GetData()->GetVoidPointer(0)));
  }
  output->SetPoints(last.Points);
  if (made.Polys)
  {
    output->SetPolys(made.Polys);
  }
  else
  {
    // Kept whole: the input's own cells (the numbering is the input's).
    auto* poly = vtkPolyData::SafeDownCast(input);
    output->SetVerts(poly->GetVerts());
    output->SetLines(poly->GetLines());
    output->SetPolys(poly->GetPolys());
    output->SetStrips(poly->GetStrips());
  }

  // The level's gathered arrays, shared; the morphed ones (normals, ...) new, blended (or
  // the last output's, when the part did not change).
  vtkPointData* outPD = output->GetPointData();
  outPD->ShallowCopy(made.Gathered);
  if (reuse)
  {
    for (vtkDataArray* array : last.Morphed)
    {
      outPD->AddArray(array);
    }
  }
  const int position = ladder.Mesh.GetPositionAttribute();
  for (size_t a = 0; a < ladder.Mesh.GetNumberOfAttributes() && !reuse; ++a)
  {
    if (static_cast<int>(a) == position)
    {
      continue;
    }
    const morphnode::AnyMorphAttribute& attribute = ladder.Mesh.GetAttribute(a);
    const std::string& name =
      std::visit([](const auto& v) -> const std::string& { return v.GetName(); }, attribute);
    vtkDataArray* gathered = outPD->GetArray(name.c_str());
    if (!gathered)
    {
      continue;
    }
    vtkSmartPointer<vtkDataArray> array = vtk::TakeSmartPointer(gathered->NewInstance());
    array->SetName(gathered->GetName());
    array->SetNumberOfComponents(gathered->GetNumberOfComponents());
    array->SetNumberOfTuples(vn);
    if (std::holds_alternative<morphnode::MorphAttribute<float>>(attribute))
    {
      BlendInto<float>(scene, part, a, array, n);
    }
    else
    {
      BlendInto<double>(scene, part, a, array, n);
    }
    outPD->AddArray(array); // in the gathered one's place (and attribute)
    last.Morphed.push_back(array);
  }

  output->GetFieldData()->PassData(input->GetFieldData());
  const morphnode::ControllerDecision& d = frame.Decision;
  const bool slides = d.MorphTowards >= 0 && level == d.Level &&
    static_cast<size_t>(level) + 1 < ladder.Levels.size();
  vtkNew<vtkDoubleArray> lod;
  lod->SetName(LevelOfDetailArray);
  lod->SetNumberOfComponents(5);
  lod->SetComponentName(0, "Level");
  lod->SetComponentName(1, "MorphTowards");
  lod->SetComponentName(2, "Alpha");
  lod->SetComponentName(3, "ActiveTargets");
  lod->SetComponentName(4, "Points");
  const double tuple[5] = { static_cast<double>(level),
    slides ? static_cast<double>(d.MorphTowards) : -1.0, slides ? d.Alpha : 0.0,
    static_cast<double>(d.ActiveTargets), static_cast<double>(frame.NumberOfPoints) };
  lod->InsertNextTuple(tuple);
  output->GetFieldData()->AddArray(lod);
}
void SceneLevels::Clear()
{
  if (this->Inputs.empty() && this->Generation == 0)
  {
    return; // nothing built
  }
  this->Generation = 0;
  this->Inputs.clear();
  this->Scene = morphnode::ScalableScene();
  this->Configured = false;
  this->Output.Reset();
}

void SceneLevels::SetParts(const std::vector<const morphnode::MorphMesh*>& models,
  const std::vector<vtkPointSet*>& parts, const std::vector<std::string>& names,
  uint64_t generation)
{
  if (generation == this->Generation && !this->Inputs.empty())
  {
    return;
  }
  this->Clear();
  morphnode::ScalableScene::Ladders ladders;
  if (models.size() != parts.size() ||
    std::find(models.begin(), models.end(), nullptr) != models.end())
  {
    throw morphnode::InputError("mesh levels: a part without its model");
  }
  for (size_t p = 0; p < parts.size(); ++p)
  {
    ladders.push_back(BuildLadder(
      *models[p], parts[p], morphnode::LadderSettings(), p < names.size() ? names[p] : "a part"));
  }
  this->Scene.SetParts(ladders, morphnode::ScalableScene::Calibrate(ladders));
  this->Inputs = parts;
  this->Generation = generation;
}

const morphnode::SceneFrame& SceneLevels::Update(const std::vector<std::string>& names,
  const std::vector<double>& weights, const morphnode::ControllerSettings& settings,
  double pixelsPerUnit)
{
  if (this->Inputs.empty())
  {
    throw morphnode::InputError("mesh levels: no parts");
  }
  const morphnode::ControllerSettings& was = this->Scene.GetSettings();
  if (!this->Configured || was.FrameBudget != settings.FrameBudget ||
    was.PixelBound != settings.PixelBound || was.FinestLevel != settings.FinestLevel ||
    was.MaxGeomorphPixels != settings.MaxGeomorphPixels || was.Thresholds != settings.Thresholds ||
    was.TargetPixelBound != settings.TargetPixelBound)
  {
    this->Scene.SetSettings(settings);
    this->Configured = true;
  }
  // The filter's weights by name onto the scene's targets (the same names: both are the
  // parts' matched as MorphScene matches them).
  const std::vector<std::string>& targets = this->Scene.GetTargetNames();
  this->Weights.assign(targets.size(), 0.0);
  for (size_t t = 1; t < targets.size() && !names.empty(); ++t)
  {
    const auto it = std::find(names.begin() + 1, names.end(), targets[t]);
    if (it != names.end() && static_cast<size_t>(it - names.begin()) < weights.size())
    {
      this->Weights[t] = weights[static_cast<size_t>(it - names.begin())];
    }
  }
  double sum = 0.0;
  for (size_t t = 1; t < this->Weights.size(); ++t)
  {
    sum += this->Weights[t];
  }
  this->Weights[0] = 1.0 - sum; // the model's targets no part has weigh on the neutral
  return this->Scene.Update(this->Weights, pixelsPerUnit);
}

void SceneLevels::Assemble(size_t part, vtkPolyData* output)
{
  this->Output.Assemble(this->Scene, part, this->Inputs.at(part), output);
}
} // namespace vtkMorphMeshLevels
