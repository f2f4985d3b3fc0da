"""Visibility.from_matrix (issue 42, "Select on any matrix"): selection on a matrix made elsewhere
gives the optimum found by enumerating every subset; the matrix saves to a .vis that
load_visibility and `vantage select FILE` read back unchanged; it is the file
scripts/vis_writer.py writes from the same rows, byte for byte; bad input raises TypeError or
InputError naming the argument (the table of test_arguments.py checks the types and ranges)."""

import itertools
import json
import math
import random
import sys

import numpy as np
import pytest
import scipy.sparse

import vantage
from conftest import ROOT, run_cli
import vis_format

sys.path.insert(0, str(ROOT / "scripts"))
from vis_writer import write_vis  # noqa: E402

M, CELLS = 8, 24


def instance(seed):
    """Rows (sorted cells), per-cell point counts and costs of a random 8 x 24 matrix in which
    every cell is seen."""
    rng = random.Random(seed)
    rows = [sorted(e for e in range(CELLS) if rng.random() < 0.25) for _ in range(M)]
    for e in range(CELLS):
        if not any(e in r for r in rows):
            rows[rng.randrange(M)].append(e)
    rows = [sorted(r) for r in rows]
    counts = [[rng.randint(1, 4) for _ in r] for r in rows]
    costs = [rng.choice([1.0, 1.5, 2.0, 3.0]) for _ in range(M)]
    return rows, counts, costs


def csr_of(rows, counts):
    indptr = np.cumsum([0] + [len(r) for r in rows])
    return scipy.sparse.csr_matrix(
        (np.concatenate([np.array(c, dtype=float) for c in counts]),
         np.concatenate([np.array(r, dtype=np.int32) for r in rows]), indptr),
        shape=(len(rows), CELLS))


def cells_at(subset, rows, counts, k=1, points=None):
    """Cells seen by >= k of `subset`, or (points) holding >= points of their counts."""
    seen, pixels = [0] * CELLS, [0] * CELLS
    for i in subset:
        for e, h in zip(rows[i], counts[i]):
            seen[e] += 1
            pixels[e] += h
    if points is not None:
        return sum(p >= points for p in pixels)
    return sum(s >= k for s in seen)


def subsets(up_to):
    for t in range(1, up_to + 1):
        yield from itertools.combinations(range(M), t)


def check(selection, best, rows, counts, k=1, points=None, optimal=True):
    """`selection`'s coverage is what its sensors reach, never above the enumerated `best`; exact
    reaches it and proves it."""
    assert selection.coverage == pytest.approx(cells_at(selection.indices, rows, counts, k, points)
                                               / CELLS)
    assert selection.coverage <= best + 1e-12
    if optimal:
        assert selection.coverage == pytest.approx(best)
        assert selection.optimal and selection.upper_bound >= best - 1e-9


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_selection_on_a_matrix_is_the_enumerated_optimum(seed):
    rows, counts, costs = instance(seed)
    vis = vantage.Visibility.from_matrix(csr_of(rows, counts), names=[f"cam{i}" for i in range(M)],
                                         costs=costs)
    assert [c.cost for c in vis.candidates] == costs
    # n sensors, most coverage.
    best = max(cells_at(s, rows, counts) for s in itertools.combinations(range(M), 3)) / CELLS
    for method in ["greedy", "local", "ransac"]:
        chosen = vis.select(n=3, method=method)
        assert chosen.n == 3
        check(chosen, best, rows, counts, optimal=False)
    exact = vis.select(n=3, method="exact", time_limit=20)
    check(exact, best, rows, counts)
    assert exact.sensors == [f"cam{i}" for i in exact.indices]
    # k-coverage.
    best = max(cells_at(s, rows, counts, k=2) for s in itertools.combinations(range(M), 4)) / CELLS
    check(vis.select(n=4, k=2, method="exact", time_limit=20), best, rows, counts, k=2)
    # The budget, with the candidates' costs.
    budget = 4.0
    best = max(cells_at(s, rows, counts) for s in subsets(M)
               if sum(costs[i] for i in s) <= budget) / CELLS
    chosen = vis.select(budget=budget, method="exact", time_limit=20)
    assert chosen.cost == pytest.approx(sum(costs[i] for i in chosen.indices))
    assert chosen.cost <= budget
    check(chosen, best, rows, counts)
    # Point counts (the matrix's data): a cell counts once the chosen put 5 points in it.
    best = max(cells_at(s, rows, counts, points=5) for s in itertools.combinations(range(M), 3))
    check(vis.select(n=3, min_points=5, method="exact", time_limit=20), best / CELLS, rows, counts,
          points=5)
    # The fewest sensors that see every cell.
    fewest = next(len(s) for s in subsets(M) if cells_at(s, rows, counts) == CELLS)
    cover = vis.select(goal=1.0, method="exact", time_limit=20)
    assert cover.n == fewest and cover.optimal and cover.n_lower_bound == fewest
    assert cells_at(cover.indices, rows, counts) == CELLS


