#!/usr/bin/env bash
# Installs the npm tools MorphNode's tests use into a project-local prefix (default
# .ci/npm-tools, which CMake looks in; ignored by git): the Khronos glTF validator
# (gltf-validator), which checks the glTF exports (Testing/GltfValidator.cmake). Needs node
# and npm: Debian's `nodejs` (.ci/packages.txt) and `npm`, installed here when npm is missing
# (Node.js packages from elsewhere, e.g. NodeSource's, bring their own npm). Also gltfpack
# 1.3.0 (meshoptimizer's WebAssembly build), the yardstick of the level-of-detail study
# (docs/lod.md): Debian 12's /usr/bin/gltfpack is 0.18, older than the version compared.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
prefix="${1:-$here/npm-tools}"
validator_version="2.0.0-dev.3.10"
gltfpack_version="1.3.0"
if ! command -v npm >/dev/null 2>&1; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends npm
fi
has() { [ -f "$prefix/node_modules/$1/package.json" ] &&
  grep -q "\"version\": \"$2\"" "$prefix/node_modules/$1/package.json"; }
if has gltf-validator "$validator_version" && has gltfpack "$gltfpack_version"; then
  echo "install-npm-tools: gltf-validator $validator_version and gltfpack $gltfpack_version present in $prefix"
  exit 0
fi
mkdir -p "$prefix"
npm install --prefix "$prefix" --no-audit --no-fund --no-save \
  "gltf-validator@$validator_version" "gltfpack@$gltfpack_version"
echo "install-npm-tools: gltf-validator $validator_version and gltfpack $gltfpack_version installed in $prefix"
