#!/usr/bin/env bash
# Configure and build the MorphNode ParaView plugin, then run its tests without a GUI:
#   1. TestMorphNodePlugin.py       pvbatch, one process, screenshot (under xvfb-run
#                                   when there is no X display)
#   2. TestMorphNodeProxies.py      pvbatch: every class's proxy through its properties
#      TestMorphGltfWriterProxy.py  pvbatch: the glTF writer (File > Save Data)
#      TestMorphNodeTextures.py     pvbatch: a part's base colour texture on screen
#   3. TestMorphNodeDistributed.py  pvbatch on one rank (reference), then
#                                   mpiexec -n 2 pvbatch, compared with it
# Exits non-zero when the build or a test fails; a test whose data is missing is
# reported as skipped (and fails under CI, i.e. when CI is set and not "false").
#
# Needs the Debian packages paraview-dev (pulls in paraview) and openmpi-bin, plus what
# MorphNode's core needs (libglm-dev, nlohmann-json3-dev, libopenmesh-dev) and xvfb,
# xauth. python3-paraview must NOT be installed (it conflicts with python3-vtk9): it is
# extracted into a private prefix by prepare-paraview-python.sh.
#
# Environment:
#   MORPHNODE_PARAVIEW_BUILD_DIR       build folder (default /tmp/build-paraview)
#   MORPHNODE_PARAVIEW_PYTHON_PREFIX   where python3-paraview is extracted
#                                      (default /opt/paraview-python)
#   MORPHNODE_FACE                     the ICT-FaceKit GLB (default
#                                      ../shared/data/ict-facekit/ict_face11248_sparse53.glb)
#   JOBS                               parallel build jobs (default 1)
#   TEST_TIMEOUT                       seconds per pvbatch run (default 600)
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${MORPHNODE_PARAVIEW_BUILD_DIR:-/tmp/build-paraview}"
jobs="${JOBS:-1}"
test_timeout="${TEST_TIMEOUT:-600}"
export MORPHNODE_PARAVIEW_PYTHON_PREFIX="${MORPHNODE_PARAVIEW_PYTHON_PREFIX:-/opt/paraview-python}"

say() { printf '\n=== %s\n' "$*"; }
die() { printf 'run-tests: %s\n' "$*" >&2; exit 1; }

# --- ParaView's Python modules, without installing python3-paraview -------------------
say "python3-paraview, extracted into $MORPHNODE_PARAVIEW_PYTHON_PREFIX"
site="$("$here/prepare-paraview-python.sh" "$MORPHNODE_PARAVIEW_PYTHON_PREFIX")" ||
  die "could not extract python3-paraview"
echo "$site"

# --- configure and build ---------------------------------------------------------------
say "configure and build the plugin in $build"
generator=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DMORPHNODE_PARAVIEW_PYTHON_PREFIX="$MORPHNODE_PARAVIEW_PYTHON_PREFIX" ||
  die "configure failed"
cmake --build "$build" --parallel "$jobs" || die "build failed"
plugin="$(cat "$build/morphnode-plugin-path.txt")"
[ -f "$plugin" ] || die "the plugin was not built: $plugin"
echo "plugin: $plugin"

# --- the environment of pvbatch ----------------------------------------------------------
# ParaView's own Python modules (`paraview`, ParaView's `vtkmodules`) must come before
# /usr/lib/python3/dist-packages, where python3-vtk9's `vtkmodules` (VTK 9.1) lives.
export PYTHONPATH="$site${PYTHONPATH:+:$PYTHONPATH}"
export MORPHNODE_PLUGIN="$plugin"
# So that ParaView (GUI, pvpython, pvbatch) also finds the plugin by name.
export PV_PLUGIN_PATH="$(dirname "$plugin")${PV_PLUGIN_PATH:+:$PV_PLUGIN_PATH}"
out="$build/Testing"
mkdir -p "$out"

x11=()
if [ -z "${DISPLAY:-}" ]; then
  command -v xvfb-run >/dev/null || die "no X display and no xvfb-run (install xvfb xauth)"
  x11=(xvfb-run -a -s "-screen 0 1024x768x24")
