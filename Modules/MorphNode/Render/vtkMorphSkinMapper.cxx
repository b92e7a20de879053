// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMorphSkinMapper.h"

#include "vtkMorphSkinArrays.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLHelper.h"
#include "vtkOpenGLVertexBufferObject.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkShader.h"
#include "vtkShaderProgram.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkMorphSkinMapper);

namespace
{
/// Vertex uniform components left to VTK's own uniforms (matrices, clipping planes, coincident
/// offsets, ...) when counting the joints that fit.
constexpr int ReservedComponents = 256;

/// Vertex attribute names in the shader.
constexpr const char* JointsAttribute = "skinJoints";
constexpr const char* WeightsAttribute = "skinWeights";
constexpr const char* DeltasUniform = "skinDeltas";

/// The skin convention's arrays on a part (vtkMorphSkinArrays.h).
struct SkinArrays
{
  vtkFloatArray* Rows = nullptr; ///< SkinJointDeltas, three rows of four a joint
  vtkDataArray* Joints = nullptr;
  vtkDataArray* Weights = nullptr;
};

/// `poly`'s skin arrays when they are whole and finite (what both the drawing and the posed
/// bounds need); else false, with `why` saying what is wrong (empty: the part has no
/// SkinJointDeltas at all).
bool ReadSkin(vtkPolyData* poly, SkinArrays& skin, std::string& why)
{
  why.clear();
  vtkDataArray* deltas =
    poly ? poly->GetFieldData()->GetArray(vtkMorphSkinArrays::JointDeltasArray) : nullptr;
  if (!deltas)
  {
    return false;
  }
  auto* rows = vtkFloatArray::FastDownCast(deltas);
  vtkDataArray* indices = poly->GetFieldData()->GetArray(vtkMorphSkinArrays::JointIndicesArray);
  vtkDataArray* joints = poly->GetPointData()->GetArray(vtkMorphSkinArrays::JointsArray);
  vtkDataArray* weights = poly->GetPointData()->GetArray(vtkMorphSkinArrays::WeightsArray);
  const vtkIdType n = poly->GetNumberOfPoints();
  const vtkIdType count = deltas->GetNumberOfTuples();
  std::ostringstream message;
  if (!rows || deltas->GetNumberOfComponents() != 12)
  {
    message << vtkMorphSkinArrays::JointDeltasArray << " must be a vtkFloatArray of 12 components";
  }
  else if (!indices || indices->GetNumberOfTuples() != count)
  {
    message << vtkMorphSkinArrays::JointDeltasArray << " has " << count << " joints, the skin ("
            << vtkMorphSkinArrays::JointIndicesArray << ") "
            << (indices ? indices->GetNumberOfTuples() : 0);
  }
  else if (count < 1)
  {
    message << vtkMorphSkinArrays::JointDeltasArray << " has no joints";
  }
  else if (!joints || !weights || joints->GetNumberOfComponents() != 4 ||
    weights->GetNumberOfComponents() != 4 || joints->GetNumberOfTuples() != n ||
    weights->GetNumberOfTuples() != n)
  {
    message << vtkMorphSkinArrays::JointsArray << " and " << vtkMorphSkinArrays::WeightsArray
            << " must give 4 influences for each of the " << n << " points";
  }
  else
  {
    const float* d = rows->GetPointer(0);
    for (vtkIdType i = 0; i < 12 * count; ++i)
    {
      if (!std::isfinite(d[i]))
      {
        message << vtkMorphSkinArrays::JointDeltasArray << " of joint " << i / 12
                << " is not finite";
        break;
      }
    }
  }
  why = message.str();
  if (!why.empty())
  {
    return false;
  }
  skin.Rows = rows;
  skin.Joints = joints;
  skin.Weights = weights;
  return true;
}
}

//------------------------------------------------------------------------------
vtkMorphSkinMapper::vtkMorphSkinMapper()
{
  // The deltas apply to the coordinates as stored: never shifted and scaled.
  this->SetVBOShiftScaleMethod(vtkOpenGLVertexBufferObject::DISABLE_SHIFT_SCALE);
  this->MapDataArrayToVertexAttribute(
    JointsAttribute, vtkMorphSkinArrays::JointsArray, vtkDataObject::FIELD_ASSOCIATION_POINTS, -1);
  this->MapDataArrayToVertexAttribute(WeightsAttribute, vtkMorphSkinArrays::WeightsArray,
    vtkDataObject::FIELD_ASSOCIATION_POINTS, -1);
}

