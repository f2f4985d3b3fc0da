"""Every keyword argument and dict entry of the module, one table (issue 44): a value of the wrong
type raises TypeError naming the keyword, a value of the right type that no option takes (too
large for any double or integer, negative where a count is meant, a NUL in a path) raises
vantage.InputError naming it; never RuntimeError "Unable to cast Python instance"."""

import inspect

import pytest

import vantage
from conftest import CUBE_CELL

REAL = {"type": ["sixty", True, [1.0], 1j], "value": [10**400, -(10**400)]}
INT = {"type": ["three", 2.5, True, object()], "value": [2**70, -(2**70)]}
UNSIGNED = {"type": ["x", 1.5, False], "value": [-1, 2**64]}
BOOL = {"type": ["yes", 1, 0.0], "value": []}
TEXT = {"type": [5, b"greedy", ["exact"]], "value": []}
POINT = {"type": ["abc", 5, (0, "a", 0), (0, None, 0)], "value": [(1, 2), (0, 10**400, 0)]}
PATH = {"type": [5, 2.0, object()], "value": ["a\0b"]}
PATHS = {"type": [5, [5]], "value": [["a\0b"]]}
CALLABLE = {"type": [5, "print"], "value": []}
# Visibility.from_matrix (issue 42), called on a 2 x 3 matrix given as (indptr, indices), cells=3.
CSR = {"type": [5, "m.npz", object(), ([0, 1, 3], [0.0, 1.0, 2.0])],
       "value": [([0, 2, 3], [1, 0, 2]), ([0, 2, 3], [1, 1, 2]), ([0, 1, 3], [0, 1, 7]),
                 ([0, 1, 3], [0, 1, 2], [1, 0, 1]), ([0, 1, 3, 2], [0, 1])]}
NAMES = {"type": [5, "ab", ["a", 2], [b"a", b"b"]],
         "value": [["a", "a"], ["a"], ["", "b"], ["a\n", "b"], ["a", "\udcff"]]}
COSTS = {"type": ["ab", 1.0, ["a", 1], [None, 1]],
         "value": [[float("nan"), 1], [-1, 1], [1], [10**400, 1], [1, float("inf")]]}
STATES = {"type": [], "value": [["empty", "full", "full"], 5]}
# (metres, degrees): pose_tolerance.
PAIR = {"type": ["0.02,2", 5, (0.02, "a"), (None, 2)], "value": [(0.02,), (0.02, 10**400)]}

# keyword -> kind, for every keyword of every function (checked against the signatures below).
KINDS = {
    "cell_size": REAL, "time_limit": REAL, "goal": REAL, "budget": REAL, "stop": REAL,
    "max_memory": REAL, "fov_tolerance": REAL, "alternatives_within": REAL,
    "interference_overlap": REAL, "calibration_overlap_frac": REAL, "min_density": REAL,
    "max_seconds": REAL, "cycle_time": REAL, "joint_speed": REAL, "motion_resolution": REAL,
    "plan_time": REAL, "move_penalty": REAL, "state_interval": REAL, "fov": REAL,
    "n": INT, "k": INT, "iterations": INT, "threads": INT, "refine_rounds": INT,
    "min_points": INT, "pose_samples": INT, "frames": INT, "width": INT, "height": INT,
    "arm_view": INT,
    "seed": UNSIGNED, "calibration_overlap": UNSIGNED,
    "random_roll": BOOL, "cull": BOOL, "refine": BOOL, "interference": BOOL,
    "physical": BOOL, "exposed_only": BOOL, "cheapest": BOOL, "keep_existing": BOOL,
    "by_type": BOOL, "track": BOOL, "frusta": BOOL, "from_below": BOOL, "legend": BOOL,
    "method": TEXT, "over_states": TEXT, "over_parts": TEXT,
    "observation_point": POINT, "eye": POINT, "look_at": POINT, "pose_tolerance": PAIR,
    "out": PATH, "constellation": PATH, "file": PATH, "run": PATH, "png": PATH,
    "model_path": PATHS, "resource_path": PATHS, "package_path": PATHS,
    "progress": CALLABLE,
    "cells": UNSIGNED, "csr": CSR, "names": NAMES, "costs": COSTS, "states": STATES,
}
# Checked elsewhere with their own messages: the scene/file positional, targets and quality.
OWN_TESTS = {"path", "scene", "targets", "quality", "level"}


