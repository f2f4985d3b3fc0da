"""docs/scene.schema.json, the JSON Schema editors use for the YAML scene (issue 46), kept true:
every example scene names it on its first line and validates; scenes vantage refuses for a key
or a value the schema can see (a sample of tests/bad_input_test.cpp's cases) are refused by it
too, each for the key at fault; and vantage itself accepts what the schema accepts there."""

import copy
import json
import pathlib
import subprocess
import os

import jsonschema
import pytest
import yaml

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCHEMA_PATH = ROOT / "docs" / "scene.schema.json"
SCHEMA = json.loads(SCHEMA_PATH.read_text())
EXAMPLES = sorted((ROOT / "examples" / "scenes").glob("*.yaml"))
FIXTURES = sorted((ROOT / "tests" / "data" / "cli").glob("*.yaml"))
EXAMPLE = ROOT / "examples" / "scenes" / "bin_picking_cell.yaml"
BINARY = os.environ.get("VANTAGE_BINARY")


def errors(scene):
    validator = jsonschema.Draft7Validator(SCHEMA)
    return sorted(validator.iter_errors(scene), key=lambda e: list(e.absolute_path))


def test_schema_is_a_valid_draft7_schema():
    jsonschema.Draft7Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_names_the_schema_on_its_first_line(path):
    first = path.read_text().splitlines()[0]
    prefix = "# yaml-language-server: $schema="
    assert first.startswith(prefix), first
    assert (path.parent / first[len(prefix):]).resolve() == SCHEMA_PATH


@pytest.mark.parametrize("path", EXAMPLES + FIXTURES, ids=lambda p: p.name)
def test_scene_validates(path):
    assert errors(yaml.safe_load(path.read_text())) == []


def edited(change):
    scene = yaml.safe_load(EXAMPLE.read_text())
    change(scene)
    return scene


def set_in(path, value):
    def change(scene):
        node = scene
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value
    return change


def drop(path):
    def change(scene):
        node = scene
        for key in path[:-1]:
            node = node[key]
        del node[path[-1]]
    return change


