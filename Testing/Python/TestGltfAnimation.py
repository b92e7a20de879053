# SPDX-License-Identifier: BSD-3-Clause
"""glTF animations through vtkMorphTargetReader from Python: the animations listed after
UpdateInformation, the time steps, the weights table at a time, the morph node driven by it
(weights by target name), the animated geometry and a clear error for a missing animation.

Input: the animated head of the C++ tests (Testing/Core/gltf/GltfAnimatedTestFiles.h), as
written into FuzzGltf's seed corpus by Testing/Fuzz/tools/MakeGltfSeeds.cpp. Its "Linear"
animation moves the face's weights jawOpen, smile, eyeBlinkLeft through
(0, 0.2, 0) (0.8, 0.5, 0.1) (0.3, 1, 0.9) (0, 0, 0.2) at 0, 0.5, 1.25 and 2 s.
"""
import os
import sys
import unittest

from morphnode import vtkMorphNodeFilter, vtkMorphTargetReader

from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

from morphnode_testing import Errors

HEAD = os.path.join(os.environ.get("MORPHNODE_SOURCE_DIR", "."),
                    "Testing", "Fuzz", "corpus", "gltf", "animated-head.glb")


def column(table, name, component=0):
    array = table.GetColumnByName(name)
    assert array is not None, name
    return array.GetComponent(0, component)


def leaves(data):
    out = []
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        out.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return out


class TestGltfAnimation(unittest.TestCase):
    def test_animations_and_weights_table(self):
        reader = vtkMorphTargetReader()
        reader.SetFileName(HEAD)
        reader.SetAnimationName("Linear")
        reader.UpdateInformation()
        self.assertEqual(reader.GetNumberOfAnimations(), 4)
        self.assertEqual([reader.GetAnimationNameByIndex(i) for i in range(4)],
                         ["Linear", "Step", "Cubic", "Pose"])
        self.assertEqual(reader.GetChosenAnimation(), 0)
        info = reader.GetOutputInformation(1)
        key = vtkStreamingDemandDrivenPipeline.TIME_STEPS()
        self.assertEqual([info.Get(key, i) for i in range(info.Length(key))], [0, 0.5, 1.25, 2])

        reader.UpdateTimeStep(0.9)
        table = reader.GetWeightsOutput()
        u = 0.4 / 0.75
        self.assertAlmostEqual(column(table, "jawOpen"), 0.8 + u * (0.3 - 0.8), places=6)
        self.assertAlmostEqual(column(table, "smile"), 0.5 + u * 0.5, places=6)

        # The morph node driven by the table (glTF's relative blend): the face's point 1 is
        # the rest point plus the weighted deltas of jawOpen (y -0.2) and smile (x +0.1, y +0.05).
        morph = vtkMorphNodeFilter()
        morph.SetInputConnection(reader.GetOutputPort(0))
        morph.SetWeightsConnection(reader.GetOutputPort(1))
        morph.SetWeightModeToRelative()
        morph.SetOptimizerPreset(vtkMorphNodeFilter.OPTIMIZER_NONE)
        morph.UpdateTimeStep(0.9)
        face = leaves(morph.GetOutputDataObject(0))[0]
        x, y, _ = face.GetPoint(1)
        jaw, smile = column(table, "jawOpen"), column(table, "smile")
        self.assertAlmostEqual(x, 0.5 + 0.1 * smile, places=6)
        self.assertAlmostEqual(y, 1 - 0.5 - 0.2 * jaw + 0.05 * smile, places=6)

        # The same geometry from the reader itself.
        reader.SetApplyAnimation(vtkMorphTargetReader.ANIMATION_TRANSFORMS_AND_WEIGHTS)
        reader.UpdateTimeStep(0.9)
        applied = leaves(reader.GetOutputDataObject(0))[0]
        for k in range(3):
            self.assertAlmostEqual(applied.GetPoint(1)[k], face.GetPoint(1)[k], places=6)

    def test_missing_animation_is_an_error(self):
        reader = vtkMorphTargetReader()
        errors = Errors(reader)
        reader.SetFileName(HEAD)
        reader.SetAnimationIndex(7)
        self.assertEqual(reader.GetExecutive().Update(), 0)
        self.assertTrue(any("animation index 7 out of range" in m for m in errors.messages), errors.messages)
        self.assertEqual(len(leaves(reader.GetOutputDataObject(0))), 0)
        self.assertEqual(reader.GetWeightsOutput().GetNumberOfColumns(), 0)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + sys.argv[1:])