fi

failed=0
skipped=0
record() { # name exit-code
  case "$2" in
    0) echo "--- $1: passed" ;;
    125)
      if [ -n "${CI:-}" ] && [ "${CI}" != false ]; then
        # CI expects the data beside the repository: a skip there would pass vacuously.
        echo "--- $1: FAILED (skipped for missing data, and CI requires the data)"
        failed=$((failed + 1))
      else
        echo "--- $1: SKIPPED"; skipped=$((skipped + 1))
      fi ;;
    124) echo "--- $1: FAILED (timed out after ${test_timeout}s)"; failed=$((failed + 1)) ;;
    *) echo "--- $1: FAILED (exit code $2)"; failed=$((failed + 1)) ;;
  esac
}

# --- 1. one process, with a screenshot ---------------------------------------------------
say "TestMorphNodePlugin (pvbatch)"
timeout -k 10 "$test_timeout" "${x11[@]}" pvbatch --force-offscreen-rendering \
  "$here/Testing/TestMorphNodePlugin.py" --plugin "$plugin" \
  --png "$out/morphnode-animated-region.png"
record TestMorphNodePlugin $?

# --- 2. every class's proxy, driven through its properties --------------------------------
say "TestMorphNodeProxies (pvbatch)"
timeout -k 10 "$test_timeout" pvbatch "$here/Testing/TestMorphNodeProxies.py" --plugin "$plugin"
record TestMorphNodeProxies $?

# --- 2b. the glTF writer proxy: a head and a behaviour's track saved as glTF ---------------
say "TestMorphGltfWriterProxy (pvbatch)"
timeout -k 10 "$test_timeout" pvbatch "$here/Testing/TestMorphGltfWriterProxy.py" --plugin "$plugin"
record TestMorphGltfWriterProxy $?

# --- 2c. a part's base colour texture shown through the representation's Texture ---------
say "TestMorphNodeTextures (pvbatch)"
timeout -k 10 "$test_timeout" "${x11[@]}" pvbatch --force-offscreen-rendering \
  "$here/Testing/TestMorphNodeTextures.py" --plugin "$plugin"
record TestMorphNodeTextures $?

# --- 3. the face split across two MPI ranks ------------------------------------------------
say "TestMorphNodeDistributed (pvbatch, 1 rank: the reference)"
reference="$out/distributed-one-rank.npz"
rm -f "$reference"
timeout -k 10 "$test_timeout" pvbatch \
  "$here/Testing/TestMorphNodeDistributed.py" --plugin "$plugin" --save "$reference"
code=$?
record "TestMorphNodeDistributed (1 rank)" $code

if [ $code -eq 0 ]; then
  say "TestMorphNodeDistributed (mpiexec -n 2 pvbatch)"
  if ! command -v mpiexec >/dev/null; then
    echo "mpiexec not found (install openmpi-bin)"
    record "TestMorphNodeDistributed (2 ranks)" 1
  else
    mpi=(mpiexec -n 2)
    if mpiexec --version 2>&1 | grep -q -i -E "open ?mpi|openrte"; then
      # Two ranks even on one core; Open MPI refuses root unless told.
      mpi+=(--oversubscribe)
      [ "$(id -u)" -ne 0 ] || mpi+=(--allow-run-as-root)
    fi
    timeout -k 10 "$test_timeout" "${mpi[@]}" pvbatch \
      "$here/Testing/TestMorphNodeDistributed.py" --plugin "$plugin" --compare "$reference"
    record "TestMorphNodeDistributed (2 ranks)" $?
  fi
elif [ $code -eq 125 ]; then
  record "TestMorphNodeDistributed (2 ranks)" 125
else
  record "TestMorphNodeDistributed (2 ranks)" 1
fi

say "summary: $failed failed, $skipped skipped"
[ -f "$out/morphnode-animated-region.png" ] && echo "screenshot: $out/morphnode-animated-region.png"
[ $failed -eq 0 ]
