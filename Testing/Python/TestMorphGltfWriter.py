# SPDX-License-Identifier: BSD-3-Clause
"""vtkMorphGltfWriter from Python: the default head with a performance built in numpy
(weights of its targets, head yaw) written to .glb, read back by vtkMorphTargetReader (the
parts) and VTK's vtkGLTFReader (one animation, its time range); the behaviour source's
whole track (port 1) as the performance; errors."""
import os
import tempfile
import unittest

import numpy as np

from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkTable
from vtkmodules.vtkIOGeometry import vtkGLTFReader
from vtkmodules.util.numpy_support import numpy_to_vtk

from morphnode import vtkMorphGltfWriter, vtkMorphTargetReader, vtkBehaviorTimeSource

SOURCE = os.environ.get("MORPHNODE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HEAD = os.path.join(SOURCE, "Data", "DefaultFace", "default_head.glb")
OUT = os.environ.get("MORPHNODE_TEST_OUTPUT_DIR", tempfile.gettempdir())


def column(name, values):
    array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
    array.SetName(name)
    return array


class TestMorphGltfWriter(unittest.TestCase):
    def setUp(self):
        self.reader = vtkMorphTargetReader()
        self.reader.SetFileName(HEAD)
        self.reader.Update()

    def test_numpy_performance(self):
        frames = 31
        times = np.arange(frames) / 30.0
        table = vtkTable()
        table.AddColumn(column("Time", times))
        table.AddColumn(column("O", 0.5 + 0.5 * np.sin(times * 6)))
        table.AddColumn(column("EyesClosed", (times > 0.5).astype(float)))
        table.AddColumn(column("HeadYaw", 10 * np.sin(times * 3)))
        writer = vtkMorphGltfWriter()
        writer.SetInputConnection(self.reader.GetOutputPort())
        writer.SetPerformanceData(table)
        path = os.path.join(OUT, "python_default_head.glb")
        writer.SetFileName(path)
        self.assertEqual(writer.Write(), 1)
        self.assertEqual(writer.GetNumberOfFrames(), frames)
        self.assertEqual(writer.GetNumberOfWeightColumns(), 2)
        self.assertIn("ApplyOptimizer", str(writer))  # PrintSelf

        back = vtkMorphTargetReader()
        back.SetFileName(path)
        back.Update()
        self.assertEqual(back.GetOutputDataObject(0).GetNumberOfPartitionedDataSets(),
                         self.reader.GetOutputDataObject(0).GetNumberOfPartitionedDataSets())
        gltf = vtkGLTFReader()
        gltf.SetFileName(path)
        gltf.UpdateInformation()
        self.assertEqual(gltf.GetNumberOfAnimations(), 1)
        self.assertAlmostEqual(gltf.GetAnimationDuration(0), times[-1], places=5)

    def test_behaviour_track(self):
        behavior = vtkBehaviorTimeSource()
        behavior.SetDuration(2.0)
        behavior.SetMood("happy", 0.6)
        writer = vtkMorphGltfWriter()
        writer.SetInputConnection(self.reader.GetOutputPort())
        writer.SetPerformanceConnection(behavior.GetOutputPort(1))
        writer.ApplyOptimizerOn()
        writer.SetThreshold(0.2)
        path = os.path.join(OUT, "python_behaviour.gltf")
        writer.SetFileName(path)
        self.assertEqual(writer.Write(), 1)
        self.assertEqual(writer.GetNumberOfFrames(), 61)
        with open(path, "rb") as f:
            self.assertEqual(f.read(1), b"{")  # .gltf: JSON

    def test_errors(self):
        table = vtkTable()
        table.AddColumn(column("Time", [0.0, 0.1, 0.1]))
        table.AddColumn(column("O", [0.0, 0.5, 1.0]))
        writer = vtkMorphGltfWriter()
        writer.GlobalWarningDisplayOff()
        writer.SetInputConnection(self.reader.GetOutputPort())
        writer.SetPerformanceData(table)
        path = os.path.join(OUT, "python_bad.glb")
        if os.path.exists(path):
            os.remove(path)
        writer.SetFileName(path)
        writer.Write()
        self.assertNotEqual(writer.GetErrorCode(), 0)
        self.assertFalse(os.path.exists(path))


if __name__ == "__main__":
    unittest.main()