def test_saved_matrix_reads_back_and_the_cli_selects_on_it(tmp_path):
    rows, counts, costs = instance(4)
    names = [f"sensor {i}" for i in range(M)]
    vis = vantage.Visibility.from_matrix(csr_of(rows, counts), names=names, costs=costs)
    vis.save(tmp_path / "m.vis")
    saved = vis_format.read_vis(tmp_path / "m.vis")  # the independent reader
    assert [c.name for c in saved.candidates] == names
    assert [c.cost for c in saved.candidates] == costs
    assert [c.reference_indices for c in saved.candidates] == rows
    assert [c.reference_hits for c in saved.candidates] == counts
    assert len(saved.keys) == CELLS and saved.keys == sorted(set(saved.keys))
    again = vantage.load_visibility(tmp_path / "m.vis")
    assert (again.matrix != vis.matrix).nnz == 0 and again.matrix.shape == (M, CELLS)
    assert [c.name for c in again.candidates] == names
    assert list(again.reference_keys) == list(vis.reference_keys)
    again.save(tmp_path / "again.vis")
    assert (tmp_path / "again.vis").read_bytes() == (tmp_path / "m.vis").read_bytes()
    # `vantage select FILE` on it: the enumerated optimum, as the module's select.
    best = max(cells_at(s, rows, counts) for s in itertools.combinations(range(M), 2)) / CELLS
    run_cli("select", tmp_path / "m.vis", "-n", "2", "--method", "exact", "--out", tmp_path / "out")
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    result = report["results"][-1]
    assert result["coverage"] == pytest.approx(best) and result["optimal"]
    assert result["coverage"] == pytest.approx(vis.select(n=2, method="exact").coverage)
    assert cells_at([names.index(n) for n in result["sensors"]], rows, counts) / CELLS == \
        pytest.approx(best)


@pytest.mark.parametrize("with_names", [False, True])
def test_the_file_is_vis_writers(tmp_path, with_names):
    rows, counts, costs = instance(5)
    counts[0][0] = 70000  # above what a .vis holds: both store 65535
    options = dict(names=[f"n{i}" for i in range(M)], costs=costs) if with_names else {}
    write_vis(tmp_path / "writer.vis", rows, CELLS, hits=counts, **options)
    vantage.load_visibility(tmp_path / "writer.vis").save(tmp_path / "writer_resaved.vis")
    ours = vantage.Visibility.from_matrix(csr_of(rows, counts), **options)
    ours.save(tmp_path / "ours.vis")
    assert (tmp_path / "ours.vis").read_bytes() == (tmp_path / "writer_resaved.vis").read_bytes()
    assert vis_format.read_vis(tmp_path / "ours.vis").candidates[0].reference_hits[0] == 65535


