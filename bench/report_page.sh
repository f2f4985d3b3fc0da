#!/usr/bin/env bash
# Writing the outputs of a scene of millions of triangles: one target plate and one occluder
# sphere of radius R m (tessellated to the 1 cm cell's chord error, so the triangles grow as R),
# seen by one camera. report.html embeds the meshes, simplified by vertex clustering to at most
# 300 000 triangles; that simplification dominates the outputs.
# Prints the scene's triangles, `vantage optimize` wall time, the pipeline's own total (its
# `timings` line), the rest (= writing the outputs) and peak memory (GNU time).
# Usage: bench/report_page.sh BIN OUT_DIR [R...=50 150 404]
set -uo pipefail
BIN=$(realpath "$1"); OUT=$(realpath -m "$2")
shift 2
RADII=("$@"); [ ${#RADII[@]} -eq 0 ] && RADII=(50 150 404)
mkdir -p "$OUT"
printf 'radius_m\ttriangles\twall_s\tpipeline_s\toutputs_s\tpeak_MiB\texit\n'
for r in "${RADII[@]}"; do
  cat >"$OUT/sphere$r.yaml" <<YAML
settings: {cell_size: 0.01, n: 1}
objects:
  - {name: plate, role: target, pose: {xyz: [0, 0, -1]}, plane: {size: [0.2, 0.2]}}
  - {name: ball, role: occluder, pose: {xyz: [0, 0, -$((r + 100))]}, sphere: {radius: $r}}
sensors:
  - {name: top, type: kinect_xbox_360, position: [0, 0, 0.5], orientation: {rpy: [0, 1.5708, 0]}}
YAML
  /usr/bin/time -f '%e %M' -o "$OUT/sphere$r.time" timeout 900 "$BIN" optimize \
    "$OUT/sphere$r.yaml" --out "$OUT/sphere$r" >"$OUT/sphere$r.out" 2>&1
  code=$?
  read -r wall kib <"$OUT/sphere$r.time" 2>/dev/null || { wall=?; kib=0; }
  triangles=$(grep -o '[0-9]* triangles' "$OUT/sphere$r.out" | head -1 | cut -d' ' -f1)
  total=$(grep -o 'total [0-9.]* s' "$OUT/sphere$r.out" | head -1 | cut -d' ' -f2)
  rest=$(python3 -c "print(f'{$wall - ${total:-0}:.2f}')" 2>/dev/null || echo ?)
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$r" "$triangles" "$wall" "$total" "$rest" \
    "$((kib / 1024))" "$code"
done