//------------------------------------------------------------------------------
vtkMorphSkinMapper::~vtkMorphSkinMapper() = default;

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::Say(int state, const std::string& message)
{
  this->SkinState = state;
  if (message == this->LastMessage)
  {
    return;
  }
  this->LastMessage = message;
  if (state == SKIN_DAMAGED)
  {
    vtkErrorMacro(<< message);
  }
  else if (state == SKIN_TOO_MANY_JOINTS)
  {
    vtkWarningMacro(<< message);
  }
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::CheckSkin()
{
  this->Deltas = nullptr;
  this->NumberOfJoints = 0;
  SkinArrays skin;
  std::string why;
  if (!ReadSkin(this->CurrentInput, skin, why))
  {
    this->Say(why.empty() ? SKIN_NONE : SKIN_DAMAGED,
      why.empty() ? "" : "the skin convention is damaged: " + why + "; nothing drawn");
    return;
  }
  const vtkIdType count = skin.Rows->GetNumberOfTuples();
  if (this->UniformJoints < 0)
  {
    GLint components = 0;
    glGetIntegerv(GL_MAX_VERTEX_UNIFORM_COMPONENTS, &components);
    this->UniformJoints = std::max(0, (components - ReservedComponents) / 12);
  }
  const int fit =
    this->MaxJoints > 0 ? std::min(this->MaxJoints, this->UniformJoints) : this->UniformJoints;
  if (count > fit)
  {
    std::ostringstream message;
    message << "the skin has " << count << " joints, the vertex shader takes " << fit
            << ": drawn as given (at rest); skin the points on the CPU instead";
    this->Say(SKIN_TOO_MANY_JOINTS, message.str());
    return;
  }
  this->NumberOfJoints = static_cast<int>(count);
  this->Deltas = skin.Rows->GetPointer(0);
  this->Say(SKIN_GPU, "");
}

//------------------------------------------------------------------------------
const std::vector<vtkIdType>& vtkMorphSkinMapper::UsedJoints(
  vtkDataArray* joints, vtkDataArray* weights, vtkIdType count)
{
  std::vector<std::pair<const void*, vtkMTimeType>> key = { { joints, joints->GetMTime() },
    { weights, weights->GetMTime() }, { nullptr, static_cast<vtkMTimeType>(count) } };
  if (key == this->UsedKey)
  {
    return this->Used;
  }
  // Once per influence arrays (the morph node passes the same arrays every frame).
  std::vector<char> used(static_cast<size_t>(count), 0);
  for (vtkIdType i = 0; i < joints->GetNumberOfTuples(); ++i)
  {
    for (int s = 0; s < 4; ++s)
    {
      if (weights->GetComponent(i, s) != 0.0)
      {
        // As the shader reads it: rounded, clamped to the skin's joints.
        const double j = std::round(joints->GetComponent(i, s));
        used[static_cast<size_t>(std::min<double>(std::max(j, 0.0), double(count - 1)))] = 1;
      }
    }
  }
  this->Used.clear();
  for (vtkIdType k = 0; k < count; ++k)
  {
    if (used[static_cast<size_t>(k)])
    {
      this->Used.push_back(k);
    }
  }
  this->UsedKey = std::move(key);
  return this->Used;
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::ComputeBounds()
{
  this->Superclass::ComputeBounds();
  vtkPolyData* poly = this->GetInput();
  if (!poly || !vtkMath::AreBoundsInitialized(this->Bounds))
  {
    return;
  }
  SkinArrays skin;
  std::string why;
  if (!ReadSkin(poly, skin, why))
  {
    return; // drawn as given, or not at all (CheckSkin says why)
  }
  vtkFloatArray* rows = skin.Rows;
  double b[6] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MIN, VTK_DOUBLE_MAX, VTK_DOUBLE_MIN, VTK_DOUBLE_MAX,
    VTK_DOUBLE_MIN };
  const double* rest = this->Bounds;
  for (vtkIdType k : this->UsedJoints(skin.Joints, skin.Weights, rows->GetNumberOfTuples()))
  {
    const float* d = rows->GetPointer(12 * k);
    for (int c = 0; c < 8; ++c)
    {
      const double p[3] = { rest[c & 1], rest[2 + ((c >> 1) & 1)], rest[4 + ((c >> 2) & 1)] };
      for (int r = 0; r < 3; ++r)
      {
        const double x = d[4 * r] * p[0] + d[4 * r + 1] * p[1] + d[4 * r + 2] * p[2] + d[4 * r + 3];
        if (!std::isfinite(x))
        {
          return; // damaged: nothing is drawn (CheckSkin)
        }
        b[2 * r] = std::min(b[2 * r], x);
        b[2 * r + 1] = std::max(b[2 * r + 1], x);
      }
    }
  }
  if (b[0] <= b[1])
  {
    std::copy(b, b + 6, this->Bounds);
  }
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::RenderPieceStart(vtkRenderer* ren, vtkActor* act)
{
  this->CheckSkin();
  this->Superclass::RenderPieceStart(ren, act);
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::RenderPieceDraw(vtkRenderer* ren, vtkActor* act)
{
  if (this->SkinState == SKIN_DAMAGED)
  {
    return; // said in CheckSkin
  }
  this->Superclass::RenderPieceDraw(ren, act);
}

//------------------------------------------------------------------------------
bool vtkMorphSkinMapper::GetNeedToRebuildShaders(
  vtkOpenGLHelper& cellBO, vtkRenderer* ren, vtkActor* act)
{
  const int joints = this->SkinState == SKIN_GPU ? this->NumberOfJoints : 0;
  const bool rebuild = this->Superclass::GetNeedToRebuildShaders(cellBO, ren, act);
  auto it = this->ShaderJoints.find(&cellBO);
  if (rebuild || it == this->ShaderJoints.end() || it->second != joints)
  {
    this->ShaderJoints[&cellBO] = joints;
    return true;
  }
  return false;
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::ReplaceShaderValues(
  std::map<vtkShader::Type, vtkShader*> shaders, vtkRenderer* ren, vtkActor* act)
{
  this->Superclass::ReplaceShaderValues(shaders, ren, act);
  ++this->NumberOfShaderBuilds;
  if (this->SkinState != SKIN_GPU)
  {
    return;
  }
  std::string vs = shaders[vtkShader::Vertex]->GetSource();
  const size_t main = vs.find("void main()");
  const size_t body = main == std::string::npos ? main : vs.find('{', main);
  if (body == std::string::npos)
  {
    vtkErrorMacro(<< "no main() in the vertex shader: drawn as given");
    return;
  }
  const int n = this->NumberOfJoints;
  // The shader's own names stay: after the skinned values are formed, the preprocessor
  // makes every later use of vertexMC / normalMC in main() read them instead, wherever
  // VTK's replacements put those uses.
  const bool normals = vs.find("in vec3 normalMC;") != std::string::npos;
  std::ostringstream dec;
  dec << "in vec4 " << JointsAttribute << ";\n"
      << "in vec4 " << WeightsAttribute << ";\n"
      << "uniform vec4 " << DeltasUniform << "[" << 3 * n << "];\n";
  std::ostringstream impl;
  impl << "\n"
       << "  // linear blend skinning (vtkMorphSkinMapper): rows of sum_k w_k Delta_k\n"
       << "  vec4 skinRow0 = vec4(0.0), skinRow1 = vec4(0.0), skinRow2 = vec4(0.0);\n"
       << "  for (int s = 0; s < 4; ++s)\n"
       << "  {\n"
       << "    int j = 3 * clamp(int(" << JointsAttribute << "[s] + 0.5), 0, " << n - 1 << ");\n"
       << "    float w = " << WeightsAttribute << "[s];\n"
       << "    skinRow0 += w * " << DeltasUniform << "[j];\n"
       << "    skinRow1 += w * " << DeltasUniform << "[j + 1];\n"
       << "    skinRow2 += w * " << DeltasUniform << "[j + 2];\n"
       << "  }\n"
       << "  vec4 skinVertexMC = vec4(dot(skinRow0, vertexMC), dot(skinRow1, vertexMC),\n"
       << "    dot(skinRow2, vertexMC), vertexMC.w);\n";
  if (normals)
  {
    impl << "  vec3 skinCol0 = vec3(skinRow0.x, skinRow1.x, skinRow2.x);\n"
         << "  vec3 skinCol1 = vec3(skinRow0.y, skinRow1.y, skinRow2.y);\n"
         << "  vec3 skinCol2 = vec3(skinRow0.z, skinRow1.z, skinRow2.z);\n"
         << "  // the cofactor: det(M) M^-T, by columns\n"
         << "  vec3 skinNormalMC = normalize(mat3(cross(skinCol1, skinCol2),\n"
         << "    cross(skinCol2, skinCol0), cross(skinCol0, skinCol1)) * normalMC);\n"
         << "#define normalMC skinNormalMC\n";
  }
  impl << "#define vertexMC skinVertexMC\n";
  vs.insert(body + 1, impl.str());
  vs.insert(main, dec.str());
  shaders[vtkShader::Vertex]->SetSource(vs);
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::SetMapperShaderParameters(
  vtkOpenGLHelper& cellBO, vtkRenderer* ren, vtkActor* act)
{
  this->Superclass::SetMapperShaderParameters(cellBO, ren, act);
  if (this->SkinState == SKIN_GPU && this->Deltas && cellBO.Program->IsUniformUsed(DeltasUniform))
  {
    cellBO.Program->SetUniform4fv(DeltasUniform, 3 * this->NumberOfJoints, this->Deltas);
  }
}

//------------------------------------------------------------------------------
void vtkMorphSkinMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  static const char* const states[] = { "none (drawn as given)", "GPU",
    "too many joints (drawn as given)", "damaged (nothing drawn)" };
  os << indent << "SkinState: " << states[this->SkinState] << "\n";
  os << indent << "NumberOfJoints: " << this->NumberOfJoints << "\n";
  os << indent << "MaxJoints: " << this->MaxJoints << "\n";
  os << indent << "NumberOfShaderBuilds: " << this->NumberOfShaderBuilds << "\n";
}
