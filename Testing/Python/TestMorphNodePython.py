# SPDX-License-Identifier: BSD-3-Clause
"""The Python wrapping of MorphNode: import, a pipeline, errors, time through port 1."""
import math
import os
import unittest

from morphnode import vtkMorphNodeFilter
import morphnode

from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkTable
from vtkmodules.vtkCommonTransforms import vtkTransform
from vtkmodules.vtkFiltersGeneral import vtkTransformPolyDataFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource

from morphnode_testing import Errors


def scaled(source, sx, sy, sz):
    transform = vtkTransform()
    transform.Scale(sx, sy, sz)
    f = vtkTransformPolyDataFilter()
    f.SetInputConnection(source.GetOutputPort())
    f.SetTransform(transform)
    return f


class TestMorphNodePython(unittest.TestCase):
    def setUp(self):
        self.sphere = vtkSphereSource()
        self.sphere.SetThetaResolution(16)
        self.sphere.SetPhiResolution(16)
        self.wide = scaled(self.sphere, 2, 1, 1)
        self.tall = scaled(self.sphere, 1, 3, 1)
        self.morph = vtkMorphNodeFilter()
        for src in (self.sphere, self.wide, self.tall):
            self.morph.AddInputConnection(0, src.GetOutputPort())

    def test_package(self):
        self.assertTrue(morphnode.__version__)
        self.assertEqual(vtkMorphNodeFilter.__name__, "vtkMorphNodeFilter")

    def test_pipeline_blends(self):
        self.morph.SetWeight(0, 0.5)
        self.morph.SetWeight(1, 0.5)
        self.morph.Update()
        out = self.morph.GetOutput()
        self.assertEqual(out.GetNumberOfPoints(), self.sphere.GetOutput().GetNumberOfPoints())
        # A point on the equator at x = 0.5 on the unit sphere (radius 0.5).
        best = max(range(out.GetNumberOfPoints()), key=lambda i: self.sphere.GetOutput().GetPoint(i)[0])
        x_neutral = self.sphere.GetOutput().GetPoint(best)[0]
        self.assertAlmostEqual(out.GetPoint(best)[0], 1.5 * x_neutral, places=5)
        self.assertEqual(self.morph.GetNumberOfTargets(), 3)
        self.assertEqual(self.morph.GetTargetName(2), "target1")
        self.assertEqual(self.morph.GetActiveTargetCount(), 1)
        weights = out.GetFieldData().GetArray("EffectiveWeights")
        self.assertAlmostEqual(weights.GetValue(1), 0.5)

    def test_strict_mode_error_gives_empty_output(self):
        errors = Errors(self.morph)
        Errors(self.morph.GetExecutive())  # the failed update's report, kept off the console
        self.morph.SetWeightModeToStrict()
        self.morph.SetWeight(1, 0.5)  # sum 1.5
        self.morph.Update()
        self.assertEqual(self.morph.GetOutput().GetNumberOfPoints(), 0)
        self.assertTrue(any("sum to 1.5" in m for m in errors.messages), errors.messages)

    def test_weights_table_on_port_1(self):
        table = vtkTable()
        for name, value in (("target1", 0.25), ("HeadYaw", 12.0)):
            column = vtkDoubleArray()
            column.SetName(name)
            column.InsertNextValue(value)
            table.AddColumn(column)
        self.morph.SetInputData(1, table)
        self.morph.Update()
        self.assertAlmostEqual(self.morph.GetEffectiveWeight(2), 0.25)
        self.assertAlmostEqual(self.morph.GetEffectiveWeight(0), 0.75)

    def test_optimizer_settings(self):
        self.morph.SetWeight(0, 0.55)
        self.morph.SetWeight(1, 0.4)
        self.morph.SetWeight(2, 0.05)
        self.morph.SetThreshold(0.1)
        self.morph.SetRedistributionStrategyToMaximum()
        self.morph.Update()
        self.assertEqual(self.morph.GetEffectiveWeight(2), 0.0)
        self.assertAlmostEqual(self.morph.GetEffectiveWeight(0), 0.6)
        self.assertEqual(self.morph.GetRedistributionStrategyAsString(), "Maximum")
        self.assertGreater(self.morph.GetErrorBound(), 0.0)

    def test_optimizer_presets(self):
        self.morph.SetWeight(0, 0.55)
        self.morph.SetWeight(1, 0.4)
        self.morph.SetWeight(2, 0.05)
        self.morph.SetThreshold(0.1)
        self.morph.SetOptimizerPresetByName("fixed-maximum")
        self.assertEqual(self.morph.GetOptimizerPreset(), vtkMorphNodeFilter.OPTIMIZER_FIXED_MAXIMUM)
        self.assertEqual(self.morph.GetOptimizerPresetAsString(), "fixed-maximum")
        self.assertEqual(self.morph.UpdateTimeStep(0.0), 1)
        self.assertEqual(self.morph.GetEffectiveWeight(2), 0.0)
        self.morph.SetOptimizerPreset(vtkMorphNodeFilter.OPTIMIZER_NONE)
        self.morph.Update()
        self.assertAlmostEqual(self.morph.GetEffectiveWeight(2), 0.05)
        errors = Errors(self.morph)
        self.morph.SetOptimizerPresetByName("fastest")
        self.assertTrue(any("unknown optimizer method" in m for m in errors.messages), errors.messages)
        self.assertEqual(self.morph.GetOptimizerPresetAsString(), "none")

    def test_failed_update_reports_failure(self):
        errors = Errors(self.morph)
        Errors(self.morph.GetExecutive())  # keeps the executive's report off the console
        self.morph.SetWeight(1, float("nan"))
        self.assertEqual(self.morph.UpdateTimeStep(0.0), 0)
        self.assertEqual(self.morph.GetOutput().GetNumberOfPoints(), 0)
        self.assertTrue(any("weight 1 is nan" in m for m in errors.messages), errors.messages)


if __name__ == "__main__":
    unittest.main()
