"""pvbatch test of the MorphNode plugin with the face split across MPI ranks.

    pvbatch TestMorphNodeDistributed.py --plugin P.so --save one.npz
    mpiexec -n 2 pvbatch TestMorphNodeDistributed.py --plugin P.so --compare one.npz

Pipeline: MorphNode Face Reader (one mesh; not piece-aware: the whole face on rank 0,
nothing on the others) -> Generate Ids (the original point index, PointIds) ->
Redistribute DataSet (the face's cells split across the ranks, with the point arrays
target<k>_* and the field data TargetNames) -> Ghost Cells (a layer of ghost cells; the
points a rank holds but another owns flagged DUPLICATEPOINT in vtkGhostType) -> Morph Node
(runs on every rank, on its piece) -> each rank's piece fetched to rank 0. Boundary and
ghost points are duplicated across pieces; PointIds puts every point back in its place, so
the gathered result is compared point by point with the same pipeline run on one rank
(--save / --compare) and must match it.

Checked on more than one rank: every rank holds part of the face, every rank resolves
the same effective weights, blended points and AnimatedRegion equal the one-rank
result. The decisions that depend on the whole face (dist_norm for AdjustThreshold, the
targets' largest displacements for MaxVertexError and MaxActiveTargets, the error bound)
are made over the whole face on every rank (the filter exchanges each piece's figures
through the multiprocess controller): in every optimizer mode, every rank holds the same
DistNorm, ErrorBound and effective weights, and they equal the one-rank run's (DistNorm
to 1e-12 when the pieces flag their duplicated points as ghosts, else within the share of
the points duplicated on piece boundaries).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import morphnode_pvtest as t  # noqa: E402

WEIGHTS = ["jawOpen", "0.6", "mouthSmile_L", "0.8", "browInnerUp_L", "0.05",
           "eyeBlink_R", "0.3"]

# Every optimizer mode, through the filter's properties (each after the defaults below).
# jawOpen (0.6) survives Threshold 0.7 only where its dist_norm > 1/7 (AdjustThreshold);
# MaxVertexError and MaxActiveTargets weigh the targets' largest displacements.
DEFAULTS = {"Threshold": 0.0, "RedistributionStrategy": "Remaining", "AdjustThreshold": 0,
            "MaxVertexError": 0.0, "MaxActiveTargets": 0, "Hysteresis": 0.0}
MODES = [
    ("none", {}),
    ("fixed-maximum", {"Threshold": 0.35, "RedistributionStrategy": "Maximum"}),
    ("fixed-remaining", {"Threshold": 0.35}),
    ("adjusted", {"Threshold": 0.7, "AdjustThreshold": 1}),  # keeps jawOpen (0.6) by its dist_norm
    ("error-bounded", {"MaxVertexError": 0.002}),
    ("budget", {"MaxActiveTargets": 2}),
    ("adjusted+budget+hysteresis", {"Threshold": 0.2, "AdjustThreshold": 1, "MaxActiveTargets": 3,
                                    "Hysteresis": 0.5}),
]


def run(c, args):
    import numpy as np
    from paraview import simple
    from paraview import servermanager as sm

    face = t.face_or_skip(args.face)
    t.load_plugin(args.plugin, globals())
    ranks = sm.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    print("ranks: %d" % ranks, flush=True)

    reader = MorphNodeFaceReader(FileName=face, MeshIndex=0)  # noqa: F821 - one mesh
    ids = simple.GenerateIds(Input=reader)
    ids.GeneratePointIds = 1
    ids.PointIdsArrayName = "PointIds"
    ids.GenerateCellIds = 0
    split = simple.RedistributeDataSet(Input=ids)
    ghosts = simple.GhostCellsGenerator(Input=split)
    morph = MorphNode(Input=ghosts)  # noqa: F821
    morph.TargetWeights = WEIGHTS
    morph.WeightMode = "Relative"
    morph.Threshold = 0.1               # prunes browInnerUp_L (0.05): weights only, the
    morph.RedistributionStrategy = "Remaining"  # same on every piece
    morph.GenerateDistanceArrays = 1

    # Every rank holds part of the face. (Each piece is fetched on its own: Fetch()
    # without a rank appends pieces only for the data types it knows how to append.)
    pieces = [sm.Fetch(morph, rank) for rank in range(ranks)]
    counts = [piece.GetNumberOfPoints() for piece in pieces]
    print("points per rank: %s" % counts, flush=True)
    c.require(all(n > 0 for n in counts), "every rank holds part of the face")
    if ranks > 1:
        c.check(all(n < 11248 for n in counts), "no rank holds the whole face")

    # Every rank resolved the same effective weights.
    weights = [t.field_values(piece, "EffectiveWeights") for piece in pieces]
    c.require(weights[0] is not None and len(weights[0]) == 54,
              "EffectiveWeights: one per target (neutral first)")
    c.check(all(w == weights[0] for w in weights), "all ranks use the same effective weights")
    active = t.field_values(pieces[0], "ActiveTargetCount")
    c.check(active == [3], "Threshold 0.1 prunes browInnerUp_L: 3 active targets (got %s)" % active)

    # Gather, put every point back in its place by PointIds.
    gathered = [t.point_arrays(piece) for piece in pieces]
    c.require(all("PointIds" in a and "AnimatedRegion" in a for _, a in gathered),
              "every piece carries PointIds and AnimatedRegion")
    points = np.concatenate([p for p, _ in gathered])
    arrays = {name: np.concatenate([a[name] for _, a in gathered])
              for name in ("PointIds", "AnimatedRegion", "Distance_jawOpen")}
    pid = arrays["PointIds"].astype(np.int64)
    unique, first = np.unique(pid, return_index=True)
    print("gathered %d points, %d distinct (%d duplicated on piece boundaries)"
          % (len(pid), len(unique), len(pid) - len(unique)), flush=True)
    c.require(len(unique) == 11248 and unique[0] == 0 and unique[-1] == 11247,
              "the pieces cover all 11248 points")
    # A duplicated point must have the same result on both sides of a boundary.
    order = np.argsort(pid, kind="stable")
    same = pid[order][1:] == pid[order][:-1]
    seam = float(np.abs(points[order][1:][same] - points[order][:-1][same]).max()) \
        if same.any() else 0.0
    c.check(seam == 0.0, "duplicated boundary points agree exactly (max difference %g)" % seam)
    result = {
        "points": points[first].astype(np.float64),
        "region": arrays["AnimatedRegion"][first].astype(np.float64),
        "jaw": arrays["Distance_jawOpen"][first].astype(np.float64),
        "weights": np.array(weights[0], dtype=np.float64),
    }
    region = result["region"]
    print("AnimatedRegion: range [%.6g, %.6g], sum %.9g; points: sum %s"
          % (region.min(), region.max(), region.sum(), result["points"].sum(axis=0)),
          flush=True)
    c.check(region.min() >= 0.0 and region.max() > 0.0, "AnimatedRegion has a sensible range")

    # Every optimizer mode: the same decision on every rank, the one-rank run's.
    flagged = [piece.GetPointData().GetArray("vtkGhostType") is not None for piece in pieces]
    print("pieces with a point ghost array (duplicated points flagged): %s" % flagged, flush=True)
    morph.TargetWeights = WEIGHTS
    for mode, settings in MODES:
        for prop, value in {**DEFAULTS, **settings}.items():
            setattr(morph, prop, value)
        morph.SMProxy.InvokeCommand("ResetHysteresis")
        mode_pieces = [sm.Fetch(morph, rank) for rank in range(ranks)]
        per_rank = {name: [t.field_values(piece, name) for piece in mode_pieces]
                    for name in ("EffectiveWeights", "DistNorm", "ErrorBound", "ActiveTargetCount")}
        for name, values in per_rank.items():
            c.check(values[0] is not None and all(v == values[0] for v in values),
                    "%s: every rank holds the same %s" % (mode, name))
        print("%s: active %s, error bound %s, effective weights of the set targets %s" % (
            mode, per_rank["ActiveTargetCount"][0], per_rank["ErrorBound"][0],
            [round(per_rank["EffectiveWeights"][0][i], 6) for i in (27, 46, 3, 12)]), flush=True)
        result["weights " + mode] = np.array(per_rank["EffectiveWeights"][0], dtype=np.float64)
        result["distnorm " + mode] = np.array(per_rank["DistNorm"][0], dtype=np.float64)
    for prop, value in DEFAULTS.items():
        setattr(morph, prop, value)

    if args.save:
        np.savez(args.save, **result)
        print("saved %s" % args.save, flush=True)
    if args.compare:
        reference = np.load(args.compare)
        scale = float(np.linalg.norm(np.ptp(reference["points"], axis=0)))
        tolerance = 1e-6 * scale
        for key, what in (("points", "blended points"), ("region", "AnimatedRegion"),
                          ("jaw", "Distance_jawOpen"), ("weights", "effective weights")):
            error = float(np.abs(result[key] - reference[key]).max())
            c.check(error <= tolerance, "%s equal the one-rank result (max difference %.3g, "
                    "tolerance %.3g)" % (what, error, tolerance))
        for key in ("points", "region"):
            c.near(float(result[key].sum()), float(reference[key].sum()),
                   tolerance * result[key].size, "sum of %s against one rank" % key)
        # The whole face's decisions: those of one rank. Without ghost flags, points
        # duplicated on piece boundaries count twice in dist_morph (DistNorm moves by a
        # fraction of their share); with them, only the order of the sums differs.
        duplicated = (len(pid) - len(unique)) / float(len(unique))
        allowed = 1e-12 if all(flagged) else 2.0 * duplicated
        for mode, _ in MODES:
            error = float(np.abs(result["distnorm " + mode] - reference["distnorm " + mode]).max())
            c.check(error <= allowed, "%s: DistNorm of the whole face, as on one rank (max difference "
                    "%.3g, allowed %.3g)" % (mode, error, allowed))
            error = float(np.abs(result["weights " + mode] - reference["weights " + mode]).max())
            c.check(error <= 1e-12, "%s: the effective weights of one rank (max difference %.3g)"
                    % (mode, error))


if __name__ == "__main__":
    parser = t.common_arguments(__doc__.splitlines()[0])
    parser.add_argument("--save", help="write the gathered result (numpy .npz) here")
    parser.add_argument("--compare", help="compare with a result written by --save")
    arguments = parser.parse_args()
    t.main(lambda c: run(c, arguments), "TestMorphNodeDistributed")
