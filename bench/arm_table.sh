#!/usr/bin/env bash
# The arm benchmark of issue 45: bench/arm_table.sh BUILD OUT [VIEWS] [CYCLE_SECONDS].
# Writes a cell of about 50 k triangles (the example's arm, bin and parts; the table a wavy
# 158 x 158-quad height field: 49,928 triangles) with a `reach:` region of VIEWS poses and VIEWS
# joint-space views drawn over all six joints, then runs bench/arm_table (one JSON line).
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-/tmp/arm_bench}
VIEWS=${3:-1000}
CYCLE=${4:-10}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$OUT"
python3 - "$OUT/table.obj" <<'PY'
import math, sys
n = 158                       # quads per side: 2 n^2 = 49,928 triangles
with open(sys.argv[1], "w") as f:
    for j in range(n + 1):
        for i in range(n + 1):
            x = -0.5 + 1.6 * i / n
            y = -0.6 + 1.2 * j / n
            z = -0.004 - 0.004 * math.sin(31 * x) * math.cos(29 * y)   # at most 8 mm below 0
            f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            b, c, d = a + 1, a + n + 1, a + n + 2
            f.write(f"f {a} {b} {d}\nf {a} {d} {c}\n")
PY
sed -e "s|urdf: ../robots/ur5e_class_arm.urdf|urdf: $ROOT/examples/robots/ur5e_class_arm.urdf|" \
    -e "s|^  - name: table .*|  - name: table|" \
    -e "s|^    box: {size: \[1.6, 1.2, 0.04\]}|    mesh: {file: $OUT/table.obj}|" \
    -e "s|^    pose: {xyz: \[0.3, 0, -0.02\]}|    pose: {xyz: [0, 0, 0]}|" \
    -e "s|^    count: 120|    count: $VIEWS|" \
    -e "s|^    count: 60|    count: $VIEWS|" \
    -e "s|^      sampling: halton|      sampling: random|" \
    -e "s|^      joints: \[wrist_1_joint, wrist_2_joint, wrist_3_joint\]|      joints: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint, wrist_2_joint, wrist_3_joint]\n      allowed_collisions: [[shoulder_link, table]]|" \
    "$ROOT/examples/scenes/arm_wrist_camera.yaml" > "$OUT/scene.yaml"
"$BUILD/bench/arm_table" "$OUT/scene.yaml" "$CYCLE"
