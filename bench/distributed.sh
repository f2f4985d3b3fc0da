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
echo "| candidates | ranks × threads | observe s | CPU s (all ranks) | CPU ms per candidate |" \
  "rays M | gathered MiB | bytes per set | same .vis |"
echo "|---|---|---|---|---|---|---|---|---|"
for count in "${COUNTS[@]}"; do
  scene="$TMP/scene_$count.yaml"
  sed -e "s/count: 40 *$/count: $count/" examples/scenes/bin_picking_cell.yaml >"$scene"
  sed -i "s#file: \.\./meshes/#file: $(pwd)/examples/meshes/#" "$scene"
  layouts=("1 1" "1 $CORES" "2 1")
  [ "$CORES" -ge 4 ] && layouts+=("2 $((CORES / 2))")
  for layout in "${layouts[@]}"; do
    read -r ranks threads <<<"$layout"
    out="$TMP/${count}_${ranks}x${threads}.vis"
    launch=()
    [ "$ranks" -eq 1 ] || launch=(mpirun --bind-to none -np "$ranks")
    # CPU seconds of the whole command, every rank included (mpirun's children).
    /usr/bin/time -f "%U %S" -o "$out.cpu" "${launch[@]}" "$VANTAGE" --threads "$threads" \
      observe "$scene" --out "$out" >"$out.stdout" 2>"$out.log"
    seconds=$(awk '/^observe /{print $2}' "$out.stdout")
    rays=$(grep -o '[0-9.]* M rays traced' "$out.log" | head -1 | cut -d' ' -f1 || true)
    gathered=$(grep -o 'gather: .*' "$out.log" | head -1 |
      sed -E 's/.* ([0-9.]+) MiB \(([0-9]+) bytes.*/\1 \2/' || true)
    [ -n "$gathered" ] || gathered="- -"
    same="-"
    [ -f "$TMP/${count}_1x1.vis" ] && cmp -s "$out" "$TMP/${count}_1x1.vis" && same=yes
    total=$((count + 33))
    cpu=$(awk '{print $1 + $2}' "$out.cpu")
    awk -v c="$total" -v s="$seconds" -v cpu="$cpu" -v l="$ranks × $threads" -v r="$rays" \
        -v g="$gathered" -v same="$same" 'BEGIN { split(g, G, " ");
      printf "| %d | %s | %.3f | %.2f | %.2f | %s | %s | %s | %s |\n", c, l, s, cpu,
             1000 * cpu / c, r, G[1], G[2], same }'
  done
done
