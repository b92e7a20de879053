#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Play a behaviour script (docs/behavior.md) on a face with morph targets, offscreen:
PNG frames, the weight track as CSV and, when the script speaks, the speech as WAV go to
an output folder; a progress bar goes to stderr.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/play_script.py \
        Data/scripts/greeting.txt --out greeting-frames

Make a video with
    ffmpeg -framerate 30 -i greeting-frames/frame_%05d.png -i greeting-frames/speech.wav -shortest out.mp4
"""
import argparse
import math
import os
import sys

from example_support import HeadActors, ProgressBar, head_bounds, set_up_view, size
from morphnode import vtkBehaviorTimeSource, vtkMorphAvatarPipeline

import vtkmodules.vtkInteractionStyle  # noqa: F401  (default interactor style)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the render backend)
from vtkmodules.vtkIOCore import vtkDelimitedTextWriter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
DEFAULT_SCRIPT = os.path.join(DATA, "scripts", "greeting.txt")
DEFAULT_FACE = os.path.join(DATA, "DefaultFace", "default_head.glb")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("script", nargs="?", default=DEFAULT_SCRIPT)
    parser.add_argument("--face", default=DEFAULT_FACE)
    parser.add_argument("--rig", help="a rig onto the face's targets, e.g. Data/rigs/arkit.json for an ARKit face")
    parser.add_argument("--out", default="play_script-out")
    parser.add_argument("--fps", type=float, help="override the script's frame rate")
    parser.add_argument("--duration", type=float, help="override the script's duration (s)")
    parser.add_argument("--frames", type=int, help="render only the first N frames")
    parser.add_argument("--size", type=size, default=(480, 480), help="WxH (default 480x480)")
    parser.add_argument("--voice", help="eSpeak NG voice, e.g. en, de")
    parser.add_argument("--visemes", choices=["paper6", "oculus15", "german16"])
    args = parser.parse_args(argv)

    # Speech settings first: Say synthesizes while the script loads.
    behavior = vtkBehaviorTimeSource()
    if args.voice:
        behavior.SetVoice(args.voice)
    if args.visemes:
        behavior.SetVisemeSetFromString(args.visemes)
    if not behavior.LoadScript(args.script):
        return 1  # the error, with its line number, is printed already
    if args.fps:
        behavior.SetFrameRate(args.fps)
    if args.duration is not None:
        behavior.SetDuration(args.duration)
    os.makedirs(args.out, exist_ok=True)

    # The whole track (port 1) as CSV, and the speech lined up with it.
    csv = vtkDelimitedTextWriter()
    csv.SetFileName(os.path.join(args.out, "track.csv"))
    csv.SetInputConnection(behavior.GetOutputPort(1))
    if not csv.Write():
        return 1
    wav = os.path.join(args.out, "speech.wav") if behavior.HasAudio() else None
    if wav and not behavior.WriteAudio(wav):
        return 1

    # The avatar's pipeline in one class: the whole scene (every part of the head) morphed by
    # the behaviour's weights (through the rig onto an ARKit face's own targets), the eyes
    # looking where it looks (EyeYaw, EyePitch), the head pose as one transform.
    avatar = vtkMorphAvatarPipeline()
    avatar.SetFileName(args.face)
    if args.rig:
        avatar.SetRigFileName(args.rig)
    avatar.SetWeightsConnection(behavior.GetOutputPort(0))
    avatar.UpdateTimeStep(0.0)
    bounds = head_bounds(avatar.GetOutputDataObject())
    if bounds is None:
        print("nothing to show (see the errors above)", file=sys.stderr)
        return 1
    morph = avatar.GetMorph()
    if not args.rig and not any(morph.GetTargetIndex(behavior.GetChannelName(c)) >= 0
                                for c in range(behavior.GetNumberOfChannels())):
        print(f"play_script.py: no behaviour channel names a target of {args.face}; give a rig with "
              "--rig (e.g. Data/rigs/arkit.json)", file=sys.stderr)
        return 1

    renderer = vtkRenderer()
    # One actor per part, all turned by the head pose.
    head = HeadActors(avatar.GetOutputDataObject(), renderer, avatar.GetHeadPose())
    window = vtkRenderWindow()
    window.SetSize(*args.size)
    window.SetMultiSamples(0)
    window.OffScreenRenderingOn()
    window.AddRenderer(renderer)
    set_up_view(renderer, bounds)
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    png = vtkPNGWriter()
    png.SetInputConnection(grab.GetOutputPort())

    rate = behavior.GetFrameRate()
    frames = int(math.floor(behavior.GetEffectiveDuration() * rate + 1e-9)) + 1
    if args.frames is not None:
        frames = max(0, min(frames, args.frames))
    print(f"{args.script}: {behavior.GetEffectiveDuration():g} s at {rate:g} fps, "
          f"{behavior.GetNumberOfChannels()} channels -> {args.out}", file=sys.stderr)
    progress = ProgressBar(frames)
    for f in range(frames):
        if not avatar.UpdateTimeStep(f / rate) or not head.update(avatar.GetOutputDataObject()):
            print(f"\nthe face could not be morphed at t = {f / rate:g}", file=sys.stderr)
            return 1
        window.Render()
        grab.Modified()
        png.SetFileName(os.path.join(args.out, f"frame_{f:05d}.png"))
        png.Write()
        progress.show(f + 1)
    print(f"wrote {frames} frames, {csv.GetFileName()}" + (f" and {wav}" if wav else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
