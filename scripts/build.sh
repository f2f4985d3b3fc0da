#!/usr/bin/env bash
# Configures and builds vantage into $BUILD with $JOBS jobs, quietly: the compiler's output goes to
# $BUILD/build.log and only its warnings, errors and the time taken are printed.
#   scripts/build.sh             # everything (library, tool, tests, benchmarks)
#   scripts/build.sh vantage     # only the command-line tool (what `make run` needs)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
JOBS=${JOBS:-2}
BUILD_TYPE=${BUILD_TYPE:-Release}
mkdir -p "$BUILD"
log="$BUILD/build.log"
start=$(date +%s)
targets=()
for target in "$@"; do targets+=(--target "$target"); done
what=${*:-everything}
echo "build: $what into $BUILD/ with $JOBS jobs (log: $log) ..."
if ! { cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE="$BUILD_TYPE" ${CMAKE_ARGS:-} &&
       cmake --build "$BUILD" -j"$JOBS" "${targets[@]}" -- --no-print-directory; } >"$log" 2>&1; then
  grep -E "error|Error" "$log" | head -40 || true
  echo "build: FAILED after $(( $(date +%s) - start )) s — the whole output is in $log" >&2
  exit 1
fi
# (lto-wrapper's "using serial compilation" is a note of the linker of the Python module's LTO.)
grep -E "warning:" "$log" | grep -v "lto-wrapper: warning: using serial compilation" | sort -u |
  head -20 || true
echo "build: done in $(( $(date +%s) - start )) s"
