"""Visibility.matrix against the .vis file's sets, read by an independent parser
(vis_format.py), and against the CLI's report.json."""

import numpy as np
import pytest
import scipy.sparse

import vantage
from conftest import EXAMPLE, read_report
from vis_format import read_vis, unpack_key


def rows_of(matrix):
    return [list(matrix.indices[matrix.indptr[i]:matrix.indptr[i + 1]])
            for i in range(matrix.shape[0])]


def test_matrix_equals_the_saved_sets(example_vis, tmp_path):
    example_vis.save(tmp_path / "m.vis")
    saved = read_vis(tmp_path / "m.vis")
    m = example_vis.matrix
    assert isinstance(m, scipy.sparse.csr_matrix)
    assert m.shape == (len(saved.candidates), len(saved.keys))
    assert rows_of(m) == [c.reference_indices for c in saved.candidates]
    assert np.all(m.data == 1.0)
    assert example_vis.matrix is m, "built once"


def test_matrix_equals_the_cli_observe_file(example_vis, cli_example):
    cli = read_vis(cli_example / "example.vis")
    assert rows_of(example_vis.matrix) == [c.reference_indices for c in cli.candidates]
    assert [c.name for c in example_vis.candidates] == [c.name for c in cli.candidates]
    assert list(example_vis.reference_keys) == cli.keys
    assert example_vis.cell_size == cli.cell_size
    # Cell centres: (index + 1/2) F of the unpacked keys.
    expected = (np.array([unpack_key(k) for k in cli.keys], dtype=float) + 0.5) * cli.cell_size
    np.testing.assert_array_equal(example_vis.reference, expected)


def test_row_sums_are_observed_voxels(example_vis, cli_example):
    report = read_report(cli_example / "optimize")
    sums = np.asarray(example_vis.matrix.sum(axis=1)).ravel()
    assert list(sums) == [c["observed_voxels"] for c in report["candidates"]]
    assert report["reference_voxels"] == example_vis.matrix.shape[1]


def test_candidates_as_report_json(example_vis, cli_example):
    report = read_report(cli_example / "optimize")
    for ours, theirs in zip(example_vis.candidates, report["candidates"], strict=True):
        assert ours.name == theirs["name"] and ours.type == theirs["type"]
        np.testing.assert_allclose(ours.position, theirs["position"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(ours.quaternion, theirs["quaternion"], rtol=0, atol=1e-12)
        for field in ("width", "height", "fx", "fy", "cx", "cy", "near", "far", "coverage",
                      "observed_voxels"):
            assert getattr(ours, field) == pytest.approx(theirs[field], abs=1e-12), field
        assert abs(np.linalg.norm(ours.quaternion) - 1) < 1e-12


def test_load_visibility_round_trip(example_vis, tmp_path):
    example_vis.save(tmp_path / "m.vis")
    again = vantage.load_visibility(str(tmp_path / "m.vis"))
    assert (again.matrix != example_vis.matrix).nnz == 0
    assert again.scene == example_vis.scene and again.seed == example_vis.seed


def test_problem_before_observe(example_problem, example_vis):
    assert example_problem.source == str(EXAMPLE)
    assert [c.name for c in example_problem.candidates] == [c.name for c in example_vis.candidates]
    assert all(c.coverage is None for c in example_problem.candidates)
    assert example_problem.cell_size == example_vis.cell_size == 0.005


def test_quality_filter_keeps_a_subset(example_problem, example_vis):
    strict = example_problem.observe(quality={"max_incidence": 30})
    assert strict.quality["max_incidence"] == 30
    plain, filtered = rows_of(example_vis.matrix), rows_of(strict.matrix)
    assert all(set(f) <= set(p) for p, f in zip(plain, filtered, strict=True))
    assert sum(map(len, filtered)) < sum(map(len, plain))
