// SPDX-License-Identifier: BSD-3-Clause
// Fuzz target: the OBJ reader (ParseObj). Whatever it accepts must be a consistent mesh:
// finite coordinates, every triangle corner's indices in range.
#include "base/Error.h"
#include "rig/ObjSet.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

namespace
{
template <typename V>
void RequireFinite(const V& values)
{
  for (const auto v : values)
  {
    if (!std::isfinite(v))
    {
      std::abort();
    }
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try
  {
    const morphnode::ObjMesh mesh = morphnode::ParseObj(in, "fuzz.obj");
    if (mesh.Positions.empty() || mesh.Positions.size() % 3 != 0 ||
      mesh.TexCoords.size() % 2 != 0 || mesh.Normals.size() % 3 != 0 ||
      mesh.Triangles.size() % 3 != 0 || mesh.CornerTexCoords.size() != mesh.Triangles.size() ||
      mesh.CornerNormals.size() != mesh.Triangles.size() ||
      mesh.GetNumberOfTriangles() < mesh.NumberOfPolygons)
    {
      std::abort();
    }
    RequireFinite(mesh.Positions);
    RequireFinite(mesh.TexCoords);
    RequireFinite(mesh.Normals);
    for (size_t i = 0; i < mesh.Triangles.size(); ++i)
    {
      const long vt = mesh.CornerTexCoords[i];
      const long vn = mesh.CornerNormals[i];
      if (mesh.Triangles[i] >= mesh.GetNumberOfPoints() || vt < -1 ||
        vt >= static_cast<long>(mesh.TexCoords.size() / 2) || vn < -1 ||
        vn >= static_cast<long>(mesh.Normals.size() / 3))
      {
        std::abort();
      }
    }
  }
  catch (const morphnode::InputError&)
  {
    // rejected input is fine
  }
  return 0;
}
