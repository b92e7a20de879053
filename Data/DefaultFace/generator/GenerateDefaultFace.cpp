// SPDX-License-Identifier: BSD-3-Clause
// GenerateDefaultFace: builds MorphNode's own default face and writes it as one glTF 2.0
// binary (GLB) with the 12 non-neutral morph targets of Berner's Table 1.
//
//   GenerateDefaultFace <output.glb>     (prints vertex/triangle counts and dist_norm)
//
// The face is procedural: a head made of horizontal cross-sections (a "generalized
// cylinder" whose rows are spaced by arc length along the front profile, denser over the
// face), displaced by analytic features (nose, eye sockets, brows, cheekbones, lips, chin,
// ears). The mouth and the eyes are slits: the grid row at the lip line (and at each eye)
// has duplicated vertices, one copy for the skin above and one for the skin below, so
// that lips and lids can separate. A mouth bag and teeth sit behind the lips, eyeballs
// behind the lids.
//
// Every pose (neutral and each target) is computed by one function from a few pose
// parameters (jaw angle, lip motions, lid closure, brow motions), so targets are
// consistent everywhere, the mouth bag and teeth included; deltas are pose - neutral.
//
// Output is deterministic: positions are rounded to 1 micrometre and normals to 1e-5
// before writing, the JSON is written in a fixed key order, and nothing depends on time
// or the environment. A test regenerates the file and compares it byte for byte.
//
// Conventions: metres, +Y up, the face looks along +Z, the head is about 0.2 m from chin
// to crown.

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using glm::dvec2;
using glm::dvec3;
constexpr double Pi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------
// Small numeric helpers
// ---------------------------------------------------------------------------------------
double Clamp01(double t)
{
  return std::min(1.0, std::max(0.0, t));
}

/// 0 at or below edge0, 1 at or above edge1 (edges may be given in either order).
double SmoothStep(double edge0, double edge1, double x)
{
  const double t = Clamp01((x - edge0) / (edge1 - edge0));
  return t * t * (3.0 - 2.0 * t);
}

/// A compact smooth bump: 1 at r = 0, 0 for r >= 1, zero slope at both ends.
double Bump(double r)
{
  if (r >= 1.0)
  {
    return 0.0;
  }
  const double q = 1.0 - r * r;
  return q * q;
}

/// Interpolating cubic through (x_i, y_i) with finite-difference tangents (Catmull-Rom on
/// non-uniform knots); clamped outside the knots.
class Curve
{
public:
  Curve(std::initializer_list<dvec2> knots)
    : Knots(knots)
  {
  }
  double operator()(double x) const
  {
    const auto& k = this->Knots;
    if (x <= k.front().x)
    {
      return k.front().y;
    }
    if (x >= k.back().x)
    {
      return k.back().y;
    }
    size_t i = 0;
    while (k[i + 1].x < x)
    {
      ++i;
    }
    const double h = k[i + 1].x - k[i].x;
    const double t = (x - k[i].x) / h;
    const double m0 = this->Slope(i) * h;
    const double m1 = this->Slope(i + 1) * h;
    const double t2 = t * t;
    const double t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * k[i].y + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * k[i + 1].y +
      (t3 - t2) * m1;
  }

private:
  double Slope(size_t i) const
  {
    const auto& k = this->Knots;
    if (i == 0)
    {
      return (k[1].y - k[0].y) / (k[1].x - k[0].x);
    }
    if (i + 1 == k.size())
    {
      return (k[i].y - k[i - 1].y) / (k[i].x - k[i - 1].x);
    }
    return (k[i + 1].y - k[i - 1].y) / (k[i + 1].x - k[i - 1].x);
  }
  std::vector<dvec2> Knots;
};

dvec3 RotateX(const dvec3& p, const dvec3& pivot, double angle)
{
  const dvec3 d = p - pivot;
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return pivot + dvec3(d.x, c * d.y - s * d.z, s * d.y + c * d.z);
}

// ---------------------------------------------------------------------------------------
// Design constants (before the final scale)
// ---------------------------------------------------------------------------------------
constexpr int Columns = 96;         // around the head
constexpr int Rows = 84;            // neck bottom to just below the crown
constexpr double NeckBottom = -0.170;
constexpr double Crown = 0.135;
constexpr double FinalScale = 0.88; // chin to crown about 0.205 m
constexpr double MouthCornerX = 0.025;
constexpr double EyeCenterX = 0.033;
constexpr double EyeHalfWidth = 0.0125; // eye corners at EyeCenterX -/+ this
constexpr double EyeballRadius = 0.0125;
constexpr double LidOffset = 0.0016;   // lid skin above the eyeball
constexpr int MouthBagRings = 5;
constexpr int TeethSegments = 18;
constexpr int EyeballSegments = 20;
constexpr int EyeballStacks = 14;

// Side view: front (z of the base head before features), back, and half width, by height y.
const Curve FrontZ{ { -0.170, 0.040 }, { -0.130, 0.046 }, { -0.115, 0.052 }, { -0.106, 0.068 },
  { -0.099, 0.083 }, { -0.088, 0.093 }, { -0.070, 0.097 }, { -0.050, 0.100 }, { -0.030, 0.101 },
  { -0.005, 0.098 }, { 0.020, 0.093 }, { 0.040, 0.096 }, { 0.070, 0.090 }, { 0.095, 0.074 },
  { 0.115, 0.050 }, { 0.128, 0.025 }, { 0.135, -0.010 } };
const Curve BackZ{ { -0.170, -0.045 }, { -0.110, -0.050 }, { -0.070, -0.070 }, { -0.030, -0.098 },
  { 0.020, -0.110 }, { 0.070, -0.104 }, { 0.100, -0.085 }, { 0.120, -0.058 }, { 0.130, -0.035 },
  { 0.135, -0.010 } };
const Curve HalfWidth{ { -0.170, 0.047 }, { -0.120, 0.049 }, { -0.100, 0.058 }, { -0.080, 0.065 },
  { -0.050, 0.071 }, { -0.020, 0.075 }, { 0.020, 0.077 }, { 0.060, 0.076 }, { 0.090, 0.069 },
  { 0.112, 0.052 }, { 0.126, 0.030 }, { 0.135, 0.000 } };

// Nose: ridge height over the base and ridge half width, by y.
const Curve NoseHeight{ { 0.045, 0.000 }, { 0.032, 0.005 }, { 0.015, 0.011 }, { 0.000, 0.017 },
  { -0.014, 0.024 }, { -0.022, 0.029 }, { -0.027, 0.026 }, { -0.031, 0.016 }, { -0.034, 0.006 },
  { -0.037, 0.000 } };
const Curve NoseWidth{ { 0.045, 0.011 }, { 0.020, 0.009 }, { 0.000, 0.010 }, { -0.015, 0.013 },
  { -0.024, 0.016 }, { -0.032, 0.019 }, { -0.037, 0.019 } };

