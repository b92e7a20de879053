// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A synthetic face for the transfer's tests: a curved sheet with a mouth slit (lips that
// touch, or apart by `gap`), two eye openings, analytic targets (jawOpen moves the lower lip
// and chin, eyeBlink_L/R the upper lids, mouthSmile_L the left corner) and optionally a
// "tooth": a closed box that jawOpen turns rigidly. Any grid spacing whose rows meet the
// mouth line gives the same surface and the same targets, so a finer or coarser copy is a
// remesh with a known answer.

#include "transfer/Transfer.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace synthetic
{
constexpr double MouthY = -0.5;
constexpr double MouthHalfWidth = 0.4;

inline double Height(double x, double y)
{
  return 0.5 - 0.2 * x * x - 0.1 * y * y + 0.15 * std::exp(-(x * x + (y - 0.1) * (y - 0.1)) / 0.02);
}

inline bool InEye(double x, double y)
{
  const double dx = std::abs(x) - 0.4, dy = y - 0.3;
  return dx * dx / (0.15 * 0.15) + dy * dy / (0.07 * 0.07) < 1.0;
}

/// The analytic delta of each target at (x, y), lower: on the lower lip's side of the slit.
inline glm::dvec3 Delta(const std::string& name, double x, double y, bool lower)
{
  if (name == "jawOpen")
  {
    if (!(lower || y < MouthY - 1e-9))
      return glm::dvec3(0.0);
    // Fading out towards the corners: continuous wherever the sheet is whole.
    const double f =
      std::exp(-x * x / 0.3) * std::clamp((MouthHalfWidth - std::abs(x)) / 0.1, 0.0, 1.0);
    return glm::dvec3(0.0, -0.2 * f, 0.05 * f);
  }
  if (name == "eyeBlink_L" || name == "eyeBlink_R")
  {
    const double cx = name == "eyeBlink_L" ? 0.4 : -0.4;
    const double r2 = (x - cx) * (x - cx) + (y - 0.3) * (y - 0.3);
    if (y <= 0.3 || r2 > 0.25 * 0.25)
      return glm::dvec3(0.0);
    // Zero on the eye's centre line: continuous beside the opening.
    const double f = (1.0 - r2 / (0.25 * 0.25)) * std::clamp((y - 0.3) / 0.07, 0.0, 1.0);
    return glm::dvec3(0.0, -0.08 * f * f, 0.0);
  }
  if (name == "mouthSmile_L")
  {
    const double r2 = (x - 0.4) * (x - 0.4) + (y - MouthY) * (y - MouthY);
    const double f = std::exp(-r2 / 0.02);
    return glm::dvec3(0.03 * f, 0.04 * f, -0.01 * f);
  }
  return glm::dvec3(0.0);
}

inline const std::vector<std::string>& Names()
{
  static const std::vector<std::string> names{ "jawOpen", "eyeBlink_L", "eyeBlink_R",
    "mouthSmile_L" };
  return names;
}

struct Face
{
  morphnode::TransferSurface Surface;
  std::vector<std::vector<glm::dvec3>> Deltas; // per Names()
  std::vector<int> Side; // +1 upper lip copy on the slit, -1 lower lip copy, 0 elsewhere
  std::vector<bool> Tooth;
  std::vector<glm::dvec2> Uv;
};

/// The tooth's rigid motion under jawOpen: a turn about the x axis through (0, -0.45, 0.3).
inline glm::dvec3 ToothMotion(const glm::dvec3& p)
{
  const glm::dvec3 pivot(0.0, -0.45, 0.3);
  const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), 0.2, glm::dvec3(1, 0, 0));
  return pivot + glm::dvec3(r * glm::dvec4(p - pivot, 1.0)) - p;
}

