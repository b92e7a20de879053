// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfSkin.h"

#include "GltfCheck.h"
#include "GltfSkinRead.h"

#include "base/Error.h"

#include <cmath>
#include <cstring>
#include <set>

namespace morphnode
{
glm::dmat4 GltfToGlm(const GltfMatrix& m)
{
  glm::dmat4 out;
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 4; ++r)
    {
      out[c][r] = m[static_cast<size_t>(c * 4 + r)];
    }
  }
  return out;
}

Skeleton GltfSkeleton(const GltfScene& scene)
{
  Skeleton skeleton;
  for (size_t n = 0; n < scene.Nodes.size(); ++n)
  {
    const GltfNode& node = scene.Nodes[n];
    Joint joint;
    joint.Name = GltfNodeName(scene, static_cast<int>(n));
    joint.Parent = node.Parent;
    if (node.HasMatrix)
    {
      joint.HasMatrix = true;
      joint.Matrix = GltfToGlm(node.Local);
    }
    else
    {
      joint.Translation = glm::dvec3(node.Translation[0], node.Translation[1], node.Translation[2]);
      joint.Rotation =
        glm::dquat(node.Rotation[3], node.Rotation[0], node.Rotation[1], node.Rotation[2]);
      joint.Scale = glm::dvec3(node.Scale[0], node.Scale[1], node.Scale[2]);
    }
    skeleton.AddJoint(joint);
  }
  skeleton.Validate();
  return skeleton;
}

SkinJoints GltfSkinJoints(const GltfScene& scene, int skin)
{
  if (skin < 0 || static_cast<size_t>(skin) >= scene.Skins.size())
  {
    throw InputError("glTF: no skin " + std::to_string(skin));
  }
  const GltfSkin& s = scene.Skins[static_cast<size_t>(skin)];
  SkinJoints out;
  out.Name = s.Name;
  out.Joints = s.Joints;
  for (const auto& m : s.InverseBind)
  {
    out.InverseBind.push_back(GltfToGlm(m));
  }
  return out;
}

namespace gltfskin
{
namespace
{
std::string SkinPointer(size_t s)
{
  return "/skins/" + std::to_string(s);
}

/// A MAT4 FLOAT accessor's matrices, bounds-checked (the loader's reader reads vectors only).
std::vector<GltfMatrix> ReadMatrices(const tinygltf::Model& model, int index,
  const std::string& source, const std::string& use,
  const std::map<int, std::vector<unsigned char>>* decoded)
{
  const std::string p = "/accessors/" + std::to_string(index);
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
  {
    throw InputError(
      source + ": " + use + ": accessor " + std::to_string(index) + " does not exist");
  }
  const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(index)];
  if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
  {
    throw InputError(
      source + ": " + p + ": the inverse bind matrices (" + use + ") must be MAT4 of FLOAT");
  }
  if (a.sparse.isSparse || a.bufferView < 0)
  {
    throw InputError(source + ": " + p + ": inverse bind matrices (" + use +
      ") must be stored in a bufferView (sparse ones are not supported)");
  }
  const size_t v = static_cast<size_t>(a.bufferView);
  if (v >= model.bufferViews.size())
  {
    throw InputError(source + ": " + p + ": no such bufferView " + std::to_string(v));
  }
  const tinygltf::BufferView& view = model.bufferViews[v];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
  {
    throw InputError(source + ": /bufferViews/" + std::to_string(v) + ": no such buffer");
  }
  // The view's bytes: decoded by the loader (EXT_meshopt_compression) or in its buffer.
  const auto found = decoded ? decoded->find(static_cast<int>(v)) : decltype(decoded->end()){};
  const bool isDecoded = decoded && found != decoded->end();
  const std::vector<unsigned char>& data =
    isDecoded ? found->second : model.buffers[static_cast<size_t>(view.buffer)].data;
  const size_t viewOffset = isDecoded ? 0 : view.byteOffset;
  const size_t viewLength = isDecoded ? found->second.size() : view.byteLength;
  const uint64_t stride = view.byteStride ? view.byteStride : 64;
  if (a.count == 0 || stride < 64 || viewOffset > data.size() ||
    viewLength > data.size() - viewOffset ||
    uint64_t(a.byteOffset) + stride * (a.count - 1) + 64 > viewLength)
  {
    throw InputError(source + ": " + p + ": the inverse bind matrices (" + use +
      ") run past bufferView " + std::to_string(v));
  }
  const unsigned char* bytes = data.data() + viewOffset + a.byteOffset;
  std::vector<GltfMatrix> out(a.count);
  for (size_t i = 0; i < a.count; ++i)
  {
    for (size_t k = 0; k < 16; ++k)
    {
      float f;
      std::memcpy(&f, bytes + i * stride + 4 * k, 4);
      out[i][k] = f;
    }
  }
  return out;
}
} // namespace

