"""vtkMorphNodeFilter's MeshLevels from Python: off, the output is the input's structure as
always; on, the output holds the level the screen asks for (the full mesh near, coarser and
fewer points far, the kept points exactly the blend of the levels-off output by
OriginalPointId), every part of a composite at one level (a part too small to reduce kept
whole), a phone's profile never shows the full mesh."""
import unittest

from morphnode import vtkMorphNodeFilter

from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource

from TestMorphNodeFrameBudget import TARGETS, face


def scaled(data, scale, dx):
    """A copy of `data` scaled by `scale` and moved by `dx` along x, targets scaled too."""
    out = vtkPolyData()
    out.DeepCopy(data)
    points = out.GetPoints()
    for p in range(out.GetNumberOfPoints()):
        x = points.GetPoint(p)
        points.SetPoint(p, x[0] * scale + dx, x[1] * scale, x[2] * scale)
    for k in range(TARGETS):
        delta = out.GetPointData().GetArray("target%d_position" % k)
        for p in range(out.GetNumberOfPoints()):
            delta.SetTuple3(p, *(scale * v for v in delta.GetTuple3(p)))
    return out


def morph(data):
    f = vtkMorphNodeFilter()
    f.SetInputData(data)
    f.SetWeightModeToRelative()
    for k in range(TARGETS):
        f.SetWeight(k + 1, 0.1 * (k % 3))
    return f


def level_of(data_set):
    return int(data_set.GetFieldData().GetArray("LevelOfDetail").GetComponent(0, 0))


@unittest.skipUnless(vtkMorphNodeFilter.HasMeshLevels(), "built without the reduction (OpenMesh)")
class TestMorphNodeMeshLevels(unittest.TestCase):
    def test_off_is_the_input_structure(self):
        data = face()
        f = morph(data)
        f.SetPixelsPerUnit(10.0)
        f.Update()
        out = f.GetOutput()
        self.assertEqual(out.GetNumberOfPoints(), data.GetNumberOfPoints())
        self.assertEqual(out.GetNumberOfCells(), data.GetNumberOfCells())
        self.assertIsNone(out.GetPointData().GetArray("OriginalPointId"))
        self.assertIsNone(out.GetFieldData().GetArray("LevelOfDetail"))
        self.assertEqual(f.GetLevel(), -1)

    def test_follows_the_screen(self):
        data = face()
        full = morph(data)
        full.Update()
        f = morph(data)
        f.MeshLevelsOn()
        f.SetPixelsPerUnit(1e6)  # a face many thousands of pixels high: full resolution
        f.Update()
        self.assertEqual(f.GetLevel(), 0)
        out = f.GetOutput()
        self.assertEqual(out.GetNumberOfPoints(), data.GetNumberOfPoints())
        ids = out.GetPointData().GetArray("OriginalPointId")
        self.assertEqual(sorted(int(ids.GetValue(i)) for i in range(ids.GetNumberOfTuples())),
                         list(range(data.GetNumberOfPoints())))
        # The same points as the full blend, in the ladder's order.
        for i in range(out.GetNumberOfPoints()):
            a = out.GetPoint(i)
            b = full.GetOutput().GetPoint(int(ids.GetValue(i)))
            self.assertLess(max(abs(a[c] - b[c]) for c in range(3)), 1e-5)
        self.assertIsNotNone(out.GetFieldData().GetArray("EffectiveWeights"))
        self.assertIsNone(out.GetPointData().GetArray("target0_position"))
        # Dolly out: coarser levels, fewer points, never back.
        levels = []
        for i in range(200):
            f.SetPixelsPerUnit(1e4 * 0.95 ** i)
            f.Update()
            levels.append(f.GetLevel())
            out = f.GetOutput()
            self.assertEqual(level_of(out), f.GetLevel())
            self.assertEqual(out.GetFieldData().GetArray("LevelOfDetail").GetComponent(0, 4),
                             out.GetNumberOfPoints())
        self.assertEqual(levels, sorted(levels))
        self.assertEqual(levels[-1], 3)
        out = f.GetOutput()
        self.assertLess(out.GetNumberOfPoints(), data.GetNumberOfPoints() // 5)
        self.assertLess(out.GetNumberOfCells(), data.GetNumberOfCells() // 5)
        ids = out.GetPointData().GetArray("OriginalPointId")
        self.assertEqual(ids.GetNumberOfTuples(), out.GetNumberOfPoints())
        # Every triangle on the level's points.
        polys = out.GetPolys()
        self.assertLess(max(polys.GetData().GetValue(i) for i in range(polys.GetData().GetNumberOfTuples())
                            if i % 4), out.GetNumberOfPoints())
        # Back to levels off: the input's structure again.
        f.MeshLevelsOff()
        f.Update()
        self.assertEqual(f.GetOutput().GetNumberOfPoints(), data.GetNumberOfPoints())
        self.assertEqual(f.GetLevel(), -1)

    def test_parts_switch_together(self):
        blocks = vtkMultiBlockDataSet()
        small = vtkSphereSource()
        small.SetThetaResolution(6)
        small.SetPhiResolution(5)  # under 100 triangles: kept whole
        small.Update()
        eye = vtkPolyData()
        eye.DeepCopy(small.GetOutput())
        parts = [face(), scaled(face(), 3.0, 5.0), eye]
        for i, p in enumerate(parts):
            blocks.SetBlock(i, p)
        f = morph(blocks)
        f.MeshLevelsOn()
        seen = set()
        for i in range(120):
            f.SetPixelsPerUnit(1e2 * 0.88 ** i)
            f.Update()
            out = f.GetOutputDataObject(0)
            levels = [level_of(out.GetBlock(b)) for b in range(2)]
            self.assertEqual(levels, [f.GetLevel()] * 2)
            # The small part at its only level, whole, with its own cells.
            self.assertEqual(level_of(out.GetBlock(2)), 0)
            self.assertEqual(out.GetBlock(2).GetNumberOfPoints(), eye.GetNumberOfPoints())
            self.assertEqual(out.GetBlock(2).GetNumberOfCells(), eye.GetNumberOfCells())
            seen.add(f.GetLevel())
        self.assertEqual(seen, {0, 1, 2, 3})

    def test_profile(self):
        data = face()
        f = morph(data)
        f.MeshLevelsOn()
        f.SetDeviceProfile("phone")
        self.assertEqual(f.GetFinestLevel(), 1)
        self.assertEqual(f.GetLevelPixelBound(), 2.0)
        f.SetPixelsPerUnit(1e6)
        for _ in range(5):
            f.Update()
            self.assertGreaterEqual(f.GetLevel(), 1)
            self.assertLess(f.GetOutput().GetNumberOfPoints(), data.GetNumberOfPoints())
        self.assertIn("MeshLevels: On", str(f))


if __name__ == "__main__":
    unittest.main()
