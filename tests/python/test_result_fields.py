"""Every key of report.json's results and candidates that `vantage select FILE` writes is on
vantage.Selection and vantage.Candidate with the same value: the binary, run here on the same
.vis with the same flags, is the reference (docs/outputs.md lists the keys)."""

import pytest

import vantage
from conftest import EXAMPLE, read_report, run_cli

# Result keys and the Selection attribute holding each (None in Python where the key is absent).
RESULT_KEYS = ["method", "n", "sensors", "coverage", "paper_coverage", "upper_bound", "gap",
               "optimal", "plain_coverage", "min_points", "goal", "n_lower_bound", "cost",
               "cost_lower_bound", "part_coverage", "ideal_coverage", "constraints",
               "objective", "budget"]
CANDIDATE_KEYS = ["name", "type", "width", "height", "fx", "fy", "cx", "cy", "near", "far",
                  "coverage", "paper_coverage", "population", "observed_voxels", "rays_traced",
                  "ideal_coverage", "plain_coverage", "target_pixels", "quality_pixels"]


@pytest.fixture(scope="module")
def quality_vis(tmp_path_factory):
    """The example observed with a quality filter: plain coverage beside the filtered one."""
    path = tmp_path_factory.mktemp("quality") / "q.vis"
    run_cli("observe", EXAMPLE, "--max-incidence", 60, "--out", path)
    return path


def check_results(report, selections):
    assert len(selections) == len(report["results"])
    for expected, got in zip(report["results"], selections):
        for key in RESULT_KEYS:
            value = getattr(got, key)
            if key == "optimal" and "optimal" not in expected:
                assert value is False
            elif key == "method" and expected[key] == "best":
                assert value == "best"
            else:
                assert value == expected.get(key), (expected["method"], key)
        assert got.k == expected.get("k", 1)  # report.json writes k from 2 on
        assert got.ceiling == report["ceiling"]["coverage"]
        if got.part_coverage:  # per part, weighted by its voxels, they add up to coverage
            voxels = {p["name"]: p["voxels"] for p in report["ceiling"]["parts"]}
            assert sum(got.part_coverage[n] * voxels[n] for n in voxels) / \
                report["reference_voxels"] == pytest.approx(got.coverage, abs=1e-12)


@pytest.mark.parametrize("flags,kwargs", [
    (["-n", 3, "--method", "exact"], {"n": 3, "method": "exact"}),
    (["-n", 3, "--method", "local", "--min-points", 4], {"n": 3, "method": "local",
                                                         "min_points": 4}),
    (["--goal", 0.6, "--cheapest", "--method", "exact"], {"goal": 0.6, "cheapest": True,
                                                          "method": "exact"}),
    (["-n", 3, "--method", "local", "--interference-overlap", 0.2, "--calibration-overlap", 20],
     {"n": 3, "method": "local", "interference_overlap": 0.2, "calibration_overlap": 20}),
    (["--budget", 600, "--method", "exact"], {"budget": 600, "method": "exact"}),
    (["-n", 3, "--k", 2, "--method", "greedy"], {"n": 3, "k": 2, "method": "greedy"}),
], ids=["exact", "min_points", "cheapest", "constraints", "budget", "k"])
def test_select_result_fields_as_cli(cli_example, example_vis, flags, kwargs, tmp_path):
    run_cli("select", cli_example / "example.vis", *flags, "--out", tmp_path / "cli")
    report = read_report(tmp_path / "cli")
    check_results(report, [example_vis.select(**kwargs)])
    got = example_vis.select(**kwargs)
    assert got.ideal_coverage is not None  # the example is physical: report.json has the key
    assert got.part_coverage  # R knows its target parts
    if "interference_overlap" in kwargs:
        assert got.constraints["satisfied"] is True


def test_select_all_fields_as_cli(cli_example, example_vis, tmp_path):
    run_cli("select", cli_example / "example.vis", "-n", 2, "--out", tmp_path / "cli")
    check_results(read_report(tmp_path / "cli"), example_vis.select_all(n=2))


def test_quality_fields_as_cli(quality_vis, tmp_path):
    run_cli("select", quality_vis, "-n", 2, "--method", "greedy", "--out", tmp_path / "cli")
    report = read_report(tmp_path / "cli")
    vis = vantage.load_visibility(quality_vis)
    got = vis.select(n=2, method="greedy")
    check_results(report, [got])
    assert got.plain_coverage >= got.coverage  # the filter only drops pixels
    check_candidates(report, vis)
    assert all(c.quality_pixels <= c.target_pixels for c in vis.candidates)


def check_candidates(report, vis):
    assert len(report["candidates"]) == len(vis.candidates)
    for expected, got in zip(report["candidates"], vis.candidates):
        for key in CANDIDATE_KEYS:
            assert getattr(got, key) == expected.get(key), (expected["name"], key)
        assert list(got.position) == expected["position"]
        assert list(got.quaternion) == expected["quaternion"]


def test_candidate_fields_as_cli(cli_example, example_vis):
    report = read_report(cli_example / "optimize")
    check_candidates(report, example_vis)
    assert example_vis.physical is True and example_vis.exposed_only is False
    ideal = vantage.load(EXAMPLE).observe(physical=False)
    assert ideal.physical is False
    assert all(c.ideal_coverage is None for c in ideal.candidates)
    # The ideal pinhole counts every pixel whose ray meets a target first: never fewer cells.
    assert all(c.ideal_coverage >= c.coverage for c in example_vis.candidates)


def test_a_matrix_from_elsewhere_has_no_parts():
    """from_matrix knows no target parts, no physics and no filter: those fields are None, and
    the ceiling is every row together (2 of the 3 cells here)."""
    vis = vantage.Visibility.from_matrix(([0, 1, 2], [0, 2]), cells=3)
    got = vis.select(n=1, method="exact")
    assert (got.part_coverage, got.ideal_coverage, got.plain_coverage, got.constraints) == \
        (None, None, None, None)
    assert got.ceiling == pytest.approx(2 / 3)
    assert got.gap == 0.0 and got.upper_bound == pytest.approx(1 / 3)


def test_parts_and_exposure_per_cell_as_cli(cli_example, example_vis):
    """Visibility.parts / reference_parts / reference_exposed count, per part, the voxels and
    unexposed voxels that the binary's report.json ceiling.parts lists."""
    report = read_report(cli_example / "optimize")
    parts = report["ceiling"]["parts"]
    assert example_vis.parts == [p["name"] for p in parts]
    of, exposed = example_vis.reference_parts, example_vis.reference_exposed
    assert len(of) == len(exposed) == report["reference_voxels"]
    for index, part in enumerate(parts):
        assert int((of == index).sum()) == part["voxels"]
        assert int(((of == index) & ~exposed).sum()) == part["unexposed_voxels"]
    assert int((~exposed).sum()) == report["ceiling"]["unexposed_voxels"]
    external = vantage.Visibility.from_matrix(([0, 1], [0]), cells=2)
    assert (external.parts, external.reference_parts, external.reference_exposed) == \
        ([], None, None)
