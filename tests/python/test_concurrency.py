"""Concurrent callers in one process (issue 44): two threads writing one folder or one .vis file
both succeed and the result is one writer's whole output; two threads touching NumPy first
together do not deadlock; a call blocked in a progress callable still ends on SIGTERM/SIGINT."""

import json
import os
import pathlib
import signal
import subprocess
import sys
import textwrap
import threading

import vantage
from conftest import CUBE_CELL, normalised

ENV = dict(os.environ)


def run_python(script, timeout=120, env=None, **kwargs):
    """Runs `script` in a fresh interpreter (NumPy not yet touched), the module on PYTHONPATH."""
    return subprocess.run([sys.executable, "-c", textwrap.dedent(script)], capture_output=True,
                          text=True, timeout=timeout, env=env or ENV, **kwargs)


def leftovers(folder):
    return sorted(p.name for p in folder.parent.iterdir()
                  if p.name.startswith(folder.name + ".tmp-") or
                  p.name.startswith(folder.name + ".old-"))


def test_two_threads_optimize_into_one_folder(tmp_path):
    """Each file written takes 20 ms (the test hook), so the two writes overlap; both calls
    succeed, and the folder holds one run's files, all of them, and no other's."""
    out = tmp_path / "out"
    script = f"""
        import json, threading, vantage
        results = {{}}
        errors = []
        def work(n):
            try:
                results[n] = vantage.optimize({str(CUBE_CELL)!r}, n=n, method="greedy",
                                              out={str(out)!r}, threads=1)
            except Exception as e:
                errors.append(repr(e))
        threads = [threading.Thread(target=work, args=(n,)) for n in (1, 2)]
        for t in threads: t.start()
        for t in threads: t.join()
        print(json.dumps({{"errors": errors, "results": results}}))
    """
    env = dict(ENV, VANTAGE_TEST_WRITE_DELAY_S="0.02")
    for _ in range(3):
        result = run_python(script, env=env)
        assert result.returncode == 0, result.stderr
        outcome = json.loads(result.stdout)
        assert outcome["errors"] == []
        written = json.loads((out / "report.json").read_text(encoding="utf-8"))
        runs = {int(n): normalised(report) for n, report in outcome["results"].items()}
        winner = [n for n, report in runs.items() if report == normalised(written)]
        assert len(winner) == 1
        # The other files are the same run's: its chosen sensors in static_transforms.yaml.
        chosen = written["results"][written["primary_result"]]["sensors"]
        transforms = (out / "static_transforms.yaml").read_text(encoding="utf-8")
        assert f"n: {winner[0]}," in transforms
        for name in chosen:
            assert f'name: "{name}"' in transforms
        assert leftovers(out) == []


def test_two_threads_save_one_file(tmp_path):
    problem = vantage.load(CUBE_CELL)
    visibilities = [problem.observe(), problem.observe(quality={"max_incidence": 40})]
    path = tmp_path / "m.vis"
    errors = []

    def work(vis):
        for _ in range(20):
            try:
                vis.save(path)
            except Exception as e:  # noqa: BLE001 - any error is the failure
                errors.append(repr(e))

    threads = [threading.Thread(target=work, args=(v,)) for v in visibilities]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    loaded = vantage.load_visibility(path)
    assert loaded.quality in [v.quality for v in visibilities]
    assert leftovers(path) == []


def test_numpy_first_touched_by_two_threads_does_not_deadlock():
    """Two threads reading Visibility.matrix at once, and a progress callable reading an earlier
    matrix from the worker threads: both deadlocked on pybind11's NumPy lookup before."""
    script = f"""
        import threading, vantage
        problem = vantage.load({str(CUBE_CELL)!r})
        first = problem.observe(threads=2)
        second = problem.observe(threads=2)
        barrier = threading.Barrier(2)
        shapes = []
        def read(vis):
            barrier.wait()
            shapes.append(vis.matrix.shape)
        threads = [threading.Thread(target=read, args=(v,)) for v in (first, second)]
        for t in threads: t.start()
        for t in threads: t.join()
        earlier = problem.observe(threads=1)
        seen = []
        problem.observe(threads=4, progress=lambda done, total: seen.append(earlier.matrix.nnz))
        print(len(shapes), len(seen) == len(problem.candidates))
    """
    result = run_python(script, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["2", "True"]


def blocked_call(sig):
    """A call whose progress callable never returns; `sig` once it is blocked: the process must
    end by that signal within the watchdog's grace (3 s), not hang."""
    script = f"""
        import sys, threading, vantage
        problem = vantage.load({str(CUBE_CELL)!r})
        def progress(done, total):
            print("blocked", flush=True)
            threading.Event().wait()
        problem.observe(threads=2, progress=progress)
        print("returned", flush=True)
    """
    process = subprocess.Popen([sys.executable, "-c", textwrap.dedent(script)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    try:
        assert process.stdout.readline().startswith("blocked")
        process.send_signal(sig)
        process.wait(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    return process.returncode


def test_a_blocked_call_still_ends_on_sigterm():
    assert blocked_call(signal.SIGTERM) == -signal.SIGTERM


def test_a_blocked_call_still_ends_on_sigint():
    assert blocked_call(signal.SIGINT) == -signal.SIGINT


def test_relative_out_after_the_working_folder_was_deleted(tmp_path):
    """exit 2 (InputError) naming the folder, not "filesystem error: cannot make absolute path"
    (exit 1, RuntimeError)."""
    gone = tmp_path / "gone"
    gone.mkdir()
    script = f"""
        import os, vantage
        os.chdir({str(gone)!r})
        os.rmdir({str(gone)!r})
        try:
            vantage.optimize({str(CUBE_CELL)!r}, n=1, out="run")
        except vantage.InputError as e:
            print("InputError", e)
    """
    result = run_python(script)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("InputError run: a relative path, and the working folder no "
                                    "longer exists"), result.stdout
    from conftest import BINARY
    for command in (["optimize", str(CUBE_CELL), "-n", "1", "--out", "run"],
                    ["observe", str(CUBE_CELL), "--out", "m.vis"]):
        gone.mkdir()
        cli = subprocess.run(["sh", "-c", f'cd "{gone}" && rmdir "{gone}" && exec "$0" "$@"',
                              str(BINARY), "-q", *command], capture_output=True, text=True)
        assert cli.returncode == 2, cli.stderr
        assert "a relative path, and the working folder no longer exists" in cli.stderr
        assert command[-1] in cli.stderr
