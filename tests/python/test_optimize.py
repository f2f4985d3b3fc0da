"""vantage.optimize writes what `vantage optimize` writes (report.json equal, timings aside)."""

import os
import pathlib

import pytest

import vantage
from conftest import COSTA, EXAMPLE, needs_shared, normalised, read_report, run_cli


def compare_folders(cli_folder, py_folder, returned):
    cli_report, py_report = read_report(cli_folder), read_report(py_folder)
    assert normalised(py_report) == normalised(cli_report)
    assert normalised(returned) == normalised(py_report)
    cli_files = sorted(p.name for p in pathlib.Path(cli_folder).iterdir())
    assert sorted(p.name for p in pathlib.Path(py_folder).iterdir()) == cli_files
    for name in ("candidates.csv", "observed.ply", "reference.ply"):
        assert (pathlib.Path(py_folder) / name).read_bytes() == \
            (pathlib.Path(cli_folder) / name).read_bytes(), name


def test_example_defaults(cli_example, tmp_path):
    returned = vantage.optimize(EXAMPLE, out=tmp_path / "py")
    compare_folders(cli_example / "optimize", tmp_path / "py", returned)
    assert returned["results"], "the run chose nothing"


def test_example_with_options(tmp_path):
    run_cli("optimize", EXAMPLE, "-n", 2, "--method", "local", "--max-incidence", 60,
            "--seed", 7, "--alternatives-within", 2, "--out", tmp_path / "cli")
    returned = vantage.optimize(EXAMPLE, n=2, method="local", out=tmp_path / "py",
                                quality={"max_incidence": 60}, seed=7, alternatives_within=2,
                                threads=1)
    compare_folders(tmp_path / "cli", tmp_path / "py", returned)
    assert [r["method"] for r in returned["results"]] == ["local"]


def test_without_out_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    report = vantage.optimize(EXAMPLE, n=1, method="best")
    assert report["results"][0]["method"] == "best"
    assert list(tmp_path.iterdir()) == []


@needs_shared()
def test_shared_world(tmp_path):
    world = COSTA / "worlds" / "bin_picking.world"
    paths = ["--model-path", COSTA / "media" / "models", "--resource-path", COSTA / "media"]
    run_cli("optimize", world, *paths, "--out", tmp_path / "cli")
    returned = vantage.optimize(world, out=tmp_path / "py", model_path=COSTA / "media" / "models",
                                resource_path=[str(COSTA / "media")])
    compare_folders(tmp_path / "cli", tmp_path / "py", returned)
    assert (tmp_path / "py" / "constellation.world").read_bytes() == \
        (tmp_path / "cli" / "constellation.world").read_bytes()


@needs_shared()
def test_physical_on_a_gazebo_world_as_cli(tmp_path):
    """A Gazebo world of the paper's system is ideal by default; physical=True is --physical."""
    world = COSTA / "worlds" / "bin_picking.world"
    paths = ["--model-path", COSTA / "media" / "models", "--resource-path", COSTA / "media"]
    run_cli("optimize", world, *paths, "-n", 2, "--method", "greedy", "--physical",
            "--out", tmp_path / "cli")
    returned = vantage.optimize(world, n=2, method="greedy", physical=True,
                                model_path=COSTA / "media" / "models",
                                resource_path=COSTA / "media")
    assert normalised(returned) == normalised(read_report(tmp_path / "cli"))
    assert returned["sensor_model"]["model"] == "physical"


def test_evaluate_matches_cli(cli_example, tmp_path):
    constellation = cli_example / "optimize" / "report.json"
    cli = run_cli("evaluate", EXAMPLE, "--constellation", constellation, "--out", tmp_path / "cli")
    result = vantage.evaluate(EXAMPLE, constellation=constellation, out=tmp_path / "py")
    assert normalised(read_report(tmp_path / "py")) == normalised(read_report(tmp_path / "cli"))
    # The CLI prints "sensor  NAME  xx.xx %" per sensor, then the union.
    printed = [line.split() for line in cli.stdout.splitlines() if line.startswith("sensor ")]
    assert result["sensors"] == [words[1] for words in printed]
    for coverage, words in zip(result["sensor_coverage"], printed):
        assert 100 * coverage == pytest.approx(float(words[2]), abs=0.005)
    primary = read_report(cli_example / "optimize")
    chosen = primary["results"][primary["primary_result"]]
    assert result["coverage"] == pytest.approx(chosen["coverage"], abs=1e-12)


def constrained_example(cli_example, folder):
    """The example with a keep-out box around its best layout's first sensor and a minimum
    separation of 0.3 m (docs/constraints.md, Mounting rules), written into `folder`."""
    report = read_report(cli_example / "optimize")
    first = report["results"][report["primary_result"]]["sensors"][0]
    (position,) = [c["position"] for c in report["candidates"] if c["name"] == first]
    text = EXAMPLE.read_text(encoding="utf-8").replace(
        "../meshes/", str(EXAMPLE.parent.parent / "meshes") + "/")
    text += (f"keep_out:\n  - {{name: pillar, center: {list(position)}, size: [0.05, 0.05, 0.05]}}\n"
             "min_separation: 0.3\n")
    scene = pathlib.Path(folder) / "constrained.yaml"
    scene.write_text(text, encoding="utf-8")
    return scene, first


