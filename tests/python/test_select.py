"""Visibility.select gives what `vantage select FILE` gives, for every method."""

import pytest

import vantage
from conftest import METHODS, read_report, run_cli


@pytest.fixture(scope="module")
def cli_vis(cli_example):
    return vantage.load_visibility(cli_example / "example.vis")


@pytest.mark.parametrize("method", METHODS)
def test_each_method_as_cli(cli_example, cli_vis, example_vis, method, tmp_path):
    run_cli("select", cli_example / "example.vis", "-n", 3, "--method", method,
            "--out", tmp_path / "cli")
    (expected,) = read_report(tmp_path / "cli")["results"]
    for vis in (cli_vis, example_vis):  # the CLI's matrix and the module's own
        selection = vis.select(n=3, method=method)
        assert selection.method == expected["method"] == method
        assert selection.sensors == expected["sensors"]
        assert selection.n == expected["n"] == len(selection.sensors)
        assert selection.coverage == expected["coverage"]
        assert selection.paper_coverage == expected["paper_coverage"]
        assert selection.upper_bound == expected.get("upper_bound")
        assert selection.optimal == expected.get("optimal", False)
        names = [c.name for c in vis.candidates]
        assert [names[i] for i in selection.indices] == selection.sensors


def test_coverage_from_the_matrix(cli_vis):
    """coverage = |(union of the chosen rows) ∩ R| / |R|, recomputed with SciPy."""
    selection = cli_vis.select(n=3, method="greedy")
    union = cli_vis.matrix[selection.indices].sum(axis=0)
    assert (union > 0).sum() / cli_vis.matrix.shape[1] == pytest.approx(selection.coverage,
                                                                        abs=1e-15)


def test_exact_bound_holds(cli_vis):
    for n in (1, 2, 3):
        exact = cli_vis.select(n=n, method="exact")
        assert exact.upper_bound is not None and exact.coverage <= exact.upper_bound + 1e-12
        for method in ("ransac", "greedy", "local"):
            assert cli_vis.select(n=n, method=method).coverage <= exact.upper_bound + 1e-12


def test_select_all_as_cli(cli_example, cli_vis, tmp_path):
    run_cli("select", cli_example / "example.vis", "-n", 2, "--out", tmp_path / "cli")
    expected = read_report(tmp_path / "cli")["results"]
    ours = cli_vis.select_all(n=2)
    assert [(s.method, s.n, s.sensors, s.coverage) for s in ours] == \
        [(r["method"], r["n"], r["sensors"], r["coverage"]) for r in expected]


@pytest.mark.parametrize("flags,kwargs", [
    (["--goal", "0.6", "--method", "greedy"], {"goal": 0.6, "method": "greedy"}),
    (["-n", "3", "--k", "2", "--method", "local"], {"n": 3, "k": 2, "method": "local"}),
    (["--budget", "2000", "--method", "exact"], {"budget": 2000, "method": "exact"}),
])
def test_objectives_as_cli(cli_example, cli_vis, tmp_path, flags, kwargs):
    run_cli("select", cli_example / "example.vis", *flags, "--out", tmp_path / "cli")
    (expected,) = read_report(tmp_path / "cli")["results"]
    selection = cli_vis.select(**kwargs)
    assert selection.sensors == expected["sensors"]
    assert selection.coverage == expected["coverage"]
    assert selection.objective == expected["objective"]


@pytest.mark.parametrize("method,flags,kwargs", [
    ("exact", ["--interference", "true", "--interference-overlap", "0.05"],
     {"interference": True, "interference_overlap": 0.05}),
    ("local", ["--calibration-overlap", "20"], {"calibration_overlap": 20}),
    ("greedy", ["--calibration-overlap-frac", "0.1", "--interference", "false"],
     {"calibration_overlap_frac": 0.1, "interference": False}),
    # Constraints with the other objectives (issue 20).
    ("exact", ["--k", "2", "--interference", "true"], {"k": 2, "interference": True}),
    ("local", ["--min-points", "10", "--calibration-overlap", "20"],
     {"min_points": 10, "calibration_overlap": 20}),
])
def test_constraints_as_cli(cli_example, cli_vis, method, flags, kwargs, tmp_path):
    run_cli("select", cli_example / "example.vis", "-n", 3, "--method", method, *flags,
            "--out", tmp_path / "cli")
    report = read_report(tmp_path / "cli")
    (expected,) = report["results"]
    selection = cli_vis.select(n=3, method=method, **kwargs)
    assert (selection.sensors, selection.coverage, selection.upper_bound) == \
        (expected["sensors"], expected["coverage"], expected.get("upper_bound"))
    assert expected["constraints"]["satisfied"]


def test_interference_is_the_enumerated_optimum(cli_vis):
    """interference=True (F = 0.1) at n = 3 gives the best triple without an interfering pair,
    found here by enumerating all triples of the example's matrix; the default (off) gives the
    unconstrained optimum."""
    import itertools

    matrix = cli_vis.matrix.tocsr()
    rows = [set(matrix.indices[matrix.indptr[i]:matrix.indptr[i + 1]].tolist())
            for i in range(matrix.shape[0])]
    masks = [sum(1 << c for c in row) for row in rows]
    projecting = [c.technology.startswith(("structured light", "time of flight"))
                  for c in cli_vis.candidates]
    conflict = set()
    for a, b in itertools.combinations(range(len(rows)), 2):
        if projecting[a] and projecting[b] and \
                len(rows[a] & rows[b]) > 0.1 * min(len(rows[a]), len(rows[b])):
            conflict.add((a, b))
    best_free, best_any = 0, 0
    for a, b, c in itertools.combinations(range(len(rows)), 3):
        cells = bin(masks[a] | masks[b] | masks[c]).count("1")
        best_any = max(best_any, cells)
        if (a, b) not in conflict and (a, c) not in conflict and (b, c) not in conflict:
            best_free = max(best_free, cells)
    cells = matrix.shape[1]
    assert cli_vis.select(n=3, method="exact", interference=True).coverage == \
        pytest.approx(best_free / cells, abs=1e-15)
    assert cli_vis.select(n=3, method="exact").coverage == pytest.approx(best_any / cells,
                                                                         abs=1e-15)
    assert best_free < best_any  # the example's optimum pairs two interfering Kinects


def test_min_points_is_the_enumerated_optimum(cli_vis, cli_example):
    """min_points=P at n = 2: the best pair counting only cells where the two sensors' pixel hits
    (read from the CLI's .vis by the independent parser) add up to P; min_density gives the same
    P through ceil(D · F² in cm²)."""
    import itertools

    from vis_format import read_vis

    saved = read_vis(cli_example / "example.vis")
    points = 20
    hits = [dict(zip(c.reference_indices, c.reference_hits)) for c in saved.candidates]
    best = 0
    for a, b in itertools.combinations(range(len(hits)), 2):
        cells = set(hits[a]) | set(hits[b])
        dense = sum(1 for e in cells if hits[a].get(e, 0) + hits[b].get(e, 0) >= points)
        best = max(best, dense)
    expected = best / len(saved.keys)
    chosen = cli_vis.select(n=2, method="exact", min_points=points)
    assert chosen.coverage == pytest.approx(expected, abs=1e-15)
    density = points / (saved.cell_size * 100) ** 2  # points per cm² of a cell's face
    assert cli_vis.select(n=2, method="exact", min_density=density).coverage == \
        pytest.approx(expected, abs=1e-15)
    assert expected < cli_vis.select(n=2, method="exact").coverage