std::vector<GltfSkin> ReadSkins(const tinygltf::Model& model, const std::vector<GltfNode>& nodes,
  const std::string& source, const std::map<int, std::vector<unsigned char>>* decoded)
{
  std::vector<GltfSkin> skins;
  for (size_t s = 0; s < model.skins.size(); ++s)
  {
    const tinygltf::Skin& skin = model.skins[s];
    const std::string sp = SkinPointer(s);
    GltfSkin out;
    out.Name = skin.name;
    if (skin.joints.empty())
    {
      throw InputError(source + ": " + sp + "/joints: a skin needs at least one joint");
    }
    std::set<int> seen;
    for (size_t k = 0; k < skin.joints.size(); ++k)
    {
      const int j = skin.joints[k];
      if (j < 0 || static_cast<size_t>(j) >= nodes.size())
      {
        throw InputError(source + ": " + sp + "/joints/" + std::to_string(k) + ": node " +
          std::to_string(j) + " does not exist");
      }
      if (!seen.insert(j).second)
      {
        throw InputError(source + ": " + sp + "/joints/" + std::to_string(k) + ": node " +
          std::to_string(j) + " is a joint twice");
      }
    }
    out.Joints = skin.joints;
    if (skin.skeleton >= 0 && static_cast<size_t>(skin.skeleton) >= nodes.size())
    {
      throw InputError(source + ": " + sp + "/skeleton: node " + std::to_string(skin.skeleton) +
        " does not exist");
    }
    out.Skeleton = skin.skeleton;
    if (skin.inverseBindMatrices >= 0)
    {
      out.InverseBind =
        ReadMatrices(model, skin.inverseBindMatrices, source, sp + "/inverseBindMatrices", decoded);
      if (out.InverseBind.size() < out.Joints.size())
      {
        throw InputError(source + ": " + sp +
          "/inverseBindMatrices: " + std::to_string(out.InverseBind.size()) + " matrices for " +
          std::to_string(out.Joints.size()) + " joints");
      }
      out.InverseBind.resize(out.Joints.size());
    }
    else
    {
      out.InverseBind.assign(out.Joints.size(), GltfIdentity());
    }
    // Finite, affine, invertible: the skin concept's check, in glTF's words.
    Skeleton skeleton;
    for (size_t n = 0; n < nodes.size(); ++n)
    {
      Joint j;
      j.Name = nodes[n].Name.empty() ? "node" + std::to_string(n) : nodes[n].Name;
      skeleton.AddJoint(j);
    }
    SkinJoints joints;
    joints.Joints = out.Joints;
    for (const auto& m : out.InverseBind)
    {
      joints.InverseBind.push_back(GltfToGlm(m));
    }
    joints.Validate(skeleton, source + ": " + sp);
    skins.push_back(std::move(out));
  }
  for (size_t n = 0; n < model.nodes.size(); ++n)
  {
    const int skin = model.nodes[n].skin;
    if (skin >= 0 && static_cast<size_t>(skin) >= skins.size())
    {
      throw InputError(source + ": /nodes/" + std::to_string(n) + "/skin: skin " +
        std::to_string(skin) + " does not exist (the file has " + std::to_string(skins.size()) +
        ")");
    }
  }
  return skins;
}

