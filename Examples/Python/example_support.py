# SPDX-License-Identifier: BSD-3-Clause
"""What the Python examples share, as the C++ programs share Modules/Applications/AppKit:
the optimizer presets by name (from vtkMorphNodeFilter, which spells them as
morph/OptimizerPresets.h does), WxH sizes, a head's parts as actors in their own colours
(AppKit/HeadActors), and a progress bar. The pipeline and the head pose are the wrapped
vtkMorphAvatarPipeline's, as in the C++ programs.
"""
import argparse
import math
import sys
import time

from morphnode import vtkMorphNodeFilter
from vtkmodules.vtkCommonCore import vtkFloatArray, vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData
from vtkmodules.vtkImagingCore import vtkImageExtractComponents, vtkImageThreshold
from vtkmodules.vtkImagingCore import vtkImageAppendComponents
from vtkmodules.vtkRenderingCore import vtkActor, vtkLightKit, vtkPolyDataMapper, vtkTexture

SKIN = (0.86, 0.72, 0.62)  # a part without a material


def preset_names():
    """The optimizer presets' names in their order: none, fixed-maximum, ..."""
    f = vtkMorphNodeFilter()
    names = []
    for preset in range(f.OPTIMIZER_NONE, f.OPTIMIZER_ERROR_BOUNDED + 1):
        f.SetOptimizerPreset(preset)
        names.append(f.GetOptimizerPresetAsString())
    return names


def preset(text):
    """argparse type: a preset's name (case-insensitive) or number -> its number."""
    names = preset_names()
    key = text.strip().lower()
    if key.isdigit() and int(key) < len(names):
        return int(key)
    if key in names:
        return names.index(key)
    known = ", ".join(f"{i}|{n}" for i, n in enumerate(names))
    raise argparse.ArgumentTypeError(f"unknown optimizer method {text!r} (known: {known})")


