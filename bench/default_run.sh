#!/usr/bin/env bash
# The default run on the stand-in of the paper's largest world (issue 47): `vantage optimize`
# with no options on bench/worlds/multi_bin_picking_1e6.world (450 candidates, 211 k triangles,
# its plugin asking N = 10 and 10^6 RANSAC iterations). Prints wall time, the stages, and exact's
# gap (bound - coverage, in points) per N. Targets: <= 15 s, every gap <= 0.5 point.
# Usage: bench/default_run.sh [WORLD]  (a Release build in build/)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
SHARED=${SHARED:-../shared/worlds/costa2017}
WORLD=${1:-bench/worlds/multi_bin_picking_1e6.world}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
echo "commit $(git rev-parse --short HEAD), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)"
start=$(date +%s.%N)
/usr/bin/time -f "%U %S %M" -o "$TMP/time" "$BUILD/vantage" -q optimize "$WORLD" \
  --model-path "$SHARED/media/models" --resource-path "$SHARED/media" --out "$TMP/out" >/dev/null
end=$(date +%s.%N)
python3 - "$TMP/out/report.json" "$start" "$end" "$TMP/time" <<'PYEOF'
import json, sys
report, start, end, tfile = sys.argv[1:]
r = json.load(open(report))
user, system, rss = open(tfile).read().split()
t = r["timings"]
print(f"wall {float(end) - float(start):.2f} s (cpu {float(user) + float(system):.2f} s, peak {int(rss) / 1024:.0f} MiB); "
      + ", ".join(f"{k} {v:.2f}" for k, v in t.items()))
ransac = {x["n"]: x["seconds"] for x in r["results"] if x["method"] == "ransac"}
worst = 0.0
for x in r["results"]:
    if x["method"] != "exact":
        continue
    gap = 100 * (x["upper_bound"] - x["coverage"])
    worst = max(worst, gap)
    print(f"N={x['n']:2d} exact {100 * x['coverage']:.2f} % bound {100 * x['upper_bound']:.2f} % "
          f"gap {gap:.2f} pt{' (proven)' if x.get('proven_optimal') else ''}; ransac {ransac.get(x['n'], 0):.2f} s")
print(f"worst gap {worst:.2f} pt (target <= 0.5)")
PYEOF
