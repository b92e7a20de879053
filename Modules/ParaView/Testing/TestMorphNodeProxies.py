"""pvbatch test: every MorphNode class has a working proxy in the plugin.

    pvbatch TestMorphNodeProxies.py --plugin .../MorphNodePlugin.so

Drives each proxy the way a ParaView user does, through properties only, and checks what
comes out against the same class run directly: the Morph Rig filter (an ARKit face's
weights from semantic ones), the Morph Rig Baker (the paper's shapes as targets), the
Animation-Aware Decimation (fewer triangles, targets carried), the Behavior Time
Source (time steps that drive ParaView's animation), and the Live Link Face Capture (an
ARKit take on the ICT face's targets). The ICT-FaceKit faces are used (the
test is skipped without them, and fails under CI): the decimation needs a manifold mesh,
which the repository's one-mesh default face (mouth bag and teeth fused into the skin) is
not.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import morphnode_pvtest as t  # noqa: E402

REPOSITORY = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
ARKIT_RIG = os.path.join(REPOSITORY, "Data", "rigs", "arkit.json")

# Semantic weights for the rig: one row, the paper's O and a smile.
SEMANTIC_TABLE = """
from vtkmodules.vtkCommonCore import vtkDoubleArray
table = self.GetOutput()
for name, value in (("O", 1.0), ("MouthSmile", 0.5), ("headYaw", 3.0)):
    column = vtkDoubleArray()
    column.SetName(name)
    column.InsertNextValue(value)
    table.AddColumn(column)
