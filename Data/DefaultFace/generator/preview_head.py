#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Renders the default head (or any multi-part glTF face) in poses, with VTK's own glTF reader.

Each pose is a set of target weights by name ("A", "O=0.6", "EyesClosed+MouthSmile=0.8"); the
weights are written into the meshes' default weights (mesh.weights) of a temporary copy of the
file, which vtkGLTFReader applies to every mesh that has a target of that name. Every primitive
is coloured by its material's baseColorFactor times its COLOR_0, as glTF defines it.

    xvfb-run -a python3 preview_head.py Data/DefaultFace/default_head.glb out.png \\
        --poses neutral A O EyesClosed MouthSmile --views front threequarter

makes one picture with a row per view and a column per pose. "gaze:YAW:PITCH" in a pose turns
the eye nodes (EyeLeft, EyeRight) by yaw toward the character's left and pitch up, in degrees.
Needs VTK's Python module (Debian: python3-vtk9); --palette also Pillow.
"""

import argparse
import json
import math
import os
import struct
import sys
import tempfile

import vtk
from vtk.util import numpy_support

VIEWS = {
    # name: (azimuth, elevation) of the camera around the head, degrees
    "front": (0.0, 0.0),
    "threequarter": (38.0, 3.0),
    "side": (90.0, 0.0),
    "left": (-38.0, 6.0),
    "below": (0.0, -18.0),
    "level": (0.0, 0.0),
    "back": (160.0, 15.0),
    "top": (20.0, 60.0),
}


def read_glb(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2:
        raise SystemExit(f"{path}: not a glTF 2.0 binary")
    json_length, json_type = struct.unpack_from("<II", data, 12)
    document = json.loads(data[20:20 + json_length].decode("utf-8"))
    return document, data[20 + json_length:]


def write_glb(path, document, rest):
    text = json.dumps(document).encode("utf-8")
    text += b" " * ((4 - len(text) % 4) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + len(rest)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A))
        f.write(text)
        f.write(rest)


def parse_pose(text):
    """'neutral', 'A', 'O=0.6', 'EyesClosed+MouthSmile=0.8', 'gaze:20:-10+A'
    -> (label, {name: weight}, (yaw, pitch) of the eyes in degrees or None)."""
    weights = {}
    gaze = None
    if text.lower() != "neutral":
        for item in text.split("+"):
            if item.startswith("gaze:"):
                _, yaw, pitch = item.split(":")
                gaze = (float(yaw), float(pitch))
                continue
            name, _, value = item.partition("=")
            weights[name] = float(value) if value else 1.0
    return text, weights, gaze


def gaze_rotation(yaw, pitch):
    """Unit quaternion (x, y, z, w): turn toward +X (the character's left) by yaw, then up
    by pitch, both in degrees; the eyes look along +Z at rest."""
    hy, hp = math.radians(yaw) / 2.0, math.radians(-pitch) / 2.0
    cy, sy, cp, sp = math.cos(hy), math.sin(hy), math.cos(hp), math.sin(hp)
    return [cy * sp, sy * cp, -sy * sp, cy * cp]


def posed_copy(document, rest, weights, gaze, directory, index):
    doc = json.loads(json.dumps(document))
    if gaze is not None:
        for node in doc.get("nodes", []):
            if node.get("name") in ("EyeLeft", "EyeRight"):
                node["rotation"] = gaze_rotation(*gaze)
    used = set()
    for mesh in doc.get("meshes", []):
        names = mesh.get("extras", {}).get("targetNames", [])
        if not names:
            continue
        mesh["weights"] = [weights.get(n, 0.0) for n in names]
        used.update(n for n in names if n in weights)
    unknown = set(weights) - used
    if unknown:
        raise SystemExit("no mesh has a target named " + ", ".join(sorted(unknown)))
    path = os.path.join(directory, f"pose{index}.glb")
    write_glb(path, doc, rest)
    return path


def actors_for(path, document, culling, hidden=()):
    reader = vtk.vtkGLTFReader()
    reader.SetFileName(path)
    reader.Update()
    actors = []
    materials = document.get("materials", [])

    def visit(block, name):
        if block is None:
            return
        if block.IsA("vtkMultiBlockDataSet"):
            for i in range(block.GetNumberOfBlocks()):
                md = block.GetMetaData(i)
                child_name = md.Get(vtk.vtkCompositeDataSet.NAME()) if md.Has(vtk.vtkCompositeDataSet.NAME()) else ""
                if block.GetBlock(i) is not None and not block.GetBlock(i).IsA("vtkMultiBlockDataSet"):
                    actors.append(make_actor(block.GetBlock(i), name, i))
                else:
                    visit(block.GetBlock(i), child_name)

    def make_actor(polydata, mesh_name, primitive_index):
        mesh_index = int(mesh_name.split("_")[-1])
        if document["meshes"][mesh_index].get("name") in hidden:
            return None
        primitive = document["meshes"][mesh_index]["primitives"][primitive_index]
        material = materials[primitive["material"]] if "material" in primitive else {}
        pbr = material.get("pbrMetallicRoughness", {})
        base = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
        roughness = pbr.get("roughnessFactor", 1.0)
        pd = vtk.vtkPolyData()
        pd.ShallowCopy(polydata)
        normals = pd.GetPointData().GetArray("NORMAL")
        if normals is not None:
            pd.GetPointData().SetNormals(normals)
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputData(pd)
        colors = pd.GetPointData().GetArray("COLOR_0")
        if colors is not None:
            c = numpy_support.vtk_to_numpy(colors)[:, :3]
            rgb = (c * base[:3] * 255.0).clip(0, 255).astype("uint8")
            array = numpy_support.numpy_to_vtk(rgb, deep=1)
            array.SetName("rgb")
            pd.GetPointData().SetScalars(array)
            mapper.SetColorModeToDirectScalars()
            mapper.ScalarVisibilityOn()
        else:
            mapper.ScalarVisibilityOff()
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        prop = actor.GetProperty()
        prop.SetColor(base[:3])
        prop.SetAmbient(0.08)
        prop.SetDiffuse(0.92)
        prop.SetSpecular(0.05 + 0.5 * (1.0 - roughness) ** 2)
        prop.SetSpecularPower(8.0 + 60.0 * (1.0 - roughness))
        if culling and not material.get("doubleSided", False):
            prop.BackfaceCullingOn()
        return actor

    visit(reader.GetOutput(), "")
    return [a for a in actors if a is not None]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("glb")
    parser.add_argument("png")
    parser.add_argument("--poses", nargs="+", default=["neutral"])
    parser.add_argument("--views", nargs="+", default=["front"], choices=sorted(VIEWS))
    parser.add_argument("--size", type=int, nargs=2, default=[320, 400], metavar=("W", "H"),
                        help="size of one panel in pixels")
    parser.add_argument("--zoom", type=float, default=1.0, help="1: the whole head; 2.5: the face")
    parser.add_argument("--focus", type=float, nargs=3, default=None, metavar=("X", "Y", "Z"),
                        help="point the camera looks at (metres); default: the head's centre")
    parser.add_argument("--labels", action="store_true", help="write the pose under each panel")
    parser.add_argument("--columns", type=int, default=0, help="panels per row (default: one per pose)")
    parser.add_argument("--palette", action="store_true", help="write a 256-colour PNG (needs Pillow)")
    parser.add_argument("--culling", action="store_true", help="hide back faces (to check winding)")
    parser.add_argument("--hide", nargs="+", default=[], metavar="MESH", help="meshes not to draw, e.g. Head Hair")
    parser.add_argument("--headlight", action="store_true", help="one light at the camera, as MorphAvatar")
    args = parser.parse_args()

    document, rest = read_glb(args.glb)
    poses = [parse_pose(p) for p in args.poses]
    width, height = args.size
    # One panel per view and pose, views in rows; --columns wraps them into a grid.
    panels = [(view, pose_index) for view in args.views for pose_index in range(len(poses))]
    columns = args.columns if args.columns else len(poses)
    rows = (len(panels) + columns - 1) // columns
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width * columns, height * rows)
    window.SetMultiSamples(8)
    with tempfile.TemporaryDirectory() as directory:
        paths = [posed_copy(document, rest, weights, gaze, directory, i)
                 for i, (_, weights, gaze) in enumerate(poses)]
        for index, (view, pose_index) in enumerate(panels):
            column, row = index % columns, index // columns
            label = poses[pose_index][0]
            renderer = vtk.vtkRenderer()
            renderer.SetViewport(column / columns, 1.0 - (row + 1) / rows, (column + 1) / columns, 1.0 - row / rows)
            renderer.SetBackground(0.15, 0.16, 0.2)
            renderer.SetBackground2(0.32, 0.34, 0.42)
            renderer.GradientBackgroundOn()
            for actor in actors_for(paths[pose_index], document, args.culling, args.hide):
                renderer.AddActor(actor)
            if not args.headlight:
                kit = vtk.vtkLightKit()
                kit.SetKeyLightIntensity(0.85)
                kit.AddLightsToRenderer(renderer)
            camera = renderer.GetActiveCamera()
            focus = args.focus if args.focus else (0.0, -0.005, 0.0)
            azimuth, elevation = VIEWS[view]
            distance = 0.62 / args.zoom
            a, e = math.radians(azimuth), math.radians(elevation)
            camera.SetFocalPoint(*focus)
            camera.SetPosition(focus[0] + distance * math.sin(a) * math.cos(e),
                               focus[1] + distance * math.sin(e),
                               focus[2] + distance * math.cos(a) * math.cos(e))
            camera.SetViewUp(0.0, 1.0, 0.0)
            camera.SetViewAngle(30.0)
            renderer.ResetCameraClippingRange()
            if args.labels and (row == rows - 1 or len(args.views) == 1):
                text = vtk.vtkTextActor()
                text.SetInput(label)
                text.GetTextProperty().SetFontSize(max(12, height // 18))
                text.GetTextProperty().SetColor(0.95, 0.95, 0.85)
                text.GetTextProperty().SetJustificationToCentered()
                text.SetPosition(width / 2, 6)
                renderer.AddActor2D(text)
            window.AddRenderer(renderer)
        window.Render()
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(args.png)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
    if args.palette:
        # Small pictures for the docs: 256 colours, dithered (needs Pillow).
        from PIL import Image
        image = Image.open(args.png).convert("RGB")
        image.quantize(colors=256, method=Image.Quantize.MEDIANCUT,
                       dither=Image.Dither.FLOYDSTEINBERG).save(args.png, optimize=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
