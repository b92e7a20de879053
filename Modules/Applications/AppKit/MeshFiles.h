// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file MeshFiles.h
/// @brief A mesh file of any format the programs take as a scene: glTF/GLB through the
/// core's validated loader, OBJ, PLY, STL and VTP through VTK's readers as one part.

#include "gltf/GltfScene.h"

#include <string>

namespace morphnode
{
namespace appkit
{
/// Reads `fileName` by its extension (.glb, .gltf, .obj, .ply, .stl, .vtp). A non-glTF file
/// becomes one part (node "Mesh") of triangles: polygons are triangulated; STL's triangle
/// soup is welded (coincident points merged, tolerance 0); other formats keep their points
/// as they are. Throws InputError naming the file.
GltfScene ReadMeshScene(const std::string& fileName);
} // namespace appkit
} // namespace morphnode