"""


def run(c, args):
    import numpy as np
    from paraview import simple
    from paraview import servermanager as sm

    t.load_plugin(args.plugin, globals())
    for proxy in ("MorphRig", "MorphRigBaker", "AnimationAwareDecimation", "MorphNodeFaceReader",
                  "MorphNodeBehaviorTimeSource", "EyeGaze", "MorphLevelOfDetail"):
        c.require(proxy in globals(), "the plugin defines %s" % proxy)

    ict = t.face_or_skip(args.face)
    small = os.path.join(os.path.dirname(ict), "ict_face_dec70_sparse53.glb")
    t.face_or_skip(small)

    # --- Animation-Aware Decimation on the ICT face decimated by 70 % (2,948 points) -----
    face = MorphNodeFaceReader(FileName=small, MeshIndex=0)  # noqa: F821 - one mesh
    full = sm.Fetch(face)
    c.require(full.GetNumberOfPoints() == 2948, "the small ICT face reads")
    decimate = AnimationAwareDecimation(Input=face)  # noqa: F821
    decimate.TargetReduction = 0.5
    reduced = sm.Fetch(decimate)
    ratio = reduced.GetNumberOfCells() / float(full.GetNumberOfCells())
    c.check(0.45 <= ratio <= 0.55, "TargetReduction 0.5 halves the triangles (kept %.3f)" % ratio)
    _, arrays = t.point_arrays(reduced)
    c.check("OriginalPointId" in arrays and "target0_position" in arrays,
            "the reduced face carries OriginalPointId and its targets")
    names_full = t.field_values(full, "TargetNames")
    c.check(t.field_values(reduced, "TargetNames") == names_full, "TargetNames passed on")
    decimate.NumberOfTriangles = 1000
    c.check(abs(sm.Fetch(decimate).GetNumberOfCells() - 1000) <= 2,
            "NumberOfTriangles 1000 wins over TargetReduction")
    decimate.NumberOfTriangles = 0
    decimate.TargetReduction = 0.8
    # The animated regions keep more points than plain decimation does.
    _, aware = t.point_arrays(sm.Fetch(decimate))
    decimate.AnimationWeight = 0.0
    _, plain = t.point_arrays(sm.Fetch(decimate))
    _, fa = t.point_arrays(full)
    reach = np.max([np.linalg.norm(fa[k], axis=1) for k in fa if k.endswith("_position")], axis=0)
    moving = reach > 0.25 * reach.max()  # the strongly animated points: lips, lids, jaw
    kept_aware = np.count_nonzero(moving[aware["OriginalPointId"].astype(int)])
    kept_plain = np.count_nonzero(moving[plain["OriginalPointId"].astype(int)])
    c.check(kept_aware > kept_plain, "AnimationWeight > 0 keeps more strongly animated points than 0 "
            "(%d vs %d)" % (kept_aware, kept_plain))

    # --- Morph Level Of Detail: the level the screen asks for (docs/lod.md) ---------------
    lod = MorphLevelOfDetail(Input=face)  # noqa: F821
    lod.Weights = ["24", "0.6", "11", "0.8"]  # jawOpen-ish and a blink, by number
    lod.PixelsPerUnit = 1e6
    near = sm.Fetch(lod)
    c.check(near.GetNumberOfPoints() == 2948, "Morph Level Of Detail: a near face is the full mesh")
    for i in range(100):  # one execution per frame: switches wait 20 frames, geomorphs 8+
        lod.PixelsPerUnit = 20.0 + 1e-6 * i
        far = sm.Fetch(lod)
    c.check(far.GetNumberOfPoints() < 2948 // 2, "a far face shows a coarse level (%d points)"
            % far.GetNumberOfPoints())
    lod.FinestLevel = 1  # a phone's largest level
    lod.PixelsPerUnit = 1e6
    c.check(sm.Fetch(lod).GetNumberOfPoints() < 2948, "FinestLevel 1 never shows the full mesh")
    morph_lod = MorphNode(Input=face)  # noqa: F821
    morph_lod.DeviceProfile = "phone"
    morph_lod.PixelsPerUnit = 20.0
    morph_lod.TargetPixelBound = 1.0
    c.check(sm.Fetch(morph_lod).GetNumberOfPoints() == 2948, "Morph Node with a device profile runs")
    # Mesh levels through the Morph Node itself: a phone's finest level is level 1.
    morph_lod.MeshLevels = 1
    morph_lod.PixelsPerUnit = 1e6
    shown = sm.Fetch(morph_lod)
    _, shown_arrays = t.point_arrays(shown)
    c.check(0 < shown.GetNumberOfPoints() < 2948 and "OriginalPointId" in shown_arrays,
            "Morph Node MeshLevels with the phone profile shows a reduced level (%d points)"
            % shown.GetNumberOfPoints())

    # --- the rig proxies, on the ARKit-named ICT face ------------------------------------
    arkit = MorphNodeFaceReader(FileName=ict, MeshIndex=0)  # noqa: F821 - one mesh
    semantic = simple.ProgrammableSource(OutputDataSetType="vtkTable", Script=SEMANTIC_TABLE)
    rig = MorphRig(Input=semantic, Face=arkit)  # noqa: F821
    rig.RigFileName = ARKIT_RIG
    weights = sm.Fetch(rig)
    columns = [weights.GetColumnName(i) for i in range(weights.GetNumberOfColumns())]
    ict_names = t.field_values(sm.Fetch(arkit), "TargetNames")
    c.check(columns[:53] == ict_names[1:], "Morph Rig: one column per face target, in order")
    pucker = weights.GetColumnByName("mouthPucker").GetValue(0)
    c.check(pucker > 0.3, "O drives mouthPucker (%.3f)" % pucker)
    c.check("headYaw" in columns, "PassOtherColumns passes headYaw")
    rig.PassOtherColumns = 0
    weights = sm.Fetch(rig)
    c.check(weights.GetColumnByName("headYaw") is None, "PassOtherColumns 0 drops headYaw")

    baker = MorphRigBaker(Input=arkit)  # noqa: F821
    baker.RigFileName = ARKIT_RIG
    baker.ShapeSet = "paper"
    baked = sm.Fetch(baker)
    names = t.field_values(baked, "TargetNames")
    c.check(names is not None and names[0] == "Neutral" and "O" in names and "EyesClosed" in names,
            "Morph Rig Baker: the paper's shapes as targets (%s)" % names)
    # A baked shape at weight 1 equals the rig's expansion at weight 1.
    morph_baked = MorphNode(Input=baker)  # noqa: F821
    morph_baked.WeightMode = "Relative"
    morph_baked.TargetWeights = ["O", "1"]
    p_baked, _ = t.point_arrays(sm.Fetch(morph_baked))
    one = simple.ProgrammableSource(OutputDataSetType="vtkTable", Script="""
