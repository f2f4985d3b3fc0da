#!/usr/bin/env bash
# The "Further objectives" table of bench/RESULTS.md: set cover and k-coverage on the bench
# matrices (the shared bin_picking worlds and bench/worlds/multi_bin_picking.world), run with
# binary BIN, one row per result: world, objective, method, n, coverage %, bound, seconds.
# Run it with two binaries (before and after a change) to set them side by side.
#
# Usage: bench/objectives_table.sh BIN [VIS_DIR]
# Env:   SHARED (default ../shared/worlds/costa2017). The .vis files are made once in VIS_DIR
#        (default a temporary folder) with BIN's observe.
set -euo pipefail
BIN=$(realpath "$1")
cd "$(dirname "$0")/.."
SHARED=${SHARED:-../shared/worlds/costa2017}
VIS=${2:-}
if [[ -z "$VIS" ]]; then
  VIS=$(mktemp -d)
  trap 'rm -rf "$VIS"' EXIT
fi
mkdir -p "$VIS"
GZ=(--model-path "$SHARED/media/models" --resource-path "$SHARED/media")
for world in "$SHARED/worlds/bin_picking.world" "$SHARED/worlds/bin_picking_with_occlusions.world" \
             bench/worlds/multi_bin_picking.world; do
  vis="$VIS/$(basename "$world" .world).vis"
  [[ -f "$vis" ]] || "$BIN" -q observe "$world" --out "$vis" "${GZ[@]}" >/dev/null
done
OUT=$(mktemp -d)
row() {  # world, label, args...
  local world=$1 label=$2; shift 2
  "$BIN" -q select "$VIS/$world.vis" "$@" --out "$OUT/r" >/dev/null 2>&1 || { echo "| $world | $label | failed |"; return; }
  jq -r --arg w "$world" --arg l "$label" '.results[] |
    "| \($w) | \($l) | \(.method) | \(.n) | \(.coverage * 10000 | round / 100) | " +
    (if .n_lower_bound then "≥ \(.n_lower_bound) sensors" elif .upper_bound then
       "\(.upper_bound * 10000 | floor / 100) %" else "" end) +
    (if .optimal then " (optimal)" else "" end) + " | \(.seconds * 100 | round / 100) |"' \
    "$OUT/r/report.json"
}
echo "| world | objective | method | n | coverage % | bound | seconds |"
echo "|---|---|---|---|---|---|---|"
row bin_picking "goal 0.5" --goal 0.5
row bin_picking "goal 0.55" --goal 0.55
row multi_bin_picking "goal 0.5" --goal 0.5
row multi_bin_picking "goal 0.6" --goal 0.6
row bin_picking_with_occlusions "goal 0.04" --goal 0.04
row bin_picking "k = 2, n = 3" --k 2 -n 3
row bin_picking "k = 2, n = 5" --k 2 -n 5 --method exact
row multi_bin_picking "k = 2, n = 4" --k 2 -n 4 --method exact
rm -rf "$OUT"
