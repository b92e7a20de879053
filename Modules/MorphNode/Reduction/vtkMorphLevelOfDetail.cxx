// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphLevelOfDetail.h"

#include "vtkMorphMeshLevels.h"

#include "base/Error.h"
#include "budget/DeviceProfile.h"
#include "lod/MorphLadder.h"
#include "lod/ScalableScene.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkMorphLevelOfDetail);

class vtkMorphLevelOfDetail::vtkInternals
{
public:
  vtkPolyData* Input = nullptr; // the input the ladder was built for (not held)
  vtkMTimeType InputTime = 0;
  std::shared_ptr<const morphnode::MorphLadder> Ladder;
  std::vector<morphnode::CostModel> Costs;
  morphnode::ScalableScene Scene; // of the one part
  bool SceneHasLadder = false;
  vtkMorphMeshLevels::Assembler Output;
  std::vector<double> Weights; // relative, index 1.. (0 unused)
  int Level = -1;
  int Active = 0;
  vtkIdType Points = 0;
};

vtkMorphLevelOfDetail::vtkMorphLevelOfDetail()
  : Internals(new vtkInternals)
{
}

vtkMorphLevelOfDetail::~vtkMorphLevelOfDetail() = default;

void vtkMorphLevelOfDetail::SetWeight(int target, double weight)
{
  if (target < 1)
  {
    vtkErrorMacro(<< "Target " << target << ": targets are numbered from 1 (0 is the neutral).");
    return;
  }
  auto& w = this->Internals->Weights;
  if (static_cast<size_t>(target) >= w.size())
  {
    w.resize(static_cast<size_t>(target) + 1, 0.0);
  }
  if (w[static_cast<size_t>(target)] != weight)
  {
    w[static_cast<size_t>(target)] = weight;
    this->Modified();
  }
}

void vtkMorphLevelOfDetail::ResetWeights()
{
  auto& w = this->Internals->Weights;
  if (std::any_of(w.begin(), w.end(), [](double x) { return x != 0.0; }))
  {
    this->Modified();
  }
  w.clear();
}

double vtkMorphLevelOfDetail::GetWeight(int target) const
{
  const auto& w = this->Internals->Weights;
  return target >= 1 && static_cast<size_t>(target) < w.size() ? w[static_cast<size_t>(target)]
                                                               : 0.0;
}

void vtkMorphLevelOfDetail::SetDeviceProfile(const char* name)
{
  try
  {
    const morphnode::DeviceProfile& p = morphnode::FindDeviceProfile(name ? name : "");
    this->SetFrameBudget(1e3 * p.FrameBudget);
    this->SetFinestLevel(p.FinestLevel);
    this->SetPixelBound(p.PixelBound);
    this->SetTargetPixelBound(p.TargetPixelBound);
  }
  catch (const morphnode::InputError& e)
  {
    vtkErrorMacro(<< e.what());
  }
}

int vtkMorphLevelOfDetail::GetLevel() const
{
  return this->Internals->Level;
}

int vtkMorphLevelOfDetail::GetNumberOfLevels() const
{
  return this->Internals->Ladder ? static_cast<int>(this->Internals->Ladder->Levels.size()) : 0;
}

vtkIdType vtkMorphLevelOfDetail::GetNumberOfLevelPoints() const
{
  return this->Internals->Points;
}

int vtkMorphLevelOfDetail::GetActiveTargetCount() const
{
  return this->Internals->Active;
}

int vtkMorphLevelOfDetail::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkInternals& in = *this->Internals;
  in.Level = -1;
  in.Active = 0;
  in.Points = 0;
  if (!input)
  {
    vtkErrorMacro(<< "No input.");
    return 0;
  }
  try
  {
    // The ladder, once per input.
    if (!in.Ladder || in.Input != input || in.InputTime != input->GetMTime())
    {
      in.Ladder.reset();
      in.SceneHasLadder = false;
      in.Output.Reset();
      auto ladder =
        vtkMorphMeshLevels::BuildLadder(input, morphnode::LadderSettings(), "the input");
      in.Costs = morphnode::ScalableScene::Calibrate({ ladder });
      in.Ladder = ladder;
      in.Input = input;
      in.InputTime = input->GetMTime();
    }
    morphnode::ControllerSettings s;
    s.FrameBudget = this->FrameBudget > 0.0 ? 1e-3 * this->FrameBudget : 1.0;
    s.PixelBound = this->PixelBound;
    s.TargetPixelBound = this->TargetPixelBound;
    s.FinestLevel = this->FinestLevel;
    s.MaxGeomorphPixels = this->MaxGeomorphPixels;
    s.Strategy = morphnode::Redistribution::Neutral;
    const morphnode::ControllerSettings& was = in.Scene.GetSettings();
    if (!in.SceneHasLadder || was.FrameBudget != s.FrameBudget || was.PixelBound != s.PixelBound ||
      was.TargetPixelBound != s.TargetPixelBound || was.FinestLevel != s.FinestLevel ||
      was.MaxGeomorphPixels != s.MaxGeomorphPixels)
    {
      in.Scene.SetSettings(s);
      if (!in.SceneHasLadder)
      {
        in.Scene.SetParts({ in.Ladder }, in.Costs);
        in.SceneHasLadder = true;
      }
    }
    const morphnode::MorphLadder& ladder = *in.Ladder;
    // Absolute weights (neutral first) from the relative ones.
    std::vector<double> absolute(ladder.Mesh.GetNumberOfTargets(), 0.0);
    double sum = 0.0;
    for (size_t k = 1; k < absolute.size(); ++k)
    {
      absolute[k] = k < in.Weights.size() ? in.Weights[k] : 0.0;
      sum += absolute[k];
    }
    absolute[0] = 1.0 - sum;
    const morphnode::SceneFrame& frame = in.Scene.Update(absolute, this->PixelsPerUnit);
    in.Level = frame.Decision.Level;
    in.Active = frame.Decision.ActiveTargets;
    in.Points = static_cast<vtkIdType>(frame.NumberOfPoints);
    in.Output.Assemble(in.Scene, 0, input, output);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    in.Level = -1;
    output->Initialize();
    return 0;
  }
  return 1;
}

void vtkMorphLevelOfDetail::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PixelsPerUnit: " << this->PixelsPerUnit << "\n";
  os << indent << "PixelBound: " << this->PixelBound << " px\n";
  os << indent << "TargetPixelBound: " << this->TargetPixelBound << " px\n";
  os << indent << "FrameBudget: " << this->FrameBudget << " ms\n";
  os << indent << "FinestLevel: " << this->FinestLevel << "\n";
  os << indent << "MaxGeomorphPixels: " << this->MaxGeomorphPixels << " px\n";
  os << indent << "Level: " << this->GetLevel() << " of " << this->GetNumberOfLevels() << "\n";
}
