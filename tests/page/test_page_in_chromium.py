#!/usr/bin/env python3
"""report.html in a real browser (issue 46), driven by a script over the DevTools protocol:
- the default view has every chosen camera inside the picture;
- a click on a candidate in the 3D view changes the coverage shown and the layout;
- the page's live coverage after scripted clicks (and its "best next camera", added) equals
  `vantage evaluate` of the same set, cell for cell;
- its per-part coverages add up to the whole, weighted by the parts' cells.
Usage: test_page_in_chromium.py VANTAGE_BINARY SCENE WORK_DIR [SCREENSHOT_DIR]
Exit 77 (skipped) without Chromium."""
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402


def run(args):
    done = subprocess.run(args, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        sys.exit(f"{' '.join(args)} exited {done.returncode}:\n{done.stderr}")
    return done.stdout


def shown(browser):
    """The coverage the page shows: its text, and the counts behind it."""
    return browser.evaluate(
        "(function () { var e = document.getElementById('whatif-coverage');"
        " return {text: e.textContent, covered: Number(e.getAttribute('data-covered')),"
        " cells: Number(e.getAttribute('data-cells'))}; })()")


def main():
    vantage, scene, work = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
    shots = sys.argv[4] if len(sys.argv) > 4 else None
    chromium = cdp.find_chromium()
    if chromium is None:
        print("Chromium not found (install Debian's chromium: scripts/install-deps.sh)")
        return 77
    os.makedirs(work, exist_ok=True)
    out = os.path.join(work, "out")
    run([vantage, "optimize", scene, "-n", "3", "--method", "greedy", "--by-type", "--out", out])
    report = json.load(open(os.path.join(out, "report.json")))
    names = [c["name"] for c in report["candidates"]]
    primary = report["results"][report["primary_result"]]
    failures = []

    def check(ok, what):
        print(("ok    " if ok else "FAIL  ") + what)
        if not ok:
            failures.append(what)

    browser = cdp.Browser(chromium, os.path.join(work, "profile"))
    try:
        browser.open("file://" + os.path.join(out, "report.html"))
        status = browser.wait_for(
            "(function () { var s = document.getElementById('vantage-status');"
            " return s && s.textContent !== 'loading' ? s.textContent : null; })()")
        check(status == "ok", f"page status is ok ({status})")
        if shots:
            browser.screenshot(os.path.join(shots, "page_default.png"))

        # optimize --by-type (issue 43): a row per type and n, and one per n for the mix.
        rows = browser.evaluate("document.querySelectorAll('#by-type-table tbody tr').length")
        by_type = report["by_type"]
        expected = sum(len(t["best"]) for t in by_type["types"]) + len(by_type["mix"])
        check(rows == expected, f"the by-type table shows each type and the mix ({rows} of {expected} rows)")

        # The ceiling and each part (issue 46): report.json's numbers, a row per part.
        ceiling = report["ceiling"]
        text = browser.evaluate("document.getElementById('ceiling-text').textContent")
        check(f"{100 * ceiling['coverage']:.2f} %" in text, f"the page gives the ceiling ({text[:80]})")
        rows = browser.evaluate("document.querySelectorAll('#parts-table tbody tr').length")
        check(rows == len(ceiling["parts"]), f"a row per target part ({rows} of {len(ceiling['parts'])})")

        # Framing: every chosen camera inside the default picture, and not under one of the
        # panels that stand over the view (the element drawn at its point is the 3D canvas).
        chosen = [names.index(n) for n in primary["sensors"]]
        for i in chosen:
            at = browser.evaluate(f"window.vantagePage.screenOf({i})")
            check(at["inside"], f"chosen camera {names[i]} is inside the default view ({at})")
            top = browser.evaluate(
                f"(function () {{ var e = document.elementFromPoint({at['x']}, {at['y']});"
                " return e ? (e.tagName === 'CANVAS' ? 'CANVAS' : e.id || e.className || e.tagName) : null; })()")
            check(top == "CANVAS", f"chosen camera {names[i]} is not under a panel (at its point: {top})")

        # The result itself: the page shows report.json's coverage.
        first = shown(browser)
        check(abs(first["covered"] / first["cells"] - primary["coverage"]) < 1e-12,
              f"the page shows the result's coverage ({first['text']}, report {primary['coverage']})")

        # Clicks: a candidate outside the layout whose marker stands clear of the others, then
        # one of the layout's.
        layout = browser.evaluate("window.vantagePage.layout()")
        places = browser.evaluate(
            "(function () { var out = []; for (var i = 0; i < %d; ++i) out.push(window.vantagePage.screenOf(i));"
            " return out; })()" % len(names))

        def clear_of_others(i):
            p = places[i]
            return p["inside"] and all(
                j == i or math.hypot(p["x"] - q["x"], p["y"] - q["y"]) > 12
                for j, q in enumerate(places))

        outside = [i for i in range(len(names)) if i not in layout and clear_of_others(i)]
        inside = [i for i in layout if clear_of_others(i)]
        check(bool(outside) and bool(inside), "candidates to click stand clear in the view")
        if outside and inside:
            added = outside[len(outside) // 2]
            browser.click(places[added]["x"], places[added]["y"])
            after_add = shown(browser)
            new_layout = browser.evaluate("window.vantagePage.layout()")
            check(added in new_layout, f"a click adds {names[added]} to the layout")
            check(after_add["text"] != first["text"] or after_add["covered"] >= first["covered"],
                  f"the number shown follows the click ({first['text']} -> {after_add['text']})")
            removed = inside[0]
            browser.click(places[removed]["x"], places[removed]["y"])
            after_remove = shown(browser)
            check(removed not in browser.evaluate("window.vantagePage.layout()"),
                  f"a click removes {names[removed]} from the layout")
            check(after_remove["text"] != after_add["text"],
                  f"the number shown changes ({after_add['text']} -> {after_remove['text']})")
        # The page's suggestion, added with its button.
        before = shown(browser)
        browser.evaluate("document.getElementById('whatif-add').click()")
        suggested = shown(browser)
        check(suggested["covered"] > before["covered"],
              f"adding the best next camera raises coverage ({before['text']} -> {suggested['text']})")
        layout = browser.evaluate("window.vantagePage.layout()")
        parts = browser.evaluate("window.vantagePage.parts()")
        check(sum(p["covered"] for p in parts) == suggested["covered"] and
              sum(p["cells"] for p in parts) == suggested["cells"],
              f"the {len(parts)} parts' covered cells and cells add up to the whole")
        if shots:
            browser.screenshot(os.path.join(shots, "page_whatif.png"))
    finally:
        browser.close()

    # `vantage evaluate` of the same set: the run's report with that layout as its result.
    constellation = dict(report)
    constellation["results"] = [{"method": "given", "sensors": [names[i] for i in layout]}]
    constellation["primary_result"] = 0
    path = os.path.join(work, "layout.json")
    with open(path, "w") as f:
        json.dump(constellation, f)
    evaluated = os.path.join(work, "evaluated")
    run([vantage, "evaluate", "-c", path, "--out", evaluated])
    expected = json.load(open(os.path.join(evaluated, "report.json")))["results"][0]["coverage"]
    page = suggested["covered"] / suggested["cells"]
    check(abs(page - expected) < 1e-12,
          f"the page's live coverage {page:.6f} equals vantage evaluate's {expected:.6f} "
          f"({len(layout)} sensors)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