from vtkmodules.vtkCommonCore import vtkDoubleArray
a = vtkDoubleArray(); a.SetName("O"); a.InsertNextValue(1.0); self.GetOutput().AddColumn(a)
""")
    rig_one = MorphRig(Input=one, Face=arkit, RigFileName=ARKIT_RIG)  # noqa: F821
    morph_rig = MorphNode(Input=arkit, WeightsTable=rig_one)  # noqa: F821
    morph_rig.WeightMode = "Relative"
    p_rig, _ = t.point_arrays(sm.Fetch(morph_rig))
    error = float(np.abs(p_baked - p_rig).max())
    c.check(error < 1e-6, "baked O at 1 = the rig's O at 1 (max difference %.3g)" % error)


    # --- the Behavior Time Source: a script as a property, time steps for the animation ----
    behavior = MorphNodeBehaviorTimeSource()  # noqa: F821
    behavior.Script = "duration 3\nat 1.0 gesture smile duration 1.5 intensity 1\n"
    behavior.FrameRate = 10
    behavior.UpdatePipelineInformation()
    steps = list(behavior.TimestepValues)
    c.check(len(steps) == 31 and abs(steps[-1] - 3.0) < 1e-9,
            "31 time steps over the script's 3 s at 10 per second (got %d)" % len(steps))
    smile = {}
    for time in (0.2, 1.75):
        at = simple.ForceTime(Input=behavior, ForcedTime=time, IgnorePipelineTime=1)
        table = sm.Fetch(at)
        column = table.GetColumnByName("MouthSmile")
        smile[time] = column.GetValue(0) if column is not None else float("nan")
        simple.Delete(at)
    c.check(smile[1.75] > 0.3 and smile[0.2] < 0.5 * smile[1.75],
            "the script's smile shows at 1.75 s, not at 0.2 s (%s)" % smile)
    # Through the rig onto the ARKit face: the animation moves the mouth corners.
    rig_behavior = MorphRig(Input=behavior, Face=arkit, RigFileName=ARKIT_RIG)  # noqa: F821
    animated = MorphNode(Input=arkit, WeightsTable=rig_behavior)  # noqa: F821
    animated.WeightMode = "Relative"
    points = {}
    for time in (0.2, 1.75):
        at = simple.ForceTime(Input=animated, ForcedTime=time, IgnorePipelineTime=1)
        points[time], _ = t.point_arrays(sm.Fetch(at))
        simple.Delete(at)
    moved = float(np.linalg.norm(points[1.75] - points[0.2], axis=1).max())
    c.check(moved > 1e-3, "scrubbing time animates the face through the rig (moved %.4g m)" % moved)
    behavior.Script = "at 1.0 gesture no_such_gesture\n"
    print("(an error about 'no_such_gesture' is expected here)", flush=True)
    at = simple.ForceTime(Input=behavior, ForcedTime=1.0, IgnorePipelineTime=1)
    c.check(sm.Fetch(at).GetNumberOfRows() == 0, "a bad script gives an empty table, no crash")
    simple.Delete(at)

    check_eye_gaze(c)
    check_skin_pose(c)
    check_live_link(c, ict)


def check_eye_gaze(c):
    """The Eye Gaze proxy on the default head: the pupils look where EyeYaw/EyePitch say
    (within a degree), the limits clamp, other parts pass through, and a Behavior Time
    Source on Gaze drives it at the animation's time."""
    import builtins  # LoadPlugin's namespace may hold VTK's numpy algorithms' all, sum, ...
    import math
    import numpy as np
    from paraview import simple
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet

    def output(proxy):  # pvbatch on one process: the output itself (Fetch cannot move a collection)
        proxy.UpdatePipeline()
        return proxy.GetClientSideObject().GetOutputDataObject(0)

    def parts(collection):
        return {collection.GetMetaData(i).Get(vtkCompositeDataSet.NAME()): collection.GetPartition(i, 0)
                for i in range(collection.GetNumberOfPartitionedDataSets())}

    def pupil_angle(part, yaw, pitch):
        p, _ = t.point_arrays(part)
        d = p.astype(np.float64).mean(axis=0) - np.array(t.field_values(part, "NodeOrigin"))
        r, q = math.radians(yaw), math.radians(pitch)
        target = np.array([math.cos(q) * math.sin(r), math.sin(q), math.cos(q) * math.cos(r)])
        return math.degrees(math.acos(float(np.dot(d, target) / np.linalg.norm(d))))

    head = MorphNodeFaceReader(FileName=os.path.join(REPOSITORY, "Data", "DefaultFace", "default_head.glb"))  # noqa: F821
    gaze = EyeGaze(Input=head)  # noqa: F821
    gaze.EyeYaw = 25.0
    gaze.EyePitch = -10.0
    before, after = parts(output(head)), parts(output(gaze))
    c.require(sorted(before) == sorted(after), "Eye Gaze keeps the head's parts")
    for name in ("EyeLeft/Pupil", "EyeRight/Pupil"):
        angle = pupil_angle(after[name], 25.0, -10.0)
        c.check(angle < 1.0, "Eye Gaze: %s looks at yaw 25, pitch -10 (off by %.3f deg)" % (name, angle))
    same = builtins.all(np.array_equal(t.point_arrays(before[n])[0], t.point_arrays(after[n])[0])
               for n in before if not n.startswith("Eye"))
    c.check(same, "Eye Gaze: the other parts pass through")
    gaze.EyeYaw = 80.0
    c.check(t.field_values(parts(output(gaze))["EyeLeft/Iris"], "EyeGaze")[0] == 40.0,
            "Eye Gaze: MaxEyeYaw (40) clamps 80")
    gaze.EyeNames = ["EyeRight"]
    turned = [n for n, part in parts(output(gaze)).items() if t.field_values(part, "EyeGaze")]
    c.check(sorted(turned) == ["EyeRight/Iris", "EyeRight/Pupil", "EyeRight/Sclera"],
            "Eye Gaze: EyeNames picks the eyes (%s)" % turned)
    gaze.EyeNames = []

    behavior = MorphNodeBehaviorTimeSource()  # noqa: F821
    behavior.Script = "duration 3\nat 0.5 look 20 -5 duration 2\n"
    gaze.Gaze = behavior
    for time in (0.2, 1.5):
        at = simple.ForceTime(Input=gaze, ForcedTime=time, IgnorePipelineTime=1)
        table_at = simple.ForceTime(Input=behavior, ForcedTime=time, IgnorePipelineTime=1)
        table = output(table_at)
        yaw = table.GetColumnByName("EyeYaw").GetValue(0)
        pitch = table.GetColumnByName("EyePitch").GetValue(0)
        angle = pupil_angle(parts(output(at))["EyeLeft/Pupil"], yaw, pitch)
        c.check(angle < 1.0, "Eye Gaze on the Behavior Time Source at %.1f s: the pupil looks at "
                "(%.2f, %.2f) (off by %.3f deg)" % (time, yaw, pitch, angle))
        simple.Delete(at)
        simple.Delete(table_at)