void ReadInfluences(const tinygltf::Model& model, const tinygltf::Primitive& primitive, int skin,
  const std::vector<GltfSkin>& skins, const std::string& pp, const FloatReader& read,
  const std::string& source, GltfPart& part)
{
  const size_t points = part.GetNumberOfPoints();
  const size_t numJoints = skins.at(static_cast<size_t>(skin)).Joints.size();
  SkinInfluences influences;
  for (int set = 0;; ++set)
  {
    const std::string js = "JOINTS_" + std::to_string(set), ws = "WEIGHTS_" + std::to_string(set);
    const auto j = primitive.attributes.find(js), w = primitive.attributes.find(ws);
    if (j == primitive.attributes.end() && w == primitive.attributes.end())
    {
      if (set == 0)
      {
        throw InputError(source + ": " + pp +
          "/attributes: the mesh is skinned (its node has skin " + std::to_string(skin) +
          ") but the primitive has no JOINTS_0 and WEIGHTS_0");
      }
      break;
    }
    if (j == primitive.attributes.end() || w == primitive.attributes.end())
    {
      throw InputError(source + ": " + pp +
        "/attributes: " + (j == primitive.attributes.end() ? ws : js) + " needs " +
        (j == primitive.attributes.end() ? js : ws));
    }
    const auto accessor = [&](int index) -> const tinygltf::Accessor&
    { return model.accessors.at(static_cast<size_t>(index)); };
    const tinygltf::Accessor& ja = accessor(j->second);
    const tinygltf::Accessor& wa = accessor(w->second);
    if (ja.type != TINYGLTF_TYPE_VEC4 || ja.normalized ||
      (ja.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        ja.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))
    {
      throw InputError(source + ": " + pp + "/attributes/" + js + ": accessor " +
        std::to_string(j->second) +
        " must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT (not normalized)");
    }
    if (wa.type != TINYGLTF_TYPE_VEC4 ||
      !(wa.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        (wa.normalized &&
          (wa.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
            wa.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))))
    {
      throw InputError(source + ": " + pp + "/attributes/" + ws + ": accessor " +
        std::to_string(w->second) +
        " must be VEC4 of FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT");
    }
    const std::vector<float> joints = read(j->second, js + " of " + pp);
    const std::vector<float> weights = read(w->second, ws + " of " + pp);
    if (joints.size() != 4 * points || weights.size() != 4 * points)
    {
      throw InputError(
        source + ": " + pp + ": " + js + "/" + ws + " do not have one element per point");
    }
    influences.AddSet(joints, weights, points);
  }
  influences.Normalize(numJoints, source + ": " + pp + " (skin " + std::to_string(skin) + ")");
  part.Skin = skin;
  part.Influences = std::move(influences);
}

void SkinAtRest(GltfPart& part, const GltfScene& scene, const std::string& what)
{
  std::vector<GltfMatrix> world;
  for (const auto& node : scene.Nodes)
  {
    world.push_back(node.World);
  }
  GltfSkinPart(part, scene, world, what);
}
} // namespace gltfskin

