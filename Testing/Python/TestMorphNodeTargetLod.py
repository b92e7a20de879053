"""vtkMorphNodeFilter's target level of detail and device profiles from Python: targets whose
weighted reach projects below TargetPixelBound pixels are left out (the error bound holds on
every point), a near face keeps them all; a profile sets the budget and the pixel bound."""
import math
import unittest

from morphnode import vtkMorphNodeFilter

from TestMorphNodeFrameBudget import TARGETS, face


def morph(data, ppu, bound=1.0):
    f = vtkMorphNodeFilter()
    f.SetInputData(data)
    f.SetWeightModeToRelative()
    f.SetPixelsPerUnit(ppu)
    f.SetTargetPixelBound(bound)
    return f


def blend(data, weights):
    """The unoptimized blend, for the error against it."""
    f = vtkMorphNodeFilter()
    f.SetInputData(data)
    f.SetWeightModeToRelative()
    for k, w in enumerate(weights):
        f.SetWeight(k + 1, w)
    f.Update()
    return f.GetOutput()


class TestMorphNodeTargetLod(unittest.TestCase):
    def test_far_faces_blend_fewer_targets_within_the_bound(self):
        data = face()
        near, far = morph(data, 1e5), morph(data, 20.0)
        near_active = far_active = 0
        for frame in range(10):
            weights = [0.02 + 0.3 * max(0.0, math.sin(0.37 * frame + 1.3 * k)) for k in range(TARGETS)]
            for f in (near, far):
                for k, w in enumerate(weights):
                    f.SetWeight(k + 1, w)
                f.Update()
            near_active += near.GetActiveTargetCount()
            far_active += far.GetActiveTargetCount()
            # The bound: no point farther than a pixel from the unoptimized blend.
            self.assertLessEqual(far.GetErrorBound() * 20.0, 1.0 + 1e-9)
            exact = blend(data, weights)
            worst = 0.0
            out = far.GetOutput()
            for p in range(0, out.GetNumberOfPoints(), 7):
                a, b = out.GetPoint(p), exact.GetPoint(p)
                worst = max(worst, math.dist(a, b))
            self.assertLessEqual(worst * 20.0, 1.0 + 1e-5)
            self.assertEqual(far.GetFrameBudgetThreshold(), -1.0)  # no budget: no threshold chosen
        self.assertEqual(near_active, 10 * TARGETS)
        self.assertLess(far_active, near_active)
        # Off (no screen): every target again.
        far.SetPixelsPerUnit(0.0)
        far.Update()
        self.assertEqual(far.GetActiveTargetCount(), TARGETS)

    def test_profiles(self):
        f = vtkMorphNodeFilter()
        self.assertIsNone(f.GetDeviceProfile())
        f.SetDeviceProfile("phone")
        self.assertEqual(f.GetDeviceProfile(), "phone")
        self.assertAlmostEqual(f.GetFrameBudget(), 0.4)
        self.assertEqual(f.GetTargetPixelBound(), 1.0)
        f.SetDeviceProfile("Desktop")
        self.assertEqual(f.GetDeviceProfile(), "desktop")
        self.assertAlmostEqual(f.GetFrameBudget(), 2.0)
        self.assertEqual(f.GetTargetPixelBound(), 0.25)
        f.GlobalWarningDisplayOff()
        f.SetDeviceProfile("watch")  # an error; nothing changes
        self.assertEqual(f.GetDeviceProfile(), "desktop")
        self.assertAlmostEqual(f.GetFrameBudget(), 2.0)
        self.assertIn("DeviceProfile: desktop", str(f))
        f.SetDeviceProfile("")
        self.assertIsNone(f.GetDeviceProfile())


if __name__ == "__main__":
    unittest.main()
