# SPDX-License-Identifier: BSD-3-Clause
"""vtkMorphTransferFilter from Python: the decimated ICT face given its own targets back
through a turned and scaled copy (exact up to float), the arrays and names it adds, and a
clear error for a source that is not a face."""
import math
import os
import unittest

from morphnode import vtkMorphTargetReader, vtkMorphTransferFilter

from vtkmodules.vtkCommonTransforms import vtkTransform
from vtkmodules.vtkFiltersGeneral import vtkTransformPolyDataFilter

from morphnode_testing import Errors

SOURCE_DIR = os.environ.get("MORPHNODE_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
FACEKIT = os.environ.get("MORPHNODE_FACEKIT_DIR", "")
FACE = os.path.join(FACEKIT, "ict_face_dec70_sparse53.glb")


def reader(path):
    r = vtkMorphTargetReader()
    r.SetFileName(path)
    r.SetMeshIndex(0)
    return r


@unittest.skipUnless(os.path.exists(FACE), "ICT-FaceKit not found: " + FACE)
class TransferFilter(unittest.TestCase):
    def test_similar_copy_gets_the_targets_exactly(self):
        source = reader(FACE)
        # The target: the face turned by 20 degrees and scaled by 1.2, its targets dropped.
        transform = vtkTransform()
        transform.RotateY(20.0)
        transform.Scale(1.2, 1.2, 1.2)
        moved = vtkTransformPolyDataFilter()
        moved.SetTransform(transform)
        moved.SetInputConnection(source.GetOutputPort())
        moved.Update()
        bare = moved.GetOutput().NewInstance()
        bare.ShallowCopy(moved.GetOutput())
        bare.GetPointData().Initialize()
        transfer = vtkMorphTransferFilter()
        transfer.SetInputData(bare)
        transfer.SetSourceConnection(source.GetOutputPort())
        transfer.Update()
        out = transfer.GetOutput()
        self.assertEqual(out.GetNumberOfPoints(), bare.GetNumberOfPoints())
        names = out.GetFieldData().GetAbstractArray("TargetNames")
        self.assertEqual(names.GetNumberOfValues(), 54)
        jaw = [names.GetValue(i) for i in range(54)].index("jawOpen") - 1
        self.assertAlmostEqual(transfer.GetScale(), 1.2, places=5)
        got = out.GetPointData().GetArray("target%d_position" % jaw)
        want = source.GetOutput().GetPointData().GetArray("target%d_position" % jaw)
        worst = 0.0
        for i in range(out.GetNumberOfPoints()):
            w = transform.TransformVector(want.GetTuple3(i))
            worst = max(worst, math.dist(got.GetTuple3(i), w))
        self.assertLess(worst, 1e-5)  # metres: float deltas of a 2 cm motion
        confidence = out.GetPointData().GetArray("TransferConfidence")
        self.assertGreater(confidence.GetRange()[0], 0.5)
        side = out.GetPointData().GetArray("TransferSide")
        self.assertEqual(side.GetRange(), (-3.0, 3.0))

    def test_a_source_that_is_not_a_face(self):
        head = reader(os.path.join(SOURCE_DIR, "Data", "DefaultFace", "default_head.glb"))
        face = reader(FACE)
        transfer = vtkMorphTransferFilter()
        transfer.SetInputConnection(face.GetOutputPort())
        transfer.SetSourceConnection(head.GetOutputPort())
        errors = Errors(transfer)
        transfer.Update()
        self.assertTrue(any("not a face" in m for m in errors.messages), errors.messages)
        self.assertEqual(transfer.GetOutput().GetNumberOfPoints(), 0)


if __name__ == "__main__":
    unittest.main()
