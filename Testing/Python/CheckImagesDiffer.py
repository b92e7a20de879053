#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Checks that an example drew what it was asked to: two PNGs of the same size must differ.

    CheckImagesDiffer.py MORPHED.png NEUTRAL.png MIN_CHANGE

MORPHED is the example's render with weights, NEUTRAL the same call without them; their mean
absolute RGB difference (0-255 grey levels, over the whole image) must exceed MIN_CHANGE. An
example that exits 0 but ignores --weight (or draws nothing) fails.
"""
import sys

from vtkmodules.vtkIOImage import vtkPNGReader


def read(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    scalars = image.GetPointData().GetScalars()
    assert scalars is not None, f"{path}: no image"
    return image.GetDimensions(), scalars.GetNumberOfComponents(), memoryview(scalars).tobytes()


def main(argv):
    (dims_a, comps, a), (dims_b, _, b) = read(argv[1]), read(argv[2])
    minimum = float(argv[3])
    assert dims_a == dims_b, f"sizes differ: {dims_a} and {dims_b}"
    total, count = 0, 0
    for i in range(0, len(a), comps):
        for k in range(min(comps, 3)):
            total += abs(a[i + k] - b[i + k])
            count += 1
    change = total / count
    print(f"mean change between {argv[1]} and {argv[2]}: {change:.3f} grey levels")
    assert change > minimum, f"the weights do not show: mean change {change:.3f} <= {minimum}"
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
