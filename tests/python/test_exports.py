"""Every export of a run parses with a standard parser whatever the sensors' and targets' names
(issue 44: `cam--left` in an XML comment made cameras.urdf.xacro malformed; `cam 1` and `cam_1`
were one link), frame names are unique and give the sensor's name back by the mapping that
docs/outputs.md ("Frame names") documents; the command in constellation.sdf reproduces the run's
coverage."""

import ast
import csv
import json
import pathlib
import re
import shlex
import subprocess
import xml.etree.ElementTree as ElementTree

import pytest
import yaml

from conftest import BINARY, EXAMPLE, run_cli

# Quotes, "--", "]]>", spaces, non-ASCII, leading digits, xacro's "$", SDF's "::", names that
# collide once sanitised, names ending like an optical frame, the default parent frame.
HOSTILE = ["cam--left", "cam 1", "cam_1", "q'uote\"s", "cdata]]>end", "kamera_ü", "1st",
           "a::b", "a__b", "x/y", "x_y", "$(arg x)${y}", "cam", "cam_optical",
           "cam_optical_frame", "world", "<tag>&amp;", "-dash-", "日本"]
TARGETS = ["cube--v2", "cube v2", "cube_v2"]


def frame_to_name(frame):
    """docs/outputs.md, Frame names: '..' is '::', '.hh' one byte, anything else itself."""
    out = bytearray()
    i = 0
    while i < len(frame):
        if frame[i] != ".":
            assert re.fullmatch(r"[A-Za-z0-9_-]", frame[i]), frame
            out += frame[i].encode()
            i += 1
        elif frame[i + 1] == ".":
            out += b"::"
            i += 2
        else:
            out.append(int(frame[i + 1:i + 3], 16))
            i += 3
    return out.decode("utf-8")


def hostile_scene(folder):
    sensors = []
    for k, name in enumerate(HOSTILE):
        # A ring around the targets, each looking at the observation point.
        sensors.append({"name": name, "type": "tiny_cam",
                        "position": [0.5 * (1 if k % 2 else -1), 0.03 * k - 0.3, 0.4]})
    objects = [{"name": "plate", "role": "occluder", "box": {"size": [0.6, 0.6, 0.02]},
                "pose": {"xyz": [0, 0, -0.01]}}]
    for k, name in enumerate(TARGETS):
        objects.append({"name": name, "role": "target", "box": {"size": [0.05, 0.05, 0.05]},
                        "pose": {"xyz": [0.07 * (k - 1), 0, 0.025]}})
    scene = {"settings": {"cell_size": 0.01, "n": 2, "observation_point": [0, 0, 0.03]},
             "sensor_types": [{"id": "tiny_cam", "resolution": [80, 60], "hfov": 1.0,
                               "range": [0.1, 3.0]}],
             "objects": objects, "sensors": sensors}
    path = folder / "hostile.yaml"
    path.write_text(yaml.safe_dump(scene, allow_unicode=True), encoding="utf-8")
    return path


def launch_calls(text):
    """The _static_transform(node, child, parent, xyz, xyzw) calls of the launch file."""
    calls = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "_static_transform":
            args = node.args
            parent = args[2].value if isinstance(args[2], ast.Constant) else None
            calls.append((args[0].value, args[1].value, parent))
    return calls


@pytest.fixture(scope="module")
def hostile_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hostile")
    scene = hostile_scene(folder)
    # evaluate scores the scene's own sensors: every hostile name is in the primary result.
    run_cli("evaluate", scene, "--out", folder / "out")
    return folder / "out"


