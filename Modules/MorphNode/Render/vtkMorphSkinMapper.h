// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphSkinMapper
 * @brief   draws a skinned part posed by vtkMorphSkinFilter's "pose only" output, skinning
 *          every vertex in the vertex shader
 *
 * Input: one vtkPolyData, a skinned part as vtkMorphSkinFilter gives it with SkinPoints off:
 * its points and normals in the rest pose (morphed), point data `SkinJoints` and
 * `SkinWeights` (4 components: one set of four influences) and field data
 * `SkinJointDeltas` (12 components, one tuple per joint of the skin, the rows of
 * J_k(pose) J_k(rest)^-1; the skin convention, vtkMorphSkinArrays.h and docs/avatars.md).
 * The mapper maps SkinJoints and SkinWeights as vertex attributes, sends the deltas as a
 * uniform array (three vec4 per joint) and, in the vertex shader, blends the point's four
 * matrices (linear blend skinning: M = sum w_k Delta_k), moves the position by M and the
 * normal by M's cofactor, renormalized: what morphnode::RestSkin does on the CPU. The points
 * are uploaded only when they change (a morph); a new pose is one uniform array per draw,
 * and the shader is built again only when the number of joints changes.
 *
 * When it draws as given (GetSkinState):
 * - SKIN_NONE: no SkinJointDeltas: drawn as a plain vtkOpenGLPolyDataMapper draws;
 * - SKIN_TOO_MANY_JOINTS: the joints do not fit the vertex uniforms
 *   (GL_MAX_VERTEX_UNIFORM_COMPONENTS, less a reserve for VTK's own uniforms; or
 *   MaxJoints when set): drawn at rest, with a warning (vtkMorphSkinFilter with SkinPoints
 *   on moves the points instead);
 * - SKIN_DAMAGED: the convention is damaged (SkinJointDeltas without 12 components or with
 *   another tuple count than SkinJointIndices, non-finite deltas, SkinJoints/SkinWeights
 *   missing or not 4 components per point): nothing is drawn, with an error saying why.
 * Errors and warnings are said once per change of the reason, not every frame.
 *
 * Vertex coordinates are never shifted and scaled (DISABLE_SHIFT_SCALE): the deltas apply
 * to the coordinates as stored. Bounds are those of the posed part (ComputeBounds).
 *
 * No ParaView proxy: ParaView draws with its own representations (docs/paraview.md).
 *
 * @sa vtkMorphSkinFilter vtkOpenGLPolyDataMapper morphnode::RestSkin
 */

#ifndef vtkMorphSkinMapper_h
#define vtkMorphSkinMapper_h

#include "vtkMorphNodeRenderModule.h" // For export macro
#include "vtkOpenGLPolyDataMapper.h"

#include <map>     // For std::map
#include <string>  // For std::string
#include <utility> // For std::pair
#include <vector>  // For std::vector

class VTKMORPHNODERENDER_EXPORT vtkMorphSkinMapper : public vtkOpenGLPolyDataMapper
{
public:
  static vtkMorphSkinMapper* New();
  vtkTypeMacro(vtkMorphSkinMapper, vtkOpenGLPolyDataMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SkinStates
  {
    SKIN_NONE = 0,            ///< no SkinJointDeltas: drawn as given
    SKIN_GPU = 1,             ///< skinned in the vertex shader
    SKIN_TOO_MANY_JOINTS = 2, ///< the joints do not fit the uniforms: drawn as given, warned
    SKIN_DAMAGED = 3          ///< a damaged convention: nothing drawn, an error
  };

  /** What the last draw did (SKIN_NONE before). */
  vtkGetMacro(SkinState, int);
  /** The joints of the last draw's skin (0 without). */
  vtkGetMacro(NumberOfJoints, int);

  ///@{
  /**
   * The most joints skinned on the GPU (0, the default: as many as the vertex uniforms take).
   * A part with more is drawn as given, with a warning.
   */
  vtkSetClampMacro(MaxJoints, int, 0, VTK_INT_MAX);
  vtkGetMacro(MaxJoints, int);
  ///@}

  /**
   * Shader sources built so far (VTK builds a source when a primitive's shader must change;
   * a new pose never builds one). For checking that the pose goes by uniforms only.
   */
  vtkGetMacro(NumberOfShaderBuilds, int);

protected:
  vtkMorphSkinMapper();
  ~vtkMorphSkinMapper() override;

  /**
   * The input's bounds, or with valid SkinJointDeltas the bounds of the posed part: the
   * rest bounds' corners moved by every joint some point has a weight on (a blended point
   * lies in the convex hull of its joints' images of it), so that culling and the camera's
   * clipping range see where the part is drawn.
   */
  void ComputeBounds() override;

  void RenderPieceStart(vtkRenderer* ren, vtkActor* act) override;
  void RenderPieceDraw(vtkRenderer* ren, vtkActor* act) override;
  bool GetNeedToRebuildShaders(vtkOpenGLHelper& cellBO, vtkRenderer* ren, vtkActor* act) override;
  void ReplaceShaderValues(
    std::map<vtkShader::Type, vtkShader*> shaders, vtkRenderer* ren, vtkActor* act) override;
  void SetMapperShaderParameters(vtkOpenGLHelper& cellBO, vtkRenderer* ren, vtkActor* act) override;

  int SkinState = SKIN_NONE;
  int NumberOfJoints = 0;
  int MaxJoints = 0;
  int NumberOfShaderBuilds = 0;

private:
  vtkMorphSkinMapper(const vtkMorphSkinMapper&) = delete;
  void operator=(const vtkMorphSkinMapper&) = delete;

  /// The skin state of the current input (SkinState, NumberOfJoints, Deltas), said once.
  void CheckSkin();
  void Say(int state, const std::string& message);

  /// The joints some point has a weight on (ComputeBounds), for these influence arrays.
  const std::vector<vtkIdType>& UsedJoints(
    vtkDataArray* joints, vtkDataArray* weights, vtkIdType count);
  std::vector<vtkIdType> Used;
  std::vector<std::pair<const void*, vtkMTimeType>> UsedKey;

  const float* Deltas = nullptr; ///< the current input's SkinJointDeltas (rows)
  int UniformJoints = -1;        ///< joints the vertex uniforms take (-1: not asked yet)
  std::string LastMessage;
  std::map<const vtkOpenGLHelper*, int> ShaderJoints; ///< per primitive: built for (0: plain)
};

#endif
