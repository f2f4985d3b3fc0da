#!/usr/bin/env python3
"""Reads the libFuzzer logs of one target's campaigns (oldest first) and says whether its coverage
has reached the plateau of fuzz/README.md: fewer than 0.5 % new edges (libFuzzer's `cov:`) in the
second half of the executions. The half is counted in executions, not seconds, so that the verdict
does not depend on the load of the machine; the executions of several logs are added up (a
campaign that continues from the merged corpus of the one before continues its count). The
features (`ft:`, edges and their hit-count buckets) are printed beside the edges, and
`--measure ft` judges them instead (the rule of sessions 5 to 19, see fuzz/README.md).

    python3 fuzz/plateau.py fuzz/build/pipeline.log
    python3 fuzz/plateau.py --threshold 0.5 run1.log run2.log
    python3 fuzz/plateau.py --doublings run1.log run2.log   # the gain in each doubling too

Prints one line per log and a verdict; exits 0 on a plateau, 1 otherwise, 2 on a log without
status lines.
"""
import argparse
import re
import sys

STATUS = re.compile(r"^#(\d+)\s+(\w+)\s+cov: (\d+) ft: (\d+)(?: corp: (\d+)/(\S+))?")
DONE = re.compile(r"^Done (\d+) runs in (\d+) second")


def read_log(path):
    """(points, seconds): points are (executions, cov, ft, corpus entries, corpus size, kind)."""
    points = []
    seconds = None
    with open(path, encoding="utf-8", errors="replace") as log:
        for line in log:
            match = STATUS.match(line)
            if match:
                points.append((int(match[1]), int(match[3]), int(match[4]),
                               int(match[5] or 0), match[6] or "", match[2]))
                continue
            match = DONE.match(line)
            if match:
                seconds = int(match[2])
    return points, seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("logs", nargs="+")
    parser.add_argument("--threshold", type=float, default=0.5,
                        help="percent of the final edges (or features) (default 0.5)")
    parser.add_argument("--measure", choices=("cov", "ft"), default="cov",
                        help="judge the edges (cov, default) or the features (ft)")
    parser.add_argument("--doublings", action="store_true",
                        help="also print the gain in each doubling of the executions")
    args = parser.parse_args()

    timeline = []  # (cumulative executions, cov, ft)
    offset = 0
    for path in args.logs:
        points, seconds = read_log(path)
        if not points:
            print(f"{path}: no libFuzzer status line", file=sys.stderr)
            return 2
        start = next((p for p in points if p[5] == "INITED"), points[0])
        end = points[-1]
        rate = f", {end[0] / seconds:.0f}/s" if seconds else ""
        print(f"{path}: {seconds if seconds is not None else '?'} s, {end[0]} executions{rate}; "
              f"cov/ft {start[1]}/{start[2]} at start (INITED), {end[1]}/{end[2]} at the end; "
              f"corpus {end[3]} entries, {end[4]}")
        timeline += [(offset + p[0], p[1], p[2]) for p in points]
        offset += end[0]

    def at(executions):
        """The last status at or before `executions` (the first one if none is)."""
        before = [p for p in timeline if p[0] <= executions]
        return before[-1] if before else timeline[0]

    def gain(first, last, column):
        return last[column] - first[column], 100.0 * (last[column] - first[column]) / last[column]

    total = timeline[-1][0]
    if args.doublings:
        executions = 1000
        while executions < total:
            upto = min(2 * executions, total)
            first, last = at(executions), at(upto)
            (cov, cov_pc), (ft, ft_pc) = gain(first, last, 1), gain(first, last, 2)
            print(f"  {executions:>9} to {upto:>9} executions: cov +{cov} ({cov_pc:.2f} %), "
                  f"ft +{ft} ({ft_pc:.2f} %)")
            executions = upto
    half = total / 2
    middle, end = at(half), timeline[-1]
    (cov, cov_pc), (ft, ft_pc) = gain(middle, end, 1), gain(middle, end, 2)
    judged = cov_pc if args.measure == "cov" else ft_pc
    plateau = judged < args.threshold
    print(f"second half ({half:.0f} to {total} executions): cov {middle[1]} -> {end[1]} "
          f"(+{cov}, {cov_pc:.2f} %), ft {middle[2]} -> {end[2]} (+{ft}, {ft_pc:.2f} %): "
          f"{'plateau' if plateau else 'still growing'} "
          f"({args.measure}, threshold {args.threshold} %)")
    return 0 if plateau else 1


if __name__ == "__main__":
    sys.exit(main())
