// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphNodeModel.h"

#include "vtkMorphModelAdapter.h"
#include "vtkMorphNodeOutput.h"

#include "base/Error.h"
#include "morph/WeightRequests.h"

#include "vtkAlgorithm.h"
#include "vtkCompositeDataSet.h"
#include "vtkCompositeDataSetRange.h"
#include "vtkDataObject.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkPointSet.h"

#include <functional>
#include <memory>
#include <string>

namespace adapter = vtkMorphModelAdapter;

//------------------------------------------------------------------------------
bool vtkMorphNodeModel::IsParallel(vtkMultiProcessController* controller)
{
  return controller && controller->GetNumberOfProcesses() > 1;
}

//------------------------------------------------------------------------------
void vtkMorphNodeModel::Collect(vtkInformationVector* port0)
{
  this->Inputs.clear();
  this->LeafInputs.clear();
  this->CompositeInput = vtkCompositeDataSet::GetData(port0, 0);
  std::vector<vtkPointSet*> shapes = adapter::AbsoluteShapes(this->CompositeInput);
  if (!shapes.empty() && port0->GetNumberOfInformationObjects() == 1)
  {
    this->CompositeInput = nullptr; // the Java3D form in one connection
    this->Inputs = std::move(shapes);
    return;
  }
  if (!this->CompositeInput)
  {
    for (int i = 0; i < port0->GetNumberOfInformationObjects(); ++i)
    {
      this->Inputs.push_back(vtkPointSet::GetData(port0, i));
    }
    return;
  }
  if (port0->GetNumberOfInformationObjects() > 1)
  {
    throw morphnode::InputError("a composite input (a whole head) must be the only connection of "
                                "port 0; the Java3D form takes point sets");
  }
  for (vtkDataObject* leaf :
    vtk::Range(this->CompositeInput, vtk::CompositeDataSetOptions::SkipEmptyNodes))
  {
    auto* points = vtkPointSet::SafeDownCast(leaf);
    if (!points)
    {
      throw morphnode::InputError("part '" +
        adapter::LeafNames(this->CompositeInput, this->LeafInputs.size())[this->LeafInputs.size()] +
        "' of the composite input is a " + leaf->GetClassName() +
        "; the morph node blends point sets");
    }
    this->LeafInputs.push_back(points);
  }
}

//------------------------------------------------------------------------------
bool vtkMorphNodeModel::Unchanged(double sparseCoverage)
{
  this->From.clear();
  if (this->CompositeInput)
  {
    this->From.emplace_back(this->CompositeInput, this->CompositeInput->GetMTime());
    for (vtkPointSet* leaf : this->LeafInputs)
    {
      this->From.emplace_back(leaf, leaf->GetMTime());
    }
  }
  for (vtkPointSet* input : this->Inputs)
  {
    this->From.emplace_back(input, input ? input->GetMTime() : 0);
  }
  return this->Ready && this->From == this->BuiltFrom &&
    this->Composite == (this->CompositeInput != nullptr) &&
    this->BuiltSparseCoverage == sparseCoverage;
}

//------------------------------------------------------------------------------
void vtkMorphNodeModel::BuildParts(double sparseCoverage, bool parallel, vtkMorphNodeOutput& output)
{
  std::vector<std::shared_ptr<const morphnode::MorphMesh>> meshes;
  std::vector<std::vector<uint8_t>> flags;
  auto add = [&](vtkPointSet* input, const std::string& name, auto build)
  {
    vtkMorphNodeOutput::Part part;
    part.Input = input;
    part.Name = name;
    if (build)
    {
      auto built = std::make_shared<adapter::BuiltModel>(build());
      part.ScenePart = static_cast<int>(meshes.size());
      meshes.emplace_back(built, &built->Model);
      flags.push_back(adapter::DuplicateFlags(input));
      part.Built = std::move(built);
    }
    output.Parts.push_back(std::move(part)); // without a model: passes through
  };
  using Build = std::function<adapter::BuiltModel()>;
  if (this->Composite)
  {
    const std::vector<std::string> names =
      adapter::LeafNames(this->CompositeInput, this->LeafInputs.size());
    for (size_t i = 0; i < this->LeafInputs.size(); ++i)
    {
      vtkPointSet* leaf = this->LeafInputs[i];
      try
      {
        add(
          leaf, names[i],
          leaf->GetNumberOfPoints() == 0 ? Build()
                                         : [&]
            { return adapter::BuildModel({ leaf }, sparseCoverage); });
      }
      catch (const std::exception& e)
      {
        throw morphnode::InputError("part '" + names[i] + "': " + e.what());
      }
    }
    if (meshes.empty() && !parallel)
    {
      throw morphnode::InputError("the composite input has no points in any part");
    }
  }
  else if (this->Inputs.empty())
  {
    throw morphnode::InputError("no input: connect the neutral (and the targets) to port 0");
  }
  else
  {
    vtkPointSet* neutral = this->Inputs[0];
    const bool emptyPiece = parallel && neutral && neutral->GetNumberOfPoints() == 0;
    add(
      neutral, "",
      emptyPiece ? Build() : [&] { return adapter::BuildModel(this->Inputs, sparseCoverage); });
  }
  if (!meshes.empty())
  {
    this->Scene.SetParts(meshes, flags);
    this->HasScene = true;
  }
}

//------------------------------------------------------------------------------
void vtkMorphNodeModel::Update(double sparseCoverage, vtkMultiProcessController* controller,
  vtkMorphNodeOutput& output, morphnode::WeightRequests& requests, vtkAlgorithm* progress)
{
  if (this->Unchanged(sparseCoverage))
  {
    return; // the same data set objects, unchanged: the same model
  }
  this->Ready = false;
  this->HasScene = false;
  this->Scene = morphnode::MorphScene();
  output.Parts.clear();
  this->BuiltFrom.clear();
  requests.SetTargets({});
  this->Composite = this->CompositeInput != nullptr;
  const bool parallel = IsParallel(controller);
  progress->UpdateProgress(0.0);
  std::string error;
  try
  {
    this->BuildParts(sparseCoverage, parallel, output);
  }
  catch (const std::exception& e)
  {
    error = *e.what() ? e.what() : "the input could not be made into a model";
  }
  morphnode::NamedTargetDistances model;
  if (parallel)
  {
    // The whole model's figures, the same on every process.
    model = adapter::GatherModel(controller,
      this->HasScene && error.empty() ? &this->Scene.GetPartsDistances() : nullptr, error);
    if (this->HasScene)
    {
      this->Scene.SetModel(model);
    }
  }
  else if (!error.empty())
  {
    throw morphnode::InputError(error);
  }
  ++this->Generation;
  this->Ready = true;
  this->BuiltFrom = this->From;
  this->BuiltSparseCoverage = sparseCoverage;
  const std::vector<std::string>& names = parallel ? model.Names : this->Scene.GetTargetNames();
  requests.SetTargets(names);
  output.SetModel(names,
    parallel ? morphnode::MakeTargetDistances(model).DistNorm
             : this->Scene.GetTargetDistances().DistNorm);
}
