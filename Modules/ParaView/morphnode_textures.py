"""ParaView 5.11 and the MorphNode Face reader's textures (docs/paraview.md, docs/materials.md).

The reader puts each part's glTF material on the part: point data TCoords (the base colour
texture's coordinates, KHR_texture_transform applied) and field data <Slot>Image (RGBA
bytes, rows top first), <Slot>ImageSize (width, height) for the slots BaseColor,
MetallicRoughness, Normal, Occlusion, Emissive. ParaView's representations take a texture
only as a texture proxy read from an image file (ImageTexture), one per representation,
so a part's image goes through a PNG:

    from paraview.simple import *
    import morphnode_textures
    reader = MorphNodeFaceReader(FileName="avatar.glb")
    part = ExtractBlock(Input=reader, Selectors=["//Body"])  # one part
    png = morphnode_textures.save_part_image(reader, "/tmp/body.png", name="Body")
    display = Show(part)
    display.Texture = morphnode_textures.image_texture(png)

Runs in pvpython (built-in session) and pvbatch: the data is taken from the local
process, not fetched from a remote server.
"""
import vtkmodules.vtkCommonDataModel as dm
import vtkmodules.vtkIOImage as io


def parts(data):
    """The polydata leaves of a fetched reader output (or the polydata itself)."""
    if data.IsA("vtkPolyData"):
        return [data]
    out = []
    it = data.NewIterator()
    it.SkipEmptyNodesOn()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        leaf = it.GetCurrentDataObject()
        if leaf is not None and leaf.IsA("vtkPolyData"):
            out.append(leaf)
        it.GoToNextItem()
    return out


def output_of(reader):
    """The reader's output data object, updated. ParaView 5.11's servermanager.Fetch cannot
    gather a partitioned dataset collection ("cannot be added as a block"), so this takes
    the local copy: pvpython's built-in session and pvbatch's rank 0 (on several ranks,
    rank 0's parts only)."""
    reader.UpdatePipeline()
    return reader.GetClientSideObject().GetOutputDataObject(0)


def part_name(part):
    a = part.GetFieldData().GetAbstractArray("PartName")
    return a.GetValue(0) if a is not None and a.GetNumberOfValues() > 0 else ""


def image_of(part, slot="BaseColor"):
    """The part's <slot> texture image as vtkImageData (4 components; VTK's row 0 is the
    file's first row, which is what the part's TCoords sample at t = 0), or None."""
    fd = part.GetFieldData()
    pixels, size = fd.GetArray(slot + "Image"), fd.GetArray(slot + "ImageSize")
    if pixels is None or size is None or size.GetNumberOfValues() < 2:
        return None
    width, height = int(size.GetValue(0)), int(size.GetValue(1))
    if width <= 0 or height <= 0 or pixels.GetNumberOfComponents() != 4 or \
            pixels.GetNumberOfTuples() != width * height:
        return None
    image = dm.vtkImageData()
    image.SetDimensions(width, height, 1)
    image.GetPointData().SetScalars(pixels)
    return image


def save_part_image(reader, path, name=None, slot="BaseColor"):
    """Writes the <slot> image of the reader's part named name (the first part with
    one when None) as a PNG that ParaView's ImageTexture reads back in the orientation the
    part's TCoords expect (the PNG itself looks upside down in an image viewer). Returns
    path, or None when no such part carries that image."""
    for part in parts(output_of(reader)):
        if name is not None and part_name(part) != name:
            continue
        image = image_of(part, slot)
        if image is None:
            continue
        writer = io.vtkPNGWriter()
        writer.SetInputData(image)
        writer.SetFileName(path)
        writer.Write()
        return path
    return None


def image_texture(path):
    """A texture proxy of the PNG, for a representation's Texture (classic lighting) or
    BaseColorTexture (Interpolation 'PBR')."""
    from paraview import servermanager
    texture = servermanager.rendering.ImageTexture()
    texture.FileName = path
    return texture
