"""The keywords that mirror the CLI's newer flags (sensor model, exposed-only, cheapest,
keep-existing, point density, pose tolerance, by-type, package paths, arm tours): each gives the
report.json that the `vantage` binary, run here, writes for the same flags (timings aside), and
each refusal is the CLI's."""

import pathlib
import re

import pytest

import vantage
from conftest import EXAMPLE, ROOT, normalised, read_report, run_cli
from vis_format import read_vis

ARM_WRIST = ROOT / "examples" / "scenes" / "arm_wrist_camera.yaml"
ARM_TRACK = ROOT / "examples" / "scenes" / "arm_track_hand.yaml"
DEEP_BIN = ROOT / "examples" / "scenes" / "deep_bin.yaml"
STATES = ROOT / "examples" / "scenes" / "bin_picking_states.yaml"
QUICK = (["-n", 2, "--method", "greedy"], {"n": 2, "method": "greedy"})

# (id, scene, CLI flags, keywords): each run once by the CLI and once by vantage.optimize.
CASES = [
    ("ideal", EXAMPLE, ["--ideal"], {"physical": False}),
    ("physical", EXAMPLE, ["--physical"], {"physical": True}),
    ("exposed_only", EXAMPLE, ["--exposed-only"], {"exposed_only": True}),
    ("cheapest", EXAMPLE, ["--goal", 0.6, "--cheapest", "--method", "greedy"],
     {"goal": 0.6, "cheapest": True, "method": "greedy"}),
    ("keep_existing", EXAMPLE, ["--keep-existing", "-n", 3, "--method", "greedy"],
     {"keep_existing": True, "n": 3, "method": "greedy"}),
    ("min_points", EXAMPLE, ["--min-points", 4], {"min_points": 4}),
    ("min_density", EXAMPLE, ["--min-density", 10], {"min_density": 10}),
    ("pose_tolerance", EXAMPLE, ["--pose-tolerance", "0.02,2", "--pose-samples", 6],
     {"pose_tolerance": (0.02, 2), "pose_samples": 6}),
    ("by_type", EXAMPLE, ["--by-type"], {"by_type": True}),
    ("over_parts", DEEP_BIN, ["--over-parts", "min"], {"over_parts": "min"}),
    ("over_states_sum", STATES, ["--over-states", "sum"], {"over_states": "sum"}),
    ("max_seconds", EXAMPLE, ["--max-seconds", 3600], {"max_seconds": 3600}),
    ("cycle_time", ARM_WRIST, ["--cycle-time", 6, "--joint-speed", 2, "--frames", 2,
                               "--motion-resolution", 0.02, "--plan-time", 1],
     {"cycle_time": 6, "joint_speed": 2, "frames": 2, "motion_resolution": 0.02,
      "plan_time": 1}),
    ("track", ARM_TRACK, ["--track", "--move-penalty", 0.01, "--state-interval", 5],
     {"track": True, "move_penalty": 0.01, "state_interval": 5}),
]


def quick(flags, kwargs):
    """n = 2 by greedy unless the case chooses otherwise (keeps each run under a second)."""
    flags = list(flags)
    kwargs = dict(kwargs)
    if not {"n", "method", "goal", "cycle_time", "track"} & set(kwargs):
        flags = QUICK[0] + flags
        kwargs.update(QUICK[1])
    return flags, kwargs


