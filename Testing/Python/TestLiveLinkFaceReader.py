# SPDX-License-Identifier: BSD-3-Clause
"""vtkLiveLinkFaceReader from Python: a take written here, read as a temporal weight source,
mapped onto ICT-FaceKit's target names, names that map to nothing, a bad row."""
import math
import os
import tempfile
import unittest

from morphnode import vtkLiveLinkFaceReader

from vtkmodules.vtkCommonCore import vtkCommand, vtkStringArray
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

TAKE = ("Timecode,BlendShapeCount,EyeBlinkLeft,JawOpen,BrowInnerUp,TongueOut,Blink,HeadYaw\n"
        "10:00:00:00.250,4,0,0,0,0,7,0\n"
        "10:00:00:02.250,4,1,0.8,0.4,1,7,0.1\n")


class Errors:
    def __init__(self, obj):
        self.messages = []
        obj.AddObserver(vtkCommand.ErrorEvent, self)

    def __call__(self, caller, event):
        self.messages.append(caller.GetClassName())


def write(text):
    handle, path = tempfile.mkstemp(suffix=".csv")
    with os.fdopen(handle, "w") as f:
        f.write(text)
    return path


class TestLiveLinkFaceReader(unittest.TestCase):
    def test_take_on_ict_names(self):
        reader = vtkLiveLinkFaceReader()
        reader.SetFileName(write(TAKE))
        names = vtkStringArray()
        for n in ["Neutral", "eyeBlink_L", "jawOpen", "browInnerUp_L", "browInnerUp_R"]:
            names.InsertNextValue(n)
        reader.SetTargetNames(names)
        reader.UpdateInformation()
        info = reader.GetOutputInformation(0)
        steps = info.Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
        self.assertEqual(len(steps), 2)
        self.assertAlmostEqual(steps[1], 1.0 / 30.0, places=9)
        reader.UpdateTimeStep(0.5 / 30.0)
        frame = reader.GetOutputDataObject(0)
        self.assertAlmostEqual(frame.GetColumnByName("jawOpen").GetValue(0), 0.4, places=9)
        self.assertAlmostEqual(frame.GetColumnByName("browInnerUp_R").GetValue(0), 0.2, places=9)
        self.assertAlmostEqual(frame.GetColumnByName("HeadYaw").GetValue(0),
                               math.degrees(0.05), places=9)
        unmapped = [reader.GetUnmappedName(i) for i in range(reader.GetNumberOfUnmappedNames())]
        self.assertEqual(unmapped, ["Blink", "tongueOut"])
        self.assertIn("map to nothing: Blink tongueOut", reader.GetMappingReport())

    def test_bad_row(self):
        reader = vtkLiveLinkFaceReader()
        errors = Errors(reader)
        reader.SetFileName(write("Timecode,JawOpen\n00:00:00:00,0.5\n00:00:00:01,oops\n"))
        reader.Update()
        self.assertTrue(errors.messages)
        self.assertEqual(reader.GetOutputDataObject(0).GetNumberOfColumns(), 0)


if __name__ == "__main__":
    unittest.main()
