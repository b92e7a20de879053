"""vtkMorphNodeFilter's FrameBudget from Python: the threshold chosen per execution from
measured morph times. A budget no morph misses never prunes, one no morph meets prunes;
turning it off gives the filter's own threshold back."""
import math
import unittest

from morphnode import vtkMorphNodeFilter

from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource

TARGETS = 6


def face():
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(40)
    sphere.SetPhiResolution(30)
    sphere.Update()
    out = vtkPolyData()
    out.DeepCopy(sphere.GetOutput())
    for k in range(TARGETS):
        delta = vtkFloatArray()
        delta.SetName("target%d_position" % k)
        delta.SetNumberOfComponents(3)
        delta.SetNumberOfTuples(out.GetNumberOfPoints())
        for p in range(out.GetNumberOfPoints()):
            x = out.GetPoint(p)
            delta.SetTuple3(p, *(0.1 * (k + 1) * math.sin(3.0 * x[c] + k) for c in range(3)))
        out.GetPointData().AddArray(delta)
    return out


def morph(data, budget):
    f = vtkMorphNodeFilter()
    f.SetInputData(data)
    f.SetWeightModeToRelative()
    f.SetOptimizerPresetByName("fixed-remaining")
    f.SetThreshold(0.9)
    f.SetFrameBudget(budget)
    return f


class TestMorphNodeFrameBudget(unittest.TestCase):
    def test_loose_and_tight(self):
        data = face()
        loose, tight = morph(data, 1000.0), morph(data, 1e-4)
        loose_active = tight_active = 0
        for frame in range(20):
            for f in (loose, tight):
                for k in range(TARGETS):
                    f.SetWeight(k + 1, 0.16 + 0.14 * math.sin(0.37 * frame + 1.3 * k))
                f.Update()
            self.assertEqual(loose.GetFrameBudgetThreshold(), 0.0)
            self.assertGreater(tight.GetFrameBudgetThreshold(), 0.0)
            self.assertLessEqual(tight.GetActiveTargetCount(), loose.GetActiveTargetCount())
            self.assertGreater(loose.GetMorphTime(), 0.0)
            loose_active += loose.GetActiveTargetCount()
            tight_active += tight.GetActiveTargetCount()
        self.assertEqual(loose_active, 20 * TARGETS)
        self.assertLess(tight_active, loose_active // 2)
        tight.SetFrameBudget(0.0)
        tight.Update()
        self.assertEqual(tight.GetFrameBudgetThreshold(), -1.0)
        self.assertLessEqual(tight.GetActiveTargetCount(), 1)

    def test_property(self):
        f = vtkMorphNodeFilter()
        self.assertEqual(f.GetFrameBudget(), 0.0)
        self.assertEqual(f.GetFrameBudgetThreshold(), -1.0)
        f.SetFrameBudget(-3.0)
        self.assertEqual(f.GetFrameBudget(), 0.0)  # clamped
        f.SetFrameBudget(2.5)
        self.assertIn("FrameBudget: 2.5 ms", str(f))


if __name__ == "__main__":
    unittest.main()