def test_constrained_run_matches_cli(cli_example, tmp_path):
    scene, kept_out = constrained_example(cli_example, tmp_path)
    flags = ["-n", 3, "--method", "local", "--interference-overlap", 0.2,
             "--calibration-overlap", 20]
    run_cli("optimize", scene, *flags, "--out", tmp_path / "cli")
    returned = vantage.optimize(scene, n=3, method="local", out=tmp_path / "py",
                                interference_overlap=0.2, calibration_overlap=20)
    compare_folders(tmp_path / "cli", tmp_path / "py", returned)
    constraints = returned["constraints"]
    assert constraints["keep_out"]["excluded_candidates"] == 1
    assert constraints["separation"]["min_separation"] == 0.3
    assert constraints["calibration"]["min_cells"] == 20
    assert kept_out not in [c["name"] for c in returned["candidates"]]
    (result,) = returned["results"]
    assert result["constraints"]["satisfied"]

    # evaluate checks the same layout against the same rules, from Python as from the CLI.
    cli = tmp_path / "cli" / "report.json"
    run_cli("evaluate", scene, "--constellation", cli, "--interference-overlap", 0.2,
            "--out", tmp_path / "cli_eval")
    evaluated = vantage.evaluate(scene, constellation=cli, interference_overlap=0.2,
                                 out=tmp_path / "py_eval")
    assert normalised(evaluated["report"]) == normalised(read_report(tmp_path / "cli_eval"))


def test_refined_constrained_run_matches_cli(cli_example, tmp_path):
    """--refine under every constraint (issue 20): the same folder from Python as from the CLI,
    the refined layout satisfies them, and no new pose lies in the keep-out box."""
    scene, _ = constrained_example(cli_example, tmp_path)
    flags = ["-n", 3, "--method", "greedy", "--refine", "--interference-overlap", 0.2,
             "--calibration-overlap", 20]
    run_cli("optimize", scene, *flags, "--out", tmp_path / "cli")
    returned = vantage.optimize(scene, n=3, method="greedy", refine=True, out=tmp_path / "py",
                                interference_overlap=0.2, calibration_overlap=20)
    compare_folders(tmp_path / "cli", tmp_path / "py", returned)
    (refined,) = [r for r in returned["results"] if r["method"] == "refined"]
    assert refined["constraints"]["satisfied"]
    assert returned["refinement"]["new_candidates"] > 0
    (box,) = returned["constraints"]["keep_out"]["regions"]
    for candidate in returned["candidates"]:
        assert any(abs(p - c) > s / 2 for p, c, s in
                   zip(candidate["position"], box["center"], box["size"])), candidate["name"]


def test_sensors_match_cli_json():
    import json
    cli = json.loads(run_cli("sensors", "--json").stdout)
    ours = vantage.sensors()
    assert [{k: entry[k] for k in cli[0]} for entry in ours] == cli
    assert all(set(entry) == set(cli[0]) | {"depth_noise"} for entry in ours)


def test_visibility_file_keeps_the_mounting_rules(cli_example, tmp_path):
    """A .vis of a scene with mounting rules (format 5 on) holds them (read by the independent
    reader), with R's target parts and exposure (format 6 on), and Visibility.select applies its min_separation as optimize on the scene does."""
    from vis_format import read_vis
    scene, kept_out = constrained_example(cli_example, tmp_path)
    run_cli("observe", scene, "--out", tmp_path / "c.vis")
    raw = read_vis(tmp_path / "c.vis")
    assert raw.version == 10
    # How observe read the scene (format 10): absolute, so that select reloads it from anywhere.
    assert raw.scene_path == os.path.abspath(scene) and os.path.isabs(raw.scene_path)
    assert raw.model_paths == [] and raw.targets == [] and raw.cell_size_override is None
    assert len(raw.part_of) == len(raw.keys) and len(raw.exposed) == len(raw.keys)
    assert set(raw.part_of) <= set(range(len(raw.part_names)))
    assert raw.min_separation == 0.3
    assert [box[0] for box in raw.keep_out] == ["pillar"]
    assert raw.kept_out == 1
    assert kept_out not in [c.name for c in raw.candidates]
    returned = vantage.optimize(scene, n=3, method="local", out=tmp_path / "py")
    (expected,) = returned["results"]
    assert expected["constraints"]["satisfied"]
    selection = vantage.load_visibility(tmp_path / "c.vis").select(n=3, method="local")
    assert (selection.sensors, selection.coverage) == (expected["sensors"], expected["coverage"])
