#!/usr/bin/env python3
"""Writes a vantage visibility file (.vis, format 5; docs/outputs.md, "The visibility matrix")
from any matrix, so that `vantage select` runs its selection on visibility computed elsewhere:
another simulator, a real capture, a set-cover benchmark. Plain Python, no vantage needed;
with the module built, vantage.Visibility.from_matrix makes the same matrix in memory
(docs/python.md).

As a module:

    from vis_writer import write_vis
    write_vis("m.vis", rows=[[0, 2], [1, 2], [2]], cell_count=3,
              names=["a", "b", "c"], costs=[1.0, 1.0, 2.5])

As a command (OR-Library set-cover files: rows are cells, columns are candidates):

    scripts/vis_writer.py --orlib scp41.txt scp41.vis
    scripts/vis_writer.py --rows matrix.txt --cells 117 out.vis   # one line per candidate:
                                                                  # its cell indices

The candidates get placeholder poses and a placeholder sensor (its cost is the candidate's
cost); the cells get placeholder keys of 1 cm voxels in a row. `vantage select FILE` then
reports selection as usual (report.html without meshes; ignore the robustness read-out, which
re-traces the placeholder poses)."""

import argparse
import math
import numbers
import struct
import sys

MAGIC = b"VANTVIS\0"
VERSION = 5
KEY_OFFSET = 1 << 20
MAX_CELLS = 1 << 32  # indices into R are 32-bit
MAX_POINT_COUNT = 65535  # where vantage's counts saturate; no --min-points is above it


def fnv1a64(data):
    h = 0xCBF29CE484222325
    for byte in data:
        h ^= byte
        h = (h * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


class _Writer:
    def __init__(self):
        self.parts = []

    def raw(self, fmt, *values):
        self.parts.append(struct.pack(fmt, *values))

    def u32(self, value):
        self.raw("<I", value)

    def u64(self, value):
        self.raw("<Q", value)

    def f64(self, value):
        self.raw("<d", value)

    def string(self, text):
        data = text.encode("utf-8")
        self.u64(len(data))
        self.parts.append(data)

    def array(self, code, values):
        self.u64(len(values))
        self.parts.append(struct.pack(f"<{len(values)}{code}", *values))

    def optional(self, value):
        self.u32(0 if value is None else 1)
        self.f64(0.0 if value is None else float(value))

    def bytes(self):
        return b"".join(self.parts)


def cell_key(index):
    """The packed key (docs/outputs.md) of placeholder cell `index`: (i, j, k) with k fastest,
    2^20 cells per axis, so that the keys ascend with the index as R's must (the same as
    vantage's CellOfExternalIndex)."""
    side = 1 << 20
    i, j, k = index // side // side, index // side % side, index % side
    return ((i + KEY_OFFSET) << 42) | ((j + KEY_OFFSET) << 21) | (k + KEY_OFFSET)


def name_problem(name):
    """What vantage's readers refuse in a name (its NameProblem), or None."""
    for ch in name:
        code = ord(ch)
        if code < 0x20 or 0x7F <= code <= 0x9F or code in (0x2028, 0x2029):
            return f"has a control character or line break (U+{code:04X})"
        if 0xD800 <= code <= 0xDFFF:
            return f"has a lone surrogate (U+{code:04X}), which UTF-8 cannot hold"
    return None


def _whole(value, what):
    """An integer (Python's or NumPy's, not bool), or a whole float; TypeError otherwise."""
    if isinstance(value, bool):
        raise TypeError(f"{what}: give a whole number, not bool")
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real) and math.isfinite(value) and value == int(value):
        return int(value)
    if isinstance(value, numbers.Real):
        raise ValueError(f"{what}: {value} is not a whole number")
    raise TypeError(f"{what}: give a whole number, not {type(value).__name__}")