namespace
{
/// Point i of `part` by an affine transform: its position to l p + t, its target position
/// deltas by l, its normal and the normal deltas by `nm` (the normal's transform up to a
/// positive factor), the normal renormalized and its deltas scaled alike (as the loader's
/// transforms: the blended normal, renormalized, is then the transformed normal of the
/// file's blend). Returns whether the position is finite in float.
bool TransformPoint(
  GltfPart& part, size_t i, const glm::dmat3& l, const glm::dvec3& t, const glm::dmat3& nm)
{
  float* p = &part.Positions[3 * i];
  const glm::dvec3 q = l * glm::dvec3(p[0], p[1], p[2]) + t;
  for (int k = 0; k < 3; ++k)
  {
    p[k] = static_cast<float>(q[k]);
  }
  double normalScale = 1.0;
  if (!part.Normals.empty())
  {
    float* m = &part.Normals[3 * i];
    const glm::dvec3 v = nm * glm::dvec3(m[0], m[1], m[2]);
    const double len = glm::length(v);
    normalScale = len > 0.0 ? 1.0 / len : 1.0;
    for (int k = 0; k < 3; ++k)
    {
      m[k] = static_cast<float>(v[k] * normalScale);
    }
  }
  for (auto& target : part.Targets)
  {
    float* d = &target.PositionDeltas[3 * i];
    const glm::dvec3 e = l * glm::dvec3(d[0], d[1], d[2]);
    for (int k = 0; k < 3; ++k)
    {
      d[k] = static_cast<float>(e[k]);
    }
    if (!target.NormalDeltas.empty())
    {
      float* dn = &target.NormalDeltas[3 * i];
      const glm::dvec3 f = nm * glm::dvec3(dn[0], dn[1], dn[2]);
      for (int k = 0; k < 3; ++k)
      {
        dn[k] = static_cast<float>(f[k] * normalScale);
      }
    }
  }
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}
} // namespace

void GltfSkinPart(GltfPart& part, const GltfScene& scene, const std::vector<GltfMatrix>& nodeWorlds,
  const std::string& what)
{
  if (part.Skin < 0 || part.TransformApplied || nodeWorlds.size() != scene.Nodes.size())
  {
    throw InputError(what + ": not a skinned part in bind space, or not one transform per node");
  }
  const SkinJoints joints = GltfSkinJoints(scene, part.Skin);
  std::vector<glm::dmat4> world(scene.Nodes.size());
  for (size_t n = 0; n < scene.Nodes.size(); ++n)
  {
    world[n] = GltfToGlm(nodeWorlds[n]);
  }
  const std::vector<glm::dmat4> matrices = joints.Matrices(world);
  const size_t n = part.GetNumberOfPoints();
  bool finite = true;
  for (size_t i = 0; i < n; ++i)
  {
    const glm::dmat4 b = BlendedMatrix(part.Influences, matrices, i);
    const glm::dmat3 l(b);
    const glm::dmat3 cof(glm::cross(l[1], l[2]), glm::cross(l[2], l[0]), glm::cross(l[0], l[1]));
    const glm::dmat3 nm = glm::determinant(l) < 0.0 ? -cof : cof;
    finite = TransformPoint(part, i, l, glm::dvec3(b[3]), nm) && finite;
  }
  if (!finite)
  {
    throw InputError(
      what + ": skin " + std::to_string(part.Skin) + " takes the points beyond the range of float");
  }
  part.TransformApplied = true;
}

GltfMatrix GltfFromGlm(const glm::dmat4& m)
{
  GltfMatrix out{};
  for (int c = 0; c < 4; ++c)
  {
    for (int r = 0; r < 4; ++r)
    {
      out[static_cast<size_t>(c * 4 + r)] = m[c][r];
    }
  }
  return out;
}

