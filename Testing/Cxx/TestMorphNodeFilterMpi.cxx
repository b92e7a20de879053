// SPDX-License-Identifier: BSD-3-Clause
// vtkMorphNodeFilter in parallel (run under mpiexec with 2 processes): each process holds
// half of a face, its targets in its own order; the processes exchange their figures
// (vtkMultiProcessStream through AllGather) and decide exactly as one process holding the
// whole face does. A process with a broken piece fails every process, naming itself; a
// process with an empty piece takes part; a frame budget chooses alike on every process.
// Without the exchange (no controller) the halves decide differently: the negative control.
#include "vtkMorphNodeFilter.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMPIController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace
{
int Failures = 0;

void Check(bool ok, const std::string& what, int rank)
{
  if (!ok)
  {
    std::cerr << "process " << rank << ": FAILED: " << what << "\n";
    ++Failures;
  }
}

/// Points [begin, end) of a face of 200 points along x; target "wide" moves every point by
/// 0.01, "jaw" moves points >= 100 by 0.3 (only the second half), "blink" points < 20 by
/// 0.05. `reversed`: the targets in the opposite order.
vtkSmartPointer<vtkPolyData> Piece(int begin, int end, bool reversed)
{
  auto face = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  for (int i = begin; i < end; ++i)
  {
    points->InsertNextPoint(0.01 * i, 0.0, 0.0);
  }
  face->SetPoints(points);
  std::vector<std::string> targets = { "wide", "jaw", "blink" };
  if (reversed)
  {
    targets = { "blink", "jaw", "wide" };
  }
  vtkNew<vtkStringArray> names;
  names->SetName("TargetNames");
  names->InsertNextValue("Neutral");
  for (size_t k = 0; k < targets.size(); ++k)
  {
    names->InsertNextValue(targets[k]);
    vtkNew<vtkFloatArray> delta;
    delta->SetName(("target" + std::to_string(k) + "_position").c_str());
    delta->SetNumberOfComponents(3);
    for (int i = begin; i < end; ++i)
    {
      const double dy = targets[k] == "wide" ? 0.01
        : targets[k] == "jaw"                ? (i >= 100 ? 0.3 : 0.0)
                                             : (i < 20 ? 0.05 : 0.0);
      delta->InsertNextTuple3(0.0, dy, 0.0);
    }
    face->GetPointData()->AddArray(delta);
  }
  face->GetFieldData()->AddArray(names);
  return face;
}

/// The filter's effective weights and DistNorm, by target name (the model's order).
std::vector<double> Figures(vtkMorphNodeFilter* filter)
{
  std::vector<double> figures;
  for (const char* name : { "Neutral", "wide", "jaw", "blink" })
  {
    const int i = filter->GetTargetIndex(name);
    figures.push_back(i < 0 ? -1.0 : filter->GetEffectiveWeight(i));
    figures.push_back(i < 0 ? -1.0 : filter->GetDistNorm()->GetValue(i));
  }
  return figures;
}

/// Update's success (each process's input is its own piece already).
bool Run(vtkMorphNodeFilter* filter)
{
  return filter->UpdatePiece(0, 1, 0) == 1;
}

void Configure(vtkMorphNodeFilter* filter)
{
  filter->SetWeightModeToRelative();
  filter->SetOptimizerPresetByName("adjusted");
  filter->SetThreshold(0.3);
  filter->SetWeightByName("wide", 0.4);
  filter->SetWeightByName("jaw", 0.5);
  filter->SetWeightByName("blink", 0.2);
}
} // namespace

int main(int argc, char* argv[])
{
  vtkNew<vtkMPIController> controller;
  controller->Initialize(&argc, &argv);
  vtkMultiProcessController::SetGlobalController(controller);
  const int rank = controller->GetLocalProcessId();
  if (controller->GetNumberOfProcesses() != 2)
  {
    std::cerr << "run with 2 processes (mpiexec -n 2)\n";
    controller->Finalize();
    return 1;
  }

  // The whole face on one process: what both halves must decide.
  vtkNew<vtkMorphNodeFilter> whole;
  whole->SetController(nullptr);
  whole->SetInputData(Piece(0, 200, false));
  Configure(whole);
  Check(Run(whole), "the whole face updates", rank);
  const std::vector<double> expected = Figures(whole);

  // Half of it on each process, the second half's targets in the opposite order.
  vtkNew<vtkMorphNodeFilter> half;
  half->SetInputData(rank == 0 ? Piece(0, 100, false) : Piece(100, 200, true));
  Configure(half);
  Check(Run(half), "the half updates", rank);
  const std::vector<double> got = Figures(half);
  for (size_t i = 0; i < expected.size(); ++i)
  {
    Check(std::abs(got[i] - expected[i]) < 1e-12,
      "figure " + std::to_string(i) + ": " + std::to_string(got[i]) + " vs the whole face's " +
        std::to_string(expected[i]),
      rank);
  }
  Check(half->GetNumberOfTargets() == 4, "the model's four targets", rank);

  // Negative control: without the exchange the first half has no "jaw" movement, so its
  // own DistNorm differs from the whole face's.
  vtkNew<vtkMorphNodeFilter> alone;
  alone->SetController(nullptr);
  alone->SetInputData(rank == 0 ? Piece(0, 100, false) : Piece(100, 200, true));
  Configure(alone);
  Run(alone);
  Check(Figures(alone) != expected, "a half deciding alone differs (negative control)", rank);

  // A frame budget: both processes choose the same threshold (the slowest one's times).
  half->SetFrameBudget(1e-6);
  Check(Run(half), "the half updates with a budget", rank);
  half->SetWeightByName("jaw", 0.45);
  Check(Run(half), "the half updates again with a budget", rank);
  double threshold[2] = { half->GetFrameBudgetThreshold(), 0.0 };
  double thresholds[4] = { 0, 0, 0, 0 };
  controller->AllGather(threshold, thresholds, 2);
  Check(thresholds[0] == thresholds[2] && thresholds[0] >= 0.0, "the same budget threshold", rank);

  // An empty piece on process 1: it takes part and gives an empty output.
  vtkNew<vtkMorphNodeFilter> partial;
  partial->SetInputData(rank == 0 ? Piece(0, 200, false) : Piece(0, 0, false));
  Configure(partial);
  Check(Run(partial), "a process with an empty piece takes part", rank);
  if (rank == 0)
  {
    const std::vector<double> full = Figures(partial);
    Check(full == expected, "the other process's figures are the whole face's", rank);
  }

  // A broken piece on process 1 (TargetNames of the wrong count): every process fails.
  vtkNew<vtkMorphNodeFilter> broken;
  auto piece = rank == 0 ? Piece(0, 100, false) : Piece(100, 200, true);
  if (rank == 1)
  {
    vtkStringArray::SafeDownCast(piece->GetFieldData()->GetAbstractArray("TargetNames"))
      ->InsertNextValue("extra");
  }
  broken->SetInputData(piece);
  std::cerr << "process " << rank << ": an error naming process 1 is expected next\n";
  Check(!Run(broken), "a broken piece on another process fails this one too", rank);

  std::cout << "process " << rank << ": " << (Failures ? "FAILED" : "passed") << "\n";
  int failures[2] = { Failures, 0 };
  int all[4] = { 0, 0, 0, 0 };
  controller->AllGather(failures, all, 2);
  controller->Finalize();
  return all[0] + all[2] == 0 ? 0 : 1;
}
