"""observe from two Python threads at once gives the matrices it gives one after another, and
releases the GIL while it traces."""

import threading

import numpy as np

import vantage
from conftest import EXAMPLE


def same(a, b):
    return (np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
            and a.shape == b.shape)


def test_two_threads_as_sequential():
    problem = vantage.load(EXAMPLE)
    quality = [None, {"max_incidence": 50}]
    sequential = [problem.observe(quality=q).matrix for q in quality]
    results = [None, None]

    def work(i):
        results[i] = problem.observe(quality=quality[i], threads=2).matrix

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(same(r, s) for r, s in zip(results, sequential, strict=True))
    assert not same(sequential[0], sequential[1])


def test_gil_released_while_tracing():
    """The main thread counts its loops while the other thread is inside observe: none would
    run if observe held the GIL."""
    problem = vantage.load(EXAMPLE)
    state = {"inside": False, "finished": False}

    def work():
        state["inside"] = True
        problem.observe(threads=1)
        state["inside"] = False
        state["finished"] = True

    thread = threading.Thread(target=work)
    ticks_inside = 0
    thread.start()
    while not state["finished"]:
        if state["inside"]:
            ticks_inside += 1
    thread.join()
    assert ticks_inside > 1000, "the main thread did not run while observe traced"


def test_progress_reports_every_candidate():
    problem = vantage.load(EXAMPLE)
    seen = []
    lock = threading.Lock()

    def progress(done, total):
        with lock:
            seen.append((done, total))

    vis = problem.observe(progress=progress)
    total = len(vis.candidates)
    assert sorted(d for d, _ in seen) == list(range(1, total + 1))
    assert {t for _, t in seen} == {total}
