// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphNodeOutput.h"

#ifdef MORPHNODE_WITH_SKINS
#include "vtkMorphSkinArrays.h"
#endif
#include "vtkMorphTargetArrays.h"

#include "base/Error.h"

#include "vtkCellData.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <utility>

namespace adapter = vtkMorphModelAdapter;

namespace
{
/// Field-data arrays the filter writes; a neutral's arrays of these names are replaced.
const char* const OutputFieldArrays[] = { adapter::TargetNamesArray, adapter::EffectiveWeightsArray,
  adapter::ActiveTargetCountArray, adapter::ErrorBoundArray, adapter::DistNormArray
#ifdef MORPHNODE_WITH_SKINS
  ,
  vtkMorphSkinArrays::MorphedRangesArray, vtkMorphSkinArrays::MorphedTimeArray
#endif
};

/// `values` in the ArrayT held by `slot`, rewritten in place when only `slot` and
/// `holders` more references (the kept output leaves) hold it; `fresh` tells whether a new
/// array was made.
template <typename ArrayT, typename Range>
vtkDataArray* Values(vtkSmartPointer<vtkDataArray>& slot, const char* name, const Range& values,
  int holders, bool& fresh)
{
  ArrayT* array = ArrayT::SafeDownCast(slot);
  fresh = !array || slot->GetReferenceCount() != 1 + holders;
  if (fresh)
  {
    auto made = vtkSmartPointer<ArrayT>::New();
    made->SetName(name);
    slot = made;
    array = made;
  }
  array->SetNumberOfValues(static_cast<vtkIdType>(std::size(values)));
  vtkIdType i = 0;
  for (const auto value : values)
  {
    array->SetValue(i++, static_cast<typename ArrayT::ValueType>(value));
  }
  array->Modified();
  return array;
}
} // namespace

