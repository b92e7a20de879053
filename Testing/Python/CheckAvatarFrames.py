#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Checks what an offscreen avatar run (Examples/Python/morph_avatar.py, MorphAvatar) wrote.

    CheckAvatarFrames.py DIR FRAMES [FILE=MAGIC ...]

DIR holds frame_00000.png ... and the media files FILE, each starting with MAGIC (default
avatar.ogv=OggS avatar.wav=RIFF, what morph_avatar.py --video writes). Besides the count and the file
headers, the face must move: the mouth region (the lower face, away from the overlay text
at the top) of some frame must differ from the first frame's by more than MOUTH_CHANGE grey
levels on average. File sizes are no evidence: the overlay's frame counter alone makes every
PNG a different size even when the face is frozen.
"""
import os
import sys

from vtkmodules.vtkIOImage import vtkPNGReader

MOUTH_CHANGE = 5.0  # mean absolute difference, 0-255 grey levels (moving ~14, frozen ~1.4)
ROWS = (0.15, 0.45)  # fraction of the height, from the bottom (VTK's rows run bottom-up)


def read(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    scalars = image.GetPointData().GetScalars()
    return width, height, scalars.GetNumberOfComponents(), memoryview(scalars).tobytes()


def mean_difference(a, b):
    """Mean absolute RGB difference over ROWS and the middle half of the columns."""
    width, height, comps, pa = a
    _, _, _, pb = b
    total, count = 0, 0
    for y in range(int(ROWS[0] * height), int(ROWS[1] * height)):
        row = (y * width) * comps
        for x in range(width // 4, 3 * width // 4):
            i = row + x * comps
            for k in range(min(comps, 3)):
                total += abs(pa[i + k] - pb[i + k])
                count += 1
    return total / count if count else 0.0


def main(argv):
    folder, expected = argv[1], int(argv[2])
    frames = sorted(f for f in os.listdir(folder) if f.startswith("frame_") and f.endswith(".png"))
    assert len(frames) == expected, f"{len(frames)} frames, expected {expected}: {frames}"
    media = [item.split("=", 1) for item in argv[3:]] or [("avatar.ogv", "OggS"), ("avatar.wav", "RIFF")]
    for name, magic in media:
        with open(os.path.join(folder, name), "rb") as f:
            assert f.read(len(magic)) == magic.encode(), f"{name} is not a {magic} file"
    first = read(os.path.join(folder, frames[0]))
    changes = [mean_difference(first, read(os.path.join(folder, f))) for f in frames[1:]]
    largest = max(changes)
    print("mouth-region change from the first frame, per frame:", " ".join(f"{c:.2f}" for c in changes))
    assert largest > MOUTH_CHANGE, (
        f"the face is frozen: the mouth region changes by at most {largest:.2f} grey levels "
        f"(needs > {MOUTH_CHANGE})")
    print(f"ok: {len(frames)} frames, {', '.join(n for n, _ in media)}; the mouth region moves (up to {largest:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
