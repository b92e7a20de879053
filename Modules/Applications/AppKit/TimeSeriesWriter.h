// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TimeSeriesWriter.h
/// @brief A polydata over time as a ParaView time series: FILE.pvd lists FILE/face_*.vtp
/// with their times. Each .vtp carries the data set's arrays and field data, its time
/// (field data `TimeValue`) and, when given, a row of weights (field data
/// `BehaviorWeights`, named by `BehaviorChannels`).

#include <string>
#include <utility>
#include <vector>

class vtkPolyData;
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

  /// One time step: `face` (not modified) and row 0 of `weights` (may be null). Throws
  /// std::runtime_error.
  void Write(vtkPolyData* face, vtkTable* weights, double time);

  /// Writes the .pvd and prints what it wrote. Throws std::runtime_error.
  void Close();

private:
  std::string Pvd, Folder, FolderPath;
  std::vector<std::pair<double, std::string>> Entries;
};
} // namespace appkit
} // namespace morphnode
