// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphMeshLevels.h"

#include "vtkMorphNodeOutput.h"
#include "vtkMorphSkinArrays.h"
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "skin/AvatarBones.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCompositeDataSet.h"
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

void Assembler::MakeLevel(
  Level& made, const morphnode::MorphLadder& ladder, int level, vtkPointSet* input)
{
  const auto vn = static_cast<vtkIdType>(ladder.Levels[static_cast<size_t>(level)].NumberOfPoints);
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
  vtkMorphTargetArrays::GatherTuples(inPD, from, made.Gathered);
  vtkMorphTargetArrays::RemoveTargetArrays(made.Gathered);
  vtkNew<vtkIdTypeArray> original;
  original->SetName(OriginalPointIdArray);
  original->SetNumberOfTuples(vn);
  for (vtkIdType i = 0; i < vn; ++i)
  {
    original->SetValue(i, from->GetId(i));
  }
  made.Gathered->AddArray(original);
  made.ExtraSources.clear();
  made.Extras.clear();
  if (ladder.Levels.size() > 1 || !vtkPolyData::SafeDownCast(input))
  {
    const morphnode::LadderLevel& shown = ladder.Levels[static_cast<size_t>(level)];
    const std::vector<uint32_t>& triangles = shown.Triangles;
    const auto nt = static_cast<vtkIdType>(triangles.size() / 3);
    made.Polys = vtkSmartPointer<vtkCellArray>::New();
    made.Polys->AllocateExact(nt, static_cast<vtkIdType>(triangles.size()));
    for (size_t t = 0; t + 2 < triangles.size(); t += 3)
    {
      const vtkIdType tri[3] = { triangles[t], triangles[t + 1], triangles[t + 2] };
      made.Polys->InsertNextCell(3, tri);
    }
    // The input's cell data of each level triangle: a reduced part is a vtkPolyData of
    // triangles only (Reducible), so an input triangle's index is its cell id.
    vtkCellData* inCD = input->GetCellData();
    made.Cells = vtkSmartPointer<vtkCellData>::New();
    if (inCD->GetNumberOfArrays() > 0 &&
      shown.OriginalTriangleIds.size() == static_cast<size_t>(nt) &&
      input->GetNumberOfCells() >= static_cast<vtkIdType>(ladder.Levels[0].Triangles.size() / 3))
    {
      vtkNew<vtkIdList> cells;
      cells->SetNumberOfIds(nt);
      for (vtkIdType t = 0; t < nt; ++t)
      {
        cells->SetId(t, static_cast<vtkIdType>(shown.OriginalTriangleIds[static_cast<size_t>(t)]));
      }
      vtkMorphTargetArrays::GatherTuples(inCD, cells, made.Cells);
    }
  }
}

