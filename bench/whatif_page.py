#!/usr/bin/env python3
"""report.html's what-if at the size issue 46 names: 450 candidates x about 20 000 cells.
Writes a scene (a 0.26 m target box on a table, 450 random candidates above it), runs
`vantage optimize -n 3 --method greedy`, then opens the page in headless Chromium (tests/page/cdp.py)
and prints: the page's size, its what-if data's size, the time until the page's script has run,
and the time of one layout change (a click's work: scoring, voxel colours, markers, the panel and
its best-next search), the median of 10.
Usage: bench/whatif_page.py VANTAGE_BINARY OUT_DIR"""
import json
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "page"))
import cdp  # noqa: E402

SCENE = """settings: {cell_size: 0.005, n: 3, method: greedy, seed: 1, observation_point: [0, 0, 0.9]}
objects:
  - {name: table, role: occluder, box: {size: [1.2, 1.2, 0.04]}, pose: {xyz: [0, 0, 0.75]}}
  - {name: part, role: target, box: {size: [0.26, 0.26, 0.26]}, pose: {xyz: [0, 0, 0.9]}}
populations:
  - {name: above, type: kinect_xbox_360, distribution: random, count: 450,
     box: {size: [2.0, 2.0, 0.6]}, pose: {xyz: [0, 0, 1.9]}}
"""


def main():
    vantage, out = sys.argv[1], os.path.abspath(sys.argv[2])
    os.makedirs(out, exist_ok=True)
    scene = os.path.join(out, "whatif450.yaml")
    with open(scene, "w") as f:
        f.write(SCENE)
    start = time.time()
    subprocess.run([vantage, "optimize", scene, "--out", os.path.join(out, "run")], check=True,
                   stdout=subprocess.DEVNULL)
    print(f"optimize: {time.time() - start:.1f} s")
    page = os.path.join(out, "run", "report.html")
    report = json.load(open(os.path.join(out, "run", "report.json")))
    html = open(page, encoding="utf-8").read()
    begin = html.index('<script id="vantage-data" type="application/json">')
    data = json.loads(html[html.index(">", begin) + 1:html.index("</script>", begin)])
    sets = len(data["whatif"]["sets"]) if data.get("whatif") else 0
    print(f"candidates {len(report['candidates'])}, cells {report['reference_voxels']}")
    print(f"report.html {os.path.getsize(page) / 1e6:.2f} MB, of which what-if sets {sets / 1e6:.2f} MB")
    browser = cdp.Browser(cdp.find_chromium(), os.path.join(out, "profile"))
    try:
        start = time.time()
        browser.open("file://" + page)
        status = browser.wait_for(
            "(function () { var s = document.getElementById('vantage-status');"
            " return s && s.textContent !== 'loading' ? s.textContent : null; })()", timeout=120)
        print(f"page status {status} after {time.time() - start:.2f} s")
        times = []
        for _ in range(10):
            times.append(browser.evaluate(
                "(function () { var t = performance.now();"
                " document.getElementById('whatif-add').click();"
                " return performance.now() - t; })()"))
        print(f"one layout change (add the best next camera): median {statistics.median(times):.1f} ms,"
              f" max {max(times):.1f} ms")
    finally:
        browser.close()


if __name__ == "__main__":
    main()
