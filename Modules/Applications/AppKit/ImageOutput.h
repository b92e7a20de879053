// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ImageOutput.h
/// @brief PNG files of what the programs render: a render window's frame, or a chart.
/// Each creates the file's folder if needed and throws std::runtime_error (with the path)
/// when it cannot write.

#include <string>

class vtkContextView;
class vtkRenderWindow;

namespace morphnode
{
namespace appkit
{
/// Creates `folder` and its parents (nothing for ""). Throws std::runtime_error.
void MakeFolder(const std::string& folder);

/// The window's last rendered frame (its back buffer) to a PNG.
void WritePng(vtkRenderWindow* window, const std::string& file);

/// A chart view rendered offscreen without multisampling (so files are reproducible).
void WritePng(vtkContextView* view, const std::string& file);
} // namespace appkit
} // namespace morphnode