def test_array_forms_are_the_same_matrix(tmp_path):
    rows, counts, _ = instance(6)
    m = csr_of(rows, counts)
    forms = [
        m,
        (m.indptr, m.indices, m.data),
        (m.indptr.astype(np.uint64), m.indices.astype(np.int64), m.data.astype(np.int16)),
        (list(m.indptr), list(m.indices), list(m.data)),
    ]
    if hasattr(scipy.sparse, "csr_array"):
        forms.append(scipy.sparse.csr_array(m))
    for i, form in enumerate(forms):
        kw = {} if scipy.sparse.issparse(form) else {"cells": CELLS}
        vantage.Visibility.from_matrix(form, **kw).save(tmp_path / f"{i}.vis")
    for i in range(1, len(forms)):
        assert (tmp_path / f"{i}.vis").read_bytes() == (tmp_path / "0.vis").read_bytes(), i
    # Without data: one point per cell seen, as a 0/1 matrix.
    plain = vantage.Visibility.from_matrix((m.indptr, m.indices), cells=CELLS)
    ones = vantage.Visibility.from_matrix(scipy.sparse.csr_matrix((np.ones(m.nnz), m.indices,
                                                                   m.indptr), shape=m.shape))
    plain.save(tmp_path / "plain.vis")
    ones.save(tmp_path / "ones.vis")
    assert (tmp_path / "plain.vis").read_bytes() == (tmp_path / "ones.vis").read_bytes()
    assert vis_format.read_vis(tmp_path / "plain.vis").candidates[1].reference_hits == \
        [1] * len(rows[1])
    # Defaults: names c0, c1, ..., cost 1; an empty row is a candidate that sees nothing.
    empty = vantage.Visibility.from_matrix(([0, 2, 2], [0, 1]), cells=3)
    assert [c.name for c in empty.candidates] == ["c0", "c1"]
    assert [c.cost for c in empty.candidates] == [1.0, 1.0]
    assert [c.observed_voxels for c in empty.candidates] == [2, 0]
    assert empty.select(n=1, method="exact").coverage == pytest.approx(2 / 3)


SMALL = scipy.sparse.csr_matrix(np.array([[1, 0, 1], [0, 1, 1]]))


def unsorted():
    m = SMALL.copy()
    m.indices[[0, 1]] = m.indices[[1, 0]]
    m.has_sorted_indices = False
    return m


def duplicated():
    return scipy.sparse.csr_matrix((np.ones(3), np.array([0, 0, 1]), np.array([0, 2, 3])),
                                   shape=(2, 3))


