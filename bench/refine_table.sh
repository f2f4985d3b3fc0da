#!/usr/bin/env bash
# The refined-poses table of issue 9: on the shared costa2017 bin-picking worlds, for N = 1..5,
# the coverage of `local` over the deployed candidates and after refinement (new poses around the
# chosen sensors, only those traced, re-selection), the gain in points, the new candidates and the
# extra rays traced (and their ratio to the rays of observing every deployed candidate), and the
# seconds of the refinement. Target: refined >= unrefined at every N (the driver exits 1 if not).
# Results: bench/RESULTS.md, "Refined poses".
#
# Usage: bench/refine_table.sh [extra refine_table options, e.g. --rounds 6 --per-sensor 24]
# Env:   BUILD (default build), SHARED (default ../shared/worlds/costa2017).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
SHARED=${SHARED:-../shared/worlds/costa2017}
exe="$BUILD/bench/refine_table"
if [[ ! -x "$exe" ]]; then
  echo "refine_table.sh: $exe not found — build first (cmake -S . -B $BUILD && cmake --build $BUILD)" >&2
  exit 2
fi
GZ=(--model-path "$SHARED/media/models" --resource-path "$SHARED/media")
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo
header=(--header)
for world in bin_picking bin_picking_with_occlusions; do
  "$exe" "$SHARED/worlds/$world.world" "${GZ[@]}" "${header[@]}" "$@"
  header=()
done
