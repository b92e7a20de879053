# SPDX-License-Identifier: BSD-3-Clause
"""vtkBehaviorTimeSource from Python: the default face animated through UpdateTimeStep."""
import os
import tempfile
import unittest

from morphnode import vtkBehaviorTimeSource, vtkMorphNodeFilter, vtkMorphTargetReader

from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

SOURCE_DIR = os.environ.get("MORPHNODE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_FACE = os.path.join(SOURCE_DIR, "Data", "DefaultFace", "default_face.glb")
OUTPUT_DIR = os.environ.get("MORPHNODE_TEST_OUTPUT_DIR", tempfile.gettempdir())


class Errors:
    """Collects the error messages an object reports."""

    def __init__(self, obj):
        self.messages = []

        @calldata_type(VTK_STRING)
        def on_error(caller, event, message):
            self.messages.append(message)

        obj.AddObserver(vtkCommand.ErrorEvent, on_error)


def column(table, name, row=0):
    array = table.GetColumnByName(name)
    if array is None:
        raise KeyError(name)
    return array.GetValue(row)


class TestBehaviorTimeSource(unittest.TestCase):
    def setUp(self):
        self.reader = vtkMorphTargetReader()
        self.reader.SetFileName(DEFAULT_FACE)
        self.behavior = vtkBehaviorTimeSource()
        self.behavior_errors = Errors(self.behavior)
        self.morph = vtkMorphNodeFilter()
        self.morph.SetInputConnection(self.reader.GetOutputPort())
        self.morph.SetWeightsConnection(self.behavior.GetOutputPort(0))
        self.morph.SetWeightModeToRelative()
        self.morph_errors = Errors(self.morph)

    def tearDown(self):
        self.assertEqual(self.behavior_errors.messages, [])
        self.assertEqual(self.morph_errors.messages, [])

    def test_api(self):
        b = self.behavior
        b.SetSeed(2004)
        self.assertEqual(b.GetSeed(), 2004)
        b.SetFrameRate(25)
        b.SetDuration(3)
        self.assertEqual(b.GetEffectiveDuration(), 3.0)
        b.SetVoice("de")
        self.assertEqual(b.GetVoice(), "de")
        b.SetVisemeSetToGerman()
        self.assertEqual(b.GetVisemeSetAsString(), "german16")
        self.assertTrue(b.SetVisemeSetFromString("Paper6"))
        self.assertEqual(b.GetVisemeSet(), vtkBehaviorTimeSource.PAPER6)
        b.SetSpeechRate(160)
        self.assertEqual(b.GetSpeechRate(), 160)
        names = [b.GetChannelName(i) for i in range(b.GetNumberOfChannels())]
        self.assertEqual(names[:3], ["EyesClosed", "BrowsUp", "BrowsFright"])
        self.assertEqual(names[10:15], ["HeadYaw", "HeadPitch", "HeadRoll", "EyeYaw", "EyePitch"])

    def test_default_face_through_update_time_step(self):
        b = self.behavior
        b.SetSeed(5)
        self.assertTrue(b.SetMood("happy", 0.8))  # start and fade from their defaults
        self.assertTrue(b.Gesture("raise_brows", 1.0, 1.0, 0.9))
        self.assertTrue(b.Gesture("close_eyes", 2.5))
        self.assertTrue(b.LookAt(10, 0, 3.0, 1.0))

        self.morph.UpdateInformation()
        info = self.morph.GetOutputInformation(0)
        steps = info.Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
        self.assertEqual(len(steps), int(b.GetEffectiveDuration() * 30 + 1e-9) + 1)
        self.assertAlmostEqual(steps[1], 1 / 30)
        self.assertEqual(info.Get(vtkStreamingDemandDrivenPipeline.TIME_RANGE()), (0.0, b.GetEffectiveDuration()))

        targets = None
        for t, expectation in ((0.0, None), (1.5, "BrowsUp"), (3.2, "EyesClosed")):
            self.morph.UpdateTimeStep(t)
            face = self.morph.GetOutput()
            self.assertGreater(face.GetNumberOfPoints(), 0)
            self.assertEqual(face.GetInformation().Get(face.DATA_TIME_STEP()), t)
            table = b.GetOutputDataObject(0)
            if targets is None:
                targets = [self.morph.GetTargetName(k) for k in range(self.morph.GetNumberOfTargets())]
                self.assertEqual(len(targets), 13)
            # Relative mode: every target's effective weight is its channel in the table.
            for k, name in enumerate(targets[1:], start=1):
                expected = column(table, name) if table.GetColumnByName(name) else 0.0
                self.assertAlmostEqual(self.morph.GetEffectiveWeight(k), expected, places=12, msg=f"{name} at {t}")
            if expectation:
                self.assertGreater(column(table, expectation), 0.8, f"{expectation} at {t}")
        self.assertGreater(column(b.GetOutputDataObject(0), "EyeYaw"), 4.0)  # looking left

        # The whole track on port 1.
        b.Update(1)
        track = b.GetOutputDataObject(1)
        self.assertEqual(track.GetColumnName(0), "Time")
        self.assertEqual(track.GetNumberOfRows(), len(steps))
        self.assertEqual(track.GetNumberOfColumns(), b.GetNumberOfChannels() + 1)

    def test_errors(self):
        b = self.behavior
        self.assertFalse(b.Gesture("wiggle", 1.0))
        self.assertFalse(b.SetMood("happy", 3.0))
        bad = os.path.join(OUTPUT_DIR, "TestBehaviorTimeSourcePython_bad.txt")
        with open(bad, "w") as f:
            f.write("fps 30\nat 1 gesture nod\nat x mood happy\n")
        self.assertFalse(b.LoadScript(bad))
        self.assertTrue(any("wiggle" in m for m in self.behavior_errors.messages))
        self.assertTrue(any("line 3" in m for m in self.behavior_errors.messages), self.behavior_errors.messages)
        self.behavior_errors.messages.clear()

    def test_say_and_wav(self):
        b = self.behavior
        self.assertTrue(b.Say("Hello world"))  # start omitted: after the previous (at 0)
        self.assertTrue(b.Say("Good bye", 3.0))
        self.assertEqual(b.GetNumberOfUtterances(), 2)
        self.assertIn("A", [b.GetChannelName(i) for i in range(b.GetNumberOfChannels())])
        wav = os.path.join(OUTPUT_DIR, "TestBehaviorTimeSourcePython.wav")
        self.assertTrue(b.WriteAudio(wav))
        self.assertGreater(os.path.getsize(wav), 44 + 2 * 22050 * 3)
        self.morph.UpdateTimeStep(0.4)
        mouth = sum(self.morph.GetEffectiveWeight(self.morph.GetTargetIndex(v)) for v in "AEOSFL")
        self.assertGreater(mouth, 0.1)


if __name__ == "__main__":
    unittest.main()
