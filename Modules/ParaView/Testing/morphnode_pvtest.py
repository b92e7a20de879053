"""Helpers shared by MorphNode's pvbatch tests (run by pvbatch, never by plain python3).

Exit codes: 0 passed, 1 failed, 125 skipped (data missing); the driver run-tests.sh
maps them. Two pvbatch 5.11 quirks shape main():
- under mpiexec, a script that dies of an uncaught exception hangs (rank 0 stops, the
  other ranks wait for it, spinning), so every error becomes sys.exit(1);
- sys.exit() after a render window was created ends in an X error (GLXBadContext in
  X_GLXMakeCurrent) and exit code 1, so a passing test ends normally, without sys.exit.
"""
import argparse
import os
import sys
import traceback

SKIP = 125
DEFAULT_FACE = os.path.join(
    os.path.dirname(os.path.abspath(__file__)),
    "..", "..", "..", "..", "shared", "data", "ict-facekit", "ict_face11248_sparse53.glb")


class TestFailure(Exception):
    pass


class Checker:
    """Collects check results; a failed check does not stop the test."""

    def __init__(self, name):
        self.name = name
        self.failures = []

    def check(self, condition, what):
        print("[%s] %s: %s" % (self.name, "ok  " if condition else "FAIL", what), flush=True)
        if not condition:
            self.failures.append(what)
        return condition

    def near(self, value, expected, tolerance, what):
        return self.check(abs(value - expected) <= tolerance,
                          "%s: %.9g vs %.9g (tolerance %g)" % (what, value, expected, tolerance))

    def require(self, condition, what):
        """A check the rest of the test depends on."""
        if not self.check(condition, what):
            raise TestFailure(what)


def common_arguments(description):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--plugin", default=os.environ.get("MORPHNODE_PLUGIN"),
                        help="MorphNodePlugin.so (default: $MORPHNODE_PLUGIN)")
    parser.add_argument("--face", default=os.environ.get("MORPHNODE_FACE", DEFAULT_FACE),
                        help="the ICT-FaceKit GLB (default: $MORPHNODE_FACE or "
                             "../shared/data/ict-facekit/ict_face11248_sparse53.glb)")
    return parser


def load_plugin(path, namespace):
    from paraview import simple
    if not path or not os.path.isfile(path):
        raise TestFailure("plugin not found: %r (pass --plugin or set MORPHNODE_PLUGIN)" % path)
    # remote=False: pvbatch's client and server are the same process (rank 0); the
    # plugin is loaded on every rank all the same.
    simple.LoadPlugin(path, remote=False, ns=namespace)


def face_or_skip(path):
    if not path or not os.path.isfile(path):
        print("SKIP: the ICT-FaceKit face %r is missing (read-only data, never copied "
              "into the repository); set MORPHNODE_FACE or pass --face" % path, flush=True)
        sys.exit(SKIP)
    return os.path.abspath(path)


def point_arrays(data):
    """{name: numpy array} of a VTK data set's point data, and its points."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    arrays = {}
    pd = data.GetPointData()
    for i in range(pd.GetNumberOfArrays()):
        a = pd.GetArray(i)
        if a is not None and a.GetName():
            arrays[a.GetName()] = vtk_to_numpy(a)
    points = vtk_to_numpy(data.GetPoints().GetData()) if data.GetPoints() else None
    return points, arrays


def field_values(data, name):
    a = data.GetFieldData().GetAbstractArray(name)
    if a is None:
        return None
    return [a.GetValue(i) for i in range(a.GetNumberOfValues())]  # strings or numbers


def main(run, name):
    """Runs run(checker): returns when it passed, else exits with 1 (or 125: skipped)."""
    checker = Checker(name)
    try:
        run(checker)
    except SystemExit:
        raise
    except TestFailure as e:
        print("[%s] stopped: %s" % (name, e), flush=True)
    except Exception:  # noqa: BLE001 - any error must become an exit code (see above)
        traceback.print_exc()
        checker.failures.append("exception")
    if checker.failures:
        print("[%s] FAILED: %d check(s)" % (name, len(checker.failures)), flush=True)
        sys.exit(1)
    print("[%s] PASSED" % name, flush=True)
