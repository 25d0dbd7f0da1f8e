"""Ctrl-C cancels a render: the GIL is released while it runs (other Python threads
go on), and a SIGINT raises ``KeyboardInterrupt`` out of ``render`` once the
renderer has stopped; the scene renders again afterwards.

The render asked for takes minutes (64 samples per pixel over 256 x 32768 pixels,
5 x 10^8 eye rays; a row, the unit the renderer checks for cancellation between,
is 16 384), and the signal comes after a fraction of a second: if it did not stop
the render, ``render`` would return and the test fail. No timing is measured.

Python's own handler is installed for the test: a process started with SIGINT
ignored (a background job of a non-interactive shell) has none."""

from __future__ import annotations

import os
import signal
import threading

import numpy as np
import pytest

import nffrt

SCENE = (
    "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 256 32768\n"
    "l 0 0 9\nf 1 1 1 0.5 0.5 10 0.5 1.5\ns 0 0 0 1\ns 0.5 0.5 -1 1\n"
)


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals go to the main thread")
def test_sigint_cancels_a_render_and_the_gil_is_free_meanwhile() -> None:
    scene = nffrt.parse(SCENE)
    started = threading.Event()
    ticks = []

    def interrupt() -> None:
        # Runs Python code while the render holds no GIL, then sends Ctrl-C.
        started.wait()
        for _ in range(20):
            ticks.append(sum(range(1000)))
            threading.Event().wait(0.02)
        os.kill(os.getpid(), signal.SIGINT)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    thread = threading.Thread(target=interrupt)
    thread.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            started.set()
            scene.render(spp=64, threads=2)
    finally:
        thread.join()
        signal.signal(signal.SIGINT, previous)
    assert len(ticks) == 20
    assert scene.last_stats is None  # it never finished
    small = scene.render(width=8, height=8)
    assert small.shape == (8, 8, 3) and np.isfinite(small).all()