def write_vis(path, rows, cell_count, names=None, costs=None, hits=None, scene="external matrix",
              seed=1):
    """Writes `rows` (one per candidate: the indices of the cells it sees, in [0, cell_count),
    each once, in any order) as a format-5 .vis file: the file vantage.Visibility.from_matrix
    builds from the same matrix (its save() writes it in the current format). `names`: distinct,
    non-empty, printable (default c0, c1, ...); `costs`: one per candidate, finite and >= 0
    (default 1); `hits`: optional, one list per row, each cell's point count for --min-points,
    a whole number >= 1, stored at most 65535 (default 1 per cell seen). Raises ValueError (a bad
    value) or TypeError (a value of the wrong type) naming what is wrong before writing
    anything."""
    m = len(rows)
    if m < 1:
        raise ValueError("rows: no rows — give one row per candidate")
    cell_count = _whole(cell_count, "cell_count")
    if not 1 <= cell_count <= MAX_CELLS:
        raise ValueError(f"cell_count: {cell_count} is out of range — give 1 to {MAX_CELLS}")
    names = list(names) if names is not None else [f"c{i}" for i in range(m)]
    costs = list(costs) if costs is not None else [1.0] * m
    if len(names) != m:
        raise ValueError(f"names: {len(names)} names for {m} rows — give one per row")
    if len(costs) != m:
        raise ValueError(f"costs: {len(costs)} costs for {m} rows — give one per row")
    for i, name in enumerate(names):
        if not isinstance(name, str):
            raise TypeError(f"names[{i}]: give a str, not {type(name).__name__}")
        if not name:
            raise ValueError(f"names[{i}] is empty — name it")
        if problem := name_problem(name):
            raise ValueError(f"names[{i}] {name!r} {problem}")
    if len(set(names)) != m:
        raise ValueError("names must be distinct")
    for i, c in enumerate(costs):
        if isinstance(c, bool) or not isinstance(c, numbers.Real):
            raise TypeError(f"costs[{i}]: give a number, not {type(c).__name__}")
        if not (math.isfinite(c) and c >= 0):
            raise ValueError(f"costs[{i}]: {c} is not a cost — give a finite number >= 0")
    if hits is not None and len(hits) != m:
        raise ValueError(f"hits: {len(hits)} lists for {m} rows — give one per row")
    sorted_rows, sorted_hits = [], []
    for i, row in enumerate(rows):
        cells = [_whole(e, f"row {i}") for e in row]
        counts = ([_whole(h, f"row {i}: hits") for h in hits[i]] if hits is not None
                  else [1] * len(cells))
        if len(counts) != len(cells):
            raise ValueError(f"row {i}: hits must have one count per cell")
        pairs = sorted(zip(cells, counts))
        for k, (e, h) in enumerate(pairs):
            if not 0 <= e < cell_count:
                raise ValueError(f"row {i}: cell {e} is outside [0, {cell_count})")
            if k and pairs[k - 1][0] == e:
                raise ValueError(f"row {i}: cell {e} is listed twice")
            if h < 1:
                raise ValueError(f"row {i}: point count {h} of cell {e} is below 1")
        sorted_rows.append([e for e, _ in pairs])
        sorted_hits.append([min(h, MAX_POINT_COUNT) for _, h in pairs])
    w = _Writer()
    w.parts.append(MAGIC)
    w.u32(VERSION)
    w.string(scene)
    w.u64(seed)
    w.u32(1)  # n
    w.u32(1000)  # RANSAC iterations
    w.f64(1.0)  # RANSAC stop coverage
    w.string("")  # method: the default
    w.optional(None)  # goal
    w.u32(1)  # k
    w.optional(None)  # budget
    w.optional(None)  # quality filter: max incidence
    w.optional(None)  # max depth noise
    w.f64(0.01)  # cell size [m]
    w.array("Q", [cell_key(e) for e in range(cell_count)])
    w.u64(m)
    for i in range(m):
        w.string(names[i])
        w.string(f"t{i}")  # type id: one type per candidate, so each has its own cost
        w.string("external")  # population
        w.string(f"t{i}")  # sensor id, name, technology
        w.string("placeholder sensor")
        w.string("external")
        w.u32(64)  # width, height
        w.u32(48)
        w.raw("<8d", 50.0, 50.0, 31.5, 23.5, 0.1, 5.0, 30.0, float(costs[i]))
        w.u32(0)  # no depth noise model
        w.raw("<3d", 0.0, 0.0, 0.0)
        w.string("")
        w.u32(0)  # interferes: unset
        w.raw("<7d", float(i), 0.0, 1.0, 1.0, 0.0, 0.0, 0.0)  # position, rotation w x y z
        w.array("I", sorted_rows[i])
        w.array("Q", [])  # keys outside R
        pixels = 64 * 48
        w.u64(pixels)  # rays traced
        w.array("I", [])  # plain indices (no quality filter)
        w.u64(pixels)  # target pixels
        w.u64(pixels)  # quality pixels
        w.array("H", sorted_hits[i])
    w.u64(0)  # keep-out boxes
    w.optional(None)  # min_separation
    w.string("")
    w.u32(0)
    w.u64(0)  # candidates kept out
    body = w.bytes()
    data = body + struct.pack("<Q", fnv1a64(body))
    with open(path, "wb") as f:
        f.write(data)


def read_orlib(path):
    """An OR-Library set-cover file: m rows (cells), n columns (candidates), n costs, then per
    row its count and its columns (1-based). Returns (rows per candidate, cell count, costs)."""
    with open(path) as f:
        numbers = [int(t) for t in f.read().split()]
    cells, m = numbers[0], numbers[1]
    costs = [float(c) for c in numbers[2:2 + m]]
    at = 2 + m
    rows = [[] for _ in range(m)]
    for cell in range(cells):
        count = numbers[at]
        for column in numbers[at + 1:at + 1 + count]:
            rows[column - 1].append(cell)
        at += 1 + count
    return rows, cells, costs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--orlib", help="an OR-Library set-cover file (scp*.txt format)")
    source.add_argument("--rows", help="one line per candidate: its cell indices")
    parser.add_argument("--cells", type=int, help="with --rows: the number of cells in R")
    parser.add_argument("out", help="the .vis file to write")
    args = parser.parse_args()
    if args.orlib:
        rows, cells, costs = read_orlib(args.orlib)
    else:
        if args.cells is None:
            parser.error("--rows needs --cells")
        with open(args.rows) as f:
            rows = [[int(t) for t in line.split()] for line in f if line.strip()]
        cells, costs = args.cells, None
    try:
        write_vis(args.out, rows, cells, costs=costs)
    except (TypeError, ValueError) as e:
        sys.exit(f"{args.out}: {e}")


if __name__ == "__main__":
    main()
