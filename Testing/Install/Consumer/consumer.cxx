// Blends two triangles with the installed vtkMorphNodeFilter; exits 0 when the blend is right.
#include "morph/Weights.h"
#include <vtkMorphNodeFilter.h>

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <cmath>
#include <iostream>

int main()
{
  vtkNew<vtkMorphNodeFilter> morph;
  vtkNew<vtkPolyData> shapes[2];
  for (int s = 0; s < 2; ++s)
  {
    vtkNew<vtkPoints> points;
    points->InsertNextPoint(0, 0, 0);
    points->InsertNextPoint(1 + s, 0, 0);
    points->InsertNextPoint(0, 1, 0);
    shapes[s]->SetPoints(points);
    morph->AddInputData(0, shapes[s]);
  }
  morph->SetWeight(0, 0.5);
  morph->SetWeight(1, 0.5);
  morph->Update();
  const double x = morph->GetOutput()->GetPoint(1)[0];
  std::cout << "blended x = " << x << " ("
            << morphnode::WeightModeName(morphnode::WeightMode::Normalize) << ")\n";
  return std::abs(x - 1.5) < 1e-6 ? 0 : 1;
}