// ---------------------------------------------------------------------------------------
// Pose: what a target changes. The neutral is the all-zero pose.
// ---------------------------------------------------------------------------------------
struct Pose
{
  double JawAngle = 0.0;       // radians, opens the mouth
  double UpperLipRaise = 0.0;  // m, centre of the upper lip up
  double LowerLipDrop = 0.0;   // m, centre of the lower lip down (beyond the jaw)
  double LowerLipTuck = 0.0;   // m, lower lip up and back under the upper teeth (F)
  double Pucker = 0.0;         // 0..1, lips narrow and push forward (O)
  dvec3 CornerMove{ 0.0 };     // m, mouth corners: x outward, y up, z forward
  double CheekRaise = 0.0;     // m
  double ChinRaise = 0.0;      // m, lower lip and chin pushed up (sad)
  double LidClose = 0.0;       // 0..1, upper lids down to the lower lids
  double BrowInnerUp = 0.0;    // m
  double BrowOuterUp = 0.0;    // m
  double BrowSqueeze = 0.0;    // m, brows toward the midline
  double BrowForward = 0.0;    // m
};

struct Target
{
  const char* Name;
  Pose Shape;
};

// The 12 non-neutral targets of Berner's Table 1, in table order.
std::vector<Target> Targets()
{
  std::vector<Target> targets;
  Pose p;

  p = Pose();
  p.LidClose = 1.0;
  targets.push_back({ "EyesClosed", p });

  p = Pose();
  p.BrowInnerUp = 0.0075;
  p.BrowOuterUp = 0.0075;
  targets.push_back({ "BrowsUp", p });

  p = Pose(); // teeth nearly closed, lips slightly spread and parted
  p.JawAngle = 0.025;
  p.UpperLipRaise = 0.0018;
  p.LowerLipDrop = 0.0012;
  p.CornerMove = dvec3(0.0035, 0.0005, -0.001);
  targets.push_back({ "S", p });

  p = Pose(); // lower lip up and back against the upper teeth
  p.JawAngle = 0.04;
  p.UpperLipRaise = 0.0015;
  p.LowerLipTuck = 0.0045;
  targets.push_back({ "F", p });

  p = Pose(); // inner brows up and together
  p.BrowInnerUp = 0.009;
  p.BrowOuterUp = 0.0015;
  p.BrowSqueeze = 0.0035;
  targets.push_back({ "BrowsFright", p });

  p = Pose(); // brows down and together
  p.BrowInnerUp = -0.0075;
  p.BrowOuterUp = -0.002;
  p.BrowSqueeze = 0.0045;
  p.BrowForward = 0.002;
  targets.push_back({ "BrowsAngry", p });

  p = Pose(); // open, relaxed lips (no tongue)
  p.JawAngle = 0.14;
  p.UpperLipRaise = 0.0015;
  p.LowerLipDrop = 0.001;
  targets.push_back({ "L", p });

  p = Pose(); // wide, slightly open
  p.JawAngle = 0.10;
  p.UpperLipRaise = 0.0025;
  p.LowerLipDrop = 0.0015;
  p.CornerMove = dvec3(0.0065, 0.0012, -0.002);
  p.CheekRaise = 0.0015;
  targets.push_back({ "E", p });

  p = Pose(); // jaw and lips open wide
  p.JawAngle = 0.26;
  p.UpperLipRaise = 0.003;
  p.LowerLipDrop = 0.002;
  p.CornerMove = dvec3(-0.002, 0.0, 0.0);
  targets.push_back({ "A", p });

  p = Pose();
  p.CornerMove = dvec3(0.0085, 0.0085, -0.004);
  p.CheekRaise = 0.0045;
  p.UpperLipRaise = 0.0008;
  targets.push_back({ "MouthSmile", p });

  p = Pose();
  p.CornerMove = dvec3(0.002, -0.0085, -0.001);
  p.ChinRaise = 0.0035;
  p.BrowInnerUp = 0.0025;
  p.BrowSqueeze = 0.0015;
  targets.push_back({ "MouthSad", p });

  p = Pose(); // round open
  p.JawAngle = 0.17;
  p.Pucker = 1.0;
  p.UpperLipRaise = 0.003;
  p.LowerLipDrop = 0.003;
  targets.push_back({ "O", p });
  return targets;
}

// ---------------------------------------------------------------------------------------
// Topology
// ---------------------------------------------------------------------------------------
enum class Side : uint8_t
{
  None,  // ordinary skin
  Upper, // belongs to the skin above a slit (upper lip, upper lid)
  Lower  // belongs to the skin below a slit
};

enum class Part : uint8_t
{
  Skin,
  MouthBag,
  UpperTeeth,
  LowerTeeth,
  Eyeball,
  LidMargin // rings from an eye slit toward the eyeball: the lids' thickness
};

struct VertexInfo
{
  Part Kind = Part::Skin;
  Side Which = Side::None;
  int Row = 0;    // skin grid row (the crown and neck centres use -1 and Rows)
  int Column = 0; // skin grid column, or ring / segment index elsewhere
  int Ring = 0;   // mouth bag ring (1..MouthBagRings, MouthBagRings + 1 = apex)
  int Loop = -1;  // mouth bag: index into the slit loop of the skin vertex it hangs from
  int Eye = 0;    // -1 right (x < 0), +1 left
  dvec3 Local{ 0.0 }; // teeth/eyeball: local parameters
};

struct Mesh
{
  std::vector<VertexInfo> Info;
  std::vector<uint32_t> Triangles;
  std::vector<double> RowY;      // height of each skin row
  std::vector<double> ColumnAngle;
  int MouthRow = 0;
  int EyeRow = 0;
  double MouthY = 0.0;
  double EyeY = 0.0;
  std::vector<std::vector<int>> SkinIndex;      // [row][column] -> vertex (Side None/Lower)
  std::vector<std::vector<int>> SkinUpperIndex; // [row][column] -> upper copy or -1
  std::vector<int> MouthLoop;                   // corner, upper copies, corner, lower copies
};

/// A slit's boundary as a closed loop: left corner, upper copies left to right, right
/// corner, lower copies right to left (columns grow toward +X).
std::vector<int> SlitLoop(const Mesh& mesh, int row, const std::vector<int>& slitColumns)
{
  std::vector<int> loop{ mesh.SkinIndex[row][slitColumns.front() - 1] };
  for (int c : slitColumns)
  {
    loop.push_back(mesh.SkinUpperIndex[row][c]);
  }
  loop.push_back(mesh.SkinIndex[row][slitColumns.back() + 1]);
  for (auto it = slitColumns.rbegin(); it != slitColumns.rend(); ++it)
  {
    loop.push_back(mesh.SkinIndex[row][*it]);
  }
  return loop;
}