def test_every_export_parses_and_frames_are_unique_and_reversible(hostile_run):
    out = hostile_run
    report = json.loads((out / "report.json").read_text(encoding="utf-8"))
    chosen = report["results"][report["primary_result"]]["sensors"]
    assert sorted(chosen) == sorted(HOSTILE)

    # cameras.urdf.xacro: XML; links and joints unique; each body link decodes to its sensor.
    robot = ElementTree.parse(out / "cameras.urdf.xacro").getroot()
    macro = robot.find("{http://www.ros.org/wiki/xacro}macro")
    links = [link.get("name") for link in macro.iter("link")]
    joints = [joint.get("name") for joint in macro.iter("joint")]
    assert len(links) == len(set(links)) == 2 * len(HOSTILE)
    assert len(joints) == len(set(joints)) == 2 * len(HOSTILE)
    body = [link for link in links if not link.endswith("_optical_frame")]
    assert sorted(frame_to_name(frame) for frame in body) == sorted(HOSTILE)
    assert all(f"{frame}_optical_frame" in links for frame in body)
    # No "$" for xacro to expand but its own substitutions.
    text = (out / "cameras.urdf.xacro").read_text(encoding="utf-8")
    text = re.sub(r"<!--.*?-->", "", text, flags=re.S)  # xacro leaves comments alone
    assert set(re.findall(r"\$[({][^)}]*[)}]", text)) == {
        "${parent}", "${-pi/2}", "$(arg parent_frame)", "$(arg vantage_standalone)"}

    # static_transforms.launch.py: Python; node names and child frames unique, the xacro's.
    calls = launch_calls((out / "static_transforms.launch.py").read_text(encoding="utf-8"))
    nodes = [node for node, _, _ in calls]
    children = [child for _, child, _ in calls]
    assert len(nodes) == len(set(nodes)) == 2 * len(HOSTILE)
    assert all(re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", node) for node in nodes)
    assert sorted(children) == sorted(links)

    # static_transforms.yaml: YAML; each body entry names its sensor and its frame, unique.
    transforms = yaml.safe_load((out / "static_transforms.yaml").read_text(encoding="utf-8"))
    entries = transforms["transforms"]
    child_frames = [entry["child_frame"] for entry in entries]
    assert sorted(child_frames) == sorted(links)
    for entry in entries:
        if "type" in entry:  # a body entry
            assert frame_to_name(entry["child_frame"]) == entry["name"]
            assert entry["parent_frame"] == "world"
    assert sorted(entry["name"] for entry in entries if "type" in entry) == sorted(HOSTILE)

    # constellation.sdf: XML; model names unique (SDF wants siblings' names unique).
    world = ElementTree.parse(out / "constellation.sdf").getroot().find("world")
    models = [model.get("name") for model in world.findall("model")]
    assert len(models) == len(set(models)) == len(HOSTILE) + 1 + len(TARGETS)
    topics = [topic.text for topic in world.iter("topic")]
    assert len(topics) == len(set(topics)) == len(HOSTILE)

    # constellation.yaml, candidates.csv: the names as they were.
    constellation = yaml.safe_load((out / "constellation.yaml").read_text(encoding="utf-8"))
    assert sorted(s["name"] for s in constellation["sensors"]) == sorted(HOSTILE)
    with open(out / "candidates.csv", encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    assert sorted(row["name"] for row in rows) == sorted(HOSTILE)


def rescore(folder):
    """Runs the command of constellation.sdf's <vantage:rescore> in its folder; the coverage."""
    root = ElementTree.parse(folder / "constellation.sdf").getroot()
    command = root.find("world").find("{https://vantage.invalid/sdf}rescore").text
    words = shlex.split(command)
    assert words[:3] == ["vantage", "evaluate", "constellation.sdf"], command
    result = subprocess.run([str(BINARY), "-q", *words[1:], "--out", str(folder / "again")],
                            cwd=folder, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    report = json.loads((folder / "again" / "report.json").read_text(encoding="utf-8"))
    return report["results"][report["primary_result"]]["coverage"], command


@pytest.mark.parametrize("options", [
    [],
    ["--cell-size", "0.01", "--max-incidence", "55", "--target", "motor", "--target", "pipe"],
    ["--cell-size", "0.008", "--max-depth-noise", "1.5", "--target", "gear_block"],
], ids=["example", "cell-filter-targets", "cell-noise-target"])
def test_the_rescore_command_reproduces_the_coverage(tmp_path, options):
    run_cli("optimize", EXAMPLE, "-n", "2", "--method", "greedy", *options,
            "--out", tmp_path / "run")
    report = json.loads((tmp_path / "run" / "report.json").read_text(encoding="utf-8"))
    coverage = report["results"][report["primary_result"]]["coverage"]
    again, command = rescore(tmp_path / "run")
    assert again == pytest.approx(coverage, abs=1e-12), command
    words = shlex.split(command)
    assert float(words[words.index("--cell-size") + 1]) == report["cell_size"]


def test_the_rescore_command_quotes_hostile_targets(hostile_run):
    root = ElementTree.parse(hostile_run / "constellation.sdf").getroot()
    command = root.find("world").find("{https://vantage.invalid/sdf}rescore").text
    words = shlex.split(command)
    targets = [words[i + 1] for i, word in enumerate(words) if word == "--target"]
    assert sorted(targets) == sorted(TARGETS)
