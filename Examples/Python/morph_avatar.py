#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""MorphAvatar in Python: an avatar speaks a sentence or plays a behaviour script, with
idle behaviour, through the weight optimizer of Berner (WSCG 2004, Figure 6).

    vtkBehaviorTimeSource -> vtkMorphAvatarPipeline (the avatar's chain in one class:
    vtkMorphTargetReader, the whole scene -> [vtkMorphRigFilter] -> vtkMorphNodeFilter ->
    vtkEyeGazeFilter, the behaviour's EyeYaw/EyePitch turn the eyes -> vtkMorphSkinFilter;
    HeadYaw/Pitch/Roll -> its head pose transform) -> one actor per part in its own colour
    (example_support.HeadActors), all turned by the head pose

Offscreen, every frame at the frame rate to PNG frames (and optionally a Theora video and
the WAV); without --frames/--video a window where time runs in real time (keys 0-4
method, +/- threshold, q quit), as the C++ MorphAvatar (docs/avatar.md).

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/morph_avatar.py \\
        --script Data/scripts/greeting.txt --duration 2 --frames out/
"""
import argparse
import math
import os
import sys
import time

from example_support import HeadActors, ProgressBar, head_bounds, preset, preset_names, set_up_view, size
from morphnode import vtkBehaviorTimeSource, vtkMorphAvatarPipeline

import vtkmodules.vtkInteractionStyle  # noqa: F401  (default interactor style)
import vtkmodules.vtkRenderingFreeType  # noqa: F401  (text)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the render backend)
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (
    vtkRenderer,
    vtkRenderWindow,
    vtkRenderWindowInteractor,
    vtkTextActor,
    vtkWindowToImageFilter,
)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
DEFAULT_FACE = os.path.join(DATA, "DefaultFace", "default_head.glb")
def ranged(lo, hi):
    def parse(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expects a number, got {text!r}")
        if not (lo <= v <= hi) or math.isnan(v):
            raise argparse.ArgumentTypeError(f"must be in [{lo}, {hi}], got {text}")
        return v
    return parse


class Avatar:
    def __init__(self, args):
        self.args = args
        self.behavior = vtkBehaviorTimeSource()
        self.behavior.SetVoice(args.voice)
        if not self.behavior.SetVisemeSetFromString(args.visemes):
            raise SystemExit(f"morph_avatar: --visemes expects paper6, oculus15 or german16; got {args.visemes!r}")
        if args.script and not self.behavior.LoadScript(args.script):
            raise SystemExit(f"morph_avatar: cannot load the script {args.script} (see above)")
        start = -1.0 if args.script else 0.5
        if args.audio or args.timings:
            # A recording timed by its transcript, by a timing file of it, or by recognition;
            # or a timing file alone (a mouth without sound).
            transcript = args.text or ""
            if args.text_file:
                with open(args.text_file, encoding="utf-8") as f:
                    transcript = f.read()
            if not args.audio:
                spoken = self.behavior.SpeakTimingFile(args.timings, start)
            elif args.timings:
                spoken = self.behavior.SpeakAudioFileWithTimings(args.audio, args.timings, start)
            else:
                spoken = self.behavior.SpeakAudioFile(args.audio, transcript, start)
            if not spoken:
                raise SystemExit(f"morph_avatar: cannot speak {args.audio or args.timings!r} (see above)")
        say = args.say
        if not say and not args.script and not args.audio and not args.timings:
            say = "Hallo! Ich bin ein Avatar." if args.voice.startswith("de") else "Hello! I am an avatar."
        if say and not self.behavior.Say(say, start):
            raise SystemExit(f"morph_avatar: cannot say {say!r} with voice {args.voice!r} (see above)")
        if args.seed is not None:
            self.behavior.SetSeed(args.seed)
        if args.fps is not None:
            self.behavior.SetFrameRate(args.fps)
        if args.duration is not None:
            self.behavior.SetDuration(args.duration)
        self.fps = self.behavior.GetFrameRate()
        self.duration = self.behavior.GetEffectiveDuration()

        # The face morphed by the behaviour (through the rig), the eyes looking where it looks
        # (its "eyes" section names the eye parts), the head pose as one transform.
        self.avatar = vtkMorphAvatarPipeline()
        self.avatar.SetFileName(args.face)
        if args.rig:
            self.avatar.SetRigFileName(args.rig)
        self.avatar.SetWeightsConnection(self.behavior.GetOutputPort(0))
        self.morph = self.avatar.GetMorph()
        self.method, self.threshold = args.method, args.threshold
        self.head = None  # the parts' actors, made below
        if not self.update(0.0):
            raise SystemExit(f"morph_avatar: cannot morph the face {args.face} (see above)")
        b = head_bounds(self.avatar.GetOutputDataObject())
        self.diagonal = math.dist((b[0], b[2], b[4]), (b[1], b[3], b[5])) or 1.0
        self.max_error = args.max_error if args.max_error is not None else 0.005 * self.diagonal
        self.apply_method()
        self.update(0.0)

        self.renderer = vtkRenderer()
        self.head = HeadActors(self.avatar.GetOutputDataObject(), self.renderer, self.avatar.GetHeadPose())
        w, h = args.size
        self.overlay = vtkTextActor()
        tp = self.overlay.GetTextProperty()
        tp.SetFontFamilyToCourier()
        tp.SetFontSize(max(10, h // 40))
        tp.SetColor(0.95, 0.95, 0.85)
        tp.SetBackgroundColor(0, 0, 0)
        tp.SetBackgroundOpacity(0.45)
        tp.SetVerticalJustificationToTop()
        self.overlay.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        self.overlay.SetPosition(0.012, 0.988)
        self.overlay.SetVisibility(not args.no_overlay)
        self.renderer.AddActor2D(self.overlay)
        self.window = vtkRenderWindow()
        self.window.SetSize(w, h)
        self.window.SetMultiSamples(0)
        self.window.AddRenderer(self.renderer)
        self.window.SetWindowName("morph_avatar.py")
        set_up_view(self.renderer, b)

    def apply_method(self):
        """The optimizer preset (morph/OptimizerPresets.h) with the threshold and the bound."""
        m = self.morph
        m.SetThreshold(self.threshold)
        m.SetMaxVertexError(self.max_error)
        m.SetOptimizerPreset(self.method)
        m.ResetHysteresis()

    def update(self, t):
        """The face at time t: weights, blend, eyes, head pose."""
        self.time = t
        if not self.avatar.UpdateTimeStep(t):
            return False
        face = self.avatar.GetOutputDataObject()  # the reader's structure: parts, or one mesh
        if head_bounds(face) is None:
            return False
        return self.head is None or self.head.update(face)

    def overlay_text(self, first_line):
        lines = [first_line, f"method {self.method}: {self.morph.GetOptimizerPresetAsString()}"]
        if self.method in (1, 2, 3):
            lines.append(f"threshold {self.threshold:.3f}")
        elif self.method == 4:
            lines.append(f"max vertex error {100 * self.max_error / self.diagonal:.2f} % of the face")
        else:
            lines.append("threshold -")
        targets = max(0, self.morph.GetNumberOfTargets() - 1)
        lines.append(f"active targets {self.morph.GetActiveTargetCount()} / {targets}   "
                     f"error bound {100 * self.morph.GetErrorBound() / self.diagonal:.2f} %")
        lines.append(f"t = {self.time:.2f} s / {self.duration:.2f} s")
        return "\n".join(lines)

    def run_offscreen(self):
        args = self.args
        self.window.OffScreenRenderingOn()
        frames = int(math.floor(self.duration * self.fps + 1e-9)) + 1
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ReadFrontBufferOff()
        grab.SetInputBufferTypeToRGB()
        png = vtkPNGWriter()
        png.SetInputConnection(grab.GetOutputPort())
        video = None
        if args.frames:
            os.makedirs(args.frames, exist_ok=True)
        if args.video:
            from vtkmodules.vtkIOOggTheora import vtkOggTheoraWriter
            stem = os.path.splitext(args.video)[0]
            os.makedirs(os.path.dirname(os.path.abspath(stem)), exist_ok=True)
            video = vtkOggTheoraWriter()
            video.SetInputConnection(grab.GetOutputPort())
            video.SetFileName(stem + ".ogv")
            video.SetRate(max(1, round(self.fps)))
            video.SetQuality(2)
        progress = ProgressBar(frames, enabled=not args.quiet)
        for f in range(frames):
            if not self.update(f / self.fps):
                print(f"\nmorph_avatar: cannot morph the face at t = {f / self.fps}", file=sys.stderr)
                return 1
            self.overlay.SetInput(self.overlay_text(f"{self.fps:.1f} fps   frame {f} / {frames}"))
            self.window.Render()
            grab.Modified()
            if args.frames:
                png.SetFileName(os.path.join(args.frames, f"frame_{f:05d}.png"))
                png.Write()
            if video is not None:
                if f == 0:
                    grab.Update()
                    video.Start()
                video.Write()
            progress.show(f + 1)
        if video is not None:
            video.End()
            wav = os.path.splitext(args.video)[0] + ".wav"
            if not self.behavior.WriteAudio(wav):
                print(f"morph_avatar: cannot write {wav}", file=sys.stderr)
                return 1
            print(f"wrote {os.path.splitext(args.video)[0]}.ogv (silent) and {wav}")
        if args.frames:
            print(f"wrote {frames} frames to {args.frames}/frame_*.png at {self.fps:g} fps")
        return 0

    def run_interactive(self):
        interactor = vtkRenderWindowInteractor()
        interactor.SetRenderWindow(self.window)
        interactor.Initialize()
        start = time.monotonic()
        state = {"frames": 0, "fps": 0.0, "since": start}

        def on_key(obj, _event):
            key, sym = obj.GetKeyCode(), obj.GetKeySym()
            if key in "01234" and key:
                self.method = int(key)
            elif key in "+=" and key or sym in ("plus", "KP_Add"):
                if self.method == 4:
                    self.max_error *= 1.25
                else:
                    self.threshold = min(1.0, self.threshold + 0.025)
            elif key == "-" or sym in ("minus", "KP_Subtract"):
                if self.method == 4:
                    self.max_error /= 1.25
                else:
                    self.threshold = max(0.0, self.threshold - 0.025)
            self.apply_method()

        def on_timer(obj, _event):
            now = time.monotonic()
            self.update((now - start) % self.duration)
            state["frames"] += 1
            if now - state["since"] >= 0.5:
                state["fps"], state["frames"], state["since"] = state["frames"] / (now - state["since"]), 0, now
            self.overlay.SetInput(self.overlay_text(f"{state['fps']:.1f} fps") +
                                  "\nkeys: 0-4 method  +/- threshold  q quit")
            obj.Render()

        interactor.AddObserver("KeyPressEvent", on_key, 1.0)
        interactor.AddObserver("TimerEvent", on_timer)
        interactor.CreateRepeatingTimer(5)
        self.window.Render()
        interactor.Start()
        return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--say", help="speak this text (eSpeak NG)")
    parser.add_argument("--voice", default="en", help="eSpeak NG voice (default en)")
    parser.add_argument("--visemes", default="paper6", help="paper6 (default), oculus15, german16")
    parser.add_argument("--script", help="a behaviour script (docs/behavior.md)")
    parser.add_argument("--audio", help="speak a recording (WAV, FLAC, OGG); the video's sound")
    parser.add_argument("--text", help="the transcript of --audio (aligned with eSpeak NG)")
    parser.add_argument("--text-file", help="the transcript of --audio, from a file")
    parser.add_argument("--timings", help="a timing file of --audio, or alone: a mouth without sound")
    parser.add_argument("--seed", type=int, help="seed of the idle behaviour")
    parser.add_argument("--duration", type=ranged(0.0, 86400.0), help="seconds (default: automatic)")
    parser.add_argument("--fps", type=ranged(1.0, 240.0), help="frame rate (default 30)")
    parser.add_argument("--face", default=DEFAULT_FACE, help="a face with morph targets")
    parser.add_argument("--rig", help="a rig mapping the channels onto the face's targets")
    parser.add_argument("--method", type=preset, default=3,
                        help="0-4 or " + ", ".join(preset_names()) + " (default 3, adjusted)")
    parser.add_argument("--threshold", type=ranged(0.0, 1.0), default=0.1, help="th_fix (default 0.1)")
    parser.add_argument("--max-error", type=ranged(0.0, 1e30), help="method 4's bound, model units")
    parser.add_argument("--size", type=size, default=(640, 640), help="WxH (default 640x640)")
    parser.add_argument("--offscreen", action="store_true", help="no window (needs --frames or --video)")
    parser.add_argument("--frames", help="write frame_00000.png ... into this folder")
    parser.add_argument("--video", help="write FILE.ogv (silent Theora) and FILE.wav")
    parser.add_argument("--no-overlay", action="store_true")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.seed is not None and args.seed < 0:
        parser.error("--seed expects an unsigned integer")
    if (args.text or args.text_file) and not args.audio:
        parser.error("--text and --text-file need --audio")
    if sum(bool(x) for x in (args.text, args.text_file, args.timings)) > 1:
        parser.error("give one of --text, --text-file and --timings")
    for option, path in (("--script", args.script), ("--face", args.face), ("--rig", args.rig),
                         ("--audio", args.audio), ("--text-file", args.text_file),
                         ("--timings", args.timings)):
        if path and not os.path.exists(path):
            parser.error(f"{option}: no file {path!r}")
    offscreen = args.offscreen or args.frames or args.video
    if offscreen and not (args.frames or args.video):
        parser.error("--offscreen needs somewhere to write: --frames DIR or --video FILE")
    if not os.environ.get("DISPLAY"):
        parser.error("no X display (DISPLAY is not set): run under `xvfb-run -a`")
    avatar = Avatar(args)
    return avatar.run_offscreen() if offscreen else avatar.run_interactive()


if __name__ == "__main__":
    sys.exit(main())
