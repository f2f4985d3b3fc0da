#!/usr/bin/env python3
"""Coverage versus the number of sensors for every selection method, from one ray casting.

Loads the bundled example (or the scene given), observes it once, selects N = 1..6 sensors with
each method and plots coverage against N, with the exact solver's proven upper bound as a band
(between what exact found and what no N sensors can beat). Writes a PNG (matplotlib) and prints
the table.

    PYTHONPATH=build/python python3 examples/python/coverage_curve.py [SCENE] [--out curve.png]
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402

import vantage  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
METHODS = ["best", "ransac", "greedy", "local", "exact"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=ROOT / "examples/scenes/bin_picking_cell.yaml")
    parser.add_argument("--out", default="coverage_curve.png", help="PNG to write")
    parser.add_argument("--max-n", type=int, default=6)
    parser.add_argument("--time-limit", type=float, default=20, help="seconds per exact solve")
    args = parser.parse_args()

    problem = vantage.load(args.scene)
    vis = problem.observe()
    print(f"{problem.source}: {vis.matrix.shape[0]} candidates, {vis.matrix.shape[1]} reference "
          f"cells of {vis.cell_size} m")
    ns = list(range(1, args.max_n + 1))
    curves = {m: [vis.select(n=n, method=m, time_limit=args.time_limit) for n in ns]
              for m in METHODS}

    print("   n" + "".join(f"{m:>9}" for m in METHODS) + "    bound")
    for i, n in enumerate(ns):
        row = "".join(f"{100 * curves[m][i].coverage:9.2f}" for m in METHODS)
        exact = curves["exact"][i]
        mark = "*" if exact.optimal else ""
        print(f"{n:4d}{row}{100 * exact.upper_bound:9.2f}{mark}")
    print("(* = proven optimal; best always chooses one sensor)")

    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=120)
    exact = curves["exact"]
    # The band: from what exact found up to its proven bound (zero width where proven optimal,
    # so the bound is also drawn as a wide translucent stroke to stay visible).
    bound = [100 * s.upper_bound for s in exact]
    ax.fill_between(ns, [100 * s.coverage for s in exact], bound, color="tab:purple", alpha=0.25,
                    label="exact: found .. proven bound")
    ax.plot(ns, bound, color="tab:purple", alpha=0.2, linewidth=9, solid_capstyle="round",
            label="proven upper bound")
    # The colours of report.html and render (kMethodColors in vantage/visualize.hpp: tab10).
    styles = {"best": ("tab:blue", "s", ":"), "ransac": ("tab:orange", "^", "-"),
              "greedy": ("tab:green", "o", "-"), "local": ("tab:red", "D", "--"),
              "exact": ("tab:purple", "*", "-")}
    for m in METHODS:
        color, marker, line = styles[m]
        ax.plot(ns, [100 * s.coverage for s in curves[m]], line, color=color, marker=marker,
                label="best (one sensor)" if m == "best" else m,
                markersize=7 if m == "exact" else 5)
    ax.set_xlabel("number of sensors N")
    ax.set_ylabel("coverage of the targets' surface cells [%]")
    ax.set_title(f"{pathlib.Path(problem.source).name}: {vis.matrix.shape[0]} candidates, "
                 f"{vis.matrix.shape[1]} cells of {1000 * vis.cell_size:g} mm")
    ax.set_xticks(ns)
    ax.grid(alpha=0.3)
    ax.legend(loc="center right", framealpha=0.9)
    fig.tight_layout()
    fig.savefig(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