//------------------------------------------------------------------------------
vtkMorphNodeOutput::vtkMorphNodeOutput()
{
  this->DistNorm->SetName(adapter::DistNormArray);
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::SetModel(
  const std::vector<std::string>& names, const std::vector<double>& distNorm)
{
  this->Names = names;
  this->DistNorm->SetNumberOfValues(static_cast<vtkIdType>(distNorm.size()));
  std::copy(distNorm.begin(), distNorm.end(), this->DistNorm->GetPointer(0));
  this->TargetNames = adapter::MakeNamesArray(adapter::TargetNamesArray, names);
  this->DistNormOut = vtkSmartPointer<vtkDoubleArray>::New();
  this->DistNormOut->DeepCopy(this->DistNorm);
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::PrepareArrays(Part& part)
{
  const morphnode::MorphMesh& mesh = part.Built->Model;
  const auto& bindings = part.Built->Bindings;
  const vtkIdType numPoints = static_cast<vtkIdType>(mesh.GetNumberOfPoints());
  const size_t numAttributes = mesh.GetNumberOfAttributes();
  adapter::BlendOutputs& outputs = part.Outputs;
  // The last frame's points when nothing else holds them, else the frame's before
  // (BlendOutputs), else new ones with the held ones kept as the spare.
  auto free = [](vtkPoints* p)
  {
    return p && p->GetReferenceCount() == 1 && p->GetData() &&
      p->GetData()->GetReferenceCount() == 1;
  };
  if (outputs.Points && !free(outputs.Points))
  {
    if (free(outputs.SparePoints))
    {
      std::swap(outputs.Points, outputs.SparePoints);
    }
    else
    {
      outputs.SparePoints = outputs.Points;
    }
  }
  // The points' array is held by the vtkPoints and by `points` here.
  vtkSmartPointer<vtkDataArray> points = outputs.Points ? outputs.Points->GetData() : nullptr;
  const bool pointsFree = outputs.Points && outputs.Points->GetReferenceCount() == 1;
  vtkDataArray* pointArray =
    adapter::ReuseOrNew(points, bindings[0].Prototype, numPoints, pointsFree ? 2 : 0);
  if (!pointsFree || outputs.Points->GetData() != pointArray)
  {
    outputs.Points = vtkSmartPointer<vtkPoints>::New();
    outputs.Points->SetData(pointArray);
  }
  outputs.Arrays.resize(numAttributes - 1);
  outputs.SpareArrays.resize(numAttributes - 1);
  part.Where.resize(numAttributes);
  part.FloatScratch.resize(numAttributes);
  part.DoubleScratch.resize(numAttributes);
  for (size_t a = 0; a < numAttributes; ++a)
  {
    vtkDataArray* out = a == 0 ? pointArray
                               : adapter::ReuseOrNew(outputs.Arrays[a - 1], bindings[a].Prototype,
                                   numPoints, 1, &outputs.SpareArrays[a - 1]);
    const size_t values = static_cast<size_t>(numPoints) * out->GetNumberOfComponents();
    if (std::holds_alternative<morphnode::MorphAttribute<float>>(mesh.GetAttribute(a)))
    {
      auto* direct = vtkFloatArray::FastDownCast(out);
      part.FloatScratch[a].resize(direct ? 0 : values);
      part.Where[a] = direct ? direct->GetPointer(0) : part.FloatScratch[a].data();
    }
    else
    {
      auto* direct = vtkDoubleArray::FastDownCast(out);
      part.DoubleScratch[a].resize(direct ? 0 : values);
      part.Where[a] = direct ? direct->GetPointer(0) : part.DoubleScratch[a].data();
    }
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::ReleaseLeaves()
{
  this->Leaves.Release();
}

//------------------------------------------------------------------------------
std::vector<size_t> vtkMorphNodeOutput::Prepare(const morphnode::MorphScene& scene, bool composite)
{
  this->ReleaseLeaves();
  std::vector<size_t> blend;
  this->WhereByScenePart.assign(scene.GetNumberOfParts(), nullptr);
  for (Part& part : this->Parts)
  {
    if (composite)
    {
      // Last execution's leaf: emptied for reuse (which frees the points and arrays it
      // held, for the blend to write them in place) when no one else holds it, else a new one.
      part.LeafKept = part.OutputLeaf && part.OutputLeaf->GetReferenceCount() == 1 &&
        part.OutputLeaf->IsA(part.Input->GetClassName());
      if (part.LeafKept)
      {
        part.OutputLeaf->SetPoints(nullptr);
        part.OutputLeaf->GetPointData()->Initialize();
      }
      else
      {
        part.OutputLeaf.TakeReference(part.Input->NewInstance());
      }
    }
    part.Blended =
      part.ScenePart >= 0 && (!composite || scene.IsPartMoved(static_cast<size_t>(part.ScenePart)));
    if (part.Blended)
    {
      const size_t p = static_cast<size_t>(part.ScenePart);
      PrepareArrays(part);
      scene.GetPartNode(p).CheckOutputs(part.Where);
      this->WhereByScenePart[p] = &part.Where;
      blend.push_back(p);
    }
  }
  return blend;
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::Finish()
{
  for (Part& part : this->Parts)
  {
    if (!part.Blended)
    {
      continue;
    }
    const size_t numAttributes = part.Built->Model.GetNumberOfAttributes();
    for (size_t a = 0; a < numAttributes; ++a)
    {
      vtkDataArray* out =
        a == 0 ? part.Outputs.Points->GetData() : part.Outputs.Arrays[a - 1].GetPointer();
      if (!part.FloatScratch[a].empty())
      {
        vtkMorphTargetArrays::CopyToArray(part.FloatScratch[a].data(), out);
      }
      else if (!part.DoubleScratch[a].empty())
      {
        vtkMorphTargetArrays::CopyToArray(part.DoubleScratch[a].data(), out);
      }
      out->Modified(); // written through raw pointers: renderers re-upload on MTime
    }
    part.Outputs.Points->Modified();
  }
}

//------------------------------------------------------------------------------
const std::vector<vtkSmartPointer<vtkDataArray>>& vtkMorphNodeOutput::DistanceArrays(
  Part& part, const morphnode::MorphScene* scene)
{
  // A part's animated region and each of the model's targets' per-point distance from the
  // neutral (zeros for a target the part does not have).
  if (!part.Distances.empty())
  {
    return part.Distances;
  }
  const auto& names = this->Names;
  if (!part.Built || part.ScenePart < 0 || !scene)
  {
    const size_t n = part.Input ? static_cast<size_t>(part.Input->GetNumberOfPoints()) : 0;
    const std::vector<double> zeros(n, 0.0);
    part.Distances.push_back(adapter::MakeDoubleArray(adapter::AnimatedRegionArray, zeros));
    for (size_t i = 1; i < names.size(); ++i)
    {
      part.Distances.push_back(
        adapter::MakeDoubleArray((adapter::DistancePrefix + names[i]).c_str(), zeros));
    }
    return part.Distances;
  }
  const morphnode::MorphMesh& model = part.Built->Model;
  part.Distances.push_back(
    adapter::MakeDoubleArray(adapter::AnimatedRegionArray, model.ComputeAnimatedRegion()));
  const std::vector<size_t>& targets = scene->GetPartTargets(static_cast<size_t>(part.ScenePart));
  std::vector<size_t> own(names.size(), 0); // the part's target of each scene target, 0: none
  for (size_t k = 1; k < targets.size(); ++k)
  {
    own[targets[k]] = k;
  }
  for (size_t i = 1; i < names.size(); ++i)
  {
    const std::string name = adapter::DistancePrefix + names[i];
    part.Distances.push_back(adapter::MakeDoubleArray(name.c_str(),
      own[i] ? model.ComputePointDistances(own[i])
             : std::vector<double>(model.GetNumberOfPoints(), 0.0)));
  }
  return part.Distances;
}

//------------------------------------------------------------------------------
std::vector<vtkDataArray*> vtkMorphNodeOutput::FieldArrays(
  const morphnode::MorphScene* scene, bool distances, int kept, bool& fresh)
{
  // EffectiveWeights, ActiveTargetCount, ErrorBound (rewritten in place when only this
  // helper and its `kept` output leaves hold them: `fresh` tells whether any is new, so that
  // kept leaves need it), and DistNorm when distances are asked for.
  static const std::vector<double> none;
  const auto& effective = scene ? scene->GetEffectiveWeights() : none;
  std::vector<vtkDataArray*> arrays;
  bool made[3] = { false, false, false };
  arrays.push_back(Values<vtkDoubleArray>(
    this->EffectiveWeightsOut, adapter::EffectiveWeightsArray, effective, kept, made[0]));
  const int active[] = { scene ? scene->GetActiveTargetCount() : 0 };
  arrays.push_back(Values<vtkIntArray>(
    this->ActiveTargetCountOut, adapter::ActiveTargetCountArray, active, kept, made[1]));
  const double bound[] = { scene ? scene->GetErrorBound() : 0.0 };
  arrays.push_back(
    Values<vtkDoubleArray>(this->ErrorBoundOut, adapter::ErrorBoundArray, bound, kept, made[2]));
  fresh = made[0] || made[1] || made[2];
  if (distances)
  {
    arrays.push_back(this->DistNormOut);
  }
  return arrays;
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::AddFieldArrays(const std::vector<vtkFieldData*>& fds,
  const std::vector<bool>& kept, const morphnode::MorphScene* scene, bool distances)
{
  const int holders = static_cast<int>(std::count(kept.begin(), kept.end(), true));
  bool fresh = false;
  const std::vector<vtkDataArray*> arrays = this->FieldArrays(scene, distances, holders, fresh);
  for (size_t i = 0; i < fds.size(); ++i)
  {
    if (i < kept.size() && kept[i] && !fresh)
    {
      continue; // holds them, rewritten in place
    }
    for (vtkDataArray* array : arrays)
    {
      fds[i]->AddArray(array);
    }
    fds[i]->AddArray(this->TargetNames);
  }
}

//------------------------------------------------------------------------------
std::vector<vtkDataArray*> vtkMorphNodeOutput::GetDistanceArrays(
  Part& part, const morphnode::MorphScene* scene)
{
  std::vector<vtkDataArray*> arrays;
  for (const auto& array : this->DistanceArrays(part, scene))
  {
    arrays.push_back(array);
  }
  return arrays;
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::SetMovedRanges(Part& part, vtkPointSet* output, vtkFieldData* fd)
{
#ifndef MORPHNODE_WITH_SKINS
  // The morph module alone knows no skins: no part carries moved ranges.
  (void)part;
  (void)output;
  (void)fd;
#else
  if (part.Built && part.Input && part.MovedRangesOf.lock() != part.Built)
  {
    // Once per model (a new array per model: the skin filter knows a model by its array),
    // for skinned parts only.
    part.MovedRanges = nullptr;
    part.MovedRangesOf = part.Built;
    if (vtkMorphSkinArrays::IsSkinned(part.Input))
    {
      const std::vector<size_t> ranges = part.Built->Model.MovedPointRanges();
      vtkNew<vtkIdTypeArray> array;
      array->SetName(vtkMorphSkinArrays::MorphedRangesArray);
      array->SetNumberOfComponents(2);
      array->SetNumberOfTuples(static_cast<vtkIdType>(ranges.size() / 2));
      for (size_t i = 0; i < ranges.size(); ++i)
      {
        array->SetValue(static_cast<vtkIdType>(i), static_cast<vtkIdType>(ranges[i]));
      }
      part.MovedRanges = array;
    }
  }
  if (part.Blended && part.Built && part.MovedRanges)
  {
    // The ranges hold for these very arrays: their modification times (a filter between
    // here and the skin filter that changes points or normals changes them).
    vtkDataArray* points = output->GetPoints() ? output->GetPoints()->GetData() : nullptr;
    vtkDataArray* normals = output->GetPointData()->GetNormals();
    if (!part.MovedTime || part.MovedTime->GetReferenceCount() != 1)
    {
      vtkNew<vtkIdTypeArray> time;
      time->SetName(vtkMorphSkinArrays::MorphedTimeArray);
      time->SetNumberOfValues(2);
      part.MovedTime = time;
    }
    part.MovedTime->SetValue(0, points ? static_cast<vtkIdType>(points->GetMTime()) : 0);
    part.MovedTime->SetValue(1, normals ? static_cast<vtkIdType>(normals->GetMTime()) : 0);
    part.MovedTime->Modified();
    fd->AddArray(part.MovedRanges);
    fd->AddArray(part.MovedTime);
  }
  else if (part.MovedRanges)
  {
    fd->RemoveArray(vtkMorphSkinArrays::MorphedRangesArray);
    fd->RemoveArray(vtkMorphSkinArrays::MorphedTimeArray);
  }
#endif
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::AssemblePart(Part& part, vtkPointSet* output,
  const morphnode::MorphScene* scene, bool distances, const std::vector<vtkDataArray*>& fieldArrays,
  bool kept)
{
  vtkPointSet* neutral = part.Input;
  if (!kept)
  {
    output->CopyStructure(neutral);
  }
  vtkPointData* pd = output->GetPointData();
  if (part.Blended)
  {
    output->SetPoints(part.Outputs.Points);
    adapter::AssemblePointData(neutral->GetPointData(), *part.Built, part.Outputs, pd);
  }
  else if (part.Built)
  {
    // Not moved: the neutral's points and arrays as they are, the target arrays left out.
    output->SetPoints(neutral->GetPoints());
    for (const adapter::OutputArraySource& source : part.Built->PointArrays)
    {
      vtkAbstractArray* array = neutral->GetPointData()->GetAbstractArray(source.NeutralIndex);
      if (array)
      {
        const int index = pd->AddArray(array);
        if (source.Attribute >= 0)
        {
          pd->SetActiveAttribute(index, source.Attribute);
        }
      }
    }
  }
  else
  {
    output->SetPoints(neutral->GetPoints());
    pd->PassData(neutral->GetPointData());
    vtkMorphTargetArrays::RemoveTargetArrays(pd);
  }
  if (distances)
  {
    for (vtkDataArray* array : this->DistanceArrays(part, scene))
    {
      pd->AddArray(array);
    }
  }
  vtkFieldData* fd = output->GetFieldData();
  if (kept)
  {
    // The neutral's field data, the model's names and (unless `fieldArrays` holds new
    // ones) this execution's arrays, rewritten in place, are there already.
    if (part.HasDistNorm != distances)
    {
      if (distances)
      {
        fd->AddArray(this->DistNormOut);
      }
      else
      {
        fd->RemoveArray(adapter::DistNormArray);
      }
      part.HasDistNorm = distances;
    }
    for (vtkDataArray* array : fieldArrays)
    {
      fd->AddArray(array);
    }
    SetMovedRanges(part, output, fd);
    return;
  }
  part.HasDistNorm = distances;
  output->GetCellData()->PassData(neutral->GetCellData());
  vtkFieldData* neutralFD = neutral->GetFieldData();
  for (int a = 0; a < neutralFD->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = neutralFD->GetAbstractArray(a);
    const char* name = array ? array->GetName() : nullptr;
    const bool ours = name &&
      std::any_of(std::begin(OutputFieldArrays), std::end(OutputFieldArrays),
        [name](const char* own) { return std::strcmp(own, name) == 0; });
    if (array && !ours)
    {
      fd->AddArray(array);
    }
  }
  fd->AddArray(this->TargetNames);
  for (vtkDataArray* array : fieldArrays)
  {
    fd->AddArray(array);
  }
  SetMovedRanges(part, output, fd);
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::Assemble(vtkDataObject* output, vtkCompositeDataSet* input,
  const morphnode::MorphScene* scene, bool distances)
{
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(output); composite && input)
  {
    this->AssembleComposite(input, composite, scene, distances);
  }
  else if (auto* points = vtkPointSet::SafeDownCast(output);
           points && !input && this->Parts.size() == 1)
  {
    bool fresh = false;
    this->AssemblePart(this->Parts[0], points, scene, distances,
      this->FieldArrays(scene, distances, 0, fresh), false);
  }
  else
  {
    throw morphnode::InputError(std::string("internal: an output of type ") +
      output->GetClassName() + " for an input of " + std::to_string(this->Parts.size()) + " parts");
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::AssembleComposite(vtkCompositeDataSet* input, vtkCompositeDataSet* output,
  const morphnode::MorphScene* scene, bool distances)
{
  const int kept = static_cast<int>(std::count_if(
    this->Parts.begin(), this->Parts.end(), [](const Part& p) { return p.LeafKept; }));
  bool fresh = false;
  const std::vector<vtkDataArray*> fieldArrays = this->FieldArrays(scene, distances, kept, fresh);
  const std::vector<vtkDataArray*> none;
  for (Part& part : this->Parts)
  {
    this->AssemblePart(part, part.OutputLeaf, scene, distances,
      part.LeafKept && !fresh ? none : fieldArrays, part.LeafKept);
  }
  this->PlaceLeaves(input, output);
}

//------------------------------------------------------------------------------
void vtkMorphNodeOutput::PlaceLeaves(vtkCompositeDataSet* input, vtkCompositeDataSet* output)
{
  std::vector<vtkDataObject*> leaves;
  leaves.reserve(this->Parts.size());
  for (const Part& part : this->Parts)
  {
    leaves.push_back(part.OutputLeaf);
  }
  this->Leaves.Place(input, leaves, output);
  output->GetFieldData()->PassData(input->GetFieldData());
  output->GetFieldData()->AddArray(this->TargetNames);
}
