"""The whole avatar's morph stage per mesh level (vtkMorphNodeFilter's MeshLevels) against
the filter without levels, in one run (docs/lod.md).

    PYTHONPATH=build/lib/python3/dist-packages python3 Testing/Benchmarks/bench_mesh_levels.py \
        [--face ../shared/data/makehuman-avatar/makehuman_avatar.glb] [--rounds 5] [--frames 60]

Every part of the avatar (the reader's collection) goes through one filter per
configuration: levels off (the yardstick), and MeshLevels on with FinestLevel l and a screen
that asks for full resolution, so that level l is shown (l = 0..3). Each frame sets new
speech-like weights (a fixed seed; a few targets at a time, as visemes are) and times
Update (weights, optimizer, the level's blend and its output data sets). Configurations take
turns in every round; per round the 10th percentile of a configuration's frames (the frame
as it costs when no other job takes the cores), then the median over the rounds; speed-ups
are medians of the per-round ratios. Morph stage only: no rendering.
"""
import argparse
import os
import random
import statistics
import time

from morphnode import vtkMorphNodeFilter, vtkMorphTargetReader


def parse():
    here = os.path.dirname(os.path.abspath(__file__))
    default = os.path.join(here, "..", "..", "..", "shared", "data", "makehuman-avatar", "makehuman_avatar.glb")
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--face", default=os.path.normpath(default))
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--frames", type=int, default=60)
    return p.parse_args()


def main():
    args = parse()
    reader = vtkMorphTargetReader()
    reader.SetFileName(args.face)
    reader.Update()
    configs = [("levels off", None)] + [("level %d" % l, l) for l in range(4)]
    filters = []
    for name, level in configs:
        f = vtkMorphNodeFilter()
        f.SetInputConnection(reader.GetOutputPort())
        f.SetWeightModeToRelative()
        if level is not None:
            f.MeshLevelsOn()
            f.SetFinestLevel(level)
            f.SetPixelsPerUnit(1e9)  # the screen asks for full resolution: FinestLevel is shown
        started = time.perf_counter()
        f.Update()
        built = time.perf_counter() - started
        filters.append((name, level, f, built))
    names = [filters[0][2].GetTargetName(i) for i in range(1, filters[0][2].GetNumberOfTargets())]
    rng = random.Random(7)

    def frame_weights():
        chosen = rng.sample(names, min(3, len(names)))
        return {n: (rng.uniform(0.2, 0.8) if n in chosen else 0.0) for n in names}

    def run(f, frames):
        times = []
        for _ in range(frames):
            for n, w in frame_weights().items():
                f.SetWeightByName(n, w)
            t = time.perf_counter()
            f.Update()
            times.append(time.perf_counter() - t)
        return times

    # Warm-up: every levelled filter reaches its level (geomorphs from level 0 take frames).
    for name, level, f, _ in filters:
        run(f, 150)
    per_round = {name: [] for name, *_ in filters}
    for _ in range(args.rounds):
        for name, level, f, _ in filters:
            t = sorted(run(f, args.frames))
            per_round[name].append(t[len(t) // 10])
    base = per_round["levels off"]
    print("| run | level shown | points | morph (ms) | speed-up | first Update (s) |")
    print("|---|---|---|---|---|---|")
    for name, level, f, built in filters:
        points = f.GetOutputDataObject(0).GetNumberOfPoints()
        ms = 1e3 * statistics.median(per_round[name])
        speedup = statistics.median(b / x for b, x in zip(base, per_round[name]))
        shown = "-" if level is None else str(f.GetLevel())
        print("| %s | %s | %d | %.3f | %.2f x | %.2f |" % (name, shown, points, ms, speedup, built))
    print("\nload average: %.1f %.1f %.1f" % os.getloadavg())


if __name__ == "__main__":
    main()