@pytest.fixture(scope="module")
def subjects(tmp_path_factory):
    folder = tmp_path_factory.mktemp("arguments")
    problem = vantage.load(CUBE_CELL)
    vis = problem.observe(threads=1)
    vantage.optimize(CUBE_CELL, n=1, method="greedy", out=folder / "run")
    vis.save(folder / "cube.vis")
    calls = {
        "load": lambda **kw: vantage.load(CUBE_CELL, **kw),
        "observe": lambda **kw: problem.observe(**kw),
        "select": lambda **kw: vis.select(**{"n": 1, "method": "greedy", **kw}),
        "select_all": lambda **kw: vis.select_all(**{"n": 1, "method": "greedy", **kw}),
        "optimize": lambda **kw: vantage.optimize(CUBE_CELL, **{"n": 1, "method": "greedy", **kw}),
        "evaluate": lambda **kw: vantage.evaluate(
            CUBE_CELL, **{"constellation": folder / "run" / "report.json", **kw}),
        "from_matrix": lambda **kw: vantage.Visibility.from_matrix(
            **{"csr": ([0, 1, 3], [0, 1, 2]), "cells": 3, **kw}),
        "select_file": lambda **kw: vantage.select(
            **{"file": folder / "cube.vis", "n": 1, "method": "greedy", **kw}),
        "render": lambda **kw: vantage.render(
            **{"run": folder / "run", "png": folder / "view.png", "width": 16, "height": 16,
               **kw}),
    }
    functions = {"load": vantage.load, "observe": vantage.Problem.observe,
                 "select": vantage.Visibility.select, "select_all": vantage.Visibility.select_all,
                 "optimize": vantage.optimize, "evaluate": vantage.evaluate,
                 "from_matrix": vantage.Visibility.from_matrix, "select_file": vantage.select,
                 "render": vantage.render}
    return calls, functions


def keywords(function):
    """The keyword names in pybind11's signature line of the docstring."""
    signature = function.__doc__.splitlines()[0]
    inside = signature[signature.index("(") + 1:signature.rindex(")")]
    names = []
    for part in inside.split(","):
        name = part.strip().split(":")[0].strip()
        if name and name not in ("*", "self"):
            names.append(name)
    return names


def cases():
    for function in ["load", "observe", "select", "select_all", "optimize", "evaluate",
                     "from_matrix", "select_file", "render"]:
        for kind_name, kind in KINDS.items():
            for wrong in kind["type"]:
                yield function, kind_name, wrong, TypeError
            for bad in kind["value"]:
                yield function, kind_name, bad, vantage.InputError


def test_the_table_covers_every_keyword(subjects):
    _, functions = subjects
    for name, function in functions.items():
        missing = set(keywords(function)) - set(KINDS) - OWN_TESTS
        assert not missing, f"{name}: keywords without a row: {missing}"


@pytest.mark.parametrize("function,key,value,error",
                         [c for c in cases()],
                         ids=[f"{c[0]}-{c[1]}-{type(c[2]).__name__}-{c[3].__name__}"
                              for c in cases()])
def test_wrong_type_and_bad_value(subjects, function, key, value, error):
    calls, functions = subjects
    if key not in keywords(functions[function]):
        pytest.skip(f"{function} has no {key}")
    with pytest.raises(error) as raised:
        calls[function](**{key: value})
    assert type(raised.value) is error or isinstance(raised.value, error)
    assert str(raised.value).startswith(f"{key}") or f"{key}:" in str(raised.value), \
        str(raised.value)


@pytest.mark.parametrize("value,error", [
    ("sixty", TypeError), (True, TypeError), ([60], TypeError),
    (10**400, vantage.InputError), (-(10**400), vantage.InputError)])
@pytest.mark.parametrize("key", ["max_incidence", "max_depth_noise"])
def test_quality_entries(subjects, key, value, error):
    calls, _ = subjects
    with pytest.raises(error, match=rf"^quality\['{key}'\]"):
        calls["observe"](quality={key: value})
    with pytest.raises(error, match=rf"^quality\['{key}'\]"):
        calls["optimize"](quality={key: value})


def test_quality_itself(subjects):
    calls, _ = subjects
    with pytest.raises(TypeError, match="^quality: give a dict"):
        calls["observe"](quality=60)
    with pytest.raises(TypeError, match="^quality: every key is a str"):
        calls["observe"](quality={1: 60})
    with pytest.raises(vantage.InputError, match="^quality: unknown key 'sixty'"):
        calls["observe"](quality={"sixty": 60})


def test_positional_paths_and_words(subjects, tmp_path):
    with pytest.raises(TypeError, match="^path: give a path"):
        vantage.load(5)
    with pytest.raises(TypeError, match="^scene: give a path"):
        vantage.optimize(5.0, n=1)
    with pytest.raises(TypeError, match="^path: give a path"):
        vantage.load_visibility(None)
    with pytest.raises(vantage.InputError, match="^path: .* holds a NUL"):
        vantage.load_visibility("a\0b")
    calls, _ = subjects
    with pytest.raises(TypeError):
        vantage.set_log_level(3)
    with pytest.raises(vantage.InputError, match="^level: unknown log level"):
        vantage.set_log_level("loud")


def test_numpy_numbers_are_numbers(subjects):
    np = pytest.importorskip("numpy")
    calls, _ = subjects
    problem = calls["load"](cell_size=np.float64(0.01), seed=np.uint64(3),
                            observation_point=np.array([0.0, 0.0, 0.05]),
                            random_roll=np.bool_(False))
    assert problem.cell_size == 0.01 and problem.seed == 3
    selection = calls["select"](n=np.int64(2), time_limit=np.float32(5))
    assert selection.n == 2