/// Rows spaced by arc length of the front profile, weighted to be denser over the face.
std::vector<double> SampleRows()
{
  const int dense = 6000;
  std::vector<double> ys(dense + 1), length(dense + 1, 0.0);
  for (int k = 0; k <= dense; ++k)
  {
    ys[k] = NeckBottom + (Crown - NeckBottom) * k / dense;
  }
  for (int k = 1; k <= dense; ++k)
  {
    const double dy = ys[k] - ys[k - 1];
    const double dz = FrontZ(ys[k]) - FrontZ(ys[k - 1]);
    const double y = 0.5 * (ys[k] + ys[k - 1]);
    // Three times denser from the chin to the brows, where the features are.
    const double density = 1.0 + 2.0 * SmoothStep(-0.125, -0.105, y) * SmoothStep(0.075, 0.055, y);
    length[k] = length[k - 1] + std::sqrt(dy * dy + dz * dz) * density;
  }
  std::vector<double> rows(Rows);
  int k = 0;
  for (int r = 0; r < Rows; ++r)
  {
    // The last row stays below the crown: the crown itself is one centre vertex.
    const double target = length[dense] * r / Rows;
    while (k < dense && length[k + 1] < target)
    {
      ++k;
    }
    const double t = (target - length[k]) / std::max(1e-12, length[k + 1] - length[k]);
    rows[r] = ys[k] + t * (ys[k + 1] - ys[k]);
  }
  return rows;
}

/// Column angles: 0 faces +Z, positive toward +X; denser at the front.
std::vector<double> SampleColumns()
{
  std::vector<double> angles(Columns);
  for (int c = 0; c < Columns; ++c)
  {
    const double t = -1.0 + 2.0 * c / Columns; // [-1, 1)
    angles[c] = Pi * (0.5 * t + 0.5 * t * t * t);
  }
  return angles;
}

int NearestRow(const std::vector<double>& rows, double y)
{
  int best = 0;
  for (int r = 1; r < static_cast<int>(rows.size()); ++r)
  {
    if (std::abs(rows[r] - y) < std::abs(rows[best] - y))
    {
      best = r;
    }
  }
  return best;
}

/// Base head point (no features) at a row height and column angle.
dvec3 BaseHead(double y, double angle)
{
  const double front = FrontZ(y);
  const double back = BackZ(y);
  const double mid = 0.5 * (front + back);
  const double c = std::cos(angle);
  const double z = c >= 0.0 ? mid + (front - mid) * c : mid + (mid - back) * c;
  return dvec3(HalfWidth(y) * std::sin(angle), y, z);
}

bool InMouthSlit(const Mesh& mesh, int column)
{
  const dvec3 p = BaseHead(mesh.MouthY, mesh.ColumnAngle[column]);
  return std::cos(mesh.ColumnAngle[column]) > 0.0 && std::abs(p.x) < MouthCornerX;
}

/// -1/+1 when the column is strictly inside an eye's slit, 0 otherwise.
int InEyeSlit(const Mesh& mesh, int column)
{
  const dvec3 p = BaseHead(mesh.EyeY, mesh.ColumnAngle[column]);
  if (std::cos(mesh.ColumnAngle[column]) <= 0.0)
  {
    return 0;
  }
  if (std::abs(std::abs(p.x) - EyeCenterX) < EyeHalfWidth)
  {
    return p.x < 0.0 ? -1 : 1;
  }
  return 0;
}

void AddTriangle(Mesh& mesh, int a, int b, int c)
{
  mesh.Triangles.push_back(static_cast<uint32_t>(a));
  mesh.Triangles.push_back(static_cast<uint32_t>(b));
  mesh.Triangles.push_back(static_cast<uint32_t>(c));
}

/// Quad a-b-c-d split along its shorter diagonal's natural order (deterministic).
void AddQuad(Mesh& mesh, int a, int b, int c, int d)
{
  AddTriangle(mesh, a, b, c);
  AddTriangle(mesh, a, c, d);
}

int AddVertex(Mesh& mesh, const VertexInfo& info)
{
  mesh.Info.push_back(info);
  return static_cast<int>(mesh.Info.size()) - 1;
}

