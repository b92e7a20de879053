"""vtkMorphNodeFilter's MeshLevels from Python: off, the output is the input's structure as
always; on, the output holds the level the screen asks for (the full mesh near, coarser and
fewer points far, the kept points exactly the blend of the levels-off output by
OriginalPointId), every part of a composite at one level (a part too small to reduce kept
whole), a phone's profile never shows the full mesh; at a coarse level the input's cell
data (by the level triangles' original cells) and the distance arrays (by OriginalPointId)
are carried; an output held downstream is never written by the next execution."""
import unittest

from morphnode import vtkMorphNodeFilter

from vtkmodules.vtkCommonCore import vtkFloatArray, vtkIntArray
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

    def test_cell_data_and_distances_at_a_coarse_level(self):
        data = face()
        # Two cell arrays: each cell's id, and a "material" per band of cells.
        tag, material = vtkFloatArray(), vtkIntArray()
        tag.SetName("CellTag")
        material.SetName("Material")
        for c in range(data.GetNumberOfCells()):
            tag.InsertNextValue(float(c))
            material.InsertNextValue(c // 97)
        data.GetCellData().AddArray(tag)
        data.GetCellData().AddArray(material)
        full = morph(data)
        full.GenerateDistanceArraysOn()
        full.Update()
        reference = full.GetOutput()
        f = morph(data)
        f.GenerateDistanceArraysOn()
        f.MeshLevelsOn()
        for i in range(200):  # dolly out to the coarsest level
            f.SetPixelsPerUnit(1e4 * 0.95 ** i)
            f.Update()
        self.assertEqual(f.GetLevel(), 3)
        out = f.GetOutput()
        self.assertLess(out.GetNumberOfCells(), data.GetNumberOfCells() // 5)
        # Cell data: every kept triangle carries its input cell's values. The input cell is
        # the triangle itself with collapsed corners moved onto their representatives, so it
        # lies where the triangle lies: within a coarse edge (the sphere is 1 across; a
        # shuffled assignment puts the median at 0.65).
        tags = out.GetCellData().GetArray("CellTag")
        materials = out.GetCellData().GetArray("Material")
        self.assertIsNotNone(tags)
        self.assertIsNotNone(materials)
        self.assertEqual(tags.GetNumberOfTuples(), out.GetNumberOfCells())

        def centroid(ds, c):
            ids = ds.GetCell(c).GetPointIds()
            return [sum(ds.GetPoint(ids.GetId(k))[i] for k in range(3)) / 3 for i in range(3)]

        distances = []
        for t in range(out.GetNumberOfCells()):
            o = int(tags.GetValue(t))
            self.assertEqual(materials.GetValue(t), o // 97)
            a, b = centroid(out, t), centroid(reference, o)
            distances.append(sum((a[i] - b[i]) ** 2 for i in range(3)) ** 0.5)
        self.assertLess(max(distances), 0.15)
        self.assertLess(sorted(distances)[len(distances) // 2], 0.06)
        self.assertEqual(len({int(tags.GetValue(t)) for t in range(out.GetNumberOfCells())}),
                         out.GetNumberOfCells())
        ids = out.GetPointData().GetArray("OriginalPointId")
        # Distance arrays: the levels-off output's, at each point's original id.
        names = ["AnimatedRegion"] + ["Distance_" + f.GetTargetName(k) for k in range(1, f.GetNumberOfTargets())]
        for name in names:
            mine, theirs = out.GetPointData().GetArray(name), reference.GetPointData().GetArray(name)
            self.assertIsNotNone(mine, name)
            self.assertEqual(mine.GetNumberOfTuples(), out.GetNumberOfPoints())
            for i in range(out.GetNumberOfPoints()):
                self.assertEqual(mine.GetValue(i), theirs.GetValue(int(ids.GetValue(i))), name)
        self.assertGreater(max(out.GetPointData().GetArray(names[1]).GetRange()), 0.0)
        self.assertIsNotNone(out.GetFieldData().GetArray("DistNorm"))
        # Off again: no distance arrays on the level.
        f.GenerateDistanceArraysOff()
        f.Update()
        self.assertIsNone(f.GetOutput().GetPointData().GetArray(names[1]))
        self.assertIsNone(f.GetOutput().GetFieldData().GetArray("DistNorm"))
        self.assertIsNotNone(f.GetOutput().GetCellData().GetArray("CellTag"))

    def test_an_output_held_downstream_is_not_written(self):
        # The level's data set and arrays are filled again in place only when no one else
        # holds them: a snapshot of the last output keeps its points.
        data = face()
        f = morph(data)
        f.MeshLevelsOn()
        f.SetFinestLevel(1)
        f.SetPixelsPerUnit(1e6)
        for _ in range(3):
            f.Update()
        self.assertEqual(f.GetLevel(), 1)
        snapshot = vtkPolyData()
        snapshot.ShallowCopy(f.GetOutput())
        before = [snapshot.GetPoint(i) for i in range(snapshot.GetNumberOfPoints())]
        normals = snapshot.GetPointData().GetNormals()
        normals_before = [normals.GetTuple3(i) for i in range(normals.GetNumberOfTuples())]
        f.SetWeight(1, 0.9)
        f.Update()
        after = f.GetOutput()
        self.assertEqual([snapshot.GetPoint(i) for i in range(snapshot.GetNumberOfPoints())], before)
        self.assertEqual([normals.GetTuple3(i) for i in range(normals.GetNumberOfTuples())], normals_before)
        self.assertNotEqual([after.GetPoint(i) for i in range(after.GetNumberOfPoints())], before)
        # Without a holder, the next executions write the same arrays again and stay exact:
        # each equals the levels-off blend at its original ids.
        del snapshot
        full = morph(data)
        for w in (0.2, 0.5, 0.7):
            f.SetWeight(2, w)
            full.SetWeight(1, 0.9)
            full.SetWeight(2, w)
            f.Update()
            full.Update()
            out = f.GetOutput()
            ids = out.GetPointData().GetArray("OriginalPointId")
            for i in range(0, out.GetNumberOfPoints(), 7):
                a, b = out.GetPoint(i), full.GetOutput().GetPoint(int(ids.GetValue(i)))
                self.assertLess(max(abs(a[c] - b[c]) for c in range(3)), 1e-5)


if __name__ == "__main__":
    unittest.main()
