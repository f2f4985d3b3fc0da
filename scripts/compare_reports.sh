#!/usr/bin/env bash
# Runs a fixed set of vantage commands with binary $1 into folder $2 (one subfolder per case), so
# that two binaries (before and after a refactor) can be compared with `diff -r` on the
# normalised report.json files (timings and per-result seconds removed).
# Usage: scripts/compare_reports.sh BIN OUT_DIR
set -uo pipefail
BIN=$(realpath "$1"); OUT=$(realpath -m "$2")
cd "$(dirname "$0")/.."
COSTA=../shared/worlds/costa2017
GZ=(--model-path "$COSTA/media/models" --resource-path "$COSTA/media")
EX=examples/scenes/bin_picking_cell.yaml
ST=examples/scenes/bin_picking_states.yaml
mkdir -p "$OUT"
run() {  # name, args...
  local name=$1; shift
  "$BIN" "$@" --out "$OUT/$name" >"$OUT/$name.stdout" 2>"$OUT/$name.stderr"
  echo "$?" >"$OUT/$name.rc"
}
run example optimize "$EX"
run example_greedy_refine optimize "$EX" -n 3 --method greedy --refine
run example_k2 optimize "$EX" -n 3 --k 2
run example_goal optimize "$EX" --goal 0.6
run example_budget optimize "$EX" --budget 2000
run example_incidence optimize "$EX" -n 3 --max-incidence 60
run example_incidence_refine optimize "$EX" -n 3 --method greedy --refine --max-incidence 60
run states_mean optimize "$ST"
run states_min optimize "$ST" --over-states min -n 2
run bin_picking optimize "$COSTA/worlds/bin_picking.world" "${GZ[@]}"
run bin_picking_n3 optimize "$COSTA/worlds/bin_picking.world" "${GZ[@]}" -n 3 --method local
run occlusions optimize "$COSTA/worlds/bin_picking_with_occlusions.world" "${GZ[@]}"
"$BIN" observe "$EX" --out "$OUT/example.vis" >/dev/null 2>&1
run select_vis select "$OUT/example.vis" -n 2
run evaluate evaluate "$EX" --constellation "$OUT/example/report.json"
run evaluate_incidence evaluate "$EX" --constellation "$OUT/example/report.json" --max-incidence 20
for f in "$OUT"/*/report.json; do
  jq -S 'del(.timings, .version) | walk(if type == "object" then del(.seconds) else . end)' "$f" \
    >"${f%.json}.normalised.json"
done