def check_skin_pose(c):
    """The Skin Pose proxy on the shared MakeHuman avatar (skipped without it): EyeYaw turns
    the eye joints (the eyeballs move, the feet do not), TurnJaw On with JawOpen opens the
    jaw joint (the teeth move down), both through properties only."""
    import numpy as np
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet

    avatar = os.path.join(os.environ.get("MORPHNODE_AVATAR_DIR", ""), "makehuman_avatar.glb")
    if not os.path.exists(avatar):
        print("SKIP Skin Pose: the MakeHuman avatar is not at %s" % avatar, flush=True)
        return

    def parts(proxy):
        proxy.UpdatePipeline()
        collection = proxy.GetClientSideObject().GetOutputDataObject(0)
        return {collection.GetMetaData(i).Get(vtkCompositeDataSet.NAME()): t.point_arrays(collection.GetPartition(i, 0))[0]
                for i in range(collection.GetNumberOfPartitionedDataSets())}

    reader = MorphNodeFaceReader(FileName=avatar)  # noqa: F821
    pose = SkinPose(Input=reader)  # noqa: F821
    rest = parts(reader)
    pose.EyeYaw = 25.0
    turned = parts(pose)
    eye = float(np.linalg.norm(turned["EyeLeft"] - rest["EyeLeft"], axis=1).max())
    c.check(eye > 1e-3, "Skin Pose: EyeYaw turns the left eyeball (moved %.4g m)" % eye)
    feet = float(np.abs(turned["Body"][:, 1].min() - rest["Body"][:, 1].min()))
    c.check(feet < 1e-6, "Skin Pose: the feet stay (%.3g m)" % feet)
    pose.EyeYaw = 0.0
    pose.JawOpen = 1.0
    pose.TurnJaw = 2  # On: the avatar's jawOpen target would keep the joint still otherwise
    jaw = parts(pose)
    down = float((jaw["Teeth"][:, 1] - rest["Teeth"][:, 1]).min())
    c.check(down < -5e-3, "Skin Pose: JawOpen with TurnJaw On lowers the teeth (%.4g m)" % down)


