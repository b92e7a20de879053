// SPDX-License-Identifier: BSD-3-Clause
#ifndef MorphNodeMouthPixels_h
#define MorphNodeMouthPixels_h
/// @file MorphNodeMouthPixels.h
/// @brief Counts what an open mouth shows in a rendered frame: teeth (light, nearly grey:
/// blue close to red) and tongue or gums (red well above green and blue), in the lower half
/// of the frame (the mouth, not the whites of the eyes). Skin is neither (its blue is about
/// 0.65 of its red). For render tests that must see teeth and a tongue, and their negative
/// controls (a closed mouth shows neither).

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>

namespace morphnode_test
{
struct MouthPixels
{
  int Teeth = 0;
  int Tongue = 0;
};

/// The counts of an RGB(A) image.
inline MouthPixels CountMouthPixels(vtkImageData* image)
{
  MouthPixels count;
  auto* rgb = image ? vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars()) : nullptr;
  if (!rgb || rgb->GetNumberOfComponents() < 3)
  {
    return count;
  }
  int dims[3];
  image->GetDimensions(dims);
  const int c = rgb->GetNumberOfComponents();
  // Rows run bottom-up: the first half of the tuples is the lower half of the frame.
  const vtkIdType lowerHalf =
    std::min(static_cast<vtkIdType>(dims[0]) * (dims[1] / 2), rgb->GetNumberOfTuples());
  for (vtkIdType i = 0; i < lowerHalf; ++i)
  {
    const double r = rgb->GetValue(c * i), g = rgb->GetValue(c * i + 1), b = rgb->GetValue(c * i + 2);
    if (r > 150 && g > 140 && b > 0.82 * r)
    {
      ++count.Teeth;
    }
    else if (r > 60 && r > 1.9 * g && r > 1.6 * b)
    {
      ++count.Tongue;
    }
  }
  return count;
}

/// The counts of what a render window shows.
inline MouthPixels CountMouthPixels(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  return CountMouthPixels(grab->GetOutput());
}
} // namespace morphnode_test

#endif
