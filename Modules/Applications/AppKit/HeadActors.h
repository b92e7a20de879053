// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file HeadActors.h
/// @brief A head on screen: every part of the reader's (or the morph filter's) composite
/// (docs/scene.md), or one vtkPolyData, as one actor per part in the part's own colour:
/// field data `BaseColor` (linear RGBA) times point data `COLOR_0` (RGBA) where the part has
/// it, as glTF defines a material's colour; a part without a material (an OBJ set, a GLB
/// without materials) is skin-coloured. A part with the glTF material fields of
/// vtkMorphTargetReader (docs/materials.md) is drawn with VTK's PBR: base colour texture
/// (sRGB), metallic-roughness, emissive, alpha modes (MASK as a 0/1 alpha at the cutoff,
/// BLEND translucent, both drawn after the opaque parts by depth peeling), back faces
/// culled unless double-sided, unlit; SetUpView lights it with an environment made here. One
/// transform (the head pose) moves every part.
///
/// Why one actor per part and not vtkCompositePolyDataMapper2: VTK 9.1's composite display
/// attributes set a colour, an opacity and a visibility per block, but not a material
/// (specular, back-face culling), nor whether a block's scalars are shown; a part with
/// COLOR_0 next to one without would need one scalar array on every block. Per part, each
/// actor has its own property (colour, shine, opacity) and colour array, and the eyes
/// could be turned by their own transform; a head has about a dozen parts, so the number of
/// draw calls does not matter (BenchAvatarFrameRate).

#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <memory>
#include <string>
#include <vector>

class vtkActor;
class vtkDataObject;
class vtkLinearTransform;
class vtkPolyData;
class vtkPolyDataMapper;
class vtkRenderer;
class vtkScalarsToColors;
class vtkTexture;
class vtkUnsignedCharArray;

namespace morphnode
{
namespace appkit
{
/// The polydata leaves of `head` in traversal order (a vtkPolyData alone is its own only
/// part); empty leaves left out.
std::vector<vtkPolyData*> HeadParts(vtkDataObject* head);

/// The bounds of all parts of `head` (x0, x1, y0, y1, z0, z1). False when it has no point.
bool HeadBounds(vtkDataObject* head, double bounds[6]);

/// The skin colour of a part without a material.
constexpr double SkinColor[3] = { 0.86, 0.72, 0.62 };

class HeadActors
{
public:
  HeadActors();
  ~HeadActors();

  /// One actor per part of `head` (see HeadParts), added to `renderer`, each with `pose` as
  /// its user transform (may be null). False when `head` has no part with points.
  bool Build(vtkDataObject* head, vtkRenderer* renderer, vtkLinearTransform* pose);

  /// The parts' new geometry: `head` is the composite (or polydata) of Build at another time,
  /// with the same parts (a morph filter's output; a part shown at another mesh level, with
  /// point data OriginalPointId, is the same part, its colours and tangents made per level).
  /// False when the parts differ.
  bool Update(vtkDataObject* head);

  /// Colours every part by a point array (e.g. AnimatedRegion, Distance_O) through `lut`
  /// over the range of all parts together; parts without it keep their colour. Returns the
  /// range in `range`; false when no part has the array.
  bool ColorBy(const std::string& array, vtkScalarsToColors* lut, double range[2]);

  /// Draw with vtkMorphSkinMapper (skinning in the vertex shader; parts without the skin
  /// filter's SkinJointDeltas are drawn as given), for a vtkMorphSkinFilter that poses
  /// only (SkinPoints off). Default off: plain mappers. Set before Build.
  void SetSkinOnGpu(bool on) { this->SkinOnGpu = on; }
  bool GetSkinOnGpu() const { return this->SkinOnGpu; }

  int GetNumberOfParts() const { return static_cast<int>(this->Parts.size()); }
  vtkActor* GetActor(int part) const;
  /// The part's name (field data PartName), or "part <i>".
  std::string GetPartName(int part) const;

  /// Sets up `renderer` for a head: a light kit (key, fill and back lights), a gradient
  /// background, and the camera in front of the face (the head looks along +Z, +Y up) so
  /// that `bounds` fill most of the view, a little above the middle. Call it after adding
  /// `renderer` to its window: on a window without multisampling it turns FXAA on.
  static void SetUpView(vtkRenderer* renderer, const double bounds[6], double zoom = 1.0);

  /// The lights of SetUpView alone: the light kit (white), image-based lighting from
  /// MakeEnvironment (optional: it costs a few seconds per renderer on a software GL, where
  /// it is computed), depth peeling for the translucent parts.
  static void SetUpLights(vtkRenderer* renderer, bool imageBasedLighting = true);

  /// The environment of image-based lighting SetUpView gives the renderer: an
  /// equirectangular sky, horizon and floor made here (linear RGB, 64 x 32).
  static vtkSmartPointer<vtkTexture> MakeEnvironment();

private:
  HeadActors(const HeadActors&) = delete;
  void operator=(const HeadActors&) = delete;

  struct Part;
  std::vector<std::unique_ptr<Part>> Parts;
  bool SkinOnGpu = false;
};
} // namespace appkit
} // namespace morphnode
