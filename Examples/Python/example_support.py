# SPDX-License-Identifier: BSD-3-Clause
"""What the Python examples share, as the C++ programs share Modules/Applications/AppKit:
the optimizer presets by name (from vtkMorphNodeFilter, which spells them as
morph/OptimizerPresets.h does), WxH sizes, the head pose, and a progress bar.
"""
import argparse
import sys
import time

from morphnode import vtkMorphNodeFilter


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


def head_pivot(bounds):
    """The pivot the head turns about: the top of the neck (behavior/HeadPose.h HeadPivot)."""
    x0, x1, y0, y1, z0, z1 = bounds
    return ((x0 + x1) / 2, y0 + 0.25 * (y1 - y0), (z0 + z1) / 2)


def set_head_pose(transform, weights, pivot):
    """The head angles of a behaviour weight table (row 0 of HeadYaw, HeadPitch, HeadRoll, in
    degrees) on a vtkTransform, in the one convention of behavior/HeadPose.h (the C++
    programs call HeadPoseMatrix through AppKit; this mirrors it, the core not being
    wrapped): seen from the character, yaw > 0 turns to its left (+X; it looks along +Z),
    pitch > 0 looks up, roll > 0 tilts the crown to its left; R = Ry(yaw) Rx(-pitch)
    Rz(-roll) about the pivot."""
    def channel(name):
        column = weights.GetColumnByName(name) if weights is not None else None
        return column.GetValue(0) if column is not None and column.GetNumberOfTuples() else 0.0

    transform.Identity()  # PreMultiply: the calls compose right to left on a point
    transform.Translate(pivot)
    transform.RotateY(channel("HeadYaw"))
    transform.RotateX(-channel("HeadPitch"))
    transform.RotateZ(-channel("HeadRoll"))
    transform.Translate(-pivot[0], -pivot[1], -pivot[2])


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
