# SPDX-License-Identifier: BSD-3-Clause
"""vtkMorphSkinFilter from Python on the shared MakeHuman avatar: the reader shows it at
rest with its skin arrays, the gaze turns the eyeballs about their joints, the head pose
moves the head and not the feet, the pose from a table, PrintSelf, a damaged skin refused;
the skin filter as the morph node's pose filter (one pass) gives the second pass's parts."""
import math
import os
import unittest

from morphnode import vtkMorphNodeFilter, vtkMorphSkinFilter, vtkMorphTargetReader

from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkTable

from morphnode_testing import Errors

AVATAR = os.path.join(os.environ.get("MORPHNODE_AVATAR_DIR", ""), "makehuman_avatar.glb")


def parts(collection):
    return {collection.GetMetaData(i).Get(vtkCompositeDataSet.NAME()): collection.GetPartition(i, 0)
            for i in range(collection.GetNumberOfPartitionedDataSets())}


def centroid(part):
    n = part.GetNumberOfPoints()
    return [sum(part.GetPoint(i)[c] for i in range(0, n, 7)) / len(range(0, n, 7)) for c in range(3)]


@unittest.skipUnless(os.path.exists(AVATAR), "MakeHuman avatar not found: " + AVATAR)
class TestMorphSkinFilter(unittest.TestCase):
    def setUp(self):
        self.reader = vtkMorphTargetReader()
        self.reader.SetFileName(AVATAR)
        self.morph = vtkMorphNodeFilter()
        self.morph.SetInputConnection(self.reader.GetOutputPort())
        self.morph.SetWeightModeToRelative()
        self.skin = vtkMorphSkinFilter()
        self.skin.SetInputConnection(self.morph.GetOutputPort())

    def run_skin(self):
        self.skin.Update()
        return parts(self.skin.GetOutput())

    def test_rest_and_arrays(self):
        rest = self.run_skin()
        self.assertEqual(len(rest), 7)
        self.assertEqual(self.skin.GetNumberOfSkinnedParts(), 7)
        self.assertTrue(self.skin.GetHasEyeBones())
        self.assertIn("left eye 'LeftEye'", self.skin.GetBones())
        body = rest["Body"]
        self.assertIsNotNone(body.GetPointData().GetArray("SkinWeights"))
        self.assertEqual(body.GetFieldData().GetAbstractArray("SkeletonNames").GetNumberOfValues(), 84)  # 76 joints, Armature, 7 mesh nodes

    def test_gaze_and_head(self):
        rest = self.run_skin()
        eye0, body0 = centroid(rest["EyeLeft"]), rest["Body"].GetPoint(0)
        self.skin.SetEyeYaw(25)
        turned = self.run_skin()
        self.assertGreater(math.dist(centroid(turned["EyeLeft"]), eye0), 0.001)
        self.assertLess(math.dist(centroid(turned["EyeLeft"]), eye0), 0.01)  # in its socket
        self.skin.SetEyeYaw(0)
        # The pose from a table (the behaviour's channels) wins over the properties.
        table = vtkTable()
        for name, value in (("HeadYaw", 30.0), ("EyeYaw", 0.0)):
            column = vtkDoubleArray()
            column.SetName(name)
            column.InsertNextValue(value)
            table.AddColumn(column)
        self.skin.SetInputData(1, table)
        headed = self.run_skin()
        self.assertGreater(math.dist(centroid(headed["EyeLeft"]), eye0), 0.02)
        lowest = min(range(rest["Body"].GetNumberOfPoints()), key=lambda i: rest["Body"].GetPoint(i)[1])
        self.assertLess(math.dist(headed["Body"].GetPoint(lowest), rest["Body"].GetPoint(lowest)), 1e-6)
        del body0

    def test_posed_in_the_morph_nodes_pass(self):
        self.skin.SetHeadYaw(20)
        self.skin.SetEyeYaw(-10)
        self.skin.SkinPointsOff()
        two = self.run_skin()
        morph = vtkMorphNodeFilter()
        morph.SetInputConnection(self.reader.GetOutputPort())
        morph.SetWeightModeToRelative()
        poser = vtkMorphSkinFilter()
        poser.SetHeadYaw(20)
        poser.SetEyeYaw(-10)
        poser.SkinPointsOff()
        morph.SetPoseFilter(poser)
        self.assertIs(morph.GetPoseFilter(), poser)
        morph.Update()
        one = parts(morph.GetOutputDataObject(0))
        self.assertEqual(poser.GetNumberOfPosedOnlyParts(), 7)
        for name, part in two.items():
            deltas = [one[name].GetFieldData().GetArray("SkinJointDeltas"),
                      part.GetFieldData().GetArray("SkinJointDeltas")]
            self.assertEqual(deltas[0].GetNumberOfTuples(), deltas[1].GetNumberOfTuples())
            self.assertEqual([deltas[0].GetValue(i) for i in range(0, deltas[0].GetNumberOfValues(), 5)],
                             [deltas[1].GetValue(i) for i in range(0, deltas[1].GetNumberOfValues(), 5)])
            self.assertEqual(one[name].GetFieldData().GetArray("SkinPose").GetValue(0), 20.0)
        self.assertIn("PoseFilter: vtkMorphSkinFilter", str(morph))

    def test_print_and_damage(self):
        self.assertIn("NeckShare: 0.4", str(self.skin))
        self.reader.Update()
        head = self.reader.GetOutputDataObject(0)
        body = parts(head)["Body"]
        body.GetPointData().GetArray("SkinWeights").SetValue(0, float("nan"))
        skin = vtkMorphSkinFilter()
        skin.SetInputData(head)
        skin.SetHeadYaw(10)
        errors = Errors(skin)
        skin.Update()
        self.assertTrue(any("weight" in m for m in errors.messages), errors.messages)
        self.assertEqual(skin.GetOutput().GetNumberOfPartitionedDataSets(), 0)


if __name__ == "__main__":
    unittest.main()