@pytest.mark.parametrize("scene,flags,kwargs", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_optimize_as_cli(scene, flags, kwargs, tmp_path):
    flags, kwargs = quick(flags, kwargs)
    run_cli("optimize", scene, *flags, "--out", tmp_path / "cli")
    returned = vantage.optimize(scene, out=tmp_path / "py", **kwargs)
    cli = normalised(read_report(tmp_path / "cli"))
    assert normalised(read_report(tmp_path / "py")) == cli
    assert normalised(returned) == cli
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == \
        sorted(p.name for p in (tmp_path / "cli").iterdir())


def test_each_option_reached_the_run(tmp_path):
    """Not only equal to the CLI: each keyword changed what the run reports (a keyword the
    module dropped would give the default run, which the CLI with the flag does not)."""
    plain = vantage.optimize(EXAMPLE, n=2, method="greedy")
    assert "sensor_model" in plain  # the example is a YAML scene: physical by default
    ideal = vantage.optimize(EXAMPLE, n=2, method="greedy", physical=False)
    assert "sensor_model" not in ideal and "ideal_coverage" not in ideal["results"][0]
    exposed = vantage.optimize(EXAMPLE, n=2, method="greedy", exposed_only=True)
    assert exposed["ceiling"]["exposed_only"] is True
    assert exposed["reference_voxels"] == \
        plain["reference_voxels"] - plain["ceiling"]["unexposed_voxels"]
    cheap = vantage.optimize(EXAMPLE, goal=0.6, cheapest=True, method="greedy")
    assert cheap["inputs"]["cheapest"] is True and cheap["results"][0]["cost"] > 0
    kept = vantage.optimize(EXAMPLE, n=3, method="greedy", keep_existing=True)
    declared = [c["name"] for c in kept["candidates"] if c["population"] == ""]
    assert declared and set(declared) <= set(kept["results"][0]["sensors"])
    posed = vantage.optimize(EXAMPLE, n=2, method="greedy", pose_tolerance=(0.02, 2),
                             pose_samples=6)
    assert (posed["pose_tolerance"]["position_m"], posed["pose_tolerance"]["angle_deg"],
            posed["pose_tolerance"]["samples"]) == (0.02, 2, 6)
    typed = vantage.optimize(EXAMPLE, n=2, method="greedy", by_type=True)
    assert {t["type"] for t in typed["by_type"]["types"]} == \
        {c["type"] for c in typed["candidates"]}


def test_ideal_matrix_is_the_cli_files(tmp_path):
    """observe(physical=False) gives the sets of `vantage observe --ideal`, read from the file
    by the independent reader; the default gives `vantage observe`'s physical ones."""
    run_cli("observe", EXAMPLE, "--ideal", "--out", tmp_path / "ideal.vis")
    run_cli("observe", EXAMPLE, "--out", tmp_path / "physical.vis")
    problem = vantage.load(EXAMPLE)
    for physical, name in ((False, "ideal.vis"), (None, "physical.vis")):
        raw = read_vis(tmp_path / name)
        assert raw.physical == (physical is None)
        matrix = problem.observe(physical=physical).matrix
        assert [list(matrix.indices[matrix.indptr[i]:matrix.indptr[i + 1]])
                for i in range(matrix.shape[0])] == \
            [list(c.reference_indices) for c in raw.candidates]


def test_exposed_only_reference_is_the_cli_files(tmp_path):
    run_cli("observe", EXAMPLE, "--exposed-only", "--out", tmp_path / "e.vis")
    raw = read_vis(tmp_path / "e.vis")
    vis = vantage.load(EXAMPLE, exposed_only=True).observe()
    assert raw.exposed_only
    assert list(vis.reference_keys) == list(raw.keys)
    assert len(raw.keys) < len(vantage.load(EXAMPLE).observe().reference_keys)


@pytest.mark.parametrize("flags,kwargs", [
    (["--goal", 0.6, "--cheapest", "--method", "exact"],
     {"goal": 0.6, "cheapest": True, "method": "exact"}),
    (["--keep-existing", "-n", 3, "--method", "local"],
     {"keep_existing": True, "n": 3, "method": "local"}),
], ids=["cheapest", "keep_existing"])
def test_select_as_cli(cli_example, example_vis, flags, kwargs, tmp_path):
    run_cli("select", cli_example / "example.vis", *flags, "--out", tmp_path / "cli")
    (expected,) = read_report(tmp_path / "cli")["results"]
    got = example_vis.select(**kwargs)
    assert got.sensors == expected["sensors"]
    assert got.coverage == expected["coverage"]
    assert got.cost == expected.get("cost")
    (listed,) = example_vis.select_all(**kwargs)
    assert listed.sensors == expected["sensors"]


def test_cheapest_exact_is_the_least_cost(example_vis):
    """The cheapest layout reaching the goal costs no more than the fewest-sensors one, and
    exact proves its cost: nothing cheaper reaches the goal (cost_lower_bound == cost)."""
    cheapest = example_vis.select(goal=0.6, cheapest=True, method="exact")
    fewest = example_vis.select(goal=0.6, method="exact")
    assert cheapest.coverage >= 0.6 and cheapest.optimal
    costs = {c.name: c.cost for c in example_vis.candidates}
    assert cheapest.cost == pytest.approx(sum(costs[s] for s in cheapest.sensors))
    assert cheapest.cost <= sum(costs[s] for s in fewest.sensors) + 1e-9


def test_evaluate_as_cli(cli_example, tmp_path):
    constellation = cli_example / "optimize" / "report.json"
    flags = ["--pose-tolerance", "0.01,1", "--pose-samples", 4, "--ideal"]
    run_cli("evaluate", EXAMPLE, "--constellation", constellation, *flags,
            "--out", tmp_path / "cli")
    result = vantage.evaluate(EXAMPLE, constellation=constellation, pose_tolerance=(0.01, 1),
                              pose_samples=4, physical=False, out=tmp_path / "py")
    assert normalised(result["report"]) == normalised(read_report(tmp_path / "cli"))
    assert result["report"]["pose_tolerance"]["samples"] == 4
    # Without a constellation: the sensors the scene declares, as the CLI without one.
    run_cli("evaluate", EXAMPLE, "--out", tmp_path / "cli_declared")
    declared = vantage.evaluate(EXAMPLE, out=tmp_path / "py_declared")
    assert normalised(declared["report"]) == normalised(read_report(tmp_path / "cli_declared"))
    assert declared["sensors"] == read_report(tmp_path / "cli_declared")["results"][0]["sensors"]


def test_package_path_as_cli(tmp_path, monkeypatch):
    """A URDF whose mesh is a package:// path loads through package_path, as --package-path."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    urdf = ROOT / "tests" / "data" / "urdf" / "mesh_arm.urdf"
    packages = ROOT / "tests" / "data" / "urdf" / "packages"
    scene = tmp_path / "scene.yaml"
    scene.write_text(
        "objects:\n  - {name: part, role: target, box: {size: [0.1, 0.1, 0.1]}}\n"
        f"robots:\n  - name: arm\n    urdf: {urdf}\n    joints:\n      {{}}\n"
        "sensors:\n  - {name: cam, type: intel_realsense_d415, position: [1, 0, 1]}\n",
        encoding="utf-8")
    with pytest.raises(vantage.InputError, match="package 'arm3_description'"):
        vantage.load(scene)
    run_cli("optimize", scene, "--package-path", packages, "--out", tmp_path / "cli")
    returned = vantage.optimize(scene, package_path=packages, out=tmp_path / "py")
    assert normalised(returned) == normalised(read_report(tmp_path / "cli"))
    assert returned["inputs"]["package_paths"] == [str(packages)]
    assert vantage.load(scene, package_path=[packages]).candidates[0].name == "cam"


# Refusals: the CLI's message for the same flags, word for word after the option's name.
REFUSALS = [
    ({"by_type": True, "goal": 0.5}, ["--by-type", "--goal", 0.5], "--by-type: "),
    ({"keep_existing": True, "n": 2}, ["--keep-existing", "-n", 2], "--keep-existing: "),
    ({"cheapest": True, "n": 2}, ["--cheapest", "-n", 2], "--cheapest: "),
    ({"move_penalty": 0.1}, ["--move-penalty", 0.1], "--move-penalty: "),
    ({"cycle_time": 5}, ["--cycle-time", 5], "--cycle-time: "),
    ({"pose_tolerance": (2, 1)}, ["--pose-tolerance", "2,1"], "--pose-tolerance"),
    ({"max_seconds": -1}, ["--max-seconds", -1], "--max-seconds"),
    ({"over_parts": "sum"}, ["--over-parts", "sum"], "--over-parts: "),
]


@pytest.mark.parametrize("kwargs,flags,prefix", REFUSALS,
                         ids=[r[2].strip(": ") for r in REFUSALS])
def test_refusals_as_cli(kwargs, flags, prefix, tmp_path):
    from conftest import CUBE_CELL  # 16 candidates and no declared sensors
    with pytest.raises(vantage.InputError) as raised:
        vantage.optimize(CUBE_CELL, out=tmp_path / "py", **kwargs)
    assert str(raised.value).startswith(prefix), str(raised.value)
    assert not (tmp_path / "py").exists()
    cli = run_cli("optimize", CUBE_CELL, *flags, "--out", tmp_path / "cli", check=False)
    assert cli.returncode == 2
    if not prefix.endswith(": "):  # CLI11 checks these itself, with its own wording
        return
    assert str(raised.value) in cli.stderr, cli.stderr


def test_python_only_refusals(tmp_path):
    with pytest.raises(vantage.InputError, match="^pose_samples: only pose_tolerance"):
        vantage.optimize(EXAMPLE, n=1, method="best", pose_samples=8)
    with pytest.raises(vantage.InputError, match=r"^pose_tolerance: has 3 values"):
        vantage.optimize(EXAMPLE, n=1, method="best", pose_tolerance=(0.01, 1, 1))
    with pytest.raises(TypeError, match=r"^pose_tolerance: give a pair"):
        vantage.optimize(EXAMPLE, n=1, method="best", pose_tolerance="0.02,2")
    from conftest import CUBE_CELL  # no declared sensors to keep
    with pytest.raises(vantage.InputError, match="^--keep-existing: .* declares no sensors"):
        vantage.load(CUBE_CELL).observe().select(n=2, keep_existing=True)


@pytest.mark.parametrize("flags,kwargs", [
    (["-n", 2, "--interference-overlap", 0.2], {"n": 2, "interference_overlap": 0.2}),
    (["-n", 2, "--method", "local", "--fov-tolerance", 2, "--alternatives-within", 3,
      "--pose-tolerance", "0.01,1", "--pose-samples", 4, "--seed", 5],
     {"n": 2, "method": "local", "fov_tolerance": 2, "alternatives_within": 3,
      "pose_tolerance": (0.01, 1), "pose_samples": 4, "seed": 5}),
    (["--goal", 0.6, "--cheapest", "--method", "exact"],
     {"goal": 0.6, "cheapest": True, "method": "exact"}),
    (["--keep-existing", "-n", 3, "--method", "greedy", "--min-points", 2],
     {"keep_existing": True, "n": 3, "method": "greedy", "min_points": 2}),
], ids=["all", "assessed", "cheapest", "keep_existing"])
def test_select_file_as_cli(cli_example, flags, kwargs, tmp_path):
    """vantage.select(FILE) is `vantage select FILE`: the same report.json and files."""
    vis = cli_example / "example.vis"
    run_cli("select", vis, *flags, "--out", tmp_path / "cli")
    returned = vantage.select(vis, out=tmp_path / "py", **kwargs)
    cli = normalised(read_report(tmp_path / "cli"))
    assert normalised(read_report(tmp_path / "py")) == cli
    assert normalised(returned) == cli
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == \
        sorted(p.name for p in (tmp_path / "cli").iterdir())
    if "pose_tolerance" in kwargs:
        assert returned["pose_tolerance"]["samples"] == 4
        assert returned["robustness"]["fov_tolerance_deg"] == 2


def test_select_file_refusals(cli_example, tmp_path):
    vis = cli_example / "example.vis"
    with pytest.raises(vantage.InputError, match="^--over-states: a visibility file holds one"):
        vantage.select(vis, over_states="min", out=tmp_path / "py")
    with pytest.raises(TypeError, match="^file: give a path"):
        vantage.select(None)
    assert not (tmp_path / "py").exists()


def test_observe_n_is_the_cli_files(tmp_path):
    """observe(n=2) stores n = 2 with the matrix as `vantage observe -n 2`: the same bytes."""
    run_cli("observe", EXAMPLE, "-n", 2, "--out", tmp_path / "cli.vis")
    problem = vantage.load(EXAMPLE)
    problem.observe(n=2).save(tmp_path / "py.vis")
    assert (tmp_path / "py.vis").read_bytes() == (tmp_path / "cli.vis").read_bytes()
    problem.observe().save(tmp_path / "plain.vis")
    assert (tmp_path / "plain.vis").read_bytes() != (tmp_path / "cli.vis").read_bytes()
    assert [s.n for s in vantage.load_visibility(tmp_path / "py.vis").select_all()][-1] == 2
    with pytest.raises(vantage.InputError, match="^-n: "):
        problem.observe(n=0)


@pytest.mark.parametrize("flags,kwargs", [
    ([], {}),
    (["--eye", 0.6, -0.5, 0.7, "--look-at", 0, 0, 0.05, "--fov", 50, "--no-frusta",
      "--no-legend"],
     {"eye": (0.6, -0.5, 0.7), "look_at": (0, 0, 0.05), "fov": 50, "frusta": False,
      "legend": False}),
    (["--from-below"], {"from_below": True}),
], ids=["default", "viewpoint", "from_below"])
def test_render_is_the_cli_png(flags, kwargs, tmp_path):
    """render() writes the PNG `vantage render` writes for the same flags, byte for byte."""
    from conftest import CUBE_CELL
    run_cli("optimize", CUBE_CELL, "-n", 2, "--method", "greedy", "--out", tmp_path / "run")
    size = ["--width", 96, "--height", 64]
    run_cli("render", tmp_path / "run", *size, *flags, "--png", tmp_path / "cli.png")
    result = vantage.render(tmp_path / "run", png=tmp_path / "py.png", width=96, height=64,
                            **kwargs)
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    assert result["png"] == str(tmp_path / "py.png") and result["sensors"] == 2
    primary = read_report(tmp_path / "run")
    assert result["coverage"] == \
        pytest.approx(primary["results"][primary["primary_result"]]["coverage"], abs=1e-12)


def test_render_refusals(tmp_path):
    from conftest import CUBE_CELL
    vantage.optimize(CUBE_CELL, n=1, method="best", out=tmp_path / "run")
    with pytest.raises(vantage.InputError, match="^width: 8 is out of range — give 16 to 8192"):
        vantage.render(tmp_path / "run", width=8)
    with pytest.raises(vantage.InputError, match="^fov: 0 is out of range — give 1 to 170"):
        vantage.render(tmp_path / "run", fov=0)
    with pytest.raises(vantage.InputError, match="^png: the path is empty"):
        vantage.render(tmp_path / "run", png="")
    with pytest.raises(vantage.InputError, match="--arm-view"):
        vantage.render(tmp_path / "run", arm_view=2, width=16, height=16)
    assert not (tmp_path / "run" / "view.png").exists()


def test_arm_views_kept_in_the_vis_are_optimizes(tmp_path):
    """The .vis of an arm scene (format 11) keeps each view's joints: read by the independent
    reader they are the positions optimize's views.yaml gives the same views (written to 9
    significant digits), and `select` of the file gives optimize's views.yaml byte for byte."""
    run_cli("observe", ARM_WRIST, "--out", tmp_path / "arm.vis")
    raw = read_vis(tmp_path / "arm.vis")
    assert raw.version == 11
    assert all(c.arm is not None for c in raw.candidates)  # every population is on the arm
    by_name = {c.name: c for c in raw.candidates}
    run_cli("optimize", ARM_WRIST, "-n", 4, "--method", "greedy", "--out", tmp_path / "o")
    views = (tmp_path / "o" / "views.yaml").read_text(encoding="utf-8")
    (joint_names,) = re.findall(r"^joint_names: \[(.*)\]$", views, re.M)
    listed = re.findall(r"^  - name: (\S+)\n    positions: \[(.*)\]$", views, re.M)
    assert len(listed) == 4
    for name, positions in listed:
        robot, names, joints = by_name[name].arm
        assert robot == "arm" and names == joint_names.split(", ")
        assert joints == pytest.approx([float(p) for p in positions.split(", ")], rel=1e-8,
                                       abs=1e-12)
    run_cli("select", tmp_path / "arm.vis", "-n", 4, "--method", "greedy",
            "--out", tmp_path / "s")
    assert (tmp_path / "s" / "views.yaml").read_text(encoding="utf-8") == views


def test_select_of_an_arm_file_as_cli(tmp_path):
    """vantage.select of a format-11 file with an arm's tour keywords gives the CLI's report
    (the cycle-time choice and its tour) and views.yaml for the same flags."""
    run_cli("observe", ARM_WRIST, "--out", tmp_path / "arm.vis")
    run_cli("select", tmp_path / "arm.vis", "--cycle-time", 6, "--joint-speed", 2, "--frames", 2,
            "--motion-resolution", 0.02, "--plan-time", 1, "--out", tmp_path / "cli")
    returned = vantage.select(tmp_path / "arm.vis", out=tmp_path / "py", cycle_time=6,
                              joint_speed=2, frames=2, motion_resolution=0.02, plan_time=1)
    report = read_report(tmp_path / "cli")
    assert normalised(returned) == normalised(report)
    (result,) = report["results"]
    assert result["method"] == "cycle-time" and report["cycle_time"] == 6
    assert 0 < result["tour"]["seconds"] <= 6  # the tour's time, not a timing
    assert (tmp_path / "py" / "views.yaml").read_text(encoding="utf-8") == \
        (tmp_path / "cli" / "views.yaml").read_text(encoding="utf-8")