def size(text):
    """argparse type: WxH, both in [16, 8192] -> (W, H)."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expects WxH, e.g. 640x480; got {text!r}")
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise argparse.ArgumentTypeError(f"W and H must be in [16, 8192]; got {text!r}")
    return w, h


def head_parts(head):
    """The vtkPolyData parts of a head: the leaves of the reader's (or the morph filter's)
    composite in traversal order, or a vtkPolyData alone (AppKit HeadParts)."""
    if head is None:
        return []
    if head.IsA("vtkPolyData"):
        return [head]
    parts = []
    if head.IsA("vtkCompositeDataSet"):
        it = head.NewIterator()
        it.SkipEmptyNodesOn()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaf = it.GetCurrentDataObject()
            if leaf is not None and leaf.IsA("vtkPolyData"):
                parts.append(leaf)
            it.GoToNextItem()
    return parts


def head_bounds(head):
    """The bounds of all parts of a head, or None when it has no point."""
    bounds = None
    for part in head_parts(head):
        if part.GetNumberOfPoints() == 0:
            continue
        b = part.GetBounds()
        bounds = list(b) if bounds is None else [
            min(bounds[k], b[k]) if k % 2 == 0 else max(bounds[k], b[k]) for k in range(6)]
    return bounds


def _field_string(part, name):
    array = part.GetFieldData().GetAbstractArray(name)
    return array.GetValue(0) if array is not None and array.GetNumberOfValues() else ""


def part_color(part):
    """Linear RGBA of a part: field data BaseColor, or skin without a material."""
    base = part.GetFieldData().GetArray("BaseColor")
    if base is None or base.GetNumberOfValues() < 3 or not _field_string(part, "MaterialName"):
        return (*SKIN, 1.0)
    values = [base.GetValue(k) for k in range(min(4, base.GetNumberOfValues()))] + [1.0]
    return tuple(min(1.0, max(0.0, v)) if math.isfinite(v) else 1.0 for v in values[:4])


def point_colors(part, base):
    """COLOR_0 times the base colour as RGB bytes (array DisplayColors), or None."""
    color = part.GetPointData().GetArray("COLOR_0")
    if color is None or color.GetNumberOfComponents() < 3 or color.GetNumberOfTuples() != part.GetNumberOfPoints():
        return None
    try:
        import numpy
        from vtkmodules.util import numpy_support
    except ImportError:
        return None  # the base colour alone
    scale = 1.0 / 255.0 if color.IsA("vtkUnsignedCharArray") else 1.0
    rgb = numpy_support.vtk_to_numpy(color)[:, :3] * scale * numpy.asarray(base[:3])
    array = numpy_support.numpy_to_vtk(numpy.rint(rgb.clip(0.0, 1.0) * 255.0).astype(numpy.uint8), deep=1,
                                       array_type=vtkUnsignedCharArray().GetDataType())
    array.SetName("DisplayColors")
    return array


def _field_number(part, name, component=0, default=0.0):
    array = part.GetFieldData().GetArray(name)
    if array is None or array.GetNumberOfValues() <= component:
        return default
    return array.GetValue(component)


def part_texture(part, slot, srgb, mode="BLEND", cutoff=0.5):
    """The texture of field data <slot>Image (vtkMorphTargetReader, docs/materials.md), as
    AppKit/HeadActors makes it: OPAQUE drops alpha, MASK makes it 0 or 1 at the cutoff.
    None when the part has no such image."""
    pixels = part.GetFieldData().GetArray(slot + "Image")
    width = int(_field_number(part, slot + "ImageSize", 0))
    height = int(_field_number(part, slot + "ImageSize", 1))
    if pixels is None or pixels.GetNumberOfComponents() != 4 or width * height != pixels.GetNumberOfTuples():
        return None
    image = vtkImageData()
    image.SetDimensions(width, height, 1)
    image.GetPointData().SetScalars(pixels)
    rgb = vtkImageExtractComponents()
    rgb.SetInputData(image)
    rgb.SetComponents(0, 1, 2)
    source = rgb
    if mode != "OPAQUE":
        alpha = vtkImageExtractComponents()
        alpha.SetInputData(image)
        alpha.SetComponents(3)
        joined = vtkImageAppendComponents()
        joined.AddInputConnection(rgb.GetOutputPort())
        if mode == "MASK":
            cut = vtkImageThreshold()
            cut.SetInputConnection(alpha.GetOutputPort())
            cut.ThresholdByUpper(cutoff * 255.0 - 1e-6)
            cut.SetInValue(255)
            cut.SetOutValue(0)
            cut.ReplaceInOn()
            cut.ReplaceOutOn()
            joined.AddInputConnection(cut.GetOutputPort())
        else:
            joined.AddInputConnection(alpha.GetOutputPort())
        source = joined
    source.Update()
    texture = vtkTexture()
    texture.SetInputData(source.GetOutput())
    texture.SetUseSRGBColorSpace(srgb)
    texture.SetInterpolate(int(_field_number(part, slot + "Sampler", 0)) != 9728)
    minification = int(_field_number(part, slot + "Sampler", 1))
    texture.SetMipmap(minification == 0 or minification >= 9984)
    texture.SetRepeat(int(_field_number(part, slot + "Sampler", 2, 10497)) != 33071)
    return texture


def apply_material(part, actor, color):
    """The part's glTF material drawn with VTK's PBR, as AppKit/HeadActors draws it (base
    colour, metallic, roughness, emissive, alpha modes, double-sided, unlit); False when the
    part has no material fields."""
    if part.GetFieldData().GetArray("MetallicFactor") is None:
        return False
    prop = actor.GetProperty()
    mode = _field_string(part, "AlphaMode")
    cutoff = _field_number(part, "AlphaCutoff", 0, 0.5)
    prop.SetInterpolationToPBR()
    prop.SetColor(color[:3])
    prop.SetMetallic(_field_number(part, "MetallicFactor", 0, 1.0))
    prop.SetRoughness(_field_number(part, "RoughnessFactor", 0, 1.0))
    prop.SetEmissiveFactor(*[_field_number(part, "EmissiveFactor", k) for k in range(3)])
    prop.SetBackfaceCulling(_field_number(part, "DoubleSided") == 0)
    prop.SetOpacity(color[3] if mode == "BLEND" else 1.0)
    base = None
    if part.GetPointData().GetTCoords() is not None:
        base = part_texture(part, "BaseColor", True, mode or "OPAQUE", cutoff)
        if base is not None:
            prop.SetBaseColorTexture(base)
        emissive = part_texture(part, "Emissive", True, "OPAQUE")
        if emissive is not None:
            prop.SetEmissiveTexture(emissive)
    if _field_number(part, "Unlit") != 0:
        prop.SetInterpolationToFlat()
        prop.LightingOff()
        prop.RemoveAllTextures()
        if base is not None:
            actor.SetTexture(base)
    return True


class HeadActors:
    """One actor per part of a head, each in its own colour (BaseColor x COLOR_0), all moved
    by one transform (the head pose): the Python twin of AppKit/HeadActors, which says why
    one actor per part rather than vtkCompositePolyDataMapper2 (VTK 9.1's composite
    attributes have no per-block material nor per-block scalar visibility)."""

    def __init__(self, head, renderer, pose=None):
        self.parts = []
        for part in head_parts(head):
            color = part_color(part)
            display = vtkPolyData()
            mapper = vtkPolyDataMapper()
            mapper.SetInputData(display)
            actor = vtkActor()
            actor.SetMapper(mapper)
            if pose is not None:
                actor.SetUserTransform(pose)
            prop = actor.GetProperty()
            if not apply_material(part, actor, color):
                prop.SetColor(color[:3])
                prop.SetOpacity(color[3])
                prop.SetAmbient(0.08)
                prop.SetDiffuse(0.92)
                prop.SetSpecular(0.15)
                prop.SetSpecularPower(20.0)
            entry = {"display": display, "mapper": mapper, "actor": actor,
                     "colors": point_colors(part, color), "points": part.GetNumberOfPoints(),
                     "name": _field_string(part, "PartName")}
            self.parts.append(entry)
            self._take(entry, part)
            self._own_colors(entry)
            renderer.AddActor(actor)

    @staticmethod
    def _take(entry, part):
        entry["display"].ShallowCopy(part)  # our own array list: the filter's output stays as it is
        if entry["colors"] is not None:
            entry["display"].GetPointData().AddArray(entry["colors"])

    @staticmethod
    def _own_colors(entry):
        mapper = entry["mapper"]
        if entry["colors"] is not None:
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray("DisplayColors")
            mapper.SetColorModeToDirectScalars()
            mapper.ScalarVisibilityOn()
        else:
            mapper.ScalarVisibilityOff()

    def update(self, head):
        """The parts' new geometry (the same parts, at another time). False if they differ."""
        parts = head_parts(head)
        if len(parts) != len(self.parts) or any(
                p.GetNumberOfPoints() != e["points"] for p, e in zip(parts, self.parts)):
            return False
        for entry, part in zip(self.parts, parts):
            self._take(entry, part)
        return True

    def color_by(self, name, lut):
        """Every part coloured by point array `name` through `lut` over the range of all
        parts; parts without it keep their colour. The range, or None if no part has it."""
        ranges = [e["display"].GetPointData().GetArray(name).GetRange() for e in self.parts
                  if e["display"].GetPointData().GetArray(name) is not None]
        if not ranges:
            return None
        rng = (min(r[0] for r in ranges), max(r[1] for r in ranges))
        for entry in self.parts:
            mapper = entry["mapper"]
            if entry["display"].GetPointData().GetArray(name) is None:
                self._own_colors(entry)
                continue
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray(name)
            mapper.SetColorModeToMapScalars()
            mapper.SetLookupTable(lut)
            mapper.UseLookupTableScalarRangeOff()
            mapper.SetScalarRange(rng)
            mapper.ScalarVisibilityOn()
        return rng


