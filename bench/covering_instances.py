#!/usr/bin/env python3
"""Classic set-cover instances of known optimum as .vis files (scripts/vis_writer.py), for the
fewest-sensors objective (`vantage select F.vis --goal 1 --method exact`; bench/RESULTS.md,
"Set cover on covering designs"). Built from their definitions, not read from the OR-Library:

- sts N (N = 3^a or 15 * 3^a): a Steiner triple system on N points (Fulkerson, Nemhauser,
  Trotter 1974: A_3n from A_n); candidates = points, cells = triples; the fewest points that
  meet every triple. Optima: 27 -> 18, 45 -> 30, 81 -> 61.
- cyc D: the D-cube's edges (candidates) and 4-cycles (cells), an edge covering the 4-cycles it
  lies on: the fewest edges whose removal leaves no 4-cycle (Grossman, Wool 1997; OR-Library
  cyc06 = D 6: 192 x 240, optimum 60).
- clr N: the 4-subsets of N points (candidates) and the 2-colourings of the points with both
  colours, up to swapping (cells); a subset covers a colouring in which it is monochromatic: the
  fewest 4-subsets that no 2-colouring avoids (OR-Library clr10 = N 10: 210 x 511, optimum 25).
- random M C P SEED: M candidates, C cells, each candidate seeing each cell with probability P
  (every cell seen by at least one).

    bench/covering_instances.py sts 27 /tmp/sts27.vis
"""

import itertools
import os
import random
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from vis_writer import write_vis  # noqa: E402


def steiner_triples(n):
    """Triples of an STS(n), n = 3^a or 15 * 3^a: STS(3n) from STS(n) (points (x, i), i in Z_3:
    {(x,0),(x,1),(x,2)}, and (x,i),(y,j),(z,-i-j) for each triple xyz), STS(15) by Bose's."""
    if n == 3:
        return [(0, 1, 2)]
    if n == 15:
        return bose_triples(5)
    if n % 3 != 0 or n < 9:
        raise ValueError(f"no construction here for STS({n})")
    base = steiner_triples(n // 3)
    m = n // 3
    point = lambda x, i: x * 3 + i  # noqa: E731
    triples = [(point(x, 0), point(x, 1), point(x, 2)) for x in range(m)]
    for x, y, z in base:
        for i in range(3):
            for j in range(3):
                k = (-i - j) % 3
                triples.append((point(x, i), point(y, j), point(z, k)))
    return triples


def bose_triples(q):
    """Bose's STS(3q) for odd q: points (x, i), x in Z_q, i in Z_3."""
    half = (q + 1) // 2  # the inverse of 2 mod q
    point = lambda x, i: x * 3 + i  # noqa: E731
    triples = [(point(x, 0), point(x, 1), point(x, 2)) for x in range(q)]
    for i in range(3):
        for x in range(q):
            for y in range(x + 1, q):
                z = ((x + y) * half) % q
                triples.append((point(x, i), point(y, i), point(z, (i + 1) % 3)))
    return triples


def sts(n):
    triples = steiner_triples(n)
    assert len(triples) == n * (n - 1) // 6
    rows = [[] for _ in range(n)]
    for cell, triple in enumerate(triples):
        for p in triple:
            rows[p].append(cell)
    return rows, len(triples)


def cyc(d):
    edges = [(v, v | (1 << b)) for v in range(1 << d) for b in range(d) if not v & (1 << b)]
    edge_index = {e: i for i, e in enumerate(edges)}
    rows = [[] for _ in edges]
    cell = 0
    for a, b in itertools.combinations(range(d), 2):
        for v in range(1 << d):
            if v & (1 << a) or v & (1 << b):
                continue
            corners = [v, v | 1 << a, v | 1 << a | 1 << b, v | 1 << b]
            for s in range(4):
                p, q = corners[s], corners[(s + 1) % 4]
                rows[edge_index[(min(p, q), max(p, q))]].append(cell)
            cell += 1
    return rows, cell


def clr(n):
    subsets = list(itertools.combinations(range(n), 4))
    colourings = range(1, 1 << (n - 1))  # point n-1 always colour 0; both colours used
    rows = []
    for s in subsets:
        mask = sum(1 << p for p in s)
        rows.append([c for c, colour in enumerate(colourings)
                     if colour & mask in (0, mask)])
    return rows, len(colourings)


def random_instance(m, cells, p, seed):
    rng = random.Random(seed)
    rows = [[e for e in range(cells) if rng.random() < p] for _ in range(m)]
    for e in range(cells):
        if not any(e in row for row in rows):
            rows[rng.randrange(m)].append(e)
    return [sorted(r) for r in rows], cells


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    kind, args, out = sys.argv[1], [float(a) for a in sys.argv[2:-1]], sys.argv[-1]
    if kind == "sts":
        rows, cells = sts(int(args[0]))
    elif kind == "cyc":
        rows, cells = cyc(int(args[0]))
    elif kind == "clr":
        rows, cells = clr(int(args[0]))
    elif kind == "random":
        rows, cells = random_instance(int(args[0]), int(args[1]), args[2], int(args[3]))
    else:
        sys.exit(f"unknown instance class '{kind}' (sts, cyc, clr, random)")
    write_vis(out, rows, cells, scene=f"{kind} {' '.join(sys.argv[2:-1])}")
    print(f"{out}: {len(rows)} candidates x {cells} cells")


if __name__ == "__main__":
    main()
