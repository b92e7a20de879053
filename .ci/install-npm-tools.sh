#!/usr/bin/env bash
# Installs the npm tools MorphNode's tests use into a project-local prefix (default
# .ci/npm-tools, which CMake looks in; ignored by git): the Khronos glTF validator
# (gltf-validator), which checks the glTF exports (Testing/GltfValidator.cmake); three.js
# (three), the browser face of the avatar stream (docs/streaming.md) and the independent glTF
# renderer beside MorphNode's (Testing/Browser, docs/materials.md), and playwright-core, which
# drives Debian's chromium in those browser tests (no browser download). Needs node
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
three_version="0.187.0"
playwright_core_version="1.65.1"
packages=("gltf-validator@$validator_version" "three@$three_version" "playwright-core@$playwright_core_version"
  "gltfpack@$gltfpack_version")
missing=()
for package in "${packages[@]}"; do
  name="${package%@*}"
  version="${package##*@}"
  if [ -f "$prefix/node_modules/$name/package.json" ] &&
    grep -q "\"version\": \"$version\"" "$prefix/node_modules/$name/package.json"; then
    echo "install-npm-tools: $name $version present in $prefix"
  else
    missing+=("$package")
  fi
done
[ "${#missing[@]}" -eq 0 ] && exit 0
mkdir -p "$prefix"
# All of them in one call: npm install --no-save prunes what the call does not name.
npm install --prefix "$prefix" --no-audit --no-fund --no-save "${packages[@]}"
echo "install-npm-tools: ${packages[*]} installed in $prefix"
