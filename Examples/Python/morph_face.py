#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Read a face with morph targets, set weights, optionally optimize, render to a PNG.

A glTF file is read as a whole scene (every part: skin, mouth, teeth, tongue, eyes, ...),
morphed as one head and drawn one actor per part in its own colour; an OBJ set is one mesh.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/morph_face.py \
        Data/DefaultFace/default_head.glb --weight O=0.8 --weight BrowsUp=0.5 --png o.png
"""
import argparse
import math
import os
import sys

from example_support import HeadActors, head_bounds, preset, preset_names, set_up_view, size
from morphnode import vtkMorphNodeFilter, vtkMorphTargetReader

import vtkmodules.vtkInteractionStyle  # noqa: F401  (default interactor style)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the render backend)
from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
from vtkmodules.vtkRenderingCore import (
    vtkRenderer,
    vtkRenderWindow,
    vtkRenderWindowInteractor,
    vtkWindowToImageFilter,
)

DEFAULT_FACE = os.path.join(os.path.dirname(__file__), "..", "..", "Data", "DefaultFace", "default_head.glb")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("face", nargs="?", default=DEFAULT_FACE)
    parser.add_argument("--weight", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--mode", choices=["strict", "normalize", "relative"], default="normalize")
    parser.add_argument("--method", type=preset, default=0,
                        help="optimizer: 0-4 or " + ", ".join(preset_names()) + " (default none)")
    parser.add_argument("--threshold", type=float, default=0.1,
                        help="th_fix of the threshold methods (default 0.1, as MorphAvatar)")
    parser.add_argument("--max-error", type=float, default=None,
                        help="bound of error-bounded, model units (default 0.5 %% of the face's diagonal, as MorphAvatar)")
    parser.add_argument("--color", help="AnimatedRegion or Distance_<target>")
    parser.add_argument("--png", help="render offscreen to this file")
    parser.add_argument("--size", type=size, default=(600, 600), help="WxH (default 600x600)")
    args = parser.parse_args(argv)

    reader = vtkMorphTargetReader()
    reader.SetFileName(args.face)
    morph = vtkMorphNodeFilter()
    morph.SetInputConnection(reader.GetOutputPort())
    getattr(morph, "SetWeightModeTo" + args.mode.capitalize())()
    morph.SetThreshold(args.threshold)
    if args.max_error is None:
        # MorphAvatar's default: 0.5 % of the face's diagonal (a zero bound prunes nothing).
        reader.Update()
        rest = head_bounds(reader.GetOutputDataObject(0))
        if rest is None:
            print(f"{args.face}: no face to morph (see the errors above)", file=sys.stderr)
            return 1
        args.max_error = 0.005 * math.sqrt(sum((rest[2 * i + 1] - rest[2 * i]) ** 2 for i in range(3)))
    morph.SetMaxVertexError(args.max_error)
    morph.SetOptimizerPreset(args.method)
    morph.SetGenerateDistanceArrays(bool(args.color))
    for item in args.weight:
        name, _, value = item.partition("=")
        morph.SetWeightByName(name, float(value))
    morph.Update()
    face = morph.GetOutputDataObject(0)  # the input's structure: parts, or one vtkPolyData
    bounds = head_bounds(face)
    if bounds is None:
        print("nothing to show (see the errors above)", file=sys.stderr)
        return 1
    print(f"{args.face}: {morph.GetNumberOfTargets()} targets, {morph.GetActiveTargetCount()} active, "
          f"error bound {morph.GetErrorBound():g} (method {morph.GetOptimizerPresetAsString()}, "
          f"threshold {args.threshold:g}, max error {args.max_error:g})")

    renderer = vtkRenderer()
    head = HeadActors(face, renderer)  # one actor per part, in its own colour
    if args.color:
        still_to_moving = vtkLookupTable()  # blue where the face stays still, red where it moves
        still_to_moving.SetHueRange(0.667, 0.0)
        if head.color_by(args.color, still_to_moving) is None:
            print(f"no point array {args.color!r}", file=sys.stderr)
            return 1
        bar = vtkScalarBarActor()
        bar.SetLookupTable(still_to_moving)
        bar.SetTitle(args.color)
        bar.SetMaximumWidthInPixels(90)
        renderer.AddActor2D(bar)
    window = vtkRenderWindow()
    window.SetSize(*args.size)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    set_up_view(renderer, bounds)
    if args.png:
        window.OffScreenRenderingOn()
        window.Render()
        grab = vtkWindowToImageFilter()
        grab.SetInput(window)
        writer = vtkPNGWriter()
        writer.SetFileName(args.png)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
        print("wrote", args.png)
        return 0
    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    window.Render()
    interactor.Start()
    return 0


if __name__ == "__main__":
    sys.exit(main())
