#!/usr/bin/env bash
# Distributed observe on one machine (issue 18, docs/distributed.md): ranks × threads for 1k and
# 10k candidates (examples/scenes/bin_picking_cell.yaml with its d415 population grown), the
# observe seconds (trace + gather), the cost per candidate and the bytes per gathered set.
# Prints a markdown table; the model for clusters is in bench/RESULTS.md. Needs Open MPI.
# Usage: bench/distributed.sh [COUNTS...]   (default: 1000 10000)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
VANTAGE=$(realpath "$BUILD/vantage")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
COUNTS=("$@")
[ ${#COUNTS[@]} -gt 0 ] || COUNTS=(1000 10000)
CORES=$(nproc)

echo "machine: $CORES cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo
echo "| candidates | ranks × threads | observe s | ms per candidate | rays M | gathered MiB | bytes per set | same .vis |"
echo "|---|---|---|---|---|---|---|---|"
for count in "${COUNTS[@]}"; do
  scene="$TMP/scene_$count.yaml"
  sed -e "s/count: 40 *$/count: $count/" examples/scenes/bin_picking_cell.yaml >"$scene"
  sed -i "s#file: \.\./meshes/#file: $(pwd)/examples/meshes/#" "$scene"
  for layout in "1 1" "1 $CORES" "2 1" "2 $((CORES / 2 > 0 ? CORES / 2 : 1))"; do
    read -r ranks threads <<<"$layout"
    out="$TMP/${count}_${ranks}x${threads}.vis"
    if [ "$ranks" -eq 1 ]; then
      "$VANTAGE" --threads "$threads" observe "$scene" --out "$out" >"$out.stdout" 2>"$out.log"
    else
      mpirun --bind-to none -np "$ranks" "$VANTAGE" --threads "$threads" observe "$scene" \
        --out "$out" >"$out.stdout" 2>"$out.log"
    fi
    seconds=$(awk '/^observe /{print $2}' "$out.stdout")
    rays=$(grep -o '[0-9.]* M rays traced' "$out.log" | head -1 | cut -d' ' -f1)
    gathered=$(grep -o 'gather: .*' "$out.log" | head -1 | sed -E 's/.* ([0-9.]+) MiB \(([0-9]+) bytes.*/\1 \2/')
    [ -n "$gathered" ] || gathered="- -"
    same="-"
    [ -f "$TMP/${count}_1x1.vis" ] && cmp -s "$out" "$TMP/${count}_1x1.vis" && same=yes
    total=$((count + 33))
    awk -v c="$total" -v s="$seconds" -v l="$ranks × $threads" -v r="$rays" -v g="$gathered" \
        -v same="$same" 'BEGIN { split(g, G, " ");
      printf "| %d | %s | %.3f | %.3f | %s | %s | %s | %s |\n", c, l, s, 1000 * s / c, r, G[1], G[2], same }'
  done
done
