#!/usr/bin/env bash
# Runs the bundled example and lists what it wrote (used by `make run`).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
EXAMPLE=${EXAMPLE:-examples/scenes/bin_picking_cell.yaml}
OUT=${OUT:-out/example}
echo "run: $BUILD/vantage optimize $EXAMPLE --out $OUT"
echo
start=$(date +%s)
"./$BUILD/vantage" optimize "$EXAMPLE" --out "$OUT"
echo
echo "run: done in $(( $(date +%s) - start )) s. The tool is $BUILD/vantage (\`make install\` puts it"
echo "on the PATH); the results are in $OUT/:"
ls -l "$OUT"
echo
echo "Open $OUT/report.html in a browser for the 3D view and the coverage curve, or picture the"
echo "result without one: $BUILD/vantage render $OUT --png $OUT/view.png"
