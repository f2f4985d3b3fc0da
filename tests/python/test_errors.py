"""Bad input raises vantage.InputError (a ValueError) with the CLI's message; the interpreter
never aborts."""

import os

import pytest

import vantage
from conftest import CUBE_CELL, EXAMPLE, run_cli


def cli_error(*args):
    result = run_cli(*args, check=False)
    assert result.returncode == 2, result.stderr
    return result.stderr.strip().removeprefix("[error] ")


def test_broken_scene_names_the_line(tmp_path):
    lines = EXAMPLE.read_text(encoding="utf-8").splitlines()
    at = next(i for i, line in enumerate(lines) if line.strip().startswith("cell_size:"))
    lines[at] = lines[at].split(":")[0] + ": -0.5"
    (tmp_path / "scenes").mkdir()
    (tmp_path / "meshes").symlink_to(EXAMPLE.parent.parent / "meshes")  # ../meshes/ as written
    broken = tmp_path / "scenes" / "broken.yaml"
    broken.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(vantage.InputError) as error:
        vantage.load(broken)
    assert isinstance(error.value, ValueError)
    message = str(error.value)
    assert message.startswith(f"{broken}:{at + 1}:"), message
    assert message == cli_error("optimize", broken, "--out", tmp_path / "out")
    with pytest.raises(vantage.InputError, match=f"^{broken}:{at + 1}:"):
        vantage.optimize(broken, out=tmp_path / "py")
    assert not (tmp_path / "py").exists()


def test_yaml_syntax_error(tmp_path):
    broken = tmp_path / "syntax.yaml"
    broken.write_text("objects:\n  - name: a\n    mesh: [unclosed\n", encoding="utf-8")
    with pytest.raises(vantage.InputError) as error:
        vantage.load(broken)
    assert str(error.value) == cli_error("optimize", broken, "--out", tmp_path / "out")
    assert str(error.value).startswith(f"{broken}:")


def test_missing_file():
    with pytest.raises(vantage.InputError, match="nowhere.yaml"):
        vantage.load("nowhere.yaml")


def test_option_errors_name_the_option(example_vis, example_problem, tmp_path):
    with pytest.raises(vantage.InputError, match=r"^-n: "):
        example_vis.select(n=0, method="greedy")
    with pytest.raises(vantage.InputError, match=r"^method: unknown method 'fastest'"):
        example_vis.select(n=2, method="fastest")
    with pytest.raises(vantage.InputError, match=r"^method: 'all'"):
        example_vis.select(n=2, method="all")
    with pytest.raises(vantage.InputError, match=r"^--max-incidence"):
        example_problem.observe(quality={"max_incidence": 120})
    with pytest.raises(vantage.InputError, match=r"^quality: unknown key 'incidence'"):
        example_problem.observe(quality={"incidence": 60})
    with pytest.raises(vantage.InputError, match=r"^threads: "):
        example_problem.observe(threads=-1)
    with pytest.raises(vantage.InputError, match=r"^--cell-size"):
        vantage.load(EXAMPLE, cell_size=-1.0)
    with pytest.raises(vantage.InputError, match=r"^-n: "):
        vantage.optimize(EXAMPLE, n=1000, out=tmp_path / "out")
    with pytest.raises(TypeError):
        example_vis.select(n="three")


def test_corrupt_visibility_file(tmp_path):
    bad = tmp_path / "bad.vis"
    bad.write_bytes(b"not a matrix at all")
    with pytest.raises(vantage.InputError) as error:
        vantage.load_visibility(bad)
    assert str(error.value) == cli_error("select", bad, "--out", tmp_path / "out")


def test_progress_exception_reaches_the_caller(example_problem):
    calls = []

    def progress(done, total):
        calls.append((done, total))
        raise KeyboardInterrupt("stop")

    with pytest.raises(KeyboardInterrupt, match="stop"):
        example_problem.observe(progress=progress, threads=2)
    assert calls
    assert example_problem.observe(threads=1).matrix.shape[0] == len(example_problem.candidates)


def test_paths_as_the_os_names_them(tmp_path):
    """Session 14: a scene path as bytes was read as the text "b'...'", a file name that is not
    UTF-8 (a str with surrogate escapes, as os.listdir gives it) raised "Unable to cast Python
    instance", and a message quoting it raised UnicodeDecodeError instead of InputError."""
    scene_text = CUBE_CELL.read_text(encoding="utf-8")
    odd = os.fsdecode(b"\xff cell.yaml")
    (tmp_path / odd).write_text(scene_text, encoding="utf-8")
    problem = vantage.load(tmp_path / odd)
    assert problem.source == str(tmp_path / odd)  # the same surrogate escapes back
    assert len(problem.candidates) == 16  # cube_cell.yaml: 10 random + 2 x 3 grid
    from_bytes = vantage.load(os.fsencode(tmp_path / odd))
    assert from_bytes.source == problem.source
    broken = tmp_path / os.fsdecode(b"\xfe broken.yaml")
    broken.write_text(scene_text.replace("cell_size: 0.01", "cell_size: -1"), encoding="utf-8")
    with pytest.raises(vantage.InputError) as error:
        vantage.load(broken)
    assert str(error.value).startswith(f"{broken}:4: settings.cell_size = -1"), str(error.value)
    with pytest.raises(vantage.InputError, match="holds a NUL character"):
        vantage.load(str(tmp_path / "a\0b.yaml"))
    # An empty output path is named, not std::filesystem's "cannot make absolute path".
    with pytest.raises(vantage.InputError, match="the output path is empty"):
        problem.observe().save("")


def test_options_the_cli_refuses_are_refused_here_too(tmp_path):
    """Session 14: max_memory=0 was taken as "no limit of the caller's own" (the CLI refuses
    --max-memory 0), refine_rounds=0 under refine=True did nothing and refine_rounds without
    refine=True was ignored (the CLI refuses both), and targets=3 raised RuntimeError."""
    problem = vantage.load(CUBE_CELL)
    with pytest.raises(vantage.InputError, match="^max_memory: 0 is not a positive number of MiB"):
        problem.observe(max_memory=0)
    with pytest.raises(vantage.InputError, match="^--refine-rounds: 0 is out of range"):
        vantage.optimize(CUBE_CELL, n=1, refine=True, refine_rounds=0, out=tmp_path / "a")
    with pytest.raises(vantage.InputError, match="^refine_rounds: only refine=True runs rounds"):
        vantage.optimize(CUBE_CELL, n=1, refine_rounds=3, out=tmp_path / "b")
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
    with pytest.raises(TypeError, match="targets: give a name or a list of names, not int"):
        vantage.load(CUBE_CELL, targets=3)
    with pytest.raises(TypeError, match="targets: every name is a str, not int"):
        vantage.load(CUBE_CELL, targets=["cube", 3])
    assert len(vantage.load(CUBE_CELL, targets=("cube",)).candidates) == 16
