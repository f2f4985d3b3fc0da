#!/usr/bin/env python3
"""The what-if page of a big run in headless Chromium (issue 46): load time, best-next clicks.
Usage: bench/page_whatif.py OUT  (OUT from `vantage optimize ... --out OUT`). Writes /tmp/big_page.png."""
import os, sys, time, json
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "page"))
import cdp
out = sys.argv[1]
chromium = cdp.find_chromium()
b = cdp.Browser(chromium, "/tmp/page_whatif_profile")
try:
    t0 = time.time()
    b.open("file://" + os.path.abspath(out) + "/report.html")
    st = b.wait_for("(function () { var s = document.getElementById('vantage-status'); return s && s.textContent !== 'loading' ? s.textContent : null; })()")
    t1 = time.time()
    print("status", st, "load+parse+first render %.2f s" % (t1 - t0))
    for k in range(3):
        t = time.time()
        b.evaluate("document.getElementById('whatif-add').click()")
        e = b.evaluate("document.getElementById('whatif-coverage').textContent")
        print("best-next add %d: %.3f s -> %s" % (k, time.time() - t, e))
    t = time.time()
    n = b.evaluate("window.vantagePage.layout().length")
    print("layout", n)
    b.screenshot("/tmp/big_page.png")
finally:
    b.close()
