#!/usr/bin/env bash
# The selection table of issue #5: observes the shared costa2017 worlds (and vantage's stand-in for
# the paper's multiple bin picking world) once into visibility matrices, then runs
# build/bench/selection_table on them and on a generated instance of 1,000 candidates: method, N,
# coverage, exact's bound and gap, seconds, for N = 1..10, and the targets (greedy and local never
# below RANSAC; exact optimal or within 0.1 point, 0.5 on multi_bin_picking_b and the generated
# instance, for N <= 10 in 10 s: issue 14). Results: bench/RESULTS.md, "Selection".
#
# Usage: bench/selection_table.sh [extra selection_table options, e.g. --n-max 5]
# Env:   BUILD (default build), SHARED (default ../shared/worlds/costa2017), VIS (folder for the
#        .vis files; default a temporary one), THREADS (--threads for observe).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
SHARED=${SHARED:-../shared/worlds/costa2017}
for exe in "$BUILD/vantage" "$BUILD/bench/selection_table"; do
  if [[ ! -x "$exe" ]]; then
    echo "selection_table.sh: $exe not found — build first (cmake -S . -B $BUILD && cmake --build $BUILD)" >&2
    exit 2
  fi
done
if [[ -z "${VIS:-}" ]]; then
  VIS=$(mktemp -d)
  trap 'rm -rf "$VIS"' EXIT
fi
GLOBAL=(-q)
[[ -n "${THREADS:-}" ]] && GLOBAL+=(--threads "$THREADS")
GZ=(--model-path "$SHARED/media/models" --resource-path "$SHARED/media")
files=()
for world in "$SHARED/worlds/bin_picking.world" "$SHARED/worlds/bin_picking_with_occlusions.world" \
             bench/worlds/multi_bin_picking.world bench/worlds/multi_bin_picking_b.world; do
  vis="$VIS/$(basename "$world" .world).vis"
  [[ -f "$vis" ]] || "$BUILD/vantage" "${GLOBAL[@]}" observe "$world" --out "$vis" "${GZ[@]}" >/dev/null
  files+=("$vis")
done
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo
"$BUILD/bench/selection_table" "$@" --generated "${files[@]}"
