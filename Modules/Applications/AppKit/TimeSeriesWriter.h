// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TimeSeriesWriter.h
/// @brief A head over time as a ParaView time series: FILE.pvd lists one file per time
/// step with its time: FILE/face_*.vtp for one vtkPolyData, FILE/face_*.vtm for a head of
/// parts (a composite such as the reader's vtkPartitionedDataSetCollection), a multiblock of
/// one block per part named by the part (PartName), its parts in FILE/face_*/ (.vtp). A
/// multiblock rather than a .vtpc because every ParaView and VTK reader of .pvd collections
/// reads .vtm. Each part carries its arrays and field data, the time (field data
/// `TimeValue`) and, when given, a row of weights (field data `BehaviorWeights`, named by
/// `BehaviorChannels`).

#include <string>
#include <utility>
#include <vector>

class vtkDataObject;
class vtkTable;

namespace morphnode
{
namespace appkit
{
class TimeSeriesWriter
{
public:
  /// `pvd` must end in .pvd; the folder beside it (FILE/) is created. Throws
  /// std::runtime_error.
  explicit TimeSeriesWriter(const std::string& pvd);

  /// One time step: `face` (a vtkPolyData or a composite of vtkPolyData parts; not
  /// modified) and row 0 of `weights` (may be null). Throws std::runtime_error.
  void Write(vtkDataObject* face, vtkTable* weights, double time);

  /// Writes the .pvd and prints what it wrote. Throws std::runtime_error.
  void Close();

private:
  std::string Pvd, Folder, FolderPath;
  std::vector<std::pair<double, std::string>> Entries;
};
} // namespace appkit
} // namespace morphnode