void GltfUnskinPart(GltfPart& part, const GltfScene& scene,
  const std::vector<GltfMatrix>& nodeWorlds, const std::string& what)
{
  if (part.Skin < 0 || !part.TransformApplied || nodeWorlds.size() != scene.Nodes.size())
  {
    throw InputError(what + ": not a skinned part in world space, or not one transform per node");
  }
  const SkinJoints joints = GltfSkinJoints(scene, part.Skin);
  std::vector<glm::dmat4> world(scene.Nodes.size());
  for (size_t n = 0; n < scene.Nodes.size(); ++n)
  {
    world[n] = GltfToGlm(nodeWorlds[n]);
  }
  const std::vector<glm::dmat4> matrices = joints.Matrices(world);
  const size_t n = part.GetNumberOfPoints();
  if (part.Influences.GetNumberOfPoints() != n)
  {
    throw InputError(what + ": " + std::to_string(part.Influences.GetNumberOfPoints()) +
      " skin influences for " + std::to_string(n) + " points");
  }
  for (size_t i = 0; i < n; ++i)
  {
    const glm::dmat4 b = BlendedMatrix(part.Influences, matrices, i);
    const glm::dmat3 l(b);
    const double det = glm::determinant(l);
    if (!(std::abs(det) > 1e-12) || !std::isfinite(det))
    {
      throw InputError(
        what + ": point " + std::to_string(i) + "'s blended joint matrix is singular");
    }
    // The inverse: p = l^-1 (q - t); a normal skinned by the cofactor matrix (det times the
    // inverse transpose) comes back by the transpose divided by det, its sign kept.
    const glm::dmat3 inv = glm::inverse(l);
    const glm::dmat3 back = glm::transpose(l) / det;
    TransformPoint(part, i, inv, -(inv * glm::dvec3(b[3])), det < 0.0 ? -back : back);
  }
  part.TransformApplied = false;
}

std::vector<GltfNode> GltfNodesFromSkeleton(Skeleton skeleton)
{
  skeleton.Validate();
  const size_t count = skeleton.GetNumberOfJoints();
  std::vector<GltfNode> nodes(count);
  for (size_t j = 0; j < count; ++j)
  {
    const Joint& joint = skeleton.GetJoint(j);
    GltfNode& node = nodes[j];
    node.Name = joint.Name;
    node.Parent = joint.Parent;
    node.InScene = true;
    if (joint.Parent >= 0)
    {
      nodes[static_cast<size_t>(joint.Parent)].Children.push_back(static_cast<int>(j));
    }
    const glm::dmat4 local = joint.Local();
    node.Local = GltfFromGlm(local);
    // TRS when the matrix is one: columns of the 3x3 are the rotation's scaled by positive
    // scales, orthogonal to each other, and the last row is (0, 0, 0, 1).
    glm::dvec3 scale(glm::length(glm::dvec3(local[0])), glm::length(glm::dvec3(local[1])),
      glm::length(glm::dvec3(local[2])));
    bool trs = scale.x > 0.0 && scale.y > 0.0 && scale.z > 0.0 && local[0][3] == 0.0 &&
      local[1][3] == 0.0 && local[2][3] == 0.0 && local[3][3] == 1.0;
    glm::dmat3 r(1.0);
    if (trs)
    {
      r = glm::dmat3(glm::dvec3(local[0]) / scale.x, glm::dvec3(local[1]) / scale.y,
        glm::dvec3(local[2]) / scale.z);
      trs = glm::determinant(r) > 0.0 && std::abs(glm::dot(r[0], r[1])) < 1e-9 &&
        std::abs(glm::dot(r[1], r[2])) < 1e-9 && std::abs(glm::dot(r[0], r[2])) < 1e-9;
    }
    if (trs)
    {
      const glm::dquat q = glm::normalize(glm::quat_cast(r));
      node.Translation = { { local[3][0], local[3][1], local[3][2] } };
      node.Rotation = { { q.x, q.y, q.z, q.w } };
      node.Scale = { { scale.x, scale.y, scale.z } };
      const double eps = 1e-12;
      for (double* v : { &node.Scale[0], &node.Scale[1], &node.Scale[2] })
      {
        if (std::abs(*v - 1.0) < eps)
        {
          *v = 1.0;
        }
      }
      node.Local = GltfComposeTrs(node.Translation, node.Rotation, node.Scale);
    }
    else
    {
      node.HasMatrix = true;
    }
  }
  std::vector<glm::dmat4> locals;
  for (const auto& node : nodes)
  {
    locals.push_back(GltfToGlm(node.Local));
  }
  const std::vector<glm::dmat4> worlds = skeleton.World(locals);
  for (size_t j = 0; j < count; ++j)
  {
    nodes[j].World = GltfFromGlm(worlds[j]);
  }
  return nodes;
}
} // namespace morphnode
