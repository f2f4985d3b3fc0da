#!/usr/bin/env bash
# Runs the bundled example and lists what it wrote (used by `make run`).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
EXAMPLE=${EXAMPLE:-examples/scenes/bin_picking_cell.yaml}
OUT=${OUT:-out/example}
"./$BUILD/vantage" optimize "$EXAMPLE" --out "$OUT"
echo
echo "wrote:"
ls -l "$OUT"
