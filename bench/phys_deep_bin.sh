#!/usr/bin/env bash
# Issue 43 benchmark on the deep bin (examples/scenes/deep_bin.yaml): coverage per sensor type
# under the ideal pinhole and the physical model (optimize --by-type, greedy, n = 1..3), which
# type ranks first under each, and observe time with and without the second aperture (report.json
# timings.observe), the two models interleaved, RUNS times each. bench/RESULTS.md quotes it.
#
#   bench/phys_deep_bin.sh [build/vantage] [runs]
set -euo pipefail
cd "$(dirname "$0")/.."
vantage=${1:-build/vantage}
runs=${2:-2}
scene=examples/scenes/deep_bin.yaml
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "commit $(git rev-parse --short HEAD), $(nproc) cores, load: $(uptime | sed 's/.*load average: //')"
for run in $(seq "$runs"); do
  for model in ideal physical; do
    nice "$vantage" optimize "$scene" -n 3 --method greedy --by-type "--$model" \
      --out "$out/$model$run" > /dev/null
  done
done
python3 - "$out" "$runs" <<'PY'
import json, sys
out, runs = sys.argv[1], int(sys.argv[2])
reports = {m: [json.load(open(f"{out}/{m}{r}/report.json")) for r in range(1, runs + 1)]
           for m in ("ideal", "physical")}
first = {m: reports[m][0] for m in reports}
print("| type | ideal n = 1 / 2 / 3 | physical n = 1 / 2 / 3 |")
print("|---|---|---|")
rows = {}
for m, report in first.items():
    for t in report["by_type"]["types"]:
        rows.setdefault(t["type"], {})[m] = [b["coverage"] for b in t["best"]]
    rows.setdefault("mix", {})[m] = [b["coverage"] for b in report["by_type"]["mix"]]
fmt = lambda c: " / ".join(f"{100 * x:.2f}" for x in c) + " %"
for name, by in rows.items():
    print(f"| {name} | {fmt(by['ideal'])} | {fmt(by['physical'])} |")
for m, report in first.items():
    for b in report["by_type"]["mix"]:
        print(f"{m} n={b['n']}: best single type {b['best_single_type']} "
              f"{100 * b['best_single_coverage']:.2f} %, mix gains {100 * b['gain']:+.2f} points")
for t in first["physical"].get("sensor_model", {}).get("types", []):
    print("physical model:", json.dumps(t))
for m in reports:
    times = ", ".join(f"{r['timings']['observe']:.2f}" for r in reports[m])
    print(f"observe {m}: {times} s")
PY