/// h: grid spacing, with 0.7 / h a whole number (the mouth line is a row).
inline Face MakeFace(double h, double gap = 0.0, bool openMouth = true, bool tooth = false)
{
  Face face;
  const int nx = int(std::lround(2.0 / h)) + 1;
  const int ny = int(std::lround(2.2 / h)) + 1;
  const int mouthRow = int(std::lround((MouthY + 1.2) / h));
  std::vector<int> id(size_t(nx * ny)), lowerId(size_t(nx * ny), -1);
  auto add = [&](double x, double y, bool lower, int side)
  {
    const double yy = lower ? y - gap : y;
    face.Surface.Points.emplace_back(x, yy, Height(x, yy));
    std::vector<glm::dvec3> d;
    face.Side.push_back(side);
    face.Uv.emplace_back(x, y);
    face.Tooth.push_back(false);
    return int(face.Surface.Points.size() - 1);
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const double x = -1.0 + i * h, y = -1.2 + j * h;
      const bool slit = openMouth && j == mouthRow && std::abs(x) < MouthHalfWidth - 1e-9;
      id[size_t(j * nx + i)] = add(x, y, false, slit ? 1 : 0);
      if (slit)
        lowerId[size_t(j * nx + i)] = add(x, y, true, -1);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i)
    {
      const double cx = -1.0 + (i + 0.5) * h, cy = -1.2 + (j + 0.5) * h;
      if (InEye(cx, cy))
        continue;
      // The row below the slit uses the lower lip's copies.
      auto v = [&](int ii, int jj)
      {
        const size_t k = size_t(jj * nx + ii);
        return uint32_t(jj == mouthRow && j < mouthRow && lowerId[k] >= 0 ? lowerId[k] : id[k]);
      };
      const uint32_t a = v(i, j), b = v(i + 1, j), c = v(i + 1, j + 1), d = v(i, j + 1);
      face.Surface.Triangles.insert(face.Surface.Triangles.end(), { a, b, c, a, c, d });
    }
  if (tooth)
  {
    // A closed box (12 triangles) behind the mouth.
    const uint32_t base = uint32_t(face.Surface.Points.size());
    for (int k = 0; k < 8; ++k)
    {
      face.Surface.Points.emplace_back(
        (k & 1) ? 0.15 : -0.15, (k & 2) ? -0.5 : -0.6, (k & 4) ? 0.3 : 0.2);
      face.Side.push_back(0);
      face.Uv.emplace_back(0, 0);
      face.Tooth.push_back(true);
    }
    const uint32_t q[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 },
      { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
    for (const auto& f : q)
      face.Surface.Triangles.insert(face.Surface.Triangles.end(),
        { base + f[0], base + f[1], base + f[2], base + f[0], base + f[2], base + f[3] });
  }
  // Drop the points the eyes' openings left without triangles.
  {
    std::vector<int> remap(face.Surface.Points.size(), -1);
    for (uint32_t v : face.Surface.Triangles)
      remap[v] = 0;
    Face compact;
    for (size_t i = 0; i < remap.size(); ++i)
      if (remap[i] == 0)
      {
        remap[i] = int(compact.Surface.Points.size());
        compact.Surface.Points.push_back(face.Surface.Points[i]);
        compact.Side.push_back(face.Side[i]);
        compact.Uv.push_back(face.Uv[i]);
        compact.Tooth.push_back(face.Tooth[i]);
      }
    for (uint32_t v : face.Surface.Triangles)
      compact.Surface.Triangles.push_back(uint32_t(remap[v]));
    face = compact;
  }
  for (const auto& name : Names())
  {
    std::vector<glm::dvec3> d;
    for (size_t i = 0; i < face.Surface.Points.size(); ++i)
    {
      if (face.Tooth[i])
        d.push_back(name == "jawOpen" ? ToothMotion(face.Surface.Points[i]) : glm::dvec3(0.0));
      else
        d.push_back(Delta(name, face.Uv[i].x, face.Uv[i].y, face.Side[i] < 0));
    }
    face.Deltas.push_back(d);
  }
  return face;
}

inline morphnode::TransferSource ToSource(const Face& face)
{
  morphnode::TransferSource s;
  s.Surface = face.Surface;
  s.TargetNames = Names();
  s.Deltas = face.Deltas;
  return s;
}
} // namespace synthetic