vtkPolyData* Assembler::Assemble(const morphnode::ScalableScene& scene, size_t part,
  vtkPointSet* input, const std::vector<vtkDataArray*>& extra)
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
    this->Previous.resize(scene.GetNumberOfParts());
  }
  this->Levels[part].resize(ladder.Levels.size());
  Level& made = this->Levels[part][static_cast<size_t>(level)];
  if (!made.Gathered)
  {
    this->MakeLevel(made, ladder, level, input);
  }
  if (made.ExtraSources != extra)
  {
    // The caller's per-point arrays (distance maps) gathered to the level's points.
    made.ExtraSources = extra;
    made.Extras.clear();
    vtkDataArray* ids = made.Gathered->GetArray(OriginalPointIdArray);
    vtkNew<vtkIdList> from;
    from->SetNumberOfIds(vn);
    for (vtkIdType i = 0; i < vn; ++i)
    {
      from->SetId(i, static_cast<vtkIdType>(ids->GetTuple1(i)));
    }
    for (vtkDataArray* source : extra)
    {
      if (!source || source->GetNumberOfTuples() != input->GetNumberOfPoints())
      {
        throw morphnode::InputError("mesh levels: an extra point array does not fit the part");
      }
      vtkSmartPointer<vtkDataArray> gathered = vtk::TakeSmartPointer(source->NewInstance());
      gathered->SetName(source->GetName());
      gathered->SetNumberOfComponents(source->GetNumberOfComponents());
      gathered->SetNumberOfTuples(vn);
      source->GetTuples(from, gathered);
      made.Extras.push_back(gathered);
    }
  }

  // The kept output: filled again when only this helper holds it, else a new one.
  Kept& kept = this->Previous[part];
  kept.Kept = kept.Output && kept.Output->GetReferenceCount() == 1;
  if (!kept.Kept)
  {
    kept.Output = vtkSmartPointer<vtkPolyData>::New();
    kept.Level = -1;
  }
  vtkPolyData* output = kept.Output;
  vtkPointData* outPD = output->GetPointData();
  // The structure, the gathered arrays and the cell data: again on a change of level.
  std::vector<vtkDataArray*> extrasNow;
  for (const auto& array : made.Extras)
  {
    extrasNow.push_back(array);
  }
  const bool restructure =
    kept.Level != level || kept.GatheredFrom != made.Gathered.Get() || kept.ExtrasFrom != extrasNow;
  kept.Kept = kept.Kept && !restructure;
  if (restructure)
  {
    output->Initialize();
    if (made.Polys)
    {
      output->SetPolys(made.Polys);
      output->GetCellData()->ShallowCopy(made.Cells);
    }
    else
    {
      // Kept whole: the input's own cells (the numbering is the input's) and cell data.
      auto* poly = vtkPolyData::SafeDownCast(input);
      output->SetVerts(poly->GetVerts());
      output->SetLines(poly->GetLines());
      output->SetPolys(poly->GetPolys());
      output->SetStrips(poly->GetStrips());
      output->GetCellData()->ShallowCopy(input->GetCellData());
    }
    outPD->ShallowCopy(made.Gathered);
    for (vtkDataArray* array : extrasNow)
    {
      outPD->AddArray(array);
    }
    output->GetFieldData()->PassData(input->GetFieldData());
    kept.GatheredFrom = made.Gathered;
    kept.ExtrasFrom = extrasNow;
  }

  // The points and the morphed arrays (normals, ...): untouched when the scene did not
  // blend the part again at this level; else written in place when only the kept output
  // and this helper hold them, or new.
  const bool same = !scene.IsPartChanged(part) && kept.Level == level && kept.Points;
  kept.Level = level;
  auto free = [](vtkObjectBase* object, bool inOutput)
  { return object && object->GetReferenceCount() == 1 + (inOutput ? 1 : 0); };
  if (!same)
  {
    if (!free(kept.Points, output->GetPoints() == kept.Points) ||
      kept.Points->GetData()->GetReferenceCount() != 1 || kept.Points->GetDataType() != VTK_FLOAT)
    {
      kept.Points = vtkSmartPointer<vtkPoints>::New();
      kept.Points->SetDataTypeToFloat();
    }
    kept.Points->SetNumberOfPoints(vn);
    std::copy_n(scene.GetPositions(part).data(), 3 * n,
      static_cast<float*>(kept.Points->GetData()->GetVoidPointer(0)));
    kept.Points->Modified();
  }
  output->SetPoints(kept.Points);
  const int position = ladder.Mesh.GetPositionAttribute();
  kept.Morphed.resize(ladder.Mesh.GetNumberOfAttributes());
  for (size_t a = 0; a < ladder.Mesh.GetNumberOfAttributes(); ++a)
  {
    if (static_cast<int>(a) == position)
    {
      continue;
    }
    vtkSmartPointer<vtkDataArray>& array = kept.Morphed[a];
    if (same && array && !restructure)
    {
      continue; // in the output as the last frame left it
    }
    if (!same || !array)
    {
      const morphnode::AnyMorphAttribute& attribute = ladder.Mesh.GetAttribute(a);
      const std::string& name =
        std::visit([](const auto& v) -> const std::string& { return v.GetName(); }, attribute);
      vtkDataArray* gathered = made.Gathered->GetArray(name.c_str());
      if (!gathered)
      {
        continue;
      }
      const bool inOutput = outPD->GetArray(name.c_str()) == array.Get() && array;
      if (!free(array, inOutput) || array->GetDataType() != gathered->GetDataType() ||
        array->GetNumberOfComponents() != gathered->GetNumberOfComponents())
      {
        array = vtk::TakeSmartPointer(gathered->NewInstance());
        array->SetName(gathered->GetName());
        array->SetNumberOfComponents(gathered->GetNumberOfComponents());
      }
      array->SetNumberOfTuples(vn);
      if (std::holds_alternative<morphnode::MorphAttribute<float>>(attribute))
      {
        BlendInto<float>(scene, part, a, array, n);
      }
      else
      {
        BlendInto<double>(scene, part, a, array, n);
      }
      array->Modified();
    }
    if (outPD->GetArray(array->GetName()) != array.Get())
    {
      outPD->AddArray(array); // in the gathered one's place (and attribute)
    }
  }

  const morphnode::ControllerDecision& d = frame.Decision;
  const bool slides = d.MorphTowards >= 0 && level == d.Level &&
    static_cast<size_t>(level) + 1 < ladder.Levels.size();
  vtkFieldData* fd = output->GetFieldData();
  if (!free(kept.LevelOfDetail, fd->GetArray(LevelOfDetailArray) == kept.LevelOfDetail.Get()))
  {
    kept.LevelOfDetail = vtkSmartPointer<vtkDoubleArray>::New();
    kept.LevelOfDetail->SetName(LevelOfDetailArray);
    kept.LevelOfDetail->SetNumberOfComponents(5);
    kept.LevelOfDetail->SetComponentName(0, "Level");
    kept.LevelOfDetail->SetComponentName(1, "MorphTowards");
    kept.LevelOfDetail->SetComponentName(2, "Alpha");
    kept.LevelOfDetail->SetComponentName(3, "ActiveTargets");
    kept.LevelOfDetail->SetComponentName(4, "Points");
    kept.LevelOfDetail->SetNumberOfTuples(1);
  }
  const double tuple[5] = { static_cast<double>(level),
    slides ? static_cast<double>(d.MorphTowards) : -1.0, slides ? d.Alpha : 0.0,
    static_cast<double>(d.ActiveTargets), static_cast<double>(frame.NumberOfPoints) };
  kept.LevelOfDetail->SetTypedTuple(0, tuple);
  kept.LevelOfDetail->Modified();
  if (fd->GetArray(LevelOfDetailArray) != kept.LevelOfDetail.Get())
  {
    fd->AddArray(kept.LevelOfDetail);
  }
  output->Modified();
  return output;
}

