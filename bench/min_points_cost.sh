#!/usr/bin/env bash
# The coverage cost of point density (docs/constraints.md, "Point density") on the shared
# costa2017 worlds: exact selection at N = 3 and 5 without it and with each --min-points given,
# each from one saved visibility matrix.
# Usage: bench/min_points_cost.sh BIN OUT_DIR [TIME_LIMIT=30] [POINTS...=5 20]
set -uo pipefail
BIN=$(realpath "$1"); OUT=$(realpath -m "$2"); LIMIT=${3:-30}
shift 3 2>/dev/null || shift $#
POINTS=("$@"); [ ${#POINTS[@]} -eq 0 ] && POINTS=(5 20)
cd "$(dirname "$0")/.."
COSTA=../shared/worlds/costa2017
GZ=(--model-path "$COSTA/media/models" --resource-path "$COSTA/media")
mkdir -p "$OUT"
printf 'world\tN\tmin_points\tcoverage\tupper_bound\toptimal\tseconds\n'
for world in bin_picking bin_picking_with_occlusions; do
  "$BIN" -q observe "$COSTA/worlds/$world.world" "${GZ[@]}" --out "$OUT/$world.vis" || exit 1
  for n in 3 5; do
    for p in none "${POINTS[@]}"; do
      flags=(); [ "$p" != none ] && flags=(--min-points "$p")
      dir="$OUT/${world}_n${n}_p$p"
      "$BIN" -q select "$OUT/$world.vis" -n "$n" --method exact --time-limit "$LIMIT" \
        "${flags[@]}" --out "$dir" >/dev/null || exit 1
      jq -r --arg w "$world" --arg p "$p" --arg n "$n" '.results[0] |
        [$w, $n, $p, (.coverage * 100 | . * 100 | round / 100), (.upper_bound * 100 | . * 100 | round / 100),
         .optimal, (.seconds * 100 | round / 100)] | @tsv' "$dir/report.json"
    done
  done
done
