#!/usr/bin/env bash
# Loading large URDF robots: a chain of N revolute joints, the same chain with each joint
# mimicking the one before (a mimic chain N long), and a star (N joints from one link), each as
# the robot of a one-camera YAML scene;
# `vantage optimize` wall time and peak memory (GNU time), the load dominating.
# Usage: bench/urdf_load.sh BIN OUT_DIR [N...=2000 20000]
set -uo pipefail
BIN=$(realpath "$1"); OUT=$(realpath -m "$2")
shift 2
SIZES=("$@"); [ ${#SIZES[@]} -eq 0 ] && SIZES=(2000 20000)
mkdir -p "$OUT"
printf 'robot\tjoints\tseconds\tpeak_MiB\texit\n'
for n in "${SIZES[@]}"; do
  for kind in chain mimic star; do
    python3 - "$OUT/$kind$n.urdf" "$n" "$kind" <<'PY'
import sys
path, n, kind = sys.argv[1], int(sys.argv[2]), sys.argv[3]
out = ['<?xml version="1.0"?>', '<robot name="r">', '<link name="l0"/>']
for i in range(1, n):
    mimic = f'<mimic joint="j{i-1}"/>' if kind == 'mimic' and i > 1 else ''
    parent = 0 if kind == 'star' else i - 1
    out.append(f'<link name="l{i}"/><joint name="j{i}" type="revolute"><parent link="l{parent}"/>'
               f'<child link="l{i}"/><axis xyz="0 0 1"/>'
               f'<limit lower="-1" upper="1" effort="1" velocity="1"/>{mimic}</joint>')
open(path, 'w').write('\n'.join(out + ['</robot>']))
PY
    cat >"$OUT/$kind$n.yaml" <<YAML
settings: {cell_size: 0.01, n: 1}
objects:
  - {name: plate, role: target, pose: {xyz: [0, 0, -1]}, plane: {size: [0.2, 0.2]}}
robots:
  - {name: arm, urdf: $kind$n.urdf}
sensors:
  - {name: top, type: kinect_xbox_360, position: [0, 0, 1], orientation: {rpy: [0, 1.5708, 0]}}
YAML
    /usr/bin/time -f '%e %M' -o "$OUT/$kind$n.time" timeout 900 "$BIN" -q optimize \
      "$OUT/$kind$n.yaml" --out "$OUT/$kind$n" >/dev/null 2>&1
    code=$?
    read -r seconds kib <"$OUT/$kind$n.time" 2>/dev/null || { seconds=?; kib=0; }
    printf '%s\t%s\t%s\t%s\t%s\n' "$kind" "$n" "$seconds" "$((kib / 1024))" "$code"
  done
done
