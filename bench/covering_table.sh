#!/usr/bin/env bash
# The "Set cover on covering designs" table of bench/RESULTS.md: the fewest sensors reaching the
# whole of R (`--goal 1 --method exact`) on classic set-cover instances of known optimum, built
# by bench/covering_instances.py and loaded as .vis files. One row per instance: instance, size,
# sensors, proven lower bound, seconds. Run it with two binaries (before and after a change) to
# set them side by side.
#
# Usage: bench/covering_table.sh BIN [TIME_LIMIT]   (default 20 s)
set -euo pipefail
BIN=$(realpath "$1")
LIMIT=${2:-20}
cd "$(dirname "$0")/.."
DIR=$(mktemp -d)
trap 'rm -rf "$DIR"' EXIT
echo "| instance | candidates × cells | optimum | sensors | proven ≥ | seconds |"
echo "|---|---|---|---|---|---|"
while read -r name optimum args; do
  python3 bench/covering_instances.py $args "$DIR/$name.vis" >/dev/null
  size=$(python3 -c "import sys; sys.path.insert(0, 'tests/python'); import vis_format as v; \
f = v.read_vis('$DIR/$name.vis'); print(f'{len(f.candidates)} × {len(f.keys)}')")
  if ! "$BIN" -q select "$DIR/$name.vis" --goal 1 --method exact --time-limit "$LIMIT" \
       --out "$DIR/r" >/dev/null 2>&1; then
    echo "| $name | $size | $optimum | failed | | |"
    continue
  fi
  jq -r --arg name "$name" --arg size "$size" --arg opt "$optimum" '.results[] |
    "| \($name) | \($size) | \($opt) | \(.n) | \(.n_lower_bound)\(if .optimal then " (optimal)" else "" end) | \(.seconds * 10 | round / 10) |"' \
    "$DIR/r/report.json"
done <<'LIST'
sts27 18 sts 27
sts45 30 sts 45
sts81 61 sts 81
cyc6 60 cyc 6
clr10 25 clr 10
rand500x50 ? random 500 50 0.1 1
LIST