def make_environment(scale=0.3):
    """The image-based lighting of AppKit HeadActors::MakeEnvironment: an equirectangular
    neutral sky, horizon and floor made here (linear RGB, 64 x 32; nothing downloaded)."""
    width, height = 64, 32
    values = vtkFloatArray()
    values.SetNumberOfComponents(3)
    values.SetNumberOfTuples(width * height)
    for y in range(height):
        up = (y + 0.5) / height * 2.0 - 1.0
        t = math.sqrt(abs(up))
        if up >= 0:
            a, b = (0.95, 0.92, 0.88), (0.9, 0.9, 0.92)
        else:
            a, b = (0.7, 0.67, 0.63), (0.3, 0.28, 0.26)
        rgb = [scale * (a[c] + (b[c] - a[c]) * t) for c in range(3)]
        for x in range(width):
            values.SetTuple3(y * width + x, *rgb)
    image = vtkImageData()
    image.SetDimensions(width, height, 1)
    image.GetPointData().SetScalars(values)
    texture = vtkTexture()
    texture.SetInputData(image)
    texture.InterpolateOn()
    texture.MipmapOn()
    return texture


def set_up_view(renderer, bounds, zoom=1.0):
    """A white light kit, image-based lighting (make_environment), depth peeling, a gradient
    background and the camera in front of the face (it looks along +Z, +Y up), the head
    filling the view (AppKit HeadActors::SetUpView)."""
    renderer.UseImageBasedLightingOn()
    renderer.SetEnvironmentTexture(make_environment())
    renderer.SetUseDepthPeeling(True)
    renderer.SetMaximumNumberOfPeels(6)
    renderer.SetOcclusionRatio(0.0)
    renderer.RemoveAllLights()
    lights = vtkLightKit()
    lights.SetKeyLightIntensity(0.85)
    for set_warmth in (lights.SetKeyLightWarmth, lights.SetFillLightWarmth, lights.SetBackLightWarmth,
                       lights.SetHeadLightWarmth):
        set_warmth(0.5)  # white lights: glTF's colours are drawn gamma-correct
    lights.AddLightsToRenderer(renderer)
    renderer.SetBackground(0.15, 0.16, 0.2)
    renderer.SetBackground2(0.32, 0.34, 0.42)
    renderer.GradientBackgroundOn()
    # A portrait: the head from the top down to the neck (the lowest 15 % of the bounds may
    # leave the frame), the face a little below the middle; from the front, 30 degrees.
    b = bounds
    bottom = b[2] + 0.15 * (b[3] - b[2])
    height = 1.12 * (b[3] - bottom)
    center = (0.5 * (b[0] + b[1]), 0.5 * (bottom + b[3]) + 0.04 * height, 0.5 * (b[4] + b[5]))
    distance = 0.5 * height / math.tan(math.radians(15.0)) / (zoom if zoom > 0 else 1.0)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(center)
    camera.SetPosition(center[0], center[1], b[5] + distance)  # the height fits at the front
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(30.0)
    d = math.dist(b[0::2], b[1::2])  # far enough for a head turned by the pose
    renderer.ResetCameraClippingRange(b[0] - d, b[1] + d, b[2] - d, b[3] + d, b[4] - d, b[5] + d)
    # Smooth edges without multisampling; FXAA on a multisampled window renders black under
    # Xvfb, so only on a window without it (call this after adding the renderer to it).
    window = renderer.GetRenderWindow()
    renderer.SetUseFXAA(window is not None and window.GetMultiSamples() == 0)


class ProgressBar:
    """On stderr: in place on a terminal, every 10 % in a log; the time left, then taken."""

    def __init__(self, total, unit="frames", enabled=True):
        self.total, self.unit, self.enabled = total, unit, enabled
        self.tty, self.begin, self.decile = sys.stderr.isatty(), time.monotonic(), -1

    def show(self, done):
        if not self.enabled:
            return
        last = done >= self.total
        percent = 100 * done // self.total if self.total else 100
        if not self.tty and not last and percent // 10 == self.decile:
            return
        self.decile = percent // 10
        elapsed = time.monotonic() - self.begin
        eta = elapsed * (self.total - done) / done if done else 0.0
        bar = "#" * (30 * done // self.total if self.total else 30)
        line = (f"[{bar:.<30}] {percent:3d}%  {done}/{self.total} {self.unit}  "
                + (f"done in {elapsed:.1f} s" if last else f"ETA {eta:.1f} s"))
        print(("\r" if self.tty else "") + line, end="\n" if (last or not self.tty) else "",
              file=sys.stderr, flush=True)
