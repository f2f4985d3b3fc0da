"""Fixtures of the Python module's tests: paths (set by CTest, else found from the checkout) and
the CLI's own outputs on the example, made once per session to compare the module with."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = pathlib.Path(os.environ.get("VANTAGE_BINARY", ROOT / "build" / "vantage"))
SHARED = pathlib.Path(os.environ.get("VANTAGE_SHARED_DIR", ROOT.parent / "shared"))
EXAMPLE = ROOT / "examples" / "scenes" / "bin_picking_cell.yaml"
CUBE_CELL = ROOT / "tests" / "data" / "cli" / "cube_cell.yaml"  # tiny: 16 candidates
COSTA = SHARED / "worlds" / "costa2017"
METHODS = ["best", "ransac", "greedy", "local", "exact"]


def run_cli(*args, check=True):
    """Runs the vantage CLI quietly; returns the completed process."""
    result = subprocess.run([str(BINARY), "-q", *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"vantage {' '.join(map(str, args))}: {result.stderr}")
    return result


def normalised(report):
    """report.json without what differs between two runs of the same input: timings, seconds."""
    def strip(value):
        if isinstance(value, dict):
            return {k: strip(v) for k, v in value.items() if k != "seconds"}
        if isinstance(value, list):
            return [strip(v) for v in value]
        return value
    report = dict(report)
    report.pop("timings", None)
    return strip(report)


def read_report(folder):
    with open(pathlib.Path(folder) / "report.json", encoding="utf-8") as f:
        return json.load(f)


@pytest.fixture(scope="session")
def cli_example(tmp_path_factory):
    """The CLI's optimize folder and observe file of the example."""
    folder = tmp_path_factory.mktemp("cli")
    run_cli("optimize", EXAMPLE, "--out", folder / "optimize")
    run_cli("observe", EXAMPLE, "--out", folder / "example.vis")
    return folder


@pytest.fixture(scope="session")
def example_problem():
    import vantage
    return vantage.load(EXAMPLE)


@pytest.fixture(scope="session")
def example_vis(example_problem):
    return example_problem.observe()


def needs_shared():
    return pytest.mark.skipif(not (COSTA / "worlds" / "bin_picking.world").exists(),
                              reason=f"no shared worlds at {COSTA}")
