#!/usr/bin/env bash
# The paper's experiments (SYSTEM.md, "The paper's results") on the shared worlds, plus vantage's
# own stand-in for the paper's multiple bin picking world: `vantage optimize --method all` per
# (world, N), then ONE markdown table of the paper's RANSAC coverage beside vantage's best single
# sensor and its ransac / greedy / local / exact coverage at N, exact's proven upper bound, the
# candidate and reference-voxel counts and the end-to-end seconds.
#
# Usage: bench/paper.sh [--quick]   (--quick: the two N = 1 rows only)
# Env:   BUILD (default build: runs $BUILD/vantage), SHARED (default ../shared/worlds/costa2017),
#        THREADS (passed as --threads when set), SEED (--seed when set).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
VANTAGE="$BUILD/vantage"
SHARED=${SHARED:-../shared/worlds/costa2017}
PY=/usr/bin/python3
QUICK=0
[[ "${1:-}" == "--quick" ]] && QUICK=1
if [[ ! -x "$VANTAGE" ]]; then
  echo "paper.sh: $VANTAGE not found — build first (cmake -S . -B $BUILD && cmake --build $BUILD)" >&2
  exit 2
fi
GZ=(--model-path "$SHARED/media/models" --resource-path "$SHARED/media")
GLOBAL=(-q)
[[ -n "${THREADS:-}" ]] && GLOBAL+=(--threads "$THREADS")
EXTRA=()
[[ -n "${SEED:-}" ]] && EXTRA+=(--seed "$SEED")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), threads: ${THREADS:-all}"
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown), vantage $("$VANTAGE" --version 2>/dev/null || echo '')"
echo
echo "| world | N | paper (RANSAC) | best single | ransac | greedy | local | exact | exact's bound | candidates | reference voxels | seconds |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"

run() {  # label world N paper_coverage
  local label=$1 world=$2 n=$3 paper=$4
  local out="$TMP/$label-$n" start end
  start=$(date +%s.%N)
  "$VANTAGE" "${GLOBAL[@]}" optimize "$world" "${GZ[@]}" "${EXTRA[@]}" -n "$n" --method all \
    --out "$out" >/dev/null
  end=$(date +%s.%N)
  "$PY" - "$label" "$n" "$paper" "$out/report.json" "$start" "$end" <<'PYEOF'
import json, sys
label, n, paper, path, start, end = sys.argv[1:]
n = int(n)
report = json.load(open(path))
pct = lambda v: "—" if v is None else f"{100 * v:.2f} %"
def at_n(method):
    for r in report["results"]:
        if r["method"] == method and r["n"] == n:
            return r
    return None
best = next((r for r in report["results"] if r["method"] == "best"), None)
cells = [pct(best["coverage"]) if best else "—"]
for m in ("ransac", "greedy", "local", "exact"):
    r = at_n(m)
    cells.append(pct(r["coverage"]) if r else "—")
exact = at_n("exact")
bound = "—"
if exact and "upper_bound" in exact:
    bound = "optimal" if exact.get("optimal") else pct(exact["upper_bound"])
print(f"| {label} | {n} | {paper} | " + " | ".join(cells) +
      f" | {bound} | {len(report['candidates'])} | {report['reference_voxels']} | "
      f"{float(end) - float(start):.1f} |")
PYEOF
}

run bin_picking "$SHARED/worlds/bin_picking.world" 1 "45.10 %"
[[ $QUICK == 0 ]] && run bin_picking "$SHARED/worlds/bin_picking.world" 5 "64.63 %"
run bin_picking_with_occlusions "$SHARED/worlds/bin_picking_with_occlusions.world" 1 "19.27 %"
if [[ $QUICK == 0 ]]; then
  run bin_picking_with_occlusions "$SHARED/worlds/bin_picking_with_occlusions.world" 3 "31.19 %"
  run "multi_bin_picking (vantage's stand-in: 4 motors, 450 sensors, 7 types)" \
    bench/worlds/multi_bin_picking.world 10 "43.93 % (paper's own world)"
fi
