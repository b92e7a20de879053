"""vtkMorphLevelOfDetail from Python: the shown level follows the screen (a near face at full
resolution, a far one coarser, fewer points, same triangles of the ladder), the kept points
are the blended input points (OriginalPointId), a phone never shows the full mesh, bad input
is an error."""
import math
import unittest

from morphnode import vtkMorphLevelOfDetail, vtkMorphNodeFilter

from vtkmodules.vtkCommonDataModel import vtkPolyData

from TestMorphNodeFrameBudget import TARGETS, face


def lod(data):
    f = vtkMorphLevelOfDetail()
    f.SetInputData(data)
    for k in range(TARGETS):
        f.SetWeight(k + 1, 0.1 * (k % 3))
    return f


class TestMorphLevelOfDetail(unittest.TestCase):
    def test_follows_the_screen(self):
        data = face()
        f = lod(data)
        f.SetPixelsPerUnit(1e6)  # a face many thousands of pixels high: full resolution
        f.Update()
        self.assertEqual(f.GetNumberOfLevels(), 4)
        self.assertEqual(f.GetLevel(), 0)
        self.assertEqual(f.GetOutput().GetNumberOfPoints(), data.GetNumberOfPoints())
        # The same points as the morph node's blend (relative weights), by OriginalPointId.
        node = vtkMorphNodeFilter()
        node.SetInputData(data)
        node.SetWeightModeToRelative()
        for k in range(TARGETS):
            node.SetWeight(k + 1, 0.1 * (k % 3))
        node.Update()
        out = f.GetOutput()
        ids = out.GetPointData().GetArray("OriginalPointId")
        for p in range(0, out.GetNumberOfPoints(), 5):
            a, b = out.GetPoint(p), node.GetOutput().GetPoint(ids.GetValue(p))
            self.assertLess(math.dist(a, b), 1e-5)
        self.assertIsNone(out.GetPointData().GetArray("target0_position"))
        # Dolly out: coarser levels, fewer points, never back, each level once.
        levels = []
        for i in range(200):
            f.SetPixelsPerUnit(1e4 * 0.95 ** i)
            f.Update()
            levels.append(f.GetLevel())
        self.assertEqual(levels, sorted(levels))
        self.assertEqual(levels[-1], 3)
        self.assertLess(f.GetOutput().GetNumberOfPoints(), data.GetNumberOfPoints() // 5)
        self.assertEqual(f.GetOutput().GetNumberOfPoints(), f.GetNumberOfLevelPoints())
        info = f.GetOutput().GetFieldData().GetArray("LevelOfDetail")
        self.assertEqual(info.GetComponent(0, 0), 3)

    def test_profile_and_bad_input(self):
        f = lod(face())
        f.SetDeviceProfile("phone")
        self.assertEqual(f.GetFinestLevel(), 1)
        self.assertAlmostEqual(f.GetFrameBudget(), 0.4)
        f.SetPixelsPerUnit(1e6)
        f.Update()
        self.assertGreaterEqual(f.GetLevel(), 1)
        self.assertIn("FinestLevel: 1", str(f))
        f.GlobalWarningDisplayOff()
        f.SetDeviceProfile("watch")
        self.assertEqual(f.GetFinestLevel(), 1)
        empty = vtkMorphLevelOfDetail()
        empty.SetInputData(vtkPolyData())
        empty.Update()
        self.assertEqual(empty.GetLevel(), -1)
        self.assertEqual(empty.GetOutput().GetNumberOfPoints(), 0)


if __name__ == "__main__":
    unittest.main()
