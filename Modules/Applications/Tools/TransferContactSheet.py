# SPDX-License-Identifier: BSD-3-Clause
"""A contact sheet of a face's own targets beside transferred ones (docs/transfer.md):
row 1 the face's own, row 2 the transferred, columns neutral and the pairs of target names.

    python3 TransferContactSheet.py OWN.glb TRANSFERRED.glb MESH OUT.png \\
        jawOpen=jawOpen mouthSmileLeft=mouthSmile_L eyeBlinkLeft=eyeBlink_L

Each pair is OWN_NAME=TRANSFERRED_NAME. MESH names the mesh of both files to show (e.g.
Body). Run with Debian's python3 and PYTHONPATH at the build's morphnode package; rendered
offscreen (under xvfb-run -a without a display)."""
import sys

from morphnode import vtkMorphTargetReader

from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkFiltersCore import vtkPolyDataNormals
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkTextActor, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingFreeType  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

own_file, moved_file, mesh, out = sys.argv[1:5]
pairs = [p.split("=") for p in sys.argv[5:]]


def read(path):
    r = vtkMorphTargetReader()
    r.SetFileName(path)
    r.SetMeshName(mesh)
    r.Update()
    return r.GetOutput()


def posed(face, name):
    names = face.GetFieldData().GetAbstractArray("TargetNames")
    names = [names.GetValue(i) for i in range(names.GetNumberOfValues())]
    points = vtkPoints()
    points.DeepCopy(face.GetPoints())
    if name:
        delta = face.GetPointData().GetArray("target%d_position" % (names.index(name) - 1))
        for i in range(points.GetNumberOfPoints()):
            p = points.GetPoint(i)
            d = delta.GetTuple3(i)
            points.SetPoint(i, p[0] + d[0], p[1] + d[1], p[2] + d[2])
    copy = face.NewInstance()
    copy.ShallowCopy(face)
    copy.SetPoints(points)
    copy.GetPointData().Initialize()
    normals = vtkPolyDataNormals()
    normals.SetInputData(copy)
    normals.Update()
    return normals.GetOutput()


faces = [read(own_file), read(moved_file)]
# The camera looks at what the first pair's own target moves.
names = faces[0].GetFieldData().GetAbstractArray("TargetNames")
names = [names.GetValue(i) for i in range(names.GetNumberOfValues())]
jaw = faces[0].GetPointData().GetArray("target%d_position" % (names.index(pairs[0][0]) - 1))
moving = [faces[0].GetPoint(i) for i in range(faces[0].GetNumberOfPoints())
          if sum(c * c for c in jaw.GetTuple3(i)) > 1e-6]
centre = [sum(p[k] for p in moving) / len(moving) for k in range(3)]
centre[1] += 0.03  # between the mouth and the eyes

columns = [("neutral", None, None)] + [(a, a, b) for a, b in pairs]
size = 260
window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetSize(size * len(columns), size * 2)
window.SetMultiSamples(0)
for row, face in enumerate(faces):
    for col, (label, a, b) in enumerate(columns):
        renderer = vtkRenderer()
        renderer.SetViewport(col / len(columns), (1 - row) / 2, (col + 1) / len(columns), (2 - row) / 2)
        renderer.SetBackground(0.32, 0.34, 0.43)
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(posed(face, a if row == 0 else b))
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(0.93, 0.78, 0.68)
        renderer.AddActor(actor)
        camera = renderer.GetActiveCamera()
        camera.SetFocalPoint(*centre)
        camera.SetPosition(centre[0], centre[1], centre[2] + 0.45)
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(30)
        renderer.ResetCameraClippingRange()
        text = vtkTextActor()
        text.SetInput(("own: " if row == 0 else "transferred: ") + (label if row == 0 or not b else b))
        text.GetTextProperty().SetFontSize(14)
        text.SetPosition(6, 6)
        renderer.AddActor2D(text)
        window.AddRenderer(renderer)
window.Render()
grab = vtkWindowToImageFilter()
grab.SetInput(window)
writer = vtkPNGWriter()
writer.SetFileName(out)
writer.SetInputConnection(grab.GetOutputPort())
writer.Write()
