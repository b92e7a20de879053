# SPDX-License-Identifier: BSD-3-Clause
"""vtkBehaviorTimeSource from Python: the default face animated through UpdateTimeStep; lip sync
made elsewhere (Rhubarb cues, MBROLA .pho, TextGrid, speech marks, a recording with its
transcript) driven into it; frames, parameters, viseme tables."""
import json
import os
import tempfile
import unittest

from morphnode import vtkBehaviorTimeSource, vtkMorphNodeFilter, vtkMorphTargetReader

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

from morphnode_testing import Errors

SOURCE_DIR = os.environ.get("MORPHNODE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_FACE = os.path.join(SOURCE_DIR, "Data", "DefaultFace", "default_head.glb")
OUTPUT_DIR = os.environ.get("MORPHNODE_TEST_OUTPUT_DIR", tempfile.gettempdir())
CORPUS = os.path.join(SOURCE_DIR, "Testing", "Fuzz", "corpus")


def column(table, name, row=0):
    array = table.GetColumnByName(name)
    if array is None:
        raise KeyError(name)
    return array.GetValue(row)


def peak(track, name, start, end):
    """The largest value of a track column over [start, end] seconds."""
    return max(column(track, name, r) for r in range(track.GetNumberOfRows())
               if start <= column(track, "Time", r) <= end)


class TestBehaviorTimeSource(unittest.TestCase):
    def setUp(self):
        self.reader = vtkMorphTargetReader()
        self.reader.SetFileName(DEFAULT_FACE)
        self.reader.SetMeshIndex(0)  # the head's skin (every Table 1 target), one vtkPolyData
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

    def test_rhubarb_cues_from_python(self):
        """Rhubarb Lip Sync's output (as Python makes or reads it) drives the mouth."""
        b = self.behavior
        b.SetDuration(6)
        # TSV written by Python (as `rhubarb -f tsv` would), JSON as a string.
        tsv = os.path.join(OUTPUT_DIR, "TestBehaviorTimeSourcePython_cues.tsv")
        with open(tsv, "w") as f:
            f.write("0.00\tX\n0.10\tD\n0.50\tB\n0.80\tX\n")
        before = b.GetMTime()
        self.assertTrue(b.SpeakRhubarbFile(tsv, 1.0))
        self.assertGreater(b.GetMTime(), before)
        cues = {"metadata": {"soundFile": "hello.wav", "duration": 0.6},
                "mouthCues": [{"start": 0.0, "end": 0.1, "value": "X"},
                              {"start": 0.1, "end": 0.5, "value": "E"},
                              {"start": 0.5, "end": 0.6, "value": "X"}]}
        self.assertTrue(b.SpeakRhubarbCues(json.dumps(cues), 3.0))
        self.assertTrue(b.SpeakRhubarbFile(os.path.join(CORPUS, "rhubarb_json", "sample.json")))  # queued
        self.assertEqual(b.GetNumberOfUtterances(), 3)
        self.assertEqual((b.GetUtteranceStart(0), b.GetUtteranceEnd(0)), (1.0, 1.8))
        self.assertAlmostEqual(b.GetUtteranceStart(2), 3.6)
        self.assertFalse(b.HasAudio())

        b.Update(1)
        track = b.GetOutputDataObject(1)
        # The paper's table: Rhubarb D (open) -> A, B (clenched) -> S, E (rounded) -> O.
        self.assertGreater(peak(track, "A", 1.15, 1.45), 0.5)
        self.assertGreater(peak(track, "S", 1.55, 1.75), 0.5)
        self.assertGreater(peak(track, "O", 3.15, 3.45), 0.5)
        self.assertLess(peak(track, "A", 0.0, 0.9), 0.01)
        # ... and through UpdateTimeStep onto the face's targets.
        self.morph.UpdateTimeStep(1.3)
        self.assertGreater(self.morph.GetEffectiveWeight(self.morph.GetTargetIndex("A")), 0.5)

        # Bad cues: False, an error naming the problem, the source unchanged.
        before = b.GetMTime()
        self.assertFalse(b.SpeakRhubarbFile(os.path.join(CORPUS, "rhubarb_tsv", "decreasing.tsv")))
        self.assertFalse(b.SpeakRhubarbCues('{"mouthCues": [{"start": 0.5, "end": 0.2, "value": "A"}]}'))
        self.assertFalse(b.SpeakRhubarbFile(os.path.join(OUTPUT_DIR, "no_such_cues.tsv")))
        self.assertFalse(b.SpeakRhubarbCues(""))
        messages = self.behavior_errors.messages
        self.assertEqual(len(messages), 4, messages)
        self.assertIn("decreasing.tsv", messages[0])
        self.assertIn("ends before it starts", messages[1])
        self.assertIn("cannot be opened", messages[2])
        self.assertIn("no mouth cues", messages[3])
        self.assertEqual(b.GetMTime(), before)
        self.assertEqual(b.GetNumberOfUtterances(), 3)
        messages.clear()

    def test_pho_from_python(self):
        """MBROLA .pho phonemes, as a file and as text, drive the mouth."""
        b = self.behavior
        self.assertTrue(b.SpeakPhonemeFile(os.path.join(CORPUS, "pho", "hello.pho"), 0.5))
        pho = "\n".join(["_ 50", "h 60", "A: 250 50 120", "_ 100"])  # English SAMPA
        self.assertTrue(b.SpeakPhonemes(pho))  # after hello
        self.assertEqual(b.GetNumberOfUtterances(), 2)
        start = b.GetUtteranceStart(1)
        self.assertEqual(start, b.GetUtteranceEnd(0))
        # 0.46 s of phonemes; the end is the viseme track's last frame when that is later.
        self.assertTrue(0.46 - 1e-9 <= b.GetUtteranceEnd(1) - start < 0.5, b.GetUtteranceEnd(1) - start)
        b.Update(1)
        track = b.GetOutputDataObject(1)
        self.assertGreater(peak(track, "A", start + 0.12, start + 0.35), 0.5)
        self.assertGreater(peak(track, "O", 0.5, start), 0.3)  # "hello" rounds the lips

        before = b.GetMTime()
        self.assertFalse(b.SpeakPhonemes("a 80 50"))  # an odd pitch list
        self.assertFalse(b.SpeakPhonemeFile(os.path.join(OUTPUT_DIR, "missing.pho")))
        self.assertIn("pho line 1", self.behavior_errors.messages[0])
        self.assertEqual(len(self.behavior_errors.messages), 2)
        self.assertEqual(b.GetMTime(), before)
        self.behavior_errors.messages.clear()

    def test_timing_files_and_recordings_from_python(self):
        """Timings from other tools (TextGrid, speech marks) and a recording with its transcript."""
        b = self.behavior
        self.assertTrue(b.SpeakTimingFile(os.path.join(CORPUS, "textgrid", "mfa_long.TextGrid"), 0.5))
        self.assertTrue(b.SpeakTimingFile(os.path.join(CORPUS, "speech_marks", "polly.marks")))
        self.assertEqual(b.GetNumberOfUtterances(), 2)
        self.assertFalse(b.HasAudio())
        b.Update(1)
        track = b.GetOutputDataObject(1)
        # "bee moo": the lips close for b and m (sil in the paper's set), then open.
        self.assertGreater(peak(track, "E", 0.5, 1.5), 0.3)
        self.assertFalse(b.SpeakTimingFile(os.path.join(CORPUS, "textgrid", "out_of_order.TextGrid")))
        self.assertIn("out_of_order.TextGrid", self.behavior_errors.messages[-1])
        self.behavior_errors.messages.clear()

        # A recording: eSpeak's rendering written by another source (sound only).
        speaker = vtkBehaviorTimeSource()
        speaker.SetDuration(0.1)
        if not speaker.Say("Hello world, how are you?", 0.0):
            self.skipTest("no eSpeak NG in this build")
        wav = os.path.join(OUTPUT_DIR, "TestBehaviorTimeSourcePython_recording.wav")
        self.assertTrue(speaker.WriteAudio(wav))
        length = speaker.GetUtteranceEnd(0)
        self.assertTrue(b.SpeakAudioFile(wav, "Hello world, how are you?", 3.0))
        self.assertTrue(b.HasAudio())
        self.assertEqual(b.GetUtteranceStart(2), 3.0)
        self.assertAlmostEqual(b.GetUtteranceEnd(2), 3.0 + length, delta=0.3)
        b.Update(1)
        track = b.GetOutputDataObject(1)
        mouth = max(sum(column(track, v, r) for v in "AEOSFL") for r in range(track.GetNumberOfRows())
                    if 3.1 <= column(track, "Time", r) <= 3.0 + length)
        self.assertGreater(mouth, 0.5)
        self.assertFalse(b.SpeakAudioFile(os.path.join(OUTPUT_DIR, "missing.wav"), "Hello"))
        self.assertEqual(len(self.behavior_errors.messages), 1)
        self.behavior_errors.messages.clear()

    def test_frames_parameters_and_viseme_table(self):
        b = self.behavior
        b.SetFrameRate(24)
        b.SetDuration(2.3)
        self.assertEqual(b.GetNumberOfFrames(), 56)
        b.UpdateInformation()
        steps = b.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
        self.assertEqual(list(steps), [b.GetFrameTime(i) for i in range(b.GetNumberOfFrames())])

        names = [b.GetBehaviorParameterName(i) for i in range(b.GetNumberOfBehaviorParameters())]
        self.assertIn("BlinkRateRest", names)
        self.assertEqual(b.GetBehaviorParameter("BlinkRateRest"), 17.0)
        before = b.GetMTime()
        self.assertTrue(b.SetBehaviorParameter("BlinkRateRest", 30.0))
        self.assertGreater(b.GetMTime(), before)
        self.assertEqual(b.GetBehaviorParameter("blink_rate_rest"), 30.0)
        self.assertFalse(b.SetBehaviorParameter("BlinkRateRest", 1e6))
        self.assertEqual(b.GetBehaviorParameter("BlinkRateRest"), 30.0)
        b.ResetBehaviorParameters()
        self.assertEqual(b.GetBehaviorParameter("BlinkRateRest"), 17.0)

        table = os.path.join(SOURCE_DIR, "Modules", "Core", "speech", "data", "visemes_oculus15_en.json")
        self.assertTrue(b.SetVisemeTableFileName(table))
        self.assertTrue(b.SpeakPhonemes("_ 50\np 80\nA: 200\n_ 50", 0.2))
        channels = [b.GetChannelName(i) for i in range(b.GetNumberOfChannels())]
        self.assertIn("PP", channels)
        self.assertFalse(b.SetVisemeTableFileName(os.path.join(OUTPUT_DIR, "no_table.json")))
        self.assertEqual(b.GetVisemeTableFileName(), table)
        self.assertEqual(len(self.behavior_errors.messages), 2, self.behavior_errors.messages)
        self.behavior_errors.messages.clear()


if __name__ == "__main__":
    unittest.main()
