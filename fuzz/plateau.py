#!/usr/bin/env python3
"""Reads the libFuzzer logs of one target's campaigns (oldest first) and says whether its coverage
has reached the plateau of fuzz/README.md: fewer than 0.5 % new features (libFuzzer's `ft:`) in
the second half of the executions. The half is counted in executions, not seconds, so that the
verdict does not depend on the load of the machine; the executions of several logs are added up
(a campaign that continues from the merged corpus of the one before continues its count).

    python3 fuzz/plateau.py fuzz/build/pipeline.log
    python3 fuzz/plateau.py --threshold 0.5 run1.log run2.log

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
                        help="percent of the final features (default 0.5)")
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

    total = timeline[-1][0]
    half = total / 2
    at_half = [p for p in timeline if p[0] <= half] or timeline[:1]
    ft_half, ft_end = at_half[-1][2], timeline[-1][2]
    cov_half, cov_end = at_half[-1][1], timeline[-1][1]
    gain = 100.0 * (ft_end - ft_half) / ft_end
    plateau = gain < args.threshold
    print(f"second half ({half:.0f} to {total} executions): ft {ft_half} -> {ft_end} "
          f"(+{ft_end - ft_half}, {gain:.2f} %), cov {cov_half} -> {cov_end}: "
          f"{'plateau' if plateau else 'still growing'} (threshold {args.threshold} %)")
    return 0 if plateau else 1


if __name__ == "__main__":
    sys.exit(main())
