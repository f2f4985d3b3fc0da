"""scripts/vis_writer.py (docs/outputs.md, "Writing one from any matrix"): a matrix written by it
reads back through the independent reader (vis_format.py) and through `vantage select`, whose
answers on it match enumeration of every subset."""

import itertools
import json
import random
import sys

import pytest

from conftest import ROOT, run_cli
import vis_format

sys.path.insert(0, str(ROOT / "scripts"))
from vis_writer import write_vis  # noqa: E402


def random_rows(seed, m, cells, p):
    rng = random.Random(seed)
    rows = [[e for e in range(cells) if rng.random() < p] for _ in range(m)]
    for e in range(cells):  # every cell seen, so a goal of 1 is reachable
        if not any(e in r for r in rows):
            rows[rng.randrange(m)].append(e)
    return [sorted(r) for r in rows]


def test_written_file_reads_back(tmp_path):
    rows = [[0, 2], [1, 2], [2]]
    path = tmp_path / "m.vis"
    write_vis(path, rows, 3, names=["a", "b", "c"], costs=[1.0, 1.0, 2.5], hits=[[3, 1], [2, 2], [7]])
    vis = vis_format.read_vis(path)
    assert vis.version == 5
    assert len(vis.keys) == 3 and vis.keys == sorted(set(vis.keys))
    assert [c.name for c in vis.candidates] == ["a", "b", "c"]
    assert [c.reference_indices for c in vis.candidates] == rows
    assert [c.reference_hits for c in vis.candidates] == [[3, 1], [2, 2], [7]]


@pytest.mark.parametrize("bad", [
    dict(rows=[[3]], cell_count=3),              # cell out of range
    dict(rows=[[1, 1]], cell_count=3),           # listed twice
    dict(rows=[[0], [1]], cell_count=3, names=["a", "a"]),
    dict(rows=[[0]], cell_count=3, costs=[-1.0]),
    dict(rows=[[0]], cell_count=0),
])
def test_bad_input_writes_nothing(tmp_path, bad):
    path = tmp_path / "bad.vis"
    with pytest.raises(ValueError):
        write_vis(path, **bad)
    assert not path.exists()


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_select_on_a_written_matrix_matches_enumeration(tmp_path, seed):
    m, cells = 10, 30
    rows = random_rows(seed, m, cells, 0.15)
    path = tmp_path / "m.vis"
    write_vis(path, rows, cells)
    run_cli("select", path, "--goal", "1", "--method", "exact", "--time-limit", "20",
            "--out", tmp_path / "out")
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    result = report["results"][-1]
    fewest = next(t for t in range(1, m + 1) for s in itertools.combinations(range(m), t)
                  if len(set().union(*(rows[i] for i in s))) == cells)
    names = {f"c{i}": i for i in range(m)}
    chosen = [names[n] for n in result["sensors"]]
    assert len(set().union(*(rows[i] for i in chosen))) == cells
    assert result["n"] == fewest
    assert result["optimal"] and result["n_lower_bound"] == fewest
