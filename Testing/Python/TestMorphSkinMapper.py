# SPDX-License-Identifier: BSD-3-Clause
"""vtkMorphSkinMapper from Python: a square bound to a joint moved 0.6 along x is drawn
there (pixels read back), the same square without SkinJointDeltas where it is; with NaN
deltas nothing is drawn and the error says why; the skin filter's pose-only output of the
MakeHuman avatar drawn by it looks as the CPU's re-skin (when the avatar is there)."""
import math
import os
import unittest

from morphnode import (vtkMorphNodeFilter, vtkMorphSkinFilter, vtkMorphSkinMapper,
                       vtkMorphTargetReader)

from vtkmodules.vtkCommonCore import vtkFloatArray, vtkIntArray, vtkPoints, vtkUnsignedShortArray
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderWindow,
                                         vtkRenderer, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL classes behind the factories)

from morphnode_testing import Errors

AVATAR = os.path.join(os.environ.get("MORPHNODE_AVATAR_DIR", ""), "makehuman_avatar.glb")
IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]


def square(deltas, with_deltas=True):
    """A square of side 0.2 at the origin facing +z, bound to joint 1 of `deltas`."""
    poly = vtkPolyData()
    points = vtkPoints()
    joints = vtkUnsignedShortArray()
    joints.SetName("SkinJoints")
    joints.SetNumberOfComponents(4)
    weights = vtkFloatArray()
    weights.SetName("SkinWeights")
    weights.SetNumberOfComponents(4)
    for x, y in ((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)):
        points.InsertNextPoint(x, y, 0)
        joints.InsertNextTuple4(1, 0, 0, 0)
        weights.InsertNextTuple4(1, 0, 0, 0)
    cells = vtkCellArray()
    cells.InsertNextCell(4, [0, 1, 2, 3])
    poly.SetPoints(points)
    poly.SetPolys(cells)
    poly.GetPointData().AddArray(joints)
    poly.GetPointData().AddArray(weights)
    indices = vtkIntArray()
    indices.SetName("SkinJointIndices")
    d = vtkFloatArray()
    d.SetName("SkinJointDeltas")
    d.SetNumberOfComponents(12)
    for k, delta in enumerate(deltas):
        indices.InsertNextValue(k)
        d.InsertNextTuple(delta)
    poly.GetFieldData().AddArray(indices)
    if with_deltas:
        poly.GetFieldData().AddArray(d)
    return poly


# One offscreen window for the whole test: VTK 9.1 opens an X connection per window, and
# opening many in a row now and then fails ("bad X server connection").
WINDOW = vtkRenderWindow()
WINDOW.SetOffScreenRendering(1)
WINDOW.SetMultiSamples(0)


def draw(polys, mapper_class, size=200, camera=None):
    """The polydata drawn (orthographic [-1, 1]^2 unless `camera` sets the view), as a
    function (x, y) -> lit (r + g + b of the pixel at that point), the image and mappers."""
    window = WINDOW
    renderers = window.GetRenderers()
    while renderers.GetNumberOfItems():
        window.RemoveRenderer(renderers.GetFirstRenderer())
    window.SetSize(size, size)
    renderer = vtkRenderer()
    window.AddRenderer(renderer)
    mappers = []
    for poly in polys:
        mapper = mapper_class()
        mapper.ScalarVisibilityOff()
        mapper.SetInputData(poly)
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(0.86, 0.72, 0.62)
        renderer.AddActor(actor)
        mappers.append(mapper)
    cam = renderer.GetActiveCamera()
    if camera:
        camera(renderer, cam)
    else:
        cam.ParallelProjectionOn()
        cam.SetParallelScale(1.0)
        cam.SetPosition(0, 0, 5)
        cam.SetFocalPoint(0, 0, 0)
        renderer.ResetCameraClippingRange(-2, 2, -2, 2, -2, 2)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    image = grab.GetOutput()
    scalars = image.GetPointData().GetScalars()

    def lit(x, y):
        px, py = round(size / 2 * (x + 1)), round(size / 2 * (y + 1))
        return sum(scalars.GetTuple3(py * size + px))
    return lit, scalars, mappers


