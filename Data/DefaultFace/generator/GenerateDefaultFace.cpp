// SPDX-License-Identifier: BSD-3-Clause
// GenerateDefaultFace: builds MorphNode's own default head and writes it as one glTF 2.0
// binary (GLB): a scene of parts (head skin, mouth interior, upper and lower teeth, tongue,
// two eyes, eyelashes, brows, hair, ears), each part that moves carrying the morph targets
// of Berner's Table 1 under the same names. docs/default-face.md describes the result.
//
//   GenerateDefaultFace <output.glb>     (prints the parts, their counts and dist_norm)
//
// The head skin is procedural: a "generalized cylinder" of horizontal cross-sections whose
// rows are spaced by arc length along the front profile (denser over the face), displaced
// by analytic features (nose, eye sockets, brows, cheekbones, lips, chin) and pulled in under
// the jaw to the neck; the ears are their own part, set into its sides. The mouth
// and the eyes are slits: the grid row at the lip line (and at each eye) has duplicated
// vertices, one copy for the skin above and one for the skin below, so that lips and lids
// separate. Behind the lips, two rings of inner lip lead into the dark mouth interior (its
// own part); behind the lids, lid margins lead to the eyeballs (their own parts, one node
// each, centred on the eyeball, rotated for gaze). Lips, lid rims and cheeks are tinted by
// COLOR_0 (a multiplier of the skin's base colour, as glTF defines it).
//
// Every pose (neutral and each target) is computed by one function from a few pose
// parameters (jaw angle, lip motions, lid closure, brow motions, tongue tip), so targets
// are consistent across parts: the lower teeth, the tongue and the mouth interior follow
// the jaw, lashes follow the lids, brows and hair follow the forehead. Deltas are
// pose - neutral; a part that a target does not move lacks that target.
//
// Output is deterministic: positions are rounded to 1 micrometre and normals to 1e-5
// before writing, the JSON is written in a fixed key order, and nothing depends on time
// or the environment. A test regenerates the file and compares it byte for byte.
//
// Conventions: metres, +Y up, the face looks along +Z (the character's left is +X), the
// head is about 0.2 m from chin to crown.

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
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

double Mix(double a, double b, double t)
{
  return a + (b - a) * t;
}

/// sign(v) |v|^e: squares a circle into a rounded box for e < 1.
double SignedPow(double v, double e)
{
  return (v < 0.0 ? -1.0 : 1.0) * std::pow(std::abs(v), e);
}

