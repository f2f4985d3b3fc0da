#!/usr/bin/env python3
"""Peak memory of Visibility.matrix on a 450 x ~20,000 candidates x cells matrix (issue 17).

Observes bench/worlds/multi_bin_picking.world (450 candidates, 20,091 reference cells) once and
saves the .vis file, then, in a fresh interpreter, loads it and builds the SciPy matrix,
reporting the process's resident memory before and the peak while building (VmHWM, reset just
before through /proc/self/clear_refs), the matrix's own bytes (data + indices + indptr) and
tracemalloc's peak of the allocations the build made (NumPy's arrays included). A build that
copied the index lists twice would peak at about twice the index bytes above the matrix.

    PYTHONPATH=build/python python3 bench/python_matrix_memory.py [--shared ../shared]
"""

import argparse
import os
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
MiB = 1024.0 * 1024.0


def status_kib(field):
    with open("/proc/self/status", encoding="ascii") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    raise KeyError(field)


def measure(vis_path):
    import tracemalloc

    import numpy  # noqa: F401  (imported before the baseline)
    import scipy.sparse  # noqa: F401

    import vantage

    vis = vantage.load_visibility(vis_path)
    rss_before = status_kib("VmRSS")
    with open("/proc/self/clear_refs", "w", encoding="ascii") as f:
        f.write("5")  # resets VmHWM to the current RSS
    tracemalloc.start()
    m = vis.matrix
    _, traced_peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    hwm = status_kib("VmHWM")
    own = m.data.nbytes + m.indices.nbytes + m.indptr.nbytes
    print(f"matrix {m.shape[0]} x {m.shape[1]}, {m.nnz} ones ({100 * m.nnz / (m.shape[0] * m.shape[1]):.2f} % dense), "
          f"index dtype {m.indices.dtype}")
    print(f"matrix bytes: data {m.data.nbytes / MiB:.1f} MiB + indices {m.indices.nbytes / MiB:.1f} MiB"
          f" + indptr {m.indptr.nbytes / MiB:.3f} MiB = {own / MiB:.1f} MiB")
    print(f"tracemalloc peak during the build: {traced_peak / MiB:.1f} MiB "
          f"({traced_peak / own:.2f} x the matrix)")
    print(f"RSS before {rss_before / 1024:.1f} MiB, peak while building {hwm / 1024:.1f} MiB: "
          f"+{(hwm - rss_before) / 1024:.1f} MiB")
    print(f"peak RSS of the process {status_kib('VmHWM') / 1024:.1f} MiB")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shared", default=ROOT.parent / "shared", type=pathlib.Path)
    parser.add_argument("--measure", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure:
        measure(args.measure)
        return
    import vantage

    media = args.shared / "worlds" / "costa2017" / "media"
    with tempfile.TemporaryDirectory() as tmp:
        vis_path = os.path.join(tmp, "multi.vis")
        problem = vantage.load(ROOT / "bench" / "worlds" / "multi_bin_picking.world",
                               model_path=media / "models", resource_path=media)
        problem.observe().save(vis_path)
        print(f"observed and saved; peak RSS of that process {status_kib('VmHWM') / 1024:.1f} MiB")
        subprocess.run([sys.executable, __file__, "--measure", vis_path], check=True)


if __name__ == "__main__":
    main()
