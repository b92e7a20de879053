"""pvbatch test: a part's base colour texture from the MorphNode Face reader shown in ParaView.

    pvbatch TestMorphNodeTextures.py --plugin .../MorphNodePlugin.so

A GLB written here: one quad (x -1..1, y -1..1, glTF's v = 0 at the top) whose base
colour texture has 2 x 2 texels, red and green in its first (top) row, blue and white in
the second, and a second, untextured quad ("Plain") behind it.
The reader's part carries point TCoords and the image as field data (BaseColorImage,
BaseColorImageSize); morphnode_textures.save_part_image writes it as a PNG that ParaView's
ImageTexture reads; shown with it as the representation's Texture, the frame's quarters
are red (top left), green, blue, white, so the orientation is right both ways. Negative
control: the same part without the texture is grey everywhere. The PBR route (Interpolation 'PBR', BaseColorTexture) is
rendered too and its colours printed (not checked: see docs/paraview.md).
"""
import json
import os
import struct
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))
import morphnode_pvtest as t  # noqa: E402
import morphnode_textures  # noqa: E402


def png(rows):
    """An RGBA PNG of rows (top first) of RGBA texels."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xffffffff)
    raw = b"".join(b"\0" + bytes(v for p in row for v in p) for row in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def write_glb(path):
    blob = bytearray()
    views, accessors = [], []

    def view(data, target=None):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        if target:
            views[-1]["target"] = target
        blob.extend(data)
        return len(views) - 1

    def accessor(values, kind, count, component=5126, minmax=False):
        fmt = "<%d%s" % (len(values), "f" if component == 5126 else "H")
        a = {"bufferView": view(struct.pack(fmt, *values)), "componentType": component, "count": count,
             "type": kind}
        if minmax:
            a["min"] = [min(values[k::3]) for k in range(3)]
            a["max"] = [max(values[k::3]) for k in range(3)]
        accessors.append(a)
        return len(accessors) - 1

    def quad(z, material):
        p = accessor([-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z], "VEC3", 4, minmax=True)
        n = accessor([0, 0, 1] * 4, "VEC3", 4)
        uv = accessor([0, 1, 1, 1, 1, 0, 0, 0], "VEC2", 4)
        i = accessor([0, 1, 2, 0, 2, 3], "SCALAR", 6, component=5123)
        return {"primitives": [{"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": uv}, "indices": i,
                                "material": material}]}

    meshes = [quad(0.0, 0), quad(-0.5, 1)]
    image = view(png([[(255, 0, 0, 255), (0, 255, 0, 255)], [(0, 0, 255, 255), (255, 255, 255, 255)]]))
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 0}],
        "bufferViews": views, "accessors": accessors, "meshes": meshes,
        "images": [{"bufferView": image, "mimeType": "image/png"}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [
            {"name": "Painted", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
            {"name": "Grey", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}],
        "nodes": [{"name": "Painted", "mesh": 0}, {"name": "Plain", "mesh": 1}],
        "scenes": [{"nodes": [0, 1]}], "scene": 0,
    }
    while len(blob) % 4:
        blob.append(0)
    doc["buffers"][0]["byteLength"] = len(blob)
    text = json.dumps(doc).encode()
    text += b" " * ((4 - len(text) % 4) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(blob), b"BIN\0") + bytes(blob)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)


def frame(view, path):
    from paraview import simple
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    simple.SaveScreenshot(path, view, ImageResolution=[200, 200])
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    return lambda x, y: [int(v) for v in pixels[int((y + 1) / 2 * h), int((x + 1) / 2 * w), :3]]


def run(c, args):
    from paraview import simple

    t.load_plugin(args.plugin, globals())
    out = tempfile.mkdtemp(prefix="morphnode-textures-")
    glb = os.path.join(out, "painted.glb")
    write_glb(glb)
    reader = MorphNodeFaceReader(FileName=glb)  # noqa: F821
    reader.UpdatePipeline()
    parts = {morphnode_textures.part_name(p): p for p in morphnode_textures.parts(morphnode_textures.output_of(reader))}
    c.require(sorted(parts) == ["Painted", "Plain"], "two parts: %s" % sorted(parts))
    tcoords = parts["Painted"].GetPointData().GetTCoords()
    c.check(tcoords is not None and tcoords.GetNumberOfComponents() == 2 and
            tcoords.GetNumberOfTuples() == 4, "the painted part has point TCoords")
    c.check(parts["Plain"].GetPointData().GetTCoords() is None, "the plain part has none")
    image = morphnode_textures.image_of(parts["Painted"])
    c.require(image is not None and image.GetDimensions()[:2] == (2, 2),
              "BaseColorImage (2 x 2) reachable as field data")
    c.check([int(image.GetScalarComponentAsDouble(0, 0, 0, k)) for k in range(4)] == [255, 0, 0, 255],
            "its first texel (top left) is red")
    c.check(morphnode_textures.image_of(parts["Plain"]) is None, "no image on the plain part")

    png_path = morphnode_textures.save_part_image(reader, os.path.join(out, "painted.png"), name="Painted")
    c.require(png_path is not None and os.path.isfile(png_path), "the part's image written as a PNG")

    painted = simple.ExtractBlock(Input=reader, Selectors=["//Painted"])
    view = simple.CreateRenderView()
    view.OrientationAxesVisibility = 0
    view.Background = [0, 0, 0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = simple.Show(painted, view)
    display.ColorArrayName = ["POINTS", ""]  # solid colour (ColorBy(display, None) fails here)
    display.DiffuseColor = [1, 1, 1]
    view.CameraPosition = [0, 0, 5]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 1.0

    plain = frame(view, os.path.join(out, "untextured.png"))
    quarters = [plain(x, y) for x, y in ((-0.5, 0.5), (0.5, 0.5), (-0.5, -0.5), (0.5, -0.5))]
    print("untextured: %s" % quarters)
    c.check(all(max(q) - min(q) < 20 for q in quarters), "negative control: without the texture all grey")

    display.Texture = morphnode_textures.image_texture(png_path)
    textured = frame(view, os.path.join(out, "textured.png"))
    expected = {"red": (1, 0, 0), "green": (0, 1, 0), "blue": (0, 0, 1), "white": (1, 1, 1)}
    for (x, y), name in zip(((-0.5, 0.5), (0.5, 0.5), (-0.5, -0.5), (0.5, -0.5)), expected):
        colour = textured(x, y)
        c.check(all((v > 100) if e else (v < 40) for v, e in zip(colour, expected[name])),
                "quarter (%g, %g) %s: %s" % (x, y, name, colour))

    display.Texture = None
    display.Interpolation = "PBR"
    display.BaseColorTexture = morphnode_textures.image_texture(png_path)
    pbr = frame(view, os.path.join(out, "pbr.png"))
    print("PBR BaseColorTexture (not checked): top left %s, top right %s" % (pbr(-0.5, 0.5), pbr(0.5, 0.5)))


if __name__ == "__main__":
    arguments = t.common_arguments(__doc__.splitlines()[0]).parse_args()
    t.main(lambda c: run(c, arguments), "TestMorphNodeTextures")
