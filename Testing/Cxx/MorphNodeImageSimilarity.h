// SPDX-License-Identifier: BSD-3-Clause
#ifndef MorphNodeImageSimilarity_h
#define MorphNodeImageSimilarity_h
/// @file MorphNodeImageSimilarity.h
/// @brief The structural similarity (SSIM, Wang, Bovik, Sheikh and Simoncelli, IEEE TIP
/// 2004) of two RGB(A) images over a region, on luma (Rec. 601), with the paper's 11 x 11
/// Gaussian window (sigma 1.5) and constants C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 255.
/// Written here because neither VTK 9.1 nor Debian has it for C++ (VTK's vtkImageSSIM came
/// in 9.3). Why SSIM for comparing renderers: it scores local structure (edges of irises,
/// brows and lashes, their contrast) and forgives a uniform difference in brightness, which
/// two renderers' light models give even for the same scene.
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include <cmath>
#include <vector>

namespace morphnode_test
{
/// Mean SSIM over the region [x0, x1) x [y0, y1) (VTK's image coordinates: rows from the
/// bottom), windows clipped to the region. -1 when the images are not RGB(A) bytes of the
/// same size or the region is outside them.
inline double Ssim(vtkImageData* a, vtkImageData* b, int x0, int x1, int y0, int y1)
{
  auto* pa = vtkUnsignedCharArray::SafeDownCast(a->GetPointData()->GetScalars());
  auto* pb = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetScalars());
  int da[3], db[3];
  a->GetDimensions(da);
  b->GetDimensions(db);
  if (!pa || !pb || pa->GetNumberOfComponents() < 3 || pb->GetNumberOfComponents() < 3 ||
    da[0] != db[0] || da[1] != db[1] || x0 < 0 || y0 < 0 || x1 > da[0] || y1 > da[1] ||
    x1 - x0 < 11 || y1 - y0 < 11)
  {
    return -1.0;
  }
  const int w = x1 - x0, h = y1 - y0;
  auto luma = [&](vtkUnsignedCharArray* p, int width)
  {
    std::vector<double> out(static_cast<size_t>(w) * h);
    const int c = p->GetNumberOfComponents();
    for (int y = 0; y < h; ++y)
    {
      for (int x = 0; x < w; ++x)
      {
        const vtkIdType i = static_cast<vtkIdType>(y + y0) * width + (x + x0);
        out[static_cast<size_t>(y) * w + x] = 0.299 * p->GetValue(c * i) +
          0.587 * p->GetValue(c * i + 1) + 0.114 * p->GetValue(c * i + 2);
      }
    }
    return out;
  };
  const std::vector<double> X = luma(pa, da[0]), Y = luma(pb, db[0]);
  // Separable Gaussian, normalized over the part of the window inside the region.
  double kernel[11];
  for (int k = -5; k <= 5; ++k)
  {
    kernel[k + 5] = std::exp(-(k * k) / (2 * 1.5 * 1.5));
  }
  auto blur = [&](const std::vector<double>& in)
  {
    std::vector<double> tmp(in.size()), out(in.size());
    for (int y = 0; y < h; ++y)
    {
      for (int x = 0; x < w; ++x)
      {
        double s = 0, n = 0;
        for (int k = -5; k <= 5; ++k)
        {
          if (x + k >= 0 && x + k < w)
          {
            s += kernel[k + 5] * in[static_cast<size_t>(y) * w + x + k];
            n += kernel[k + 5];
          }
        }
        tmp[static_cast<size_t>(y) * w + x] = s / n;
      }
    }
    for (int y = 0; y < h; ++y)
    {
      for (int x = 0; x < w; ++x)
      {
        double s = 0, n = 0;
        for (int k = -5; k <= 5; ++k)
        {
          if (y + k >= 0 && y + k < h)
          {
            s += kernel[k + 5] * tmp[static_cast<size_t>(y + k) * w + x];
            n += kernel[k + 5];
          }
        }
        out[static_cast<size_t>(y) * w + x] = s / n;
      }
    }
    return out;
  };
  std::vector<double> XX(X.size()), YY(X.size()), XY(X.size());
  for (size_t i = 0; i < X.size(); ++i)
  {
    XX[i] = X[i] * X[i];
    YY[i] = Y[i] * Y[i];
    XY[i] = X[i] * Y[i];
  }
  const std::vector<double> mx = blur(X), my = blur(Y), sxx = blur(XX), syy = blur(YY),
                            sxy = blur(XY);
  const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  double sum = 0;
  for (size_t i = 0; i < X.size(); ++i)
  {
    const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i],
                 cov = sxy[i] - mx[i] * my[i];
    sum += ((2 * mx[i] * my[i] + c1) * (2 * cov + c2)) /
      ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
  }
  return sum / static_cast<double>(X.size());
}
} // namespace morphnode_test

#endif