/// Interpolating cubic through (x_i, y_i) with finite-difference tangents (Catmull-Rom on
/// non-uniform knots); clamped outside the knots. Knots may be given in either order.
class Curve
{
public:
  Curve(std::initializer_list<dvec2> knots)
    : Knots(knots)
  {
    std::sort(this->Knots.begin(), this->Knots.end(),
      [](const dvec2& a, const dvec2& b) { return a.x < b.x; });
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
    return (2 * t3 - 3 * t2 + 1) * k[i].y + (t3 - 2 * t2 + t) * m0 +
      (-2 * t3 + 3 * t2) * k[i + 1].y + (t3 - t2) * m1;
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

dvec3 Normalized(const dvec3& v)
{
  const double len = glm::length(v);
  return len > 0.0 ? v / len : dvec3(0.0, 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------
// Design constants (before the final scale)
// ---------------------------------------------------------------------------------------
constexpr int Columns = 104; // around the head
constexpr int Rows = 92;     // neck bottom to just below the crown
constexpr double NeckBottom = -0.170;
constexpr double Crown = 0.135;
constexpr double FinalScale = 0.88; // chin to crown about 0.205 m
constexpr double MouthY = -0.056;   // the lip line
constexpr double EyeY = 0.018;      // the eye slits
constexpr double MouthCornerX = 0.025;
constexpr double EyeCenterX = 0.0345;
constexpr double EyeHalfWidth = 0.0150; // eye corners at EyeCenterX -/+ this
constexpr double EyeballRadius = 0.0125;
constexpr double LidOffset = 0.0016; // lid skin above the eyeball
constexpr int InnerLipRings = 2;
constexpr int MouthBagRings = 4;

// Side view: front (z of the base head before features), back, and half width, by height y.
const Curve FrontZ{ { -0.170, 0.040 }, { -0.130, 0.046 }, { -0.115, 0.052 }, { -0.106, 0.068 },
  { -0.099, 0.083 }, { -0.088, 0.093 }, { -0.070, 0.097 }, { -0.050, 0.100 }, { -0.030, 0.101 },
  { -0.005, 0.098 }, { 0.020, 0.093 }, { 0.040, 0.096 }, { 0.070, 0.090 }, { 0.095, 0.074 },
  { 0.115, 0.050 }, { 0.128, 0.025 }, { 0.135, -0.010 } };
const Curve BackZ{ { -0.170, -0.050 }, { -0.110, -0.053 }, { -0.070, -0.070 }, { -0.030, -0.098 },
  { 0.020, -0.110 }, { 0.070, -0.104 }, { 0.100, -0.085 }, { 0.120, -0.058 }, { 0.130, -0.035 },
  { 0.135, -0.010 } };
const Curve HalfWidth{ { -0.170, 0.051 }, { -0.120, 0.0515 }, { -0.100, 0.054 }, { -0.080, 0.060 },
  { -0.050, 0.0665 }, { -0.020, 0.0725 }, { 0.020, 0.0765 }, { 0.060, 0.0770 }, { 0.090, 0.0705 },
  { 0.112, 0.053 }, { 0.126, 0.031 }, { 0.135, 0.000 } };

// Nose: the midline profile (absolute z) from between the brows to the base of the nose,
// and the half width of its ridge, by y.
const Curve NoseProfile{ { 0.030, 0.0920 }, { 0.020, 0.0935 }, { 0.010, 0.0972 }, { 0.000, 0.1018 },
  { -0.010, 0.1068 }, { -0.018, 0.1118 }, { -0.024, 0.1160 }, { -0.028, 0.1172 },
  { -0.031, 0.1150 }, { -0.034, 0.1090 }, { -0.036, 0.1030 }, { -0.038, 0.0990 } };
const Curve NoseWidth{ { 0.030, 0.0075 }, { 0.018, 0.0078 }, { 0.005, 0.0082 }, { -0.010, 0.0092 },
  { -0.020, 0.0108 }, { -0.026, 0.0118 }, { -0.032, 0.0112 }, { -0.038, 0.0095 } };
// The lower jaw's border: its height by column angle (0 the chin, then along the jaw to
// its angle below the ear).
const Curve JawLine{ { 0.0, -0.107 }, { 0.4, -0.103 }, { 0.7, -0.095 }, { 1.0, -0.086 },
  { 1.3, -0.079 }, { 1.6, -0.075 }, { 1.9, -0.073 } };

// ---------------------------------------------------------------------------------------
// Pose: what a target changes. The neutral is the all-zero pose.
// ---------------------------------------------------------------------------------------
struct Pose
{
  double JawAngle = 0.0;      // radians, opens the mouth
  double UpperLipRaise = 0.0; // m, centre of the upper lip up
  double LowerLipDrop = 0.0;  // m, centre of the lower lip down beyond the jaw (negative: less far)
  double LowerLipTuck = 0.0;  // m, lower lip up and back under the upper teeth (F)
  double Pucker = 0.0;        // 0..1, lips narrow and push forward (O)
  dvec3 CornerMove{ 0.0 };    // m, mouth corners: x outward, y up, z forward
  double CheekRaise = 0.0;    // m
  double ChinRaise = 0.0;     // m, lower lip and chin pushed up (sad)
  double LidClose = 0.0;      // 0..1, upper lids down to the lower lids
  double BrowInnerUp = 0.0;   // m
  double BrowOuterUp = 0.0;   // m
  double BrowSqueeze = 0.0;   // m, brows toward the midline
  double BrowForward = 0.0;   // m
  double TongueTipUp = 0.0;   // m, tongue tip raised toward the upper teeth (L)
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
  p.LowerLipDrop = 0.0008;
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

  p = Pose(); // open, relaxed lips, tongue tip up behind the upper teeth
  p.JawAngle = 0.14;
  p.UpperLipRaise = 0.0015;
  p.LowerLipDrop = -0.0008;
  p.TongueTipUp = 1.0;
  targets.push_back({ "L", p });

  p = Pose(); // wide, slightly open
  p.JawAngle = 0.10;
  p.UpperLipRaise = 0.0025;
  p.LowerLipDrop = -0.0002;
  p.CornerMove = dvec3(0.0065, 0.0012, -0.002);
  p.CheekRaise = 0.0015;
  targets.push_back({ "E", p });

  p = Pose(); // jaw and lips open wide
  p.JawAngle = 0.26;
  p.UpperLipRaise = 0.003;
  p.LowerLipDrop = -0.002;
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
  p.LowerLipDrop = -0.0015;
  targets.push_back({ "O", p });
  return targets;
}

// ---------------------------------------------------------------------------------------
// A part of the scene: vertices, triangles grouped into primitives (one material each),
// and the function that places the vertices in a pose.
// ---------------------------------------------------------------------------------------
enum Material : int
{
  MatSkin,
  MatMouth,
  MatTeeth,
  MatTongue,
  MatSclera,
  MatIris,
  MatPupil,
  MatLashes,
  MatBrows,
  MatHair,
  MaterialCount
};

struct Primitive
{
  int Material = MatSkin;
  std::vector<uint32_t> Triangles; // indices into the part's vertices
};

struct Part
{
  std::string Name;
  size_t VertexCount = 0;
  std::vector<Primitive> Primitives;
  std::vector<dvec3> Colors; // COLOR_0 per vertex (multiplier of the base colour), or empty
  bool Rigid = false;        // no targets (the eyes: rotated for gaze instead)
  dvec3 Translation{ 0.0 };  // node translation (design units); vertices are relative to it
};

void AddTriangle(std::vector<uint32_t>& triangles, int a, int b, int c)
{
  triangles.push_back(static_cast<uint32_t>(a));
  triangles.push_back(static_cast<uint32_t>(b));
  triangles.push_back(static_cast<uint32_t>(c));
}

void AddQuad(std::vector<uint32_t>& triangles, int a, int b, int c, int d)
{
  AddTriangle(triangles, a, b, c);
  AddTriangle(triangles, a, c, d);
}

/// Flips the triangles that do not face away from `inside(centroid)` (for convex shapes).
void OrientOutward(std::vector<uint32_t>& triangles, const std::vector<dvec3>& p,
  const std::function<dvec3(const dvec3&)>& inside)
{
  for (size_t t = 0; t < triangles.size(); t += 3)
  {
    const dvec3& a = p[triangles[t]];
    const dvec3& b = p[triangles[t + 1]];
    const dvec3& c = p[triangles[t + 2]];
    const dvec3 centroid = (a + b + c) / 3.0;
    const dvec3 normal = glm::cross(b - a, c - a);
    if (glm::dot(normal, centroid - inside(centroid)) < 0.0)
    {
      std::swap(triangles[t + 1], triangles[t + 2]);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Head skin: topology
// ---------------------------------------------------------------------------------------
enum class Side : uint8_t
{
  None,  // ordinary skin
  Upper, // belongs to the skin above a slit (upper lip, upper lid)
  Lower  // belongs to the skin below a slit
};

enum class Kind : uint8_t
{
  Skin,
  LidMargin, // rings from an eye slit toward the eyeball: the lids' thickness
  InnerLip   // rings from the lip line into the mouth: the inside of the lips
};

struct VertexInfo
{
  Kind Type = Kind::Skin;
  Side Which = Side::None;
  bool MouthSlit = false;
  int Row = 0;    // skin grid row (the crown and neck centres use Rows and -1)
  int Column = 0; // skin grid column
  int Ring = 0;   // lid margin / inner lip ring
  int Loop = -1;  // lid margin / inner lip: the slit vertex it hangs from
  int Eye = 0;    // -1 right (x < 0), +1 left
};

struct Head
{
  std::vector<VertexInfo> Info;
  std::vector<uint32_t> Triangles;
  std::vector<double> RowY; // height of each skin row
  std::vector<double> ColumnAngle;
  int MouthRow = 0;
  int EyeRow = 0;
  std::vector<std::vector<int>> SkinIndex;         // [row][column] -> vertex (Side None/Lower)
  std::vector<std::vector<int>> SkinUpperIndex;    // [row][column] -> upper copy or -1
  std::vector<int> MouthLoop;                      // corner, upper copies, corner, lower copies
  std::vector<int> InnerLipLoop;                   // the innermost inner-lip ring (same order)
  std::array<std::vector<int>, 2> EyeLoops;        // right, left eye slit loops
  std::array<std::vector<int>, 2> UpperLidColumns; // columns of each eye's upper lid edge
};

int AddVertex(Head& head, const VertexInfo& info)
{
  head.Info.push_back(info);
  return static_cast<int>(head.Info.size()) - 1;
}

/// A slit's boundary as a closed loop: left corner, upper copies left to right, right
/// corner, lower copies right to left (columns grow toward +X).
std::vector<int> SlitLoop(const Head& head, int row, const std::vector<int>& slitColumns)
{
  std::vector<int> loop{ head.SkinIndex[row][slitColumns.front() - 1] };
  for (int c : slitColumns)
  {
    loop.push_back(head.SkinUpperIndex[row][c]);
  }
  loop.push_back(head.SkinIndex[row][slitColumns.back() + 1]);
  for (auto it = slitColumns.rbegin(); it != slitColumns.rend(); ++it)
  {
    loop.push_back(head.SkinIndex[row][*it]);
  }
  return loop;
}

/// Exponent of the cross-sections' front half: 2 is an ellipse, more is a flatter face.
double Squareness(double y)
{
  return 2.0 + 0.5 * SmoothStep(-0.115, -0.085, y) * SmoothStep(0.090, 0.050, y);
}

/// Base head point (no features) at a row height and column angle: a cross-section that is
/// an ellipse behind and a flatter superellipse in front, pulled in under the jaw to the neck.
dvec3 BaseHead(double y, double angle)
{
  auto section = [angle](double height, double yOut)
  {
    const double front = FrontZ(height);
    const double back = BackZ(height);
    const double mid = 0.5 * (front + back);
    const double c = std::cos(angle);
    const double s = std::sin(angle);
    if (c < 0.0)
    {
      return dvec3(HalfWidth(height) * s, yOut, mid + (mid - back) * c);
    }
    const double e = 2.0 / Squareness(height);
    // The lower face narrows toward the chin in front.
    const double taper = 1.0 - 0.20 * SmoothStep(-0.060, -0.100, height) * c * c;
    return dvec3(
      HalfWidth(height) * taper * SignedPow(s, e), yOut, mid + (front - mid) * std::pow(c, e));
  };
  dvec3 p = section(y, y);
  // Below the jaw's border the skin runs in to the neck.
  const double under = SmoothStep(0.0, 0.020, JawLine(std::abs(angle)) - y) *
    SmoothStep(2.1, 1.8, std::abs(angle)) * SmoothStep(-0.150, -0.120, y);
  if (under > 0.0)
  {
    const dvec3 neck = section(-0.135, y);
    p = p + (neck - p) * (0.65 * under);
  }
  return p;
}

/// The column angle whose base head point has this x at height y (front half).
double AngleAt(double x, double y)
{
  // The chin's taper does not reach the eyes and brows, where this is used.
  const double s = std::max(-1.0, std::min(1.0, x / HalfWidth(y)));
  return std::asin(SignedPow(s, Squareness(y) / 2.0));
}

dvec3 Features(const dvec3& p, double angle);

/// Rows spaced by arc length of the front profile (with its features), weighted to be
/// denser over the face, with one row exactly at the lip line and one at the eyes.
std::vector<double> SampleRows()
{
  const int dense = 8000;
  std::vector<double> ys(dense + 1), length(dense + 1, 0.0);
  auto profile = [](double y)
  {
    const dvec3 p = BaseHead(y, 0.0);
    return p.z + Features(p, 0.0).z;
  };
  for (int k = 0; k <= dense; ++k)
  {
    ys[k] = NeckBottom + (Crown - NeckBottom) * k / dense;
  }
  double previousZ = profile(ys[0]);
  for (int k = 1; k <= dense; ++k)
  {
    const double z = profile(ys[k]);
    const double dy = ys[k] - ys[k - 1];
    const double dz = z - previousZ;
    previousZ = z;
    const double y = 0.5 * (ys[k] + ys[k - 1]);
    // Three times denser from the chin to the brows, where the features are.
    const double density = 1.0 + 2.0 * SmoothStep(-0.125, -0.105, y) * SmoothStep(0.075, 0.055, y);
    length[k] = length[k - 1] + std::sqrt(dy * dy + dz * dz) * density;
  }
  auto lengthAt = [&](double y)
  {
    const double f = (y - NeckBottom) / (Crown - NeckBottom) * dense;
    const int k = std::min(dense - 1, static_cast<int>(f));
    return length[k] + (f - k) * (length[k + 1] - length[k]);
  };
  auto heightAt = [&](double target)
  {
    int k = 0;
    while (k < dense - 1 && length[k + 1] < target)
    {
      ++k;
    }
    const double t = (target - length[k]) / std::max(1e-12, length[k + 1] - length[k]);
    return ys[k] + t * (ys[k + 1] - ys[k]);
  };
  const double total = length[dense];
  const double mouth = lengthAt(MouthY);
  const double eye = lengthAt(EyeY);
  const int mouthRow = static_cast<int>(std::lround(Rows * mouth / total));
  const int eyeRow = static_cast<int>(std::lround(Rows * eye / total));
  std::vector<double> rows(Rows);
  for (int r = 0; r < Rows; ++r)
  {
    double target;
    if (r <= mouthRow)
    {
      target = mouth * r / mouthRow;
    }
    else if (r <= eyeRow)
    {
      target = mouth + (eye - mouth) * (r - mouthRow) / (eyeRow - mouthRow);
    }
    else
    {
      // The last row stays below the crown: the crown itself is one centre vertex.
      target = eye + (total - eye) * (r - eyeRow) / (Rows - eyeRow);
    }
    rows[r] = heightAt(target);
  }
  rows[mouthRow] = MouthY;
  rows[eyeRow] = EyeY;
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

bool InMouthSlit(double angle)
{
  const dvec3 p = BaseHead(MouthY, angle);
  return std::cos(angle) > 0.0 && std::abs(p.x) < MouthCornerX;
}

/// -1/+1 when the column is strictly inside an eye's slit, 0 otherwise.
int InEyeSlit(double angle)
{
  const dvec3 p = BaseHead(EyeY, angle);
  if (std::cos(angle) <= 0.0)
  {
    return 0;
  }
  if (std::abs(std::abs(p.x) - EyeCenterX) < EyeHalfWidth)
  {
    return p.x < 0.0 ? -1 : 1;
  }
  return 0;
}

Head BuildHeadTopology()
{
  Head head;
  head.RowY = SampleRows();
  head.ColumnAngle = SampleColumns();
  head.MouthRow = NearestRow(head.RowY, MouthY);
  head.EyeRow = NearestRow(head.RowY, EyeY);

  // Skin grid; slit rows get a second (upper) copy of the vertices inside a slit.
  head.SkinIndex.assign(Rows, std::vector<int>(Columns, -1));
  head.SkinUpperIndex.assign(Rows, std::vector<int>(Columns, -1));
  for (int r = 0; r < Rows; ++r)
  {
    for (int c = 0; c < Columns; ++c)
    {
      VertexInfo info;
      info.Row = r;
      info.Column = c;
      const bool mouth = r == head.MouthRow && InMouthSlit(head.ColumnAngle[c]);
      const int eye = r == head.EyeRow ? InEyeSlit(head.ColumnAngle[c]) : 0;
      info.Eye = eye;
      info.MouthSlit = mouth;
      if (mouth || eye != 0)
      {
        info.Which = Side::Lower;
        head.SkinIndex[r][c] = AddVertex(head, info);
        info.Which = Side::Upper;
        head.SkinUpperIndex[r][c] = AddVertex(head, info);
      }
      else
      {
        head.SkinIndex[r][c] = AddVertex(head, info);
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
        return head.SkinUpperIndex[r][col] >= 0 ? head.SkinUpperIndex[r][col]
                                                : head.SkinIndex[r][col];
      };
      // Counter-clockwise seen from outside: angle grows toward +X, rows grow upward.
      AddQuad(
        head.Triangles, below(c), below(c1), head.SkinIndex[r + 1][c1], head.SkinIndex[r + 1][c]);
    }
  }
  // Crown and neck caps.
  VertexInfo crown;
  crown.Row = Rows;
  const int crownIndex = AddVertex(head, crown);
  VertexInfo neck;
  neck.Row = -1;
  const int neckIndex = AddVertex(head, neck);
  for (int c = 0; c < Columns; ++c)
  {
    const int c1 = (c + 1) % Columns;
    AddTriangle(
      head.Triangles, head.SkinIndex[Rows - 1][c], head.SkinIndex[Rows - 1][c1], crownIndex);
    AddTriangle(head.Triangles, head.SkinIndex[0][c1], head.SkinIndex[0][c], neckIndex);
  }

  auto slitColumns = [&](int row, int eye)
  {
    std::vector<int> columns;
    for (int c = 0; c < Columns; ++c)
    {
      if (head.SkinUpperIndex[row][c] >= 0 && head.Info[head.SkinIndex[row][c]].Eye == eye)
      {
        columns.push_back(c);
      }
    }
    return columns;
  };

  // Rings hanging from a slit loop (lid margins, inner lips). Quads are oriented later.
  auto hangRings = [&](const std::vector<int>& loop, Kind kind, int rings, int eye)
  {
    std::vector<int> previous = loop;
    for (int ring = 1; ring <= rings; ++ring)
    {
      std::vector<int> current(loop.size());
      for (size_t k = 0; k < loop.size(); ++k)
      {
        VertexInfo info;
        info.Type = kind;
        info.Eye = eye;
        info.Ring = ring;
        info.Loop = loop[k];
        info.Which = head.Info[loop[k]].Which;
        current[k] = AddVertex(head, info);
      }
      for (size_t k = 0; k < loop.size(); ++k)
      {
        const size_t k1 = (k + 1) % loop.size();
        AddQuad(head.Triangles, previous[k], previous[k1], current[k1], current[k]);
      }
      previous = current;
    }
    return previous;
  };

  const std::vector<int> mouthColumns = slitColumns(head.MouthRow, 0);
  head.MouthLoop = SlitLoop(head, head.MouthRow, mouthColumns);
  head.InnerLipLoop = hangRings(head.MouthLoop, Kind::InnerLip, InnerLipRings, 0);
  for (int eye : { -1, 1 })
  {
    const std::vector<int> columns = slitColumns(head.EyeRow, eye);
    head.EyeLoops[eye < 0 ? 0 : 1] = SlitLoop(head, head.EyeRow, columns);
    head.UpperLidColumns[eye < 0 ? 0 : 1] = columns;
    hangRings(head.EyeLoops[eye < 0 ? 0 : 1], Kind::LidMargin, 2, eye);
  }
  return head;
}

// ---------------------------------------------------------------------------------------
// Head skin: geometry
// ---------------------------------------------------------------------------------------
dvec3 EyeCenter(int eye)
{
  const double x = eye * EyeCenterX;
  // The eyeball's front sits well behind the brow and cheek surface, as in a real face.
  const double frontZ = BaseHead(EyeY, AngleAt(x, EyeY)).z - 0.0050;
  return dvec3(x, EyeY, frontZ - EyeballRadius);
}

/// Heights of the upper and lower lip's red (vermilion) over and under the lip line.
void LipHeights(double ax, double& upper, double& lower)
{
  const double across = Clamp01(1.0 - std::pow(ax / (MouthCornerX + 0.003), 2.0));
  upper = 0.0030 + 0.0042 * across + 0.0009 * Bump(std::abs(ax - 0.0055) / 0.0065) -
    0.0005 * Bump(ax / 0.004);
  lower = 0.0045 + 0.0062 * std::pow(across, 0.8);
}

/// Smooth maximum of a and b, blending over k.
double SmoothMax(double a, double b, double k)
{
  const double h = Clamp01(0.5 + 0.5 * (a - b) / k);
  return b + (a - b) * h + k * h * (1.0 - h) * 0.5;
}

/// Static features: the neutral face's relief over the base head, as an offset along +Z
/// on the front (and along X for the ears).
dvec3 Features(const dvec3& p, double angle)
{
  const double front = SmoothStep(0.05, 0.45, std::cos(angle));
  const double x = p.x;
  const double y = p.y;
  const double ax = std::abs(x);
  double dz = 0.0;

  // Nose: a ridge following the profile, wings (alae) beside the tip, a crease around them.
  const double rise = std::max(0.0, NoseProfile(y) - FrontZ(y)) * SmoothStep(0.034, 0.026, y) *
    SmoothStep(-0.041, -0.037, y);
  const double ridge = ax / NoseWidth(y);
  double nose = rise * (ridge < 1.0 ? std::pow(1.0 - ridge * ridge, 1.6) : 0.0);
  const double wingR = std::hypot((ax - 0.0110) / 0.0064, (y + 0.0300) / 0.0062);
  nose = SmoothMax(nose, 0.0078 * Bump(wingR), 0.003);
  nose -= 0.0011 * Bump(std::abs(wingR - 1.05) / 0.22) * SmoothStep(-0.037, -0.030, y);
  dz += nose;
  // Eye sockets, brow ridge, brows, cheekbones, cheeks.
  const double eyeDx = ax - EyeCenterX;
  dz -= 0.010 * Bump(std::hypot(eyeDx / 0.026, (y - EyeY) / 0.019));
  dz += 0.004 * Bump(std::hypot(eyeDx / 0.032, (y - EyeY - 0.023) / 0.011));
  dz += 0.0020 * Bump(std::hypot(ax / 0.018, (y - EyeY - 0.024) / 0.010)); // glabella
  dz += 0.0036 * Bump(std::hypot((ax - 0.049) / 0.030, (y + 0.013) / 0.024));
  dz += 0.0015 * Bump(std::hypot((ax - 0.042) / 0.032, (y + 0.046) / 0.032));
  // Nasolabial fold: a soft crease from the nose wing toward the mouth corner.
  {
    const dvec2 a(0.0175, -0.030), b(0.0330, -0.064);
    const dvec2 q(ax, y);
    const double t = Clamp01(glm::dot(q - a, b - a) / glm::dot(b - a, b - a));
    const double d = glm::length(q - (a + (b - a) * t));
    dz -= 0.0008 * Bump(d / 0.0050) * std::sin(Pi * std::pow(t, 0.8));
  }
  // Lips: upper and lower vermilion bulges meeting at the lip line, philtrum, chin.
  const double dy = y - MouthY;
  const double across = Clamp01(1.0 - std::pow(ax / (MouthCornerX + 0.003), 2.0));
  double upperH, lowerH;
  LipHeights(ax, upperH, lowerH);
  if (dy >= 0.0)
  {
    dz += 0.0046 * across * Bump(std::abs(dy - 0.40 * upperH) / (0.75 * upperH));
    dz += 0.0006 * across * Bump(std::abs(dy - upperH) / 0.0014);            // the border's roll
    dz -= 0.0011 * Bump(ax / 0.0050) * Bump(std::abs(dy - 0.0135) / 0.0075); // philtrum
  }
  else
  {
    dz += 0.0060 * across * Bump(std::abs(dy + 0.45 * lowerH) / (0.75 * lowerH));
    dz -= 0.0020 * Bump(std::hypot(ax / 0.020, (dy + 0.0185) / 0.0065)); // below the lower lip
  }
  dz -= 0.0012 * Bump(std::abs(dy) / 0.0016) * across;               // lip line crease
  dz += 0.0090 * Bump(std::hypot(ax / 0.021, (y + 0.091) / 0.016));  // chin
  dz -= 0.0014 * Bump(std::hypot((ax - 0.032) / 0.008, dy / 0.012)); // mouth-corner hollow

  return dvec3(0.0, 0.0, dz * front);
}

/// Eye region: lids wrap the eyeball (a sphere slightly larger than it) and open by
/// sliding rows vertically. Returns the shaped point.
dvec3 ShapeEyeRegion(Side which, const dvec3& p, double lidClose)
{
  const int eye = p.x < 0.0 ? -1 : 1;
  const dvec3 center = EyeCenter(eye);
  const double s = (p.x - center.x) / EyeHalfWidth; // along the eye, -1..1 at the corners
  const double lateral = eye * s;                   // -1 inner corner, +1 outer corner
  const double dy = p.y - EyeY;
  const double region = Bump(std::hypot((p.x - center.x) / 0.026, dy / 0.018));
  if (region <= 0.0)
  {
    return p;
  }
  // Lid edges, as heights over the eye row: open upper and lower, and the closed line.
  // The upper lid's highest point is toward the nose, the lower lid's lowest toward the
  // ear, and the outer corner sits a little higher than the inner one.
  const double openness = std::pow(Clamp01(1.0 - s * s), 0.5);
  const double tilt = 0.0009 * s * eye;
  const double upperOpen = tilt + 0.0056 * openness * (1.0 - 0.16 * lateral);
  const double lowerOpen =
    tilt - 0.0052 * openness * (1.0 + 0.10 * lateral) * std::pow(Clamp01(1.0 - s * s), 0.15);
  const double upperEdge = upperOpen + lidClose * (lowerOpen - upperOpen);
  const double upperSpan = 0.014; // rows above the slit compress into this band
  const double lowerSpan = 0.012;
  double newDy = dy;
  if (which == Side::Upper || (which == Side::None && dy > 0.0))
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
  double z = under > 0.0 ? std::max(sphereZ, p.z + (sphereZ - p.z) * hug) : p.z;
  // The upper lid's crease, a few millimetres above its edge; it smooths out as the lid
  // closes and its skin is stretched.
  if (which != Side::Lower && dy > 0.0)
  {
    z -= 0.0008 * (1.0 - lidClose) * Bump(std::abs(dy - 0.0068) / 0.0030) * Clamp01(1.0 - s * s);
  }
  return dvec3(p.x, y, p.z + (z - p.z) * region);
}

/// Keeps skin out of the eyeballs (whatever the pose, and whichever way they look).
dvec3 OutsideEyeballs(const dvec3& p)
{
  for (int eye : { -1, 1 })
  {
    const dvec3 center = EyeCenter(eye);
    const dvec3 d = p - center;
    const double limit = EyeballRadius + 0.0006;
    const double distance = glm::length(d);
    if (d.z > 0.0 && distance < limit && distance > 0.0)
    {
      return center + d * (limit / distance);
    }
  }
  return p;
}

/// The jaw's share of a skin point's motion: 1 for the chin, 0 above the mouth; along the
/// lower lip it tapers to 0 at the corners, so the mouth opens as an oval.
double JawWeight(Side which, bool mouthSlit, const dvec3& p, double angle)
{
  const double dy = p.y - MouthY;
  const double ax = std::abs(p.x);
  const double beyond = std::max(0.0, ax - MouthCornerX);
  const bool above = mouthSlit ? which == Side::Upper : dy > 0.0;
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
  const double frontness = SmoothStep(-0.1, 0.45, std::cos(angle));
  return vertical * frontness;
}

dvec3 JawPivot()
{
  return dvec3(0.0, EyeY - 0.03, -0.005);
}

/// Lip, cheek and corner motions of a pose (not the jaw), for a skin point.
dvec3 MouthMotion(Side which, const dvec3& p, const Pose& pose)
{
  const double dy = p.y - MouthY;
  const double ax = std::abs(p.x);
  const double sign = p.x < 0.0 ? -1.0 : 1.0;
  const bool upper = which == Side::Upper || (which == Side::None && dy > 0.0);
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

dvec3 BrowMotion(const dvec3& p, const Pose& pose)
{
  const double ax = std::abs(p.x);
  const double sign = p.x < 0.0 ? -1.0 : 1.0;
  const double dy = p.y - (EyeY + 0.024);
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
  return w *
    dvec3(-sign * pose.BrowSqueeze * (0.4 + 0.6 * inner) * SmoothStep(0.0, 0.012, ax), up,
      pose.BrowForward * inner);
}

/// A skin point in a pose, from its place on the base head (height y, column angle).
/// `neutral` (optional) receives the point with the eye region shaped but no pose.
dvec3 SkinPoint(
  double y, double angle, Side which, bool mouthSlit, const Pose& pose, dvec3* neutral = nullptr)
{
  dvec3 p = BaseHead(y, angle);
  p += Features(p, angle);
  const double front = std::cos(angle);
  dvec3 rest = p;
  if (front > 0.0 && std::abs(std::abs(p.x) - EyeCenterX) < 0.034 && std::abs(p.y - EyeY) < 0.02)
  {
    rest = ShapeEyeRegion(which, p, 0.0);
    p = pose.LidClose != 0.0 ? ShapeEyeRegion(which, p, pose.LidClose) : rest;
  }
  if (neutral != nullptr)
  {
    *neutral = rest;
  }
  if (pose.JawAngle != 0.0)
  {
    // The jaw turns about its pivot. Below the jaw's border the skin is stretched down the
    // neck rather than pushed back into it, fading toward the neck's base; toward the ears
    // the backward part of the motion fades too, so the cheeks do not fold.
    const double border = JawLine(std::abs(angle));
    const double below = SmoothStep(0.0, 0.014, border - p.y);
    const double fade = SmoothStep(border - 0.060, border - 0.004, p.y);
    dvec3 d = RotateX(p, JawPivot(), pose.JawAngle) - p;
    d.z *= (1.0 - 0.5 * below) * (0.45 + 0.55 * SmoothStep(0.15, 0.7, front));
    p += JawWeight(which, mouthSlit, p, angle) * fade * d;
  }
  if (front > 0.0)
  {
    // (The eye slits' copies are ordinary skin for the mouth.)
    p += MouthMotion(mouthSlit ? which : Side::None, rest, pose) + BrowMotion(rest, pose);
    p = OutsideEyeballs(p);
  }
  return p;
}

/// Outward unit normal of the posed skin at (y, angle), by central differences.
dvec3 SkinNormal(double y, double angle, const Pose& pose)
{
  const double h = 1e-4;
  const dvec3 dy = SkinPoint(y + h, angle, Side::None, false, pose) -
    SkinPoint(y - h, angle, Side::None, false, pose);
  const dvec3 da = SkinPoint(y, angle + h, Side::None, false, pose) -
    SkinPoint(y, angle - h, Side::None, false, pose);
  return Normalized(glm::cross(da, dy));
}

struct HeadPose
{
  std::vector<dvec3> Position; // design units, every head vertex
  std::vector<dvec3> Neutral;  // skin with the eye region shaped, no pose (for rings)
};

HeadPose PlaceHead(const Head& head, const Pose& pose)
{
  const size_t n = head.Info.size();
  HeadPose out;
  out.Position.assign(n, dvec3(0.0));
  out.Neutral.assign(n, dvec3(0.0));
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = head.Info[v];
    if (info.Type != Kind::Skin)
    {
      continue;
    }
    if (info.Row == Rows)
    {
      out.Position[v] = out.Neutral[v] = dvec3(0.0, Crown, FrontZ(Crown));
    }
    else if (info.Row == -1)
    {
      out.Position[v] = out.Neutral[v] =
        dvec3(0.0, NeckBottom, 0.5 * (FrontZ(NeckBottom) + BackZ(NeckBottom)));
    }
    else
    {
      out.Position[v] = SkinPoint(head.RowY[info.Row], head.ColumnAngle[info.Column], info.Which,
        info.MouthSlit, pose, &out.Neutral[v]);
    }
  }

  // Lid margins: the slit vertex pulled toward the eye centre, onto spheres just outside
  // and inside the eyeball, so they follow the lids in every pose.
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = head.Info[v];
    if (info.Type != Kind::LidMargin)
    {
      continue;
    }
    const dvec3 center = EyeCenter(info.Eye);
    const dvec3 edge = out.Position[info.Loop];
    const double radius = info.Ring == 1 ? EyeballRadius + 0.3 * LidOffset : 0.8 * EyeballRadius;
    const double distance = glm::length(edge - center);
    out.Position[v] = distance > radius ? center + (edge - center) * (radius / distance) : edge;
  }

  // Inner lips: rings behind the lip line, rolling into the mouth, following the lips.
  const double depth[InnerLipRings + 1] = { 0.0, 0.0025, 0.0065 };
  const double height[InnerLipRings + 1] = { 0.0, 0.0015, 0.0055 };
  for (size_t v = 0; v < n; ++v)
  {
    const VertexInfo& info = head.Info[v];
    if (info.Type != Kind::InnerLip)
    {
      continue;
    }
    const dvec3 l0 = out.Neutral[info.Loop];
    const dvec3 l = out.Position[info.Loop];
    const double s = Clamp01(std::abs(l0.x) / MouthCornerX);
    const double sideSign =
      info.Which == Side::Upper ? 1.0 : (info.Which == Side::Lower ? -1.0 : 0.0);
    const double taper = std::sqrt(std::max(0.0, 1.0 - s * s));
    out.Position[v] =
      l + dvec3(0.0, sideSign * height[info.Ring] * taper, -depth[info.Ring] * (0.4 + 0.6 * taper));
  }
  return out;
}

/// COLOR_0 of the skin: lips, lid rims, a little colour in cheeks, nose and ears, as a
/// multiplier of the skin's base colour.
dvec3 SkinTint(const VertexInfo& info, const dvec3& p)
{
  const dvec3 lips(0.86, 0.62, 0.72);
  const dvec3 innerLips(0.80, 0.50, 0.62);
  const dvec3 rims(0.92, 0.76, 0.74);
  if (info.Type == Kind::InnerLip)
  {
    return innerLips;
  }
  if (info.Type == Kind::LidMargin)
  {
    // The upper lid's rim is where the lashes grow: dark.
    // Toward the corners, where the lids nearly meet, the rim lies in shadow.
    const double lateral = (std::abs(p.x) - EyeCenterX) / EyeHalfWidth;
    const double corner = SmoothStep(0.3, 0.8, std::abs(lateral));
    const dvec3 rim = rims + (dvec3(0.60, 0.46, 0.44) - rims) * corner;
    return info.Which == Side::Upper ? dvec3(0.36, 0.28, 0.26) : rim;
  }
  const double ax = std::abs(p.x);
  const double dy = p.y - MouthY;
  double upperH, lowerH;
  LipHeights(ax, upperH, lowerH);
  const double inside = SmoothStep(MouthCornerX + 0.0025, MouthCornerX - 0.0015, ax);
  double lip;
  if (info.MouthSlit ? info.Which == Side::Upper : dy > 0.0)
  {
    lip = SmoothStep(0.85 * upperH + 0.0009, 0.85 * upperH - 0.0009, dy);
  }
  else
  {
    lip = SmoothStep(-0.88 * lowerH - 0.0010, -0.88 * lowerH + 0.0010, dy);
  }
  lip *= inside * SmoothStep(0.05, 0.08, p.z);
  dvec3 tint(1.0);
  tint = tint + (lips - tint) * lip;
  // Cheeks, nose tip and ears slightly warmer; nostrils dark.
  const double front = SmoothStep(0.0, 0.04, p.z);
  const double cheek = Bump(std::hypot((ax - 0.047) / 0.026, (p.y + 0.018) / 0.022)) * front;
  const double nose = Bump(std::hypot(ax / 0.013, (p.y + 0.028) / 0.010)) * front;
  const double warm = 0.025 * cheek + 0.030 * nose;
  tint *= dvec3(1.0, 1.0 - warm, 1.0 - warm);
  const double nostril = Bump(std::hypot((ax - 0.0060) / 0.0036, (p.y + 0.0352) / 0.0024)) *
    SmoothStep(0.05, 0.08, p.z) * SmoothStep(FrontZ(p.y) + 0.001, FrontZ(p.y) + 0.004, p.z);
  tint *= 1.0 - 0.25 * nostril;
  return tint;
}

Part MakeHeadPart(Head& head, const HeadPose& neutral)
{
  Part part;
  part.Name = "Head";
  part.VertexCount = head.Info.size();
  // Orientation: skin outward (decided from the neutral), lid margins forward out of the
  // socket, inner lips toward the inside of the mouth.
  const dvec3 mouthInside(0.0, MouthY, FrontZ(MouthY) - 0.02);
  std::vector<uint32_t>& tri = head.Triangles;
  const auto& p = neutral.Position;
  for (size_t t = 0; t < tri.size(); t += 3)
  {
    const uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
    const dvec3 normal = glm::cross(p[b] - p[a], p[c] - p[a]);
    const dvec3 centroid = (p[a] + p[b] + p[c]) / 3.0;
    bool flip = false;
    const Kind ka = head.Info[a].Type, kb = head.Info[b].Type, kc = head.Info[c].Type;
    if (ka == Kind::InnerLip || kb == Kind::InnerLip || kc == Kind::InnerLip)
    {
      // Faces the mouth opening: toward the lip line's centre seen from inside.
      flip = glm::dot(normal, mouthInside - centroid) < 0.0 && glm::length(normal) > 0.0;
    }
    else if (ka == Kind::LidMargin || kb == Kind::LidMargin || kc == Kind::LidMargin)
    {
      flip = normal.z < 0.0;
    }
    if (flip)
    {
      std::swap(tri[t + 1], tri[t + 2]);
    }
  }
  part.Primitives.push_back({ MatSkin, tri });
  part.Colors.resize(part.VertexCount);
  for (size_t v = 0; v < part.VertexCount; ++v)
  {
    part.Colors[v] = SkinTint(
      head.Info[v], neutral.Neutral[head.Info[v].Type == Kind::Skin ? v : head.Info[v].Loop]);
  }
  return part;
}

// ---------------------------------------------------------------------------------------
// Mouth interior: a dark bag hanging from the innermost inner-lip ring, its lower half on
// the jaw, closed by an apex in the throat.
// ---------------------------------------------------------------------------------------
Part MakeMouthInterior(const Head& head)
{
  Part part;
  part.Name = "MouthInterior";
  const int loopSize = static_cast<int>(head.InnerLipLoop.size());
  part.VertexCount = static_cast<size_t>(loopSize) * (MouthBagRings + 1) + 1;
  Primitive prim{ MatMouth, {} };
  for (int ring = 0; ring < MouthBagRings; ++ring)
  {
    for (int k = 0; k < loopSize; ++k)
    {
      const int k1 = (k + 1) % loopSize;
      AddQuad(prim.Triangles, ring * loopSize + k, ring * loopSize + k1, (ring + 1) * loopSize + k1,
        (ring + 1) * loopSize + k);
    }
  }
  const int apex = loopSize * (MouthBagRings + 1);
  for (int k = 0; k < loopSize; ++k)
  {
    AddTriangle(prim.Triangles, MouthBagRings * loopSize + k,
      MouthBagRings * loopSize + (k + 1) % loopSize, apex);
  }
  part.Primitives.push_back(prim);
  return part;
}

std::vector<dvec3> PlaceMouthInterior(const Head& head, const HeadPose& hp, const Pose& pose)
{
  const int loopSize = static_cast<int>(head.InnerLipLoop.size());
  std::vector<dvec3> out(static_cast<size_t>(loopSize) * (MouthBagRings + 1) + 1);
  const dvec3 pivot = JawPivot();
  // Ring 0 is the inner lips' last ring; then deeper rings, taller around the teeth.
  const double depth[MouthBagRings + 2] = { 0.0, 0.006, 0.018, 0.030, 0.038, 0.050 };
  const double height[MouthBagRings + 2] = { 0.0, 0.011, 0.016, 0.014, 0.008, 0.0 };
  const double widthScale[MouthBagRings + 2] = { 1.0, 1.15, 1.15, 0.9, 0.5, 0.0 };
  const double follow[MouthBagRings + 2] = { 1.0, 0.6, 0.3, 0.15, 0.05, 0.0 };
  for (int k = 0; k < loopSize; ++k)
  {
    const int lipVertex = head.InnerLipLoop[k];
    const int loopVertex = head.Info[lipVertex].Loop; // the lip line vertex above it
    const Side which = head.Info[lipVertex].Which;
    const dvec3 l0 = hp.Neutral[loopVertex];
    const dvec3 l = hp.Position[loopVertex];
    out[k] = hp.Position[lipVertex];
    const double s = Clamp01(std::abs(l0.x) / MouthCornerX);
    const double sideSign = which == Side::Upper ? 1.0 : (which == Side::Lower ? -1.0 : 0.0);
    const double jaw = which == Side::Lower ? 1.0 : (which == Side::Upper ? 0.0 : 0.5);
    const dvec3 loopJaw = l0 + jaw * (RotateX(l0, pivot, pose.JawAngle) - l0);
    for (int ring = 1; ring <= MouthBagRings; ++ring)
    {
      const dvec3 q0(l0.x * widthScale[ring],
        MouthY + sideSign * height[ring] * std::sqrt(1.0 - s * s), l0.z - depth[ring]);
      const dvec3 jawMoved = q0 + jaw * (RotateX(q0, pivot, pose.JawAngle) - q0);
      out[static_cast<size_t>(ring) * loopSize + k] = jawMoved + follow[ring] * (l - loopJaw);
    }
  }
  const dvec3 apex0(0.0, MouthY, FrontZ(MouthY) - depth[MouthBagRings + 1]);
  out.back() = apex0 + 0.5 * (RotateX(apex0, pivot, pose.JawAngle) - apex0);
  return out;
}

// ---------------------------------------------------------------------------------------
// Teeth: one rounded box per tooth along the dental arch, upper set fixed, lower set on
// the jaw.
// ---------------------------------------------------------------------------------------
constexpr int ToothAround = 8;
constexpr int ToothRings = 5;
constexpr int TeethPerSide = 6;

struct Tooth
{
  dvec3 Center;    // middle of the crown
  dvec3 Along;     // unit tangent of the arch
  dvec3 Out;       // unit, away from the tongue
  dvec3 Half;      // half extents: along, out, vertical
  double Taper;    // thickness at the biting edge relative to the gum
  double EdgeSign; // +1: biting edge at the top (lower teeth), -1 at the bottom (upper)
};

double LipFrontZ()
{
  return FrontZ(MouthY) + 0.0065;
}

std::vector<Tooth> TeethLayout(bool upper)
{
  // Mesio-distal widths and crown heights (design units), incisor to molar.
  const double widthUpper[TeethPerSide] = { 0.0092, 0.0072, 0.0082, 0.0074, 0.0070, 0.0100 };
  const double widthLower[TeethPerSide] = { 0.0060, 0.0064, 0.0074, 0.0074, 0.0074, 0.0108 };
  const double heightUpper[TeethPerSide] = { 0.0105, 0.0092, 0.0100, 0.0082, 0.0076, 0.0070 };
  const double heightLower[TeethPerSide] = { 0.0088, 0.0088, 0.0098, 0.0082, 0.0078, 0.0072 };
  const double thickness[TeethPerSide] = { 0.0066, 0.0060, 0.0078, 0.0084, 0.0090, 0.0100 };
  // The arch: an ellipse-like curve, x = A sin(phi), z = front - B (1 - cos(phi)).
  const double front = LipFrontZ() - (upper ? 0.0120 : 0.0140);
  const double a = upper ? 0.0235 : 0.0215;
  const double b = upper ? 0.030 : 0.028;
  // Arc length along the arch by fine sampling.
  const int samples = 2000;
  std::vector<double> length(samples + 1, 0.0);
  auto arch = [&](double phi)
  { return dvec3(a * std::sin(phi), 0.0, front - b * (1.0 - std::cos(phi))); };
  const double maxPhi = 1.45;
  for (int k = 1; k <= samples; ++k)
  {
    length[k] =
      length[k - 1] + glm::length(arch(maxPhi * k / samples) - arch(maxPhi * (k - 1) / samples));
  }
  auto phiAt = [&](double s)
  {
    int k = 0;
    while (k < samples - 1 && length[k + 1] < s)
    {
      ++k;
    }
    const double t = (s - length[k]) / (length[k + 1] - length[k]);
    return maxPhi * (k + t) / samples;
  };
  std::vector<Tooth> teeth;
  for (int side : { -1, 1 })
  {
    double s = 0.0;
    for (int i = 0; i < TeethPerSide; ++i)
    {
      const double w = upper ? widthUpper[i] : widthLower[i];
      const double h = upper ? heightUpper[i] : heightLower[i];
      const double phi = phiAt(s + 0.5 * w);
      s += w;
      dvec3 c = arch(phi);
      c.x *= side;
      const dvec3 along = Normalized(dvec3(side * a * std::cos(phi), 0.0, -b * std::sin(phi)));
      const dvec3 out = Normalized(dvec3(-along.z * side, 0.0, along.x * side));
      Tooth tooth;
      tooth.Out = glm::dot(out, dvec3(c.x, 0.0, c.z - (front - b))) >= 0.0 ? out : -out;
      tooth.Along = along;
      // Upper biting edges just below the lip line (rising slowly toward the molars); the
      // lower incisors bite behind and a little above them.
      const double edge = upper ? MouthY - 0.0020 + 0.0007 * i : MouthY - 0.0025 + 0.0004 * i;
      c.y = upper ? edge + 0.5 * h : edge - 0.5 * h;
      c -= tooth.Out * (0.5 * thickness[i]);
      tooth.Center = c;
      tooth.Half = dvec3(0.46 * w, 0.5 * thickness[i], 0.5 * h);
      tooth.Taper = i < 2 ? 0.35 : (i == 2 ? 0.5 : 0.8);
      tooth.EdgeSign = upper ? -1.0 : 1.0;
      teeth.push_back(tooth);
    }
  }
  return teeth;
}

Part MakeTeeth(bool upper)
{
  Part part;
  part.Name = upper ? "UpperTeeth" : "LowerTeeth";
  const int perTooth = ToothAround * ToothRings + 2;
  const int count = 2 * TeethPerSide;
  part.VertexCount = static_cast<size_t>(perTooth) * count;
  Primitive prim{ MatTeeth, {} };
  for (int t = 0; t < count; ++t)
  {
    const int base = t * perTooth;
    const int bottom = base + ToothAround * ToothRings;
    const int top = bottom + 1;
    for (int r = 0; r + 1 < ToothRings; ++r)
    {
      for (int a = 0; a < ToothAround; ++a)
      {
        const int a1 = (a + 1) % ToothAround;
        AddQuad(prim.Triangles, base + r * ToothAround + a, base + r * ToothAround + a1,
          base + (r + 1) * ToothAround + a1, base + (r + 1) * ToothAround + a);
      }
    }
    for (int a = 0; a < ToothAround; ++a)
    {
      const int a1 = (a + 1) % ToothAround;
      AddTriangle(prim.Triangles, base + a, bottom, base + a1);
      AddTriangle(prim.Triangles, base + (ToothRings - 1) * ToothAround + a,
        base + (ToothRings - 1) * ToothAround + a1, top);
    }
  }
  part.Primitives.push_back(prim);
  return part;
}

std::vector<dvec3> PlaceTeeth(bool upper, const Pose& pose)
{
  const std::vector<Tooth> teeth = TeethLayout(upper);
  std::vector<dvec3> out;
  for (const Tooth& tooth : teeth)
  {
    for (int r = 0; r < ToothRings; ++r)
    {
      // Rings from the bottom (-1) to the top (+1) of the crown, denser near the ends.
      const double v = -std::cos(Pi * (r + 0.5) / ToothRings);
      const double vertical = SignedPow(v, 0.7);
      const double scale = std::pow(std::max(0.0, 1.0 - std::pow(std::abs(v), 4.0)), 0.25);
      // Thinner toward the biting edge.
      const double edgeness = Clamp01(0.5 + 0.5 * vertical * tooth.EdgeSign);
      const double thick = Mix(1.0, tooth.Taper, edgeness * edgeness);
      for (int a = 0; a < ToothAround; ++a)
      {
        const double t = 2.0 * Pi * (a + 0.5) / ToothAround;
        const double u = SignedPow(std::cos(t), 0.55) * scale;
        const double w = SignedPow(std::sin(t), 0.55) * scale * thick;
        out.push_back(tooth.Center + tooth.Along * (u * tooth.Half.x) +
          tooth.Out * (w * tooth.Half.y) + dvec3(0.0, vertical * tooth.Half.z, 0.0));
      }
    }
    out.push_back(tooth.Center - dvec3(0.0, tooth.Half.z, 0.0));
    out.push_back(tooth.Center + dvec3(0.0, tooth.Half.z, 0.0));
  }
  if (!upper)
  {
    for (dvec3& p : out)
    {
      p = RotateX(p, JawPivot(), pose.JawAngle);
    }
  }
  return out;
}

void OrientTeeth(Part& part, bool upper)
{
  const std::vector<dvec3> p = PlaceTeeth(upper, Pose());
  const std::vector<Tooth> teeth = TeethLayout(upper);
  const int perTooth = ToothAround * ToothRings + 2;
  for (size_t t = 0; t < part.Primitives[0].Triangles.size(); t += 3)
  {
    auto& tri = part.Primitives[0].Triangles;
    const Tooth& tooth = teeth[tri[t] / perTooth];
    const dvec3 centroid = (p[tri[t]] + p[tri[t + 1]] + p[tri[t + 2]]) / 3.0;
    const dvec3 normal = glm::cross(p[tri[t + 1]] - p[tri[t]], p[tri[t + 2]] - p[tri[t]]);
    if (glm::dot(normal, centroid - tooth.Center) < 0.0)
    {
      std::swap(tri[t + 1], tri[t + 2]);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Tongue: a flattened, rounded body lying in the lower arch, on the jaw; its tip rises
// behind the upper teeth for L.
// ---------------------------------------------------------------------------------------
constexpr int TongueRings = 12;
constexpr int TongueAround = 14;

Part MakeTongue()
{
  Part part;
  part.Name = "Tongue";
  part.VertexCount = static_cast<size_t>(TongueRings) * TongueAround + 2;
  Primitive prim{ MatTongue, {} };
  const int tip = TongueRings * TongueAround;
  const int back = tip + 1;
  for (int r = 0; r + 1 < TongueRings; ++r)
  {
    for (int a = 0; a < TongueAround; ++a)
    {
      const int a1 = (a + 1) % TongueAround;
      AddQuad(prim.Triangles, r * TongueAround + a, r * TongueAround + a1,
        (r + 1) * TongueAround + a1, (r + 1) * TongueAround + a);
    }
  }
  for (int a = 0; a < TongueAround; ++a)
  {
    const int a1 = (a + 1) % TongueAround;
    AddTriangle(prim.Triangles, a, tip, a1);
    AddTriangle(prim.Triangles, (TongueRings - 1) * TongueAround + a,
      (TongueRings - 1) * TongueAround + a1, back);
  }
  part.Primitives.push_back(prim);
  return part;
}

/// The tongue's axis point and half sizes at u (0 tip .. 1 root), before the pose.
void TongueSection(double u, dvec3& center, double& halfWidth, double& halfHeight)
{
  const double tipZ = LipFrontZ() - 0.0200;
  const double length = 0.046;
  // The tip is round in plan; the body widens quickly, the root narrows a little.
  const double plan = std::sqrt(Clamp01(u / 0.16)) * (1.0 - 0.25 * SmoothStep(0.6, 1.0, u));
  halfWidth = 0.0005 + 0.0175 * plan;
  halfHeight = 0.0012 + 0.0048 * std::sqrt(Clamp01(u / 0.25)) + 0.004 * SmoothStep(0.4, 1.0, u);
  // The top of the body a little below the lower teeth's edges, the root lower still.
  center = dvec3(0.0, MouthY - 0.0100 - 0.005 * SmoothStep(0.5, 1.0, u), tipZ - length * u);
}

std::vector<dvec3> PlaceTongue(const Pose& pose)
{
  std::vector<dvec3> out(static_cast<size_t>(TongueRings) * TongueAround + 2);
  const dvec3 pivot = JawPivot();
  auto place = [&](dvec3 p, double u)
  {
    // L: the front third curls up toward the upper teeth (before the jaw opens it).
    if (pose.TongueTipUp != 0.0)
    {
      const double bend = pose.TongueTipUp * std::pow(Clamp01(1.0 - u / 0.55), 2.0);
      p.y += 0.0250 * bend;
      p.z += 0.0020 * bend;
    }
    // The root follows the jaw less than the tip.
    const double follow = 1.0 - 0.4 * SmoothStep(0.3, 1.0, u);
    return p + follow * (RotateX(p, pivot, pose.JawAngle) - p);
  };
  for (int r = 0; r < TongueRings; ++r)
  {
    const double u = 0.03 + 0.97 * std::pow(static_cast<double>(r) / (TongueRings - 1), 1.3);
    dvec3 c;
    double hw, hh;
    TongueSection(u, c, hw, hh);
    for (int a = 0; a < TongueAround; ++a)
    {
      const double t = 2.0 * Pi * a / TongueAround;
      const double cx = std::sin(t);
      const double cy = std::cos(t);
      // Flat below, domed above with a shallow groove along the middle.
      double y = cy > 0.0 ? hh * std::pow(cy, 0.7) : 0.6 * hh * SignedPow(cy, 0.5);
      y -= cy > 0.0 ? 0.0012 * Bump(std::abs(cx) / 0.4) * Clamp01(u / 0.2) : 0.0;
      out[static_cast<size_t>(r) * TongueAround + a] =
        place(c + dvec3(hw * SignedPow(cx, 0.8), y, 0.0), u);
    }
  }
  dvec3 c;
  double hw, hh;
  TongueSection(0.0, c, hw, hh);
  out[static_cast<size_t>(TongueRings) * TongueAround] = place(c + dvec3(0.0, 0.0, 0.0015), 0.0);
  TongueSection(1.0, c, hw, hh);
  out[static_cast<size_t>(TongueRings) * TongueAround + 1] = place(c - dvec3(0.0, 0.0, 0.004), 1.0);
  return out;
}

// ---------------------------------------------------------------------------------------
// Eyes: a sphere in its own node, centred on the eyeball, looking along +Z: pupil cap,
// iris ring and sclera, one primitive each; the iris a little flatter than the sphere.
// ---------------------------------------------------------------------------------------
constexpr int EyeAround = 28;
constexpr int PupilRings = 2;
constexpr int IrisRings = 4;
constexpr int ScleraRings = 12;
constexpr double PupilAngle = 0.15; // radians from the front pole
constexpr double IrisAngle = 0.56;

Part MakeEye(int eye)
{
  Part part;
  part.Name = eye > 0 ? "EyeLeft" : "EyeRight";
  part.Rigid = true;
  part.Translation = EyeCenter(eye);
  const int rings = PupilRings + IrisRings + ScleraRings; // ring k at theta_k, k = 1..rings
  part.VertexCount = static_cast<size_t>(rings) * EyeAround + 2;
  const int front = rings * EyeAround;
  const int back = front + 1;
  auto at = [&](int ring, int a) { return (ring - 1) * EyeAround + a % EyeAround; };
  Primitive pupil{ MatPupil, {} }, iris{ MatIris, {} }, sclera{ MatSclera, {} };
  for (int a = 0; a < EyeAround; ++a)
  {
    AddTriangle(pupil.Triangles, front, at(1, a), at(1, a + 1));
    AddTriangle(sclera.Triangles, back, at(rings, a + 1), at(rings, a));
  }
  for (int ring = 1; ring < rings; ++ring)
  {
    Primitive& prim = ring < PupilRings ? pupil : (ring < PupilRings + IrisRings ? iris : sclera);
    for (int a = 0; a < EyeAround; ++a)
    {
      AddQuad(prim.Triangles, at(ring, a), at(ring + 1, a), at(ring + 1, a + 1), at(ring, a + 1));
    }
  }
  part.Primitives = { sclera, iris, pupil };
  // COLOR_0: the iris darker at its rim (limbus) and around the pupil, the white of the eye
  // shaded next to the iris.
  part.Colors.assign(part.VertexCount, dvec3(1.0));
  for (int ring = 1; ring <= rings; ++ring)
  {
    double shade = 1.0;
    if (ring >= PupilRings && ring <= PupilRings + IrisRings)
    {
      const double t = static_cast<double>(ring - PupilRings) / IrisRings; // 0 pupil .. 1 limbus
      shade = t < 0.5 ? 0.72 + 0.56 * t : 1.0 - 0.9 * (t - 0.5);
    }
    else if (ring == PupilRings + IrisRings + 1)
    {
      shade = 0.9;
    }
    for (int a = 0; a < EyeAround; ++a)
    {
      part.Colors[static_cast<size_t>(at(ring, a))] = dvec3(shade);
    }
  }
  return part;
}

/// The eye's vertices in head space, around `center` (the node's translation).
std::vector<dvec3> PlaceEye(const dvec3& center)
{
  const int rings = PupilRings + IrisRings + ScleraRings;
  std::vector<dvec3> out(static_cast<size_t>(rings) * EyeAround + 2);
  const double r = EyeballRadius;
  // The iris lies on a shallow cap a little flatter than the eyeball; the sclera rings
  // are denser near the iris, where they show.
  const double irisDepth = r * std::cos(IrisAngle);
  for (int ring = 1; ring <= rings; ++ring)
  {
    double theta;
    if (ring <= PupilRings)
    {
      theta = PupilAngle * ring / PupilRings;
    }
    else if (ring <= PupilRings + IrisRings)
    {
      theta = PupilAngle + (IrisAngle - PupilAngle) * (ring - PupilRings) / IrisRings;
    }
    else
    {
      const double t = static_cast<double>(ring - PupilRings - IrisRings) / ScleraRings;
      theta = IrisAngle + (Pi - 0.2 - IrisAngle) * std::pow(t, 1.3);
    }
    for (int a = 0; a < EyeAround; ++a)
    {
      const double phi = 2.0 * Pi * a / EyeAround;
      dvec3 p = r *
        dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      if (theta < IrisAngle)
      {
        // Flatten toward the plane of the iris edge (a third of the way).
        p.z = p.z + (irisDepth + 0.45 * (r - irisDepth) * (1.0 - theta / IrisAngle) - p.z) * 0.55;
      }
      out[static_cast<size_t>(ring - 1) * EyeAround + a] = p;
    }
  }
  out[static_cast<size_t>(rings) * EyeAround] = dvec3(
    0.0, 0.0, irisDepth + 0.45 * (r - irisDepth) + (r - irisDepth - 0.45 * (r - irisDepth)) * 0.45);
  out[static_cast<size_t>(rings) * EyeAround + 1] = dvec3(0.0, 0.0, -r);
  for (dvec3& p : out)
  {
    p += center;
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Eyelashes: a ribbon along each upper lid edge, growing out and curling up; they follow
// the lid (EyesClosed) because they are placed from the posed lid.
// ---------------------------------------------------------------------------------------
constexpr int LashSub = 3;  // ribbon points per lid-edge segment
constexpr int LashRows = 3; // base, middle, tip

struct LashEdge
{
  std::vector<int> Edge;  // head vertices along the upper lid edge (corner, upper copies, corner)
  std::vector<int> Above; // the skin vertex one row up from each
};

std::array<LashEdge, 2> LashEdges(const Head& head)
{
  std::array<LashEdge, 2> edges;
  for (int e = 0; e < 2; ++e)
  {
    const std::vector<int>& columns = head.UpperLidColumns[e];
    std::vector<int> cols{ columns.front() - 1 };
    cols.insert(cols.end(), columns.begin(), columns.end());
    cols.push_back(columns.back() + 1);
    for (size_t k = 0; k < cols.size(); ++k)
    {
      const int c = cols[k];
      const bool corner = k == 0 || k + 1 == cols.size();
      edges[e].Edge.push_back(
        corner ? head.SkinIndex[head.EyeRow][c] : head.SkinUpperIndex[head.EyeRow][c]);
      edges[e].Above.push_back(head.SkinIndex[head.EyeRow + 1][c]);
    }
  }
  return edges;
}

Part MakeLashes(const Head& head)
{
  Part part;
  part.Name = "Eyelashes";
  const auto edges = LashEdges(head);
  Primitive prim{ MatLashes, {} };
  size_t first = 0;
  for (const LashEdge& edge : edges)
  {
    const int along = static_cast<int>(edge.Edge.size() - 1) * LashSub + 1;
    for (int i = 0; i + 1 < along; ++i)
    {
      for (int r = 0; r + 1 < LashRows; ++r)
      {
        const int a = static_cast<int>(first) + r * along + i;
        AddQuad(prim.Triangles, a, a + 1, a + along + 1, a + along);
      }
    }
    first += static_cast<size_t>(along) * LashRows;
  }
  part.VertexCount = first;
  part.Primitives.push_back(prim);
  return part;
}

std::vector<dvec3> PlaceLashes(const Head& head, const HeadPose& hp)
{
  std::vector<dvec3> out;
  for (const LashEdge& edge : LashEdges(head))
  {
    const int n = static_cast<int>(edge.Edge.size());
    const int along = (n - 1) * LashSub + 1;
    std::vector<dvec3> base(along), up(along);
    for (int i = 0; i < along; ++i)
    {
      const int k = std::min(n - 2, i / LashSub);
      const double t = static_cast<double>(i - k * LashSub) / LashSub;
      const dvec3 e0 = hp.Position[edge.Edge[k]], e1 = hp.Position[edge.Edge[k + 1]];
      const dvec3 a0 = hp.Position[edge.Above[k]], a1 = hp.Position[edge.Above[k + 1]];
      base[i] = e0 + (e1 - e0) * t;
      up[i] = Normalized((a0 + (a1 - a0) * t) - base[i]);
    }
    const dvec3 center = EyeCenter(base[0].x < 0.0 ? -1 : 1);
    for (int r = 0; r < LashRows; ++r)
    {
      for (int i = 0; i < along; ++i)
      {
        const double s = static_cast<double>(i) / (along - 1); // corner to corner
        // Longest a little outside the middle, short at the corners.
        const double outer = base[0].x < 0.0 ? 1.0 - s : s; // 1 at the outer corner
        const double length = 0.0024 * std::pow(std::sin(Pi * Clamp01(0.04 + 0.92 * s)), 0.6) *
          (0.75 + 0.4 * outer) * SmoothStep(0.12, 0.35, outer);
        const dvec3 out0 = Normalized(base[i] - center); // out of the eyeball
        const dvec3 dir = Normalized(out0 + 0.35 * up[i]);
        const double t = static_cast<double>(r) / (LashRows - 1);
        // Grows outward, then curls up along the lid.
        out.push_back(base[i] + out0 * 0.0003 + dir * (length * t) +
          up[i] * (0.0012 * t * t) * (length / 0.0024));
      }
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Brows: a tapered band per side lying on the skin, following the forehead.
// ---------------------------------------------------------------------------------------
constexpr int BrowAlong = 14;
constexpr int BrowAcross = 4;

Part MakeBrows()
{
  Part part;
  part.Name = "Brows";
  part.VertexCount = 2 * static_cast<size_t>(BrowAlong) * BrowAcross;
  Primitive prim{ MatBrows, {} };
  for (int side = 0; side < 2; ++side)
  {
    const int base = side * BrowAlong * BrowAcross;
    for (int i = 0; i + 1 < BrowAlong; ++i)
    {
      for (int j = 0; j + 1 < BrowAcross; ++j)
      {
        const int a = base + i * BrowAcross + j;
        AddQuad(prim.Triangles, a, a + BrowAcross, a + BrowAcross + 1, a + 1);
      }
    }
  }
  part.Primitives.push_back(prim);
  return part;
}

std::vector<dvec3> PlaceBrows(const Pose& pose)
{
  std::vector<dvec3> out;
  for (int sign : { -1, 1 })
  {
    for (int i = 0; i < BrowAlong; ++i)
    {
      const double u = static_cast<double>(i) / (BrowAlong - 1); // inner head .. outer tail
      const double x = sign * (EyeCenterX - 0.0205 + 0.0445 * u);
      // An arch peaking two thirds along, the tail dropping.
      const double centerY =
        EyeY + 0.0215 + 0.0045 * std::sin(Pi * std::pow(u, 0.8)) - 0.0025 * u * u;
      const double halfHeight = 0.0026 * (1.0 - 0.55 * std::pow(u, 1.5)) + 0.0004;
      for (int j = 0; j < BrowAcross; ++j)
      {
        const double v = -1.0 + 2.0 * j / (BrowAcross - 1);
        const double y = centerY + v * halfHeight + 0.0008 * u * v;
        // The angle of the base head point with this x at height y.
        const double angle = AngleAt(x, y);
        const dvec3 p = SkinPoint(y, angle, Side::None, false, pose);
        const dvec3 n = SkinNormal(y, angle, pose);
        const double lift = 0.0004 + 0.0005 * (1.0 - v * v);
        out.push_back(p + n * lift);
      }
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Ears: a shell per side, a disc with a rolled rim (helix) around a hollow (concha), set
// into the side of the head at its front edge and standing out toward the back.
// ---------------------------------------------------------------------------------------
constexpr int EarAround = 20;
constexpr int EarRings = 6;
constexpr double EarY = 0.0;
constexpr double EarHalfWidth = 0.0175;
constexpr double EarHalfHeight = 0.033;
constexpr double EarTilt = 0.42; // radians between the ear and the side of the head

size_t EarVertices()
{
  return 2 + static_cast<size_t>(2 * EarRings - 1) * EarAround;
}

/// The ear's frame: front edge on the skin, axis back (along the ear), outward normal.
void EarFrame(int side, dvec3& center, dvec3& back, dvec3& outward)
{
  back = dvec3(side * std::sin(EarTilt), 0.0, -std::cos(EarTilt));
  outward = dvec3(side * std::cos(EarTilt), 0.0, std::sin(EarTilt));
  const double earZ = 0.5 * (FrontZ(EarY) + BackZ(EarY)) - 0.012;
  // The column angle where the skin is at the ear's front edge.
  double lo = 1.0, hi = 2.2;
  for (int k = 0; k < 60; ++k)
  {
    const double mid = 0.5 * (lo + hi);
    (BaseHead(EarY, mid).z > earZ + EarHalfWidth ? lo : hi) = mid;
  }
  dvec3 front = BaseHead(EarY, side * 0.5 * (lo + hi));
  front -= outward * 0.0025; // set into the skin
  center = front + back * EarHalfWidth;
}

std::vector<dvec3> PlaceEars()
{
  std::vector<dvec3> out;
  for (int side : { -1, 1 })
  {
    dvec3 center, back, outward;
    EarFrame(side, center, back, outward);
    auto point = [&](double rho, double theta, bool frontFace)
    {
      const double u = rho * std::cos(theta); // -1 front .. +1 back
      const double v = rho * std::sin(theta); // -1 lobe .. +1 top
      double w;
      if (frontFace)
      {
        const double rimSpan = Clamp01(SmoothStep(-0.7, -0.2, u) + SmoothStep(0.2, 0.6, v));
        w = 0.0016 * (1.0 - rho * rho) + 0.0030 * Bump(std::abs(rho - 0.86) / 0.15) * rimSpan -
          0.0052 * Bump(std::hypot((u + 0.18) / 0.50, (v + 0.05) / 0.42)) +
          0.0012 * Bump(std::abs(rho - 0.60) / 0.13) * SmoothStep(-0.2, 0.5, u + v);
      }
      else
      {
        w = -0.0030 * std::sqrt(std::max(0.0, 1.0 - rho * rho));
      }
      const double halfWidth = EarHalfWidth * (1.0 + 0.18 * v);
      return center + back * (halfWidth * u) + dvec3(0.0, EarY + EarHalfHeight * v, 0.0) +
        outward * w;
    };
    out.push_back(point(0.0, 0.0, true));
    for (int k = 1; k <= EarRings; ++k)
    {
      for (int a = 0; a < EarAround; ++a)
      {
        out.push_back(point(static_cast<double>(k) / EarRings, 2.0 * Pi * a / EarAround, true));
      }
    }
    for (int k = 1; k < EarRings; ++k)
    {
      for (int a = 0; a < EarAround; ++a)
      {
        out.push_back(
          point(1.0 - static_cast<double>(k) / EarRings, 2.0 * Pi * a / EarAround, false));
      }
    }
    out.push_back(point(0.0, 0.0, false));
  }
  return out;
}

Part MakeEars()
{
  Part part;
  part.Name = "Ears";
  part.VertexCount = 2 * EarVertices();
  Primitive prim{ MatSkin, {} };
  const std::vector<dvec3> p = PlaceEars();
  for (int e = 0; e < 2; ++e)
  {
    const int base = e * static_cast<int>(EarVertices());
    const int rings = 2 * EarRings - 1; // front rings 1..EarRings, then back rings
    auto at = [&](int ring, int a) { return base + 1 + (ring - 1) * EarAround + a % EarAround; };
    const int backCenter = base + static_cast<int>(EarVertices()) - 1;
    std::vector<uint32_t> front, rear;
    for (int a = 0; a < EarAround; ++a)
    {
      AddTriangle(front, base, at(1, a), at(1, a + 1));
      AddTriangle(rear, backCenter, at(rings, a), at(rings, a + 1));
    }
    for (int ring = 1; ring < rings; ++ring)
    {
      for (int a = 0; a < EarAround; ++a)
      {
        AddQuad(ring < EarRings ? front : rear, at(ring, a), at(ring + 1, a), at(ring + 1, a + 1),
          at(ring, a + 1));
      }
    }
    dvec3 center, back, outward;
    EarFrame(e == 0 ? -1 : 1, center, back, outward);
    OrientOutward(front, p, [&](const dvec3&) { return center - outward * 0.02; });
    OrientOutward(rear, p, [&](const dvec3&) { return center + outward * 0.02; });
    prim.Triangles.insert(prim.Triangles.end(), front.begin(), front.end());
    prim.Triangles.insert(prim.Triangles.end(), rear.begin(), rear.end());
  }
  part.Primitives.push_back(prim);
  part.Colors.assign(part.VertexCount, dvec3(1.0, 0.93, 0.92));
  return part;
}

// ---------------------------------------------------------------------------------------
// Hair: a short-cropped cap over the skull, a shell above the skin from the hairline up,
// closed at the hairline by a skirt down to the skin.
// ---------------------------------------------------------------------------------------
constexpr int HairAround = 96;
constexpr int HairRows = 14;

/// Height of the hairline at a column angle (0 = front).
double Hairline(double angle)
{
  static const Curve line{ { 0.00, 0.093 }, { 0.40, 0.091 }, { 0.70, 0.085 }, { 0.90, 0.079 },
    { 1.05, 0.070 }, { 1.20, 0.060 }, { 1.30, 0.042 }, { 1.38, 0.018 }, { 1.45, 0.004 },
    { 1.52, 0.006 }, { 1.56, 0.030 }, { 1.62, 0.044 }, { 1.75, 0.047 }, { 1.86, 0.042 },
    { 1.95, 0.018 }, { 2.05, -0.016 }, { 2.30, -0.040 }, { 2.70, -0.050 }, { Pi, -0.054 } };
  return line(std::abs(angle));
}

Part MakeHair()
{
  Part part;
  part.Name = "Hair";
  // Row 0 is the skirt on the skin, rows 1..HairRows the shell; then the crown vertex.
  part.VertexCount = static_cast<size_t>(HairRows + 1) * HairAround + 1;
  Primitive prim{ MatHair, {} };
  for (int r = 0; r < HairRows; ++r)
  {
    for (int a = 0; a < HairAround; ++a)
    {
      const int a1 = (a + 1) % HairAround;
      AddQuad(prim.Triangles, r * HairAround + a, r * HairAround + a1, (r + 1) * HairAround + a1,
        (r + 1) * HairAround + a);
    }
  }
  const int crown = (HairRows + 1) * HairAround;
  for (int a = 0; a < HairAround; ++a)
  {
    AddTriangle(prim.Triangles, HairRows * HairAround + a,
      HairRows * HairAround + (a + 1) % HairAround, crown);
  }
  part.Primitives.push_back(prim);
  return part;
}

std::vector<dvec3> PlaceHair(const Pose& pose)
{
  std::vector<dvec3> out(static_cast<size_t>(HairRows + 1) * HairAround + 1);
  const double top = Crown - 0.004;
  for (int a = 0; a < HairAround; ++a)
  {
    const double angle = -Pi + 2.0 * Pi * a / HairAround;
    const double line = Hairline(angle);
    for (int r = 0; r <= HairRows; ++r)
    {
      const double v = r == 0 ? 0.0 : std::pow(static_cast<double>(r - 1) / (HairRows - 1), 0.8);
      const double y = line + (top - line) * v;
      const dvec3 p = SkinPoint(y, angle, Side::None, false, pose);
      const dvec3 n = SkinNormal(y, angle, pose);
      // Thin at the hairline, fuller on top and at the back.
      const double thickness =
        r == 0 ? 0.0002 : 0.0012 + 0.0048 * SmoothStep(0.0, 0.5, v) + 0.0015 * v;
      out[static_cast<size_t>(r) * HairAround + a] = p + n * thickness;
    }
  }
  out.back() = dvec3(0.0, Crown, FrontZ(Crown)) + dvec3(0.0, 0.0085, 0.0);
  return out;
}

// ---------------------------------------------------------------------------------------
// The scene
// ---------------------------------------------------------------------------------------
struct MaterialDef
{
  const char* Name;
  std::array<double, 4> Color;
  double Roughness;
  bool DoubleSided;
};

const MaterialDef Materials[MaterialCount] = {
  { "Skin", { 0.80, 0.62, 0.52, 1.0 }, 0.6, false },
  { "MouthInterior", { 0.22, 0.06, 0.07, 1.0 }, 0.7, false },
  { "Teeth", { 0.90, 0.88, 0.80, 1.0 }, 0.35, false },
  { "Tongue", { 0.66, 0.31, 0.33, 1.0 }, 0.5, false },
  { "Sclera", { 0.91, 0.89, 0.85, 1.0 }, 0.3, false },
  { "Iris", { 0.36, 0.50, 0.60, 1.0 }, 0.3, false },
  { "Pupil", { 0.02, 0.02, 0.02, 1.0 }, 0.2, false },
  { "Eyelashes", { 0.06, 0.045, 0.035, 1.0 }, 0.8, true },
  { "Brows", { 0.28, 0.19, 0.12, 1.0 }, 0.9, false },
  { "Hair", { 0.20, 0.13, 0.08, 1.0 }, 0.9, false },
};

struct Scene
{
  Head HeadTopology;
  std::vector<Part> Parts;
};

Scene BuildScene()
{
  Scene scene;
  scene.HeadTopology = BuildHeadTopology();
  const HeadPose neutral = PlaceHead(scene.HeadTopology, Pose());
  scene.Parts.push_back(MakeHeadPart(scene.HeadTopology, neutral));
  scene.Parts.push_back(MakeMouthInterior(scene.HeadTopology));
  Part upper = MakeTeeth(true);
  OrientTeeth(upper, true);
  scene.Parts.push_back(upper);
  Part lower = MakeTeeth(false);
  OrientTeeth(lower, false);
  scene.Parts.push_back(lower);
  scene.Parts.push_back(MakeTongue());
  scene.Parts.push_back(MakeEye(1));
  scene.Parts.push_back(MakeEye(-1));
  scene.Parts.push_back(MakeLashes(scene.HeadTopology));
  scene.Parts.push_back(MakeBrows());
  scene.Parts.push_back(MakeHair());
  scene.Parts.push_back(MakeEars());
  return scene;
}

/// Every part's vertices in a pose (design units, relative to the part's node).
std::vector<std::vector<dvec3>> PlaceScene(const Scene& scene, const Pose& pose)
{
  const HeadPose hp = PlaceHead(scene.HeadTopology, pose);
  std::vector<std::vector<dvec3>> out;
  for (const Part& part : scene.Parts)
  {
    if (part.Name == "Head")
    {
      out.push_back(hp.Position);
    }
    else if (part.Name == "MouthInterior")
    {
      out.push_back(PlaceMouthInterior(scene.HeadTopology, hp, pose));
    }
    else if (part.Name == "UpperTeeth" || part.Name == "LowerTeeth")
    {
      out.push_back(PlaceTeeth(part.Name == "UpperTeeth", pose));
    }
    else if (part.Name == "Tongue")
    {
      out.push_back(PlaceTongue(pose));
    }
    else if (part.Name == "EyeLeft" || part.Name == "EyeRight")
    {
      out.push_back(PlaceEye(part.Translation));
    }
    else if (part.Name == "Eyelashes")
    {
      out.push_back(PlaceLashes(scene.HeadTopology, hp));
    }
    else if (part.Name == "Brows")
    {
      out.push_back(PlaceBrows(pose));
    }
    else if (part.Name == "Hair")
    {
      out.push_back(PlaceHair(pose));
    }
    else if (part.Name == "Ears")
    {
      out.push_back(PlaceEars());
    }
    if (out.back().size() != part.VertexCount)
    {
      std::cerr << "GenerateDefaultFace: internal error, " << part.Name << " has "
                << out.back().size() << " positions for " << part.VertexCount << " vertices\n";
      std::exit(1);
    }
  }
  return out;
}

/// Orients the triangles of the simple closed parts (mouth interior toward its inside,
/// tongue outward, eyes outward) from the neutral.
void OrientParts(Scene& scene, const std::vector<std::vector<dvec3>>& neutral)
{
  for (size_t i = 0; i < scene.Parts.size(); ++i)
  {
    Part& part = scene.Parts[i];
    const std::vector<dvec3>& p = neutral[i];
    if (part.Name == "MouthInterior")
    {
      // Faces inward: its normals point toward the mouth's axis.
      for (auto& prim : part.Primitives)
      {
        OrientOutward(prim.Triangles, p,
          [](const dvec3& c) { return dvec3(c.x * 1.6, MouthY + (c.y - MouthY) * 1.6, c.z); });
      }
    }
    else if (part.Name == "Tongue")
    {
      for (auto& prim : part.Primitives)
      {
        OrientOutward(prim.Triangles, p,
          [](const dvec3& c)
          {
            dvec3 center;
            double hw, hh;
            TongueSection(0.5, center, hw, hh);
            return dvec3(0.0, center.y, c.z);
          });
      }
    }
    else if (part.Name == "EyeLeft" || part.Name == "EyeRight")
    {
      const dvec3 center = part.Translation;
      for (auto& prim : part.Primitives)
      {
        OrientOutward(prim.Triangles, p, [center](const dvec3&) { return center; });
      }
    }
    else if (part.Name == "Hair" || part.Name == "Brows")
    {
      // Away from the head's centre.
      for (auto& prim : part.Primitives)
      {
        OrientOutward(prim.Triangles, p,
          [](const dvec3& c) { return dvec3(0.0, std::min(c.y, 0.03), -0.005); });
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------
float Quantize(double value, double step)
{
  return static_cast<float>(std::round(value / step) * step);
}

std::vector<float> QuantizePositions(const std::vector<dvec3>& positions, const dvec3& origin)
{
  std::vector<float> out;
  out.reserve(positions.size() * 3);
  for (const dvec3& p : positions)
  {
    const dvec3 q = (p - origin) * FinalScale;
    for (int k = 0; k < 3; ++k)
    {
      out.push_back(Quantize(q[k], 1e-6));
    }
  }
  return out;
}

/// Area-weighted vertex normals of float positions over all primitives, rounded to 1e-5.
std::vector<float> ComputeNormals(const std::vector<float>& positions, const Part& part)
{
  const size_t n = positions.size() / 3;
  std::vector<dvec3> sum(n, dvec3(0.0));
  auto at = [&](uint32_t i)
  { return dvec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]); };
  for (const Primitive& prim : part.Primitives)
  {
    for (size_t t = 0; t < prim.Triangles.size(); t += 3)
    {
      const uint32_t a = prim.Triangles[t], b = prim.Triangles[t + 1], c = prim.Triangles[t + 2];
      const dvec3 normal = glm::cross(at(b) - at(a), at(c) - at(a));
      sum[a] += normal;
      sum[b] += normal;
      sum[c] += normal;
    }
  }
  std::vector<float> out;
  out.reserve(n * 3);
  for (const dvec3& s : sum)
  {
    const dvec3 unit = Normalized(s);
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
  int ZeroView = -1;

  int AddView(const void* data, size_t size, int target, int stride = 0)
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
    if (stride > 0)
    {
      view["byteStride"] = stride;
    }
    if (target > 0)
    {
      view["target"] = target;
    }
    this->BufferViews.push_back(view);
    return static_cast<int>(this->BufferViews.size()) - 1;
  }

  static void Bounds(
    const std::vector<float>& values, size_t width, nlohmann::ordered_json& accessor)
  {
    std::vector<float> lo(values.begin(), values.begin() + width), hi = lo;
    for (size_t i = 0; i < values.size(); ++i)
    {
      lo[i % width] = std::min(lo[i % width], values[i]);
      hi[i % width] = std::max(hi[i % width], values[i]);
    }
    accessor["min"] = lo;
    accessor["max"] = hi;
  }

  int AddFloats(const std::vector<float>& values, const char* type, size_t width, bool withBounds)
  {
    const int view = this->AddView(values.data(), values.size() * sizeof(float), 34962);
    nlohmann::ordered_json accessor;
    accessor["bufferView"] = view;
    accessor["byteOffset"] = 0;
    accessor["componentType"] = 5126;
    accessor["count"] = values.size() / width;
    accessor["type"] = type;
    if (withBounds)
    {
      Bounds(values, width, accessor);
    }
    this->Accessors.push_back(accessor);
    return static_cast<int>(this->Accessors.size()) - 1;
  }

  /// A morph target attribute: sparse over the shared zero view (only the moved
  /// vertices stored), or the zero view alone when nothing moves.
  int AddDelta(
    const std::vector<float>& deltas, const std::vector<uint32_t>& moved, bool withBounds)
  {
    const size_t count = deltas.size() / 3;
    nlohmann::ordered_json accessor;
    accessor["bufferView"] = this->ZeroView;
    accessor["byteOffset"] = 0;
    accessor["componentType"] = 5126;
    accessor["count"] = count;
    accessor["type"] = "VEC3";
    if (withBounds)
    {
      Bounds(deltas, 3, accessor);
    }
    if (!moved.empty())
    {
      const bool shortIndices = count <= 65535;
      int indexView;
      if (shortIndices)
      {
        std::vector<uint16_t> indices(moved.begin(), moved.end());
        indexView = this->AddView(indices.data(), indices.size() * sizeof(uint16_t), 0);
      }
      else
      {
        indexView = this->AddView(moved.data(), moved.size() * sizeof(uint32_t), 0);
      }
      std::vector<float> values;
      values.reserve(moved.size() * 3);
      for (uint32_t i : moved)
      {
        values.insert(values.end(), deltas.begin() + 3 * i, deltas.begin() + 3 * i + 3);
      }
      const int valueView = this->AddView(values.data(), values.size() * sizeof(float), 0);
      accessor["sparse"] = { { "count", moved.size() },
        { "indices",
          { { "bufferView", indexView }, { "byteOffset", 0 },
            { "componentType", shortIndices ? 5123 : 5125 } } },
        { "values", { { "bufferView", valueView }, { "byteOffset", 0 } } } };
    }
    this->Accessors.push_back(accessor);
    return static_cast<int>(this->Accessors.size()) - 1;
  }

  int AddIndices(const std::vector<uint32_t>& indices, size_t vertexCount)
  {
    nlohmann::ordered_json accessor;
    int view;
    if (vertexCount <= 65535)
    {
      std::vector<uint16_t> shorts(indices.begin(), indices.end());
      view = this->AddView(shorts.data(), shorts.size() * sizeof(uint16_t), 34963);
      accessor["componentType"] = 5123;
    }
    else
    {
      view = this->AddView(indices.data(), indices.size() * sizeof(uint32_t), 34963);
      accessor["componentType"] = 5125;
    }
    accessor = nlohmann::ordered_json{ { "bufferView", view }, { "byteOffset", 0 },
      { "componentType", accessor["componentType"] }, { "count", indices.size() },
      { "type", "SCALAR" } };
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

/// One primitive's vertices: the part's vertices its triangles use, in part order.
struct Subset
{
  std::vector<uint32_t> Vertices;  // part vertex of each primitive vertex
  std::vector<uint32_t> Triangles; // renumbered
};

Subset MakeSubset(const Primitive& prim, size_t partVertices)
{
  std::vector<int64_t> local(partVertices, -1);
  for (uint32_t v : prim.Triangles)
  {
    local[v] = 0;
  }
  Subset subset;
  for (size_t v = 0; v < partVertices; ++v)
  {
    if (local[v] >= 0)
    {
      local[v] = static_cast<int64_t>(subset.Vertices.size());
      subset.Vertices.push_back(static_cast<uint32_t>(v));
    }
  }
  for (uint32_t v : prim.Triangles)
  {
    subset.Triangles.push_back(static_cast<uint32_t>(local[v]));
  }
  return subset;
}

std::vector<float> Gather(
  const std::vector<float>& values, const std::vector<uint32_t>& vertices, size_t width)
{
  std::vector<float> out;
  out.reserve(vertices.size() * width);
  for (uint32_t v : vertices)
  {
    out.insert(out.end(), values.begin() + width * v, values.begin() + width * v + width);
  }
  return out;
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: GenerateDefaultFace <output.glb>\n";
    return 2;
  }
  Scene scene = BuildScene();
  const std::vector<Target> targets = Targets();
  OrientParts(scene, PlaceScene(scene, Pose()));

  // Positions and normals of every part in every pose (index 0: neutral).
  struct Shape
  {
    std::vector<float> Position, Normal;
  };
  std::vector<std::vector<Shape>> shapes(scene.Parts.size()); // [part][pose]
  std::vector<Pose> poses{ Pose() };
  for (const Target& t : targets)
  {
    poses.push_back(t.Shape);
  }
  for (const Pose& pose : poses)
  {
    const std::vector<std::vector<dvec3>> placed = PlaceScene(scene, pose);
    for (size_t i = 0; i < scene.Parts.size(); ++i)
    {
      Shape s;
      s.Position = QuantizePositions(placed[i], scene.Parts[i].Translation);
      s.Normal = ComputeNormals(s.Position, scene.Parts[i]);
      shapes[i].push_back(s);
    }
  }

  BinaryBuilder bin;
  size_t largest = 0;
  for (const Part& part : scene.Parts)
  {
    largest = std::max(largest, part.VertexCount);
  }
  const std::vector<float> zeros(largest * 3, 0.0f);
  bin.ZeroView = bin.AddView(zeros.data(), zeros.size() * sizeof(float), 34962, 12);

  nlohmann::ordered_json meshes = nlohmann::ordered_json::array();
  nlohmann::ordered_json nodes = nlohmann::ordered_json::array();
  nlohmann::ordered_json children = nlohmann::ordered_json::array();
  std::vector<double> distMorph(targets.size(), 0.0);
  size_t totalVertices = 0, totalTriangles = 0;
  std::printf("%-14s %10s %9s %8s  %s\n", "part", "primitives", "vertices", "triangles", "targets");
  for (size_t i = 0; i < scene.Parts.size(); ++i)
  {
    const Part& part = scene.Parts[i];
    const Shape& neutral = shapes[i][0];
    // The targets that move this part (position or normal), in table order.
    std::vector<size_t> moving;
    for (size_t t = 0; t < targets.size() && !part.Rigid; ++t)
    {
      const Shape& s = shapes[i][t + 1];
      if (s.Position != neutral.Position || s.Normal != neutral.Normal)
      {
        moving.push_back(t);
      }
    }
    nlohmann::ordered_json primitives = nlohmann::ordered_json::array();
    size_t partVertices = 0, partTriangles = 0;
    for (const Primitive& prim : part.Primitives)
    {
      const Subset subset = MakeSubset(prim, part.VertexCount);
      const size_t count = subset.Vertices.size();
      partVertices += count;
      partTriangles += subset.Triangles.size() / 3;
      nlohmann::ordered_json attributes;
      attributes["POSITION"] =
        bin.AddFloats(Gather(neutral.Position, subset.Vertices, 3), "VEC3", 3, true);
      attributes["NORMAL"] =
        bin.AddFloats(Gather(neutral.Normal, subset.Vertices, 3), "VEC3", 3, false);
      if (!part.Colors.empty())
      {
        std::vector<float> colors;
        for (uint32_t v : subset.Vertices)
        {
          for (int k = 0; k < 3; ++k)
          {
            colors.push_back(Quantize(std::min(1.0, part.Colors[v][k]), 1e-4));
          }
        }
        attributes["COLOR_0"] = bin.AddFloats(colors, "VEC3", 3, false);
      }
      nlohmann::ordered_json primitive;
      primitive["attributes"] = attributes;
      primitive["indices"] = bin.AddIndices(subset.Triangles, count);
      primitive["material"] = prim.Material;
      primitive["mode"] = 4;
      if (!moving.empty())
      {
        nlohmann::ordered_json targetAccessors = nlohmann::ordered_json::array();
        for (size_t t : moving)
        {
          const Shape& s = shapes[i][t + 1];
          std::vector<float> dp(count * 3), dn(count * 3);
          std::vector<uint32_t> moved;
          for (size_t k = 0; k < count; ++k)
          {
            bool any = false;
            for (int c = 0; c < 3; ++c)
            {
              const size_t src = 3 * subset.Vertices[k] + c;
              dp[3 * k + c] = s.Position[src] - neutral.Position[src];
              dn[3 * k + c] = s.Normal[src] - neutral.Normal[src];
              any = any || dp[3 * k + c] != 0.0f || dn[3 * k + c] != 0.0f;
            }
            if (any)
            {
              moved.push_back(static_cast<uint32_t>(k));
            }
            distMorph[t] += std::sqrt(double(dp[3 * k]) * dp[3 * k] +
              double(dp[3 * k + 1]) * dp[3 * k + 1] + double(dp[3 * k + 2]) * dp[3 * k + 2]);
          }
          nlohmann::ordered_json attributesT;
          attributesT["POSITION"] = bin.AddDelta(dp, moved, true);
          attributesT["NORMAL"] = bin.AddDelta(dn, moved, false);
          targetAccessors.push_back(attributesT);
        }
        primitive["targets"] = targetAccessors;
      }
      primitives.push_back(primitive);
    }
    nlohmann::ordered_json mesh;
    mesh["name"] = part.Name;
    mesh["primitives"] = primitives;
    if (!moving.empty())
    {
      mesh["weights"] = std::vector<double>(moving.size(), 0.0);
      nlohmann::ordered_json names = nlohmann::ordered_json::array();
      for (size_t t : moving)
      {
        names.push_back(targets[t].Name);
      }
      mesh["extras"] = { { "targetNames", names } };
    }
    meshes.push_back(mesh);
    nlohmann::ordered_json node;
    node["name"] = part.Name;
    node["mesh"] = i;
    if (part.Translation != dvec3(0.0))
    {
      const dvec3 t = part.Translation * FinalScale;
      auto micrometres = [](double v) { return std::round(v / 1e-6) * 1e-6; };
      node["translation"] = { micrometres(t.x), micrometres(t.y), micrometres(t.z) };
    }
    nodes.push_back(node);
    children.push_back(i + 1);
    totalVertices += partVertices;
    totalTriangles += partTriangles;
    std::string names;
    for (size_t t : moving)
    {
      names += std::string(names.empty() ? "" : " ") + targets[t].Name;
    }
    std::printf("%-14s %10zu %9zu %8zu  %s\n", part.Name.c_str(), part.Primitives.size(),
      partVertices, partTriangles, part.Rigid ? "(none: rotated for gaze)" : names.c_str());
  }

  nlohmann::ordered_json materials = nlohmann::ordered_json::array();
  for (const MaterialDef& m : Materials)
  {
    nlohmann::ordered_json material;
    material["name"] = m.Name;
    material["pbrMetallicRoughness"] = { { "baseColorFactor", m.Color }, { "metallicFactor", 0.0 },
      { "roughnessFactor", m.Roughness } };
    if (m.DoubleSided)
    {
      material["doubleSided"] = true;
    }
    materials.push_back(material);
  }

  nlohmann::ordered_json root;
  root["name"] = "DefaultHead";
  root["children"] = children;
  nodes.insert(nodes.begin(), root);

  nlohmann::ordered_json gltf;
  gltf["asset"] = { { "version", "2.0" },
    { "generator", "MorphNode GenerateDefaultFace (Data/DefaultFace/generator)" } };
  gltf["scene"] = 0;
  gltf["scenes"] =
    nlohmann::ordered_json::array({ { { "name", "DefaultHead" }, { "nodes", { 0 } } } });
  gltf["nodes"] = nodes;
  gltf["meshes"] = meshes;
  gltf["materials"] = materials;
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

  std::printf("%s: %zu parts, %zu vertices, %zu triangles, %zu targets, %zu bytes\n", argv[1],
    scene.Parts.size(), totalVertices, totalTriangles, targets.size(), glb.size());
  const double maxDist = *std::max_element(distMorph.begin(), distMorph.end());
  std::printf("%-12s %12s %9s\n", "target", "dist_morph", "dist_norm");
  std::printf("%-12s %12.6f %9.2f\n", "Neutral", 0.0, 0.0);
  for (size_t t = 0; t < targets.size(); ++t)
  {
    std::printf("%-12s %12.6f %9.2f\n", targets[t].Name, distMorph[t], distMorph[t] / maxDist);
  }
  return 0;
}
