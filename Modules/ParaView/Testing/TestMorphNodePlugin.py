"""pvbatch test of the MorphNode plugin on the ICT-FaceKit face and head (one process).

    pvbatch --force-offscreen-rendering TestMorphNodePlugin.py \
        --plugin /tmp/build-paraview/.../MorphNodePlugin.so --png face.png

Loads the plugin, reads the face (one mesh) with the plugin's reader, blends two targets
through the filter's properties and checks the result against a blend computed here with
numpy from the reader's own target arrays; checks the AnimatedRegion distance map, the
optimizer properties, a temporal weights table on the WeightsTable input, and saves a
screenshot coloured by AnimatedRegion. Then the whole ICT head (11 parts, the reader's
default): every part morphed by the weights set once by name, checked part by part against
numpy, the same decision and distance maps in every part, and a screenshot of the head
(face.png's name with -head) coloured by Distance_jawOpen.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import morphnode_pvtest as t  # noqa: E402

# Weights of the test blend (glTF-style relative weights).
BLEND = {"jawOpen": 0.6, "mouthSmile_L": 0.8}

# A temporal weights source for the WeightsTable input: a one-row vtkTable, jawOpen
# ramps with time. This is what vtkBehaviorTimeSource will provide natively.
TABLE_INFORMATION = """
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp
info = self.GetOutputInformation(0)
info.Remove(sddp.TIME_STEPS())
for step in (0.0, 1.0, 2.0):
    info.Append(sddp.TIME_STEPS(), step)
info.Remove(sddp.TIME_RANGE())
info.Append(sddp.TIME_RANGE(), 0.0)
info.Append(sddp.TIME_RANGE(), 2.0)
"""
TABLE_DATA = """
from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp
info = self.GetOutputInformation(0)
time = info.Get(sddp.UPDATE_TIME_STEP()) if info.Has(sddp.UPDATE_TIME_STEP()) else 0.0
table = self.GetOutput()
for name, value in (("jawOpen", 0.5 * time), ("mouthSmile_L", 0.0), ("headYaw", 3.0)):
    column = vtkDoubleArray()
    column.SetName(name)
    column.InsertNextValue(value)
    table.AddColumn(column)
