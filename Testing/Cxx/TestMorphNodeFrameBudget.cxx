// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphNodeFilter's FrameBudget: the threshold chosen per execution from measured morph
// times (morphnode::FrameBudgetController). The extremes hold on any machine: a budget no
// morph misses never prunes, one no morph meets prunes as far as the candidates go; the
// property follows VTK's rules (MTime, PrintSelf, off by default).
#include "vtkMorphNodeFilter.h"

#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

namespace
{
constexpr int Targets = 8;

/// A sphere of ~4000 points with 8 relative targets, each moving every point (dense: the
/// morph's time grows with the active targets).
vtkSmartPointer<vtkPolyData> Face()
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(80);
  sphere->SetPhiResolution(50);
  sphere->Update();
  auto face = vtkSmartPointer<vtkPolyData>::New();
  face->DeepCopy(sphere->GetOutput());
  const vtkIdType n = face->GetNumberOfPoints();
  for (int k = 0; k < Targets; ++k)
  {
    vtkNew<vtkFloatArray> delta;
    delta->SetName(("target" + std::to_string(k) + "_position").c_str());
    delta->SetNumberOfComponents(3);
    delta->SetNumberOfTuples(n);
    for (vtkIdType p = 0; p < n; ++p)
    {
      double x[3];
      face->GetPoint(p, x);
      for (int c = 0; c < 3; ++c)
      {
        delta->SetValue(3 * p + c, static_cast<float>(0.1 * (k + 1) * std::sin(3.0 * x[c] + k)));
      }
    }
    face->GetPointData()->AddArray(delta);
  }
  return face;
}

/// Relative weights for frame f: every target between 0.02 and 0.3.
void SetFrame(vtkMorphNodeFilter* morph, int f)
{
  for (int k = 0; k < Targets; ++k)
  {
    morph->SetWeight(k + 1, 0.16 + 0.14 * std::sin(0.37 * f + 1.3 * k));
  }
}
} // namespace

TEST(MorphNodeFrameBudget, OffByDefault)
{
  vtkNew<vtkMorphNodeFilter> morph;
  morph->SetInputData(Face());
  morph->SetWeightModeToRelative();
  SetFrame(morph, 0);
  ASSERT_EQ(morph->GetFrameBudget(), 0.0);
  morph->Update();
  EXPECT_EQ(morph->GetFrameBudgetThreshold(), -1.0);
  EXPECT_GT(morph->GetMorphTime(), 0.0); // measured with or without a budget
  EXPECT_EQ(morph->GetActiveTargetCount(), Targets);
}

TEST(MorphNodeFrameBudget, LooseAndTightBudgets)
{
  auto face = Face();
  vtkNew<vtkMorphNodeFilter> loose, tight;
  for (vtkMorphNodeFilter* morph : { loose.Get(), tight.Get() })
  {
    morph->SetInputData(face);
    morph->SetWeightModeToRelative();
    morph->SetOptimizerPreset(vtkMorphNodeFilter::OPTIMIZER_FIXED_REMAINING);
    morph->SetThreshold(0.9); // replaced by the budget's choice
  }
  loose->SetFrameBudget(1000.0); // 1 s
  tight->SetFrameBudget(1e-4);   // 0.1 us
  int looseActive = 0, tightActive = 0;
  for (int f = 0; f < 40; ++f)
  {
    SetFrame(loose, f);
    SetFrame(tight, f);
    ASSERT_TRUE(loose->UpdatePiece(0, 1, 0));
    ASSERT_TRUE(tight->UpdatePiece(0, 1, 0));
    EXPECT_EQ(loose->GetFrameBudgetThreshold(), 0.0) << f;
    EXPECT_EQ(loose->GetActiveTargetCount(), Targets) << f;
    EXPECT_GT(tight->GetFrameBudgetThreshold(), 0.0) << f;
    EXPECT_LE(tight->GetActiveTargetCount(), loose->GetActiveTargetCount()) << f;
    EXPECT_GT(loose->GetMorphTime(), 0.0);
    looseActive += loose->GetActiveTargetCount();
    tightActive += tight->GetActiveTargetCount();
  }
  // The tight budget prunes (weights of 0.02 to 0.3 against thresholds up to 0.5).
  EXPECT_LT(tightActive, looseActive / 2);
  // Turning the budget off gives the filter's own threshold back.
  tight->SetFrameBudget(0.0);
  ASSERT_TRUE(tight->UpdatePiece(0, 1, 0));
  EXPECT_EQ(tight->GetFrameBudgetThreshold(), -1.0);
  EXPECT_LE(tight->GetActiveTargetCount(), 1); // 0.9 prunes every target but the largest
}

TEST(MorphNodeFrameBudget, PropertyFollowsVTKRules)
{
  vtkNew<vtkMorphNodeFilter> morph;
  const vtkMTimeType before = morph->GetMTime();
  morph->SetFrameBudget(morph->GetFrameBudget());
  EXPECT_EQ(morph->GetMTime(), before);
  morph->SetFrameBudget(2.0);
  EXPECT_GT(morph->GetMTime(), before);
  morph->SetFrameBudget(-1.0);
  EXPECT_EQ(morph->GetFrameBudget(), 0.0); // clamped
  morph->SetFrameBudget(2.0);
  std::ostringstream os;
  morph->Print(os);
  EXPECT_NE(os.str().find("FrameBudget: 2 ms"), std::string::npos) << os.str();
  EXPECT_NE(os.str().find("MorphTime:"), std::string::npos);
}
