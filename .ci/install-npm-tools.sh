#!/usr/bin/env bash
# Installs the npm tools MorphNode's tests use into a project-local prefix (default
# .ci/npm-tools, which CMake looks in; ignored by git): the Khronos glTF validator
# (gltf-validator), which checks the glTF exports (Testing/GltfValidator.cmake); three.js
# (three) and playwright-core, which render the same avatar in Debian's headless
# `chromium` as an independent glTF renderer (Testing/Browser, docs/materials.md). Needs node
# and npm: Debian's `nodejs` (.ci/packages.txt) and `npm`, installed here when npm is missing
# (Node.js packages from elsewhere, e.g. NodeSource's, bring their own npm).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
prefix="${1:-$here/npm-tools}"
validator_version="2.0.0-dev.3.10"
three_version="0.187.0"
playwright_version="1.65.1"
installed() { # name version
  [ -f "$prefix/node_modules/$1/package.json" ] &&
    grep -q "\"version\": \"$2\"" "$prefix/node_modules/$1/package.json"
}
if ! command -v npm >/dev/null 2>&1; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends npm
fi
if installed gltf-validator "$validator_version" && installed three "$three_version" &&
  installed playwright-core "$playwright_version"; then
  echo "install-npm-tools: gltf-validator $validator_version, three $three_version, playwright-core $playwright_version present in $prefix"
  exit 0
fi
mkdir -p "$prefix"
npm install --prefix "$prefix" --no-audit --no-fund --no-save "gltf-validator@$validator_version" \
  "three@$three_version" "playwright-core@$playwright_version"
echo "install-npm-tools: gltf-validator $validator_version, three $three_version, playwright-core $playwright_version installed in $prefix"
