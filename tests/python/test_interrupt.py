"""Ctrl-C in a notebook or script stops a long call within a second and raises KeyboardInterrupt,
as the CLI stops on it (issue 16); Python's own handler is back afterwards."""

import os
import signal
import threading
import time

import pytest

import vantage
from conftest import EXAMPLE


def test_ctrl_c_stops_observe_and_raises_keyboard_interrupt():
    # 1 mm cells and every pixel traced: seconds of ray casting, far longer than the signal's delay.
    problem = vantage.load(str(EXAMPLE), cell_size=0.001)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        problem.observe(cull=False)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 1.3, f"observe went on for {elapsed:.2f} s after the signal at 0.3 s"
    # The interpreter's handler is restored: the next Ctrl-C is Python's KeyboardInterrupt again.
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    # And the library is usable again: the same problem observes to the end.
    vis = vantage.load(str(EXAMPLE)).observe()
    assert vis.matrix.shape[0] == len(vis.candidates)
