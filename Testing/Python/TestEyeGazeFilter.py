# SPDX-License-Identifier: BSD-3-Clause
"""vtkEyeGazeFilter from Python: the default head's pupils look where EyeYaw/EyePitch say,
the limits clamp, other parts pass through, eye names, the gaze from a
vtkBehaviorTimeSource, errors."""
import math
import os
import unittest

from morphnode import vtkBehaviorTimeSource, vtkEyeGazeFilter, vtkMorphTargetReader

from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkTable

from morphnode_testing import Errors

SOURCE_DIR = os.environ.get("MORPHNODE_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_HEAD = os.path.join(SOURCE_DIR, "Data", "DefaultFace", "default_head.glb")


def parts(collection):
    return {collection.GetMetaData(i).Get(vtkCompositeDataSet.NAME()): collection.GetPartition(i, 0)
            for i in range(collection.GetNumberOfPartitionedDataSets())}


def field(part, name):
    a = part.GetFieldData().GetAbstractArray(name)
    return None if a is None else [a.GetValue(i) for i in range(a.GetNumberOfValues())]


def pupil_error(part, yaw, pitch):
    """Degrees between the pupil's direction from the eye's centre and the gaze."""
    origin = field(part, "NodeOrigin")
    n = part.GetNumberOfPoints()
    d = [sum(part.GetPoint(i)[c] for i in range(n)) / n - origin[c] for c in range(3)]
    y, p = math.radians(yaw), math.radians(pitch)
    target = (math.cos(p) * math.sin(y), math.sin(p), math.cos(p) * math.cos(y))
    cosine = sum(a * b for a, b in zip(d, target)) / math.sqrt(sum(a * a for a in d))
    return math.degrees(math.acos(max(-1.0, min(1.0, cosine))))


class TestEyeGazeFilter(unittest.TestCase):
    def setUp(self):
        self.reader = vtkMorphTargetReader()
        self.reader.SetFileName(DEFAULT_HEAD)
        self.gaze = vtkEyeGazeFilter()
        self.gaze.SetInputConnection(self.reader.GetOutputPort())

    def test_pupils_look_at_the_gaze_and_other_parts_pass(self):
        self.gaze.SetEyeYaw(-22.0)
        self.gaze.SetEyePitch(14.0)
        self.gaze.Update()
        self.assertEqual(self.gaze.GetNumberOfEyeParts(), 6)
        before = parts(self.reader.GetOutputDataObject(0))
        after = parts(self.gaze.GetOutputDataObject(0))
        self.assertEqual(sorted(before), sorted(after))
        for name in ("EyeLeft/Pupil", "EyeRight/Pupil"):
            self.assertLess(pupil_error(before[name], 0.0, 0.0), 1.0, name + " at rest")
            self.assertLess(pupil_error(after[name], -22.0, 14.0), 1.0, name)
            self.assertEqual(field(after[name], "EyeGaze"), [-22.0, 14.0])
        for name in before:
            if not name.startswith("Eye"):
                self.assertTrue(after[name].GetPoints() is before[name].GetPoints()
                                or after[name].GetPoints() == before[name].GetPoints(), name)
                self.assertIsNone(field(after[name], "EyeGaze"), name)
        self.assertEqual(field(after["EyeLeft/Iris"], "EyeSide"), ["left"])

    def test_limits_and_names(self):
        self.gaze.SetEyeYaw(70.0)
        self.gaze.SetEyePitch(-70.0)
        self.gaze.SetMaxEyeDown(20.0)
        self.gaze.AddEyeName("EyeLeft")
        self.gaze.Update()
        self.assertEqual(self.gaze.GetNumberOfEyeParts(), 3)
        out = parts(self.gaze.GetOutputDataObject(0))
        self.assertEqual(field(out["EyeLeft/Pupil"], "EyeGaze"), [40.0, -20.0])
        self.assertLess(pupil_error(out["EyeLeft/Pupil"], 40.0, -20.0), 1.0)
        self.assertIsNone(field(out["EyeRight/Pupil"], "EyeGaze"))

    def test_gaze_from_the_behaviour(self):
        behavior = vtkBehaviorTimeSource()
        behavior.SetDuration(3.0)
        self.assertTrue(behavior.LookAt(-18.0, 6.0, 0.5, 2.0))
        self.gaze.SetGazeConnection(behavior.GetOutputPort(0))
        self.gaze.UpdateTimeStep(1.5)
        table = behavior.GetOutputDataObject(0)
        yaw = table.GetColumnByName("EyeYaw").GetValue(0)
        pitch = table.GetColumnByName("EyePitch").GetValue(0)
        self.assertLess(yaw, -3.0)
        self.assertEqual(self.gaze.GetLastEyeYaw(), yaw)
        out = parts(self.gaze.GetOutputDataObject(0))
        self.assertLess(pupil_error(out["EyeRight/Pupil"], yaw, pitch), 1.0)

    def test_errors(self):
        errors = Errors(self.gaze)
        self.gaze.SetEyeYaw(float("nan"))
        self.gaze.Update()
        self.assertTrue(any("finite" in m for m in errors.messages), errors.messages)
        self.assertEqual(self.gaze.GetNumberOfEyeParts(), 0)
        self.gaze.SetEyeYaw(0.0)
        bad = vtkTable()
        column = vtkDoubleArray()
        column.SetName("HeadYaw")
        column.InsertNextValue(1.0)
        bad.AddColumn(column)
        self.gaze.SetInputData(1, bad)
        errors.messages.clear()
        self.gaze.Update()
        self.assertTrue(any("EyeYaw" in m for m in errors.messages), errors.messages)


if __name__ == "__main__":
    unittest.main()