Mesh BuildTopology()
{
  Mesh mesh;
  mesh.RowY = SampleRows();
  mesh.ColumnAngle = SampleColumns();
  mesh.MouthRow = NearestRow(mesh.RowY, -0.056);
  mesh.EyeRow = NearestRow(mesh.RowY, 0.018);
  mesh.MouthY = mesh.RowY[mesh.MouthRow];
  mesh.EyeY = mesh.RowY[mesh.EyeRow];

  // Skin grid; slit rows get a second (upper) copy of the vertices inside a slit.
  mesh.SkinIndex.assign(Rows, std::vector<int>(Columns, -1));
  mesh.SkinUpperIndex.assign(Rows, std::vector<int>(Columns, -1));
  for (int r = 0; r < Rows; ++r)
  {
    for (int c = 0; c < Columns; ++c)
    {
      VertexInfo info;
      info.Row = r;
      info.Column = c;
      const bool mouth = r == mesh.MouthRow && InMouthSlit(mesh, c);
      const int eye = r == mesh.EyeRow ? InEyeSlit(mesh, c) : 0;
      info.Eye = eye;
      if (mouth || eye != 0)
      {
        info.Which = Side::Lower;
        mesh.SkinIndex[r][c] = AddVertex(mesh, info);
        info.Which = Side::Upper;
        mesh.SkinUpperIndex[r][c] = AddVertex(mesh, info);
      }
      else
      {
        mesh.SkinIndex[r][c] = AddVertex(mesh, info);
      }
    }
  }
  // Quads between row r and r + 1: the lower row's upper copy when it has one.
  for (int r = 0; r + 1 < Rows; ++r)
  {
    for (int c = 0; c < Columns; ++c)
    {
      const int c1 = (c + 1) % Columns;
      auto below = [&](int col) {
        return mesh.SkinUpperIndex[r][col] >= 0 ? mesh.SkinUpperIndex[r][col] : mesh.SkinIndex[r][col];
      };
      // Counter-clockwise seen from outside: angle grows toward +X, rows grow upward.
      AddQuad(mesh, below(c), mesh.SkinIndex[r + 1][c], mesh.SkinIndex[r + 1][c1], below(c1));
    }
  }
  // Crown and neck caps.
  VertexInfo crown;
  crown.Row = Rows;
  const int crownIndex = AddVertex(mesh, crown);
  VertexInfo neck;
  neck.Row = -1;
  const int neckIndex = AddVertex(mesh, neck);
  for (int c = 0; c < Columns; ++c)
  {
    const int c1 = (c + 1) % Columns;
    AddTriangle(mesh, mesh.SkinIndex[Rows - 1][c], crownIndex, mesh.SkinIndex[Rows - 1][c1]);
    AddTriangle(mesh, mesh.SkinIndex[0][c1], neckIndex, mesh.SkinIndex[0][c]);
  }

  // Mouth loop: left corner (x < 0), upper copies left to right, right corner, lower copies
  // right to left. Columns grow toward +X.
  std::vector<int> slitColumns;
  for (int c = 0; c < Columns; ++c)
  {
    if (mesh.SkinUpperIndex[mesh.MouthRow][c] >= 0)
    {
      slitColumns.push_back(c);
    }
  }
  mesh.MouthLoop = SlitLoop(mesh, mesh.MouthRow, slitColumns);

  // Lid margins: two rings from each eye slit toward the eyeball, so that no gap shows
  // between lid edge and eyeball.
  for (int eye : { -1, 1 })
  {
    std::vector<int> columns;
    for (int c = 0; c < Columns; ++c)
    {
      if (mesh.SkinUpperIndex[mesh.EyeRow][c] >= 0 && mesh.Info[mesh.SkinIndex[mesh.EyeRow][c]].Eye == eye)
      {
        columns.push_back(c);
      }
    }
    const std::vector<int> loop = SlitLoop(mesh, mesh.EyeRow, columns);
    std::vector<int> previousRing = loop;
    for (int ring = 1; ring <= 2; ++ring)
    {
      std::vector<int> current(loop.size());
      for (size_t k = 0; k < loop.size(); ++k)
      {
        VertexInfo info;
        info.Kind = Part::LidMargin;
        info.Eye = eye;
        info.Ring = ring;
        info.Loop = loop[k]; // the skin vertex it hangs from
        current[k] = AddVertex(mesh, info);
      }
      for (size_t k = 0; k < loop.size(); ++k)
      {
        const size_t k1 = (k + 1) % loop.size();
        AddQuad(mesh, previousRing[k], previousRing[k1], current[k1], current[k]);
      }
      previousRing = current;
    }
  }

  // Mouth bag: rings behind the loop, closed by an apex.
  const int loopSize = static_cast<int>(mesh.MouthLoop.size());
  std::vector<int> previous = mesh.MouthLoop;
  for (int ring = 1; ring <= MouthBagRings; ++ring)
  {
    std::vector<int> current(loopSize);
    for (int k = 0; k < loopSize; ++k)
    {
      VertexInfo info;
      info.Kind = Part::MouthBag;
      info.Ring = ring;
      info.Loop = k;
      info.Which = mesh.Info[mesh.MouthLoop[k]].Which;
      current[k] = AddVertex(mesh, info);
    }
    for (int k = 0; k < loopSize; ++k)
    {
      const int k1 = (k + 1) % loopSize;
      // Seen from inside the mouth (the side one looks at through the lips).
      AddQuad(mesh, previous[k], previous[k1], current[k1], current[k]);
    }
    previous = current;
  }
  VertexInfo apex;
  apex.Kind = Part::MouthBag;
  apex.Ring = MouthBagRings + 1;
  const int apexIndex = AddVertex(mesh, apex);
  for (int k = 0; k < loopSize; ++k)
  {
    AddTriangle(mesh, previous[k], previous[(k + 1) % loopSize], apexIndex);
  }

  // Teeth: two arcs of rectangular cross-section (front-top, front-bottom, back-bottom,
  // back-top), closed at the ends.
  for (Part teeth : { Part::UpperTeeth, Part::LowerTeeth })
  {
    const int first = static_cast<int>(mesh.Info.size());
    for (int s = 0; s <= TeethSegments; ++s)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        VertexInfo info;
        info.Kind = teeth;
        info.Column = first + 4 * s; // first vertex of this cross-section (for orientation)
        info.Local = dvec3(static_cast<double>(s) / TeethSegments, corner, 0.0);
        AddVertex(mesh, info);
      }
    }
    auto at = [&](int s, int corner) { return first + 4 * s + corner; };
    for (int s = 0; s < TeethSegments; ++s)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        const int next = (corner + 1) % 4;
        AddQuad(mesh, at(s, corner), at(s, next), at(s + 1, next), at(s + 1, corner));
      }
    }
    AddQuad(mesh, at(0, 0), at(0, 3), at(0, 2), at(0, 1));
    AddQuad(mesh, at(TeethSegments, 0), at(TeethSegments, 1), at(TeethSegments, 2),
      at(TeethSegments, 3));
  }

  // Eyeballs: UV spheres.
  for (int eye : { -1, 1 })
  {
    const int first = static_cast<int>(mesh.Info.size());
    for (int st = 0; st <= EyeballStacks; ++st)
    {
      for (int sg = 0; sg < EyeballSegments; ++sg)
      {
        VertexInfo info;
        info.Kind = Part::Eyeball;
        info.Eye = eye;
        info.Local = dvec3(Pi * st / EyeballStacks, 2.0 * Pi * sg / EyeballSegments, 0.0);
        AddVertex(mesh, info);
      }
    }
    for (int st = 0; st < EyeballStacks; ++st)
    {
      for (int sg = 0; sg < EyeballSegments; ++sg)
      {
        const int sg1 = (sg + 1) % EyeballSegments;
        AddQuad(mesh, first + st * EyeballSegments + sg, first + (st + 1) * EyeballSegments + sg,
          first + (st + 1) * EyeballSegments + sg1, first + st * EyeballSegments + sg1);
      }
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------------------
dvec3 EyeCenter(const Mesh& mesh, int eye)
{
  const double x = eye * EyeCenterX;
  // The eyeball's front sits well behind the brow and cheek surface, as in a real face.
  const double frontZ = FrontZ(mesh.EyeY) * std::cos(std::asin(x / HalfWidth(mesh.EyeY))) - 0.0045;
  return dvec3(x, mesh.EyeY, frontZ - EyeballRadius);
}

/// Static features: the neutral face's relief over the base head, as an offset along +Z
/// on the front (and along X for the ears).
dvec3 Features(const Mesh& mesh, const dvec3& p, double angle)
{
  const double front = SmoothStep(0.05, 0.45, std::cos(angle));
  const double x = p.x;
  const double y = p.y;
  const double ax = std::abs(x);
  double dz = 0.0;

  // Nose ridge and wings.
  const double nw = NoseWidth(y);
  const double ridge = ax / nw;
  dz += NoseHeight(y) * (ridge < 1.0 ? std::pow(1.0 - ridge * ridge, 1.5) : 0.0);
  dz += 0.0030 * Bump(std::hypot((ax - 0.0115) / 0.0070, (y + 0.029) / 0.0060)); // wings
  // Eye sockets, brow bone, brows (a narrow ridge), cheekbones.
  const double eyeDx = ax - EyeCenterX;
  dz -= 0.010 * Bump(std::hypot(eyeDx / 0.024, (y - mesh.EyeY) / 0.019));
  dz += 0.004 * Bump(std::hypot(eyeDx / 0.030, (y - mesh.EyeY - 0.022) / 0.011));
  const double browLine = mesh.EyeY + 0.021 + 0.004 * (1.0 - std::pow(eyeDx / 0.022, 2.0));
  const double browAlong = Bump(std::abs(eyeDx + 0.002) / 0.026);
  dz += 0.0034 * browAlong * Bump(std::abs(y - browLine) / 0.0055);
  dz += 0.006 * Bump(std::hypot((ax - 0.046) / 0.026, (y + 0.014) / 0.020));
  dz += 0.004 * Bump(std::hypot((ax - 0.045) / 0.022, (y + 0.045) / 0.025)); // cheek fullness
  // Lips: upper and lower vermilion bulges meeting at the lip line, philtrum, chin.
  const double dy = y - mesh.MouthY;
  const double across = Clamp01(1.0 - std::pow(ax / (MouthCornerX + 0.003), 2.0));
  if (dy >= 0.0)
  {
    // Thinner toward the corners; a slight cupid's bow near the middle.
    const double height = 0.004 + 0.005 * across + 0.0012 * Bump(std::abs(ax - 0.006) / 0.006);
    dz += 0.0060 * across * Bump(std::abs(dy - 0.35 * height) / height);
    dz -= 0.0012 * Bump(ax / 0.005) * Bump(std::abs(dy - 0.014) / 0.008); // philtrum
  }
  else
  {
    const double height = 0.005 + 0.006 * across;
    dz += 0.0070 * across * Bump(std::abs(dy + 0.4 * height) / height);
    dz -= 0.0022 * Bump(std::hypot(ax / 0.022, (dy + 0.019) / 0.007)); // below the lower lip
  }
  dz -= 0.0015 * Bump(std::abs(dy) / 0.0018) * across;                   // lip line crease
  dz += 0.0060 * Bump(std::hypot(ax / 0.022, (y + 0.088) / 0.016));      // chin
  dz -= 0.0030 * Bump(std::hypot((ax - 0.034) / 0.010, dy / 0.016));      // mouth-corner hollow

  dvec3 offset(0.0, 0.0, dz * front);
  // Ears on the sides: a flattened oval with a hollow.
  const double side = SmoothStep(0.6, 0.9, std::abs(std::sin(angle)));
  if (side > 0.0)
  {
    const double earZ = 0.5 * (FrontZ(y) + BackZ(y)) - 0.012;
    const double r = std::hypot((p.z - earZ) / 0.017, (y - 0.002) / 0.030);
    const double ear = 0.013 * Bump(r) - 0.006 * Bump(r / 0.55);
    offset.x += (x < 0.0 ? -1.0 : 1.0) * ear * side;
  }
  return offset;
}

/// Eye region: lids wrap the eyeball (a sphere slightly larger than it) and open by
/// sliding rows vertically. Returns the new (y, z) blend for a skin vertex.
dvec3 ShapeEyeRegion(const Mesh& mesh, const VertexInfo& info, const dvec3& p, double lidClose)
{
  const int eye = p.x < 0.0 ? -1 : 1;
  const dvec3 center = EyeCenter(mesh, eye);
  const double s = (p.x - center.x) / EyeHalfWidth; // along the eye, -1..1 at the corners
  const double dy = p.y - mesh.EyeY;
  const double region = Bump(std::hypot((p.x - center.x) / 0.021, dy / 0.017));
  if (region <= 0.0)
  {
    return p;
  }
  // Lid edges, as heights over the eye row: open upper and lower, and the closed line.
  const double openness = std::pow(Clamp01(1.0 - s * s), 0.6);
  const double upperOpen = 0.0068 * openness * (1.0 + 0.15 * eye * s * -1.0);
  const double lowerOpen = -0.0042 * openness;
  const double upperEdge = upperOpen + lidClose * (lowerOpen + 0.0003 - upperOpen);
  const double upperSpan = 0.014; // rows above the slit compress into this band
  const double lowerSpan = 0.011;
  double newDy = dy;
  if (info.Which == Side::Upper || (info.Which == Side::None && dy > 0.0))
  {
    // Map [0, upperSpan] onto [upperEdge, upperSpan].
    if (dy < upperSpan)
    {
      newDy = upperEdge + dy * (upperSpan - upperEdge) / upperSpan;
    }
  }
  else if (dy > -lowerSpan)
  {
    newDy = lowerOpen + dy * (-lowerSpan - lowerOpen) / -lowerSpan;
  }
  const double horizontal = Bump(std::abs(s) / 1.7);
  const double y = p.y + (newDy - dy) * horizontal;
  // Lid surface: the eyeball sphere plus the lid's thickness, faded into the socket.
  const double rx = p.x - center.x;
  const double ry = y - center.y;
  const double radius = EyeballRadius + LidOffset;
  const double under = std::max(0.0, radius * radius - rx * rx - ry * ry);
  const double sphereZ = center.z + std::sqrt(under);
  // The lid never goes inside the eyeball: in front of the sphere the socket surface is
  // kept, behind it the lid lies on the sphere; near the lid edges the lid hugs it.
  const double hug = SmoothStep(0.95 * radius, 0.6 * radius, std::hypot(rx, ry));
  const double onSphere = under > 0.0 ? std::max(sphereZ, p.z + (sphereZ - p.z) * hug) : p.z;
  const double z = onSphere;
  return dvec3(p.x, y, p.z + (z - p.z) * region);
}

/// The jaw's share of a skin point's motion: 1 for the chin, 0 above the mouth; along the
/// lower lip it tapers to 0 at the corners, so the mouth opens as an oval.
double JawWeight(const Mesh& mesh, const VertexInfo& info, const dvec3& p, double angle)
{
  const double dy = p.y - mesh.MouthY;
  const double ax = std::abs(p.x);
  const double beyond = std::max(0.0, ax - MouthCornerX);
  const bool slit = info.Row == mesh.MouthRow && info.Which != Side::None && info.Eye == 0;
  const bool above = slit ? info.Which == Side::Upper : dy > 0.0;
  // Cheeks beyond the corners follow the jaw halfway at the lip line.
  const double cheek = 0.5 * SmoothStep(0.0, 0.012, beyond);
  double vertical;
  if (above)
  {
    vertical = cheek * SmoothStep(0.004 + 0.8 * beyond, 0.0, dy);
  }
  else
  {
    const double s = Clamp01(ax / MouthCornerX);
    const double atLine = beyond > 0.0 ? cheek : std::sqrt(1.0 - s * s);
    vertical = atLine + (1.0 - atLine) * SmoothStep(0.0, -(0.012 + 0.5 * beyond), dy);
  }
  const double neck = SmoothStep(-0.128, -0.104, p.y);
  const double frontness = SmoothStep(-0.1, 0.45, std::cos(angle));
  return vertical * neck * frontness;
}

dvec3 JawPivot(const Mesh& mesh)
{
  return dvec3(0.0, mesh.EyeY - 0.03, -0.005);
}

/// Lip, cheek and corner motions of a pose (not the jaw), for a skin point.
dvec3 MouthMotion(const Mesh& mesh, const VertexInfo& info, const dvec3& p, const Pose& pose)
{
  const double dy = p.y - mesh.MouthY;
  const double ax = std::abs(p.x);
  const double sign = p.x < 0.0 ? -1.0 : 1.0;
  const bool upper = info.Which == Side::Upper || (info.Which == Side::None && dy > 0.0);
  // Lip motions fade smoothly toward and a little past the corners (no vertical edges).
  const double across = Clamp01(1.0 - std::pow(ax / (MouthCornerX + 0.006), 2.0));
  dvec3 d(0.0);

  // Lip centres open (upper up, lower down), fading toward the corners and away from the lips.
  if (upper)
  {
    const double w = across * SmoothStep(0.024, 0.006, dy);
    d.y += pose.UpperLipRaise * w;
    d.z += 0.25 * pose.UpperLipRaise * w;
  }
  else
  {
    const double w = across * SmoothStep(-0.022, -0.008, dy);
    d.y -= pose.LowerLipDrop * w;
    d.y += pose.LowerLipTuck * w;
    d.z -= 0.9 * pose.LowerLipTuck * w;
    d.y += pose.ChinRaise * SmoothStep(-0.040, -0.010, dy) * Bump(ax / 0.045);
    d.z += 0.6 * pose.ChinRaise * SmoothStep(-0.040, -0.008, dy) * Bump(ax / 0.04);
  }
  // Corners: a soft region around each corner carries the lip corner.
  const double cornerR = std::hypot((ax - MouthCornerX) / 0.020, dy / 0.018);
  const double corner = Bump(cornerR / 1.0);
  d += corner * dvec3(sign * pose.CornerMove.x, pose.CornerMove.y, pose.CornerMove.z);
  // Pucker: the mouth region narrows and pushes forward; lips flare.
  const double mouthRegion = Bump(std::hypot(ax / 0.045, dy / 0.032));
  d.x -= pose.Pucker * 0.40 * p.x * mouthRegion;
  d.z += pose.Pucker * 0.010 * mouthRegion * mouthRegion;
  // Cheeks rise with a smile.
  const double cheek = Bump(std::hypot((ax - 0.040) / 0.024, (dy - 0.030) / 0.022));
  d.y += pose.CheekRaise * cheek;
  d.z += 0.5 * pose.CheekRaise * cheek;
  return d;
}

dvec3 BrowMotion(const Mesh& mesh, const dvec3& p, const Pose& pose)
{
  const double ax = std::abs(p.x);
  const double sign = p.x < 0.0 ? -1.0 : 1.0;
  const double dy = p.y - (mesh.EyeY + 0.024);
  // Brow region: strongest on the brows, carried partly into the forehead and upper lid.
  const double vertical = dy >= 0.0 ? SmoothStep(0.045, 0.0, dy) : SmoothStep(-0.016, 0.0, dy);
  const double horizontal = SmoothStep(0.075, 0.055, ax);
  const double w = vertical * horizontal;
  if (w <= 0.0)
  {
    return dvec3(0.0);
  }
  // Inner (near the midline) to outer blend along the brow.
  const double outer = SmoothStep(0.012, 0.055, ax);
  const double up = pose.BrowInnerUp * (1.0 - outer) + pose.BrowOuterUp * outer;
  const double inner = 1.0 - outer;
  return w * dvec3(-sign * pose.BrowSqueeze * (0.4 + 0.6 * inner) * SmoothStep(0.0, 0.012, ax), up,
                 pose.BrowForward * inner);
}

/// Every vertex of the face in a pose.
std::vector<dvec3> BuildPositions(const Mesh& mesh, const Pose& pose)
{
  const size_t n = mesh.Info.size();
  std::vector<dvec3> out(n);
  std::vector<dvec3> neutralSkin(n); // skin without pose (for the mouth bag)
  const dvec3 pivot = JawPivot(mesh);

  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = mesh.Info[v];
    if (info.Kind != Part::Skin)
    {
      continue;
    }
    dvec3 p;
    double angle = 0.0;
    if (info.Row == Rows)
    {
      p = dvec3(0.0, Crown, FrontZ(Crown));
    }
    else if (info.Row == -1)
    {
      p = dvec3(0.0, NeckBottom, 0.5 * (FrontZ(NeckBottom) + BackZ(NeckBottom)));
    }
    else
    {
      angle = mesh.ColumnAngle[info.Column];
      p = BaseHead(mesh.RowY[info.Row], angle);
      p += Features(mesh, p, angle);
    }
    const bool grid = info.Row >= 0 && info.Row < Rows;
    const double front = grid ? std::cos(angle) : -1.0;
    if (front > 0.0 && std::abs(std::abs(p.x) - EyeCenterX) < 0.03 && std::abs(p.y - mesh.EyeY) < 0.02)
    {
      neutralSkin[v] = ShapeEyeRegion(mesh, info, p, 0.0);
      p = ShapeEyeRegion(mesh, info, p, pose.LidClose);
    }
    else
    {
      neutralSkin[v] = p;
    }
    if (front > 0.0)
    {
      const dvec3 motion = MouthMotion(mesh, info, p, pose) + BrowMotion(mesh, p, pose);
      const double jaw = JawWeight(mesh, info, p, angle);
      const dvec3 opened = RotateX(p, pivot, pose.JawAngle);
      p = p + jaw * (opened - p) + motion;
    }
    out[v] = p;
  }

  // Mouth bag: rings hang from the slit loop, following its motion with decreasing
  // strength; the lower half rides on the jaw.
  const double depth[MouthBagRings + 2] = { 0.0, 0.0025, 0.007, 0.016, 0.027, 0.035, 0.040 };
  const double height[MouthBagRings + 2] = { 0.0, 0.0025, 0.011, 0.016, 0.014, 0.007, 0.0 };
  const double widthScale[MouthBagRings + 2] = { 1.0, 0.98, 1.02, 1.05, 0.85, 0.45, 0.0 };
  const double follow[MouthBagRings + 2] = { 1.0, 0.95, 0.7, 0.4, 0.2, 0.1, 0.0 };
  const dvec3 mouthCenter(0.0, mesh.MouthY, FrontZ(mesh.MouthY));
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = mesh.Info[v];
    if (info.Kind != Part::MouthBag)
    {
      continue;
    }
    const int ring = info.Ring;
    if (info.Loop < 0) // apex
    {
      const dvec3 q0 = mouthCenter + dvec3(0.0, 0.0, -depth[ring] - 0.01);
      out[v] = q0 + 0.5 * (RotateX(q0, pivot, pose.JawAngle) - q0);
      continue;
    }
    const int loopVertex = mesh.MouthLoop[info.Loop];
    const dvec3 l0 = neutralSkin[loopVertex];
    const dvec3 l = out[loopVertex];
    const double s = Clamp01(std::abs(l0.x) / MouthCornerX);
    const double sideSign =
      info.Which == Side::Upper ? 1.0 : (info.Which == Side::Lower ? -1.0 : 0.0);
    const dvec3 q0 = dvec3(l0.x * widthScale[ring], mesh.MouthY + sideSign * height[ring] * std::sqrt(1.0 - s * s),
      l0.z - depth[ring]);
    const double jaw = info.Which == Side::Lower ? 1.0 : (info.Which == Side::Upper ? 0.0 : 0.5);
    const dvec3 jawMoved = q0 + jaw * (RotateX(q0, pivot, pose.JawAngle) - q0);
    const dvec3 loopJaw = l0 + jaw * (RotateX(l0, pivot, pose.JawAngle) - l0);
    out[v] = jawMoved + follow[ring] * (l - loopJaw);
  }

  // Teeth: arcs following the dental arch, the lower set on the jaw.
  const double lipFront = FrontZ(mesh.MouthY) + 0.0065;
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = mesh.Info[v];
    if (info.Kind != Part::UpperTeeth && info.Kind != Part::LowerTeeth)
    {
      continue;
    }
    const bool upperTeeth = info.Kind == Part::UpperTeeth;
    const double u = info.Local.x * 2.0 - 1.0; // -1..1 along the arch
    const int corner = static_cast<int>(info.Local.y);
    const double archAngle = u * 1.05;
    const double archRadius = 0.021;
    const double frontZ = lipFront - 0.0135 - (upperTeeth ? 0.0 : 0.0015);
    const bool back = corner == 2 || corner == 3;
    const bool top = corner == 0 || corner == 3;
    const double r = archRadius - (back ? 0.006 : 0.0);
    dvec3 q(r * std::sin(archAngle), 0.0, frontZ - archRadius + r * std::cos(archAngle));
    if (upperTeeth)
    {
      q.y = mesh.MouthY + (top ? 0.009 : -0.0012);
    }
    else
    {
      q.y = mesh.MouthY + (top ? -0.0008 : -0.010);
    }
    if (!upperTeeth)
    {
      q = RotateX(q, pivot, pose.JawAngle);
    }
    out[v] = q;
  }

  // Lid margins: the slit vertex pulled toward the eye centre, onto spheres just outside
  // and inside the eyeball, so they follow the lids in every pose.
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = mesh.Info[v];
    if (info.Kind != Part::LidMargin)
    {
      continue;
    }
    const dvec3 center = EyeCenter(mesh, info.Eye);
    const dvec3 edge = out[info.Loop];
    const double radius = info.Ring == 1 ? EyeballRadius + 0.3 * LidOffset : 0.8 * EyeballRadius;
    const double distance = glm::length(edge - center);
    out[v] = distance > radius ? center + (edge - center) * (radius / distance) : edge;
  }

  // Eyeballs.
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = mesh.Info[v];
    if (info.Kind != Part::Eyeball)
    {
      continue;
    }
    const dvec3 center = EyeCenter(mesh, info.Eye);
    const double theta = info.Local.x; // from the front pole
    const double phi = info.Local.y;
    out[v] = center +
      EyeballRadius * dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  }

  for (auto& p : out)
  {
    p *= FinalScale;
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------
float Quantize(double value, double step)
{
  return static_cast<float>(std::round(value / step) * step);
}

std::vector<float> QuantizePositions(const std::vector<dvec3>& positions)
{
  std::vector<float> out;
  out.reserve(positions.size() * 3);
  for (const dvec3& p : positions)
  {
    for (int k = 0; k < 3; ++k)
    {
      out.push_back(Quantize(p[k], 1e-6));
    }
  }
  return out;
}

/// Area-weighted vertex normals of float positions, rounded to 1e-5.
std::vector<float> ComputeNormals(const std::vector<float>& positions, const std::vector<uint32_t>& triangles)
{
  const size_t n = positions.size() / 3;
  std::vector<dvec3> sum(n, dvec3(0.0));
  auto at = [&](uint32_t i) {
    return dvec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
  };
  for (size_t t = 0; t < triangles.size(); t += 3)
  {
    const uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    const dvec3 normal = glm::cross(at(b) - at(a), at(c) - at(a));
    sum[a] += normal;
    sum[b] += normal;
    sum[c] += normal;
  }
  std::vector<float> out;
  out.reserve(n * 3);
  for (const dvec3& s : sum)
  {
    const double len = glm::length(s);
    const dvec3 unit = len > 0.0 ? s / len : dvec3(0.0, 0.0, 1.0);
    for (int k = 0; k < 3; ++k)
    {
      out.push_back(Quantize(unit[k], 1e-5));
    }
  }
  return out;
}

struct BinaryBuilder
{
  std::vector<uint8_t> Bytes;
  nlohmann::ordered_json BufferViews = nlohmann::ordered_json::array();
  nlohmann::ordered_json Accessors = nlohmann::ordered_json::array();

  int AddView(const void* data, size_t size, int target)
  {
    while (this->Bytes.size() % 4 != 0)
    {
      this->Bytes.push_back(0);
    }
    const size_t offset = this->Bytes.size();
    const auto* bytes = static_cast<const uint8_t*>(data);
    this->Bytes.insert(this->Bytes.end(), bytes, bytes + size);
    nlohmann::ordered_json view;
    view["buffer"] = 0;
    view["byteOffset"] = offset;
    view["byteLength"] = size;
    view["target"] = target;
    this->BufferViews.push_back(view);
    return static_cast<int>(this->BufferViews.size()) - 1;
  }

  int AddVec3(const std::vector<float>& values, bool withBounds)
  {
    const int view = this->AddView(values.data(), values.size() * sizeof(float), 34962);
    nlohmann::ordered_json accessor;
    accessor["bufferView"] = view;
    accessor["byteOffset"] = 0;
    accessor["componentType"] = 5126;
    accessor["count"] = values.size() / 3;
    accessor["type"] = "VEC3";
    if (withBounds)
    {
      std::array<float, 3> lo{ values[0], values[1], values[2] };
      std::array<float, 3> hi = lo;
      for (size_t i = 0; i < values.size(); ++i)
      {
        lo[i % 3] = std::min(lo[i % 3], values[i]);
        hi[i % 3] = std::max(hi[i % 3], values[i]);
      }
      accessor["min"] = { lo[0], lo[1], lo[2] };
      accessor["max"] = { hi[0], hi[1], hi[2] };
    }
    this->Accessors.push_back(accessor);
    return static_cast<int>(this->Accessors.size()) - 1;
  }

  int AddIndices(const std::vector<uint32_t>& indices, uint32_t maxIndex)
  {
    const int view = this->AddView(indices.data(), indices.size() * sizeof(uint32_t), 34963);
    nlohmann::ordered_json accessor;
    accessor["bufferView"] = view;
    accessor["byteOffset"] = 0;
    accessor["componentType"] = 5125;
    accessor["count"] = indices.size();
    accessor["type"] = "SCALAR";
    accessor["min"] = { 0 };
    accessor["max"] = { maxIndex };
    this->Accessors.push_back(accessor);
    return static_cast<int>(this->Accessors.size()) - 1;
  }
};

void AppendU32(std::vector<uint8_t>& out, uint32_t value)
{
  for (int k = 0; k < 4; ++k)
  {
    out.push_back(static_cast<uint8_t>((value >> (8 * k)) & 0xFF)); // glTF is little-endian
  }
}

std::vector<uint8_t> ToGlb(const std::string& json, const std::vector<uint8_t>& bin)
{
  std::string jsonChunk = json;
  while (jsonChunk.size() % 4 != 0)
  {
    jsonChunk.push_back(' ');
  }
  std::vector<uint8_t> binChunk = bin;
  while (binChunk.size() % 4 != 0)
  {
    binChunk.push_back(0);
  }
  std::vector<uint8_t> out;
  AppendU32(out, 0x46546C67); // "glTF"
  AppendU32(out, 2);
  AppendU32(out, static_cast<uint32_t>(12 + 8 + jsonChunk.size() + 8 + binChunk.size()));
  AppendU32(out, static_cast<uint32_t>(jsonChunk.size()));
  AppendU32(out, 0x4E4F534A); // "JSON"
  out.insert(out.end(), jsonChunk.begin(), jsonChunk.end());
  AppendU32(out, static_cast<uint32_t>(binChunk.size()));
  AppendU32(out, 0x004E4942); // "BIN\0"
  out.insert(out.end(), binChunk.begin(), binChunk.end());
  return out;
}

/// Makes every skin and bag triangle face its proper side: skin outward, the mouth bag
/// toward the inside of the mouth. Decided once from the neutral and applied to the
/// topology, so that the orientation cannot depend on construction details.
void OrientTriangles(Mesh& mesh, const std::vector<dvec3>& neutral)
{
  const dvec3 mouthInside = dvec3(0.0, mesh.MouthY, FrontZ(mesh.MouthY) - 0.02) * FinalScale;
  for (size_t t = 0; t < mesh.Triangles.size(); t += 3)
  {
    const uint32_t a = mesh.Triangles[t], b = mesh.Triangles[t + 1], c = mesh.Triangles[t + 2];
    const dvec3 centroid = (neutral[a] + neutral[b] + neutral[c]) / 3.0;
    const dvec3 normal = glm::cross(neutral[b] - neutral[a], neutral[c] - neutral[a]);
    if (glm::length(normal) == 0.0)
    {
      continue;
    }
    const Part kind = mesh.Info[a].Kind;
    const Part kindB = mesh.Info[b].Kind;
    const Part kindC = mesh.Info[c].Kind;
    bool flip = false;
    if (kind == Part::MouthBag || kindB == Part::MouthBag || kindC == Part::MouthBag)
    {
      flip = glm::dot(normal, mouthInside - centroid) < 0.0;
    }
    else if (kind == Part::UpperTeeth || kind == Part::LowerTeeth)
    {
      // Outward from the cross-section's centre; caps point along the arch.
      auto sectionCenter = [&](int firstVertex) {
        dvec3 c(0.0);
        for (int k = 0; k < 4; ++k)
        {
          c += neutral[firstVertex + k];
        }
        return c / 4.0;
      };
      const int section = mesh.Info[a].Column;
      const dvec3 center = sectionCenter(section);
      dvec3 outward = centroid - center;
      const bool cap = mesh.Info[b].Column == section && mesh.Info[c].Column == section;
      if (cap)
      {
        const bool firstSection = mesh.Info[a].Local.x == 0.0;
        outward = firstSection ? center - sectionCenter(section + 4) : center - sectionCenter(section - 4);
      }
      flip = glm::dot(normal, outward) < 0.0;
    }
    else if (kind == Part::LidMargin || kindB == Part::LidMargin || kindC == Part::LidMargin)
    {
      // Faces forward, out of the socket.
      flip = normal.z < 0.0;
    }
    else if (kind == Part::Eyeball)
    {
      flip = glm::dot(normal, centroid - EyeCenter(mesh, mesh.Info[a].Eye) * FinalScale) < 0.0;
    }
    if (flip)
    {
      std::swap(mesh.Triangles[t + 1], mesh.Triangles[t + 2]);
    }
  }
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: GenerateDefaultFace <output.glb>\n";
    return 2;
  }
  Mesh mesh = BuildTopology();
  const std::vector<Target> targets = Targets();
  const std::vector<dvec3> neutralExact = BuildPositions(mesh, Pose());
  OrientTriangles(mesh, neutralExact);

  const std::vector<float> neutral = QuantizePositions(neutralExact);
  const std::vector<float> neutralNormals = ComputeNormals(neutral, mesh.Triangles);
  const size_t numValues = neutral.size();

  BinaryBuilder bin;
  uint32_t maxIndex = 0;
  for (uint32_t i : mesh.Triangles)
  {
    maxIndex = std::max(maxIndex, i);
  }
  const int indices = bin.AddIndices(mesh.Triangles, maxIndex);
  const int position = bin.AddVec3(neutral, true);
  const int normal = bin.AddVec3(neutralNormals, false);

  nlohmann::ordered_json targetAccessors = nlohmann::ordered_json::array();
  nlohmann::ordered_json targetNames = nlohmann::ordered_json::array();
  std::vector<double> distMorph;
  for (const Target& target : targets)
  {
    const std::vector<float> shape = QuantizePositions(BuildPositions(mesh, target.Shape));
    const std::vector<float> shapeNormals = ComputeNormals(shape, mesh.Triangles);
    std::vector<float> deltaPositions(numValues), deltaNormals(numValues);
    double sum = 0.0;
    for (size_t i = 0; i < numValues; ++i)
    {
      deltaPositions[i] = shape[i] - neutral[i];
      deltaNormals[i] = shapeNormals[i] - neutralNormals[i];
    }
    for (size_t i = 0; i < numValues; i += 3)
    {
      sum += std::sqrt(double(deltaPositions[i]) * deltaPositions[i] +
        double(deltaPositions[i + 1]) * deltaPositions[i + 1] +
        double(deltaPositions[i + 2]) * deltaPositions[i + 2]);
    }
    distMorph.push_back(sum);
    nlohmann::ordered_json attributes;
    attributes["POSITION"] = bin.AddVec3(deltaPositions, true);
    attributes["NORMAL"] = bin.AddVec3(deltaNormals, false);
    targetAccessors.push_back(attributes);
    targetNames.push_back(target.Name);
  }

  nlohmann::ordered_json gltf;
  gltf["asset"] = { { "version", "2.0" },
    { "generator", "MorphNode GenerateDefaultFace (Data/DefaultFace/generator)" } };
  gltf["scene"] = 0;
  gltf["scenes"] = nlohmann::ordered_json::array({ { { "name", "DefaultFace" }, { "nodes", { 0 } } } });
  gltf["nodes"] = nlohmann::ordered_json::array({ { { "name", "DefaultFace" }, { "mesh", 0 } } });
  nlohmann::ordered_json primitive;
  primitive["attributes"] = { { "POSITION", position }, { "NORMAL", normal } };
  primitive["indices"] = indices;
  primitive["mode"] = 4;
  primitive["targets"] = targetAccessors;
  nlohmann::ordered_json meshJson;
  meshJson["name"] = "DefaultFace";
  meshJson["primitives"] = nlohmann::ordered_json::array({ primitive });
  meshJson["weights"] = std::vector<double>(targets.size(), 0.0);
  meshJson["extras"] = { { "targetNames", targetNames } };
  gltf["meshes"] = nlohmann::ordered_json::array({ meshJson });
  gltf["accessors"] = bin.Accessors;
  gltf["bufferViews"] = bin.BufferViews;
  gltf["buffers"] = nlohmann::ordered_json::array({ { { "byteLength", bin.Bytes.size() } } });

  const std::vector<uint8_t> glb = ToGlb(gltf.dump(), bin.Bytes);
  std::ofstream out(argv[1], std::ios::binary);
  if (!out)
  {
    std::cerr << "GenerateDefaultFace: cannot write '" << argv[1] << "'\n";
    return 1;
  }
  out.write(reinterpret_cast<const char*>(glb.data()), static_cast<std::streamsize>(glb.size()));
  if (!out)
  {
    std::cerr << "GenerateDefaultFace: write to '" << argv[1] << "' failed\n";
    return 1;
  }

  std::printf("%s: %zu vertices, %zu triangles, %zu targets, %zu bytes\n", argv[1],
    neutral.size() / 3, mesh.Triangles.size() / 3, targets.size(), glb.size());
  const double maxDist = *std::max_element(distMorph.begin(), distMorph.end());
  std::printf("%-12s %12s %9s\n", "target", "dist_morph", "dist_norm");
  std::printf("%-12s %12.6f %9.2f\n", "Neutral", 0.0, 0.0);
  for (size_t t = 0; t < targets.size(); ++t)
  {
    std::printf("%-12s %12.6f %9.2f\n", targets[t].Name, distMorph[t], distMorph[t] / maxDist);
  }
  return 0;
}
