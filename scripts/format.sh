#!/usr/bin/env bash
# clang-format every C++ file of the project; --check only reports files that would change.
set -euo pipefail
cd "$(dirname "$0")/.."
files=$(git ls-files '*.cpp' '*.hpp' | grep -v '^fuzz/corpus/')
if [ "${1:-}" = "--check" ]; then
  clang-format --dry-run --Werror $files
else
  clang-format -i $files
fi
