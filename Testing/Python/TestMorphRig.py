# SPDX-License-Identifier: BSD-3-Clause
"""The Python wrapping of the rig filters: expansion, baking, errors."""
import json
import os
import tempfile
import unittest

from morphnode import vtkMorphRigBaker, vtkMorphRigFilter, vtkMorphNodeFilter, vtkMorphTargetReader

from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkTable

from morphnode_testing import Errors

SOURCE_DIR = os.environ.get("MORPHNODE_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
ARKIT = os.path.join(SOURCE_DIR, "Data", "rigs", "arkit.json")
DEFAULT_FACE = os.path.join(SOURCE_DIR, "Data", "DefaultFace", "default_head.glb")


def table(**columns):
    t = vtkTable()
    for name, values in columns.items():
        a = vtkDoubleArray()
        a.SetName(name)
        for v in values:
            a.InsertNextValue(v)
        t.AddColumn(a)
    return t


def names(values):
    a = vtkStringArray()
    for v in values:
        a.InsertNextValue(v)
    return a


class TestMorphRig(unittest.TestCase):
    def test_expand_matches_the_rig_file(self):
        with open(ARKIT) as f:
            rig = json.load(f)
        targets = rig["targets"]
        f = vtkMorphRigFilter()
        f.SetRigFileName(ARKIT)
        f.SetTargetNames(names(["Neutral"] + targets))
        f.SetInputData(table(A=[0.5], EyesClosed=[1.0], HeadYaw=[0.25]))
        f.Update()
        out = f.GetOutput()
        self.assertEqual(out.GetNumberOfColumns(), len(targets) + 1)
        self.assertEqual(out.GetColumnByName("HeadYaw").GetValue(0), 0.25)
        for target in targets:
            expected = 0.5 * rig["shapes"]["A"].get(target, 0.0) + \
                rig["shapes"]["EyesClosed"].get(target, 0.0)
            expected = min(1.0, max(0.0, expected))
            self.assertAlmostEqual(out.GetColumnByName(target).GetValue(0), expected, places=12)
        self.assertIn("RigFileName", str(f))
        self.assertEqual(f.GetShapeName(0), "EyesClosed")

    def test_errors_give_an_empty_table(self):
        f = vtkMorphRigFilter()
        errors = Errors(f)
        f.SetRigFileName(os.path.join(tempfile.gettempdir(), "no-such-rig.json"))
        f.SetTargetNames(names(["Neutral", "jawOpen"]))
        f.SetInputData(table(A=[float("nan")]))
        f.Update()
        self.assertEqual(f.GetOutput().GetNumberOfColumns(), 0)
        self.assertTrue(any("no-such-rig" in m for m in errors.messages), errors.messages)
        errors.messages.clear()
        f.SetRigFileName(ARKIT)
        f.Update()  # the ARKit rig names targets this "face" lacks
        self.assertEqual(f.GetOutput().GetNumberOfColumns(), 0)
        self.assertTrue(errors.messages)

    def test_bake_then_morph(self):
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as rig:
            json.dump({"name": "py", "shapes": {"Wow": {"BrowsUp": 1.0, "O": 0.5}}}, rig)
        try:
            reader = vtkMorphTargetReader()
            reader.SetFileName(DEFAULT_FACE)
            reader.SetMeshIndex(0)  # the head's skin (every Table 1 target), one vtkPolyData
            baker = vtkMorphRigBaker()
            baker.SetInputConnection(reader.GetOutputPort())
            baker.SetRigFileName(rig.name)
            morph = vtkMorphNodeFilter()
            morph.SetInputConnection(baker.GetOutputPort())
            morph.SetWeightModeToRelative()
            morph.SetWeightByName("Wow", 1.0)
            morph.Update()
            self.assertEqual(morph.GetNumberOfTargets(), 2)
            self.assertEqual(morph.GetTargetName(1), "Wow")
            self.assertEqual(morph.GetActiveTargetCount(), 1)
            self.assertIn("ShapeSet", str(baker))
        finally:
            os.unlink(rig.name)


if __name__ == "__main__":
    unittest.main()