"""


def run(c, args):
    import numpy as np
    from paraview import simple
    from paraview import servermanager as sm

    face = t.face_or_skip(args.face)
    t.load_plugin(args.plugin, globals())
    c.require("MorphNodeFaceReader" in globals() and "MorphNode" in globals(),
              "the plugin defines MorphNodeFaceReader and MorphNode")

    # The reader is registered for .glb / .gltf (ReaderFactory hint).
    # (Not GetPossibleReaders: it probes every reader, and Debian's Python readers fail
    # to import under Python 3.11, which only adds noise.)
    factory = sm.vtkSMProxyManager.GetProxyManager().GetReaderFactory()
    types = factory.GetSupportedFileTypes(sm.ActiveConnection.Session)
    c.check("MorphNode Face (glTF with morph targets) (*.glb *.gltf)" in types,
            "File > Open lists 'MorphNode Face (glTF with morph targets) (*.glb *.gltf)'")

    # --- the reader -------------------------------------------------------------------
    reader = MorphNodeFaceReader(FileName=face, MeshIndex=0)  # noqa: F821 - one mesh
    neutral = sm.Fetch(reader)
    c.require(neutral.GetNumberOfPoints() == 11248,
              "the ICT face has 11248 points (got %d)" % neutral.GetNumberOfPoints())
    target_names = t.field_values(neutral, "TargetNames")
    c.require(target_names is not None and len(target_names) == 54,
              "TargetNames: the neutral and 53 targets (got %s)"
              % (None if target_names is None else len(target_names)))
    p0, arrays0 = t.point_arrays(neutral)
    p0 = p0.astype(np.float64)
    deltas = {name: arrays0["target%d_position" % (k - 1)].astype(np.float64)
              for k, name in enumerate(target_names) if k > 0}
    diagonal = float(np.linalg.norm(p0.max(axis=0) - p0.min(axis=0)))
    tolerance = 1e-5 * diagonal
    print("face: %d points, %d cells, bounding-box diagonal %.4g"
          % (neutral.GetNumberOfPoints(), neutral.GetNumberOfCells(), diagonal))

    # --- the filter: weights by name, relative mode, distance maps ----------------------
    morph = MorphNode(Input=reader)  # noqa: F821
    morph.TargetWeights = [str(x) for pair in BLEND.items() for x in pair]
    morph.WeightMode = "Relative"
    morph.GenerateDistanceArrays = 1
    out = sm.Fetch(morph)
    c.require(out.GetNumberOfPoints() == 11248,
              "the morphed face has 11248 points (got %d)" % out.GetNumberOfPoints())
    c.check(out.GetNumberOfCells() == neutral.GetNumberOfCells(), "cells come from the neutral")
    p, arrays = t.point_arrays(out)
    expected = p0 + sum(w * deltas[name] for name, w in BLEND.items())
    error = float(np.abs(p.astype(np.float64) - expected).max())
    c.check(error <= tolerance, "points = neutral + 0.6 jawOpen + 0.8 mouthSmile_L "
            "(max error %.3g, tolerance %.3g)" % (error, tolerance))
    moved = float(np.linalg.norm(p - p0, axis=1).max())
    c.check(moved > 100 * tolerance, "the blend moves the face (by up to %.4g)" % moved)
    c.check(t.field_values(out, "ActiveTargetCount") == [2], "ActiveTargetCount = 2")

    c.require("AnimatedRegion" in arrays, "point array AnimatedRegion exists")
    region = arrays["AnimatedRegion"].astype(np.float64)
    lo, hi = float(region.min()), float(region.max())
    print("AnimatedRegion range [%.6g, %.6g], %.1f%% of the points animated"
          % (lo, hi, 100.0 * np.count_nonzero(region > 0) / region.size))
    c.check(np.isfinite(region).all() and lo >= 0.0, "AnimatedRegion is finite and >= 0")
    c.check(0.0 < hi < 0.5 * diagonal,
            "AnimatedRegion's maximum is positive and below half the face's size")
    largest = np.max([np.linalg.norm(d, axis=1) for d in deltas.values()], axis=0)
    c.check(float(np.abs(region - largest).max()) <= tolerance,
            "AnimatedRegion = the largest displacement of each vertex over all targets")
    c.check("Distance_jawOpen" in arrays and
            float(np.abs(arrays["Distance_jawOpen"] - np.linalg.norm(deltas["jawOpen"], axis=1)).max())
            <= tolerance, "Distance_jawOpen = the displacement of jawOpen")
    dist_norm = t.field_values(out, "DistNorm")
    c.check(dist_norm is not None and len(dist_norm) == 54 and abs(max(dist_norm) - 1.0) < 1e-12,
            "field data DistNorm: one value per target, the largest 1")

    # --- the optimizer through its properties --------------------------------------------
    morph.TargetWeights = ["jawOpen", "0.6", "mouthSmile_L", "0.05"]
    morph.Threshold = 0.1
    out = sm.Fetch(morph)
    c.check(t.field_values(out, "ActiveTargetCount") == [1],
            "Threshold 0.1 prunes the weight 0.05 (ActiveTargetCount 1)")
    morph.UpdatePropertyInformation()
    c.check(morph.GetProperty("ActiveTargetCountInfo").GetElement(0) == 1,
            "information property ActiveTargetCountInfo = 1")
    # Hysteresis keeps a target active in the previous run down to
    # threshold * (1 - Hysteresis); the command property ResetHysteresis forgets it.
    morph.TargetWeights = ["jawOpen", "0.6", "mouthSmile_L", "0.2"]
    morph.Hysteresis = 0.5
    sm.Fetch(morph)                                         # mouthSmile_L active
    morph.TargetWeights = ["jawOpen", "0.6", "mouthSmile_L", "0.08"]
    c.check(t.field_values(sm.Fetch(morph), "ActiveTargetCount") == [2],
            "Hysteresis 0.5 keeps mouthSmile_L (0.08 >= 0.1 * 0.5) active")
    morph.SMProxy.InvokeCommand("ResetHysteresis")
    morph.Threshold = 0.1000001                             # a change, to run again
    c.check(t.field_values(sm.Fetch(morph), "ActiveTargetCount") == [1],
            "after ResetHysteresis, mouthSmile_L (0.08) is pruned")
    morph.Hysteresis = 0.0
    morph.Threshold = 0.0

    # Java3D style: normalized absolute weights, the neutral named.
    morph.TargetWeights = ["Neutral", "1", "jawOpen", "1"]
    morph.WeightMode = "Normalize"
    p, _ = t.point_arrays(sm.Fetch(morph))
    error = float(np.abs(p - (p0 + 0.5 * deltas["jawOpen"])).max())
    c.check(error <= tolerance, "Normalize: Neutral 1 + jawOpen 1 = half jawOpen "
            "(max error %.3g)" % error)

    # An unknown name is an error of the filter: empty output, no crash.
    morph.TargetWeights = ["noSuchTarget", "1"]
    print("(an error about 'noSuchTarget' is expected here)", flush=True)
    c.check(sm.Fetch(morph).GetNumberOfPoints() == 0, "an unknown target name gives an empty output")

    # --- time: a temporal weights table on the WeightsTable input ----------------------
    table = simple.ProgrammableSource(OutputDataSetType="vtkTable",
                                      Script=TABLE_DATA,
                                      ScriptRequestInformation=TABLE_INFORMATION)
    morph.TargetWeights = []
    morph.WeightMode = "Relative"
    morph.WeightsTable = table
    morph.UpdatePipelineInformation()
    steps = list(morph.TimestepValues)
    c.check(steps == [0.0, 1.0, 2.0], "the filter takes the table's time steps %s" % steps)
    for time in (0.0, 2.0):
        at = simple.ForceTime(Input=morph, ForcedTime=time, IgnorePipelineTime=1)
        p, _ = t.point_arrays(sm.Fetch(at))
        error = float(np.abs(p - (p0 + 0.5 * time * deltas["jawOpen"])).max())
        c.check(error <= tolerance, "time %g: jawOpen = %g from the table (max error %.3g)"
                % (time, 0.5 * time, error))
        simple.Delete(at)
    morph.WeightsTable = []

    # --- a screenshot coloured by AnimatedRegion ----------------------------------------
    if args.png:
        morph.TargetWeights = [str(x) for pair in BLEND.items() for x in pair]
        view = simple.CreateRenderView()
        view.ViewSize = [640, 640]
        view.OrientationAxesVisibility = 0
        view.Background = [1.0, 1.0, 1.0]
        if hasattr(view, "UseColorPaletteForBackground"):
            view.UseColorPaletteForBackground = 0
        display = simple.Show(morph, view)
        simple.ColorBy(display, ("POINTS", "AnimatedRegion"))
        display.RescaleTransferFunctionToDataRange(True, False)
        simple.GetColorTransferFunction("AnimatedRegion").ApplyPreset("Turbo", True)
        view.CameraPosition = [0.0, 0.0, 1.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera()
        simple.Render(view)
        png = os.path.abspath(args.png)
        simple.SaveScreenshot(png, view, ImageResolution=[640, 640])
        ok = c.check(os.path.isfile(png) and os.path.getsize(png) > 10000,
                     "screenshot written: %s" % png)
        if ok:
            from vtkmodules.vtkIOImage import vtkPNGReader
            from vtkmodules.util.numpy_support import vtk_to_numpy
            image = vtkPNGReader()
            image.SetFileName(png)
            image.Update()
            pixels = vtk_to_numpy(image.GetOutput().GetPointData().GetScalars())[:, :3]
            colours = len(np.unique(pixels, axis=0))
            face_pixels = np.count_nonzero((pixels != 255).any(axis=1))
            c.check(colours > 50 and face_pixels > 0.1 * len(pixels),
                    "the screenshot shows the coloured face (%d colours, %.0f%% of the "
                    "pixels)" % (colours, 100.0 * face_pixels / len(pixels)))


def parts_of(collection):
    """[(name, vtkPolyData)] of a vtkPartitionedDataSetCollection, in order."""
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
    parts = []
    for i in range(collection.GetNumberOfPartitionedDataSets()):
        meta = collection.GetMetaData(i) if collection.HasMetaData(i) else None
        name = meta.Get(vtkCompositeDataSet.NAME()) if meta is not None else "#%d" % i
        parts.append((name, collection.GetPartition(i, 0)))
    return parts


def local_output(proxy):
    """The proxy's output data object itself. pvbatch on one process runs client and server
    in one process; ParaView 5.11's Fetch cannot move a vtkPartitionedDataSetCollection
    (its reduction puts the collection into a vtkMultiBlockDataSet, which refuses it)."""
    proxy.UpdatePipeline()
    return proxy.GetClientSideObject().GetOutputDataObject(0)


def check_head(c, args, face):
    """The whole ICT head: read as parts, morphed by name, distance maps per part."""
    import builtins  # LoadPlugin's namespace may hold VTK's numpy algorithms' sum, max, ...
    import numpy as np
    from paraview import simple

    head_file = os.path.join(os.path.dirname(face), "ict_head_full53.glb")
    if not os.path.isfile(head_file):
        print("SKIP (head): %s is missing" % head_file, flush=True)
        return
    reader = MorphNodeFaceReader(FileName=head_file)  # noqa: F821
    head = local_output(reader)
    information = reader.GetDataInformation().DataInformation
    c.check(information.GetNumberOfPoints() == 26041, "ParaView's data information: 26041 points")
    c.require(head is not None and head.IsA("vtkPartitionedDataSetCollection"),
              "the head reads as a vtkPartitionedDataSetCollection (got %s)"
              % (head.GetClassName() if head is not None else None))
    parts = parts_of(head)
    names = [name for name, _ in parts]
    print("head parts: %s" % names, flush=True)
    c.require(len(parts) == 11, "the ICT head has 11 parts (got %d)" % len(parts))
    total = 0
    for _, part in parts:
        total += part.GetNumberOfPoints()
    c.check(total == 26041, "26041 points in all (got %d)" % total)
    c.check("Teeth" in names and "EyeLeft/M_IrisLeft" in names, "parts named after node and material")
    c.check(len(t.field_values(head, "TargetNames")) == 54, "the head names 53 targets (and the neutral)")
    c.check(head.GetDataAssembly() is not None and
            head.GetDataAssembly().FindFirstNodeWithName("EyeLeft") > 0,
            "the data assembly mirrors the node tree")

    blend = {"jawOpen": 0.7, "eyeBlink_L": 1.0, "mouthSmile_R": 0.05}
    morph = MorphNode(Input=reader)  # noqa: F821
    morph.TargetWeights = [str(x) for pair in blend.items() for x in pair]
    morph.WeightMode = "Relative"
    morph.Threshold = 0.1           # prunes mouthSmile_R (0.05), for every part alike
    morph.RedistributionStrategy = "Neutral"
    morph.GenerateDistanceArrays = 1
    out = local_output(morph)
    c.require(out is not None and out.IsA("vtkPartitionedDataSetCollection"),
              "the morphed head keeps the collection")
    morphed = parts_of(out)
    c.require([n for n, _ in morphed] == names, "the same parts, in the same order, named alike")
    kept = {"jawOpen": 0.7, "eyeBlink_L": 1.0}
    worst, moved_parts, weights = 0.0, [], []
    for (name, before), (_, after) in zip(parts, morphed):
        p0, a0 = t.point_arrays(before)
        p1, a1 = t.point_arrays(after)
        own = t.field_values(before, "TargetNames")
        expected = p0.astype(np.float64)
        for target, w in kept.items():
            if target in own:
                expected = expected + w * a0["target%d_position" % (own.index(target) - 1)]
        worst = builtins.max(worst, float(np.abs(p1 - expected).max()))
        if float(np.abs(p1 - p0).max()) > 1e-4:
            moved_parts.append(name)
        c.check("AnimatedRegion" in a1 and "Distance_jawOpen" in a1 and
                len(a1["Distance_jawOpen"]) == before.GetNumberOfPoints(),
                "%s: its own distance maps" % name)
        weights.append(t.field_values(after, "EffectiveWeights"))
    c.check(worst < 1e-6, "every part = neutral + 0.7 jawOpen + 1 eyeBlink_L, mouthSmile_R pruned "
            "(max error %.3g m)" % worst)
    print("moved parts: %s" % moved_parts, flush=True)
    c.check("Teeth" in moved_parts and "MouthInterior" in moved_parts and "Eyelashes" in moved_parts,
            "jawOpen moves the teeth and the mouth, eyeBlink_L the lashes")
    c.check(not builtins.any(n.startswith("Eye") and "/" in n for n in moved_parts), "the eyes do not move")
    c.check(builtins.all(w == weights[0] for w in weights) and weights[0] is not None and len(weights[0]) == 54,
            "every part holds the same effective weights")
    c.check(t.field_values(morphed[0][1], "ActiveTargetCount") == [2], "2 active targets")
    teeth = dict(morphed)["Teeth"]
    _, arrays = t.point_arrays(teeth)
    c.check(float(arrays["Distance_jawOpen"].max()) > 1e-3, "the teeth's own jawOpen distance map")

    if args.png:
        view = simple.CreateRenderView()
        view.ViewSize = [640, 640]
        view.OrientationAxesVisibility = 0
        view.Background = [1.0, 1.0, 1.0]
        if hasattr(view, "UseColorPaletteForBackground"):
            view.UseColorPaletteForBackground = 0
        display = simple.Show(morph, view)
        simple.ColorBy(display, ("POINTS", "Distance_jawOpen"))
        display.RescaleTransferFunctionToDataRange(True, False)
        simple.GetColorTransferFunction("Distance_jawOpen").ApplyPreset("Turbo", True)
        view.CameraPosition = [0.0, 0.0, 1.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera()
        simple.Render(view)
        png = os.path.splitext(os.path.abspath(args.png))[0] + "-head.png"
        simple.SaveScreenshot(png, view, ImageResolution=[640, 640])
        c.check(os.path.isfile(png) and os.path.getsize(png) > 10000, "head screenshot written: %s" % png)


if __name__ == "__main__":
    parser = t.common_arguments(__doc__.splitlines()[0])
    parser.add_argument("--png", help="save a screenshot coloured by AnimatedRegion here")
    arguments = parser.parse_args()

    def both(c):
        run(c, arguments)
        check_head(c, arguments, t.face_or_skip(arguments.face))

    t.main(both, "TestMorphNodePlugin")