void Assembler::Assemble(const morphnode::ScalableScene& scene, size_t part, vtkPointSet* input,
  vtkPolyData* output, const std::vector<vtkDataArray*>& extra)
{
  output->ShallowCopy(this->Assemble(scene, part, input, extra));
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
  this->MappedNames.clear();
  this->NameMap.clear();
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
    was.MeasurementWindow != settings.MeasurementWindow || was.PixelBound != settings.PixelBound ||
    was.FinestLevel != settings.FinestLevel ||
    was.MaxGeomorphPixels != settings.MaxGeomorphPixels || was.Thresholds != settings.Thresholds ||
    was.TargetPixelBound != settings.TargetPixelBound)
  {
    this->Scene.SetSettings(settings);
    this->Configured = true;
  }
  // The filter's weights by name onto the scene's targets (the same names: both are the
  // parts' matched as MorphScene matches them); the map is made again only when the names
  // change (a new model).
  const std::vector<std::string>& targets = this->Scene.GetTargetNames();
  if (this->NameMap.size() != targets.size() || this->MappedNames != names)
  {
    this->MappedNames = names;
    this->NameMap.assign(targets.size(), 0);
    for (size_t t = 1; t < targets.size() && !names.empty(); ++t)
    {
      const auto it = std::find(names.begin() + 1, names.end(), targets[t]);
      this->NameMap[t] = it != names.end() ? static_cast<size_t>(it - names.begin()) : 0;
    }
  }
  this->Weights.assign(targets.size(), 0.0);
  for (size_t t = 1; t < targets.size(); ++t)
  {
    const size_t i = this->NameMap[t];
    if (i > 0 && i < weights.size())
    {
      this->Weights[t] = weights[i];
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

vtkPolyData* SceneLevels::Assemble(size_t part, const std::vector<vtkDataArray*>& extra)
{
  return this->Output.Assemble(this->Scene, part, this->Inputs.at(part), extra);
}
//------------------------------------------------------------------------------
int SceneLevels::Show(const morphnode::MorphScene& scene, uint64_t generation,
  const std::vector<std::string>& targetNames, const morphnode::ControllerSettings& settings,
  double pixelsPerUnit, bool distances, vtkMorphNodeOutput& parts,
  vtkCompositeDataSet* compositeInput, vtkDataObject* output)
{
  // The scene's parts: their models, data sets and names, in the scene's order.
  const size_t numScene = scene.GetNumberOfParts();
  std::vector<const morphnode::MorphMesh*> models(numScene, nullptr);
  std::vector<vtkPointSet*> inputs(numScene, nullptr);
  std::vector<std::string> names(numScene);
  for (const vtkMorphNodeOutput::Part& part : parts.Parts)
  {
    if (part.ScenePart >= 0)
    {
      const auto p = static_cast<size_t>(part.ScenePart);
      models[p] = &part.Built->Model;
      inputs[p] = part.Input;
      names[p] = part.Name.empty() ? "the input" : "part '" + part.Name + "'";
    }
  }
  this->SetParts(models, inputs, names, generation);
  const morphnode::SceneFrame& frame =
    this->Update(targetNames, scene.GetEffectiveWeights(), settings, pixelsPerUnit);

  // Every part's kept level data set (filled again in place while no one else holds it;
  // the last output's sets let go of it first), with the distance maps gathered to its
  // points when asked for, and the filter's field data (rewritten in place in the kept
  // ones). An empty leaf passes through.
  auto* composite = vtkCompositeDataSet::SafeDownCast(output);
  if (composite)
  {
    parts.ReleaseLeaves();
  }
  std::vector<vtkSmartPointer<vtkDataObject>> leaves;
  std::vector<vtkFieldData*> fields;
  std::vector<bool> kept;
  for (vtkMorphNodeOutput::Part& part : parts.Parts)
  {
    if (part.ScenePart < 0)
    {
      leaves.emplace_back(part.Input);
      continue;
    }
    const auto p = static_cast<size_t>(part.ScenePart);
    vtkPolyData* poly = this->Assemble(
      p, distances ? parts.GetDistanceArrays(part, &scene) : std::vector<vtkDataArray*>());
    leaves.emplace_back(poly);
    fields.push_back(poly->GetFieldData());
    kept.push_back(this->IsKept(p));
  }
  parts.AddFieldArrays(fields, kept, &scene, distances);
  if (composite)
  {
    // The levels in the output's structure as the filter's own leaves are placed; none
    // kept for the next execution (a level's leaf is not the input's structure).
    for (size_t i = 0; i < leaves.size(); ++i)
    {
      parts.Parts[i].OutputLeaf = vtkPointSet::SafeDownCast(leaves[i]);
    }
    parts.PlaceLeaves(compositeInput, composite);
    for (vtkMorphNodeOutput::Part& part : parts.Parts)
    {
      part.OutputLeaf = nullptr;
    }
    return frame.Decision.Level;
  }
  auto* poly = vtkPolyData::SafeDownCast(output);
  if (!poly || leaves.size() != 1)
  {
    throw morphnode::InputError(
      "MeshLevels: the input must be a vtkPolyData (or a composite of them)");
  }
  poly->ShallowCopy(leaves[0]);
  return frame.Decision.Level;
}

} // namespace vtkMorphMeshLevels
