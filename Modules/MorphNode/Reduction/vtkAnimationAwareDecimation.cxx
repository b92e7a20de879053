// SPDX-License-Identifier: BSD-3-Clause
#include "vtkAnimationAwareDecimation.h"

#include "vtkMorphTargetArrays.h"

#include "base/Error.h"
#include "reduction/AnimationAwareReduction.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <cmath>
#include <string>

vtkStandardNewMacro(vtkAnimationAwareDecimation);

namespace
{
using morphnode::InputError;

/// The core's view of the input: points, triangles and position targets (through
/// vtkMorphTargetArrays); throws InputError for anything it cannot represent.
morphnode::MorphMesh ToMorphMesh(vtkPolyData* input)
{
  vtkMorphTargetArrays::ReadOptions options;
  options.Normals = false; // the collapses look at positions only; every array is gathered
  options.Triangles = true;
  return vtkMorphTargetArrays::ToMorphMesh(input, options).Mesh;
}
} // namespace

vtkAnimationAwareDecimation::vtkAnimationAwareDecimation() = default;
vtkAnimationAwareDecimation::~vtkAnimationAwareDecimation() = default;

int vtkAnimationAwareDecimation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input)
  {
    vtkErrorMacro(<< "No input.");
    return 0;
  }
  try
  {
    const morphnode::MorphMesh mesh = ToMorphMesh(input);
    morphnode::ReductionSettings settings;
    settings.AnimationWeight = this->AnimationWeight;
    settings.PoseQuadrics = this->PoseQuadrics;
    settings.MaxNormalDeviation = this->MaxNormalDeviation;
    if (this->NumberOfTriangles > 0)
    {
      settings.TargetTriangles = static_cast<size_t>(this->NumberOfTriangles);
    }
    else
    {
      const double keep = std::round((1.0 - this->TargetReduction) * mesh.GetNumberOfTriangles());
      if (keep < 1.0 || this->TargetReduction <= 0.0)
      {
        throw InputError("TargetReduction " + std::to_string(this->TargetReduction) +
          " leaves no triangle to remove or none to keep");
      }
      settings.TargetTriangles = static_cast<size_t>(keep);
    }
    this->UpdateProgress(0.1);
    const morphnode::ReductionResult result = morphnode::ReduceAnimationAware(mesh, settings);
    this->UpdateProgress(0.9);

    vtkMorphTargetArrays::ExtractPointSubset(input, result.OriginalPointIds,
      static_cast<vtkIdType>(result.OriginalPointIds.size()), result.Mesh.GetTriangles(), output);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    return 0;
  }
  return 1;
}

void vtkAnimationAwareDecimation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "NumberOfTriangles: " << this->NumberOfTriangles << "\n";
  os << indent << "AnimationWeight: " << this->AnimationWeight << "\n";
  os << indent << "PoseQuadrics: " << (this->PoseQuadrics ? "On" : "Off") << "\n";
  os << indent << "MaxNormalDeviation: " << this->MaxNormalDeviation << "\n";
}
