#!/usr/bin/env bash
# The coverage cost of each installation constraint (docs/constraints.md) on the shared costa2017
# worlds: exact selection at N = 3 and 5 without constraints, with projector interference
# (--interference true; it is opt-in, docs/constraints.md) and with calibration connectivity,
# each from one saved visibility matrix.
# Usage: bench/constraints_cost.sh BIN OUT_DIR [CALIBRATION_CELLS=20] [TIME_LIMIT=30]
set -uo pipefail
BIN=$(realpath "$1"); OUT=$(realpath -m "$2"); CELLS=${3:-20}; LIMIT=${4:-30}
cd "$(dirname "$0")/.."
COSTA=../shared/worlds/costa2017
GZ=(--model-path "$COSTA/media/models" --resource-path "$COSTA/media")
mkdir -p "$OUT"
printf 'world\tN\tconstraint\tcoverage\tupper_bound\toptimal\tseconds\n'
for world in bin_picking bin_picking_with_occlusions; do
  "$BIN" -q observe "$COSTA/worlds/$world.world" "${GZ[@]}" --out "$OUT/$world.vis" || exit 1
  for n in 3 5; do
    for case in none interference calibration; do
      case $case in
        none) flags=(--interference false) ;;
        interference) flags=(--interference true) ;;
        calibration) flags=(--interference false --calibration-overlap "$CELLS") ;;
      esac
      dir="$OUT/${world}_n${n}_$case"
      "$BIN" -q select "$OUT/$world.vis" -n "$n" --method exact --time-limit "$LIMIT" \
        "${flags[@]}" --out "$dir" >/dev/null || exit 1
      jq -r --arg w "$world" --arg c "$case" --arg n "$n" '.results[0] |
        [$w, $n, $c, (.coverage * 100 | . * 100 | round / 100), (.upper_bound * 100 | . * 100 | round / 100),
         .optimal, (.seconds * 100 | round / 100)] | @tsv' "$dir/report.json"
    done
  done
done