@pytest.mark.parametrize("arguments,error,message", [
    (dict(csr=unsorted()), vantage.InputError, "csr: row 0 lists cell 0 after cell 2"),
    (dict(csr=duplicated()), vantage.InputError, "csr: row 0 lists cell 0 twice"),
    (dict(csr=([0, 1, 3], [0, 2, 1]), cells=3), vantage.InputError,
     "csr: row 1 lists cell 1 after cell 2"),
    (dict(csr=([0, 1], [3]), cells=3), vantage.InputError, "csr: row 0 has cell 3, outside"),
    (dict(csr=([0, 1], [-1]), cells=3), vantage.InputError, "csr: row 0 has cell -1, outside"),
    (dict(csr=([1, 1], [0]), cells=3), vantage.InputError, "csr: indptr starts at 1"),
    (dict(csr=([0, 2, 1], [0, 1]), cells=3), vantage.InputError, "csr: indptr decreases"),
    (dict(csr=([0, 1], [0, 1]), cells=3), vantage.InputError, "csr: indptr ends at 1"),
    (dict(csr=([0], []), cells=3), vantage.InputError, "csr: has no rows"),
    (dict(csr=([0, 1], [0], [1, 1]), cells=3), vantage.InputError, "csr: data has 2 entries"),
    (dict(csr=([0, 1], [0], [math.nan]), cells=3), vantage.InputError, "csr: data at row 0"),
    (dict(csr=([0, 1], [0], [0]), cells=3), vantage.InputError, "csr: data at row 0"),
    (dict(csr=([0, 1], [0], [1.5]), cells=3), vantage.InputError, "csr: data at row 0"),
    (dict(csr=([0, 1], [0], ["a"]), cells=3), TypeError, "csr: data: give point counts"),
    (dict(csr=([0, 1], [0.0]), cells=3), TypeError, "csr: indices: give integers"),
    (dict(csr=([[0, 1]], [0]), cells=3), vantage.InputError, "csr: indptr: has 2 dimensions"),
    (dict(csr=([0, 1],), cells=3), vantage.InputError, "csr: holds 1 arrays"),
    (dict(csr=([0, 1], [0])), TypeError, "cells: give the number of cells"),
    (dict(csr=SMALL, cells=4), vantage.InputError, "cells: 4, but the matrix has 3 columns"),
    (dict(csr=SMALL.tocsc()), TypeError, "csr: give a CSR matrix, not SciPy's csc"),
    (dict(csr=SMALL.toarray()), TypeError, "csr: give a scipy.sparse CSR matrix"),
    (dict(csr=scipy.sparse.csr_matrix((2, 0))), vantage.InputError, "cells: 0 is out of range"),
    (dict(csr=SMALL, names=["a", "a"]), vantage.InputError, "names: 'a' is used twice"),
    (dict(csr=SMALL, names=["a"]), vantage.InputError, "names: 1 names for 2 rows"),
    (dict(csr=SMALL, names=["a", ""]), vantage.InputError, "names: names[1] is empty"),
    (dict(csr=SMALL, names=["a", "b\nc"]), vantage.InputError, "names: names[1] 'b\\nc' has a"),
    (dict(csr=SMALL, names=["a", "b\u2028"]), vantage.InputError, "names: names[1]"),
    (dict(csr=SMALL, names=["a", "\udcff"]), vantage.InputError, "names[1]: is not valid"),
    (dict(csr=SMALL, names="ab"), TypeError, "names: give a list of names"),
    (dict(csr=SMALL, names=["a", 2]), TypeError, "names[1]: give a str"),
    (dict(csr=SMALL, costs=[1.0, math.nan]), vantage.InputError, "costs[1]: nan is not a cost"),
    (dict(csr=SMALL, costs=[1.0, 1e308]), vantage.InputError,
     "costs[1]: 1e+308 is not a cost — give a number from 0 to 1e+12"),
    (dict(csr=SMALL, costs=[1.0, -2]), vantage.InputError, "costs[1]: -2"),
    (dict(csr=SMALL, costs=np.array([math.inf, 1.0])), vantage.InputError, "costs[0]: inf"),
    (dict(csr=SMALL, costs=[1.0, 1.0, 1.0]), vantage.InputError, "costs: 3 costs for 2 rows"),
    (dict(csr=SMALL, costs=1.0), TypeError, "costs: give a list of numbers"),
    (dict(csr=SMALL, costs=[1.0, "2"]), TypeError, "costs[1]: give a number, not str"),
    (dict(csr=SMALL, states=["empty", "full", "full"]), vantage.InputError,
     "states: a .vis file holds one state's matrix"),
    (dict(csr="m.npz"), TypeError, "csr: give a scipy.sparse CSR matrix"),
])
def test_bad_input_names_the_argument(arguments, error, message):
    with pytest.raises(error) as raised:
        vantage.Visibility.from_matrix(**arguments)
    assert type(raised.value) is error
    assert str(raised.value).startswith(message), str(raised.value)


@pytest.mark.parametrize("arguments", [
    dict(rows=[[1, 0, 0]], cell_count=3),                       # listed twice
    dict(rows=[[0]], cell_count=3, names=["a\tb"]),              # a control character
    dict(rows=[[0]], cell_count=3, costs=[math.nan]),
    dict(rows=[[0]], cell_count=3, hits=[[0]]),                  # a count below 1
    dict(rows=[[0.5]], cell_count=3),                            # not an index
    dict(rows=[], cell_count=3),
])
def test_vis_writer_refuses_what_from_matrix_refuses(tmp_path, arguments):
    with pytest.raises((TypeError, ValueError)):
        write_vis(tmp_path / "bad.vis", **arguments)
    assert not (tmp_path / "bad.vis").exists()


def test_more_cells_than_one_axis_holds(tmp_path):
    """Beyond 2^20 cells the placeholder keys go on in the next row of cells, still ascending
    (vis_writer's line of cells along x wrapped around and wrote keys the reader refused)."""
    cells = (1 << 20) + 3
    write_vis(tmp_path / "writer.vis", [[0, cells - 1], [5]], cells)
    read = vantage.load_visibility(tmp_path / "writer.vis")
    keys = read.reference_keys
    assert len(keys) == cells and np.all(keys[1:] > keys[:-1])
    assert vis_format.unpack_key(int(keys[-1])) == (0, 1, 2)
    read.save(tmp_path / "writer_resaved.vis")
    vantage.Visibility.from_matrix(([0, 2, 3], [0, cells - 1, 5]), cells=cells).save(
        tmp_path / "ours.vis")
    assert (tmp_path / "ours.vis").read_bytes() == (tmp_path / "writer_resaved.vis").read_bytes()