def check_live_link(c, ict):
    """The Live Link Face Capture proxy: a take written here, its rows as time steps, its
    ARKit columns on the ICT face's targets (tongueOut, which the face lacks, left out), and
    the face animated by it through the Morph Node."""
    import tempfile
    import numpy as np
    from paraview import simple
    from paraview import servermanager as sm

    take_file = os.path.join(tempfile.mkdtemp(), "take.csv")
    with open(take_file, "w") as f:
        f.write("Timecode,BlendShapeCount,JawOpen,BrowInnerUp,TongueOut,HeadYaw\n"
                "10:00:00:00.250,3,0,0,0,0\n"
                "10:00:00:02.250,3,0.8,0.4,1,0.1\n"
                "10:00:00:04.250,3,0.4,0.2,0,0.2\n")
    face = MorphNodeFaceReader(FileName=ict, MeshIndex=0)  # noqa: F821
    take = LiveLinkFaceCapture(Face=face, FileName=take_file)  # noqa: F821
    take.UpdatePipelineInformation()
    steps = list(take.TimestepValues)
    c.check(len(steps) == 3 and abs(steps[1] - 1.0 / 30.0) < 1e-9,
            "the take's 3 rows, 1/30 s apart, are the time steps (got %s)" % steps)
    at = simple.ForceTime(Input=take, ForcedTime=1.0 / 30.0, IgnorePipelineTime=1)
    table = sm.Fetch(at)
    jaw = table.GetColumnByName("jawOpen")
    brow = table.GetColumnByName("browInnerUp_R")
    c.check(jaw is not None and abs(jaw.GetValue(0) - 0.8) < 1e-9 and brow is not None and
            abs(brow.GetValue(0) - 0.4) < 1e-9 and table.GetColumnByName("tongueOut") is None,
            "the take's JawOpen and BrowInnerUp land on the face's jawOpen and browInnerUp_R")
    simple.Delete(at)
    animated = MorphNode(Input=face, WeightsTable=take)  # noqa: F821
    animated.WeightMode = "Relative"
    points = {}
    for time in (0.0, 1.0 / 30.0):
        at = simple.ForceTime(Input=animated, ForcedTime=time, IgnorePipelineTime=1)
        points[time], _ = t.point_arrays(sm.Fetch(at))
        simple.Delete(at)
    moved = float(np.linalg.norm(points[1.0 / 30.0] - points[0.0], axis=1).max())
    c.check(moved > 1e-3, "the take animates the face through the Morph Node (moved %.4g m)" % moved)


if __name__ == "__main__":
    arguments = t.common_arguments(__doc__.splitlines()[0]).parse_args()
    t.main(lambda c: run(c, arguments), "TestMorphNodeProxies")
