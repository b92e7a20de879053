// SPDX-License-Identifier: BSD-3-Clause
#ifndef MorphNodeMouthPixels_h
#define MorphNodeMouthPixels_h
/// @file MorphNodeMouthPixels.h
/// @brief Counts what an open mouth shows in a rendered frame: teeth (light, nearly grey:
/// blue close to red) and tongue or gums (red well above green and blue), in the lower half
/// of the frame (the mouth, not the whites of the eyes). Skin is neither (its blue is at most
/// 0.86 of its red, drawn gamma-correct as glTF materials are). For render tests that must see
/// teeth and a tongue, and their negative controls (a closed mouth shows neither).

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
  auto* rgb =
    image ? vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars()) : nullptr;
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
    const double r = rgb->GetValue(c * i), g = rgb->GetValue(c * i + 1),
                 b = rgb->GetValue(c * i + 2);
    // (0.92: glTF's colours drawn gamma-correct, skin of linear (0.8, 0.62, 0.52) shows
    // blue at 0.79 to 0.86 of red, teeth at 0.96 or more.)
    if (r > 150 && g > 140 && b > 0.92 * r)
    {
      ++count.Teeth;
    }
    // (1.45: a tongue of linear (0.55, 0.18, 0.2) drawn gamma-correct shows red 1.6 times
    // green and 1.4 times blue; skin 1.1 times green.)
    else if (r > 60 && r > 1.45 * g && r > 1.3 * b)
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