class TestMorphSkinMapper(unittest.TestCase):
    def test_a_joint_moves_the_square(self):
        moved = list(IDENTITY)
        moved[3] = 0.6
        lit, _, mappers = draw([square([IDENTITY, moved])], vtkMorphSkinMapper)
        self.assertEqual(mappers[0].GetSkinState(), vtkMorphSkinMapper.SKIN_GPU)
        self.assertEqual(mappers[0].GetNumberOfJoints(), 2)
        self.assertEqual(lit(0, 0), 0)
        self.assertGreater(lit(0.6, 0), 60)
        # Without the deltas: where it is.
        lit, _, mappers = draw([square([IDENTITY, moved], False)], vtkMorphSkinMapper)
        self.assertEqual(mappers[0].GetSkinState(), vtkMorphSkinMapper.SKIN_NONE)
        self.assertGreater(lit(0, 0), 60)
        self.assertEqual(lit(0.6, 0), 0)
        self.assertIn("SkinState: none", str(mappers[0]))

    def test_nan_deltas_draw_nothing(self):
        moved = list(IDENTITY)
        moved[3] = math.nan
        poly = square([IDENTITY, moved])
        mapper = vtkMorphSkinMapper()
        errors = Errors(mapper)
        lit, _, _ = draw([poly], lambda: mapper)
        self.assertEqual(mapper.GetSkinState(), vtkMorphSkinMapper.SKIN_DAMAGED)
        self.assertIn("SkinJointDeltas of joint 1 is not finite", " ".join(errors.messages))
        self.assertEqual(lit(0, 0), 0)

    @unittest.skipUnless(os.path.exists(AVATAR), "MakeHuman avatar not found: " + AVATAR)
    def test_avatar_on_the_gpu_as_on_the_cpu(self):
        reader = vtkMorphTargetReader()
        reader.SetFileName(AVATAR)
        morph = vtkMorphNodeFilter()
        morph.SetInputConnection(reader.GetOutputPort())
        morph.SetWeightModeToRelative()
        skin = vtkMorphSkinFilter()
        skin.SetInputConnection(morph.GetOutputPort())
        skin.SetHeadYaw(-30)
        skin.SetEyeYaw(20)

        def face(renderer, cam):
            b = [0.0] * 6
            self.assertTrue(skin.GetHeadBounds(b))
            c = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
            cam.SetFocalPoint(*c)
            cam.SetPosition(c[0], c[1], c[2] + 2.6 * (b[3] - b[2]))
            cam.SetViewAngle(30)
            renderer.ResetCameraClippingRange()

        def leaves():
            skin.Update()
            out = skin.GetOutput()
            return [out.GetPartition(i, 0) for i in range(out.GetNumberOfPartitionedDataSets())]

        _, cpu, _ = draw(leaves(), vtkPolyDataMapper, 160, face)
        skin.SkinPointsOff()
        _, gpu, mappers = draw(leaves(), vtkMorphSkinMapper, 160, face)
        self.assertEqual(skin.GetNumberOfPosedOnlyParts(), 7)
        self.assertEqual([m.GetSkinState() for m in mappers], [vtkMorphSkinMapper.SKIN_GPU] * 7)
        _, plain, _ = draw(leaves(), vtkPolyDataMapper, 160, face)

        def differing(a, b):
            n = a.GetNumberOfTuples()
            return sum(1 for i in range(n)
                       if max(abs(p - q) for p, q in zip(a.GetTuple3(i), b.GetTuple3(i))) > 24) / n
        self.assertLess(differing(cpu, gpu), 0.002)
        self.assertGreater(differing(cpu, plain), 0.05)  # the negative control: head not turned


if __name__ == "__main__":
    unittest.main()
