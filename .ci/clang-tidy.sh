#!/usr/bin/env bash
# clang-tidy (Debian's 14) over the VTK layer, Modules/MorphNode/*/*.cxx, with the checks of
# .clang-tidy and the compile commands of a configured build (default: build). Any finding
# fails. Usage: .ci/clang-tidy.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
if [ ! -f "$build/compile_commands.json" ]; then
  echo "clang-tidy.sh: $build/compile_commands.json missing (configure and build first)" >&2
  exit 2
fi
# .clang-tidy makes every finding an error. The modules' generated export headers
# (vtkMorphNode*Module.h) must exist: building the modules made them.
run-clang-tidy-14 -p "$build" -quiet -j "${JOBS:-2}" \
  "$PWD/Modules/MorphNode/.*\.cxx$"
