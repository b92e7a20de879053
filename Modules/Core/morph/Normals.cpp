// SPDX-License-Identifier: BSD-3-Clause
#include "morph/Normals.h"

#include "base/Error.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <sstream>

namespace morphnode
{
std::vector<float> ComputeVertexNormals(
  const float* positions, size_t numPoints, const uint32_t* triangles, size_t numTriangles)
{
  std::vector<glm::dvec3> sum(numPoints, glm::dvec3(0.0));
  auto point = [&](uint32_t id)
  { return glm::dvec3(positions[3 * id], positions[3 * id + 1], positions[3 * id + 2]); };
  for (size_t t = 0; t < numTriangles; ++t)
  {
    const uint32_t* tri = triangles + 3 * t;
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] >= numPoints)
      {
        std::ostringstream msg;
        msg << "triangle " << t << " uses point " << tri[k] << " of a mesh of " << numPoints
            << " points";
        throw InputError(msg.str());
      }
    }
    // The cross product's length is twice the area: larger triangles weigh more.
    const glm::dvec3 n = glm::cross(point(tri[1]) - point(tri[0]), point(tri[2]) - point(tri[0]));
    for (int k = 0; k < 3; ++k)
    {
      sum[tri[k]] += n;
    }
  }
  std::vector<float> normals(numPoints * 3, 0.0f);
  for (size_t p = 0; p < numPoints; ++p)
  {
    const double len = glm::length(sum[p]);
    if (len > 0.0)
    {
      for (int c = 0; c < 3; ++c)
      {
        normals[3 * p + c] = static_cast<float>(sum[p][c] / len);
      }
    }
  }
  return normals;
}

std::vector<float> ComputeNormalDeltas(const float* basePositions, const float* positionDeltas,
  const std::vector<float>& baseNormals, size_t numPoints, const uint32_t* triangles,
  size_t numTriangles)
{
  std::vector<float> shape(numPoints * 3);
  for (size_t i = 0; i < shape.size(); ++i)
  {
    shape[i] = basePositions[i] + positionDeltas[i];
  }
  std::vector<float> deltas =
    ComputeVertexNormals(shape.data(), numPoints, triangles, numTriangles);
  for (size_t i = 0; i < deltas.size(); ++i)
  {
    deltas[i] -= baseNormals[i];
  }
  return deltas;
}
} // namespace morphnode