# A sample of the bad-input cases vantage refuses at their line (tests/bad_input_test.cpp), each
# with the path of the key the schema must blame.
BAD = {
    "misspelt_top_key": (set_in(["objcts"], []), []),
    "misspelt_object_key": (set_in(["objects", 1, "rol"], "target"), ["objects", 1]),
    "unknown_role": (set_in(["objects", 1, "role"], "targte"), ["objects", 1, "role"]),
    "no_shape": (drop(["objects", 1, "box"]), ["objects", 1]),
    "two_shapes": (set_in(["objects", 1, "sphere"], {"radius": 0.1}), ["objects", 1]),
    "negative_box": (set_in(["objects", 1, "box", "size"], [1, -1, 1]),
                     ["objects", 1, "box", "size", 1]),
    "box_of_two": (set_in(["objects", 1, "box", "size"], [1, 1]), ["objects", 1, "box", "size"]),
    "zero_cell": (set_in(["settings", "cell_size"], 0), ["settings", "cell_size"]),
    "word_cell": (set_in(["settings", "cell_size"], "fine"), ["settings", "cell_size"]),
    "zero_n": (set_in(["settings", "n"], 0), ["settings", "n"]),
    "unknown_method": (set_in(["settings", "method"], "fastest"), ["settings", "method"]),
    "goal_above_one": (set_in(["settings", "goal"], 1.5), ["settings", "goal"]),
    "stop_above_one": (set_in(["settings", "ransac", "stop_coverage"], 2), ["settings", "ransac",
                                                                           "stop_coverage"]),
    "two_rotations": (set_in(["objects", 1, "pose"], {"rpy": [0, 0, 1], "quaternion": [1, 0, 0, 0]}),
                      ["objects", 1, "pose"]),
    "short_xyz": (set_in(["objects", 1, "pose", "xyz"], [0, 0]), ["objects", 1, "pose", "xyz"]),
    "zero_count": (set_in(["populations", 0, "count"], 0), ["populations", 0, "count"]),
    "unknown_distribution": (set_in(["populations", 0, "distribution"], "even"),
                             ["populations", 0, "distribution"]),
    "population_without_type": (drop(["populations", 0, "type"]), ["populations", 0]),
    "object_without_name": (drop(["objects", 1, "name"]), ["objects", 1]),
    "mesh_without_file": (set_in(["objects", 1], {"name": "m", "mesh": {"scale": 1}}),
                          ["objects", 1, "mesh"]),
    "zero_scale": (set_in(["objects", 1], {"name": "m", "mesh": {"file": "m.stl", "scale": 0}}),
                   ["objects", 1, "mesh", "scale"]),
    "min_separation_zero": (set_in(["min_separation"], 0), ["min_separation"]),
    "keep_out_size_and_min": (set_in(["keep_out"], [{"size": [1, 1, 1], "min": [0, 0, 0],
                                                     "max": [1, 1, 1]}]), ["keep_out", 0]),
    "sensor_type_without_id": (set_in(["sensor_types", 0], {"base": "photoneo_phoxi_s"}),
                               ["sensor_types", 0]),
    "hfov_above_pi": (set_in(["sensor_types", 0, "hfov"], 4.0), ["sensor_types", 0, "hfov"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_is_refused_at_its_key(name):
    change, blamed = BAD[name]
    found = errors(edited(change))
    assert found, f"{name}: the schema accepted it"
    paths = [list(e.absolute_path) for e in found]
    assert blamed in paths, f"{name}: blamed {paths}, not {blamed}"


@pytest.mark.skipif(not BINARY, reason="VANTAGE_BINARY is not set (CTest sets it)")
@pytest.mark.parametrize("name", ["misspelt_object_key", "unknown_role", "zero_cell",
                                  "unknown_method", "two_rotations", "zero_count"])
def test_vantage_refuses_them_too(name, tmp_path):
    # The schema refuses no more than vantage does for these: both say no, vantage at the line.
    scene = edited(BAD[name][0])
    path = tmp_path / "scene.yaml"
    text = yaml.safe_dump(scene, sort_keys=False)
    path.write_text(text.replace("../meshes/", str(EXAMPLE.parent.parent / "meshes") + "/"))
    result = subprocess.run([BINARY, "-q", "optimize", str(path), "--out", str(tmp_path / "out")],
                            capture_output=True, text=True)
    assert result.returncode == 2, result.stderr
    assert str(path) + ":" in result.stderr


ARM_EXAMPLE = ROOT / "examples" / "scenes" / "arm_wrist_camera.yaml"


@pytest.mark.parametrize("change,blamed", [
    # An `arm` population has no region (vantage: "an `arm` population takes no 'box'").
    (lambda s: s["populations"][1].update(box={"size": [1, 1, 1]}), ["populations", 1]),
    (lambda s: s["populations"][1]["arm"].update(sampling="sobol"),
     ["populations", 1, "arm", "sampling"]),
    (lambda s: s["populations"][1]["arm"].update(configurations=[{"wrist_1_joint": 0}]),
     ["populations", 1, "arm"]),
    (lambda s: s["populations"][0]["reach"].update(match="roll"),
     ["populations", 0, "reach", "match"]),
    (lambda s: s["populations"][0]["reach"].update(restarts=0),
     ["populations", 0, "reach", "restarts"]),
], ids=["arm_with_region", "unknown_sampling", "sampling_and_list", "unknown_match",
        "zero_restarts"])
def test_arm_keys_are_checked(change, blamed):
    scene = yaml.safe_load(ARM_EXAMPLE.read_text())
    assert errors(scene) == []
    change(scene)
    paths = [list(e.absolute_path) for e in errors(scene)]
    assert blamed in paths, paths
