// SPDX-License-Identifier: BSD-3-Clause
#include "rig/ObjSet.h"

#include "base/Error.h"
#include "base/Text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string_view>

namespace morphnode
{
namespace
{
class LineError
{
public:
  LineError(const std::string& source, size_t line)
    : Source(source)
    , Line(line)
  {
  }
  [[noreturn]] void operator()(const std::string& what) const
  {
    throw InputError(this->Source + ":" + std::to_string(this->Line) + ": " + what);
  }

private:
  const std::string& Source;
  size_t Line;
};

bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/// Splits a line into whitespace-separated tokens (views into the line).
void Tokenize(std::string_view line, std::vector<std::string_view>& tokens)
{
  tokens.clear();
  size_t i = 0;
  while (i < line.size())
  {
    while (i < line.size() && IsSpace(line[i]))
    {
      ++i;
    }
    const size_t start = i;
    while (i < line.size() && !IsSpace(line[i]))
    {
      ++i;
    }
    if (i > start)
    {
      tokens.push_back(line.substr(start, i - start));
    }
  }
}

std::string Str(std::string_view v)
{
  return std::string(v);
}

/// OBJ index (1-based, or negative = relative to the end) to 0-based, checked.
int32_t ResolveIndex(std::string_view token, size_t count, const char* kind, const LineError& fail)
{
  long index = 0;
  if (!text::ParseNumber(token, index))
  {
    fail(std::string("bad ") + kind + " index '" + Str(token) + "'");
  }
  long resolved = index > 0 ? index - 1 : static_cast<long>(count) + index;
  if (index == 0 || resolved < 0 || resolved >= static_cast<long>(count))
  {
    fail(std::string(kind) + " index " + std::to_string(index) + " is out of range (" +
      std::to_string(count) + " " + kind + "s defined so far)");
  }
  return static_cast<int32_t>(resolved);
}

struct Corner
{
  int32_t Position;
  int32_t TexCoord;
  int32_t Normal;
};

Corner ParseCorner(std::string_view token, const ObjMesh& mesh, const LineError& fail)
{
  const size_t slash1 = token.find('/');
  Corner corner{ -1, -1, -1 };
  const std::string_view v = token.substr(0, slash1);
  if (v.empty())
  {
    fail("face corner '" + Str(token) + "' has no vertex index");
  }
  corner.Position = ResolveIndex(v, mesh.GetNumberOfPoints(), "vertex", fail);
  if (slash1 == std::string_view::npos)
  {
    return corner;
  }
  const std::string_view rest = token.substr(slash1 + 1);
  const size_t slash2 = rest.find('/');
  const std::string_view vt = rest.substr(0, slash2);
  if (!vt.empty())
  {
    corner.TexCoord = ResolveIndex(vt, mesh.TexCoords.size() / 2, "texture coordinate", fail);
  }
  if (slash2 != std::string_view::npos)
  {
    const std::string_view vn = rest.substr(slash2 + 1);
    if (vn.empty() || vn.find('/') != std::string_view::npos)
    {
      fail("face corner '" + Str(token) + "' is not one of v, v/vt, v//vn, v/vt/vn");
    }
    corner.Normal = ResolveIndex(vn, mesh.Normals.size() / 3, "normal", fail);
  }
  else if (vt.empty())
  {
    fail("face corner '" + Str(token) + "' is not one of v, v/vt, v//vn, v/vt/vn");
  }
  return corner;
}

void ParseLine(const std::vector<std::string_view>& tokens, ObjMesh& mesh,
  std::vector<Corner>& corners, const LineError& fail)
{
  const std::string_view keyword = tokens[0];
  const size_t numArgs = tokens.size() - 1;
  if (keyword == "v")
  {
    // x y z, optionally w, or x y z r g b (a common vertex-colour extension).
    if (numArgs != 3 && numArgs != 4 && numArgs != 6 && numArgs != 7)
    {
      fail("'v' needs 3 coordinates (x y z [w] or x y z r g b), got " + std::to_string(numArgs));
    }
    for (size_t i = 1; i < tokens.size(); ++i)
    {
      float value = 0.0f;
      if (!text::ParseNumber(tokens[i], value))
      {
        fail("'v' has a bad number '" + Str(tokens[i]) + "'");
      }
      if (i <= 3)
      {
        mesh.Positions.push_back(value);
      }
    }
  }
  else if (keyword == "vt")
  {
    if (numArgs < 1 || numArgs > 3)
    {
      fail("'vt' needs 1 to 3 coordinates, got " + std::to_string(numArgs));
    }
    float uv[2] = { 0.0f, 0.0f };
    for (size_t i = 1; i < tokens.size(); ++i)
    {
      float value = 0.0f;
      if (!text::ParseNumber(tokens[i], value))
      {
        fail("'vt' has a bad number '" + Str(tokens[i]) + "'");
      }
      if (i <= 2)
      {
        uv[i - 1] = value;
      }
    }
    mesh.TexCoords.insert(mesh.TexCoords.end(), uv, uv + 2);
  }
  else if (keyword == "vn")
  {
    if (numArgs != 3)
    {
      fail("'vn' needs 3 components, got " + std::to_string(numArgs));
    }
    for (size_t i = 1; i < tokens.size(); ++i)
    {
      float value = 0.0f;
      if (!text::ParseNumber(tokens[i], value))
      {
        fail("'vn' has a bad number '" + Str(tokens[i]) + "'");
      }
      mesh.Normals.push_back(value);
    }
  }
  else if (keyword == "f")
  {
    if (numArgs < 3)
    {
      fail("'f' needs at least 3 corners, got " + std::to_string(numArgs));
    }
    corners.clear();
    for (size_t i = 1; i < tokens.size(); ++i)
    {
      corners.push_back(ParseCorner(tokens[i], mesh, fail));
    }
    // Fan from the first corner: exact for the convex quads of scanned faces.
    for (size_t i = 1; i + 1 < corners.size(); ++i)
    {
      for (const Corner& c : { corners[0], corners[i], corners[i + 1] })
      {
        mesh.Triangles.push_back(static_cast<uint32_t>(c.Position));
        mesh.CornerTexCoords.push_back(c.TexCoord);
        mesh.CornerNormals.push_back(c.Normal);
      }
    }
    ++mesh.NumberOfPolygons;
  }
  // Everything else (o g s usemtl mtllib l p vp cstype ...) carries nothing a morph
  // target needs.
}

std::string Stem(const std::string& path)
{
  return std::filesystem::path(path).stem().string();
}
} // namespace

ObjMesh ParseObj(std::istream& in, const std::string& sourceName)
{
  ObjMesh mesh;
  std::string line;
  std::vector<std::string_view> tokens;
  std::vector<Corner> corners;
  size_t lineNumber = 0;
  while (std::getline(in, line))
  {
    ++lineNumber;
    std::string_view view(line);
    const size_t hash = view.find('#');
    if (hash != std::string_view::npos)
    {
      view = view.substr(0, hash);
    }
    Tokenize(view, tokens);
    if (tokens.empty())
    {
      continue;
    }
    ParseLine(tokens, mesh, corners, LineError(sourceName, lineNumber));
  }
  if (in.bad())
  {
    throw InputError(sourceName + ": read error after line " + std::to_string(lineNumber));
  }
  if (mesh.Positions.empty())
  {
    throw InputError(sourceName + ": no vertices ('v' lines) found");
  }
  return mesh;
}

ObjMesh ReadObj(const std::string& path)
{
  // One read into memory: getline on a file stream is several times slower.
  std::istringstream in(text::ReadFile(path, "OBJ file"));
  return ParseObj(in, path);
}

MorphMesh ReadObjSet(
  const std::string& neutralPath, const std::vector<std::string>& shapePaths, double sparseCoverage)
{
  ObjMesh neutral = ReadObj(neutralPath);
  MorphMesh set(neutral.GetNumberOfPoints());
  std::vector<std::string> names{ "Neutral" };
  std::set<std::string> stems;
  auto& positions = set.AddAttribute<float>("Position", AttributeRole::Position, 3);
  positions.SetNeutral(neutral.Positions.data());
  for (const std::string& path : shapePaths)
  {
    const std::string name = Stem(path);
    if (!stems.insert(name).second)
    {
      throw InputError("OBJ set: shape file '" + path + "' has the same name '" + name +
        "' as another shape file");
    }
    const ObjMesh shape = ReadObj(path);
    if (shape.GetNumberOfPoints() != neutral.GetNumberOfPoints())
    {
      throw InputError("OBJ set: shape file '" + path + "' has " +
        std::to_string(shape.GetNumberOfPoints()) + " vertices, the neutral '" + neutralPath +
        "' has " + std::to_string(neutral.GetNumberOfPoints()) +
        " (shapes must share the neutral's vertex order)");
    }
    names.push_back(name);
    positions.AddAbsoluteTarget(shape.Positions.data(), sparseCoverage);
  }
  set.SetTargetNames(std::move(names));
  set.SetTriangles(std::move(neutral.Triangles));
  return set;
}

MorphMesh ReadObjSetDirectory(
  const std::string& directory, const std::string& neutralFileName, double sparseCoverage)
{
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(directory, error))
  {
    throw InputError("OBJ set: '" + directory + "' is not a directory");
  }
  const fs::path neutral = fs::path(directory) / neutralFileName;
  if (!fs::exists(neutral, error))
  {
    throw InputError("OBJ set: the neutral '" + neutral.string() + "' does not exist");
  }
  std::vector<std::string> shapes;
  for (const auto& entry : fs::directory_iterator(directory))
  {
    const fs::path& p = entry.path();
    if (entry.is_regular_file() && p.extension() == ".obj" && p.filename() != neutralFileName)
    {
      shapes.push_back(p.string());
    }
  }
  std::sort(shapes.begin(), shapes.end());
  return ReadObjSet(neutral.string(), shapes, sparseCoverage);
}
} // namespace morphnode
