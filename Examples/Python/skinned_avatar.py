#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""A skinned avatar at rest and animated: the head turned on its neck, the eyes looking
aside in their sockets (eye joints), a vowel on the lips (morph targets), the A-pose arms
lowered; framed on the face (docs/avatars.md).

The pipeline: vtkMorphTargetReader (the skinned parts at rest, with their skin) ->
vtkMorphNodeFilter (the weights, morphed at rest) -> vtkMorphSkinFilter (the bones posed,
the morphed parts re-skinned). Two pictures: --rest (the reader's pose) and --png (the
animated one), or a window showing both side by side.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/skinned_avatar.py \
        ../shared/data/makehuman-avatar/makehuman_avatar.glb --rest rest.png --png oh.png
"""
import argparse
import os
import sys

from example_support import HeadActors, set_up_view, size
from morphnode import vtkMorphNodeFilter, vtkMorphSkinFilter, vtkMorphTargetReader

import vtkmodules.vtkInteractionStyle  # noqa: F401  (default interactor style)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the render backend)
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (
    vtkRenderer,
    vtkRenderWindow,
    vtkRenderWindowInteractor,
    vtkWindowToImageFilter,
)

DEFAULT_AVATAR = os.path.join(os.environ.get("MORPHNODE_AVATAR_DIR") or os.path.join(
    os.path.dirname(__file__), "..", "..", "..", "shared", "data", "makehuman-avatar"), "makehuman_avatar.glb")
# The vowel "O": the avatar's own Oculus viseme and a little jaw (ARKit names).
VOWEL = {"viseme_O": 1.0, "jawOpen": 0.45}


def render(scene, bounds, window_size, png):
    renderer = vtkRenderer()
    HeadActors(scene, renderer)
    window = vtkRenderWindow()
    window.SetSize(*window_size)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    set_up_view(renderer, bounds, zoom=0.75)  # down to the chin
    window.OffScreenRenderingOn()
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtkPNGWriter()
    writer.SetFileName(png)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print("wrote", png)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("avatar", nargs="?", default=DEFAULT_AVATAR)
    parser.add_argument("--head-yaw", type=float, default=20.0, help="degrees, to the avatar's left")
    parser.add_argument("--eye-yaw", type=float, default=25.0, help="degrees, relative to the head")
    parser.add_argument("--eye-pitch", type=float, default=-5.0)
    parser.add_argument("--rest", help="the rest pose, offscreen to this PNG")
    parser.add_argument("--png", help="the animated pose, offscreen to this PNG")
    parser.add_argument("--size", type=size, default=(400, 400), help="WxH (default 400x400)")
    args = parser.parse_args(argv)

    reader = vtkMorphTargetReader()
    reader.SetFileName(args.avatar)
    morph = vtkMorphNodeFilter()
    morph.SetInputConnection(reader.GetOutputPort())
    morph.SetWeightModeToRelative()
    skin = vtkMorphSkinFilter()
    # Downstream of the morph node: a second pass. The same filter can pose in the morph
    # node's own pass instead (morph.SetPoseFilter(skin), its output then the posed avatar;
    # MorphAvatar does, docs/avatars.md): the same points, one pass fewer.
    skin.SetInputConnection(morph.GetOutputPort())
    skin.RelaxArmsOn()

    # At rest: no weight, no turn (the arms lowered all the same).
    skin.Update()
    if skin.GetNumberOfSkinnedParts() == 0:
        print(f"{args.avatar}: no skinned part (see the errors above)", file=sys.stderr)
        return 1
    rest = skin.GetOutputDataObject(0).NewInstance()
    rest.DeepCopy(skin.GetOutputDataObject(0))
    bounds = [0.0] * 6
    skin.GetHeadBounds(bounds)  # the points the head joint moves: frame the face on them
    print(f"{args.avatar}: {skin.GetNumberOfSkinnedParts()} skinned parts; bones: {skin.GetBones()}")

    # Animated: the vowel, the head turned, the eyes looking aside.
    for name, weight in VOWEL.items():
        morph.SetWeightByName(name, weight)
    skin.SetHeadYaw(args.head_yaw)
    skin.SetEyeYaw(args.eye_yaw)
    skin.SetEyePitch(args.eye_pitch)
    skin.Update()
    animated = skin.GetOutputDataObject(0)
    print(f"animated: head yaw {args.head_yaw:g}, eyes {args.eye_yaw:g}/{args.eye_pitch:g} degrees, "
          + ", ".join(f"{n} {w:g}" for n, w in VOWEL.items()))

    if args.rest or args.png:
        if args.rest:
            render(rest, bounds, args.size, args.rest)
        if args.png:
            render(animated, bounds, args.size, args.png)
        return 0
    window = vtkRenderWindow()
    window.SetSize(2 * args.size[0], args.size[1])
    for i, scene in enumerate((rest, animated)):
        renderer = vtkRenderer()
        renderer.SetViewport(0.5 * i, 0.0, 0.5 * (i + 1), 1.0)
        HeadActors(scene, renderer)
        set_up_view(renderer, bounds)
        window.AddRenderer(renderer)
    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    window.Render()
    interactor.Start()
    return 0


if __name__ == "__main__":
    sys.exit(main())
