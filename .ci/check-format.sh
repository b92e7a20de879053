#!/usr/bin/env bash
# Every C and C++ file in VTK's clang-format style (.clang-format at the top level).
# Fix with: git ls-files -z '*.h' '*.hpp' '*.cxx' '*.cpp' '*.c' | xargs -0 clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
git ls-files -z '*.h' '*.hpp' '*.cxx' '*.cpp' '*.c' | xargs -0 clang-format --dry-run -Werror
echo "check-format: every C/C++ file is formatted"
