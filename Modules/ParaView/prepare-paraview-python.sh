#!/bin/sh
# Extract Debian's python3-paraview into a private prefix WITHOUT installing it.
#
# python3-paraview conflicts with python3-vtk9 (both ship the Python package
# `vtkmodules`), and MorphNode needs python3-vtk9, so it must never be installed with
# apt-get. Its files are needed all the same:
#   - ParaView's Python modules (`paraview`, ParaView's `vtkmodules`) for pvbatch;
#   - the wrapping hierarchy files lib/<arch>/vtk/hierarchy/ParaView/*-hierarchy.txt,
#     which building a plugin against paraview-dev reads.
# So: `apt-get download` the .deb (no root needed) and `dpkg -x` it into PREFIX.
#
# Usage: prepare-paraview-python.sh [PREFIX]
#   PREFIX defaults to $MORPHNODE_PARAVIEW_PYTHON_PREFIX, else /opt/paraview-python.
# Prints the PYTHONPATH to use. Idempotent: does nothing when PREFIX already holds the
# version of python3-paraview that matches the installed paraview.
set -eu

prefix=${1:-${MORPHNODE_PARAVIEW_PYTHON_PREFIX:-/opt/paraview-python}}

pv_version=$(dpkg-query -W -f='${Version}' paraview 2>/dev/null || true)
if [ -z "$pv_version" ]; then
  echo "prepare-paraview-python: the Debian package paraview is not installed" >&2
  exit 1
fi

stamp="$prefix/.python3-paraview-version"
site="$prefix/usr/lib/python3/dist-packages"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$pv_version" ] && [ -f "$site/paraview/simple.py" ]; then
  echo "$site"
  exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# apt-get download writes into the current folder; as root, let its sandbox user _apt
# write there, or it warns that the download is unsandboxed (harmless).
chmod 755 "$work"
if [ "$(id -u)" = 0 ] && id _apt >/dev/null 2>&1; then
  chown _apt "$work"
fi
(cd "$work" && apt-get download "python3-paraview=$pv_version" >&2)
deb=$(ls "$work"/python3-paraview_*.deb)
mkdir -p "$prefix"
dpkg -x "$deb" "$prefix"
echo "$pv_version" > "$stamp"
echo "$site"
