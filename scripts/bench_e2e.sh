#!/usr/bin/env bash
# End-to-end benchmark (issue #6): for each world, vantage optimize's observe time against the
# ray-casting limit measured in the same run (bench/ray_limit: every pixel, Embree packets, all
# cores, nothing else), then a scaling table. Prints markdown tables; pass --quick for the worlds
# table only. Needs a Release build in build/ with benchmarks (the default). VANTAGE=path runs
# another vantage binary against the same limit loop (old against new); VANTAGE_PREFIX="chrt -f 50"
# runs each vantage command under that prefix (on a machine shared with others, a real-time class
# gives the command both cores as on an idle machine; the limit loop runs as before).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
VANTAGE=${VANTAGE:-$BUILD/vantage}
read -r -a PREFIX <<< "${VANTAGE_PREFIX:-}"
LIMIT="$BUILD/bench/ray_limit"
SHARED=${SHARED:-../shared/worlds/costa2017}
GZ=(--model-path "$SHARED/media/models" --resource-path "$SHARED/media")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
PY=/usr/bin/python3

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), threads: ${THREADS:-all}"
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown), vantage: $VANTAGE${VANTAGE_PREFIX:+ under $VANTAGE_PREFIX}"
echo

run_world() {  # name scene [extra args...]
  local name=$1 scene=$2
  shift 2
  local out="$TMP/$name"
  local start end
  start=$(date +%s.%N)
  /usr/bin/time -f "%M" -o "$TMP/$name.rss" ${PREFIX[@]+"${PREFIX[@]}"} "$VANTAGE" -q optimize "$scene" "$@" --method greedy --out "$out" >/dev/null
  end=$(date +%s.%N)
  "$LIMIT" "$scene" "$@" > "$TMP/$name.limit"
  $PY - "$name" "$out/report.json" "$TMP/$name.limit" "$start" "$end" "$TMP/$name.rss" <<'PYEOF'
import json, sys
name, report, limit, start, end, rss = sys.argv[1:]
r = json.load(open(report)); l = json.loads(open(limit).read())
pixels = sum(c["width"] * c["height"] for c in r["candidates"])
rays = sum(c["rays_traced"] for c in r["candidates"])
obs = r["timings"]["observe"]
t = r["timings"]
wall = float(end) - float(start)
# Everything but observe and selection: load + reference + what the pipeline's total leaves out
# (process start, writing, exit): at most observe is issue 47's target.
around = t["load"] + t["reference"] + max(0.0, wall - t["total"])
assert l["culled_rays"] == rays, (l["culled_rays"], rays)  # the limit traced the same rays
print(f"| {name} | {len(r['candidates'])} | {pixels/1e6:.1f} M | {rays/1e6:.2f} M | {pixels/max(rays,1):.1f}x | "
      f"{obs:.3f} | {rays/obs/1e6:.1f} M | {l['culled_rays_per_second']/1e6:.1f} M | "
      f"{l['all_pixels_rays_per_second']/1e6:.1f} M | {obs/l['culled_seconds']:.2f} | "
      f"{obs/l['same_rays_seconds']:.2f} ({l['segments']/1e6:.2f} M segments) | "
      f"{wall:.3f} | {wall/obs:.2f} | {around:.3f} {'<=' if around <= obs else '>'} observe | "
      f"{int(open(rss).read().split()[-1])/1024:.0f} |")
PYEOF
}

echo "| world | candidates | pixels | rays traced | culling | observe s | rays/s | limit rays/s (same rays) | limit rays/s (every pixel) | ratio | ratio, same rays incl. segments | end-to-end s | end-to-end / observe | load + reference + start and writing s | peak MiB |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
run_world example examples/scenes/bin_picking_cell.yaml
run_world bin_picking "$SHARED/worlds/bin_picking.world" "${GZ[@]}"
run_world bin_picking_with_occlusions "$SHARED/worlds/bin_picking_with_occlusions.world" "${GZ[@]}"
run_world multi_bin_picking_450 bench/worlds/multi_bin_picking.world "${GZ[@]}"
echo
echo "ratio = vantage observe time / the limit loop's time for the same primary rays (the culled pixels)."
echo "ratio, same rays incl. segments = the same over the limit loop casting every ray observe casts: the"
echo "primary rays and, under the physical sensor model, the second aperture's occlusion segments (none"
echo "on the Gazebo worlds, read as the ideal pinhole); issue 47's <= 1.0 is against this one. Observe's"
echo "time includes building the BVH, the limit loop's does not (ray_limit's rays_build_seconds)."
echo "end-to-end / observe: the whole command's wall time over observe's own (target <= 1.3, issue 47)."
echo "load + reference + start and writing: report.json's load and reference, and the wall time outside"
echo "its total (process start, writing the outputs, exit); target <= observe on every world (issue 47)."
[ "${1:-}" = "--quick" ] && exit 0

echo
echo "Scaling (examples/scenes/bin_picking_cell.yaml, d415 population count and cell size varied):"
echo
echo "| candidates | cell mm | reference voxels | rays traced | observe s | select s (greedy) | end-to-end s | peak MiB |"
echo "|---|---|---|---|---|---|---|---|"
for count in 100 1000 10000; do
  for cell in 0.01 0.005 0.0025; do
    scene="$TMP/scale_${count}_${cell}.yaml"
    sed -e "s/count: 40 *$/count: $count/" -e "s/cell_size: 0.005/cell_size: $cell/" \
        examples/scenes/bin_picking_cell.yaml > "$scene"
    mkdir -p "$TMP/meshes" && cp examples/meshes/* "$TMP/meshes/" 2>/dev/null || true
    (cd "$TMP" && mkdir -p scenes && cp "$scene" scenes/s.yaml)
    start=$(date +%s.%N)
    /usr/bin/time -f "%M" -o "$TMP/rss" "$VANTAGE" -q optimize "$TMP/scenes/s.yaml" --method greedy --out "$TMP/scale_out" >/dev/null
    end=$(date +%s.%N)
    $PY - "$TMP/scale_out/report.json" "$start" "$end" "$TMP/rss" "$cell" <<'PYEOF'
import json, sys
report, start, end, rss, cell = sys.argv[1:]
r = json.load(open(report))
rays = sum(c["rays_traced"] for c in r["candidates"])
sel = sum(x["seconds"] for x in r["results"])
print(f"| {len(r['candidates'])} | {float(cell)*1000:g} | {r['reference_voxels']} | {rays/1e6:.2f} M | "
      f"{r['timings']['observe']:.3f} | {sel:.3f} | {float(end)-float(start):.3f} | {int(open(rss).read().split()[-1])/1024:.0f} |")
PYEOF
  done
done
